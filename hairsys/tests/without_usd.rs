//! The library built without its `usd` feature (`cargo test -p hairsys --no-default-features
//! --test without_usd`): a scene naming a USD scalp or USD guides, and children asked as USD,
//! are refused with an error that names the file and the missing feature, and nothing is
//! written; everything else (a built-in scalp, stepping a session, children as `.hair`) works
//! as in the default build. With the feature on, this file holds no test.
#![cfg(not(feature = "usd"))]

use std::path::Path;

use hairsys::budget::Budget;
use hairsys::output::children::{export, ChildOverrides, ExportOptions, Format};
use hairsys::output::OutputError;
use hairsys::scene::SceneFile;
use hairsys::Session;

/// A small scene on `scalp` (the body of a `[scalp.mesh]` section), with `extra` sections.
fn scene(scalp: &str, extra: &str) -> String {
    format!(
        r#"
[scene]
frames = [1, 3]

[scalp.mesh]
{scalp}

[hair]
count = 40
length = 0.05
segments = 4
seed = 3

{extra}
"#
    )
}

fn write_scene(dir: &Path, text: &str) -> std::path::PathBuf {
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// Loads and builds the scene at `path`, which names the USD file `usd_file`, and checks that it
/// is refused with an error naming that file and the missing feature.
fn assert_refused(path: &Path, usd_file: &str) {
    let text = match SceneFile::load(path).map(|scene| scene.build()) {
        Err(e) => e.to_string(),
        Ok(Err(e)) => e.to_string(),
        Ok(Ok(_)) => panic!("{usd_file} needs the usd feature"),
    };
    assert!(text.contains(usd_file), "names the file: {text}");
    assert!(
        text.contains("Cargo feature `usd`"),
        "names the feature: {text}"
    );
}

/// A one-triangle USD mesh, so the refusal is about the build, not a missing file.
const TRIANGLE_USDA: &str = r#"#usda 1.0
(
    metersPerUnit = 1
    upAxis = "Z"
)
def Mesh "scalp" {
    int[] faceVertexCounts = [3]
    int[] faceVertexIndices = [0, 1, 2]
    point3f[] points = [(0, 0, 0), (0.1, 0, 0), (0, 0.1, 0)]
}
"#;

#[test]
fn a_usd_scalp_is_refused_naming_the_file_and_the_feature() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scalp.usda"), TRIANGLE_USDA).unwrap();
    let path = write_scene(
        dir.path(),
        &scene(
            "kind = \"usd\"\npath = \"scalp.usda\"\nprim = \"/scalp\"",
            "",
        ),
    );
    assert_refused(&path, "scalp.usda");
}

#[test]
fn usd_guides_are_refused_naming_the_file_and_the_feature() {
    let dir = tempfile::tempdir().unwrap();
    let path = write_scene(
        dir.path(),
        &scene(
            "kind = \"builtin-head\"",
            "[guides]\nfile = \"guides.usdc\"\nprim = \"/hair\"",
        ),
    );
    std::fs::write(dir.path().join("guides.usdc"), b"PXR-USDC").unwrap();
    assert_refused(&path, "guides.usdc");
}

#[test]
fn a_scene_on_a_built_in_scalp_steps_and_exports_hair_children_but_no_usd() {
    let dir = tempfile::tempdir().unwrap();
    let path = write_scene(dir.path(), &scene("kind = \"builtin-head\"", ""));
    let scene = SceneFile::load(&path).unwrap();
    let mut session = Session::from_scene(&scene).unwrap();
    let rest: Vec<[f32; 3]> = session.positions().to_vec();
    session.step().unwrap();
    session.step().unwrap();
    let moved = session.positions().iter().zip(&rest).any(|(a, b)| a != b);
    assert!(moved, "gravity moves the free points");
    assert!(session
        .positions()
        .iter()
        .all(|p| p.iter().all(|c| c.is_finite())));

    let options = |format, out: &str| ExportOptions {
        cache: None,
        scene: Some(path.clone()),
        frame: None,
        shutter: (0.0, 0.0),
        motion_samples: 1,
        children: ChildOverrides::default(),
        display: true,
        format,
        out: dir.path().join(out),
        budget: Budget::default(),
        time_offset: 0.0,
    };
    let usd = dir.path().join("children.usdc");
    match export(&options(Format::Usd, "children.usdc"), || {}) {
        Err(OutputError::UsdNotBuilt { path }) => assert_eq!(path, usd),
        other => panic!(
            "children as USD need the usd feature, got {:?}",
            other.err()
        ),
    }
    assert!(!usd.exists(), "nothing is written for a refused format");

    let summary = export(&options(Format::Hair, "children.hair"), || {}).unwrap();
    assert!(summary.curves > 0 && summary.points > summary.curves);
    let bytes = std::fs::read(dir.path().join("children.hair")).unwrap();
    assert_eq!(&bytes[..4], b"HAIR", "a .hair file, by its magic");
}
