//! The bending force is the gradient of the bending energy, `F = −∂E/∂x` with
//! `E = Σ_j ½ k_j |κ_j − κ⁰_j|²` (`κ_j` the curvature binormal at point j, `κ⁰_j` its rest value
//! in segment j − 1's parallel-transported frame, as `hair_core::energy` computes it; see
//! `hair_core::integrate::curvature`), at small turns and at turns of up to 150°, where the
//! curvature energy is far from its small-angle form.
//!
//! A force field that is not a gradient does work around closed loops: an undamped strand then
//! gains energy by itself (flutter) instead of oscillating about its rest shape. Reference:
//! central finite differences of `energy(..).bend` (step 5e-5 m) at a deformed helix, a
//! deformed straight strand and a deformed folded strand; the solver's force comes from one
//! substep from rest with unit masses, `F = v / dt`. Tolerance 1e-3 of the largest force: the
//! finite differences carry O(h²) truncation and f32 rounding of ~1e-5 relative. The folded
//! strand's energy is far from quadratic (`tan²(θ/2)` near 150°), so its truncation is the
//! largest: measured 7.8e-3, 1.9e-3, 5.6e-4 and 3.8e-4 of the largest force at steps of 2e-4,
//! 1e-4, 5e-5 and 2.5e-5 m (falling as h² down to the f32 rounding floor).

mod common;

use common::*;
use hair_core::{energy, MassSpringSolver, Scalp, SolverSettings, StrandSet, Substeps};
use nalgebra::{UnitQuaternion, Vector3};

fn compare(name: &str, rest: Vec<Vector3<f32>>) -> f64 {
    let n = rest.len();
    let anchor = hair_core::Anchor::Body(hair_core::RootFrame {
        origin: Vector3::new(0.01, 0.02, -0.03),
        rotation: UnitQuaternion::from_scaled_axis(Vector3::new(0.3, 0.5, -0.4)),
    });
    let scalp = Scalp::fixed();
    let mut strands = set_on(&scalp, [strand(anchor, rest, vec![1.0; n], root_only(n))]);
    // A smooth, deterministic deformation of every free point (a few mm).
    for i in 1..n {
        let a = i as f32;
        strands.positions[i] +=
            Vector3::new((1.3 * a).sin(), (2.1 * a).cos(), (0.7 * a + 1.0).sin()) * 2e-3;
    }
    let mut params = bare_params(0.0);
    params.bend_stiffness = 1.0;
    let settings = SolverSettings {
        fps: 1.0e4,
        steps: 1,
        substeps: Substeps::Fixed(1),
        damping_iterations: 0,
        ..SolverSettings::default()
    };
    let mut solver = MassSpringSolver::new(settings, params, &strands, &scalp, 0).unwrap();
    let bend_energy = |set: &StrandSet| energy(set, &params, solver.roots()).bend;

    let h = 5e-5f32;
    let fd: Vec<Vector3<f64>> = (0..n)
        .map(|i| {
            Vector3::from_fn(|c, _| {
                if i == 0 {
                    return 0.0; // the root is pinned
                }
                let mut plus = strands.clone();
                plus.positions[i][c] += h;
                let mut minus = strands.clone();
                minus.positions[i][c] -= h;
                -(bend_energy(&plus) - bend_energy(&minus)) / (2.0 * h as f64)
            })
        })
        .collect();
    let dt = solver.dt();
    solver.step_frame(&mut strands, &scalp).unwrap();
    let scale = fd.iter().map(|f| f.norm()).fold(0.0, f64::max);
    let mut worst = 0.0f64;
    for (v, f) in strands.velocities.iter().zip(&fd).skip(1) {
        worst = worst.max((v.cast::<f64>() / dt - f).norm() / scale);
    }
    println!(
        "{name}: largest |F − (−∇E)| = {worst:.2e} × largest force ({scale:.3e} N), limit 1e-3"
    );
    worst
}

