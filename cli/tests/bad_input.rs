//! Bad input through the real `hairsys` binary: a clear message naming the file, the field and
//! the fix on stderr, a non-zero exit code, and no file left that looks like a complete cache.

mod common;

use common::{hairsys, tempdir};

/// A small valid scene; each test replaces one line to make it bad.
const SCENE: &str = r#"
[scene]
frames = [1, 3]

[physics]
stretch_stiffness = 20.0

[scalp.mesh]
kind = "uv-sphere"
radius = 0.1
segments = 12
rings = 8

[hair]
count = 10
length = 0.1
segments = 4
"#;

fn run_bad(name: &str, scene: &str, expect: &[&str]) {
    let dir = tempdir(name);
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
    let out = hairsys(
        &["simulate", "scene.toml", "--cache", "out.mcap", "--quiet"],
        &dir,
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    eprintln!("{name}: {stderr}");
    assert_eq!(
        out.status.code(),
        Some(2),
        "{name}: exit code, stderr: {stderr}"
    );
    assert!(
        stderr.contains("scene.toml"),
        "{name}: the message names the file: {stderr}"
    );
    for e in expect {
        assert!(
            stderr.contains(e),
            "{name}: the message mentions `{e}`: {stderr}"
        );
    }
    assert!(
        !dir.join("out.mcap").exists(),
        "{name}: no cache may be left"
    );
}

#[test]
fn unknown_key_is_named() {
    run_bad(
        "unknown-key",
        &SCENE.replace("stretch_stiffness = 20.0", "strech_stiffness = 20.0"),
        &["strech_stiffness"],
    );
}

#[test]
fn negative_parameter_is_named() {
    run_bad(
        "negative",
        &SCENE.replace("stretch_stiffness = 20.0", "stretch_stiffness = -1.0"),
        &["stretch_stiffness", "≥ 0"],
    );
}

#[test]
fn nan_parameter_is_named() {
    run_bad(
        "nan",
        &SCENE.replace("stretch_stiffness = 20.0", "stretch_stiffness = nan"),
        &["stretch_stiffness"],
    );
}

#[test]
fn missing_obj_is_named() {
    let scene = SCENE.replace(
        "kind = \"uv-sphere\"\nradius = 0.1\nsegments = 12\nrings = 8",
        "kind = \"obj\"\npath = \"nowhere/head.obj\"",
    );
    run_bad("missing-obj", &scene, &["head.obj"]);
}

#[test]
fn degenerate_obj_triangle_is_named() {
    let dir = tempdir("degenerate");
    std::fs::write(
        dir.join("flat.obj"),
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 4\nf 1 2 3\n",
    )
    .unwrap();
    let scene = SCENE.replace(
        "kind = \"uv-sphere\"\nradius = 0.1\nsegments = 12\nrings = 8",
        "kind = \"obj\"\npath = \"flat.obj\"",
    );
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
    let out = hairsys(
        &["simulate", "scene.toml", "--cache", "out.mcap", "--quiet"],
        &dir,
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("flat.obj") && stderr.contains("degenerate"),
        "{stderr}"
    );
    assert!(!dir.join("out.mcap").exists());
}

#[test]
fn zero_length_segment_is_named() {
    let scene =
        "[scene]\nframes = [1, 3]\n[[strands]]\npoints = [[0, 0, 0], [0, 0, -0.1], [0, 0, -0.1]]\n";
    run_bad("zero-length", scene, &["segment 1", "zero length"]);
}

#[test]
fn unwritable_cache_path_fails_before_simulating() {
    let dir = tempdir("unwritable");
    std::fs::write(dir.join("scene.toml"), SCENE).unwrap();
    let out = hairsys(
        &[
            "simulate",
            "scene.toml",
            "--cache",
            "no/such/dir/out.mcap",
            "--quiet",
        ],
        &dir,
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("no/such/dir"),
        "the message names the path: {stderr}"
    );
}

#[test]
fn blow_up_leaves_no_complete_cache() {
    // Stiff springs with a fixed substep far above the stability bound of the explicit
    // integrator (named: "auto" would take BDF2, which is stable there).
    let scene = SCENE.replace(
        "[physics]\nstretch_stiffness = 20.0",
        "[solver]\nintegrator = \"semi-implicit-euler\"\nsubsteps = 1\n[physics]\n\
         stretch_stiffness = 5000.0",
    );
    let dir = tempdir("blow-up");
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
    let out = hairsys(
        &["simulate", "scene.toml", "--cache", "out.mcap", "--quiet"],
        &dir,
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    eprintln!("{stderr}");
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("blew up at frame") && stderr.contains("2/ω"),
        "{stderr}"
    );
    assert!(
        !dir.join("out.mcap").exists(),
        "no complete-looking cache after a blow-up"
    );
}

#[test]
fn scene_init_prints_the_builtin_default_which_runs() {
    let dir = tempdir("init");
    let out = hairsys(&["scene", "init"], &dir);
    assert!(out.status.success());
    std::fs::write(dir.join("default.toml"), &out.stdout).unwrap();
    let check = hairsys(&["scene", "check", "default.toml"], &dir);
    assert!(
        check.status.success(),
        "{}",
        String::from_utf8_lossy(&check.stderr)
    );
    assert!(String::from_utf8_lossy(&check.stdout).contains("4000 strands"));
}

#[test]
fn every_command_has_help() {
    let dir = tempdir("help");
    for args in [
        &["--help"][..],
        &["simulate", "--help"],
        &["scene", "--help"],
        &["scene", "init", "--help"],
        &["scene", "check", "--help"],
        &["cache", "--help"],
        &["cache", "info", "--help"],
    ] {
        let out = hairsys(args, &dir);
        assert!(out.status.success(), "{args:?}");
        assert!(
            String::from_utf8_lossy(&out.stdout).contains("Usage"),
            "{args:?}"
        );
    }
}

/// A scene with the Sintel groom on a sphere far smaller than the groom: every root is too far.
fn guides_scene(extra: &str) -> String {
    let tfx = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../data/sintel/sintel_hair.tfx"
    );
    format!(
        "[scene]\nframes = [1, 3]\n[scalp.mesh]\nkind = \"uv-sphere\"\nradius = 0.1\nsegments = 12\nrings = 8\n\
         [guides]\nfile = \"{tfx}\"\nscale = 0.01\nup_axis = \"y\"\n{extra}"
    )
}

#[test]
fn guides_too_far_from_the_scalp_are_named() {
    run_bad(
        "guides-far",
        &guides_scene("[sim_hairs]\ncount = 10\n"),
        &["[guides]", "strand", "max_snap_distance"],
    );
}

#[test]
fn guides_without_sim_hairs_and_sim_hairs_without_guides_are_explained() {
    run_bad(
        "guides-alone",
        &guides_scene("max_snap_distance = 1.0\n"),
        &["[sim_hairs]"],
    );
    let scene = "[scene]\nframes = [1, 3]\n[scalp.mesh]\nkind = \"builtin-head\"\n[sim_hairs]\ncount = 10\n";
    run_bad("sim-hairs-alone", scene, &["[guides]"]);
    run_bad(
        "disabled-out-of-range",
        &guides_scene("max_snap_distance = 1.0\ndisabled = [500]\n[sim_hairs]\ncount = 10\n"),
        &["disabled", "500"],
    );
}
