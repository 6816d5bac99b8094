//! Rod model, head collision (seed 002, "Hair-Head Collisions"): the built-in head, its own scalp
//! as collider, turning at 10 rad/s about the vertical from rest, with strands that fall onto it
//! and are flung around it. No node may be inside the head after the projection, at any frame,
//! and segments keep their length meanwhile.
//!
//! Reference: the same independent check as the mass-spring version
//! (`collision_head_turning.rs`): the head mesh as an oriented parry `TriMesh` posed at each
//! frame's transform, each free node's signed distance to it by point projection (pseudo-normal
//! inside test). The rod keeps node centres a hair radius (2 mm) off the surface; the test
//! requires every centre outside and prints the smallest gap. Fewer strands than the mass-spring
//! test (60), because the rod model is the accurate, costly alternative.

mod common;

use common::collide::{run_posed, turning_head_scene, Gap, ParryHead};
use hair_core::{RodParams, RodSolver};

#[test]
fn rod_head_turning_at_ten_rad_per_s_keeps_every_node_outside() {
    let scene = turning_head_scene(
        "head turning at 10 rad/s, rod model",
        25,
        60,
        "air_drag = 2.0",
    );
    let mut sim = scene.build().unwrap();
    let first = sim.first_frame;
    // A wisp-sized section (0.15 mm semi-major axis) keeps the substeps few.
    let rod = RodParams {
        semi_major_axis: 1.5e-4,
        ..RodParams::default()
    };
    let mut solver = RodSolver::new(
        sim.settings,
        sim.params,
        rod,
        &sim.strands,
        &sim.scalp_at(first as f32),
        first,
    )
    .unwrap();

    let head = ParryHead::new(&hair_groom::builtin_head());
    let radius = sim.strands.radii()[0];

    let mut gap = Gap::NONE;
    let (mut contacts, mut max_strain) = (0u64, 0.0f64);
    let last = sim.last_frame;
    run_posed(
        &mut sim,
        last,
        |strands, scalp, colliders| {
            solver
                .step_frame_with_colliders(strands, scalp, colliders)
                .unwrap()
        },
        |_, sim, scalp, report| {
            contacts += report.frame.contact_points;
            max_strain = max_strain.max(report.projection.max_strain);
            gap = gap.merge(head.free_point_gap(&scalp.body, &sim.strands));
        },
    );
    let (worst_gap, inside_points) = (gap.smallest, gap.inside);
    println!(
        "rod, head at 10 rad/s: {} substeps/frame, {contacts} nodes in contact (per substep, summed over frames); \
         smallest gap between a node and the head over 24 frames: {:.3} mm (target: hair \
         radius {:.1} mm); nodes inside: {inside_points}; max strain {max_strain:.2e}",
        solver.substeps(),
        worst_gap * 1e3,
        radius * 1e3,
    );
    assert!(contacts > 0, "the hair must reach the head");
    assert_eq!(inside_points, 0, "smallest gap {worst_gap} m");
    assert!(max_strain < 1e-4, "max strain {max_strain}");
}