#[test]
fn bending_force_is_minus_the_gradient_of_bending_energy() {
    let helix: Vec<Vector3<f32>> = (0..16)
        .map(|i| {
            let a = i as f32 * 0.6;
            Vector3::new(0.02 * (a.cos() - 1.0), 0.02 * a.sin(), 0.008 * i as f32)
        })
        .collect();
    let straight_rest = straight(15, 0.01, Vector3::z());
    // Turns of 150° alternating with 60° about an axis that precesses: a folded, twisted strand.
    let mut folded = vec![Vector3::zeros()];
    let mut dir = Vector3::z();
    for i in 0..12 {
        let turn = if i % 2 == 0 { 150f32 } else { 60f32 }.to_radians();
        let axis = Vector3::new((0.5 * i as f32).cos(), (0.5 * i as f32).sin(), 0.3);
        let axis = (axis - dir * axis.dot(&dir)).normalize();
        dir =
            nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), turn) * dir;
        let last = *folded.last().unwrap();
        folded.push(last + dir * 0.01);
    }
    let e_helix = compare("deformed helix", helix);
    let e_straight = compare("deformed straight strand", straight_rest);
    let e_folded = compare("deformed folded strand (turns of 150°)", folded);
    assert!(e_folded < 1e-3, "folded strand: bending force is not −∇E");
    assert!(
        e_straight < 1e-3,
        "straight strand: bending force is not −∇E"
    );
    assert!(e_helix < 1e-3, "helix: bending force is not −∇E");
}

/// An undamped strand with bending springs swinging under gravity keeps its energy: released
/// horizontally (straight, and as a helix), 20,000 substeps at 0.2 × the stability bound. The
/// energy scale is `M g L` (what the fall can release); semi-implicit Euler's energy error at
/// `h ω_max = 0.4` stays a bounded oscillation, which must stay below 5 % of it. Non-conservative
/// bending forces grow it without bound instead (flutter).
#[test]
fn undamped_bent_strand_keeps_its_energy() {
    let helix: Vec<Vector3<f32>> = (0..17)
        .map(|i| {
            let a = i as f32 * 0.6;
            Vector3::new(0.02 * (a.cos() - 1.0), 0.02 * a.sin(), 0.008 * i as f32)
        })
        .collect();
    for (name, rest) in [
        ("straight", straight(16, 0.01, Vector3::z())),
        ("helix", helix),
    ] {
        let n = rest.len();
        let scalp = Scalp::fixed();
        let mut mass = vec![1e-5f32; n];
        mass[0] = 0.0;
        let mut strands = set_on(
            &scalp,
            [strand(
                anchor_along(Vector3::zeros(), Vector3::x()),
                rest,
                mass,
                root_only(n),
            )],
        );
        let mut params = bare_params(50.0);
        params.gravity = gravity();
        params.bend_stiffness = 0.5;
        let bound = MassSpringSolver::new(SolverSettings::default(), params, &strands, &scalp, 0)
            .unwrap()
            .bound();
        let h = 0.2 * bound.dt_max;
        let settings = SolverSettings {
            fps: (1.0 / (100.0 * h)) as f32,
            steps: 1,
            substeps: Substeps::Fixed(100),
            damping_iterations: 0,
            ..SolverSettings::default()
        };
        let mut solver = MassSpringSolver::new(settings, params, &strands, &scalp, 0).unwrap();
        let e0 = energy(&strands, &params, solver.roots()).total();
        let total_mass: f64 = strands.masses().iter().map(|&m| m as f64).sum();
        let scale = total_mass * G * strands.rest_strand_length(0) as f64;
        let mut worst = 0.0f64;
        run(&mut solver, &mut strands, &scalp, 200, |s, set| {
            let e = energy(set, &params, s.roots()).total();
            worst = worst.max((e - e0).abs() / scale);
        })
        .unwrap();
        println!(
            "{name} strand with bending, undamped, 20,000 substeps: largest |E − E0| = {worst:.3e} \
             × M g L (limit 5e-2)"
        );
        assert!(worst < 0.05, "{name}: energy changed by {worst:.3e} M g L");
    }
}
