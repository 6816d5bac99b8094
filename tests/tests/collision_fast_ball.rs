//! Fast motion: a ball (R = 0.1 m) moving 1 m per frame (24 m/s) through hanging hair, then back
//! at the same speed, keeps every hair point outside it.
//!
//! The contact model of a sphere collider is the sphere itself moving with its centre, exact at
//! any speed (`contacts::penalty`), and the detection margin covers the ball's 1 m of travel per
//! step, so no extra collision steps are needed. Reference: at every frame every point centre is
//! at least R from the ball's centre (the target is R + thickness + hair radius); the test prints
//! the smallest gap.

use std::path::PathBuf;

mod common;

use common::collide::{free_points, hanging_strand, run_with_colliders};
use hairsys::scene::SceneFile;

fn scene() -> String {
    let mut text = String::from(
        r#"
[scene]
name = "ball at 1 m per frame"
fps = 24.0
frames = [1, 10]

[physics]
stretch_stiffness = 40.0
bend_stiffness = 0.5
stretch_damping = 1000.0
air_drag = 2.0

[[colliders]]
name = "ball"
shape = { kind = "sphere", radius = 0.1 }
thickness = 0.002
friction = 0.3
motion = { interpolation = "linear", keys = [
    { frame = 1, translation = [-1.0, 0.0, -0.25] },
    { frame = 3, translation = [1.0, 0.0, -0.25] },
    { frame = 5, translation = [-1.0, 0.0, -0.25] },
] }
"#,
    );
    for k in 0..16 {
        let (x, y) = (-0.06 + 0.04 * (k % 4) as f32, -0.06 + 0.04 * (k / 4) as f32);
        text += &hanging_strand(x, y);
    }
    text
}

#[test]
fn ball_at_one_meter_per_frame_keeps_hair_outside() {
    let scene = SceneFile::parse(&scene(), "fast_ball.toml", PathBuf::from(".")).unwrap();
    let mut sim = scene.build().unwrap();
    let (mut worst, mut near, mut max_steps) = (f32::INFINITY, 0usize, 0u32);
    let last = sim.last_frame;
    run_with_colliders(&mut sim, last, |frame, sim, _, report| {
        max_steps = max_steps.max(report.steps);
        let centre = sim.colliders[0].motion.at(frame as f32).translation.vector;
        for x in free_points(&sim.strands) {
            let gap = (x - centre).norm() - 0.1;
            worst = worst.min(gap);
            near += usize::from(gap < 0.01);
        }
    });
    println!(
        "ball at 1 m/frame: {max_steps} collision step(s) per frame; {near} point-frames within \
         1 cm of the ball; smallest gap between a point centre and the ball {:.3} mm (target: \
         thickness + radius = 4 mm)",
        worst * 1e3
    );
    assert!(near > 0, "the ball should sweep through the hair");
    assert!(worst >= 0.0, "a point went {} m into the ball", -worst);
}
