//! The shipped gust scene (`scenes/gust.toml`): a keyed gust on long hair that the
//! simulation follows exactly (sim weight 1) and hands back. Held to the shipped scenes' bounds
//! (`tests/tests/shipped_scenes_look.rs`): no point deeper than 0.5 mm in the head and at most
//! 0.01 % of point-frames deeper than 0.1 mm — while the hair lies exactly on the keyed pose
//! too, which `[guides] pose_clearance` keeps outside the head —, stretch within the 1 % strain
//! limit (posed hair keeps its segment lengths), no hairpins. Before the pose was lifted and
//! its lengths kept, the same shot put hair 72 mm into the head and stretched segments by 34 %.

use std::path::Path;

use hair_cache::WriterOptions;
use hairsys::output::quality::RunQuality;
use hairsys::run::{simulate, SimulateOptions};
use hairsys::scene::SceneFile;

/// Slow (48 frames of 2,000 hairs with the quality report; 36 s in release on the 2-core
/// machine, 8 min in the test profile under load): `cargo test --release -p hairsys --test
/// gust_scene -- --ignored`.
#[test]
#[ignore = "slow: run in release with --ignored (command above)"]
fn the_keyed_gust_stays_out_of_the_head_and_unstretched() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/gust.toml");
    let dir = tempfile::tempdir().unwrap();
    let q = simulate(
        &SimulateOptions {
            scene: SceneFile::load(&path).unwrap(),
            cache: dir.path().join("gust.mcap"),
            frames: None,
            threads: None,
            writer: WriterOptions::default(),
            resume: false,
            kernel: Default::default(),
            quality: true,
        },
        |_| {},
    )
    .unwrap()
    .quality
    .expect("asked for");
    let r = &q.run;
    let p = r.penetration.as_ref().expect("the head collides");
    // The frame-end check leaves no point deeper than 25 µm: none beyond the 0.1 mm tolerance.
    assert_eq!(p.inside, 0, "{p:?}");
    // The strain limit (max_strain = 0.01) to f32 round-off, the worst segment within twice it.
    assert!(r.strain.stretch.p99() <= 0.01 + 1e-4, "{:?}", r.strain);
    assert!(r.strain.stretch.max() <= 0.02, "{:?}", r.strain);
    assert_eq!(r.hairpins.count, 0, "{:?}", r.hairpins);
    // Handed back at frame 30, the hair has fallen back near its groom by frame 48: tips within
    // 2 cm RMS (measured: 8.4 mm).
    let last = q.last.drift.as_ref().unwrap();
    assert!(last.tip_rms < 0.02, "{last:?}");
}

/// The shipped gust shortened to its first 18 frames (to the keyed pose, followed exactly from
/// frame 14), with fewer hairs, the sweep turned to `sweep`, `pose_clearance` replaced by
/// `clearance` (a line, or nothing) and the integrator set to `integrator`. Returns the run's
/// quality report and how many point-frames the frame-end check put back.
fn small_gust(sweep: &str, clearance: &str, integrator: &str) -> (RunQuality, u64) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/gust.toml");
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace("frames = [1, 48]", "frames = [1, 18]")
        .replace("count = 2000", "count = 300")
        .replace("count = 200\n", "count = 60\n")
        .replace(
            "sweep = { direction = [0.3, 1.0, 0.5], angle_deg = 70.0 }",
            sweep,
        )
        .replace(
            "pose_clearance = 0.0035        # m: posed sim hairs are lifted this far out of the head",
            clearance,
        )
        .replace("integrator = \"auto\"", &format!("integrator = \"{integrator}\""));
    assert!(text.contains(sweep) && text.contains("count = 60\n"));
    assert!(text.contains(&format!("integrator = \"{integrator}\"")));
    let dir = tempfile::tempdir().unwrap();
    let summary = simulate(
        &SimulateOptions {
            scene: SceneFile::parse(&text, "gust.toml", dir.path().into()).unwrap(),
            cache: dir.path().join("gust.mcap"),
            frames: None,
            threads: None,
            writer: WriterOptions::default(),
            resume: false,
            kernel: Default::default(),
            quality: true,
        },
        |_| {},
    )
    .unwrap();
    let put_back = summary.deep_contact_points + summary.escaped_points;
    (summary.quality.expect("asked for"), put_back)
}

