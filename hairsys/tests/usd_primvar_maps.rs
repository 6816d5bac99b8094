//! Painted maps from a USD scalp's primvars (`[maps.NAME] primvar = "…"`): a root
//! takes the barycentric blend of its triangle's corner values under each of USD's
//! interpolations (so a linear field painted per point or per face corner is the field at the
//! root, and a per-face value the value of the root's face); a primvar that is missing, whose
//! count does not fit its interpolation, or that is asked of a scalp without primvars is
//! refused naming the file, the prim, the primvar and the fix.

use std::path::Path;

use hair_core::Anchor;
use hairsys::scene::SceneFile;
use nalgebra::Vector3;

/// Cells per side of the flat grid scalp and its side, m.
const CELLS: usize = 4;
const SIDE: f32 = 0.2;

/// A linear field over the grid, within [0.1, 0.8].
fn field(x: f32, y: f32) -> f32 {
    0.1 + 1.5 * x + 2.0 * y
}

/// Value of the `per_face` primvar on face `f`.
fn face_value(f: usize) -> f32 {
    0.1 + 0.04 * f as f32
}

/// A flat `CELLS × CELLS` grid of quads in z = 0 (Z up, meters), normals up, with primvars:
/// `lin` (vertex), `lin_corners` (faceVarying, indexed: one value per point, indexed by the
/// corners), `per_face` (uniform) and `short` (vertex, one value too few).
fn scalp_usda() -> String {
    let n = CELLS + 1;
    let step = SIDE / CELLS as f32;
    let mut points = Vec::new();
    let mut lin = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (x, y) = (i as f32 * step, j as f32 * step);
            points.push(format!("({x}, {y}, 0)"));
            lin.push(format!("{}", field(x, y)));
        }
    }
    let mut indices = Vec::new();
    for j in 0..CELLS {
        for i in 0..CELLS {
            let a = j * n + i;
            // Counter-clockwise seen from +z: the normal points up.
            indices.extend([a, a + 1, a + n + 1, a + n].map(|k| k.to_string()));
        }
    }
    let faces = CELLS * CELLS;
    let per_face: Vec<String> = (0..faces).map(|f| face_value(f).to_string()).collect();
    format!(
        r#"#usda 1.0
(
    metersPerUnit = 1
    upAxis = "Z"
)
def Mesh "scalp" {{
    int[] faceVertexCounts = [{counts}]
    int[] faceVertexIndices = [{indices}]
    point3f[] points = [{points}]
    float[] primvars:lin = [{lin}] (interpolation = "vertex")
    float[] primvars:lin_corners = [{lin}] (interpolation = "faceVarying")
    int[] primvars:lin_corners:indices = [{indices}]
    float[] primvars:per_face = [{per_face}] (interpolation = "uniform")
    float[] primvars:short = [0.5, 0.5] (interpolation = "vertex")
}}
"#,
        counts = vec!["4"; faces].join(", "),
        indices = indices.join(", "),
        points = points.join(", "),
        lin = lin.join(", "),
        per_face = per_face.join(", "),
    )
}

/// A scene with hair on the USD grid scalp, goal weight 1 at every point, and `maps`.
fn scene(maps: &str) -> String {
    format!(
        r#"
[scene]
frames = [1, 2]

[scalp.mesh]
kind = "usd"
path = "scalp.usda"
prim = "/scalp"

[hair]
count = 300
length = 0.05
segments = 3
seed = 7
goal_root = 1.0
goal_tip = 1.0

{maps}
"#
    )
}

fn build(dir: &Path, text: &str) -> Result<hairsys::build::Simulation, String> {
    std::fs::write(dir.join("scalp.usda"), scalp_usda()).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let scene = SceneFile::load(&path).map_err(|e| e.to_string())?;
    scene.build().map_err(|e| e.to_string())
}

