//! Sag-free initialisation (`hair_core::integrate::sag_free`): a groomed shape made a static
//! equilibrium under gravity holds still when the simulation starts, while the same groom without
//! it sags by centimetres.
//!
//! Bounds. Sag-free makes the residual force at the groom f32 round-off (the solve is in f64 and
//! the rest data stored in f32, see `residual_is_round_off`), so a strand starts with
//! accelerations of ~10⁻⁵ g and the only motion left is the kernel's own f32 noise (stretch
//! tension `k_s·δlen` with `δlen ~ 10⁻⁸ m`). 0.5 mm over 2 s on a 25 cm strand is 0.2 % of its
//! length — well above that noise, and 20× below the centimetre sag of the plain groom, which
//! every test asserts too, so a correction that did nothing would fail.

mod common;

use common::*;
use hair_core::integrate::sag_free::residual_forces;
use hair_core::{
    make_sag_free, HairParams, MassSpringSolver, SagFreeLimits, Scalp, SolverSettings, StrandInput,
    StrandSet,
};
use nalgebra::{Isometry3, Vector3};

/// Largest speed left after sag-free settling, m/s: the kernel's f32 noise excites the stiffest
/// (stretch) mode, ω = √(k_s/m) ≈ 3.6·10³ rad/s for a 1.6·10⁻⁵ kg point on a 200 N/m spring,
/// with an amplitude below the 1 µm drift measured: ω · 1 µm ≈ 4 mm/s. (Falling 2 s under
/// gravity would give 20 m/s; the plain groom swings at ~0.1–1 m/s.)
const SPEED: f32 = 5e-3;
/// Frames simulated: 2 s at 24 fps.
const FRAMES: u32 = 48;
/// Linear density of the scenes' sim strands, kg/m.
const DENSITY: f32 = 1e-3;

/// Default material with a bending stiffness of `k_bend` N/m.
fn params(k_bend: f32) -> HairParams {
    HairParams {
        bend_stiffness: k_bend,
        ..HairParams::default()
    }
}

/// Largest distance of a point from its groomed (initial) position, m, and largest speed, m/s.
fn drift(strands: &StrandSet, groom: &[Vector3<f32>]) -> (f32, f32) {
    let d = strands
        .positions
        .iter()
        .zip(groom)
        .map(|(x, g)| (x - g).norm())
        .fold(0.0, f32::max);
    let v = strands
        .velocities
        .iter()
        .map(|v| v.norm())
        .fold(0.0, f32::max);
    (d, v)
}

/// Simulates `FRAMES` frames of `inputs` on a fixed scalp, with or without sag-free
/// initialisation; returns the drift and the final largest speed.
fn settle(inputs: &[StrandInput], params: HairParams, sag_free: bool) -> (f32, f32) {
    let scalp = Scalp::fixed();
    let mut strands = set_on(&scalp, inputs.iter().cloned());
    if sag_free {
        let roots = strands.root_frames(&scalp);
        let report =
            make_sag_free(&mut strands, &params, &roots, SagFreeLimits::default()).unwrap();
        assert!(report.unbalanced.is_empty(), "{report:?}");
        assert_eq!(report.balanced, inputs.len());
    }
    let groom = strands.positions.clone();
    let mut solver =
        MassSpringSolver::new(SolverSettings::default(), params, &strands, &scalp, 0).unwrap();
    run(&mut solver, &mut strands, &scalp, FRAMES, |_, _| {}).unwrap();
    drift(&strands, &groom)
}

/// A 25 cm strand of 16 segments held horizontally (root frame turns local z onto world x).
fn cantilever() -> StrandInput {
    let anchor = anchor_along(Vector3::new(0.0, 0.0, 0.3), Vector3::x());
    StrandInput::uniform(
        anchor,
        straight(16, 0.25 / 16.0, Vector3::z()),
        DENSITY,
        1e-4,
        0.0,
        0.0,
    )
}

