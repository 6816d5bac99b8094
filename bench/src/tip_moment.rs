//! The rod model's cantilever under a tip moment, against the elastica.
//!
//! A straight cantilever of length `L` and bending stiffness `EI`, clamped at its root and loaded
//! by a pure moment `M` at its tip, bends into a circular arc ([`crate::analytic::elastica_tip`]):
//! its tip turns by `t = ML/EI` and lies at `u = L(sin t/t − 1)` along the clamp direction and
//! `v = (L/t)(1 − cos t)` across it, and the point at arc length `s` at
//! `((L/t) sin(ts/L) − s, (L/t)(1 − cos(ts/L)))`. The case follows
//! `hair-core/tests/rod_cantilever_tip_moment.rs`: 20 segments over 0.4 m, 10 g/m, a round
//! section with `EI = 10⁻³ N m²`, the moment as a couple on the last segment that turns with it,
//! no gravity, air drag `2 ω₁` to relax it to rest in 2 s, at a small deflection (`t = 0.1`
//! rad, where beam theory's `v = ML²/2EI` holds) and a large one (`t = 1.5` rad). The errors are
//! the largest distance of a node from its place on the arc, as a fraction of `L`, and the
//! tip's turn (the last segment's angle) against `t`.
//!
//! The rod runs it through [`RodStrand::substep`] directly: a scene has no tip-moment input, and
//! neither has the mass-spring model, which is therefore not measured on it.

use std::time::Instant;

use hair_core::model::rod::strand::Root;
use hair_core::model::rod::{RodStrand, Stiffness, Substep, Workspace};
use nalgebra::{UnitQuaternion, Vector3};
use serde::Serialize;

type V3 = Vector3<f64>;

/// Segments of the cantilever.
const SEGMENTS: usize = 20;
/// Length `L`, m.
pub const LENGTH: f64 = 0.4;
/// Linear density, kg/m.
const DENSITY: f64 = 0.01;
/// Bending stiffness `EI`, N m².
const EI: f64 = 1e-3;
/// Total rotations `t = ML/EI` measured, rad: a small and a large deflection.
pub const ROTATIONS: [f64; 2] = [0.1, 1.5];
/// Simulated time, s.
const DURATION: f64 = 2.0;
/// Projection tolerance (relative strain).
const TOLERANCE: f64 = 1e-10;

/// One run of the tip-moment case.
#[derive(Debug, Clone, Serialize)]
pub struct TipMomentRun {
    /// Analytic tip turn `t = ML/EI`, rad.
    pub rotation: f64,
    /// The tip's measured turn (angle of the last segment from the clamp direction), rad.
    pub tip_angle: Option<f64>,
    /// Projection iteration limit.
    pub iterations: u32,
    /// Substep, s.
    pub dt: f64,
    /// `dt` over the rod's predicted bound `2/ω`.
    pub dt_over_bound: f64,
    /// Tip displacement along the clamp direction `u`, m (`None` if the run failed).
    pub tip_u: Option<f64>,
    /// Tip displacement across it `v`, m.
    pub tip_v: Option<f64>,
    /// Largest node distance from the analytic arc over `L`.
    pub error_over_length: Option<f64>,
    /// Largest segment strain `|len/l − 1|` at the end.
    pub max_strain: Option<f64>,
    /// Largest projection residual of any substep.
    pub residual: f64,
    /// Substeps whose projection stopped at the iteration limit above the tolerance.
    pub unconverged: u64,
    /// Substeps run.
    pub substeps: u64,
    /// Wall-clock microseconds per substep.
    pub us_per_substep: f64,
    /// How it ended: `"at rest"`, `"moving"` (not at rest after 2 s) or the failure.
    pub status: String,
}

/// The analytic tip displacement `(u, v)` under the moment turning the tip by `rotation`, m.
pub fn analytic_tip(rotation: f64) -> (f64, f64) {
    let (_, u, v) = crate::analytic::elastica_tip(LENGTH, EI, rotation * EI / LENGTH);
    (u, v)
}

/// The rod's predicted bound `2/ω`, `ω² = 32 EI / (m l³)` (as [`hair_core::RodSolver`]), s.
pub fn bound() -> f64 {
    let seg = LENGTH / SEGMENTS as f64;
    2.0 / (32.0 * EI / (DENSITY * seg * seg.powi(3))).sqrt()
}

/// Substeps as fractions of the bound, and iteration limits, of the bench.
fn grid(quick: bool) -> (Vec<f64>, Vec<u32>) {
    if quick {
        (vec![1.5, 0.5, 0.25], vec![1, 4, 20])
    } else {
        (vec![1.5, 0.9, 0.5, 0.25, 0.125], vec![1, 2, 4, 8, 20])
    }
}

/// Number of runs [`bench()`] makes.
pub fn runs(quick: bool) -> usize {
    let (f, i) = grid(quick);
    f.len() * i.len() * ROTATIONS.len()
}

