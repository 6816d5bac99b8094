//! The shipped gust scene (`scenes/gust.toml`, issue 20): a keyed gust on long hair that the
//! simulation follows exactly (sim weight 1) and hands back. Held to the shipped scenes' bounds
//! (`tests/tests/shipped_scenes_look.rs`): no point deeper than 0.5 mm in the head and at most
//! 0.01 % of point-frames deeper than 0.1 mm — while the hair lies exactly on the keyed pose
//! too, which `[guides] pose_clearance` keeps outside the head —, stretch within the 1 % strain
//! limit (posed hair keeps its segment lengths), no hairpins. Before the pose was lifted and
//! its lengths kept, the same shot put hair 72 mm into the head and stretched segments by 34 %.

use std::path::Path;

use hair_cache::WriterOptions;
use hairsys::run::{simulate, SimulateOptions};
use hairsys::scene::SceneFile;

#[test]
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
    assert!(p.inside_fraction <= 1e-4, "{p:?}");
    assert!(p.deepest <= 5e-4, "{p:?}");
    // The strain limit (max_strain = 0.01) to f32 round-off, the worst segment within twice it.
    assert!(r.strain.stretch.p99() <= 0.01 + 1e-4, "{:?}", r.strain);
    assert!(r.strain.stretch.max() <= 0.02, "{:?}", r.strain);
    assert_eq!(r.hairpins.count, 0, "{:?}", r.hairpins);
    // Handed back at frame 30, the hair has fallen back near its groom by frame 48: tips within
    // 2 cm RMS (measured 2026-11-24: 8.1 mm).
    let last = q.last.drift.as_ref().unwrap();
    assert!(last.tip_rms < 0.02, "{last:?}");
}
