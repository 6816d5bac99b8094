//! The damping sub-loop damps stretching and nothing else.
//!
//! References:
//! - one free point on a spring from the root, stretch damping γ: the point's velocity along the
//!   segment decays as `exp(−γ t)` per substep (the sub-loop's design), so the oscillation is a
//!   damped oscillator `ẍ + γ ẋ + ω² x = 0` whose amplitude decays as `exp(−γ t / 2)`. For
//!   semi-implicit Euler followed by the exact per-substep decay this holds exactly: the update
//!   matrix has determinant `exp(−γ h)`, so each substep scales the amplitude by `exp(−γ h/2)`;
//! - in a chain, stretch damping removes energy from the stretch oscillation;
//! - damping acts on the relative velocity along each segment only, so motion without stretching
//!   is not slowed: a pendulum's swing (velocity across its segment) keeps its amplitude, and a
//!   strand carried at constant velocity keeps it.
//!
//! (Linear momentum conservation of the sub-loop, which the design asks for, cannot be checked on
//! a free-floating chain through the public API: every strand has a pinned root.)

mod common;

use common::*;
use hair_core::{energy, HairParams, Integrator, MassSpringSolver, Scalp, SolverSettings};
use nalgebra::{Isometry3, Vector3};

/// Local maxima of |y| in a sampled signal, as (t, |y|).
fn peaks(samples: &[(f64, f64)]) -> Vec<(f64, f64)> {
    samples
        .windows(3)
        .filter(|w| w[1].1.abs() > w[0].1.abs() && w[1].1.abs() >= w[2].1.abs())
        .map(|w| (w[1].0, w[1].1.abs()))
        .collect()
}

/// Least-squares slope of ln(y) against t.
fn log_slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let mt = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1.ln()).sum::<f64>() / n;
    let sxy: f64 = points.iter().map(|p| (p.0 - mt) * (p.1.ln() - my)).sum();
    let sxx: f64 = points.iter().map(|p| (p.0 - mt).powi(2)).sum();
    sxy / sxx
}

#[test]
fn single_segment_stretch_oscillation_decays_at_half_the_damping_rate() {
    let (k, m, gamma) = (1.0f64, 0.01f64, 2.0f64);
    let scalp = Scalp::fixed();
    let mut strands = set_on(
        &scalp,
        [strand(
            anchor_at(Vector3::zeros()),
            straight(1, 0.1, -Vector3::z()),
            vec![0.0, m as f32],
            root_only(2),
        )],
    );
    strands.positions[1].z -= 0.01;
    let mut params = bare_params(k as f32);
    params.stretch_damping = gamma as f32;
    let fps = 240.0f32;
    let settings = fixed_settings(fps, 10, Integrator::SemiImplicitEuler);
    let mut solver = MassSpringSolver::new(settings, params, &strands, &scalp, 0).unwrap();
    let mut samples = Vec::new();
    run(&mut solver, &mut strands, &scalp, 5 * 240, |s, set| {
        let stretch = (set.positions[1] - set.positions[0]).norm() as f64 - 0.1;
        samples.push((s.frame() as f64 / fps as f64, stretch));
    })
    .unwrap();
    let p = peaks(&samples);
    let rate = -log_slope(&p);
    let err = (rate - 0.5 * gamma).abs() / (0.5 * gamma);
    println!(
        "single segment: {} peaks over 5 s, amplitude decay rate {rate:.5}/s vs γ/2 = {:.5}/s \
         (rel. error {err:.2e}); ω = {:.2} rad/s",
        p.len(),
        0.5 * gamma,
        (k / m).sqrt()
    );
    assert!(p.len() >= 10);
    assert!(err < 0.01, "decay rate off by {:.2} %", 100.0 * err);
}

#[test]
fn stretch_damping_drains_a_chain_stretch_oscillation() {
    let run_chain = |damping: f32| -> (f64, f64) {
        let scalp = Scalp::fixed();
        let mut mass = vec![1e-3f32; 5];
        mass[0] = 0.0;
        let mut strands = set_on(
            &scalp,
            [strand(
                anchor_at(Vector3::zeros()),
                straight(4, 0.05, -Vector3::z()),
                mass,
                root_only(5),
            )],
        );
        for (i, d) in [0.002f32, -0.001, 0.003, 0.001].iter().enumerate() {
            strands.positions[i + 1].z -= d;
        }
        let mut params = bare_params(50.0);
        params.stretch_damping = damping;
        // h = 0.1 × the bound: undamped, semi-implicit Euler keeps the energy within
        // [(1−a)/(1+a), (1+a)/(1−a)] of its start, a = h ω_max / 2 ≤ 0.1 (see
        // spring_chain_energy.rs).
        let bound = MassSpringSolver::new(SolverSettings::default(), params, &strands, &scalp, 0)
            .unwrap()
            .bound();
        let substeps = (1.0 / (24.0 * 0.1 * bound.dt_max)).ceil() as u32;
        let settings = fixed_settings(24.0, substeps, Integrator::SemiImplicitEuler);
        let mut solver = MassSpringSolver::new(settings, params, &strands, &scalp, 0).unwrap();
        let e0 = energy(&strands, &params, solver.roots()).total();
        let mut last = 0.0;
        run(&mut solver, &mut strands, &scalp, 48, |s, set| {
            last = energy(set, &params, s.roots()).total();
        })
        .unwrap();
        (e0, last)
    };
    let (e0, undamped) = run_chain(0.0);
    let (_, damped) = run_chain(50.0);
    println!(
        "4-segment chain after 2 s: energy/initial {:.4} undamped, {:.3e} with stretch damping \
         50/s",
        undamped / e0,
        damped / e0
    );
    assert!(
        undamped / e0 > 0.9 / 1.1 && undamped / e0 < 1.1 / 0.9,
        "undamped chain left the energy band"
    );
    assert!(
        damped < 1e-3 * e0,
        "stretch damping left {:.3e} of the energy",
        damped / e0
    );
}

