//! The strain limit (`max_strain`): after every substep no segment is longer than
//! `(1 + max_strain) × rest length` (to the limiter's relative tolerance of 10⁻⁵), and with
//! `max_strain = 0` a soft-spring pendulum swings with the period of a rigid one, `2π √(L/g)`,
//! instead of that of its sagging spring length `L' = L + m g / k`.

mod common;

use common::*;
use hair_core::{Integrator, MassSpringSolver, Scalp};
use nalgebra::Vector3;

/// A horizontal chain of soft springs released under gravity: it swings down and whips.
/// Returns the largest elongation seen at any frame end.
fn swinging_chain(max_strain: Option<f32>) -> f32 {
    let segments = 12;
    let rest = straight(segments, 0.05, Vector3::x());
    let masses = vec![1e-3; segments + 1];
    let scalp = Scalp::fixed();
    let mut strands = set_on(
        &scalp,
        [strand(
            anchor_at(Vector3::zeros()),
            rest,
            masses,
            root_only(segments + 1),
        )],
    );
    let mut params = bare_params(20.0);
    params.gravity = gravity();
    let mut settings = fixed_settings(24.0, 60, Integrator::SemiImplicitEuler);
    settings.max_strain = max_strain;
    let mut solver = MassSpringSolver::new(settings, params, &strands, &scalp, 0).unwrap();
    assert!(solver.dt() < solver.bound().dt_max * 0.8);
    let mut worst = 0.0f32;
    run(&mut solver, &mut strands, &scalp, 48, |_, set| {
        worst = worst.max(set.max_stretch())
    })
    .unwrap();
    worst
}

#[test]
fn strain_limit_bounds_every_segment() {
    let free = swinging_chain(None);
    let limited = swinging_chain(Some(0.01));
    let inextensible = swinging_chain(Some(0.0));
    println!("max elongation: springs only {free:.4}, limit 1 % {limited:.6}, inextensible {inextensible:.2e}");
    assert!(
        free > 0.05,
        "the case must stretch well past the limit without it ({free})"
    );
    // The limit, its relative tolerance 1e-5, and 1e-6 for the f32 round-off of a length.
    assert!(
        limited <= 1.01 * (1.0 + 1e-5) - 1.0 + 1e-6,
        "limit 1 % exceeded: {limited}"
    );
    assert!(
        inextensible <= 1e-5 + 1e-6,
        "inextensible chain stretched by {inextensible}"
    );
}

#[test]
fn inextensible_soft_pendulum_has_the_rigid_period() {
    // A soft spring (m g / k = 20 % of L) would lengthen the period by ~10 %; with the limit at 0
    // the pendulum swings at 2π √(L/g).
    let (length, mass, k) = (0.5f64, 0.01f64, 1.0f64);
    let theta0 = 5.0f64.to_radians();
    let bob = Vector3::new(length * theta0.sin(), 0.0, -length * theta0.cos()).cast::<f32>();
    let scalp = Scalp::fixed();
    let input = strand(
        anchor_at(Vector3::zeros()),
        vec![Vector3::zeros(), bob],
        vec![0.0, mass as f32],
        root_only(2),
    );
    let mut strands = set_on(&scalp, [input]);
    let mut params = bare_params(k as f32);
    params.gravity = gravity();
    let fps = 240.0f32;
    let mut settings = fixed_settings(fps, 4, Integrator::SemiImplicitEuler);
    settings.max_strain = Some(0.0);
    let mut solver = MassSpringSolver::new(settings, params, &strands, &scalp, 0).unwrap();
    let t_rigid = 2.0 * std::f64::consts::PI * (length / G).sqrt();
    let t_sagging = 2.0 * std::f64::consts::PI * ((length + mass * G / k) / G).sqrt();
    let frames = (10.0 * t_rigid * fps as f64).ceil() as u32;
    let mut samples = vec![(0.0, strands.positions[1].x as f64)];
    run(&mut solver, &mut strands, &scalp, frames, |s, set| {
        samples.push((s.frame() as f64 / fps as f64, set.positions[1].x as f64));
    })
    .unwrap();
    let period = period_from_crossings(&zero_crossings(&samples));
    let err = (period - t_rigid).abs() / t_rigid;
    println!("inextensible pendulum: T = {period:.5} s, rigid 2π√(L/g) = {t_rigid:.5} s (error {err:.2e}), sagging spring would give {t_sagging:.5} s");
    assert!(
        err < 0.01,
        "period off the rigid one by {:.2} %",
        100.0 * err
    );
}
