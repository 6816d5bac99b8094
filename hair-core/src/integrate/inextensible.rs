//! The inextensibility projection (seed 002, "Constraints"): after each substep's position update,
//! the strand is projected to the nearest state whose segments have their rest lengths, and the
//! velocities are corrected by the displacement.
//!
//! # Method
//! Seed 002 describes a post-integration step that "removes equation stiffness": a projection to
//! the nearest constrained state, nearest in the metric of kinetic energy (mass-weighted), by an
//! iterative manifold projection. This is the *fast projection* of Goldenthal et al. 2007
//! ("Efficient Simulation of Inextensible Cloth"), which for a chain is cheap: with one
//! constraint per segment, `C_j = |x_{j+1} − x_j| − l_j` (m), and `t_j` the segment's unit
//! direction, each iteration is one Newton step on the constraints,
//!
//! ```text
//! (G M⁻¹ Gᵀ) λ = C,        x ← x − M⁻¹ Gᵀ λ
//! ```
//!
//! where `G` is the constraint Jacobian. On a chain `G M⁻¹ Gᵀ` is tridiagonal: diagonal
//! `w_j + w_{j+1}`, off-diagonal `−w_{j+1} t_j·t_{j+1}` (`w` inverse masses, 0 for the root and
//! pinned points, which therefore never move). One Thomas solve per iteration, O(n), runs down
//! every strand of a group at once (lanes = strands). At least one iteration runs every substep;
//! iterations stop when every segment's relative length error `|len/l − 1|` is below
//! [`Inextensibility::tolerance`] in every lane, or after [`Inextensibility::max_iterations`].
//! Newton converges quadratically: from the strain one substep leaves, one iteration usually
//! reaches float precision.
//!
//! Velocities are corrected by the same kind of projection at the projected positions: every
//! segment's stretching rate `t_j·(v_{j+1} − v_j)` is removed (`G v = 0`, one more tridiagonal
//! solve), so the stretching velocity the springs would have turned back is gone, as the seed's
//! projection does. The usual correction `v += Δx/dt` is not used: it divides the f32 round-off
//! of the positions (about 3·10⁻⁸ m at 0.5 m) by dt, and at 10⁵ substeps per second that is mm/s
//! of noise per substep — with it a pendulum stops converging as the step shrinks.
//! The velocity projection converges at first order like the rest of the step. All impulses are
//! mass-weighted and equal and opposite along each segment, so a free strand's linear momentum
//! is conserved.
//!
//! It replaces stiff stretch springs: with the projection on, a scene can drop
//! `stretch_stiffness`, whose stability bound grows as √k, and keep strands inextensible at the
//! substep the bending springs need. It is off unless the host asks for it
//! ([`crate::MassSpringSolver::with_inextensibility`]) and then costs nothing.

use super::lanes::{div_or_zero, splat, Baseline, Lane, V3};
use crate::error::{HairError, Result};

/// Settings of the inextensibility projection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inextensibility {
    /// Largest relative segment length error `|len/rest − 1|` the projection iterates down to
    /// (dimensionless; 1e-4 = 0.01 %).
    pub tolerance: f32,
    /// Most projection iterations per substep (each one tridiagonal solve per strand).
    pub max_iterations: u32,
}

impl Default for Inextensibility {
    fn default() -> Self {
        Self {
            tolerance: 1e-4,
            max_iterations: 8,
        }
    }
}

impl Inextensibility {
    /// Checks the tolerance is finite and > 0 and at least one iteration is allowed.
    pub fn validate(&self) -> Result<()> {
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(HairError::Parameter {
                name: "inextensibility.tolerance".into(),
                value: self.tolerance.to_string(),
                fix: "use a finite relative length error > 0, e.g. 1e-4".into(),
            });
        }
        if self.max_iterations == 0 {
            return Err(HairError::Parameter {
                name: "inextensibility.max_iterations".into(),
                value: "0".into(),
                fix: "allow at least 1 projection iteration per substep, e.g. 8".into(),
            });
        }
        Ok(())
    }
}

/// Work buffers of the projection, refitted to each group.
#[derive(Default)]
pub(crate) struct ProjectionScratch<L = Baseline> {
    /// Per segment: unit direction, right-hand side (constraint value or rate), matrix
    /// diagonal and upper diagonal, Thomas factors, and the solution.
    pub(super) tangent: Vec<V3<L>>,
    pub(super) rhs: Vec<L>,
    pub(super) diag: Vec<L>,
    pub(super) upper: Vec<L>,
    factor: Vec<L>,
    pub(super) lambda: Vec<L>,
}

impl<L: Lane> ProjectionScratch<L> {
    /// Sizes the buffers for `segments` segments. Their old values are not cleared: the
    /// projection and the strain limit write every entry before they read it.
    #[inline(always)]
    pub(super) fn fit(&mut self, segments: usize) {
        for buf in [
            &mut self.rhs,
            &mut self.diag,
            &mut self.upper,
            &mut self.factor,
            &mut self.lambda,
        ] {
            buf.resize(segments, L::default());
        }
        self.tangent.resize(segments, V3::default());
    }

    /// Unit segment directions of `x` into `tangent`; returns the lengths' worst relative error
    /// per lane and leaves `len − rest` in `rhs`.
    #[inline(always)]
    fn measure(&mut self, x: &[V3<L>], rest_length: &[L]) -> L {
        let mut worst = splat::<L>(0.0);
        for (j, &rest) in rest_length.iter().enumerate() {
            let d = x[j + 1] - x[j];
            let len = d.dot(&d).sqrt();
            self.tangent[j] = d * div_or_zero(splat(1.0), len, 1e-9);
            self.rhs[j] = len - rest;
            worst = worst.max((self.rhs[j] / rest).abs());
        }
        worst
    }

