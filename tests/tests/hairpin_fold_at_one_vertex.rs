//! No hairpins — a turn of more than 90° at one point — where no real hair would fold (with
//! chord-spring bending the parity scene folds 1,780 of 20,000 strands, up to 179° at one point;
//! `docs/design/bending-energy.md`).
//!
//! Cause. A chord bending spring `E = ½ k_b |x_j + l d_j − x_{j+1}|² = 2 k_b l² sin²(θ/2)` has a
//! moment `k_b l² sin θ` that peaks at 90° and falls to zero at 180°: past 90° a joint softens,
//! so a bend concentrates at one vertex and a segment folded straight back is an equilibrium.
//! The curvature bending (`hair_core::integrate::curvature`) has `E = 2 k tan²(θ/2)` with the same
//! small-angle stiffness `k = k_b l²`, and a moment `M(θ) = 2 k tan(θ/2) / cos²(θ/2)` that grows
//! without bound: `M(90°) = 4 k`.
//!
//! Bound (static, analytic). In equilibrium a joint carries the moment of the weight beyond it,
//! `|Σ_{i>j} m_i g × (x_i − x_j)| ≤ (ρ g L) · L` for a strand of length `L` and line density
//! `ρ`. A strand with `ρ g L² = 3 k < M(90°)` can therefore turn by less than 90° at every point
//! once it has settled, however it lies. Yet it is far past the buckling length of a column under
//! its own weight (`ρ g L³ = 7.84 EI`, `EI = k l`; here `ρ g L³ = 48 EI`): rooted upright, it
//! must fall over and turn through more than 90° in all, spread over several joints.

mod common;

use common::*;
use hair_core::quality::{measure, Frame, QualityInput, QualityOptions};
use hair_core::{MassSpringSolver, Scalp, SolverSettings, StrandSet};
use hairsys::scene::SceneFile;
use nalgebra::Vector3;

/// Largest turn between consecutive segments of strand `s`, degrees.
fn largest_turn(strands: &StrandSet, s: usize) -> f32 {
    let x = &strands.positions[strands.points(s)];
    x.windows(3)
        .map(|w| (w[1] - w[0]).angle(&(w[2] - w[1])).to_degrees())
        .fold(0.0, f32::max)
}

#[test]
fn buckled_upright_strand_bends_over_several_joints_not_one() {
    let segments = 16;
    let seg_len = 0.02f32;
    let density = 0.01f32; // kg/m
    let length = seg_len * segments as f32;
    // ρ g L² = 3 k with the joint stiffness k = k_b l² (see the module docs).
    let k_joint = density * G as f32 * length * length / 3.0;
    let k_bend = k_joint / (seg_len * seg_len);
    let mut mass = vec![density * seg_len; segments + 1];
    mass[segments] *= 0.5;
    let scalp = Scalp::fixed();
    // Rooted pointing up, tilted 5° so that it buckles one way.
    let tilt = 5f32.to_radians();
    let normal = Vector3::new(tilt.sin(), 0.0, tilt.cos());
    let mut strands = set_on(
        &scalp,
        [strand(
            anchor_along(Vector3::zeros(), normal),
            straight(segments, seg_len, Vector3::z()),
            mass,
            root_only(segments + 1),
        )],
    );
    let mut params = bare_params(200.0);
    params.bend_stiffness = k_bend;
    params.gravity = gravity();
    params.air_drag = 5.0;
    params.stretch_damping = 50.0;
    let mut solver =
        MassSpringSolver::new(SolverSettings::default(), params, &strands, &scalp, 0).unwrap();
    let mut worst_settled = 0.0f32;
    let mut frame = 0;
    // 4 s: the fall takes under 1 s; drag 5/s damps the swing by e⁻¹⁰ in the last 2 s.
    run(&mut solver, &mut strands, &scalp, 96, |_, set| {
        frame += 1;
        if frame > 48 {
            worst_settled = worst_settled.max(largest_turn(set, 0));
        }
    })
    .unwrap();
    let tip = strands.positions[segments];
    let overall = normal
        .angle(&(strands.positions[segments] - strands.positions[segments - 1]))
        .to_degrees();
    println!(
        "upright strand, k_b = {k_bend:.3} N/m: tip at {tip:?}, overall turn {overall:.1}°, \
         largest turn at one point over the last 2 s {worst_settled:.1}°"
    );
    // It fell over: the tip is below the root and the strand turned through more than 90°.
    assert!(tip.z < 0.0 && overall > 90.0, "the strand did not buckle");
    assert!(
        worst_settled < 90.0,
        "hairpin: {worst_settled:.1}° at one point"
    );
}

