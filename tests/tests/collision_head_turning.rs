//! Fast motion: the built-in head, its own scalp as collider, turning at 10 rad/s about the
//! vertical (24° per frame at 24 fps) from rest, with 300 strands that fall onto it and are flung
//! around it. Every hair point must be outside the head mesh at every frame.
//!
//! Reference: an independent check with parry — the head mesh as an oriented parry `TriMesh`
//! posed at each frame's transform, each free point's signed distance to it by point projection
//! (pseudo-normal inside test). The solver aims at a gap of one hair radius (2 mm); the test
//! requires every point centre outside the mesh and prints the worst penetration and the smallest
//! gap. The scene is loaded from TOML like `hairsys simulate` does (`[scalp.collider]`).

mod common;

use common::collide::{run_with_colliders, turning_head_scene, Gap, ParryHead, SPRING_PHYSICS};

#[test]
fn head_turning_at_ten_rad_per_s_keeps_every_hair_point_outside() {
    let scene = turning_head_scene("head turning at 10 rad/s", 25, 300, SPRING_PHYSICS);
    let mut sim = scene.build().unwrap();
    let head = ParryHead::new(&hair_groom::builtin_head());
    let radius = sim.strands.radii()[0];

    let mut gap = Gap::NONE;
    let (mut max_steps, mut contacts) = (0u32, 0u64);
    let last = sim.last_frame;
    run_with_colliders(&mut sim, last, |_, sim, scalp, report| {
        max_steps = max_steps.max(report.steps);
        contacts += report.contact_points;
        gap = gap.merge(head.free_point_gap(&scalp.body, &sim.strands));
    });
    let (worst_gap, inside_points) = (gap.smallest, gap.inside);
    println!(
        "head at 10 rad/s: up to {max_steps} collision steps per frame, {contacts} point contacts \
         in all; smallest gap between a point centre and the head over 24 frames: {:.3} mm \
         (target: hair radius {:.1} mm); worst penetration {:.3} mm; points inside: {inside_points}",
        worst_gap * 1e3,
        radius * 1e3,
        (-worst_gap).max(0.0) * 1e3
    );
    assert!(max_steps > 1, "10 rad/s must trigger finer collision steps");
    assert!(contacts > 0);
    assert_eq!(inside_points, 0, "smallest gap {worst_gap} m");
}
