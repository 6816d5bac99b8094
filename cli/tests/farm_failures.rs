//! Farm tasks that fail, are killed and are retried (`hairsys farm simulate|export|assemble`):
//! a Simulate task killed midway and run again continues the killed run and ends with the
//! bytes of an uninterrupted run; an Export task killed while it writes leaves no half-written
//! chunk under the chunk's name (an earlier complete chunk stays whole, and the re-run replaces
//! it); Assemble refuses chunks that leave frames out; every task refuses a shot that changed
//! since the job was written; bad shots are refused naming the file, the key and the fix.

mod common;

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::{hairsys, tempdir, KILLABLE_SCENE as SCENE};

const SHOT: &str = r#"version = 1
[shot]
frames = [1, 40]

[output]
shutter = [-0.25, 0.25]

[[characters]]
name = "head"
scene = "head.toml"
"#;

fn ok(out: &Output, what: &str) -> String {
    assert!(
        out.status.success(),
        "{what} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn setup(name: &str) -> common::TestDir {
    let dir = tempdir(name);
    std::fs::write(dir.join("head.toml"), SCENE).unwrap();
    std::fs::write(dir.join("shot.toml"), SHOT).unwrap();
    dir
}

/// Starts `hairsys ARGS` in `dir`, kills it (SIGKILL) once `ready` holds, and waits for it; false
/// when it finished before `ready` held.
fn kill_when(args: &[&str], dir: &Path, ready: impl Fn() -> bool) -> bool {
    let mut child = Command::new(env!("CARGO_BIN_EXE_hairsys"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while !ready() {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "the task wrote nothing"
        );
        if child.try_wait().unwrap().is_some() {
            return false;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    true
}

#[test]
fn a_killed_simulate_task_run_again_resumes_to_the_uninterrupted_bytes() {
    let dir = setup("farm-kill-sim");
    let task = |out: &str| -> Vec<String> {
        [
            "farm",
            "simulate",
            "shot.toml",
            "--character",
            "head",
            "--out-dir",
            out,
        ]
        .map(String::from)
        .to_vec()
    };
    let args = |out: &str, extra: &[&str]| -> Vec<String> {
        let mut a = task(out);
        a.extend(extra.iter().map(|s| s.to_string()));
        a
    };
    let run = |a: Vec<String>| hairsys(&a.iter().map(String::as_str).collect::<Vec<_>>(), &dir);
    ok(&run(args("ref", &["--quiet"])), "uninterrupted task");
    let reference = std::fs::read(dir.join("ref/head/head.mcap")).unwrap();

    let partial = dir.join("run/head/head.mcap.partial");
    let killed = kill_when(
        &args("run", &["--quiet"])
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
        &dir,
        || std::fs::metadata(&partial).map_or(0, |m| m.len()) > 6 * 816_000,
    );
    assert!(killed, "the task finished before it could be killed");
    assert!(!dir.join("run/head/head.mcap").exists());

    // The farm's retry: the same command line.
    let out = ok(&run(args("run", &["--json"])), "retried task");
    let done: serde_json::Value =
        serde_json::from_str(out.lines().last().expect("a summary line")).unwrap();
    assert_eq!(done["outcome"]["start"]["start"], "resumed", "{done}");
    let from = done["outcome"]["start"]["from"].as_u64().unwrap();
    assert!((5..40).contains(&from), "resumed from frame {from}");
    assert!(!partial.exists());
    assert!(
        std::fs::read(dir.join("run/head/head.mcap")).unwrap() == reference,
        "the resumed cache is not byte-identical to the uninterrupted one"
    );

    // Once more: the complete cache is kept as it is.
    let out = ok(&run(args("run", &["--json"])), "task after completion");
    assert!(out.contains("\"start\":\"complete\""), "{out}");
    assert!(std::fs::read(dir.join("run/head/head.mcap")).unwrap() == reference);
}

#[test]
fn a_killed_export_task_leaves_no_half_written_chunk_and_its_rerun_replaces_it_whole() {
    let dir = setup("farm-kill-export");
    let sim = [
        "farm",
        "simulate",
        "shot.toml",
        "--character",
        "head",
        "--out-dir",
        "out",
        "--quiet",
    ];
    ok(&hairsys(&sim, &dir), "simulate");
    let export = [
        "farm",
        "export",
        "shot.toml",
        "--character",
        "head",
        "--frames",
        "1-40",
        "--out-dir",
        "out",
        "--quiet",
    ];
    // Before the Simulate task, nothing to export; names the task to run.
    let early = hairsys(
        &[
            "farm",
            "export",
            "shot.toml",
            "--character",
            "head",
            "--frames",
            "1-10",
            "--out-dir",
            "elsewhere",
        ],
        &dir,
    );
    assert_eq!(early.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&early.stderr).contains("Simulate task runs first"));

    let chunk = dir.join("out/head/chunks/head.0001-0040.usdc");
    let partial = dir.join("out/head/chunks/head.0001-0040.usdc.partial");
    // Killed while writing the chunk: nothing under the chunk's name.
    if kill_when(&export, &dir, || partial.exists()) {
        assert!(
            !chunk.exists(),
            "a killed export left a file under the chunk's name"
        );
    }
    ok(&hairsys(&export, &dir), "export");
    assert!(!partial.exists(), "the export left its .partial behind");
    let complete = std::fs::read(&chunk).unwrap();

    // Killed while writing it again: the earlier chunk is still there, whole.
    let caught = (0..5).any(|_| kill_when(&export, &dir, || partial.exists()));
    assert!(caught, "no export could be killed while it wrote");
    assert!(
        std::fs::read(&chunk).unwrap() == complete,
        "the chunk was damaged"
    );
    // A .partial is not a chunk: assembling sees the one whole chunk.
    ok(
        &hairsys(
            &[
                "farm",
                "assemble",
                "shot.toml",
                "--out-dir",
                "out",
                "--quiet",
            ],
            &dir,
        ),
        "assemble",
    );
    ok(&hairsys(&export, &dir), "export again");
    assert!(
        std::fs::read(&chunk).unwrap() == complete,
        "exports are deterministic"
    );
}

#[test]
fn assemble_refuses_missing_frames_and_tasks_refuse_a_changed_shot() {
    let dir = setup("farm-refusals");
    let small = SCENE.replace("count = 2000", "count = 20");
    std::fs::write(dir.join("head.toml"), small).unwrap();
    let bin = env!("CARGO_BIN_EXE_hairsys");
    let job = ok(
        &hairsys(
            &[
                "farm",
                "job",
                "shot.toml",
                "-o",
                "bundle",
                "--output-dir",
                "out",
                "--hairsys",
                bin,
                "--json",
            ],
            &dir,
        ),
        "farm job",
    );
    let job: serde_json::Value = serde_json::from_str(&job).unwrap();
    let digest = job["digest"].as_str().unwrap().to_string();
    let commands = std::fs::read_to_string(dir.join("bundle/commands.txt")).unwrap();
    assert_eq!(
        commands.lines().filter(|l| l.starts_with(bin)).count(),
        1 + 2 + 1,
        "{commands}"
    );
    let task = |verb: &str, extra: &[&str]| {
        let mut a = vec![
            "farm",
            verb,
            "shot.toml",
            "--out-dir",
            "out",
            "--shot-digest",
            &digest,
        ];
        a.extend_from_slice(extra);
        hairsys(&a, &dir)
    };
    ok(
        &task("simulate", &["--character", "head", "--quiet"]),
        "simulate",
    );
    ok(
        &task(
            "export",
            &["--character", "head", "--frames", "1-30", "--quiet"],
        ),
        "export",
    );
    let refused = task("assemble", &[]);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("miss frames 31-40"), "{stderr}");
    assert!(!dir.join("out/shot.usda").exists());

    let wrong = task("export", &["--character", "nobody", "--frames", "1-10"]);
    let stderr = String::from_utf8_lossy(&wrong.stderr);
    assert_eq!(wrong.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("\"head\""), "{stderr}");
    let outside = task("export", &["--character", "head", "--frames", "35-45"]);
    assert_eq!(outside.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&outside.stderr).contains("outside the shot's frames 1-40"));

    // The shot changes after the job was written: every task refuses it.
    let changed = SHOT.replace("[1, 40]", "[1, 30]");
    std::fs::write(dir.join("shot.toml"), changed).unwrap();
    let lines: [(&str, &[&str]); 3] = [
        ("simulate", &["--character", "head"]),
        ("export", &["--character", "head", "--frames", "1-10"]),
        ("assemble", &[]),
    ];
    for (verb, extra) in lines {
        let out = task(verb, extra);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{verb}: {stderr}");
        assert!(
            stderr.contains("changed since the job was written"),
            "{verb}: {stderr}"
        );
    }
}

#[test]
fn shot_check_prints_the_work_and_refuses_bad_shots_by_file_key_and_fix() {
    let dir = setup("farm-shot-check");
    let out = ok(
        &hairsys(&["shot", "check", "shot.toml", "--chunk-size", "10"], &dir),
        "check",
    );
    assert!(out.contains("head: "), "{out}");
    assert!(out.contains("Export: 4 task(s)"), "{out}");
    let json = ok(
        &hairsys(&["shot", "check", "shot.toml", "--json"], &dir),
        "check --json",
    );
    let json: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(json["characters"][0]["strands"], 2000);

    let cases = [
        (SHOT.replace("[1, 40]", "[40, 1]"), "frames = [40, 1]"),
        (SHOT.replace("version = 1", "version = 9"), "version = 9"),
        (
            SHOT.replace("\"head\"", "\"my head\""),
            "name = \"my head\"",
        ),
        (SHOT.replace("head.toml", "missing.toml"), "missing.toml"),
        (SHOT.replace("shutter", "shuttr"), "unknown field `shuttr`"),
    ];
    for (text, expected) in cases {
        std::fs::write(dir.join("bad.toml"), &text).unwrap();
        let out = hairsys(&["shot", "check", "bad.toml"], &dir);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{expected}: {stderr}");
        assert!(stderr.contains("bad.toml"), "{expected}: {stderr}");
        assert!(stderr.contains(expected), "{expected}: {stderr}");
    }
}

#[test]
fn every_shot_and_farm_command_has_help() {
    let dir = tempdir("farm-help");
    for args in [
        &["shot", "--help"][..],
        &["shot", "check", "--help"],
        &["farm", "--help"],
        &["farm", "job", "--help"],
        &["farm", "simulate", "--help"],
        &["farm", "export", "--help"],
        &["farm", "assemble", "--help"],
    ] {
        let out = hairsys(args, &dir);
        assert!(out.status.success(), "{args:?}");
        assert!(
            String::from_utf8_lossy(&out.stdout).contains("Usage"),
            "{args:?}"
        );
    }
}