/// A 25 cm strand combed over a sphere: it leaves the top of a 10 cm sphere along the surface,
/// follows a quarter circle of radius 11 cm down the side, then hangs straight down.
fn combed_over_a_sphere() -> StrandInput {
    let radius = 0.11f32;
    let arc = std::f32::consts::FRAC_PI_2 * radius;
    let segments = 20;
    let step = 0.25 / segments as f32;
    // Root-local coordinates: the root frame's z is world x (the combing direction), so the
    // strand starts tangent to the sphere; world = (z, y, −x) in local terms, written directly.
    let rest = (0..=segments)
        .map(|i| {
            let s = step * i as f32;
            let (along, down) = if s <= arc {
                let a = s / radius;
                (radius * a.sin(), radius * (1.0 - a.cos()))
            } else {
                (radius, radius + (s - arc))
            };
            // local z = world x (along), local x = world −z (down).
            Vector3::new(down, 0.0, along)
        })
        .collect();
    let anchor = anchor_along(Vector3::new(0.0, 0.0, 0.11), Vector3::x());
    StrandInput::uniform(anchor, rest, DENSITY, 1e-4, 0.0, 0.0)
}

#[test]
fn horizontal_cantilever_holds_its_groom_when_sag_free() {
    let p = params(5.0);
    let (sag_free, v) = settle(&[cantilever()], p, true);
    let (plain, _) = settle(&[cantilever()], p, false);
    println!(
        "cantilever: drift {sag_free:.3e} m (speed {v:.3e} m/s) sag-free, {plain:.3e} m plain"
    );
    assert!(sag_free < 5e-4, "sag-free drift {sag_free} m");
    assert!(v < SPEED, "speed {v} m/s");
    assert!(plain > 1e-2, "plain sag {plain} m");
}

#[test]
fn strand_combed_over_a_sphere_holds_its_groom_when_sag_free() {
    let p = params(5.0);
    let (sag_free, v) = settle(&[combed_over_a_sphere()], p, true);
    let (plain, _) = settle(&[combed_over_a_sphere()], p, false);
    println!("arc: drift {sag_free:.3e} m (speed {v:.3e} m/s) sag-free, {plain:.3e} m plain");
    assert!(sag_free < 5e-4, "sag-free drift {sag_free} m");
    assert!(v < SPEED, "speed {v} m/s");
    assert!(plain > 1e-2, "plain sag {plain} m");
}

#[test]
fn residual_is_round_off() {
    // A twisted, curled strand (a helix whose axis leans sideways) with goal springs and a
    // pinned middle point: every term of the bending gradient (couples, transport twist) and the
    // kinematic-point rule take part.
    let rest: Vec<Vector3<f32>> = (0..=24)
        .map(|i| {
            let a = i as f32 * 0.6;
            Vector3::new(
                0.02 * a.cos() - 0.02 + 0.004 * i as f32,
                0.02 * a.sin(),
                0.01 * i as f32,
            )
        })
        .collect();
    let mut input = StrandInput::uniform(
        anchor_along(Vector3::new(0.0, 0.0, 0.2), Vector3::new(1.0, 0.2, 0.3)),
        rest,
        DENSITY,
        1e-4,
        0.3,
        0.1,
    );
    input.pinned[12] = true;
    let scalp = Scalp::fixed();
    let mut strands = set_on(&scalp, [input]);
    let mut p = params(5.0);
    p.goal_stiffness = 2.0;
    let roots = strands.root_frames(&scalp);
    let before = residual_forces(&strands, 0, &p, &roots[0]);
    let weight = DENSITY * 0.01 * 9.81;
    let largest = |r: &[Vector3<f64>]| r.iter().fold(0.0f64, |a, f| a.max(f.norm()));
    assert!(largest(&before) > 0.5 * weight as f64);
    let report = make_sag_free(&mut strands, &p, &roots, SagFreeLimits::default()).unwrap();
    let after = residual_forces(&strands, 0, &p, &roots[0]);
    println!(
        "residual: before {:.3e} N, after {:.3e} N, {report:?}",
        largest(&before),
        largest(&after)
    );
    // f32 rest data and f32 frames (the kernel's). Bending: a relative error of 2⁻²⁴ on a rest
    // curvature is a moment error of k_j·2⁻²⁴·|κ| and a force of that over l, about
    // k_b · l · 2⁻²⁴ ≈ 5 · 1.25 cm · 6·10⁻⁸ ≈ 4·10⁻⁹ N; a point sums two joints, their near and
    // far terms and the twist sums of all later joints: allow 32 such roundings (1.2·10⁻⁷ N).
    // Stretch: the weight below a segment is carried by pre-stretching it, and its rest length is
    // stored in f32, so its tension is off by up to k_s · ½ ulp(l) ≤ k_s · l · 2⁻²⁴ along the
    // segment (the sweep feeds the stored length forward, so this does not accumulate; the
    // kernel's own f32 tension `k_s (len − l)` rounds the same way): 200 N/m · 1.62 cm · 6·10⁻⁸
    // ≈ 1.9·10⁻⁷ N. Before the correction the residual is the weight itself (1.9·10⁻⁴ N).
    let segment = (strands.positions[1] - strands.positions[0]).norm() as f64;
    let bound = 32.0 * 5.0 * 0.0125 * f64::from(f32::EPSILON) / 2.0
        + f64::from(p.stretch_stiffness) * segment * f64::from(f32::EPSILON) / 2.0;
    assert!(largest(&after) < bound, "residual {:e} N", largest(&after));
    assert!(f64::from(report.max_residual) < bound);
}