/// A strand of the parity scene alone: 1.5 m, 16 segments, 0.01 kg/m, `bend_stiffness` 0.5 N/m,
/// soft stretch with a 1.5 % strain limit, rooted pointing `normal` on a body that moves 1 m
/// sideways and back in 1 s like the parity head. Returns the largest turn at one point over
/// the run, degrees.
fn whipped_parity_strand(normal: Vector3<f32>, bend_stiffness: f32) -> f32 {
    let segments = 16;
    let seg_len = 1.5 / segments as f32;
    let mut mass = vec![0.01 * seg_len; segments + 1];
    mass[segments] *= 0.5;
    let mut scalp = Scalp::fixed();
    let mut strands = set_on(
        &scalp,
        [strand(
            anchor_along(normal, normal),
            straight(segments, seg_len, Vector3::z()),
            mass,
            root_only(segments + 1),
        )],
    );
    let params = hair_core::HairParams {
        gravity: gravity(),
        stretch_stiffness: 50.0,
        bend_stiffness,
        goal_stiffness: 0.0,
        stretch_damping: 1000.0,
        air_drag: 2.0,
    };
    let settings = SolverSettings {
        max_strain: Some(0.015),
        damping_iterations: 5,
        ..SolverSettings::default()
    };
    let mut solver = MassSpringSolver::new(settings, params, &strands, &scalp, 0).unwrap();
    let mut worst = 0.0f32;
    for frame in 1..=48u32 {
        // Smooth out and back over 24 frames, then hold for a second.
        let s = (frame.min(24) as f32 / 24.0 * std::f32::consts::TAU).cos();
        scalp.body = nalgebra::Isometry3::translation(0.5 * (1.0 - s), 0.0, 0.0);
        solver.step_frame(&mut strands, &scalp).unwrap();
        worst = worst.max(largest_turn(&strands, 0));
    }
    worst
}

/// Strands of the parity scene, alone (no other strand, no head), whipped by the head's motion
/// (upright on the crown, tilted 45° and sideways) with `bend_stiffness` 2 N/m: no turn of more
/// than 90° at one point. A chord spring folds the upright one to 99.8° (and at 0.5 N/m, the
/// scene's value, to 158.5°).
///
/// Bound (estimate). The head accelerates by up to `0.5 m · (2π/1 s)² = 19.7 m/s²`, so the strand
/// feels up to `g' = 22 m/s²` and its weight `W' = ρ g' L = 0.33` N bends it at its root. A heavy
/// elastica bent by a load `W'` on a lever of about its bend radius `R` has `EI/R = W' R`, so
/// `R ≈ √(EI/W')`, and a joint turns by about `l/R`. With `EI = k_b l³` (9.4 cm segments):
/// `k_b = 2` N/m gives `R = 7.1` cm and `l/R = 76°` — real hair of that stiffness bends over more
/// than one segment, so a hairpin is an artefact; `k_b = 0.5` N/m gives `R = 3.5` cm and
/// `l/R = 154°`: such hair would turn by more than 90° within one 9.4 cm segment, so at that
/// resolution a fold at one point is what the hair does, and is not asserted against (printed
/// only; the curvature bending gives 81.6° and 104.1° there).
#[test]
fn whipped_parity_strand_does_not_fold_at_one_vertex() {
    for (name, normal) in [
        ("upright", Vector3::new(0.05, 0.0, 1.0)),
        ("tilted 45°", Vector3::new(1.0, 0.3, 1.0)),
        ("sideways", Vector3::new(0.0, 1.0, 0.0)),
    ] {
        let soft = whipped_parity_strand(normal.normalize(), 0.5);
        let worst = whipped_parity_strand(normal.normalize(), 2.0);
        println!(
            "whipped parity strand, {name}: largest turn at one point {worst:.1}° with k_b = 2 N/m \
             ({soft:.1}° with the scene's 0.5 N/m)"
        );
        assert!(worst < 90.0, "{name}: hairpin of {worst:.1}°");
    }
}

/// What a run of the parity scene shows, over all its frames.
struct ParityRun {
    /// Hairpin points summed over frames, and the most in one frame.
    hairpins: u64,
    worst_frame: u64,
    /// Strands with a hairpin in the last frame.
    strands_last: usize,
    /// Largest turn at one point, degrees.
    max_turn: f32,
    /// Shortest and longest segment, as a fraction of its rest length.
    min_ratio: f32,
    max_ratio: f32,
}

