//! What the tests that build C and C++ programs share: finding the library cargo built and the
//! system's compilers, compiling, running.

#![allow(dead_code)] // Each test binary uses its own part of this module.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The crate's directory.
pub fn crate_dir() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The directory holding `libhairsys_capi.so`, built by cargo beside this test's binary.
pub fn library_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary's path");
    let deps = exe.parent().expect("the test binary's directory");
    for dir in [deps, deps.parent().unwrap_or(deps)] {
        if dir.join("libhairsys_capi.so").exists() {
            return dir.to_path_buf();
        }
    }
    panic!(
        "libhairsys_capi.so not found beside {}: build the crate (cargo test -p hairsys-capi)",
        deps.display()
    );
}

/// Whether `compiler` runs; otherwise says why the test is skipped.
pub fn have(compiler: &str) -> bool {
    match Command::new(compiler).arg("--version").output() {
        Ok(o) if o.status.success() => true,
        _ => {
            eprintln!(
                "SKIPPED: no `{compiler}` on this machine (install gcc and g++: apt-get install \
                 gcc g++)"
            );
            false
        }
    }
}

/// How a program links the library.
#[derive(Clone, Copy)]
pub enum Link {
    /// `-lhairsys_capi` with an rpath to `libhairsys_capi.so`.
    Shared,
    /// `libhairsys_capi.a` with the system libraries docs/c-api.md names.
    Static,
}

/// Compiles `sources` with `compiler` (`cc` or `c++`) against the shared library into `out`,
/// warnings as errors.
pub fn compile(compiler: &str, sources: &[PathBuf], out: &Path) {
    compile_linked(compiler, sources, out, Link::Shared);
}

/// [`compile`], linking as `link` says.
pub fn compile_linked(compiler: &str, sources: &[PathBuf], out: &Path, link: Link) {
    let lib = library_dir();
    let standard = if compiler == "cc" {
        "-std=c11"
    } else {
        "-std=c++20"
    };
    let mut cmd = Command::new(compiler);
    cmd.arg(standard)
        .args(["-O1", "-g", "-Wall", "-Wextra", "-Werror"])
        .arg("-I")
        .arg(crate_dir().join("include"))
        .arg("-I")
        .arg(crate_dir().join("tests/c"))
        .args(sources)
        .arg("-o")
        .arg(out);
    match link {
        Link::Shared => cmd
            .arg("-L")
            .arg(&lib)
            .arg("-lhairsys_capi")
            .arg(format!("-Wl,-rpath,{}", lib.display()))
            .arg("-lm"),
        Link::Static => cmd
            .arg(lib.join("libhairsys_capi.a"))
            .args(["-lpthread", "-ldl", "-lm"]),
    };
    let o = cmd.output().expect("the compiler runs");
    assert!(
        o.status.success(),
        "{cmd:?} failed:\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Runs `program` with `args`, asserting it succeeds; returns its output.
pub fn run(program: &Path, args: &[&str]) -> Output {
    let o = Command::new(program)
        .args(args)
        .output()
        .expect("the program runs");
    assert!(
        o.status.success(),
        "{} {args:?} failed ({}):\nstdout:\n{}\nstderr:\n{}",
        program.display(),
        o.status,
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    o
}
