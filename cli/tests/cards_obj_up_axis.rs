//! `render-children cards` through the binary: OBJ is written Y up by default (the OBJ
//! convention, which Blender's importer assumes), `--up-axis z` keeps the simulated Z up, the
//! USD export (which declares `upAxis = "Z"`) is unchanged, and a file that cannot be written
//! exits 1 like every other command's output (issues 21 and 18).

mod common;

use std::path::Path;
use std::process::Output;

use common::{hairsys, tempdir};

const SCENE: &str = r#"
[scene]
frames = [1, 3]

[solver]
model = "strips"

[scalp.mesh]
kind = "builtin-head"

[strips]
length = 0.15
segments = 4
hairs_per_strip = 50
every = 8
max_strips = 10
root_angle_deg = 60.0
region = { direction = [0.0, 0.3, 1.0], max_angle_deg = 70.0 }
"#;

fn code(o: &Output) -> i32 {
    o.status.code().expect("exited, not killed by a signal")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Rest-state cards of [`SCENE`] with `extra` arguments.
fn cards(dir: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["render-children", "cards", "--scene", "strips.toml"];
    args.extend_from_slice(extra);
    hairsys(&args, dir)
}

/// The `v` lines of an OBJ file.
fn obj_vertices(path: &Path) -> Vec<[f32; 3]> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let v: Vec<f32> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}

/// The default `points` of a cards `.usda` (the first `point3f[] points = [...]`).
fn usd_points(path: &Path) -> Vec<[f32; 3]> {
    let text = std::fs::read_to_string(path).unwrap();
    let start = text.find("point3f[] points = [").unwrap() + "point3f[] points = [".len();
    let body = &text[start..start + text[start..].find(']').unwrap()];
    body.split(')')
        .filter_map(|t| t.split_once('('))
        .map(|(_, xyz)| {
            let v: Vec<f32> = xyz.split(',').map(|x| x.trim().parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}

#[test]
fn card_obj_is_y_up_by_default_and_reimported_y_up_lands_on_the_z_up_cards() {
    let dir = tempdir("cards-up-axis");
    std::fs::write(dir.join("strips.toml"), SCENE).unwrap();
    for (args, name) in [
        (vec!["--format", "obj", "-o", "y.obj", "--quiet"], "y.obj"),
        (
            vec![
                "--format",
                "obj",
                "--up-axis",
                "z",
                "-o",
                "z.obj",
                "--quiet",
            ],
            "z.obj",
        ),
        (vec!["--format", "usd", "-o", "c.usda", "--quiet"], "c.usda"),
    ] {
        let o = cards(&dir, &args);
        assert_eq!(code(&o), 0, "{name}: {}", stderr(&o));
    }
    let y_up = obj_vertices(&dir.join("y.obj"));
    let z_up = obj_vertices(&dir.join("z.obj"));
    assert!(!z_up.is_empty());
    assert_eq!(y_up.len(), z_up.len());
    // The head is Z up: its cards reach higher in Z than in Y in the simulated (Z-up) frame,
    // and a Y-up file puts that height in Y.
    let top = |vs: &[[f32; 3]], axis: usize| vs.iter().map(|v| v[axis]).fold(f32::MIN, f32::max);
    assert_eq!(top(&y_up, 1), top(&z_up, 2));
    // Blender's OBJ importer (and hair-groom's `--up-axis y`) turns a Y-up file to Z up as
    // (x, y, z) → (x, -z, y): the Y-up cards land exactly where the Z-up ones are.
    for (y, z) in y_up.iter().zip(&z_up) {
        assert_eq!([y[0], -y[2], y[1]], *z);
    }
    let text = std::fs::read_to_string(dir.join("y.obj")).unwrap();
    assert!(text.lines().next().unwrap().contains("Y up"), "{text:.200}");
    // USD declares its up axis and keeps the simulated Z-up points.
    let usda = std::fs::read_to_string(dir.join("c.usda")).unwrap();
    assert!(usda.contains("upAxis = \"Z\""));
    let usd = usd_points(&dir.join("c.usda"));
    assert_eq!(usd.len(), z_up.len());
    for (u, z) in usd.iter().zip(&z_up) {
        for a in 0..3 {
            assert!(
                (u[a] - z[a]).abs() <= 1e-6 * (1.0 + z[a].abs()),
                "{u:?} {z:?}"
            );
        }
    }
}

#[test]
fn cards_that_cannot_be_written_exit_1_and_bad_input_exits_2() {
    let dir = tempdir("cards-write-failure");
    std::fs::write(dir.join("strips.toml"), SCENE).unwrap();
    for format in ["obj", "usd"] {
        let out = format!("missing-dir/c.{format}");
        let o = cards(&dir, &["--format", format, "-o", &out]);
        assert_eq!(code(&o), 1, "{format}: {}", stderr(&o));
        assert!(stderr(&o).contains("missing-dir"), "{}", stderr(&o));
    }
    let o = cards(&dir, &["--motion-samples", "0", "-o", "c.usda"]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
}
