//! The stability bound of explicit-type integrators on a mass-spring chain, and `substeps = auto`.
//!
//! For a chain of springs of stiffness `k` between point masses `m`, the highest normal mode has
//! angular frequency `ω ≈ 2·sqrt(k/m)`; semi-implicit Euler is stable only for `dt < 2/ω`.
//! Curvature bending (`super::curvature`) couples three points across the strand: at small turns
//! the turn at point j is `(δ_{j+1} − δ_j)/l − (δ_j − δ_{j−1})/l` for sideways displacements δ,
//! with weights 1, 2, 1, so a row of its stiffness matrix sums to `16 k_t` in absolute value, with
//! `k_t = k_j/l²` the joint's transverse stiffness (`k_b` on a uniformly segmented straight strand,
//! `(1 + |κ⁰|²/4)²` times more about a rest curvature κ⁰), against
//! `4 k_stretch` for stretch springs; the zig-zag mode across the strand reaches that. The bound
//! takes `k = k_stretch + 4 k_t` with the largest `k_t` of any joint
//! ([`super::curvature::transverse_stiffness`]; Gershgorin: it covers both directions). The
//! curvature energy stiffens as a joint bends (8× at a 90° turn), and on a curved rest shape the
//! bending forces also carry the twist of the transported frames, both of which this
//! small-angle estimate leaves out, so on a very curly, bend-dominated strand (1 rad per
//! segment, `k_bend = 10 k_stretch`) the bound may not hold within `auto`'s margin: with
//! chord-spring bending such a strand fails at 0.96 × the bound
//! (`docs/design/bending-energy.md`). A goal spring ties a point to a fixed target and adds
//! `k_goal/m` to `ω²`. The lightest free point
//! (usually a tip, which carries half a segment) sets the bound. `auto` picks the smallest
//! substep count whose `dt` is below [`AUTO_SAFETY`] times the bound.
//!
//! Explicit (forward) Euler is unstable for any undamped oscillator at any `dt`; the bound is
//! reported for it too, but it only delays the growth (see the energy test in `tests/`).

use crate::strands::StrandSet;

use super::curvature::transverse_stiffness;
use super::params::{HairParams, StrandScales};

/// Fraction of the bound `2/ω` that `substeps = "auto"` aims for.
pub const AUTO_SAFETY: f64 = 0.8;

/// The predicted stability limit of a strand set with given parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StabilityBound {
    /// Highest angular frequency ω, rad/s.
    pub omega: f64,
    /// Largest stable substep 2/ω, s (infinite when no spring acts).
    pub dt_max: f64,
    /// Effective stiffness between neighbours, stretch + 4 × the largest transverse bending
    /// stiffness (`k_bend` on uniformly segmented strands; see the module docs), N/m.
    pub stiffness: f64,
    /// Lightest free point, kg.
    pub min_mass: f64,
}

impl StabilityBound {
    /// Computes the bound for `strands` under `params`.
    pub fn of(strands: &StrandSet, params: &HairParams) -> Self {
        Self::of_scaled(strands, params, &[])
    }

    /// Computes the bound for `strands` whose strand `s` runs with `scales[s].apply(params)`
    /// (per-region physics; empty `scales`: every strand with `params`, as [`Self::of`]). Each
    /// term takes its largest value over the strands — the stiffest stretch, bending and goal
    /// springs, wherever they are — against the lightest point: a bound for every strand, and
    /// with unit scales exactly the unscaled one.
    pub fn of_scaled(strands: &StrandSet, params: &HairParams, scales: &[StrandScales]) -> Self {
        let scale = |s: usize| scales.get(s).copied().unwrap_or_default();
        let scaled = |s: usize| scale(s).apply(params);
        let min_mass = strands
            .masses()
            .iter()
            .filter(|&&m| m > 0.0)
            .fold(f64::INFINITY, |a, &m| a.min(m as f64));
        // Goal stiffness × goal weight, the largest of any point.
        let goal = if scales.is_empty() {
            let max_goal = strands
                .goal_weights()
                .iter()
                .fold(0.0f64, |a, &w| a.max(w as f64));
            params.goal_stiffness as f64 * max_goal
        } else {
            (0..strands.len())
                .map(|s| {
                    let w = strands.goal_weights()[strands.points(s)]
                        .iter()
                        .fold(0.0f64, |a, &w| a.max(w as f64));
                    scaled(s).goal_stiffness as f64 * w
                })
                .fold(0.0f64, f64::max)
        };
        let stretch = (0..scales.len()).map(|s| scaled(s).stretch_stiffness).fold(
            if scales.is_empty() {
                params.stretch_stiffness
            } else {
                0.0
            },
            f32::max,
        );
        let bend = if params.bend_stiffness > 0.0 {
            (0..strands.len())
                .map(|s| {
                    transverse_stiffness(
                        scaled(s).bend_stiffness,
                        &strands.rest_lengths()[strands.segments(s)],
                        &strands.bend_rest()[strands.segments(s)],
                    )
                })
                .fold(0.0f64, f64::max)
        } else {
            0.0
        };
        let k = stretch as f64 + 4.0 * bend;
        let omega2 = if min_mass.is_finite() {
            (4.0 * k + goal) / min_mass
        } else {
            0.0
        };
        let omega = omega2.sqrt();
        let dt_max = if omega > 0.0 {
            2.0 / omega
        } else {
            f64::INFINITY
        };
        Self {
            omega,
            dt_max,
            stiffness: k,
            min_mass,
        }
    }

    /// Substeps per step of length `step_dt` (s) that `auto` chooses: the fewest keeping
    /// `dt ≤ AUTO_SAFETY · 2/ω`, at least 1.
    pub fn auto_substeps(&self, step_dt: f64) -> u32 {
        if !self.dt_max.is_finite() {
            return 1;
        }
        (step_dt / (AUTO_SAFETY * self.dt_max))
            .ceil()
            .clamp(1.0, u32::MAX as f64) as u32
    }
}