#[test]
fn sag_free_strand_still_swings_when_its_root_moves() {
    let p = params(5.0);
    let mut scalp = Scalp::fixed();
    let mut strands = set_on(&scalp, [cantilever()]);
    let roots = strands.root_frames(&scalp);
    make_sag_free(&mut strands, &p, &roots, SagFreeLimits::default()).unwrap();
    let groom = strands.positions.clone();
    let mut solver =
        MassSpringSolver::new(SolverSettings::default(), p, &strands, &scalp, 0).unwrap();
    // Jerk the root 5 cm sideways (y) over 4 frames, then hold it there.
    let mut swing = 0.0f32;
    for frame in 0..FRAMES {
        let y = 0.05 * ((frame + 1) as f32 / 4.0).min(1.0);
        scalp.body = Isometry3::translation(0.0, y, 0.0);
        solver.step_frame(&mut strands, &scalp).unwrap();
        let tip = strands.positions[16] - groom[16] - Vector3::new(0.0, y, 0.0);
        swing = swing.max(tip.norm());
    }
    println!("swing: largest tip offset from the carried groom {swing:.3e} m");
    // The tip lags and overshoots the root by centimetres: the strand is not frozen.
    assert!(swing > 5e-3, "tip offset {swing} m");
}

#[test]
fn strands_without_bending_are_reported_unbalanced() {
    let p = params(0.0);
    let scalp = Scalp::fixed();
    let mut strands = set_on(&scalp, [cantilever()]);
    let before = strands.bend_rest().to_vec();
    let roots = strands.root_frames(&scalp);
    let report = make_sag_free(&mut strands, &p, &roots, SagFreeLimits::default()).unwrap();
    assert_eq!(report.unbalanced, vec![0]);
    assert_eq!(report.balanced, 0);
    assert_eq!(strands.bend_rest(), &before[..]);
}

#[test]
fn hair_on_the_builtin_head_holds_its_groom_when_sag_free() {
    // 100 strands of 25 cm grown along the normals of the built-in head (no collider: the test is
    // about gravity). Bending 10 N/m keeps the upright strands on the crown below the buckling
    // length of a column under its own weight, L³ = 7.84 EI/(ρg) with EI = k_b l³ (0.31 m here).
    let head = hair_groom::builtin_head();
    let opts = hair_groom::GenerateOptions {
        count: 100,
        length: 0.25,
        segments: 16,
        seed: 17,
        radius: 1e-4,
        mass_per_length: DENSITY,
        goal_root: 0.0,
        goal_tip: 0.0,
        region: hair_groom::Region::All,
        length_variation: 0.0,
    };
    let inputs = hair_groom::generate(&head, &opts).unwrap();
    let p = params(10.0);
    let scalp = Scalp {
        mesh: Some(head),
        body: Isometry3::identity(),
    };
    let mut results = Vec::new();
    for sag_free in [true, false] {
        let mut strands = set_on(&scalp, inputs.iter().cloned());
        if sag_free {
            let roots = strands.root_frames(&scalp);
            let report = make_sag_free(&mut strands, &p, &roots, SagFreeLimits::default()).unwrap();
            println!("head: {report:?}");
            assert!(report.unbalanced.is_empty());
        }
        let groom = strands.positions.clone();
        let mut solver =
            MassSpringSolver::new(SolverSettings::default(), p, &strands, &scalp, 0).unwrap();
        run(&mut solver, &mut strands, &scalp, FRAMES, |_, _| {}).unwrap();
        results.push(drift(&strands, &groom));
    }
    let ((sag_free, v), (plain, _)) = (results[0], results[1]);
    println!("head: drift {sag_free:.3e} m (speed {v:.3e} m/s) sag-free, {plain:.3e} m plain");
    assert!(sag_free < 5e-4, "sag-free drift {sag_free} m");
    assert!(v < SPEED, "speed {v} m/s");
    assert!(plain > 1e-2, "plain sag {plain} m");
}

