//! Outputs open a cache alone: after `simulate`, the scene file and every mesh it names (an OBJ
//! scalp with vertex colours, a keyframed OBJ collider, a deforming OBJ-sequence collider) are
//! moved away, and `render-children export`, `cache export` (strands and children), `preview
//! --highlight --report` and `render-children export --frames` still work and write exactly what
//! they wrote while the files were there.

mod common;

use std::path::Path;

use common::{colored_square_obj, hairsys, tempdir};

/// A tetrahedron of edge about `size` m around the origin, its apex raised by `lift` m.
fn tetrahedron(size: f32, lift: f32) -> String {
    format!(
        "v 0 0 {}\nv {s} 0 0\nv 0 {s} 0\nv 0 0 0\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n",
        size + lift,
        s = size
    )
}

const SCENE: &str = r#"
[scene]
frames = [1, 5]

[scalp.mesh]
kind = "obj"
path = "meshes/scalp.obj"

[scalp.collider]
thickness = 0.001

[hair]
count = 24
length = 0.06
segments = 5

[[colliders]]
name = "rock"
shape = { kind = "obj", path = "meshes/rock.obj" }
motion = { keys = [
    { frame = 1, translation = [0.05, 0.05, 0.03] },
    { frame = 5, translation = [0.06, 0.04, 0.02] },
] }

[[colliders]]
name = "blob"
shape = { kind = "obj-sequence", path = "meshes/blob_####.obj" }
motion = { keys = [{ frame = 1, translation = [0.02, 0.08, 0.02] }] }
"#;

fn run(dir: &Path, args: &[&str]) {
    let out = hairsys(args, dir);
    assert!(
        out.status.success(),
        "hairsys {args:?}: {}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Every output of `run.mcap` in `dir`, written with `tag` in its file names.
fn outputs(dir: &Path, tag: &str) -> Vec<String> {
    let names: Vec<String> = [
        "children.usda",
        "strands.usda",
        "shot_children.usda",
        "view.png",
    ]
    .iter()
    .map(|n| format!("{tag}_{n}"))
    .collect();
    run(
        dir,
        &[
            "render-children",
            "export",
            "--cache",
            "run.mcap",
            "--frame",
            "3",
            "--shutter=-0.25,0.25",
            "--mode",
            "interpolated",
            "-o",
            &names[0],
            "--quiet",
        ],
    );
    run(
        dir,
        &["cache", "export", "run.mcap", "-o", &names[1], "--quiet"],
    );
    run(
        dir,
        &[
            "render-children",
            "export",
            "--cache",
            "run.mcap",
            "--frames",
            "2-4",
            "--children-per-parent",
            "3",
            "-o",
            &names[2],
            "--quiet",
        ],
    );
    run(
        dir,
        &[
            "preview",
            "--cache",
            "run.mcap",
            "--frames",
            "2,3.5",
            "--highlight",
            "--report",
            "--width",
            "96",
            "--height",
            "96",
            "-o",
            &names[3],
        ],
    );
    names
}

#[test]
fn every_output_works_the_same_after_the_scene_and_its_meshes_are_moved_away() {
    let dir = tempdir("outputs-from-cache");
    let meshes = dir.join("meshes");
    std::fs::create_dir_all(&meshes).unwrap();
    std::fs::write(meshes.join("scalp.obj"), colored_square_obj()).unwrap();
    std::fs::write(meshes.join("rock.obj"), tetrahedron(0.02, 0.0)).unwrap();
    for f in 1..=5 {
        let lift = 0.004 * f as f32;
        std::fs::write(
            meshes.join(format!("blob_{f:04}.obj")),
            tetrahedron(0.02, lift),
        )
        .unwrap();
    }
    std::fs::write(dir.join("scene.toml"), SCENE).unwrap();
    run(
        &dir,
        &["simulate", "scene.toml", "--cache", "run.mcap", "--quiet"],
    );
    let before = outputs(&dir, "before");

    // The scene and its meshes go elsewhere (a studio moves a shot's files after the sim).
    let moved = dir.join("elsewhere");
    std::fs::create_dir_all(&moved).unwrap();
    std::fs::rename(&meshes, moved.join("meshes")).unwrap();
    std::fs::rename(dir.join("scene.toml"), moved.join("scene.toml")).unwrap();
    let after = outputs(&dir, "after");

    for (a, b) in before.iter().zip(&after) {
        let (x, y) = (
            std::fs::read(dir.join(a)).unwrap(),
            std::fs::read(dir.join(b)).unwrap(),
        );
        assert!(!x.is_empty(), "{a} is empty");
        assert!(
            x == y,
            "{b} differs from {a} once the scene's files are gone"
        );
    }
    // The children carry the scalp's colours and the scalp is written (from the cache's rig).
    let children = std::fs::read_to_string(dir.join(&after[0])).unwrap();
    assert!(children.contains("displayColor"), "no root colours");
    let strands = std::fs::read_to_string(dir.join(&after[1])).unwrap();
    assert!(strands.contains("def Mesh \"scalp\""), "no scalp mesh");
    let _ = std::fs::remove_dir_all(&dir);
}