/// The regression the shipped scene was held back by: a sweep towards +X turns the hair on the
/// head's −X side into it, and sim weight 1 followed it there. Lifted, the posed hair stays
/// outside and unstretched; without the lift the same keys put hair centimetres deep.
///
/// A sweep this hard against the head presses points of the hand-over blend (frames 6–14)
/// against it. Within the substeps the response holds them: semi-implicit Euler, at each of its
/// ~150 substeps per frame, to within 0.61 mm; BDF2 (what `"auto"` takes here, 7 substeps per
/// frame) applies it after each substep's solve, so the keyed pull holds a point against the
/// surface for a seventh of a frame, to within 0.85 mm. The solver's frame-end check then moves
/// every point deeper than 25 µm back to that depth (it must have had work to do here). What
/// the cached frame then holds is the hand-over blend's: sim weight blends the hair towards
/// the keyed pose *after* the solver's frame, check included, so the lift alone keeps it out:
/// under semi-implicit Euler 0.078 % of point-frames end beyond the 0.1 mm tolerance, deepest
/// 0.46 mm; under BDF2 0.22 %, deepest 0.84 mm — both within the 1 mm the lift is there to
/// keep. Stretch,
/// measured p99 0.39 %, max 2.4 %: bounded at 1 % and 3 %.
#[test]
fn a_sweep_into_the_head_is_lifted_out_of_it_with_lengths_kept() {
    let into_head = "sweep = { direction = [1.0, 0.0, 0.0], angle_deg = 80.0 }";
    for (integrator, inside_fraction) in [("semi-implicit-euler", 1e-3), ("auto", 5e-3)] {
        let (lifted, put_back) = small_gust(into_head, "pose_clearance = 0.0035", integrator);
        let p = lifted.run.penetration.as_ref().unwrap();
        assert!(
            p.deepest <= 1e-3 && p.inside_fraction <= inside_fraction,
            "{integrator}: {p:?}"
        );
        assert!(
            put_back > 0,
            "{integrator}: the sweep presses hair into the head"
        );
        let stretch = &lifted.run.strain.stretch;
        assert!(
            stretch.p99() <= 0.01 && stretch.max() <= 0.03,
            "{integrator}: {stretch:?}"
        );
    }
    let (free, _) = small_gust(into_head, "", "auto");
    let p = free.run.penetration.as_ref().unwrap();
    assert!(p.deepest > 0.01, "without the lift: {p:?}");
}

/// The shipped gust once grew its 2,000 sim hairs over the whole head — face and neck too, where
/// no guide grows — so hair covered the face and stood out under the chin. Its sim hairs now
/// grow only near the guides (`[sim_hairs] max_guide_distance`), whose region is the cone of
/// root normals within 88° of `[0, 0.4, 1]`: every sim root's normal lies within that cone
/// widened by the 1.5 cm reach on the 8 cm-radius head (about 11°). The face (normal −Y) is
/// 112° off the axis.
#[test]
fn gust_hair_grows_only_where_its_guides_grow() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/gust.toml");
    let sim = SceneFile::load(&path).unwrap().build().unwrap();
    let scalp = sim.scalp_at(sim.first_frame as f32);
    let mesh = scalp.mesh.as_ref().unwrap();
    let axis = nalgebra::Vector3::new(0.0f32, 0.4, 1.0).normalize();
    let widest = (88.0f32 + 11.0).to_radians().cos();
    let strands = &sim.strands;
    assert!(strands.len() >= 2000);
    for anchor in strands.anchors() {
        let hair_core::Anchor::Surface(sample) = anchor else {
            panic!("the gust's hair grows on the head")
        };
        let normal = mesh.evaluate(sample).rotation * nalgebra::Vector3::z();
        assert!(normal.dot(&axis) >= widest, "a root with normal {normal:?}");
    }
}
