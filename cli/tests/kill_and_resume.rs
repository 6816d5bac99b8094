//! Crash safety through the real binary: a `hairsys simulate` killed with SIGKILL leaves
//! `CACHE.partial`, from which `cache recover` rebuilds every complete frame and
//! `simulate --resume` finishes the run with frames bit-identical to an uninterrupted run; a
//! different scene is refused.

mod common;

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{hairsys, tempdir, KILLABLE_SCENE as SCENE};
use hair_cache::CacheReader;

/// A frame as (number, position bits, velocity bits).
type FrameBits = (u32, Vec<[u32; 3]>, Vec<[u32; 3]>);

fn frames_of(path: &std::path::Path) -> Vec<FrameBits> {
    let mut reader = CacheReader::open(path).unwrap();
    let bits = |v: &[nalgebra::Vector3<f32>]| {
        v.iter()
            .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
            .collect()
    };
    reader
        .frame_numbers()
        .to_vec()
        .into_iter()
        .map(|f| {
            let frame = reader.read_frame(f).unwrap();
            (f, bits(&frame.positions), bits(&frame.velocities))
        })
        .collect()
}

#[test]
fn killed_run_is_recovered_and_resumed_bit_identically() {
    let dir = tempdir("kill");
    std::fs::write(dir.join("scene.toml"), SCENE).unwrap();
    let ok = |out: std::process::Output| {
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        out
    };
    ok(hairsys(
        &["simulate", "scene.toml", "--cache", "ref.mcap", "--quiet"],
        &dir,
    ));
    let reference = frames_of(&dir.join("ref.mcap"));
    assert_eq!(reference.len(), 40);

    // Kill a second run once a handful of frames are on disk.
    let mut child = Command::new(env!("CARGO_BIN_EXE_hairsys"))
        .args(["simulate", "scene.toml", "--cache", "run.mcap", "--quiet"])
        .current_dir(&dir)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let partial = dir.join("run.mcap.partial");
    let start = Instant::now();
    // Eight frames of bytes: the cache header and its rig come first, so at least five whole
    // frames are on disk.
    while std::fs::metadata(&partial).map_or(0, |m| m.len()) < 8 * 816_000 {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "the run wrote nothing"
        );
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run finished before it could be killed"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    assert!(
        !dir.join("run.mcap").exists(),
        "a killed run leaves no complete-looking cache"
    );

    // Every complete frame comes back, bit for bit.
    let out = ok(hairsys(
        &["cache", "recover", "run.mcap.partial", "fixed.mcap"],
        &dir,
    ));
    eprintln!("{}", String::from_utf8_lossy(&out.stderr));
    let recovered = frames_of(&dir.join("fixed.mcap"));
    assert!(
        recovered.len() >= 5 && recovered.len() < 40,
        "{} frames recovered",
        recovered.len()
    );
    assert_eq!(recovered[..], reference[..recovered.len()]);

    // Another scene cannot resume it, and the refusal keeps the partial file.
    let other = SCENE.replace("air_drag = 2.0", "air_drag = 3.0");
    std::fs::write(dir.join("other.toml"), other).unwrap();
    let refused = hairsys(
        &[
            "simulate",
            "other.toml",
            "--cache",
            "run.mcap",
            "--resume",
            "--quiet",
        ],
        &dir,
    );
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("different scene"), "{stderr}");
    assert!(partial.exists());

    // Resuming finishes the run exactly as if it had never stopped.
    ok(hairsys(
        &[
            "simulate",
            "scene.toml",
            "--cache",
            "run.mcap",
            "--resume",
            "--quiet",
        ],
        &dir,
    ));
    assert!(!partial.exists());
    assert!(
        frames_of(&dir.join("run.mcap")) == reference,
        "resumed frames differ from the uninterrupted run"
    );
    assert!(
        std::fs::read(dir.join("run.mcap")).unwrap()
            == std::fs::read(dir.join("ref.mcap")).unwrap(),
        "the resumed cache is not byte-identical to the uninterrupted one"
    );
}

#[test]
fn resume_without_an_interrupted_run_is_refused() {
    let dir = tempdir("no-partial");
    std::fs::write(
        dir.join("scene.toml"),
        SCENE.replace("count = 2000", "count = 10"),
    )
    .unwrap();
    let out = hairsys(
        &[
            "simulate",
            "scene.toml",
            "--cache",
            "run.mcap",
            "--resume",
            "--quiet",
        ],
        &dir,
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("run.mcap.partial"), "{stderr}");
}

#[test]
fn sample_between_frames_and_at_a_frame() {
    let dir = tempdir("sample");
    std::fs::write(
        dir.join("scene.toml"),
        SCENE.replace("count = 2000", "count = 10"),
    )
    .unwrap();
    let out = hairsys(
        &[
            "simulate",
            "scene.toml",
            "--cache",
            "c.mcap",
            "--quiet",
            "--frames",
            "1-4",
        ],
        &dir,
    );
    assert!(out.status.success());
    let at = |t: &str| -> serde_json::Value {
        let out = hairsys(&["cache", "sample", "c.mcap", "--time", t], &dir);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let frame2 = at(&(2.0 / 24.0).to_string());
    assert_eq!(frame2["between_frames"], serde_json::json!([2, 2]));
    let mid = at(&(2.5 / 24.0).to_string());
    assert_eq!(mid["between_frames"], serde_json::json!([2, 3]));
    assert_eq!(mid["points"], 170);
    let outside = hairsys(&["cache", "sample", "c.mcap", "--time", "10"], &dir);
    assert_eq!(outside.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&outside.stderr).contains("c.mcap"));
}
