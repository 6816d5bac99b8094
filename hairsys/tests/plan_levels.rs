//! How many sim hairs the default head scene needs: render hairs
//! interpolated from N simulated hairs against all 4,000 simulated, error against cost.
//!
//! Slow (runs the default scene's 4,000 strands once, then each count): ignored by default.
//! Run it in release, the table goes to stderr:
//! `PLAN_LEVEL_FRAMES=1-25 cargo test --release -p hairsys --test plan_levels -- --ignored --nocapture`

use std::path::Path;

use hairsys::plan::study::{knee, sim_hair_levels};
use hairsys::scene::SceneFile;

#[test]
#[ignore = "slow: the default scene's 4,000 strands and seven sim-hair counts"]
fn sim_hair_levels_of_the_default_scene() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/default.toml");
    let scene = SceneFile::load(&path).unwrap();
    let frames = std::env::var("PLAN_LEVEL_FRAMES")
        .ok()
        .and_then(|s| {
            let (a, b) = s.split_once('-')?;
            Some((a.parse().ok()?, b.parse().ok()?))
        })
        .unwrap_or((1, 25));
    let rows = sim_hair_levels(&scene, frames, &[50, 100, 200, 500, 1000, 2000], 8).unwrap();
    let k = knee(&rows[..rows.len() - 1]);
    eprintln!("| sim hairs | ms/frame | worst-frame RMS mm | RMS mm | worst-frame tip RMS mm |");
    eprintln!("|---|---|---|---|---|");
    for (i, r) in rows.iter().enumerate() {
        eprintln!(
            "| {}{} | {:.1} | {:.2} | {:.2} | {:.2} |",
            r.sim_hairs,
            if Some(i) == k { " (knee)" } else { "" },
            r.ms_per_frame,
            r.errors.rms_max * 1e3,
            r.errors.rms * 1e3,
            r.errors.tip_max * 1e3
        );
    }
    // Physics, not printed figures: fewer sim hairs never interpolate the groom better by
    // much (the error falls, within noise, as the count grows), and all of them is exact.
    for w in rows.windows(2) {
        assert!(
            w[1].errors.rms_max <= w[0].errors.rms_max * 1.25 + 1e-4,
            "more sim hairs, larger error: {rows:?}"
        );
    }
    assert_eq!(rows.last().unwrap().errors.rms_max, 0.0);
}
