//! Helpers shared by the physics validation tests: strand builders, parameter sets with every
//! model component off unless asked for, a solver for a scene, and small analytic tools (zero
//! crossings, chain normal modes, the catenary). [`collide`] holds the collision tests' scene,
//! run loop and inside/outside reference.
#![allow(dead_code)]

pub mod collide;
pub mod integrators;

use hair_core::{
    Anchor, HairError, HairParams, Integrator, MassSpringSolver, RootFrame, Scalp, SolverSettings,
    StrandInput, StrandSet, Substeps,
};
use hairsys::build::Simulation;
use nalgebra::{DMatrix, UnitQuaternion, Vector3};

/// Standard gravity used by every test, m/s² (magnitude of `HairParams::default().gravity`).
pub const G: f64 = 9.81;

/// Parameters with every component off: no gravity, no bending, no goal, no damping, no drag.
/// Tests switch on exactly what they check.
pub fn bare_params(stretch_stiffness: f32) -> HairParams {
    HairParams {
        gravity: [0.0, 0.0, 0.0],
        stretch_stiffness,
        bend_stiffness: 0.0,
        goal_stiffness: 0.0,
        stretch_damping: 0.0,
        air_drag: 0.0,
    }
}

/// Gravity along −z, m/s².
pub fn gravity() -> [f32; 3] {
    [0.0, 0.0, -G as f32]
}

/// Settings with `substeps` fixed per frame, one collision step per frame.
pub fn fixed_settings(fps: f32, substeps: u32, integrator: Integrator) -> SolverSettings {
    SolverSettings {
        fps,
        steps: 1,
        substeps: Substeps::Fixed(substeps),
        damping_iterations: 10,
        integrator,
        max_strain: None,
        kernel: Default::default(),
    }
}

/// A strand input with explicit per-point masses and pinned flags (point 0 is always pinned),
/// radius 1 mm and goal weight 0.
pub fn strand(
    anchor: Anchor,
    rest: Vec<Vector3<f32>>,
    mass: Vec<f32>,
    pinned: Vec<bool>,
) -> StrandInput {
    let n = rest.len();
    assert_eq!(mass.len(), n);
    assert_eq!(pinned.len(), n);
    StrandInput {
        anchor,
        rest,
        mass,
        radius: vec![1e-3; n],
        goal_weight: vec![0.0; n],
        pinned,
    }
}

/// Pinned flags with only the root pinned.
pub fn root_only(n: usize) -> Vec<bool> {
    let mut p = vec![false; n];
    p[0] = true;
    p
}

/// `segments + 1` points from the origin along root-local `dir`, `seg_len` apart.
pub fn straight(segments: usize, seg_len: f32, dir: Vector3<f32>) -> Vec<Vector3<f32>> {
    let d = dir.normalize();
    (0..=segments).map(|i| d * (seg_len * i as f32)).collect()
}

/// The identity root frame at `origin` (root-local axes = world axes).
pub fn anchor_at(origin: Vector3<f32>) -> Anchor {
    Anchor::Body(RootFrame::at(origin))
}

/// A root frame at `origin` whose local z axis points along world `normal`.
pub fn anchor_along(origin: Vector3<f32>, normal: Vector3<f32>) -> Anchor {
    let rotation =
        UnitQuaternion::rotation_between(&Vector3::z(), &normal).expect("normal not opposite to z");
    Anchor::Body(RootFrame { origin, rotation })
}

/// A mass-spring solver for `sim` with the hair at rest at its first frame.
pub fn solver_at_first_frame(sim: &Simulation) -> MassSpringSolver {
    let first = sim.first_frame;
    MassSpringSolver::new(
        sim.settings,
        sim.params,
        &sim.strands,
        &sim.scalp_at(first as f32),
        first,
    )
    .unwrap()
}

/// Builds a set from inputs, placed at rest on `scalp`.
pub fn set_on(scalp: &Scalp, inputs: impl IntoIterator<Item = StrandInput>) -> StrandSet {
    let mut set = StrandSet::new();
    for input in inputs {
        set.push(input).expect("valid strand");
    }
    set.reset_to_rest(scalp);
    set
}

