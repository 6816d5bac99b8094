//! `hairsys preview` as a library: frames of a cache (whole and sub-frame) drawn from several
//! views into one contact sheet with one framing; highlights count what they mark.

use hair_cache::WriterOptions;
use hair_render::preview::View;
use hairsys::output::preview::{preview, PreviewOptions};
use hairsys::run::{simulate, SimulateOptions};
use hairsys::scene::{SceneFile, DEFAULT_SCENE};

fn small(extra: &str) -> SceneFile {
    let text = DEFAULT_SCENE
        .replace("count = 4000", "count = 150")
        .replace("frames = [1, 48]", "frames = [1, 6]")
        .replace("[hair]", &format!("{extra}\n[hair]"));
    SceneFile::parse(&text, "small", ".".into()).unwrap()
}

fn options(cache: Option<std::path::PathBuf>, out: std::path::PathBuf) -> PreviewOptions {
    PreviewOptions {
        cache,
        scene: None,
        frames: vec![1.0, 3.5, 6.0],
        views: vec![View::Front, View::Side],
        width: 96,
        height: 80,
        highlight: false,
        stretch_limit: 0.01,
        columns: None,
        out,
    }
}

#[test]
fn frames_and_sub_frames_of_a_cache_make_one_sheet() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("run.mcap");
    simulate(
        &SimulateOptions {
            scene: small(""),
            cache: cache.clone(),
            frames: None,
            threads: Some(1),
            writer: WriterOptions::default(),
            resume: false,
            kernel: Default::default(),
            quality: false,
        },
        |_| {},
    )
    .unwrap();
    let out = dir.path().join("sheet.png");
    let summary = preview(&options(Some(cache.clone()), out.clone())).unwrap();
    assert_eq!(summary.tiles, 6);
    // Two columns (one per view) of 96 px and three rows of 80 px, plus gaps and labels.
    assert!(
        summary.width >= 2 * 96 && summary.width < 2 * 96 + 40,
        "{}",
        summary.width
    );
    assert!(summary.height >= 3 * 80, "{}", summary.height);
    let bytes = std::fs::read(&out).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");

    let mut outside = options(Some(cache), dir.path().join("x.png"));
    outside.frames = vec![9.0];
    let e = preview(&outside).unwrap_err().to_string();
    assert!(e.contains("frame 9") && e.contains("frames 1–6"), "{e}");
}

#[test]
fn highlight_counts_hair_inside_a_collider() {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = dir.path().join("ball.toml");
    // A ball through the head at rest: the hair there starts inside it.
    let scene = small(
        "[[colliders]]\nname = \"ball\"\nshape = { kind = \"sphere\", radius = 0.12 }\n\
         motion = { keys = [{ frame = 1, translation = [0.0, 0.0, 0.2] }] }\n",
    );
    std::fs::write(&scene_path, &scene.text).unwrap();
    let mut opts = options(None, dir.path().join("rest.png"));
    opts.scene = Some(scene_path);
    opts.frames.clear();
    opts.views = vec![View::ThreeQuarter];
    opts.highlight = true;
    let summary = preview(&opts).unwrap();
    assert_eq!(summary.tiles, 1);
    assert!(summary.points_inside > 0, "{summary:?}");
    assert_eq!(
        summary.stretched_segments, 0,
        "the rest state is not stretched"
    );
}

#[test]
fn a_preview_of_nothing_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let e = preview(&options(None, dir.path().join("a.png")))
        .unwrap_err()
        .to_string();
    assert!(e.contains("--cache") && e.contains("--scene"), "{e}");
}
