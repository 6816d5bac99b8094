//! Helpers shared by the command tests: run the real binary in a fresh directory.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs `hairsys ARGS` in `dir`.
pub fn hairsys(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hairsys"))
        .args(args)
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
