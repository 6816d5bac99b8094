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

use std::path::PathBuf;

use hair_core::{RodParams, RodSolver};
use hairsys::scene::SceneFile;
use nalgebra::{Point3, Vector3};
use parry3d::math::Vector;
use parry3d::query::PointQuery;
use parry3d::shape::{TriMesh, TriMeshFlags};

const SCENE: &str = r#"
[scene]
name = "head turning at 10 rad/s, rod model"
fps = 24.0
frames = [1, 25]

[physics]
air_drag = 2.0

[scalp.mesh]
kind = "builtin-head"

[scalp.collider]
thickness = 0.0
friction = 0.3

[scalp.motion]
interpolation = "linear"
keys = [
    { frame = 1,  rotation_deg = [0.0, 0.0, 0.0] },
    { frame = 25, rotation_deg = [0.0, 0.0, 572.9578] },
]

[hair]
count = 60
length = 0.2
segments = 12
seed = 3
radius = 0.002
mass_per_length = 0.001
length_variation = 0.2
region = { direction = [0.0, 0.3, 1.0], max_angle_deg = 95.0 }
"#;

#[test]
fn rod_head_turning_at_ten_rad_per_s_keeps_every_node_outside() {
    let scene = SceneFile::parse(SCENE, "rod_head_turning.toml", PathBuf::from(".")).unwrap();
    let mut sim = scene.build().unwrap();
    let first = sim.first_frame;
    let mut colliders = sim.colliders_at(first as f32).unwrap();
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

    let head = hair_groom::builtin_head();
    let to_parry = |v: &Vector3<f32>| Vector::new(v.x, v.y, v.z);
    let vertices = head.positions().iter().map(to_parry).collect();
    let mesh =
        TriMesh::with_flags(vertices, head.triangles().to_vec(), TriMeshFlags::ORIENTED).unwrap();
    let radius = sim.strands.radii()[0];

    let mut worst_gap = f32::INFINITY;
    let (mut inside_points, mut contacts, mut max_strain) = (0usize, 0u64, 0.0f64);
    for frame in first + 1..=sim.last_frame {
        let scalp = sim.scalp_at(frame as f32);
        sim.pose_colliders(&mut colliders, frame as f32).unwrap();
        let report = solver
            .step_frame_with_colliders(&mut sim.strands, &scalp, &mut colliders)
            .unwrap();
        contacts += report.frame.contact_points;
        max_strain = max_strain.max(report.projection.max_strain);
        let inverse = scalp.body.inverse();
        for (x, &w) in sim
            .strands
            .positions
            .iter()
            .zip(sim.strands.inverse_masses())
        {
            if w == 0.0 {
                continue;
            }
            let local = inverse * Point3::from(*x);
            let proj = mesh.project_local_point(to_parry(&local.coords), false);
            let dist = (to_parry(&local.coords) - proj.point).length();
            let signed = if proj.is_inside { -dist } else { dist };
            worst_gap = worst_gap.min(signed);
            if proj.is_inside {
                inside_points += 1;
            }
        }
    }
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
