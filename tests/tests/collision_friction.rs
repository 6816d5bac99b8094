//! Friction against a moving surface: hair draped over a sphere spinning about the vertical is
//! dragged along the spin with friction and slides (stays put) without.
//!
//! Eight strands hang from roots just above the north pole of a sphere (R = 0.1 m) and drape down
//! its +x side. The sphere spins about z at 4 rad/s, so under the hair its surface moves along +y
//! at up to 0.4 m/s. References: without friction the contact forces are radial and lie in the
//! x–z plane of the strands, so no point may move along y (0 by symmetry, up to the f32 rounding
//! of the spinning sphere's pose: under 0.1 mm); with
//! μ = 0.5 the friction impulse (at most μ times the normal one) drags the hair towards +y until
//! the strands' pull back towards their roots balances it.

mod common;

use common::*;
use hair_core::{
    Collider, Colliders, HairParams, MassSpringSolver, Scalp, SolverSettings, StrandInput,
};
use nalgebra::{Isometry3, UnitQuaternion, Vector3};

const R: f32 = 0.1;
const FPS: f32 = 60.0;
const SPIN: f32 = 4.0;

/// Mean and largest y (m) of the free points after 2 s on a sphere with friction `mu`.
fn drag(mu: f32) -> (f32, f32) {
    let inputs = (0..8).map(|k| {
        let x = 0.002 * k as f32;
        let root = Vector3::new(x, 0.0, R + 0.004);
        let rest = straight(16, 0.0125, Vector3::x());
        StrandInput::uniform(anchor_at(root), rest, 1e-3, 0.002, 0.0, 0.0)
    });
    let scalp = Scalp::fixed();
    let mut strands = set_on(&scalp, inputs);
    let params = HairParams {
        gravity: gravity(),
        stretch_stiffness: 40.0,
        bend_stiffness: 0.02,
        goal_stiffness: 0.0,
        stretch_damping: 200.0,
        air_drag: 1.0,
    };
    let settings = SolverSettings {
        fps: FPS,
        ..SolverSettings::default()
    };
    let mut solver = MassSpringSolver::new(settings, params, &strands, &scalp, 0).unwrap();
    let mut colliders = Colliders::new();
    let ball = colliders
        .insert(Collider::sphere(R).with_friction(mu), Isometry3::identity())
        .unwrap();
    for f in 1..=(2.0 * FPS) as u32 {
        let angle = SPIN * f as f32 / FPS;
        let pose = Isometry3::from_parts(
            Default::default(),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), angle),
        );
        colliders.set_pose(ball, pose).unwrap();
        solver
            .step_frame_with_colliders(&mut strands, &scalp, &mut colliders)
            .unwrap();
    }
    let free: Vec<f32> = (0..strands.point_count())
        .filter(|&i| strands.inverse_masses()[i] > 0.0)
        .map(|i| strands.positions[i].y)
        .collect();
    let mean = free.iter().sum::<f32>() / free.len() as f32;
    let max = free.iter().fold(0.0f32, |a, y| a.max(y.abs()));
    (mean, max)
}

#[test]
fn spinning_sphere_drags_hair_with_friction_and_not_without() {
    let (mean_free, max_free) = drag(0.0);
    let (mean_rough, max_rough) = drag(0.5);
    println!(
        "spinning sphere, surface speed up to {:.2} m/s: mean y of the hair {:.2e} m (largest \
         |y| {max_free:.2e} m) without friction, {mean_rough:.4} m (largest {max_rough:.4} m) with μ = 0.5",
        SPIN * R,
        mean_free
    );
    assert!(
        max_free < 1e-4,
        "frictionless contact moved hair sideways by {max_free} m"
    );
    assert!(
        mean_rough > 0.01,
        "friction should drag the hair along +y, mean y = {mean_rough} m"
    );
}
