//! `[solver] model = "strips"` end to end: the scene grows strips on the built-in head,
//! `simulate` writes a cache of their edge strands, and `render-children cards` turns a cached
//! frame (three motion samples) into a USD Mesh and an OBJ; scene mistakes give clear errors.

use hairsys::output::cards::{export_cards, CardsFormat, CardsOptions};
use hairsys::run::{simulate, SimulateOptions};
use hairsys::scene::SceneFile;

const SCENE: &str = r#"
[scene]
frames = [1, 6]

[solver]
model = "strips"

[scalp.mesh]
kind = "builtin-head"

[scalp.collider]

[scalp.motion]
keys = [
    { frame = 1, rotation_deg = [0.0, 0.0, 0.0] },
    { frame = 6, rotation_deg = [0.0, 0.0, 60.0] },
]

[strips]
length = 0.15
segments = 6
hairs_per_strip = 150
every = 8
max_strips = 40
root_angle_deg = 60.0
region = { direction = [0.0, 0.3, 1.0], max_angle_deg = 70.0 }
"#;

fn args(
    cache: Option<std::path::PathBuf>,
    format: CardsFormat,
    out: std::path::PathBuf,
) -> CardsOptions {
    CardsOptions {
        cache,
        scene: None,
        frame: Some(4),
        shutter: (-0.25, 0.25),
        motion_samples: 3,
        format,
        rows_per_segment: 3,
        columns: 3,
        clearance: 1e-3,
        up_axis: Default::default(),
        out,
    }
}

#[test]
fn strips_scene_simulates_and_exports_cards_from_the_cache() {
    let dir = tempfile::tempdir().unwrap();
    let scene = SceneFile::parse(SCENE, "strips.toml", dir.path().to_path_buf()).unwrap();
    let cache = dir.path().join("strips.mcap");
    let summary = simulate(
        &SimulateOptions {
            scene,
            cache: cache.clone(),
            frames: None,
            threads: Some(1),
            writer: hair_cache::WriterOptions::default(),
            resume: false,
            kernel: Default::default(),
            quality: false,
        },
        |_| {},
    )
    .unwrap();
    assert_eq!(summary.model, "strips");
    assert_eq!(summary.strands, 80);

    let usda = dir.path().join("cards.usda");
    let written = export_cards(&args(Some(cache.clone()), CardsFormat::Usd, usda.clone())).unwrap();
    assert_eq!(written.cards, 40);
    assert_eq!(written.represented_hairs, 40 * 150);
    assert_eq!(written.time_samples, 3);
    assert_eq!(written.vertices, 40 * (6 * 3 + 1) * 3);
    let text = std::fs::read_to_string(&usda).unwrap();
    assert!(text.contains("def Mesh \"cards\"") && text.contains("points.timeSamples"));

    let obj = dir.path().join("cards.obj");
    let written = export_cards(&args(Some(cache), CardsFormat::Obj, obj.clone())).unwrap();
    assert_eq!(written.time_samples, 1);
    // One `f` line per quad (tobj round trips are tested in hair-render).
    let text = std::fs::read_to_string(&obj).unwrap();
    let faces = text.lines().filter(|l| l.starts_with("f ")).count();
    assert_eq!(faces, written.quads);
}

#[test]
fn strips_model_without_a_strips_section_and_strips_with_hair_are_refused() {
    let no_section = SCENE.split("[strips]").next().unwrap();
    let err = SceneFile::parse(no_section, "s.toml", ".".into())
        .unwrap()
        .build()
        .unwrap_err()
        .to_string();
    assert!(err.contains("needs a [strips] section"), "{err}");

    let with_hair = format!("{SCENE}\n[hair]\ncount = 10\nlength = 0.1\nsegments = 4\n");
    let err = SceneFile::parse(&with_hair, "s.toml", ".".into())
        .unwrap()
        .build()
        .unwrap_err()
        .to_string();
    assert!(err.contains("remove [hair]"), "{err}");

    let bad_angle = SCENE.replace("root_angle_deg = 60.0", "root_angle_deg = 180.0");
    let err = SceneFile::parse(&bad_angle, "s.toml", ".".into())
        .unwrap()
        .build()
        .unwrap_err()
        .to_string();
    assert!(err.contains("strictly between 0° and 180°"), "{err}");
}

#[test]
fn strips_head_scene_file_builds() {
    let path =
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../scenes/strips_head.toml");
    let sim = SceneFile::load(&path).unwrap().build().unwrap();
    assert_eq!(sim.model, hair_core::StrandModel::Strips);
    assert!(sim.strips.is_some() && sim.strands.len().is_multiple_of(2) && sim.strands.len() > 100);
}
