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
    assert_eq!(outside.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&outside.stderr);
    assert!(
        stderr.contains("c.mcap") && stderr.contains("frames 1–6"),
        "{stderr}"
    );
    assert!(!dir.join("x.usda").exists());
}
