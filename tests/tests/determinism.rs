//! Determinism: the same scene gives byte-identical caches with 1 and with 2 worker threads, and
//! with the same thread count twice (no wall-clock time, no thread-order dependence).

use std::path::PathBuf;

use hairsys::run::{simulate, SimulateOptions};
use hairsys::scene::SceneFile;

const SCENE: &str = r#"
[scene]
frames = [1, 6]

[scalp.mesh]
kind = "builtin-head"

[scalp.motion]
keys = [
    { frame = 1, rotation_deg = [0.0, 0.0, 0.0] },
    { frame = 6, rotation_deg = [20.0, 0.0, 60.0] },
]

[hair]
count = 300
length = 0.2
segments = 12
seed = 7
length_variation = 0.3
goal_tip = 0.2

[physics]
goal_stiffness = 0.5
"#;

fn run(threads: usize, name: &str) -> Vec<u8> {
    let dir = std::env::temp_dir().join(format!("hairsys-determinism-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cache: PathBuf = dir.join(name);
    let scene = SceneFile::parse(SCENE, "determinism.toml", dir.clone()).unwrap();
    let opts = SimulateOptions {
        scene,
        cache: cache.clone(),
        frames: None,
        threads: Some(threads),
        writer: hair_cache::WriterOptions::default(),
        resume: false,
        kernel: Default::default(),
        quality: false,
    };
    simulate(&opts, |_| {}).unwrap();
    std::fs::read(&cache).unwrap()
}

#[test]
fn one_and_two_threads_give_identical_caches() {
    let one = run(1, "one.mcap");
    let two = run(2, "two.mcap");
    let again = run(2, "again.mcap");
    assert!(one.len() > 1000);
    assert!(one == two, "1 thread and 2 threads differ");
    assert!(two == again, "two runs with 2 threads differ");
}
