//! Time-sampled USD primvars as painted maps (`hairsys::scene::map_primvars`): a map
//! is read once, at the scene's first frame. A groom-time map (length) takes the primvar's
//! value at the first frame's time code, whichever frame the scene starts at; a map the
//! animator would expect to follow the shot (goal, stiffness, sim weight) is refused when its
//! samples change, naming the primvar, the prim, the file and the frame rule, and read as one
//! value when they are all equal.

use std::path::Path;

use hair_core::Anchor;
use hairsys::scene::SceneFile;

/// Cells per side of the flat grid scalp and its side, m.
const CELLS: usize = 4;
const SIDE: f32 = 0.2;

/// `n` copies of `v`, as a USD array.
fn array(v: f32, n: usize) -> String {
    format!("[{}]", vec![v.to_string(); n].join(", "))
}

/// A flat grid of quads in z = 0 with time-sampled `vertex` primvars: `len` 0.5 at time code 1
/// and 1.0 at 10; `goal` 0.2 at 1 and 0.9 at 10; `steady` 0.4 at both.
fn scalp_usda() -> String {
    let n = CELLS + 1;
    let step = SIDE / CELLS as f32;
    let mut points = Vec::new();
    for j in 0..n {
        for i in 0..n {
            points.push(format!("({}, {}, 0)", i as f32 * step, j as f32 * step));
        }
    }
    let mut indices = Vec::new();
    for j in 0..CELLS {
        for i in 0..CELLS {
            let a = j * n + i;
            indices.extend([a, a + 1, a + n + 1, a + n].map(|k| k.to_string()));
        }
    }
    let v = n * n;
    let sampled = |name: &str, a: f32, b: f32| {
        format!(
            "    float[] primvars:{name} (\n        interpolation = \"vertex\"\n    )\n    \
             float[] primvars:{name}.timeSamples = {{\n        1: {},\n        10: {},\n    }}\n",
            array(a, v),
            array(b, v)
        )
    };
    format!(
        "#usda 1.0\n(\n    metersPerUnit = 1\n    upAxis = \"Z\"\n)\ndef Mesh \"scalp\" {{\n    \
         int[] faceVertexCounts = [{counts}]\n    int[] faceVertexIndices = [{indices}]\n    \
         point3f[] points = [{points}]\n{len}{goal}{steady}}}\n",
        counts = vec!["4"; CELLS * CELLS].join(", "),
        indices = indices.join(", "),
        points = points.join(", "),
        len = sampled("len", 0.5, 1.0),
        goal = sampled("goal", 0.2, 0.9),
        steady = sampled("steady", 0.4, 0.4),
    )
}

/// Straight hair 5 cm long on the USD grid, goal weight 1, frames `first`…`first + 1`.
fn scene(first: u32, maps: &str) -> String {
    format!(
        r#"
[scene]
frames = [{first}, {last}]

[scalp.mesh]
kind = "usd"
path = "scalp.usda"
prim = "/scalp"

[hair]
count = 100
length = 0.05
segments = 3
seed = 7
goal_root = 1.0
goal_tip = 1.0

{maps}
"#,
        last = first + 1
    )
}

fn build(dir: &Path, text: &str) -> Result<hairsys::build::Simulation, String> {
    std::fs::write(dir.join("scalp.usda"), scalp_usda()).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let scene = SceneFile::load(&path).map_err(|e| e.to_string())?;
    scene.build().map_err(|e| e.to_string())
}

/// Each strand's rest length, m.
fn lengths(sim: &hairsys::build::Simulation) -> Vec<f32> {
    (0..sim.strands.len())
        .map(|s| {
            sim.strands.rest_lengths()[sim.strands.segments(s)]
                .iter()
                .sum()
        })
        .collect()
}

#[test]
fn a_time_sampled_length_primvar_is_read_at_the_first_frames_time_code() {
    let dir = tempfile::tempdir().unwrap();
    let maps = "[maps.length]\nprimvar = \"len\"\n";
    // Frame 1 is time code 1 (0.5); a scene starting at frame 10 reads time code 10 (1.0); a
    // scene starting at 20 holds the last sample (1.0).
    for (first, want) in [(1, 0.5), (10, 1.0), (20, 1.0)] {
        let sim = build(dir.path(), &scene(first, maps)).unwrap();
        for (s, l) in lengths(&sim).into_iter().enumerate() {
            assert!(
                matches!(sim.strands.anchors()[s], Anchor::Surface(_)),
                "strand {s} grows on the scalp"
            );
            // Straight hair: the trim is exact but for f32 rounding.
            assert!(
                (l - 0.05 * want).abs() < 1e-6,
                "first frame {first}: strand {s} is {l} m, want {} m",
                0.05 * want
            );
        }
    }
}

#[test]
fn a_goal_primvar_whose_samples_change_is_refused_with_the_frame_rule() {
    let dir = tempfile::tempdir().unwrap();
    let e = build(dir.path(), &scene(1, "[maps.goal]\nprimvar = \"goal\"\n")).unwrap_err();
    for part in [
        "[maps.goal] primvar = \"goal\"",
        "primvars:goal of prim /scalp",
        "scalp.usda",
        "2 time samples (time codes 1 to 10)",
        "read once, at the scene's first frame (frame 1)",
        "goal_stiffness",
    ] {
        assert!(e.contains(part), "{part:?} not in: {e}");
    }
    // The same for a stiffness map; a length map of the same primvar is groom-time: accepted.
    let e = build(
        dir.path(),
        &scene(1, "[maps.stiffness]\nprimvar = \"goal\"\n"),
    )
    .unwrap_err();
    assert!(
        e.contains("a stiffness map is read once") && e.contains("set_region_params"),
        "{e}"
    );
    build(dir.path(), &scene(1, "[maps.length]\nprimvar = \"goal\"\n")).unwrap();
}

#[test]
fn a_goal_primvar_whose_samples_are_all_equal_is_one_value() {
    let dir = tempfile::tempdir().unwrap();
    let sim = build(dir.path(), &scene(1, "[maps.goal]\nprimvar = \"steady\"\n")).unwrap();
    for s in 0..sim.strands.len() {
        for g in &sim.strands.goal_weights()[sim.strands.points(s)] {
            assert!((g - 0.4).abs() < 1e-6, "strand {s}: goal {g}");
        }
    }
}
