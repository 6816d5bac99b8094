//! Cases every strand integrator is held to (`tests/tests/implicit_euler.rs`,
//! `tests/tests/xpbd.rs`): a swinging chain, its energy undamped over ten seconds, and a small
//! head scene with everything that acts on a strand, bit-identical across threads and resume.

use hair_core::{energy, HairParams, Integrator, Scalp, Solver, StrandSet};
use nalgebra::Vector3;

use super::*;

/// A chain of `segments` segments of `seg_len` along +x from a root at the origin whose frame
/// turns local z onto x (straight rest shape), with bending; masses `mass` per point.
pub fn horizontal_chain(segments: usize, seg_len: f32, mass: f32) -> (StrandSet, Scalp) {
    let scalp = Scalp::fixed();
    let mut m = vec![mass; segments + 1];
    m[segments] *= 0.5;
    let strands = set_on(
        &scalp,
        [strand(
            anchor_along(Vector3::zeros(), Vector3::x()),
            straight(segments, seg_len, Vector3::z()),
            m,
            root_only(segments + 1),
        )],
    );
    (strands, scalp)
}

/// The swinging chain's parameters: gravity, soft bending, stretch damping.
pub fn swing_params() -> HairParams {
    let mut p = bare_params(100.0);
    p.gravity = gravity();
    p.bend_stiffness = 0.5;
    p.stretch_damping = 50.0;
    p
}

/// Positions after `frames` frames at 24 fps with `substeps` substeps per frame of `integrator`.
pub fn swing(integrator: Integrator, substeps: u32, frames: u32) -> Vec<Vector3<f64>> {
    let (mut strands, scalp) = horizontal_chain(8, 0.05, 1e-3);
    let mut solver = Solver::new(
        fixed_settings(24.0, substeps, integrator),
        swing_params(),
        &strands,
        &scalp,
        0,
    )
    .unwrap();
    run(&mut solver, &mut strands, &scalp, frames, |_, _| {}).unwrap();
    strands.positions.iter().map(|p| p.cast()).collect()
}

/// Runs the chain undamped (no stretch damping, no damping loop) for 10 s at 8 substeps per
/// frame of `integrator` (`name` in the printout) and asserts that its energy never rises
/// above its start by more than 1e-5 of m g L.
pub fn assert_undamped_chain_gains_no_energy(integrator: Integrator, name: &str) {
    let (mut strands, scalp) = horizontal_chain(8, 0.05, 1e-3);
    let mut params = swing_params();
    params.stretch_damping = 0.0;
    let mut settings = fixed_settings(24.0, 8, integrator);
    settings.damping_iterations = 0;
    let mut solver = Solver::new(settings, params, &strands, &scalp, 0).unwrap();
    let total = |set: &StrandSet, s: &Solver| energy(set, s.params(), s.roots()).total();
    let e0 = total(&strands, &solver);
    // The energy scale: what the chain can convert by falling (its mass × g × its length).
    let scale = 8.5e-3 * G * 0.4;
    let mut highest = f64::NEG_INFINITY;
    let mut trace = Vec::new();
    run(&mut solver, &mut strands, &scalp, 240, |s, set| {
        let e = total(set, s);
        highest = highest.max(e - e0);
        trace.push(e - e0);
    })
    .unwrap();
    println!(
        "undamped {name} chain, h = {:.3e} s: largest gain {:.2e} J ({:.2e} of m g L); energy \
         after 1 s {:.3e} J, 10 s {:.3e} J ({:.1} % of m g L lost)",
        solver.dt(),
        highest,
        highest / scale,
        trace[23],
        trace[239],
        -100.0 * trace[239] / scale
    );
    assert!(
        highest <= 1e-5 * scale,
        "energy rose by {highest:.3e} J above its start"
    );
}

/// A small head scene on the integrator `{integrator}` (the scene key) with everything that acts on a strand besides
/// its springs: the head as a collider, hair–hair friction and repulsion, a wind field, goal
/// springs and the strain limit.
const HEAD_SCENE: &str = r#"
[scene]
frames = [1, 6]

[solver]
integrator = "{integrator}"
substeps = 4
max_strain = 0.01

[physics]
goal_stiffness = 0.5
air_drag = 2.0

[scalp.mesh]
kind = "builtin-head"

[scalp.collider]
thickness = 0.001
friction = 0.3

[scalp.motion]
keys = [
    { frame = 1, rotation_deg = [0.0, 0.0, 0.0] },
    { frame = 6, rotation_deg = [20.0, 0.0, 60.0] },
]

[hair]
count = 200
length = 0.2
segments = 12
seed = 7
length_variation = 0.3
goal_tip = 0.2

[hair_hair]
cell_size = 0.01
friction = 0.3
repulsion = 0.5
target_density = 0.2

[[fields]]
type = "wind"
strength = 2.0
direction = [1.0, 0.0, 0.0]
"#;

fn head_scene(integrator: &str) -> hairsys::scene::SceneFile {
    let text = HEAD_SCENE.replace("{integrator}", integrator);
    hairsys::scene::SceneFile::parse(&text, &format!("{integrator}_head.toml"), ".".into()).unwrap()
}

/// Runs the head scene on `integrator` from `first` (with the state `start`, if given) to its last frame on
/// `threads` threads; returns every frame's positions and velocities as bits.
fn head_run(integrator: &str, threads: usize, start: Option<(u32, &[u32])>) -> Vec<Vec<u32>> {
    let scene = head_scene(integrator);
    let mut sim = scene.build().unwrap();
    if let Some((frame, state)) = start {
        let n = sim.strands.point_count();
        let f = |i: usize| f32::from_bits(state[i]);
        for i in 0..n {
            sim.strands.positions[i] = Vector3::new(f(3 * i), f(3 * i + 1), f(3 * i + 2));
            let j = 3 * (n + i);
            sim.strands.velocities[i] = Vector3::new(f(j), f(j + 1), f(j + 2));
        }
        sim.first_frame = frame;
    }
    let last = sim.last_frame;
    let first = sim.first_frame;
    let mut session = hairsys::Session::from_simulation(sim, &scene, integrator.into()).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    session.set_thread_pool(std::sync::Arc::new(pool));
    (first..last)
        .map(|_| {
            session.step().unwrap();
            session
                .positions()
                .iter()
                .chain(session.velocities())
                .flat_map(|p| p.map(f32::to_bits))
                .collect()
        })
        .collect()
}

/// Runs the head scene on `integrator` (its scene key) on 1 and 2 threads and resumed after
/// frame 3, and asserts that all three give the same bits.
pub fn assert_head_run_is_bit_identical(integrator: &str) {
    let one = head_run(integrator, 1, None);
    let two = head_run(integrator, 2, None);
    assert_eq!(one.len(), 5);
    assert!(one == two, "1 thread and 2 threads differ");
    assert_ne!(one[0], one[4], "the hair did not move");
    // Resumed after frame 3 (index 1: frames 2, 3 ran) from the stored state.
    let resumed = head_run(integrator, 2, Some((3, &one[1])));
    assert!(
        resumed[..] == one[2..],
        "the resumed run differs from the uninterrupted one"
    );
}
