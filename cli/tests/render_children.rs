//! `hairsys render-children export` through the real binary: from a cache with motion-blur time
//! samples (the sample at shutter offset 0 is the cached frame's children exactly, read back with
//! Pixar's `usd-core`), from the rest state as `.hair`, and clear errors for a frame outside the
//! cache. Needs `pip install usd-core` (module `pxr`); fails, never skips, without it.

mod common;

use std::process::Command;

use common::{hairsys, tempdir};

const SCENE: &str = r#"
[scene]
frames = [1, 6]

[scalp.mesh]
kind = "builtin-head"

[scalp.motion]
keys = [
    { frame = 1, rotation_deg = [0.0, 0.0, 0.0] },
    { frame = 6, rotation_deg = [0.0, 0.0, 40.0] },
]

[hair]
count = 40
length = 0.2
segments = 8
"#;

#[test]
fn motion_blur_samples_and_rest_export() {
    let dir = tempdir("render");
    std::fs::write(dir.join("scene.toml"), SCENE).unwrap();
    let ok = |args: &[&str]| {
        let out = hairsys(args, &dir);
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    ok(&["simulate", "scene.toml", "--cache", "c.mcap", "--quiet"]);
    ok(&[
        "render-children",
        "export",
        "--cache",
        "c.mcap",
        "--frame",
        "4",
        "--shutter=-0.5,0.5",
        "--motion-samples",
        "3",
        "--children-per-parent",
        "3",
        "--curl-radius",
        "0.002",
        "--curl-frequency",
        "30",
        "-o",
        "blur.usda",
        "--quiet",
    ]);
    ok(&[
        "render-children",
        "export",
        "--cache",
        "c.mcap",
        "--frame",
        "4",
        "--children-per-parent",
        "3",
        "--curl-radius",
        "0.002",
        "--curl-frequency",
        "30",
        "-o",
        "still.usda",
        "--quiet",
    ]);
    ok(&[
        "render-children",
        "export",
        "--scene",
        "scene.toml",
        "--format",
        "hair",
        "-o",
        "rest.hair",
        "--quiet",
    ]);
    assert!(std::fs::metadata(dir.join("rest.hair")).unwrap().len() > 128);

    let script = r#"
import sys
from pxr import Usd, UsdGeom
blur_stage, still_stage = Usd.Stage.Open(sys.argv[1]), Usd.Stage.Open(sys.argv[2])
blur = UsdGeom.BasisCurves(blur_stage.GetDefaultPrim())
still = UsdGeom.BasisCurves(still_stage.GetDefaultPrim())
times = blur.GetPointsAttr().GetTimeSamples()
assert times == [3.5, 4.0, 4.5], times
assert len(blur.GetCurveVertexCountsAttr().Get()) == 120
centre = blur.GetPointsAttr().Get(4.0)
assert list(centre) == list(still.GetPointsAttr().Get()), "the centre sample differs from the frame"
assert list(blur.GetPointsAttr().Get(3.5)) != list(centre), "the shutter's open sample equals the frame"
print("ok", len(centre), "points per sample")
"#;
    let out = Command::new("python3")
        .args(["-c", script, "blur.usda", "still.usda"])
        .current_dir(&dir)
        .output()
        .expect("python3 runs (install Python 3 and `pip install usd-core`)");
    assert!(
        out.status.success(),
        "USD check failed (`pip install usd-core` if pxr is missing):\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );

    let outside = hairsys(
        &[
            "render-children",
            "export",
            "--cache",
            "c.mcap",
            "--frame",
            "40",
            "-o",
            "x.usda",
        ],
        &dir,
    );
    assert_eq!(outside.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&outside.stderr);
    assert!(
        stderr.contains("c.mcap") && stderr.contains("frames 1–6"),
        "{stderr}"
    );
    assert!(!dir.join("x.usda").exists());
}

/// A small scene with a `[children]` section: interpolated children, 2 per parent, shaped.
const SCENE_WITH_CHILDREN: &str = r#"
[scene]
frames = [1, 3]

[scalp.mesh]
kind = "builtin-head"

[hair]
count = 30
length = 0.15
segments = 6

[children]
mode = "interpolated"
per_parent = 2
neighbours = 3
spread = 0.01
seed = 5
clump = { factor = 0.3 }
curl = { radius = 0.002, frequency = 30 }
roughness = { endpoint = 0.001 }
display = { fraction = 0.5, subdivisions = 1 }
"#;

fn summary(out: &std::process::Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("--json prints one JSON summary")
}

#[test]
fn scene_children_section_is_used_and_flags_override_it() {
    let dir = tempdir("render-scene-children");
    std::fs::write(dir.join("scene.toml"), SCENE_WITH_CHILDREN).unwrap();
    let export = |extra: &[&str], out: &str| {
        let mut args = vec![
            "render-children",
            "export",
            "--scene",
            "scene.toml",
            "--json",
            "-o",
            out,
        ];
        args.extend_from_slice(extra);
        summary(&hairsys(&args, &dir))
    };
    // 30 parents × 2 children from the scene; 6 segments × 4 pieces + 1 points each.
    let s = export(&[], "scene.usda");
    assert_eq!(s["curves"], 60);
    assert_eq!(s["points"], 60 * 25);
    // The flag overrides the scene's count; display takes the scene's display fraction (½) and
    // subdivisions (1: the parents' 7 points).
    let s = export(&["--children-per-parent", "4", "--display"], "display.usda");
    assert_eq!(s["curves"], 60);
    assert_eq!(s["points"], 60 * 7);
    // --mode simple overrides the scene's interpolated mode: other roots, same counts.
    export(&["--mode", "simple"], "simple.usda");
    let script = r#"
import sys
from pxr import Usd, UsdGeom
stages = [Usd.Stage.Open(p) for p in sys.argv[1:3]]
a, b = (UsdGeom.BasisCurves(s.GetDefaultPrim()) for s in stages)
assert len(a.GetCurveVertexCountsAttr().Get()) == 60
assert list(a.GetPointsAttr().Get()) != list(b.GetPointsAttr().Get())
print("ok")
"#;
    let out = Command::new("python3")
        .args(["-c", script, "scene.usda", "simple.usda"])
        .current_dir(&dir)
        .output()
        .expect("python3 runs (install Python 3 and `pip install usd-core`)");
    assert!(
        out.status.success(),
        "USD check failed (`pip install usd-core` if pxr is missing):\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn bad_children_input_is_refused_and_nothing_is_left_behind() {
    let dir = tempdir("render-bad-children");
    let bad_key = SCENE_WITH_CHILDREN.replace("per_parent = 2", "per_parent = 2\ncurls = 3");
    std::fs::write(dir.join("bad_key.toml"), bad_key).unwrap();
    let bad_value =
        SCENE_WITH_CHILDREN.replace("clump = { factor = 0.3 }", "clump = { factor = 3.0 }");
    std::fs::write(dir.join("bad_value.toml"), bad_value).unwrap();
    std::fs::write(dir.join("scene.toml"), SCENE_WITH_CHILDREN).unwrap();
    std::fs::write(dir.join("junk.mcap"), b"not a cache at all").unwrap();
    let refuse = |args: &[&str], wants: &[&str]| {
        let out = hairsys(args, &dir);
        let stderr = String::from_utf8_lossy(&out.stderr);
        // Bad input exits 2; an output that cannot be written is a failed run, 1.
        let want = if args.iter().any(|a| a.starts_with("no/such/dir")) {
            1
        } else {
            2
        };
        assert_eq!(out.status.code(), Some(want), "{args:?}: {stderr}");
        for w in wants {
            assert!(stderr.contains(w), "{args:?}: `{w}` missing in: {stderr}");
        }
    };
    let base = ["render-children", "export", "-o", "x.usda", "--scene"];
    refuse(
        &[&base[..], &["bad_key.toml"]].concat(),
        &["bad_key.toml", "curls"],
    );
    refuse(
        &[&base[..], &["bad_value.toml"]].concat(),
        &["bad_value.toml", "[children] clump.factor = 3", "[-1, 1]"],
    );
    refuse(
        &[&base[..], &["scene.toml", "--children-per-parent", "0"]].concat(),
        &["children_per_parent", "at least 1"],
    );
    refuse(
        &[&base[..], &["scene.toml", "--count", "0"]].concat(),
        &["count", "at least 1"],
    );
    refuse(
        &[
            &base[..],
            &["scene.toml", "--mode", "simple", "--neighbours", "3"],
        ]
        .concat(),
        &["--neighbours", "interpolated"],
    );
    refuse(
        &[
            "render-children",
            "export",
            "--cache",
            "junk.mcap",
            "--frame",
            "1",
            "-o",
            "x.usda",
        ],
        &["junk.mcap"],
    );
    refuse(
        &[
            "render-children",
            "export",
            "--scene",
            "scene.toml",
            "-o",
            "no/such/dir/x.usda",
        ],
        &["no/such/dir/x.usda"],
    );
    refuse(
        &[
            "render-children",
            "export",
            "--scene",
            "scene.toml",
            "--format",
            "hair",
            "-o",
            "no/such/dir/x.hair",
        ],
        &["no/such/dir/x.hair"],
    );
    // Nothing half-written anywhere.
    let mut left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(
        left,
        ["bad_key.toml", "bad_value.toml", "junk.mcap", "scene.toml"]
    );
}