#[test]
fn pendulum_swing_is_not_slowed_by_stretch_damping() {
    // The swing of a stiff one-segment pendulum moves the bob across its segment; only the tiny
    // radial breathing is damped. Compare swing amplitudes over ten periods with and without
    // (strong) stretch damping.
    let swing = |damping: f32| -> (f64, f64) {
        let (length, theta0) = (0.5f32, 10.0f32.to_radians());
        let scalp = Scalp::fixed();
        let mut strands = set_on(
            &scalp,
            [strand(
                anchor_at(Vector3::zeros()),
                vec![
                    Vector3::zeros(),
                    Vector3::new(length * theta0.sin(), 0.0, -length * theta0.cos()),
                ],
                vec![0.0, 0.01],
                root_only(2),
            )],
        );
        let mut params = bare_params(1.0e4);
        params.gravity = gravity();
        params.stretch_damping = damping;
        let settings = fixed_settings(240.0, 10, Integrator::SemiImplicitEuler);
        let mut solver = MassSpringSolver::new(settings, params, &strands, &scalp, 0).unwrap();
        let mut samples = Vec::new();
        run(&mut solver, &mut strands, &scalp, 3400, |s, set| {
            samples.push((s.frame() as f64 / 240.0, set.positions[1].x as f64));
        })
        .unwrap();
        let p = peaks(&samples);
        (p[0].1, p[p.len() - 1].1)
    };
    let (first0, last0) = swing(0.0);
    let (first, last) = swing(50.0);
    println!(
        "pendulum over ~10 periods: swing amplitude kept {:.6} undamped, {:.6} with stretch \
         damping 50/s (an e-folding time of 20 ms on stretching)",
        last0 / first0,
        last / first
    );
    assert!(
        (last / first - 1.0).abs() < 1e-3,
        "stretch damping slowed the swing"
    );
}

#[test]
fn strand_carried_at_constant_velocity_is_not_slowed() {
    // The head moves at a constant 0.55 m/s; the strand starts with that velocity. Nothing
    // stretches, so stretch damping must leave the strand moving at that velocity. (Points
    // jitter by up to ~5e-3 m/s without damping, 1e-3 with: f32 rounding of positions (~6e-8 m
    // at 0.6 m) against springs ringing at ~6000 rad/s. The strand's mean velocity is the
    // clean measure.)
    let velocity = Vector3::new(0.5f32, -0.2, 0.1);
    let carried = |damping: f32| -> (f32, f32) {
        let fps = 24.0f32;
        let mut scalp = Scalp::fixed();
        let mut strands = set_on(
            &scalp,
            [hair_core::StrandInput::uniform(
                anchor_at(Vector3::zeros()),
                straight(10, 0.01, Vector3::new(1.0, 0.0, 1.0)),
                1e-3,
                1e-3,
                0.0,
                0.0,
            )],
        );
        for v in &mut strands.velocities {
            *v = velocity;
        }
        let params = HairParams {
            gravity: [0.0; 3],
            air_drag: 0.0,
            stretch_damping: damping,
            ..HairParams::default()
        };
        let mut solver =
            MassSpringSolver::new(SolverSettings::default(), params, &strands, &scalp, 0).unwrap();
        let (mut worst_mean, mut worst_point) = (0.0f32, 0.0f32);
        for f in 1..=24 {
            scalp.body = Isometry3::translation(
                velocity.x * f as f32 / fps,
                velocity.y * f as f32 / fps,
                velocity.z * f as f32 / fps,
            );
            solver.step_frame(&mut strands, &scalp).unwrap();
            let m = strands.masses();
            let total: f32 = m.iter().sum();
            let mean = strands
                .velocities
                .iter()
                .zip(m)
                .map(|(v, &m)| v * m)
                .sum::<Vector3<f32>>()
                / total;
            worst_mean = worst_mean.max((mean - velocity).norm());
            for v in &strands.velocities {
                worst_point = worst_point.max((v - velocity).norm());
            }
        }
        (worst_mean, worst_point)
    };
    let (mean0, point0) = carried(0.0);
    let (mean, point) = carried(200.0);
    println!(
        "strand carried at 0.55 m/s for 1 s: largest change of its mean velocity {mean0:.2e} m/s \
         undamped, {mean:.2e} m/s with stretch damping 200/s; of any point's {point0:.2e} / \
         {point:.2e} m/s"
    );
    // Damping the translation at 200/s would remove it within milliseconds; what is left is the
    // rounding jitter, the same size as without damping (1e-3 of the speed).
    assert!(
        mean < 1e-3 * velocity.norm(),
        "damping slowed a rigid translation"
    );
}
