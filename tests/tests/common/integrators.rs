//! Cases every strand integrator is held to (`tests/tests/implicit_euler.rs`,
//! `tests/tests/xpbd.rs`): a swinging chain, its energy undamped over ten seconds, and a small
//! head scene with everything that acts on a strand, bit-identical across threads and resume.

use hair_core::{
    energy, HairParams, Integrator, MassSpringSolver, Scalp, SolverSettings, StrandSet,
};
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
    let mut solver = MassSpringSolver::new(
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
    let mut solver = MassSpringSolver::new(settings, params, &strands, &scalp, 0).unwrap();
    let total = |set: &StrandSet, s: &MassSpringSolver| energy(set, s.params(), s.roots()).total();
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

/// `(time, x)` samples of a 5° pendulum (a 10 g bob on a 0.5 m, 10⁴ N/m spring) at one
/// substep per frame of `fps` by `integrator`, over 8 periods; returns them with the period of the stretched
/// pendulum, the substep (s) and the swing's angular frequency (rad/s).
pub fn pendulum(integrator: Integrator, fps: f32) -> (Vec<(f64, f64)>, f64, f64, f64) {
    pendulum_at(integrator, fps, 1)
}

/// [`pendulum`] at `substeps` substeps per frame, sampled once a frame.
pub fn pendulum_at(
    integrator: Integrator,
    fps: f32,
    substeps: u32,
) -> (Vec<(f64, f64)>, f64, f64, f64) {
    let length = 0.5f64;
    let (mass, k) = (PENDULUM_MASS, PENDULUM_K);
    let theta0 = 5.0f64.to_radians();
    let bob = Vector3::new(length * theta0.sin(), 0.0, -length * theta0.cos()).cast::<f32>();
    let scalp = Scalp::fixed();
    let mut strands = set_on(
        &scalp,
        [strand(
            anchor_at(Vector3::zeros()),
            vec![Vector3::zeros(), bob],
            vec![0.0, mass as f32],
            root_only(2),
        )],
    );
    let mut params = bare_params(k as f32);
    params.gravity = gravity();
    let mut solver = MassSpringSolver::new(
        fixed_settings(fps, substeps, integrator),
        params,
        &strands,
        &scalp,
        0,
    )
    .unwrap();
    let h = solver.dt();
    assert!(
        h > 5.0 * solver.bound().dt_max,
        "the test must step past the explicit bound"
    );
    let stretched = length + mass * G / k;
    let omega = (G / stretched).sqrt();
    let t_ref = 2.0 * std::f64::consts::PI / omega;
    let frames = (8.0 * t_ref * fps as f64).ceil() as u32;
    let mut samples = vec![(0.0, strands.positions[1].x as f64)];
    run(&mut solver, &mut strands, &scalp, frames, |s, set| {
        samples.push((s.frame() as f64 / fps as f64, set.positions[1].x as f64));
    })
    .unwrap();
    (samples, t_ref, h, omega)
}

/// The pendulum's bob mass, kg, and spring stiffness, N/m.
pub const PENDULUM_MASS: f64 = 0.01;
/// See [`PENDULUM_MASS`].
pub const PENDULUM_K: f64 = 1.0e4;

/// Fractional amplitude loss per `period` of a swing sampled in `samples`: the largest |x| in
/// each half of `window`, fitted by a line in log space.
pub fn decay_per_period(samples: &[(f64, f64)], window: f64, period: f64) -> f64 {
    let half = window / 2.0;
    let mut peaks = Vec::new();
    let mut start = 0.0;
    while start + half <= samples.last().unwrap().0 {
        let peak = samples
            .iter()
            .filter(|(t, _)| *t >= start && *t < start + half)
            .fold(0.0f64, |a, (_, x)| a.max(x.abs()));
        peaks.push((start + half / 2.0, peak.ln()));
        start += half;
    }
    let n = peaks.len() as f64;
    let (mt, my) = (
        peaks.iter().map(|p| p.0).sum::<f64>() / n,
        peaks.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let slope = peaks.iter().map(|p| (p.0 - mt) * (p.1 - my)).sum::<f64>()
        / peaks.iter().map(|p| (p.0 - mt).powi(2)).sum::<f64>();
    1.0 - (slope * period).exp()
}

/// The hanging chain (`hanging_chain_stretch.rs`): 8 segments of 5 cm hanging from a root at
/// z = 0.2 m, unequal point masses, stretch stiffness `K_CHAIN`, with the damping and drag that
/// settle it. Returns the strands, the scalp, the masses (kg) and the parameters.
pub fn hanging_chain() -> (StrandSet, Scalp, Vec<f32>, HairParams) {
    let segments = 8;
    let mut mass: Vec<f32> = (0..=segments)
        .map(|i| 1e-3 * (1.0 + 0.25 * i as f32))
        .collect();
    mass[0] = 0.0;
    let scalp = Scalp::fixed();
    let strands = set_on(
        &scalp,
        [strand(
            anchor_at(Vector3::new(0.0, 0.0, 0.2)),
            straight(segments, 0.05, -Vector3::z()),
            mass.clone(),
            root_only(segments + 1),
        )],
    );
    let mut params = bare_params(K_CHAIN as f32);
    params.gravity = gravity();
    params.stretch_damping = 50.0;
    params.air_drag = 20.0;
    (strands, scalp, mass, params)
}

/// The hanging chain's stretch stiffness, N/m.
pub const K_CHAIN: f64 = 100.0;

/// Per segment of a chain hanging from its first point: the measured stretch and the weight it
/// carries over `K_CHAIN` (statics of a linear spring chain), m.
pub fn chain_stretch_and_weight_over_k(strands: &StrandSet, mass: &[f32]) -> Vec<(f64, f64)> {
    let x = &strands.positions;
    (0..x.len() - 1)
        .map(|j| {
            let below: f64 = mass[j + 1..].iter().map(|&m| m as f64).sum();
            let measured =
                (x[j + 1] - x[j]).cast::<f64>().norm() - strands.rest_lengths()[j] as f64;
            (measured, G * below / K_CHAIN)
        })
        .collect()
}

/// The hanging chain settled by `integrator` (`name` in the printout) at 2 substeps per frame,
/// more than 5× the explicit bound: every segment stretches by the weight below it over k to
/// 2e-4 (see `hanging_chain_stretch.rs` for the bound).
pub fn assert_hanging_chain_settles_at_weight_below_over_k(integrator: Integrator, name: &str) {
    let (mut strands, scalp, mass, params) = hanging_chain();
    let mut solver = MassSpringSolver::new(
        fixed_settings(24.0, 2, integrator),
        params,
        &strands,
        &scalp,
        0,
    )
    .unwrap();
    assert!(solver.dt() > 5.0 * solver.bound().dt_max);
    run(&mut solver, &mut strands, &scalp, 72, |_, _| {}).unwrap();
    let worst = chain_stretch_and_weight_over_k(&strands, &mass)
        .iter()
        .map(|(measured, expected)| (measured - expected).abs() / expected)
        .fold(0.0f64, f64::max);
    println!(
        "{name} hanging chain at h = {:.3e} s ({:.0}× the explicit bound): worst relative \
         stretch error {worst:.2e} (limit 2e-4)",
        solver.dt(),
        solver.dt() / solver.bound().dt_max
    );
    assert!(worst < 2e-4, "stretch off T/k by {worst:.2e}");
}

/// The swing of [`swing`] by `integrator` (`name` in the printout) at 16…128 substeps per
/// frame against 8× the finest: the RMS error halves with the step (order 0.8–1.3). Against a
/// reference at 8× the finest step, the finest error is overestimated by 1/(1 − 1/8) for a
/// first-order method: the last ratio reads ~0.9–1.0.
pub fn assert_first_order_as_the_step_halves(integrator: Integrator, name: &str) {
    assert_order_as_the_step_halves(integrator, name, [16, 32, 64, 128], 0.8..1.3);
}

/// The swing of [`swing`] by `integrator` (`name` in the printout) at `counts` substeps per
/// frame (each twice the one before) against 8× the finest: `log2` of each successive RMS error
/// ratio must lie in `orders`.
pub fn assert_order_as_the_step_halves(
    integrator: Integrator,
    name: &str,
    counts: [u32; 4],
    orders: std::ops::Range<f64>,
) {
    let frames = 12;
    let reference = swing(integrator, 8 * counts[counts.len() - 1], frames);
    let errors: Vec<f64> = counts
        .iter()
        .map(|&n| {
            let x = swing(integrator, n, frames);
            let sum: f64 = x
                .iter()
                .zip(&reference)
                .map(|(a, b)| (a - b).norm_squared())
                .sum();
            (sum / x.len() as f64).sqrt()
        })
        .collect();
    let measured: Vec<f64> = errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
    println!(
        "{name} swing at 0.5 s, substeps/frame {counts:?}: RMS errors {errors:?} m, orders \
         {measured:.3?}"
    );
    for (i, p) in measured.iter().enumerate() {
        assert!(
            orders.contains(p),
            "order {p:.3} between {} and {} substeps (expected {orders:?})",
            counts[i],
            counts[i + 1]
        );
    }
}

/// A stiff cantilever settled over 10 s: 16 segments of 1 cm released from horizontal,
/// k = 10⁴ N/m, k_b = 50 N/m, by `integrator` at `substeps` per frame (the solver's default,
/// explicit `auto`, for `None`).
pub struct Settled {
    /// The tip at rest, m.
    pub tip: Vector3<f32>,
    /// The step over the explicit stability bound.
    pub ratio: f64,
    /// The fastest any point moved over the 10 s, m/s.
    pub fastest: f32,
    /// Substeps per frame run.
    pub substeps: u32,
}

/// Points of the stiff cantilever (segments, segment length m).
pub const CANTILEVER: (usize, f32) = (16, 0.01);

/// Settles the stiff cantilever of [`Settled`].
pub fn settle_stiff_cantilever(integrator: Integrator, substeps: Option<u32>) -> Settled {
    let (segments, seg_len) = CANTILEVER;
    let mut params = bare_params(1.0e4);
    params.gravity = gravity();
    params.bend_stiffness = 50.0;
    params.stretch_damping = 50.0;
    params.air_drag = 2.0;
    let (mut strands, scalp) = horizontal_chain(segments, seg_len, 1e-4);
    let settings = match substeps {
        Some(n) => fixed_settings(24.0, n, integrator),
        None => SolverSettings::default(),
    };
    let mut solver = MassSpringSolver::new(settings, params, &strands, &scalp, 0).unwrap();
    let ratio = solver.dt() / solver.bound().dt_max;
    let mut fastest = 0.0f32;
    run(&mut solver, &mut strands, &scalp, 240, |_, set| {
        fastest = fastest.max(set.velocities.iter().map(|v| v.norm()).fold(0.0, f32::max));
    })
    .unwrap();
    Settled {
        tip: strands.positions[segments],
        ratio,
        fastest,
        substeps: solver.substeps(),
    }
}

/// The stiff cantilever of [`settle_stiff_cantilever`] by `integrator` (`name` in the printout)
/// at `substeps` per frame, more than 100× the explicit bound: it settles without runaway (no
/// point faster than 1 m/s over 10 s) within 1 % of its sag of the explicit kernel's equilibrium.
pub fn assert_stiff_cantilever_settles_where_the_explicit_kernel_does(
    integrator: Integrator,
    name: &str,
    substeps: u32,
) {
    let r = settle_stiff_cantilever(integrator, Some(substeps));
    let explicit = settle_stiff_cantilever(Integrator::SemiImplicitEuler, None);
    let sag = -r.tip.z;
    let diff = (r.tip - explicit.tip).norm();
    println!(
        "stiff cantilever: {name} at {substeps} substep(s)/frame (h = {:.0}× the explicit bound; \
         the explicit kernel needs {}): tip sag {sag:.4e} m, {diff:.2e} m from the explicit \
         kernel's equilibrium; fastest point over 10 s {:.3} m/s",
        r.ratio, explicit.substeps, r.fastest
    );
    assert!(r.ratio > 100.0);
    assert!(sag > 0.0 && r.fastest < 1.0, "not a sag: {:?}", r.tip);
    assert!(
        diff < 0.01 * sag,
        "settled {diff:.2e} m from the explicit equilibrium (sag {sag:.2e} m)"
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
