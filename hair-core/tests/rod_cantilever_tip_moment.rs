//! Rod model: a large-rotation cantilever under a tip moment bends into the exact circular arc.
//!
//! Reference (Euler–Bernoulli, inextensible, any rotation): a straight cantilever of length `L`
//! and bending stiffness `EI` clamped at the root, loaded by a pure moment `M` at its tip, has
//! the uniform curvature `M/EI`: with `t = ML/EI` its point at arc length `s` lies at
//! `u(s) = (L/t) sin(ts/L) − s` along the clamp direction (displacement) and
//! `v(s) = (L/t)(1 − cos(ts/L))` across it; at the tip `u = L(sin t/t − 1)`,
//! `v = (L/t)(1 − cos t)`. The moment is applied as a couple on the last segment (two opposite
//! forces `M/l` perpendicular to it, following it as it turns), and the strand is relaxed to rest
//! by air drag through the rod model's own substeps (explicit step + projection). Gravity off,
//! round section. Every node must lie within 1 % of `L` of the analytic arc.

use hair_core::model::rod::strand::Root;
use hair_core::model::rod::{RodState, RodStrand, Stiffness, Substep, Workspace};
use nalgebra::{UnitQuaternion, Vector3};

type V3 = Vector3<f64>;

#[test]
fn cantilever_under_tip_moment_follows_the_analytic_arc() {
    let segments = 20usize;
    let length = 0.4f64;
    let seg = length / segments as f64;
    let density = 0.01f64; // kg/m
    let ei = 1e-3f64; // N m²
    let t = 1.5f64; // total rotation, rad
    let moment = t * ei / length;

    // Rest shape along root-local z; the root frame turns local z onto world x.
    let rest: Vec<Vector3<f32>> = (0..=segments)
        .map(|i| Vector3::new(0.0, 0.0, (seg * i as f64) as f32))
        .collect();
    let mut inv_mass = vec![(1.0 / (density * seg)) as f32; segments + 1];
    inv_mass[0] = 0.0;
    inv_mass[segments] *= 2.0;
    let stiffness = Stiffness::isotropic(ei, ei);
    let rod = RodStrand::new(&rest, &inv_mass, &vec![1e-3; segments + 1], &stiffness).unwrap();
    let root = Root {
        origin: V3::zeros(),
        rotation: UnitQuaternion::rotation_between(&V3::z(), &V3::x()).unwrap(),
    };
    let mut state: RodState = rod.rest_state(&root);
    assert!((state.x[segments] - V3::new(length, 0.0, 0.0)).norm() < 1e-7);

    // Bending over y towards +z: moment vector −y.
    let axis = -V3::y();
    let omega1 = 3.516 * (ei / (density * length.powi(4))).sqrt();
    let drag = 2.0 * omega1;
    let dt = 1.5e-4;
    let mut ws = Workspace::default();
    let mut external = vec![V3::zeros(); segments + 1];
    let mut worst_residual = 0.0f64;
    for _ in 0..(2.0 / dt) as usize {
        let e = state.x[segments] - state.x[segments - 1];
        let f = axis.cross(&e.normalize()) * (moment / e.norm());
        external[segments] = f;
        external[segments - 1] = -f;
        let input = Substep {
            dt,
            gravity: V3::zeros(),
            air_drag: drag,
            stiffness: &stiffness,
            root_start: root,
            root_end: root,
            max_iterations: 20,
            tolerance: 1e-10,
            colliders: None,
            external: Some(&external),
            torque: None,
        };
        let out = rod.substep(&mut state, &input, &mut ws);
        assert!(out.projection.converged, "{out:?}");
        worst_residual = worst_residual.max(out.projection.residual);
    }
    let speed = state.v.iter().map(|v| v.norm()).fold(0.0, f64::max);
    let radius = length / t;
    let mut worst = 0.0f64;
    for (i, x) in state.x.iter().enumerate() {
        let s = seg * i as f64;
        let expected = V3::new(
            radius * (s / radius).sin(),
            0.0,
            radius * (1.0 - (s / radius).cos()),
        );
        worst = worst.max((x - expected).norm());
    }
    let tip = state.x[segments];
    println!(
        "tip moment t = ML/EI = {t}: tip at u = {:.5} m, v = {:.5} m; analytic u = {:.5} m, \
         v = {:.5} m; worst node error {:.2e} m = {:.3} % of L; residual speed {speed:.1e} m/s; \
         projection residual ≤ {worst_residual:.1e}",
        tip.x - length,
        tip.z,
        length * (t.sin() / t - 1.0),
        radius * (1.0 - t.cos()),
        worst,
        100.0 * worst / length,
    );
    assert!(speed < 1e-4, "not at rest: {speed} m/s");
    assert!(worst < 0.01 * length, "worst node error {worst} m");
}
