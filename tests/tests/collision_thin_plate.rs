//! Where methods fail: a thin open plate (two triangles, no volume) rising at 1 m per frame into
//! hanging hair must not be tunnelled.
//!
//! A 1 m × 1 m horizontal plate, loaded from OBJ like a user's mesh, rises from z = −2.2 m to
//! z = −0.2 m in two frames (24 m/s at 24 fps) into 24 strands hanging from z = 0 to z = −0.4 m,
//! then holds. The crushed strands fold sharply, and the curvature bending stiffens with the turn
//! (`hair_core::integrate::curvature`), so the run needs more substeps than "auto" picks from the
//! small-angle bound (96): 400 (200 still blows up; the error says to try 4×). The open mesh is
//! a two-sided shell (documented in `contacts::collider`): hair is kept
//! on the side it is on, thickness + radius away. The contact model is the plate's plane moving
//! with it, exact for a translating plane at any speed, so no extra collision steps are needed
//! (`contacts::collider_set`); the detection margin covers the plate's 1 m of travel per step.
//! Reference: the hair starts above the plate and its roots
//! stay above it, so no point may ever be found below the plate's surface; at every frame every
//! point must be above `z_plate + thickness + radius` (within 0.1 mm). Once the plate holds, the
//! folded hair rests on it.

use std::path::PathBuf;

mod common;

use common::collide::{free_points, hanging_strand, run_with_colliders};
use hair_core::MeshKind;
use hairsys::scene::SceneFile;

const PLATE_OBJ: &str = "\
# 1 m x 1 m square in the plane z = 0, two triangles
v -0.5 -0.5 0
v 0.5 -0.5 0
v 0.5 0.5 0
v -0.5 0.5 0
f 1 2 3
f 1 3 4
";

fn scene() -> String {
    let mut text = String::from(
        r#"
[scene]
name = "thin plate at 1 m per frame"
fps = 24.0
frames = [1, 12]

[solver]
substeps = 400

[physics]
stretch_stiffness = 40.0
bend_stiffness = 0.5
stretch_damping = 1000.0
air_drag = 2.0

[[colliders]]
name = "plate"
shape = { kind = "obj", path = "plate.obj" }
thickness = 0.003
friction = 0.3
motion = { interpolation = "linear", keys = [
    { frame = 1, translation = [0.0, 0.0, -2.2] },
    { frame = 3, translation = [0.0, 0.0, -0.2] },
] }
"#,
    );
    for k in 0..24 {
        let (x, y) = (
            -0.1 + 0.2 * (k % 6) as f32 / 5.0,
            -0.1 + 0.2 * (k / 6) as f32 / 3.0,
        );
        text += &hanging_strand(x, y);
    }
    text
}

#[test]
fn thin_plate_at_one_meter_per_frame_is_not_tunnelled() {
    let dir = std::env::temp_dir().join(format!("hairsys-thin-plate-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("plate.obj"), PLATE_OBJ).unwrap();
    let scene = SceneFile::parse(&scene(), "thin_plate.toml", PathBuf::from(&dir)).unwrap();
    let mut sim = scene.build().unwrap();
    let colliders = sim.colliders_at(sim.first_frame as f32).unwrap();
    let Some(MeshKind::Shell { reason }) = colliders.mesh_kind(hair_core::ColliderId(0)) else {
        panic!("an open plate is a shell");
    };
    assert!(reason.contains("boundary edges"), "{reason}");
    let clearance = 0.003 + 0.002;
    let (mut worst, mut max_steps, mut hit) = (f32::INFINITY, 0u32, false);
    let last = sim.last_frame;
    run_with_colliders(&mut sim, last, |frame, sim, _, report| {
        max_steps = max_steps.max(report.steps);
        let plate_z = sim.colliders[0]
            .motion
            .at(frame as f32)
            .translation
            .vector
            .z;
        for x in free_points(&sim.strands) {
            let above = x.z - (plate_z + clearance);
            worst = worst.min(above);
            hit |= above < 1e-3;
        }
    });
    let lowest = sim
        .strands
        .positions
        .iter()
        .fold(f32::INFINITY, |a, x| a.min(x.z));
    let max_speed = sim
        .strands
        .velocities
        .iter()
        .map(|v| v.norm())
        .fold(0.0f32, f32::max);
    println!(
        "thin plate at 1 m/frame: up to {max_steps} collision steps per frame; smallest height of \
         a point centre above the plate's surface + thickness + radius over all frames: {:.3} mm; \
         after the plate stops at z = -0.2 m the lowest point is at z = {lowest:.4} m, largest \
         speed {max_speed:.2} m/s",
        worst * 1e3
    );
    assert!(hit, "the plate should reach the hair");
    assert!(worst >= -1e-4, "a point went {worst} m below the plate");
    assert!(lowest >= -0.2 + clearance - 1e-4);
}
