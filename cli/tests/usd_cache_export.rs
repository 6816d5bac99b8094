//! `hairsys cache export`: a simulated run becomes ONE animated USD file that Pixar's USD
//! (`usd-core`) opens, with one time sample per frame whose points equal the cache's (as
//! `hairsys cache sample` decodes them), in `.usdc` and `.usda`, for all frames and for a
//! `--frames` range. Fails (never skips) when python3 or pxr is missing: `scripts/test.sh`
//! installs usd-core into the venv it puts on PATH.

mod common;

use std::path::Path;
use std::process::Command;

use common::{hairsys, tempdir};

fn ok(out: &std::process::Output, what: &str) -> String {
    assert!(
        out.status.success(),
        "{what}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Runs the usd-core checker on `shot` against `hairsys cache sample` at `frames`.
fn check(dir: &Path, shot: &str, fps: f64, range: (u32, u32), frames: &[u32]) {
    let mut args = vec![
        shot.to_string(),
        fps.to_string(),
        range.0.to_string(),
        range.1.to_string(),
    ];
    for f in frames {
        let json = format!("sample_{f}.json");
        let time = format!("{}", f64::from(*f) / fps);
        ok(
            &hairsys(
                &["cache", "sample", "c.mcap", "--time", &time, "--out", &json],
                dir,
            ),
            "cache sample",
        );
        args.push(json);
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/python_check_shot.py");
    let out = Command::new("python3")
        .arg(&script)
        .args(&args)
        .current_dir(dir)
        .output()
        .unwrap_or_else(|e| panic!("cannot run python3 ({e}): run through scripts/test.sh"));
    match out.status.code() {
        Some(0) => {}
        Some(3) => panic!("pxr is missing: pip install usd-core"),
        _ => panic!(
            "usd-core check of {shot} failed: {}",
            String::from_utf8_lossy(&out.stderr)
        ),
    }
}

#[test]
fn a_whole_run_exports_as_one_animated_file_usd_core_reads_back() {
    let dir = tempdir("usd-cache-export");
    ok(
        &hairsys(
            &[
                "simulate", "--frames", "1-6", "--cache", "c.mcap", "--quiet",
            ],
            &dir,
        ),
        "simulate",
    );
    let info = ok(
        &hairsys(&["cache", "info", "c.mcap", "--json"], &dir),
        "info",
    );
    let info: serde_json::Value = serde_json::from_str(&info).unwrap();
    let fps = info["fps"].as_f64().expect("cache info has fps");

    ok(
        &hairsys(&["cache", "export", "c.mcap", "-o", "shot.usdc"], &dir),
        "export usdc",
    );
    check(&dir, "shot.usdc", fps, (1, 6), &[1, 3, 6]);

    ok(
        &hairsys(
            &[
                "cache",
                "export",
                "c.mcap",
                "-o",
                "part.usda",
                "--frames",
                "2-4",
            ],
            &dir,
        ),
        "export usda",
    );
    check(&dir, "part.usda", fps, (2, 4), &[2, 4]);

    // A range with no cached frame, and an extension that is not USD, are refused by name.
    let out = hairsys(
        &[
            "cache", "export", "c.mcap", "-o", "x.usdc", "--frames", "50-60",
        ],
        &dir,
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("c.mcap") && err.contains("1-6"), "{err}");
    let out = hairsys(&["cache", "export", "c.mcap", "-o", "x.abc"], &dir);
    assert!(String::from_utf8_lossy(&out.stderr).contains(".usdc"));
    let _ = std::fs::remove_dir_all(&dir);
}
