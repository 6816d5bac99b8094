//! The commands end to end through the real binary: `simulate` writes a cache whose frames,
//! strands and points `cache info` reports, and `--json` prints one parseable object per line.

mod common;

use common::{hairsys, tempdir};

const SCENE: &str = r#"
[scene]
frames = [1, 5]

[scalp.mesh]
kind = "uv-sphere"
radius = 0.1
segments = 12
rings = 8

[hair]
count = 30
length = 0.1
segments = 5
"#;

#[test]
fn simulate_then_cache_info() {
    let dir = tempdir("info");
    std::fs::write(dir.join("scene.toml"), SCENE).unwrap();
    let out = hairsys(
        &["simulate", "scene.toml", "--cache", "out.mcap", "--json"],
        &dir,
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines: Vec<serde_json::Value> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).expect("JSON line"))
        .collect();
    let frames: Vec<_> = lines.iter().filter(|l| l["event"] == "frame").collect();
    assert_eq!(frames.len(), 4, "frames 2..=5 are simulated");
    let done = lines.last().unwrap();
    assert_eq!(done["event"], "done");
    assert_eq!(done["summary"]["strands"], 30);
    assert_eq!(done["summary"]["points"], 180);
    assert!(done["summary"]["components"]
        .as_array()
        .unwrap()
        .iter()
        .any(|c| c == "stretch"));
    assert!(dir.join("out.mcap").exists() && !dir.join("out.mcap.partial").exists());

    let info = hairsys(&["cache", "info", "out.mcap", "--json"], &dir);
    assert!(
        info.status.success(),
        "{}",
        String::from_utf8_lossy(&info.stderr)
    );
    let summary: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    assert_eq!(
        summary["frames"], 5,
        "the rest frame and 4 simulated frames"
    );
    assert_eq!(summary["strands"], 30);
    assert_eq!(summary["points"], 180);
    assert_eq!(summary["first_frame"], 1);
    assert_eq!(summary["last_frame"], 5);

    let text = hairsys(&["cache", "info", "out.mcap"], &dir);
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(
        text.contains("frames") && text.contains("30") && text.contains("bytes per point-frame"),
        "{text}"
    );
}

#[test]
fn quiet_prints_nothing_and_frames_override_the_range() {
    let dir = tempdir("quiet");
    std::fs::write(dir.join("scene.toml"), SCENE).unwrap();
    let out = hairsys(
        &[
            "simulate",
            "scene.toml",
            "--cache",
            "out.mcap",
            "--quiet",
            "--frames",
            "2-3",
            "--threads",
            "1",
        ],
        &dir,
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.stdout.is_empty() && out.stderr.is_empty());
    let info = hairsys(&["cache", "info", "out.mcap", "--json"], &dir);
    let summary: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    assert_eq!(summary["first_frame"], 2);
    assert_eq!(summary["last_frame"], 3);
}

#[test]
fn cache_info_on_a_missing_file_fails_clearly() {
    let dir = tempdir("missing");
    let out = hairsys(&["cache", "info", "nothing.mcap"], &dir);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("nothing.mcap"));
}

#[test]
fn quantized_caches_are_half_the_size() {
    let dir = tempdir("quantize");
    std::fs::write(dir.join("scene.toml"), SCENE).unwrap();
    for (name, flag) in [("f32.mcap", None), ("q16.mcap", Some("--quantize"))] {
        let mut args = vec!["simulate", "scene.toml", "--cache", name, "--quiet"];
        args.extend(flag);
        let out = hairsys(&args, &dir);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let bytes = |name: &str| std::fs::metadata(dir.join(name)).unwrap().len() as f64;
    let frames_bytes = |name: &str| {
        let info = hairsys(&["cache", "info", name, "--json"], &dir);
        serde_json::from_slice::<serde_json::Value>(&info.stdout).unwrap()["frames"]
            .as_u64()
            .unwrap()
    };
    assert_eq!(frames_bytes("q16.mcap"), frames_bytes("f32.mcap"));
    // 180 points × 5 frames: frame data shrinks from 24 to 12 bytes per point-frame; the fixed
    // parts of the file (header, layout, summary) do not.
    let saved = bytes("f32.mcap") - bytes("q16.mcap");
    assert!(
        saved >= 0.9 * 12.0 * 180.0 * 5.0,
        "saved only {saved} bytes"
    );
}
