//! `[solver] model = "rod"` through the real binary: the rod model runs, `simulate` says so (text
//! and JSON, and in the cache's metadata), and bad `[rod]` input is refused with exit code 2.

mod common;

use common::{hairsys, tempdir};

const ROD_SCENE: &str = r#"
[scene]
name = "rod model"
frames = [1, 4]

[solver]
model = "rod"

[physics]
air_drag = 2.0

[rod]
semi_major_axis = 1.5e-4
axis_ratio = 0.7

[scalp.mesh]
kind = "builtin-head"

[scalp.collider]
thickness = 0.0
friction = 0.0

[hair]
count = 20
length = 0.15
segments = 8
seed = 2
radius = 0.002
mass_per_length = 0.001
"#;

#[test]
fn rod_scene_runs_and_reports_its_model() {
    let dir = tempdir("rod-model");
    std::fs::write(dir.join("rod.toml"), ROD_SCENE).unwrap();
    let out = hairsys(&["simulate", "rod.toml", "--cache", "rod.mcap"], &dir);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("model: rod"), "{stdout}");
    assert!(stdout.contains("projection:"), "{stdout}");
    assert!(stdout.contains("quasistatic twist"), "{stdout}");

    let out = hairsys(
        &["simulate", "rod.toml", "--cache", "rod2.mcap", "--json"],
        &dir,
    );
    assert!(out.status.success());
    let stdout = String::from_utf8_lossy(&out.stdout);
    let done = stdout
        .lines()
        .find(|l| l.contains("\"done\""))
        .expect("a summary line");
    assert!(done.contains("\"model\":\"rod\""), "{done}");
    assert!(done.contains("\"max_strain\""), "{done}");

    // The cache's metadata records the model (the header's extra map is stored as text).
    let bytes = std::fs::read(dir.join("rod.mcap")).unwrap();
    let text = String::from_utf8_lossy(&bytes);
    assert!(text.contains("model") && text.contains("rod"));
}

#[test]
fn mass_spring_is_the_default_and_says_so() {
    let dir = tempdir("mass-spring-model");
    let scene = ROD_SCENE
        .replace("model = \"rod\"", "")
        .replace("[rod]\nsemi_major_axis = 1.5e-4\naxis_ratio = 0.7\n", "");
    std::fs::write(dir.join("ms.toml"), scene).unwrap();
    let out = hairsys(&["simulate", "ms.toml", "--cache", "ms.mcap"], &dir);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    assert!(stdout.contains("model: mass-spring"), "{stdout}");
    assert!(!stdout.contains("projection:"), "{stdout}");
}

#[test]
fn bad_rod_input_is_refused_by_name() {
    let dir = tempdir("rod-bad");
    for (name, scene, expect) in [
        (
            "ratio.toml",
            ROD_SCENE.replace("axis_ratio = 0.7", "axis_ratio = 0.0"),
            "rod.axis_ratio",
        ),
        (
            "orphan.toml",
            ROD_SCENE.replace("model = \"rod\"", "model = \"mass-spring\""),
            "[rod] is given but [solver] model = \"mass-spring\"",
        ),
        (
            "unknown.toml",
            ROD_SCENE.replace("model = \"rod\"", "model = \"cosserat\""),
            "model",
        ),
    ] {
        std::fs::write(dir.join(name), scene).unwrap();
        let out = hairsys(&["simulate", name, "--cache", "x.mcap"], &dir);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name}: {stderr}");
        assert!(stderr.contains(expect), "{name}: {stderr}");
        assert!(stderr.contains(name), "{name} names the file: {stderr}");
    }
}

#[test]
fn shipped_rod_scene_checks_as_the_rod_model() {
    let scene =
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../scenes/rod_head.toml");
    let out = hairsys(
        &["scene", "check", scene.to_str().unwrap()],
        &tempdir("rod-scene-check"),
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    assert!(stdout.contains("model: rod"), "{stdout}");
}
