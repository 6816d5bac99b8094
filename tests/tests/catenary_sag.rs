//! A chain pinned at both ends settles to the catenary.
//!
//! Reference: a uniform inextensible chain of length S hung between two points at the same height
//! a span D apart takes the shape `z(x) = a cosh((x − D/2)/a) − a cosh(D/2a)`, where the catenary
//! parameter a solves `2 a sinh(D/2a) = S` (solved here by bisection). The simulated chain has 40
//! segments with equal lumped point masses (the discrete chain's nodes lie on the continuous
//! curve up to O(1/N²)), no bending, and stiff stretch springs: the largest tension, about
//! ρ g a cosh(D/2a) ≈ 0.25 N, stretches a segment by ~1e-4 of its length, which changes the sag
//! by ~5e-5 of the span, so the rest length is used as S. Air drag and stretch damping bring it to
//! rest; the released shape is a V of the right length. Criterion: the largest vertical distance
//! between the settled points and the catenary, divided by the span, below 1 %.

mod common;

use common::*;
use hair_core::{MassSpringSolver, Scalp, SolverSettings, Substeps};
use nalgebra::Vector3;

#[test]
fn chain_pinned_at_both_ends_settles_to_the_catenary() {
    let span = 0.8f64;
    let length = 1.0f64;
    let segments = 40;
    let seg_len = length / segments as f64;
    let density = 0.04f64; // kg/m
    let k = 1.0e5f64;

    // Released as a V of the full length: two straight halves meeting below the middle.
    let cos_a = span / length;
    let sin_a = (1.0 - cos_a * cos_a).sqrt();
    let rest: Vec<Vector3<f32>> = (0..=segments)
        .map(|i| {
            let along = seg_len * i.min(segments - i) as f64;
            let x = if i <= segments / 2 {
                seg_len * i as f64 * cos_a
            } else {
                span - seg_len * (segments - i) as f64 * cos_a
            };
            Vector3::new(x, 0.0, -along * sin_a).cast()
        })
        .collect();
    let mut pinned = root_only(segments + 1);
    pinned[segments] = true;
    let mass = vec![(density * seg_len) as f32; segments + 1];
    let scalp = Scalp::fixed();
    let mut strands = set_on(
        &scalp,
        [strand(anchor_at(Vector3::zeros()), rest, mass, pinned)],
    );

    let mut params = bare_params(k as f32);
    params.gravity = gravity();
    params.air_drag = 10.0;
    params.stretch_damping = 50.0;
    let settings = SolverSettings {
        substeps: Substeps::Auto,
        ..SolverSettings::default()
    };
    let mut solver = MassSpringSolver::new(settings, params, &strands, &scalp, 0).unwrap();
    // 3 s: the slowest swing (ω ≈ √(g/sag) ≈ 6 rad/s) decays as exp(−drag·t/2) = e⁻¹⁵.
    // (Speeds do not go to zero: rounding f32 positions by an ulp, ~6e-8 m, against k = 1e5 N/m
    // keeps the stiff stretch modes ringing at ~4e-3 m/s, i.e. ~4e-7 m of motion. Settling is
    // judged by how far the points still move in the last half second.)
    run(&mut solver, &mut strands, &scalp, 60, |_, _| {}).unwrap();
    let before = strands.positions.clone();
    run(&mut solver, &mut strands, &scalp, 12, |_, _| {}).unwrap();
    let moved = before
        .iter()
        .zip(&strands.positions)
        .map(|(a, b)| (a - b).norm())
        .fold(0.0f32, f32::max);

    let a = catenary_parameter(span, length);
    let mut worst = 0.0f64;
    let mut sag = 0.0f64;
    for p in &strands.positions {
        let p = p.cast::<f64>();
        let dev = (p.z - catenary_height(a, span, p.x)).abs();
        worst = worst.max(dev);
        sag = sag.max(-p.z);
    }
    let expected_sag = -catenary_height(a, span, 0.5 * span);
    let speed = strands
        .velocities
        .iter()
        .map(|v| v.norm())
        .fold(0.0f32, f32::max);
    let max_y = strands
        .positions
        .iter()
        .map(|p| p.y.abs())
        .fold(0.0f32, f32::max);
    println!(
        "catenary: a = {a:.5} m; sag measured {sag:.5} m vs analytic {expected_sag:.5} m; max \
         vertical deviation {worst:.3e} m = {:.4} % of span (limit 1 %); max stretch {:.2e}; \
         moved {moved:.2e} m in the last 0.5 s; max speed {speed:.2e} m/s; substeps/frame {}",
        100.0 * worst / span,
        strands.max_stretch(),
        solver.substeps()
    );
    assert!(
        moved < 1e-5,
        "chain has not settled (moved {moved} m in 0.5 s)"
    );
    assert!(max_y < 1e-6, "chain left its plane");
    assert!(
        worst / span < 0.01,
        "deviation {:.3} % of span",
        100.0 * worst / span
    );
}
