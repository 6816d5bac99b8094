//! Helpers shared by the command tests: run the real binary in a fresh directory.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs `hairsys ARGS` in `dir`.
#[allow(dead_code)] // each test binary compiles this module; not all of them use every helper
pub fn hairsys(args: &[&str], dir: &Path) -> Output {
    hairsys_with_env(args, dir, &[])
}

/// Runs `hairsys ARGS` in `dir` with the environment variables `env` set.
pub fn hairsys_with_env(args: &[&str], dir: &Path, env: &[(&str, &str)]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hairsys"))
        .args(args)
        .envs(env.iter().copied())
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

/// A scene whose run can be killed half-way: 2,000 strands × 17 points on a moving sphere, 40
/// frames; every frame (816 kB) closes its own cache chunk and takes tens of milliseconds.
#[allow(dead_code)] // each test binary compiles this module; not all of them use every helper
pub const KILLABLE_SCENE: &str = r#"version = 1
[scene]
frames = [1, 40]

[scalp.mesh]
kind = "uv-sphere"
radius = 0.1
segments = 24
rings = 12

[scalp.motion]
keys = [
    { frame = 1, rotation_deg = [0.0, 0.0, 0.0] },
    { frame = 40, translation = [0.2, 0.0, 0.0], rotation_deg = [0.0, 0.0, 90.0] },
]

[hair]
count = 2000
length = 0.2
segments = 16
seed = 3

[physics]
air_drag = 2.0
"#;

/// A fresh, empty temporary directory named for the test and this process, removed with
/// everything in it when the returned guard is dropped (at the end of the test, pass or fail).
#[allow(dead_code)] // each test binary compiles this module; not all of them use every helper
pub fn tempdir(name: &str) -> TestDir {
    let dir = std::env::temp_dir().join(format!("hairsys-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    TestDir(dir)
}

/// A test's temporary directory ([`tempdir`]): reads as its path, removed on drop.
pub struct TestDir(PathBuf);

impl std::ops::Deref for TestDir {
    type Target = PathBuf;
    fn deref(&self) -> &PathBuf {
        &self.0
    }
}

impl AsRef<Path> for TestDir {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for TestDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A flat 10 cm square OBJ at z = 0 (normal +z), 4 × 4 quads, with per-vertex colours
/// (`v x y z r g b`) linear in position: `(r, g, b) = (x / 0.1, y / 0.1, 0.25)`, so any point
/// inside has exactly that colour.
#[allow(dead_code)] // each test binary compiles this module; not all of them use every helper
pub fn colored_square_obj() -> String {
    use std::fmt::Write as _;
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
