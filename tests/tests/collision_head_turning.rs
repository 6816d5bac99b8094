//! Fast motion: the built-in head, its own scalp as collider, turning at 10 rad/s about the
//! vertical (24° per frame at 24 fps) from rest, with 300 strands that fall onto it and are flung
//! around it. Every hair point must be outside the head mesh at every frame.
//!
//! Reference: an independent check with parry — the head mesh as an oriented parry `TriMesh`
//! posed at each frame's transform, each free point's signed distance to it by point projection
//! (pseudo-normal inside test). The solver aims at a gap of one hair radius (2 mm); the test
//! requires every point centre outside the mesh and prints the worst penetration and the smallest
//! gap. The scene is loaded from TOML like `hairsys simulate` does (`[scalp.collider]`).

use std::path::PathBuf;

use hair_core::Solver;
use hairsys::scene::SceneFile;
use nalgebra::{Point3, Vector3};
use parry3d::math::Vector;
use parry3d::query::PointQuery;
use parry3d::shape::{TriMesh, TriMeshFlags};

const SCENE: &str = r#"
[scene]
name = "head turning at 10 rad/s"
fps = 24.0
frames = [1, 25]

[physics]
stretch_stiffness = 40.0
bend_stiffness = 0.5
stretch_damping = 1000.0
air_drag = 2.0

[scalp.mesh]
kind = "builtin-head"

[scalp.collider]
thickness = 0.0
friction = 0.3

[scalp.motion]
interpolation = "linear"
# 10 rad/s = 572.96°/s about z: one second of turning.
keys = [
    { frame = 1,  rotation_deg = [0.0, 0.0, 0.0] },
    { frame = 25, rotation_deg = [0.0, 0.0, 572.9578] },
]

[hair]
count = 300
length = 0.2
segments = 12
seed = 3
radius = 0.002
mass_per_length = 0.001
length_variation = 0.2
region = { direction = [0.0, 0.3, 1.0], max_angle_deg = 95.0 }
"#;

#[test]
fn head_turning_at_ten_rad_per_s_keeps_every_hair_point_outside() {
    let scene = SceneFile::parse(SCENE, "head_turning.toml", PathBuf::from(".")).unwrap();
    let mut sim = scene.build().unwrap();
    let first = sim.first_frame;
    let mut colliders = sim.colliders_at(first as f32).unwrap();
    let mut solver = Solver::new(
        sim.settings,
        sim.params,
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
    let (mut inside_points, mut max_steps, mut contacts) = (0usize, 0u32, 0u64);
    for frame in first + 1..=sim.last_frame {
        let scalp = sim.scalp_at(frame as f32);
        sim.pose_colliders(&mut colliders, frame as f32).unwrap();
        let report = solver
            .step_frame_with_colliders(&mut sim.strands, &scalp, &mut colliders)
            .unwrap();
        max_steps = max_steps.max(report.steps);
        contacts += report.contact_points;
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