/// Runs `scenes/parity.toml` with `count` strands over `frames` (first, last) and
/// `bend_stiffness` (N/m) and measures every frame with `hair_core::quality`.
fn run_parity(count: u32, frames: (u32, u32), bend_stiffness: f32) -> ParityRun {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    let text = std::fs::read_to_string(dir.join("parity.toml")).unwrap();
    let reduced = text
        .replacen("count = 20000", &format!("count = {count}"), 1)
        .replacen(
            "frames = [1, 24]",
            &format!("frames = [{}, {}]", frames.0, frames.1),
            1,
        )
        .lines()
        .map(|l| match l.starts_with("bend_stiffness = ") {
            true => format!("bend_stiffness = {bend_stiffness}"),
            false => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n";
    assert!(reduced.contains(&format!("count = {count}")));
    assert!(reduced.contains(&format!("bend_stiffness = {bend_stiffness}\n")));
    let mut sim = SceneFile::parse(&reduced, "parity.toml", dir)
        .unwrap()
        .build()
        .unwrap();
    let mut solver = solver_at_first_frame(&sim);
    let mut out = ParityRun {
        hairpins: 0,
        worst_frame: 0,
        strands_last: 0,
        max_turn: 0.0,
        min_ratio: f32::INFINITY,
        max_ratio: 0.0,
    };
    for frame in sim.first_frame + 1..=sim.last_frame {
        let scalp = sim.scalp_at(frame as f32);
        solver.step_frame(&mut sim.strands, &scalp).unwrap();
        let input = QualityInput {
            frame: Frame::of(&sim.strands),
            previous: None,
            colliders: None,
            reference: None,
        };
        let report = measure(&input, &QualityOptions::default()).unwrap();
        out.hairpins += report.hairpins.count;
        out.worst_frame = out.worst_frame.max(report.hairpins.worst_frame);
        out.max_turn = out.max_turn.max(report.hairpins.max_turn_deg);
        out.min_ratio = out.min_ratio.min(1.0 - report.strain.compression.max());
        out.max_ratio = out.max_ratio.max(1.0 + report.strain.stretch.max());
    }
    out.strands_last = (0..sim.strands.len())
        .filter(|&s| largest_turn(&sim.strands, s) > 90.0)
        .count();
    println!(
        "parity ({count} strands, frames {}–{}, k_b {bend_stiffness} N/m): {} hairpin points over all frames, at most {} in \
         one frame, {} strands with one in the last frame; largest turn {:.1}°; segments {:.1} – \
         {:.1} % of rest",
        frames.0,
        frames.1,
        out.hairpins,
        out.worst_frame,
        out.strands_last,
        out.max_turn,
        100.0 * out.min_ratio,
        100.0 * out.max_ratio
    );
    out
}

/// The parity scene (`scenes/parity.toml`) with 500 of its 20,000 strands, 12 of its 24 frames
/// (the head's move out, its fastest part) and its `bend_stiffness` of 2 N/m (0.5 before this
/// fix): no hairpin in any frame. 2 N/m is the stiffness at which a strand of this scene, whipped by the head,
/// bends over more than one segment (see `whipped_parity_strand_does_not_fold_at_one_vertex`);
/// at the scene's 0.5 N/m a turn of more than 90° within one 9.4 cm segment is what such hair
/// does, and the scene needs more segments or stiffer bending to show it smoothly. This reduced
/// run also passes with the old chord spring (largest turn 63.3°, measured on main): the failure
/// it guards against shows in the full scene (`parity_scene_full_run`: 72 hairpin points, up to
/// 154.5°, with the chord spring at 2 N/m; none with the curvature bending) and in
/// `whipped_parity_strand_does_not_fold_at_one_vertex`.
#[test]
fn parity_scene_folds_no_strand_into_a_hairpin() {
    let run = run_parity(500, (1, 13), 2.0);
    assert_eq!(run.hairpins, 0, "largest turn {:.1}°", run.max_turn);
}

/// The whole parity scene, for the figures in the report (about 30 s per run in the dev
/// profile), at its former `bend_stiffness` 0.5 N/m (printed) and at its own 2 N/m (no hairpins
/// asserted):
/// `cargo test -p hairsys-tests --test hairpin_fold_at_one_vertex -- --ignored --nocapture`.
#[test]
#[ignore = "the full 20,000-strand scene; run with --ignored --nocapture"]
fn parity_scene_full_run() {
    run_parity(20_000, (1, 24), 0.5);
    let run = run_parity(20_000, (1, 24), 2.0);
    assert_eq!(run.hairpins, 0, "largest turn {:.1}°", run.max_turn);
}
