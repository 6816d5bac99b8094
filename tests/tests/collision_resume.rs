//! Resuming a collider scene (`hairsys simulate --resume`) continues from the last stored frame's
//! positions and velocities with a fresh solver and a fresh collider set, as `cli/src/resume.rs`
//! does. Contact detection keeps state between steps (per point: a lower bound of its distance
//! to each collider and the mesh triangle it projected on last, a warm start); the resumed run
//! starts without it. The test pins that this state changes only the cost, not a single bit of
//! the result: frames after the resume equal those of the uninterrupted run bit for bit.
//!
//! Scene: the built-in head as its own collider turning at 10 rad/s, hair flung around it (the
//! mesh is not convex, so both the warm-started shortcut and parry's search answer contacts).

mod common;

use common::collide::{run_with_colliders, turning_head_scene, SPRING_PHYSICS};
use hairsys::scene::Simulation;
use nalgebra::Vector3;

type State = (Vec<Vector3<f32>>, Vec<Vector3<f32>>);

/// Runs `sim` from its first frame to `last`, returning the state after each frame.
fn run(sim: &mut Simulation, last: u32) -> Vec<State> {
    let mut states = Vec::new();
    run_with_colliders(sim, last, |_, sim, _, _| {
        states.push((
            sim.strands.positions.clone(),
            sim.strands.velocities.clone(),
        ));
    });
    states
}

fn bits(v: &[Vector3<f32>]) -> Vec<[u32; 3]> {
    v.iter()
        .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
        .collect()
}

#[test]
fn resumed_collider_run_is_bit_identical_to_an_uninterrupted_one() {
    let scene = turning_head_scene("head turning at 10 rad/s, resumed", 13, 300, SPRING_PHYSICS);
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