/// Each strand's root position and its goal weights after the root.
fn roots_and_goals(sim: &hairsys::build::Simulation) -> Vec<(Vector3<f32>, Vec<f32>)> {
    let scalp = sim.scalp_at(sim.first_frame as f32);
    let mesh = scalp.mesh.as_ref().unwrap();
    let strands = &sim.strands;
    (0..strands.len())
        .map(|s| {
            let Anchor::Surface(sample) = strands.anchors()[s] else {
                panic!("[hair] grows on the scalp")
            };
            let goals = strands.goal_weights()[strands.points(s)][1..].to_vec();
            (mesh.evaluate(&sample).origin, goals)
        })
        .collect()
}

#[test]
fn vertex_and_indexed_face_varying_primvars_give_each_root_the_painted_field() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["lin", "lin_corners"] {
        let sim = build(
            dir.path(),
            &scene(&format!("[maps.goal]\nprimvar = \"{name}\"\n")),
        )
        .unwrap();
        let roots = roots_and_goals(&sim);
        assert_eq!(roots.len(), 300);
        for (root, goals) in roots {
            // Barycentric blending of a linear field is the field at the root (to f32).
            let want = field(root.x, root.y);
            for g in goals {
                assert!(
                    (g - want).abs() < 1e-5,
                    "{name}: goal {g}, field {want} at {root:?}"
                );
            }
        }
    }
}

#[test]
fn a_uniform_primvar_gives_each_root_its_faces_value() {
    let dir = tempfile::tempdir().unwrap();
    let sim = build(dir.path(), &scene("[maps.goal]\nprimvar = \"per_face\"\n")).unwrap();
    let cell = SIDE / CELLS as f32;
    let mut checked = 0;
    for (root, goals) in roots_and_goals(&sim) {
        let (fx, fy) = (root.x / cell, root.y / cell);
        // A root on a cell edge may lie on either face.
        let near_edge = |f: f32| (f - f.round()).abs() < 1e-3;
        if near_edge(fx) || near_edge(fy) {
            continue;
        }
        let face = fy.floor() as usize * CELLS + fx.floor() as usize;
        for g in goals {
            assert!(
                (g - face_value(face)).abs() < 1e-6,
                "goal {g} on face {face}"
            );
        }
        checked += 1;
    }
    assert!(checked > 250, "only {checked} roots off the edges");
}

#[test]
fn a_primvar_whose_count_does_not_fit_its_interpolation_is_refused_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let e = build(dir.path(), &scene("[maps.goal]\nprimvar = \"short\"\n")).unwrap_err();
    for part in [
        "[maps.goal] primvar = \"short\"",
        "scalp.usda",
        "prim /scalp",
        "primvars:short",
        "2 values",
        "25 points",
    ] {
        assert!(e.contains(part), "{part:?} not in: {e}");
    }
}

#[test]
fn a_missing_primvar_is_refused_listing_the_prims_primvars() {
    let dir = tempfile::tempdir().unwrap();
    let e = build(dir.path(), &scene("[maps.goal]\nprimvar = \"density\"\n")).unwrap_err();
    for part in [
        "[maps.goal]",
        "scalp.usda",
        "primvars:density",
        "primvars:lin",
    ] {
        assert!(e.contains(part), "{part:?} not in: {e}");
    }
}

#[test]
fn a_primvar_map_on_an_obj_scalp_is_refused_naming_the_scalp_and_the_alternative() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("scalp.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    let text = scene("[maps.goal]\nprimvar = \"lin\"\n").replace(
        "kind = \"usd\"\npath = \"scalp.usda\"\nprim = \"/scalp\"",
        "kind = \"obj\"\npath = \"scalp.obj\"",
    );
    let e = build(dir.path(), &text).unwrap_err();
    for part in [
        "[maps.goal] primvar = \"lin\"",
        "scalp.obj",
        "no primvars",
        "vertex_colors",
    ] {
        assert!(e.contains(part), "{part:?} not in: {e}");
    }
}

#[test]
fn a_primvar_and_a_texture_in_one_map_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let e = build(
        dir.path(),
        &scene("[maps.goal]\nprimvar = \"lin\"\ntexture = \"goal.png\"\n"),
    )
    .unwrap_err();
    assert!(e.contains("give one of"), "{e}");
}
