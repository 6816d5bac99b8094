//! Resuming a collider scene (`hairsys simulate --resume`) continues from the last stored frame's
//! positions and velocities with a fresh solver and a fresh collider set, as `cli/src/resume.rs`
//! does. Contact detection keeps state between steps (per point: a lower bound of its distance
//! to each collider and the mesh triangle it projected on last, a warm start); the resumed run
//! starts without it. The test pins that this state changes only the cost, not a single bit of
//! the result: frames after the resume equal those of the uninterrupted run bit for bit.
//!
//! Scene: the built-in head as its own collider turning at 10 rad/s, hair flung around it (the
//! mesh is not convex, so both the warm-started shortcut and parry's search answer contacts).

use std::path::PathBuf;

use hair_core::Solver;
use hairsys::scene::{SceneFile, Simulation};
use nalgebra::Vector3;

const SCENE: &str = r#"
[scene]
name = "head turning at 10 rad/s, resumed"
fps = 24.0
frames = [1, 13]

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

type State = (Vec<Vector3<f32>>, Vec<Vector3<f32>>);

/// Runs `sim` from its first frame to `last`, returning the state after each frame.
fn run(sim: &mut Simulation, last: u32) -> Vec<State> {
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
    let mut states = Vec::new();
    for frame in first + 1..=last {
        let scalp = sim.scalp_at(frame as f32);
        sim.pose_colliders(&mut colliders, frame as f32).unwrap();
        solver
            .step_frame_with_colliders(&mut sim.strands, &scalp, &mut colliders)
            .unwrap();
        states.push((
            sim.strands.positions.clone(),
            sim.strands.velocities.clone(),
        ));
    }
    states
}

fn bits(v: &[Vector3<f32>]) -> Vec<[u32; 3]> {
    v.iter()
        .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
        .collect()
}

#[test]
fn resumed_collider_run_is_bit_identical_to_an_uninterrupted_one() {
    let scene = SceneFile::parse(SCENE, "resume.toml", PathBuf::from(".")).unwrap();
    let mut whole = scene.build().unwrap();
    let (last, cut) = (whole.last_frame, 7);
    let reference = run(&mut whole, last);

    // Interrupted after frame `cut`: its state, then a fresh simulation resumed from it.
    let mut before = scene.build().unwrap();
    let stopped = run(&mut before, cut);
    let (x, v) = stopped.last().unwrap();
    let mut resumed = scene.build().unwrap();
    resumed.strands.positions.copy_from_slice(x);
    resumed.strands.velocities.copy_from_slice(v);
    resumed.first_frame = cut;
    let continued = run(&mut resumed, last);

    let first = whole.first_frame;
    for (k, (a, b)) in continued
        .iter()
        .zip(&reference[(cut - first) as usize..])
        .enumerate()
    {
        let frame = cut + 1 + k as u32;
        assert!(
            bits(&a.0) == bits(&b.0) && bits(&a.1) == bits(&b.1),
            "frame {frame}: the resumed run differs from the uninterrupted one"
        );
    }
    assert_eq!(continued.len(), (last - cut) as usize);
}
