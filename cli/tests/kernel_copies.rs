//! The solver's two compiled kernel copies (baseline and AVX2, see `hair_core::kernel_instructions`)
//! write byte-identical caches for a scene that runs every part of the kernel: a turning head as
//! collider (contacts with friction), strain limiting, goal springs, hair–hair friction and
//! repulsion, and a wind field. `HAIRSYS_KERNEL` chooses the copy; a bad value is refused.
//! On a CPU without AVX2 both runs use the baseline copy and the test still checks determinism.

mod common;

use std::path::Path;
use std::process::Output;

use common::{hairsys_with_env, tempdir};

const SCENE: &str = r#"
[scene]
frames = [1, 8]

[solver]
max_strain = 0.02

[physics]
goal_stiffness = 20.0

[scalp.mesh]
kind = "uv-sphere"
radius = 0.1
segments = 16
rings = 10

[scalp.collider]
friction = 0.3

[scalp.motion]
keys = [
    { frame = 1, rotation_deg = [0.0, 0.0, 0.0] },
    { frame = 8, rotation_deg = [0.0, 0.0, 120.0] },
]

[hair]
count = 120
length = 0.15
segments = 8
goal_root = 0.5
goal_tip = 0.0

[hair_hair]
cell_size = 0.01
friction = 0.3
repulsion = 0.3

[[fields]]
name = "gust"
type = "wind"
strength = 2.0
direction = [1.0, 0.2, 0.0]
noise = 0.3
"#;

/// Runs `simulate` with `HAIRSYS_KERNEL=kernel` into `cache`.
fn simulate(dir: &Path, kernel: &str, cache: &str) -> Output {
    hairsys_with_env(
        &["simulate", "scene.toml", "--cache", cache, "--json"],
        dir,
        &[("HAIRSYS_KERNEL", kernel)],
    )
}

/// The `kernel` field of the run's summary line.
fn kernel_ran(out: &Output) -> String {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    let done: serde_json::Value = serde_json::from_str(stdout.lines().last().unwrap()).unwrap();
    done["summary"]["kernel"].as_str().unwrap().to_string()
}

#[test]
fn both_kernel_copies_write_the_same_cache() {
    let dir = tempdir("kernel-copies");
    std::fs::write(dir.join("scene.toml"), SCENE).unwrap();
    let auto = simulate(&dir, "auto", "auto.mcap");
    let baseline = simulate(&dir, "baseline", "baseline.mcap");
    let ran = kernel_ran(&auto);
    assert_eq!(kernel_ran(&baseline), "baseline");
    eprintln!("auto ran the {ran} copy");
    let (a, b) = (
        std::fs::read(dir.join("auto.mcap")).unwrap(),
        std::fs::read(dir.join("baseline.mcap")).unwrap(),
    );
    assert!(a.len() > 100_000, "the cache holds the frames");
    assert!(
        a == b,
        "the {ran} and baseline copies wrote different caches"
    );
}

#[test]
fn a_bad_kernel_choice_is_refused_by_name() {
    let dir = tempdir("kernel-bad");
    std::fs::write(dir.join("scene.toml"), SCENE).unwrap();
    let out = simulate(&dir, "avx9000", "out.mcap");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("HAIRSYS_KERNEL") && err.contains("avx9000") && err.contains("baseline"),
        "{err}"
    );
    assert!(!dir.join("out.mcap").exists() && !dir.join("out.mcap.partial").exists());
}
