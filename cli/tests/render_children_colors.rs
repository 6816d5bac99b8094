//! `hairsys render-children export` on a scene whose OBJ scalp has per-vertex colors
//! (`v x y z r g b`): every child curve gets its root's color as `primvars:displayColor` with
//! uniform interpolation, read back with Pixar's `usd-core`. Needs `pip install usd-core` (module
//! `pxr`); fails, never skips, without it.

mod common;

use std::process::Command;

use common::{colored_square_obj, hairsys, tempdir};

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
    std::fs::write(dir.join("scalp.obj"), colored_square_obj()).unwrap();
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