    /// Solves `(G M⁻¹ Gᵀ) λ = rhs` for the current tangents (Thomas algorithm; the matrix is
    /// symmetric positive semi-definite, and a segment between two fixed points has a zero row
    /// and gets λ = 0), then applies `y_j += w_j t_j λ_j`, `y_{j+1} −= w_{j+1} t_j λ_j`.
    #[inline(always)]
    fn solve_and_apply(&mut self, y: &mut [V3<L>], inv_mass: &[L]) {
        let m = self.rhs.len();
        for j in 0..m {
            self.diag[j] = inv_mass[j] + inv_mass[j + 1];
            self.upper[j] = if j + 1 < m {
                -(inv_mass[j + 1] * self.tangent[j].dot(&self.tangent[j + 1]))
            } else {
                splat(0.0)
            };
        }
        self.thomas();
        for j in 0..m {
            let step = self.tangent[j] * self.lambda[j];
            y[j] += step * inv_mass[j];
            y[j + 1] -= step * inv_mass[j + 1];
        }
    }

    /// Solves the tridiagonal system held in `diag`, `upper` (symmetric) and `rhs` into
    /// `lambda` (Thomas algorithm; a zero pivot gives λ = 0 for its row).
    #[inline(always)]
    pub(super) fn thomas(&mut self) {
        let m = self.rhs.len();
        let (mut prev_factor, mut prev_lambda) = (splat(0.0), splat(0.0));
        for j in 0..m {
            let lower = if j > 0 { self.upper[j - 1] } else { splat(0.0) };
            let inv = div_or_zero(splat(1.0), self.diag[j] - lower * prev_factor, 0.0);
            self.factor[j] = self.upper[j] * inv;
            self.lambda[j] = (self.rhs[j] - lower * prev_lambda) * inv;
            prev_factor = self.factor[j];
            prev_lambda = self.lambda[j];
        }
        for j in (0..m.saturating_sub(1)).rev() {
            self.lambda[j] = self.lambda[j] - self.factor[j] * self.lambda[j + 1];
        }
    }
}

/// Projects the group's positions `x` onto rest segment lengths `rest_length` (unpadded, one per
/// segment, m), then, with `velocities`, its velocities `v` onto the velocities that keep those
/// lengths (without: a position correction, as `contacts::coupling` asks for when it moves
/// points out of a collider). `inv_mass` (1/kg) is 0 for points that must not move.
#[inline(always)]
pub(crate) fn project<L: Lane>(
    x: &mut [V3<L>],
    v: &mut [V3<L>],
    inv_mass: &[L],
    rest_length: &[L],
    settings: &Inextensibility,
    velocities: bool,
    s: &mut ProjectionScratch<L>,
) {
    s.fit(rest_length.len());
    for iteration in 0..=settings.max_iterations {
        let worst = s.measure(x, rest_length);
        // At least one iteration always runs: skipping violations below the tolerance would
        // let radial velocity build up between projections and then remove it all at once, a
        // loss of energy that does not shrink with the substep.
        let converged = worst.to_array().iter().all(|&e| e < settings.tolerance);
        if iteration == settings.max_iterations || (iteration > 0 && converged) {
            break;
        }
        s.solve_and_apply(x, inv_mass);
    }
    if !velocities {
        return;
    }
    // Velocities: remove every segment's stretching rate t_j·(v_{j+1} − v_j) at the projected
    // positions (the tangents are those `measure` left).
    for j in 0..rest_length.len() {
        s.rhs[j] = s.tangent[j].dot(&(v[j + 1] - v[j]));
    }
    s.solve_and_apply(v, inv_mass);
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    #[test]
    fn projection_restores_lengths_removes_stretching_rates_and_conserves_momentum() {
        // A free zig-zag of four equal-mass points (no point fixed), segments stretched by 20 %
        // and squeezed by 10 %, moving apart; the same in every lane.
        let p = [
            [0.0, 0.0, 0.0],
            [1.2, 0.0, 0.0],
            [1.2, 0.9, 0.0],
            [2.0, 1.5, 0.3],
        ];
        let u = [
            [-1.0, 0.5, 0.0],
            [2.0, 0.0, 0.3],
            [0.0, 1.0, -1.0],
            [0.5, 0.5, 0.5],
        ];
        let lanes = |a: [[f32; 3]; 4]| -> Vec<V3> {
            a.iter().map(|q| V3::splat(&Vector3::from(*q))).collect()
        };
        let (mut x, mut v) = (lanes(p), lanes(u));
        let w = vec![splat(2.0); 4];
        let rest = vec![splat(1.0); 3];
        let momentum = |v: &[V3]| -> Vector3<f32> { v.iter().map(|q| q.lane(3) / 2.0).sum() };
        let before = momentum(&v);
        let mut scratch = ProjectionScratch::default();
        project(
            &mut x,
            &mut v,
            &w,
            &rest,
            &Inextensibility::default(),
            true,
            &mut scratch,
        );
        for j in 0..3 {
            let d = (x[j + 1] - x[j]).lane(0);
            assert!((d.norm() - 1.0).abs() < 1e-4, "segment {j}: {}", d.norm());
            let rate = d.normalize().dot(&(v[j + 1] - v[j]).lane(0));
            assert!(
                rate.abs() < 1e-4,
                "segment {j} still stretches at {rate} m/s"
            );
        }
        assert!((momentum(&v) - before).norm() < 1e-4, "momentum changed");
    }
}
