//! A shot on a farm, run for real: `hairsys farm job` writes an OpenJD bundle that `openjd
//! check` accepts; `openjd run` runs its Simulate, Export and Assemble steps in order on a
//! two-character, 48-frame shot (one character's strands, the other's render children, both
//! with shutter samples); the caches equal `hairsys simulate`'s byte for byte, and the
//! assembled `shot.usda` samples exactly what one `hairsys cache export` of the whole range
//! gives, every time sample and every attribute bit for bit (usd-core), for chunks of 10 and
//! again after the Export step re-runs with chunks of 30.
//!
//! Fails (never skips) when `openjd`, python3 or pxr is missing: `scripts/test.sh` installs
//! openjd-cli and usd-core (scripts/test-requirements.txt) into the venv it puts on PATH.

mod common;

use std::path::Path;
use std::process::{Command, Output};

use common::{hairsys, tempdir};

/// A small moving head with 40 strands of 6 segments.
const ALICE: &str = r#"version = 1
[scene]
frames = [1, 48]

[scalp.mesh]
kind = "uv-sphere"
radius = 0.1
segments = 12
rings = 8

[scalp.motion]
keys = [
    { frame = 1, rotation_deg = [0.0, 0.0, 0.0] },
    { frame = 48, translation = [0.1, 0.0, 0.0], rotation_deg = [0.0, 0.0, 60.0] },
]

[hair]
count = 40
length = 0.15
segments = 6
seed = 1
"#;

const SHOT: &str = r#"version = 1
[shot]
name = "farm_test"
frames = [1, 48]

[output]
shutter = [-0.25, 0.25]

[[characters]]
name = "alice"
scene = "alice.toml"

[[characters]]
name = "bob"
scene = "bob.toml"
usd = "children"
"#;

/// Another head, turning the other way, with 3 render children per strand.
fn bob() -> String {
    ALICE
        .replace("seed = 1", "seed = 2")
        .replace("60.0]", "-45.0]")
        + "\n[children]\nper_parent = 3\n"
}

fn ok(out: &Output, what: &str) -> String {
    assert!(
        out.status.success(),
        "{what} failed: {}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Runs `openjd ARGS` in `dir`.
fn openjd(args: &[&str], dir: &Path) -> Output {
    Command::new("openjd")
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap_or_else(|e| {
            panic!(
                "cannot run openjd ({e}): install openjd-cli (scripts/test-requirements.txt); \
                 scripts/test.sh does, into the venv it puts on PATH"
            )
        })
}

/// Runs the usd-core comparison of `shot` with the whole-range exports.
fn compare(dir: &Path, shot: &str) {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/python_check_farm.py");
    let out = Command::new("python3")
        .arg(&script)
        .arg(shot)
        .args([
            "/alice/hair=whole_alice.usdc:/hair",
            "/alice/scalp=whole_alice.usdc:/scalp",
            "/bob/children=whole_bob.usdc:/children",
            "/bob/scalp=whole_bob.usdc:/scalp",
        ])
        .current_dir(dir)
        .output()
        .unwrap_or_else(|e| panic!("cannot run python3 ({e}): run through scripts/test.sh"));
    match out.status.code() {
        Some(0) => eprintln!("{}", String::from_utf8_lossy(&out.stdout)),
        Some(3) => panic!("pxr is missing: pip install usd-core"),
        _ => panic!(
            "{shot} differs from the whole-range exports: {}",
            String::from_utf8_lossy(&out.stderr)
        ),
    }
}

/// The chunk files of `character` under `out`, sorted.
fn chunk_files(out: &Path, character: &str) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(out.join(character).join("chunks"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".usdc"))
        .collect();
    names.sort();
    names
}

#[test]
fn openjd_runs_the_shot_job_and_the_stage_equals_whole_range_exports() {
    let dir = tempdir("farm-openjd");
    std::fs::write(dir.join("alice.toml"), ALICE).unwrap();
    std::fs::write(dir.join("bob.toml"), bob()).unwrap();
    std::fs::write(dir.join("shot.toml"), SHOT).unwrap();
    let bin = env!("CARGO_BIN_EXE_hairsys");
    ok(
        &hairsys(
            &[
                "farm",
                "job",
                "shot.toml",
                "-o",
                "bundle",
                "--output-dir",
                "out",
                "--chunk-size",
                "10",
                "--hairsys",
                bin,
            ],
            &dir,
        ),
        "farm job",
    );
    ok(
        &openjd(&["check", "bundle/template.yaml"], &dir),
        "openjd check",
    );
    let run_step = |step: &str, extra: &[&str]| {
        let mut args = vec![
            "run",
            "bundle/template.yaml",
            "-p",
            "file://bundle/job_parameters.yaml",
        ];
        args.extend_from_slice(extra);
        args.extend(["--step", step]);
        let out = openjd(&args, &dir);
        ok(&out, &format!("openjd run --step {step}"));
    };
    for step in ["Simulate", "Export", "Assemble"] {
        run_step(step, &[]);
    }
    let out = dir.join("out");
    assert_eq!(
        chunk_files(&out, "alice").len(),
        5,
        "{:?}",
        chunk_files(&out, "alice")
    );

    // One machine: the same caches, byte for byte, and one export of the whole range.
    for c in ["alice", "bob"] {
        let scene = format!("{c}.toml");
        let cache = format!("ref_{c}.mcap");
        ok(
            &hairsys(
                &[
                    "simulate", &scene, "--frames", "1-48", "--cache", &cache, "--quiet",
                ],
                &dir,
            ),
            "simulate",
        );
        assert!(
            std::fs::read(dir.join(&cache)).unwrap()
                == std::fs::read(out.join(c).join(format!("{c}.mcap"))).unwrap(),
            "the farm's cache of {c} differs from `hairsys simulate`'s"
        );
        let whole = format!("whole_{c}.usdc");
        let mut args = vec![
            "cache",
            "export",
            &cache,
            "-o",
            &whole,
            "--shutter=-0.25,0.25",
        ];
        if c == "bob" {
            args.push("--children");
        }
        ok(&hairsys(&args, &dir), "cache export");
    }
    compare(&dir, "out/shot.usda");

    // Chunks of 30 instead: the Export step replaces the chunks of 10, Assemble stitches the new
    // ones, and the shot is the same, bit for bit.
    run_step("Export", &["-p", "ChunkSize=30"]);
    run_step("Assemble", &[]);
    for c in ["alice", "bob"] {
        let files = chunk_files(&out, c);
        assert_eq!(files.len(), 2, "{c}: {files:?}");
    }
    compare(&dir, "out/shot.usda");
}
