//! `hairsys render-children export` on a scene whose OBJ scalp has per-vertex colors
//! (`v x y z r g b`): every child curve gets its root's color as `primvars:displayColor` with
//! uniform interpolation, read back with Pixar's `usd-core`. Needs `pip install usd-core` (module
//! `pxr`); fails, never skips, without it.

mod common;

use std::fmt::Write as _;
use std::process::Command;

use common::{hairsys, tempdir};

/// A flat 10 cm square at z = 0 (normal +z), 4 × 4 quads, colored linearly:
/// `(r, g, b) = (x / 0.1, y / 0.1, 0.25)`, so any point inside has exactly that color.
fn colored_square() -> String {
    let mut obj = String::from("# colored scalp\n");
    for j in 0..5 {
        for i in 0..5 {
            let (x, y) = (0.025 * i as f32, 0.025 * j as f32);
            let _ = writeln!(obj, "v {x} {y} 0 {} {} 0.25", x / 0.1, y / 0.1);
        }
    }
    for j in 0..4 {
        for i in 0..4 {
            let v = 1 + i + 5 * j;
            let _ = writeln!(obj, "f {} {} {} {}", v, v + 1, v + 6, v + 5);
        }
    }
    obj
}

const SCENE: &str = r#"
[scene]
frames = [1, 2]

[scalp.mesh]
kind = "obj"
path = "scalp.obj"

[hair]
count = 30
length = 0.05
segments = 4
"#;

const CHECK: &str = r#"
import sys
from pxr import Usd, UsdGeom
path, tolerance = sys.argv[1], float(sys.argv[2])
stage = Usd.Stage.Open(path)
curves = UsdGeom.BasisCurves(stage.GetDefaultPrim())
counts = curves.GetCurveVertexCountsAttr().Get()
points = curves.GetPointsAttr().Get()
color = UsdGeom.PrimvarsAPI(curves).GetPrimvar("displayColor")
assert color, "no primvars:displayColor"
assert color.GetInterpolation() == UsdGeom.Tokens.uniform, color.GetInterpolation()
rgb = color.Get()
assert len(rgb) == len(counts) == 120, (len(rgb), len(counts))
start, worst = 0, 0.0
for n, c in zip(counts, rgb):
    root = points[start]
    want = (root[0] / 0.1, root[1] / 0.1, 0.25)
    worst = max(worst, max(abs(c[i] - want[i]) for i in range(3)))
    start += n
assert worst <= tolerance, f"root color off the scalp's color by {worst}"
assert len({tuple(c) for c in rgb}) > 20, "children take different colors"
print("ok", path, len(rgb), "colors, worst", worst)
"#;

#[test]
fn obj_scalp_vertex_colors_color_the_children_roots() {
    let dir = tempdir("render-colors");
    std::fs::write(dir.join("scalp.obj"), colored_square()).unwrap();
    std::fs::write(dir.join("scene.toml"), SCENE).unwrap();
    // Interpolated children sit on the scalp with its color there (exact for a linear color);
    // simple children take their parent root's color, at most the 5 mm spread away: 0.05.
    for (mode, out, tolerance) in [
        ("interpolated", "interpolated.usda", "1e-4"),
        ("simple", "simple.usda", "0.0501"),
    ] {
        let run = hairsys(
            &[
                "render-children",
                "export",
                "--scene",
                "scene.toml",
                "--mode",
                mode,
                "--children-per-parent",
                "4",
                "--spread",
                "0.005",
                "-o",
                out,
                "--quiet",
            ],
            &dir,
        );
        assert!(
            run.status.success(),
            "{mode}: {}",
            String::from_utf8_lossy(&run.stderr)
        );
        let check = Command::new("python3")
            .args(["-c", CHECK, out, tolerance])
            .current_dir(&dir)
            .output()
            .expect("python3 runs (install Python 3 and `pip install usd-core`)");
        assert!(
            check.status.success(),
            "USD check of {out} failed (`pip install usd-core` if pxr is missing):\n{}{}",
            String::from_utf8_lossy(&check.stdout),
            String::from_utf8_lossy(&check.stderr)
        );
    }
}
