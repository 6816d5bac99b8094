//! Where methods fail: hair that starts inside a collider. It must be pushed out within a bounded
//! number of frames, without explosion and without being shot away.
//!
//! Eight strands hang straight down through a sphere collider (R = 8 cm) that already swallows
//! their lower half at the first frame, some points 6 cm deep. A penetrating point is moved out as
//! a position correction that leaves no outward velocity, at most `max_push_speed` (1 m/s) × dt per
//! substep (`contacts::penalty`). References: 6 cm at 1 m/s take 60 ms, so by the end of frame 2
//! (83 ms at 24 fps) every point centre is outside the sphere (gap ≥ −0.1 mm: the sphere grown by
//! the hair radius is the target, the bare sphere the bound) and stays out; the fastest point
//! stays below 8 m/s (measured: about 5 m/s, the recoil of strands pulled apart across the
//! sphere; removing the penetration in one substep flung them at 27 m/s, and keeping the push-out
//! as velocity would give depth/dt ≈ 300 m/s), and the run never reports a blow-up.
//!
//! The scene runs 2 collision steps per frame: the untangled strands whip, and at 1 step per
//! frame (42 ms) a whipping point was measured to outrun its detection margin (it started the
//! frame 9.5 cm away at 0.9 m/s, margin 9.3 cm) and end a frame 6 mm inside, to be pushed out
//! again in the next (a documented limit of `contacts::detect`).

mod common;

use common::*;
use hair_core::{
    Collider, Colliders, HairParams, MassSpringSolver, Scalp, SolverSettings, StrandInput,
};
use nalgebra::{Isometry3, Vector3};

#[test]
fn hair_starting_inside_a_sphere_is_pushed_out_without_explosion() {
    let r = 0.08f32;
    let centre = Vector3::new(0.02, 0.0, 0.0);
    let inputs = (0..8).map(|k| {
        let root = Vector3::new(-0.012 + 0.004 * k as f32, 0.003 * k as f32, 0.15);
        let rest = straight(20, 0.01, -Vector3::z());
        StrandInput::uniform(anchor_at(root), rest, 1e-3, 0.001, 0.0, 0.0)
    });
    let scalp = Scalp::fixed();
    let mut strands = set_on(&scalp, inputs);
    let gap = |x: &Vector3<f32>| (x - centre).norm() - r;
    let deepest = strands.positions.iter().map(gap).fold(0.0f32, f32::min);
    let params = HairParams {
        gravity: gravity(),
        stretch_stiffness: 40.0,
        bend_stiffness: 0.05,
        goal_stiffness: 0.0,
        stretch_damping: 200.0,
        air_drag: 1.0,
    };
    let settings = SolverSettings {
        fps: 24.0,
        steps: 2,
        ..SolverSettings::default()
    };
    let mut solver = MassSpringSolver::new(settings, params, &strands, &scalp, 0).unwrap();
    let mut colliders = Colliders::new();
    colliders
        .insert(
            Collider::sphere(r),
            Isometry3::translation(centre.x, centre.y, centre.z),
        )
        .unwrap();
    let mut first_outside = None;
    let mut max_speed = 0.0f32;
    for f in 1..=24 {
        solver
            .step_frame_with_colliders(&mut strands, &scalp, &mut colliders)
            .expect("no blow-up");
        let worst = strands
            .positions
            .iter()
            .zip(strands.inverse_masses())
            .filter(|(_, &w)| w > 0.0)
            .map(|(x, _)| gap(x))
            .fold(f32::INFINITY, f32::min);
        max_speed = strands
            .velocities
            .iter()
            .map(|v| v.norm())
            .fold(max_speed, f32::max);
        if worst >= -1e-4 && first_outside.is_none() {
            first_outside = Some(f);
        }
        if first_outside.is_some() {
            assert!(
                worst >= -1e-4,
                "frame {f}: a point went back in ({worst} m)"
            );
        }
    }
    println!(
        "start inside: deepest point {:.1} mm inside at frame 0; every point outside from frame \
         {} on; fastest point over 1 s {max_speed:.2} m/s",
        -deepest * 1e3,
        first_outside.map_or("never".to_string(), |f| f.to_string())
    );
    assert!(deepest < -0.05, "the setup should start deep inside");
    assert!(
        first_outside.is_some_and(|f| f <= 2),
        "not pushed out by frame 2 ({first_outside:?})"
    );
    assert!(
        max_speed < 8.0,
        "pushed-out hair was shot away at {max_speed} m/s"
    );
}
