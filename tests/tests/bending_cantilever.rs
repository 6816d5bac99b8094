//! Curvature bending: a horizontal cantilever sags as a beam and springs back, and a curved rest
//! shape is an exact equilibrium.
//!
//! Reference for the sag: joint j (the point between segments j − 1 and j) has the energy
//! `½ k |κ_j − κ⁰_j|²` with `|κ| = 2 tan(θ/2)` for a relative turn θ_j and `k = EI/l = k_b l²`
//! on this uniform strand (`hair_core::integrate::curvature`), so it carries the moment
//! `2 k tan(θ/2)/cos²(θ/2) = k θ_j (1 + θ_j²/4 + …)`. Statics of everything outboard of joint j
//! then gives `θ_j = M_j / (k_b l²)` to first order, where `M_j = g Σ_{i>j} m_i (x_i − x_j)` is the
//! moment of the weight beyond the joint about it: a discrete Euler–Bernoulli beam with
//! `EI = k_b l³`. The tip deflection is `Σ_j l sin φ_j` with `φ_j = Σ_{k≤j} θ_k`; the continuous
//! cantilever formula `ρ g L⁴ / 8 EI` is printed for comparison. Deflections are ~2 % of the
//! length (the largest joint turns by ~3·10⁻³ rad, so the θ²/4 term is 2·10⁻⁶ of the moment), so
//! the first-order statics are good to a few 10⁻³ (lever arms taken horizontal); the test allows
//! 2 %.
//!
//! With gravity switched off the strand must return to its rest shape, and a helix released at its
//! rest shape with gravity off must stay there (every spring is at rest: zero force).

mod common;

use common::*;
use hair_core::{Anchor, MassSpringSolver, RootFrame, Scalp, SolverSettings, StrandSet};
use nalgebra::{UnitQuaternion, Vector3};

/// Largest distance of any point from its rest position placed by its root frame, m.
fn distance_from_rest(strands: &StrandSet, scalp: &Scalp) -> f32 {
    let roots = strands.root_frames(scalp);
    (0..strands.len())
        .flat_map(|s| strands.points(s).map(move |i| (s, i)))
        .map(|(s, i)| (strands.positions[i] - roots[s].to_world(&strands.rest_local()[i])).norm())
        .fold(0.0, f32::max)
}

#[test]
fn horizontal_cantilever_sags_like_a_beam_and_springs_back() {
    let segments = 20;
    let seg_len = 0.01f64;
    let density = 0.01f64; // kg/m
    let k_bend = 5000.0f64;
    let point_mass = density * seg_len;
    let mut mass = vec![point_mass as f32; segments + 1];
    mass[segments] *= 0.5;
    let scalp = Scalp::fixed();
    // Rest shape along local z; the root frame turns local z onto world x.
    let anchor = anchor_along(Vector3::new(0.0, 0.0, 0.1), Vector3::x());
    let mut strands = set_on(
        &scalp,
        [strand(
            anchor,
            straight(segments, seg_len as f32, Vector3::z()),
            mass.clone(),
            root_only(segments + 1),
        )],
    );
    assert!((strands.positions[segments] - Vector3::new(0.2, 0.0, 0.1)).norm() < 1e-6);

    let mut params = bare_params(100.0);
    params.bend_stiffness = k_bend as f32;
    params.gravity = gravity();
    params.air_drag = 20.0;
    params.stretch_damping = 50.0;
    let mut solver =
        MassSpringSolver::new(SolverSettings::default(), params, &strands, &scalp, 0).unwrap();
    // 2 s; the slowest bending mode (≈ 60 rad/s) decays at least as exp(−drag·t/2) = e⁻²⁰.
    run(&mut solver, &mut strands, &scalp, 48, |_, _| {}).unwrap();

    // First-order statics of the spring model (horizontal lever arms).
    let n = segments;
    let mut phi = 0.0;
    let mut predicted = 0.0;
    for j in 0..n {
        let moment: f64 = (j + 1..=n)
            .map(|i| G * mass[i] as f64 * (i - j) as f64 * seg_len)
            .sum();
        phi += moment / (k_bend * seg_len * seg_len);
        predicted += seg_len * phi.sin();
    }
    let length = seg_len * n as f64;
    let beam = density * G * length.powi(4) / (8.0 * k_bend * seg_len.powi(3));
    let sag = 0.1 - strands.positions[n].z as f64;
    let err = (sag - predicted).abs() / predicted;
    println!(
        "cantilever: tip sag {sag:.5e} m, spring-model statics {predicted:.5e} m (rel. error \
         {err:.2e}), continuous beam ρgL⁴/8EI {beam:.5e} m; sag/length {:.3} %; substeps/frame {}",
        100.0 * sag / length,
        solver.substeps()
    );
    assert!(
        sag > 0.0 && sag < 0.05 * length,
        "sag {sag} m is not slight"
    );
    assert!(
        err < 0.02,
        "sag off the beam statics by {:.2} %",
        100.0 * err
    );

    // Gravity off: it must spring back to the rest shape.
    params.gravity = [0.0; 3];
    let mut solver =
        MassSpringSolver::new(SolverSettings::default(), params, &strands, &scalp, 48).unwrap();
    run(&mut solver, &mut strands, &scalp, 48, |_, _| {}).unwrap();
    let back = distance_from_rest(&strands, &scalp);
    println!("cantilever without gravity: largest distance from rest {back:.2e} m");
    assert!(
        back < 1e-6 * length as f32 * 10.0,
        "did not return to rest ({back} m)"
    );
}

#[test]
fn curved_rest_shape_is_an_equilibrium() {
    // A helix of 24 segments rooted on a tilted frame away from the origin, undamped, no gravity:
    // every spring starts at its rest length and direction, so nothing may move.
    let rest: Vec<Vector3<f32>> = (0..25)
        .map(|i| {
            let a = i as f32 * 0.6;
            Vector3::new(0.02 * (a.cos() - 1.0), 0.02 * a.sin(), 0.008 * i as f32)
        })
        .collect();
    let n = rest.len();
    let anchor = Anchor::Body(RootFrame {
        origin: Vector3::new(0.03, -0.02, 0.05),
        rotation: UnitQuaternion::from_scaled_axis(Vector3::new(0.4, -0.7, 0.2)),
    });
    let scalp = Scalp::fixed();
    let mut strands = set_on(&scalp, [strand(anchor, rest, vec![1e-4; n], root_only(n))]);
    let mut params = bare_params(200.0);
    params.bend_stiffness = 20.0;
    let mut solver =
        MassSpringSolver::new(SolverSettings::default(), params, &strands, &scalp, 0).unwrap();
    let mut worst = 0.0f32;
    run(&mut solver, &mut strands, &scalp, 100, |_, set| {
        worst = worst.max(distance_from_rest(set, &scalp));
    })
    .unwrap();
    let speed = strands
        .velocities
        .iter()
        .map(|v| v.norm())
        .fold(0.0f32, f32::max);
    println!(
        "helix at rest, {} substeps undamped: largest distance from rest {worst:.2e} m, \
         largest speed {speed:.2e} m/s",
        100 * solver.substeps()
    );
    // Only f32 rounding moves it: ~1e-8 m per substep, random-walking in the undamped strand to
    // ~5e-7 m after 8,800 substeps. A strand that was not at equilibrium would move millimetres.
    assert!(worst < 1e-6, "helix drifted {worst} m from its rest shape");
}