/// Cost of the initialisation on the default scene's hair: 4,000 strands × 16 segments on the
/// built-in head. Run with
/// `cargo test --release -p hairsys-tests --test sag_free -- --ignored --nocapture`.
#[test]
#[ignore]
fn cost_on_the_default_scene_size() {
    let head = hair_groom::builtin_head();
    let opts = hair_groom::GenerateOptions {
        count: 4000,
        length: 0.25,
        segments: 16,
        seed: 1,
        radius: 1e-4,
        mass_per_length: DENSITY,
        goal_root: 0.0,
        goal_tip: 0.0,
        region: hair_groom::Region::All,
        length_variation: 0.3,
    };
    let inputs = hair_groom::generate(&head, &opts).unwrap();
    let scalp = Scalp {
        mesh: Some(head),
        body: Isometry3::identity(),
    };
    let mut strands = set_on(&scalp, inputs.iter().cloned());
    let roots = strands.root_frames(&scalp);
    let p = params(10.0);
    let start = std::time::Instant::now();
    let report = make_sag_free(&mut strands, &p, &roots, SagFreeLimits::default()).unwrap();
    let took = start.elapsed();
    println!(
        "sag-free on 4000 × 16: {:.1} ms; balanced {}, unbalanced {}, max turn {:.2}°, max |r| change {:.3}, max residual {:.2e} N (max weight {:.2e} N)",
        took.as_secs_f64() * 1e3,
        report.balanced,
        report.unbalanced.len(),
        report.max_turn.to_degrees(),
        report.max_length_change,
        report.max_residual,
        report.max_weight
    );
    // With the default bending (0.5 N/m) most horizontal 25 cm strands cannot be held.
    let weak = params(0.5);
    let mut strands = set_on(&scalp, inputs);
    let report = make_sag_free(&mut strands, &weak, &roots, SagFreeLimits::default()).unwrap();
    println!(
        "with k_b = 0.5 N/m: balanced {}, unbalanced {}",
        report.balanced,
        report.unbalanced.len()
    );
}

/// `[solver] sag_free = true` in a scene file: the default scene ships with it, and its groom
/// starts in equilibrium — every residual force is round-off except the push the head gives the
/// hair resting on it (an inward residual at a resting point); with a bending far too weak to
/// hold the hair the scene is refused with a message naming the key and the fix.
#[test]
fn scene_key_sag_free_balances_the_hair_or_says_why_not() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    let text = std::fs::read_to_string(dir.join("default.toml")).unwrap();
    assert!(
        text.contains("\nsag_free = true"),
        "the default scene is sag-free"
    );
    let weak = text.replacen("bend_stiffness = 5.0 ", "bend_stiffness = 0.01", 1);
    assert_ne!(weak, text);
    let refused = hairsys::scene::SceneFile::parse(&weak, "default.toml", dir.clone())
        .unwrap()
        .build()
        .unwrap_err()
        .to_string();
    assert!(
        refused.contains("sag_free") && refused.contains("bend_stiffness"),
        "{refused}"
    );
    let sim = hairsys::scene::SceneFile::parse(&text, "default.toml", dir)
        .unwrap()
        .build()
        .unwrap();
    let scalp = sim.scalp_at(sim.first_frame as f32);
    let roots = sim.strands.root_frames(&scalp);
    let supports = sim.resting_supports().unwrap();
    let mut resting = 0;
    let mut residual = 0.0f64;
    for (s, root) in roots.iter().enumerate() {
        let p = sim.strands.points(s);
        for (f, n) in residual_forces(&sim.strands, s, &sim.params, root)
            .iter()
            .zip(&supports[p])
        {
            let n = n.cast::<f64>();
            let pressed = f.dot(&n);
            // What presses a resting point into the head is the head's to carry.
            let free = if n.norm() > 0.0 && pressed < 0.0 {
                resting += 1;
                f - n * pressed
            } else {
                *f
            };
            residual = residual.max(free.norm());
        }
    }
    println!("default scene, sag-free: {resting} points resting on the head, largest other residual {residual:.2e} N");
    assert!(resting > 0);
    assert!(residual < 1e-6, "residual {residual} N");
}