/// Runs the case at `dt` with the projection limited to `iterations`, under the moment that
/// turns the tip by `rotation` (rad).
pub fn run(iterations: u32, dt: f64, rotation: f64) -> TipMomentRun {
    let seg = LENGTH / SEGMENTS as f64;
    let moment = rotation * EI / LENGTH;
    let rest: Vec<Vector3<f32>> = (0..=SEGMENTS)
        .map(|i| Vector3::new(0.0, 0.0, (seg * i as f64) as f32))
        .collect();
    let mut inv_mass = vec![(1.0 / (DENSITY * seg)) as f32; SEGMENTS + 1];
    inv_mass[0] = 0.0;
    inv_mass[SEGMENTS] *= 2.0;
    let stiffness = Stiffness::isotropic(EI, EI);
    let mut out = TipMomentRun {
        rotation,
        tip_angle: None,
        iterations,
        dt,
        dt_over_bound: dt / bound(),
        tip_u: None,
        tip_v: None,
        error_over_length: None,
        max_strain: None,
        residual: 0.0,
        unconverged: 0,
        substeps: 0,
        us_per_substep: 0.0,
        status: String::new(),
    };
    let rod = match RodStrand::new(&rest, &inv_mass, &[1e-3; SEGMENTS + 1], &stiffness) {
        Ok(rod) => rod,
        Err(j) => {
            out.status = format!("segment {j} has zero length");
            return out;
        }
    };
    let root = Root {
        origin: V3::zeros(),
        rotation: UnitQuaternion::rotation_between(&V3::z(), &V3::x())
            .unwrap_or_else(UnitQuaternion::identity),
    };
    let mut state = rod.rest_state(&root);
    let axis = -V3::y();
    let omega1 = 3.516 * (EI / (DENSITY * LENGTH.powi(4))).sqrt();
    let mut ws = Workspace::default();
    let mut external = vec![V3::zeros(); SEGMENTS + 1];
    let steps = (DURATION / dt).round() as u64;
    let t0 = Instant::now();
    for k in 0..steps {
        let e = state.x[SEGMENTS] - state.x[SEGMENTS - 1];
        let f = axis.cross(&e.normalize()) * (moment / e.norm());
        external[SEGMENTS] = f;
        external[SEGMENTS - 1] = -f;
        let input = Substep {
            dt,
            gravity: V3::zeros(),
            air_drag: 2.0 * omega1,
            stiffness: &stiffness,
            root_start: root,
            root_end: root,
            max_iterations: iterations,
            tolerance: TOLERANCE,
            colliders: None,
            external: Some(&external),
            torque: None,
        };
        let o = rod.substep(&mut state, &input, &mut ws);
        out.substeps = k + 1;
        out.residual = out.residual.max(o.projection.residual);
        if !o.projection.converged {
            out.unconverged += 1;
        }
        let finite = state.x.iter().all(|x| x.iter().all(|c| c.is_finite()));
        if !finite || !o.projection.residual.is_finite() {
            out.status = format!("unstable: non-finite position at substep {}", k + 1);
            break;
        }
        if o.projection.residual > 1e-2 {
            out.status = format!(
                "projection not converging: residual {:.2e} at substep {}",
                o.projection.residual,
                k + 1
            );
            break;
        }
    }
    out.us_per_substep = 1e6 * t0.elapsed().as_secs_f64() / out.substeps.max(1) as f64;
    if !out.status.is_empty() {
        return out;
    }
    let radius = LENGTH / rotation;
    let worst = state
        .x
        .iter()
        .enumerate()
        .map(|(i, x)| {
            let s = seg * i as f64;
            let on_arc = V3::new(
                radius * (s / radius).sin(),
                0.0,
                radius * (1.0 - (s / radius).cos()),
            );
            (x - on_arc).norm()
        })
        .fold(0.0, f64::max);
    let strain = state
        .x
        .windows(2)
        .zip(rod.rest_lengths())
        .map(|(w, &l)| ((w[1] - w[0]).norm() / l - 1.0).abs())
        .fold(0.0, f64::max);
    let tip = state.x[SEGMENTS];
    let last = state.x[SEGMENTS] - state.x[SEGMENTS - 1];
    out.tip_angle = Some(last.z.atan2(last.x));
    out.tip_u = Some(tip.x - LENGTH);
    out.tip_v = Some(tip.z);
    out.error_over_length = Some(worst / LENGTH);
    out.max_strain = Some(strain);
    let speed = state.v.iter().map(|v| v.norm()).fold(0.0, f64::max);
    out.status = if speed < 1e-4 {
        "at rest".into()
    } else {
        format!("moving ({speed:.1e} m/s after {DURATION} s)")
    };
    out
}

/// Runs the grid of substeps × iteration limits, calling `tick` after each run.
pub fn bench(quick: bool, mut tick: impl FnMut()) -> Vec<TipMomentRun> {
    let (fractions, iterations) = grid(quick);
    let mut out = Vec::new();
    for &t in &ROTATIONS {
        for &i in &iterations {
            for &f in &fractions {
                out.push(run(i, f * bound(), t));
                tick();
            }
        }
    }
    out
}
