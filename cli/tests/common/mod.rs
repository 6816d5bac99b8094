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

/// A fresh, empty temporary directory named for the test and this process.
pub fn tempdir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hairsys-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