/// Runs `frames` frames on a fixed scalp, calling `each` after every successful frame.
pub fn run(
    solver: &mut MassSpringSolver,
    strands: &mut StrandSet,
    scalp: &Scalp,
    frames: u32,
    mut each: impl FnMut(&MassSpringSolver, &StrandSet),
) -> Result<(), HairError> {
    for _ in 0..frames {
        solver.step_frame(strands, scalp)?;
        each(solver, strands);
    }
    Ok(())
}

/// Times at which the sampled signal `(t, y)` crosses zero (linear interpolation between samples).
pub fn zero_crossings(samples: &[(f64, f64)]) -> Vec<f64> {
    samples
        .windows(2)
        .filter_map(|w| {
            let ((t0, y0), (t1, y1)) = (w[0], w[1]);
            if y0 == 0.0 {
                Some(t0)
            } else if y0 * y1 < 0.0 {
                Some(t0 + (t1 - t0) * y0 / (y0 - y1))
            } else {
                None
            }
        })
        .collect()
}

/// Period from successive zero crossings (two per period): least-squares slope of crossing time
/// against crossing index, times two.
pub fn period_from_crossings(crossings: &[f64]) -> f64 {
    let n = crossings.len() as f64;
    assert!(n >= 3.0, "need at least three zero crossings, got {n}");
    let mean_i = (n - 1.0) / 2.0;
    let mean_t = crossings.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (i, t) in crossings.iter().enumerate() {
        let di = i as f64 - mean_i;
        sxy += di * (t - mean_t);
        sxx += di * di;
    }
    2.0 * sxy / sxx
}

/// Longitudinal normal modes of a straight chain of springs `k` (N/m) from a fixed root through
/// free point masses `masses` (kg, root excluded): angular frequencies (rad/s, ascending) and the
/// matching unit eigenvectors of the mass-weighted stiffness `M^{-1/2} K M^{-1/2}` (columns).
pub fn chain_modes(k: f64, masses: &[f64]) -> (Vec<f64>, DMatrix<f64>) {
    let n = masses.len();
    let mut stiffness = DMatrix::<f64>::zeros(n, n);
    // Spring j joins point j (j = 0: the fixed root) and point j + 1 (free index j).
    for j in 0..n {
        stiffness[(j, j)] += k;
        if j > 0 {
            stiffness[(j - 1, j - 1)] += k;
            stiffness[(j - 1, j)] -= k;
            stiffness[(j, j - 1)] -= k;
        }
    }
    let scaled = DMatrix::from_fn(n, n, |r, c| {
        stiffness[(r, c)] / (masses[r] * masses[c]).sqrt()
    });
    let eig = scaled.symmetric_eigen();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
    let omega = order
        .iter()
        .map(|&i| eig.eigenvalues[i].max(0.0).sqrt())
        .collect();
    let vectors = DMatrix::from_fn(n, n, |r, c| eig.eigenvectors[(r, order[c])]);
    (omega, vectors)
}

/// Angular frequencies (rad/s, ascending) of [`chain_modes`].
pub fn chain_mode_frequencies(k: f64, masses: &[f64]) -> Vec<f64> {
    chain_modes(k, masses).0
}

/// Catenary parameter `a` (m) of a chain of length `length` hung between two points at the same
/// height `span` apart: the root of `2 a sinh(span / 2a) = length`, by bisection.
pub fn catenary_parameter(span: f64, length: f64) -> f64 {
    assert!(length > span, "a catenary needs length > span");
    let f = |a: f64| 2.0 * a * (span / (2.0 * a)).sinh() - length;
    // f decreases in a, from +∞ (a → 0) to span − length < 0 (a → ∞).
    let (mut lo, mut hi) = (span * 1e-3, span * 1e3);
    while f(lo) < 0.0 || !f(lo).is_finite() {
        lo *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Height of the catenary of parameter `a` hung between `(0, 0)` and `(span, 0)` at abscissa `x`
/// (m, negative below the supports).
pub fn catenary_height(a: f64, span: f64, x: f64) -> f64 {
    a * ((x - 0.5 * span) / a).cosh() - a * (0.5 * span / a).cosh()
}

/// Largest |position| component over all points, to check finiteness and size.
pub fn all_finite(strands: &StrandSet) -> bool {
    strands
        .positions
        .iter()
        .chain(&strands.velocities)
        .all(|p| p.iter().all(|c| c.is_finite()))
}
