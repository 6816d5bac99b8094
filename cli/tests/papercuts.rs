//! The command line's papercuts, budgets, output and exit codes, each row through the real
//! binary. Exit codes as README says: 0 done, 1 failed, 2 bad input.

mod common;

use std::path::Path;
use std::process::{Command, Output, Stdio};

use common::{hairsys, tempdir};

fn code(o: &Output) -> i32 {
    o.status.code().expect("exited, not killed by a signal")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// A 3-frame run of the default scene into `dir/name`.
fn small_cache(dir: &Path, name: &str) {
    let o = hairsys(
        &["simulate", "--frames", "1-3", "--cache", name, "--quiet"],
        dir,
    );
    assert_eq!(code(&o), 0, "{}", stderr(&o));
}

/// A scene file on a uv sphere with `hair` as its `[hair]` section and `extra` appended.
fn scene(dir: &Path, hair: &str, extra: &str) -> std::path::PathBuf {
    let path = dir.join("scene.toml");
    std::fs::write(
        &path,
        format!(
            "[scene]\nname = \"t\"\nfps = 24.0\nframes = [1, 3]\n\n[scalp.mesh]\nkind = \
             \"uv-sphere\"\nradius = 0.1\nsegments = 8\nrings = 6\n\n[hair]\n{hair}\n{extra}"
        ),
    )
    .unwrap();
    path
}

#[test]
fn foxglove_flag_alone_does_not_swallow_the_scene_argument() {
    let dir = tempdir("foxglove-flag");
    let s = scene(&dir, "count = 10\nlength = 0.1\nsegments = 4", "");
    let o = hairsys(
        &[
            "simulate",
            "--foxglove",
            s.to_str().unwrap(),
            "--cache",
            "f.mcap",
            "--quiet",
        ],
        &dir,
    );
    assert_eq!(code(&o), 0, "{}", stderr(&o));
}

#[test]
fn frames_given_as_one_number_is_parsed_as_a_range_of_one() {
    let dir = tempdir("frames-one");
    let o = hairsys(&["simulate", "--frames", "3", "--cache", "o.mcap"], &dir);
    // `3` parses (no clap "invalid value" error, exit 2 from the parser with "invalid value").
    assert!(!stderr(&o).contains("invalid value"), "{}", stderr(&o));
}

#[test]
fn simulate_refuses_to_overwrite_a_complete_cache_without_force() {
    let dir = tempdir("overwrite");
    small_cache(&dir, "a.mcap");
    let o = hairsys(&["simulate", "--frames", "1-2", "--cache", "a.mcap"], &dir);
    assert_eq!(code(&o), 2);
    assert!(stderr(&o).contains("--force"), "{}", stderr(&o));
    let o = hairsys(
        &[
            "simulate", "--frames", "1-2", "--cache", "a.mcap", "--force", "--quiet",
        ],
        &dir,
    );
    assert_eq!(code(&o), 0, "{}", stderr(&o));
}

#[test]
fn simulate_over_a_killed_runs_partial_asks_for_resume_or_force() {
    let dir = tempdir("partial-left");
    std::fs::write(dir.join("p.mcap.partial"), b"left by a killed run").unwrap();
    let o = hairsys(&["simulate", "--frames", "1-2", "--cache", "p.mcap"], &dir);
    assert_eq!(code(&o), 2);
    let e = stderr(&o);
    assert!(
        e.contains("--resume") && e.contains("--force") && e.contains("cache recover"),
        "{e}"
    );
    assert!(dir.join("p.mcap.partial").exists(), "the partial is kept");
}

#[test]
fn cache_info_text_ends_with_a_newline() {
    let dir = tempdir("info-newline");
    small_cache(&dir, "a.mcap");
    let o = hairsys(&["cache", "info", "a.mcap"], &dir);
    assert_eq!(code(&o), 0);
    assert!(stdout(&o).ends_with('\n'), "{:?}", stdout(&o));
}

#[test]
fn cache_info_of_a_partial_names_recover_and_resume() {
    let dir = tempdir("info-partial");
    small_cache(&dir, "a.mcap");
    std::fs::copy(dir.join("a.mcap"), dir.join("b.mcap.partial")).unwrap();
    let o = hairsys(&["cache", "info", "b.mcap.partial"], &dir);
    assert_eq!(code(&o), 2);
    let e = stderr(&o);
    assert!(e.contains("cache recover") && e.contains("--resume"), "{e}");
}

#[test]
fn out_of_range_time_is_reported_in_frame_numbers() {
    let dir = tempdir("range-frames");
    small_cache(&dir, "a.mcap");
    let o = hairsys(&["cache", "sample", "a.mcap", "--time", "10"], &dir);
    assert_eq!(code(&o), 2);
    let e = stderr(&o);
    // 10 s at 24 fps is frame 240; the cache holds frames 1–3.
    assert!(e.contains("frame 240") && e.contains("frames 1–3"), "{e}");
    assert!(!e.contains("0.041666666666666664"), "{e}");
}

#[test]
fn cache_sample_json_has_strand_offsets_that_split_the_positions() {
    let dir = tempdir("sample-offsets");
    small_cache(&dir, "a.mcap");
    let o = hairsys(&["cache", "sample", "a.mcap", "--time", "0.0625"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let offsets: Vec<u64> = doc["strand_offsets"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_u64().unwrap())
        .collect();
    assert_eq!(offsets[0], 0);
    assert!(offsets.windows(2).all(|w| w[0] < w[1]));
    assert_eq!(
        *offsets.last().unwrap() as usize,
        doc["positions"].as_array().unwrap().len()
    );
}

#[test]
fn motion_samples_on_the_last_cached_frame_are_clamped_and_say_so() {
    let dir = tempdir("clamp");
    small_cache(&dir, "a.mcap");
    let o = hairsys(
        &[
            "render-children",
            "export",
            "--cache",
            "a.mcap",
            "--frame",
            "3",
            "--motion-samples",
            "3",
            "--count",
            "100",
            "-o",
            "c.usda",
        ],
        &dir,
    );
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stderr(&o).contains("clamped"), "{}", stderr(&o));
}

#[test]
fn shutter_alone_implies_motion_samples() {
    let dir = tempdir("shutter");
    small_cache(&dir, "a.mcap");
    let o = hairsys(
        &[
            "render-children",
            "export",
            "--cache",
            "a.mcap",
            "--frame",
            "2",
            "--shutter",
            "-0.5,0.5",
            "--count",
            "100",
            "-o",
            "c.usda",
            "--json",
        ],
        &dir,
    );
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(doc["time_samples"].as_u64().unwrap() > 1, "{doc}");
}

#[test]
fn export_extension_picks_the_format_and_a_mismatch_is_refused() {
    let dir = tempdir("ext");
    let base = [
        "render-children",
        "export",
        "--default-scene",
        "--count",
        "50",
    ];
    let run = |extra: &[&str]| {
        let mut args = base.to_vec();
        args.extend_from_slice(extra);
        hairsys(&args, &dir)
    };
    let o = run(&["-o", "a.abc"]);
    assert_eq!(code(&o), 2);
    assert!(!dir.join("a.abc").exists());
    let o = run(&["-o", "a.usdz"]);
    assert_eq!(code(&o), 2);
    assert!(stderr(&o).contains(".usdc"), "{}", stderr(&o));
    // Binary USD is written: a crate file.
    let o = run(&["-o", "a.usdc", "--quiet"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert_eq!(
        &std::fs::read(dir.join("a.usdc")).unwrap()[..8],
        b"PXR-USDC"
    );
    let o = run(&["--format", "hair", "-o", "a.usda"]);
    assert_eq!(code(&o), 2);
    assert!(!dir.join("a.usda").exists());
    let o = run(&["-o", "a.hair", "--quiet"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    // Cem Yuksel's .hair starts with the magic "HAIR".
    assert_eq!(&std::fs::read(dir.join("a.hair")).unwrap()[..4], b"HAIR");
}

#[test]
fn export_without_cache_or_scene_says_what_to_give() {
    let dir = tempdir("export-source");
    let o = hairsys(&["render-children", "export", "-o", "a.usda"], &dir);
    assert_eq!(code(&o), 2);
    assert!(stderr(&o).contains("--cache"), "{}", stderr(&o));
    assert!(!dir.join("a.usda").exists());
}

#[test]
fn completions_and_man_page_come_from_the_command_definitions() {
    let dir = tempdir("completions");
    for shell in ["bash", "zsh", "fish"] {
        let o = hairsys(&["completions", shell], &dir);
        assert_eq!(code(&o), 0);
        let text = stdout(&o);
        assert!(
            text.contains("render-children") && text.contains("allow-large"),
            "{shell}"
        );
    }
    let o = hairsys(&["man"], &dir);
    assert_eq!(code(&o), 0);
    let text = stdout(&o);
    assert!(
        text.starts_with(".ie") || text.contains(".TH hairsys 1"),
        "{text}"
    );
    assert!(text.contains("simulate"));
}

// Output.

#[test]
fn a_closed_stdout_pipe_ends_the_run_with_exit_1_not_a_panic_and_the_cache_is_written() {
    let dir = tempdir("epipe");
    let mut child = Command::new(env!("CARGO_BIN_EXE_hairsys"))
        .args(["simulate", "--frames", "1-4", "--cache", "p.mcap", "--json"])
        .current_dir(&dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take()); // the reader goes away before the first line
    let o = child.wait_with_output().unwrap();
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("cannot write to stdout"),
        "{}",
        stderr(&o)
    );
    assert!(dir.join("p.mcap").exists(), "the run finished its cache");
}

#[test]
fn a_full_stdout_ends_the_command_with_exit_1_not_a_panic() {
    let dir = tempdir("full");
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_hairsys"))
        .args(["scene", "init"])
        .current_dir(&dir)
        .stdout(full)
        .output()
        .unwrap();
    assert_eq!(code(&o), 1);
    assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
}

// Exit codes (bad input is 2 in every command).

#[test]
fn bad_files_in_groom_cache_and_render_children_exit_2() {
    let dir = tempdir("exit2");
    std::fs::write(dir.join("junk.mcap"), b"not a cache").unwrap();
    std::fs::write(dir.join("junk.hair"), b"not a groom").unwrap();
    for args in [
        vec!["cache", "info", "junk.mcap"],
        vec!["cache", "info", "missing.mcap"],
        vec!["cache", "sample", "junk.mcap", "--time", "0"],
        vec!["cache", "recover", "junk.mcap", "fixed.mcap"],
        vec!["groom", "info", "junk.hair"],
        vec!["groom", "info", "/dev/zero"],
        vec!["groom", "export", "missing.toml", "-o", "g.hair"],
        vec![
            "render-children",
            "export",
            "--cache",
            "junk.mcap",
            "--frame",
            "1",
            "-o",
            "c.usda",
        ],
        vec!["scene", "check", "/dev/zero"],
    ] {
        let o = hairsys(&args, &dir);
        assert_eq!(code(&o), 2, "{args:?}: {}", stderr(&o));
        assert!(!stderr(&o).contains("panicked"), "{args:?}");
    }
}

#[test]
fn cache_recover_onto_its_own_input_is_refused_also_through_another_path() {
    let dir = tempdir("recover-same");
    small_cache(&dir, "a.mcap");
    let before = std::fs::read(dir.join("a.mcap")).unwrap();
    for fixed in ["a.mcap", "./a.mcap"] {
        let o = hairsys(&["cache", "recover", "a.mcap", fixed], &dir);
        assert_eq!(code(&o), 2, "{}", stderr(&o));
    }
    std::fs::hard_link(dir.join("a.mcap"), dir.join("link.mcap")).unwrap();
    let o = hairsys(&["cache", "recover", "a.mcap", "link.mcap"], &dir);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert_eq!(std::fs::read(dir.join("a.mcap")).unwrap(), before);
}

// Budgets before work.

#[test]
fn ten_million_hairs_are_refused_by_scene_check_with_the_estimate_and_the_flag() {
    let dir = tempdir("budget-hair");
    let s = scene(&dir, "count = 10000000\nlength = 0.1\nsegments = 32", "");
    let o = hairsys(&["scene", "check", s.to_str().unwrap()], &dir);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("[hair] count = 10000000") && e.contains("--allow-large"),
        "{e}"
    );
}

#[test]
fn a_huge_guide_count_is_refused_before_generation() {
    let dir = tempdir("budget-guides");
    let s = scene(
        &dir,
        "count = 10\nlength = 0.1\nsegments = 4",
        "\n[guides]\ncount = 123456789012\nlength = 0.1\nsegments = 8\n",
    );
    let o = hairsys(&["scene", "check", s.to_str().unwrap()], &dir);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(
        stderr(&o).contains("[guides] count = 123456789012"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn auto_substeps_from_a_huge_stretch_stiffness_are_capped_naming_it() {
    let dir = tempdir("budget-auto");
    let s = scene(
        &dir,
        "count = 10\nlength = 0.1\nsegments = 4",
        // The explicit integrator's substeps follow the stability bound (BDF2, which
        // "auto" would pick here, has none).
        "\n[solver]\nintegrator = \"semi-implicit-euler\"\n[physics]\nstretch_stiffness = 1e15\n",
    );
    let o = hairsys(&["scene", "check", s.to_str().unwrap()], &dir);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(stderr(&o).contains("stretch_stiffness"), "{}", stderr(&o));
}

#[test]
fn a_tiny_mass_per_length_is_capped_like_a_stiff_spring() {
    let dir = tempdir("budget-mass");
    let s = scene(
        &dir,
        "count = 10\nlength = 0.1\nsegments = 4\nmass_per_length = 1e-30",
        "\n[solver]\nintegrator = \"semi-implicit-euler\"\n",
    );
    let o = hairsys(&["scene", "check", s.to_str().unwrap()], &dir);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(stderr(&o).contains("mass_per_length"), "{}", stderr(&o));
}

#[test]
fn a_billion_steps_per_frame_are_refused_before_the_run() {
    let dir = tempdir("budget-steps");
    let s = scene(
        &dir,
        "count = 10\nlength = 0.1\nsegments = 4",
        "\n[solver]\nsteps = 1000000000\n",
    );
    let o = hairsys(&["scene", "check", s.to_str().unwrap()], &dir);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(stderr(&o).contains("steps = 1000000000"), "{}", stderr(&o));
}

#[test]
fn huge_child_counts_and_motion_samples_are_refused_not_aborted() {
    let dir = tempdir("budget-children");
    for extra in [["--count", "100000000"], ["--motion-samples", "1000000000"]] {
        let mut args = vec![
            "render-children",
            "export",
            "--default-scene",
            "-o",
            "c.usda",
        ];
        args.extend_from_slice(&extra);
        let o = hairsys(&args, &dir);
        assert_eq!(code(&o), 2, "{extra:?}: {}", stderr(&o));
        assert!(stderr(&o).contains("--allow-large"), "{}", stderr(&o));
    }
}

// One writer per cache.

#[test]
fn a_second_writer_on_the_same_cache_is_refused_with_the_first_ones_pid() {
    let dir = tempdir("two-writers");
    // The default scene over 48 frames runs long enough in a test build to overlap.
    let mut first = Command::new(env!("CARGO_BIN_EXE_hairsys"))
        .args(["simulate", "--cache", "w.mcap", "--quiet"])
        .current_dir(&dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let pid_file = dir.join("w.mcap.partial.pid");
    let t0 = std::time::Instant::now();
    while !pid_file.exists() {
        assert!(
            t0.elapsed().as_secs() < 120,
            "the first run never started writing"
        );
        assert!(
            first.try_wait().unwrap().is_none(),
            "the first run ended too soon"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let second = hairsys(&["simulate", "--cache", "w.mcap", "--force"], &dir);
    let resumed = hairsys(&["simulate", "--cache", "w.mcap", "--resume"], &dir);
    let still_running = first.try_wait().unwrap().is_none();
    let _ = first.kill();
    let _ = first.wait();
    assert!(
        still_running,
        "the first run ended before the second one was tried"
    );
    for o in [&second, &resumed] {
        assert_eq!(code(o), 1, "{}", stderr(o));
        let e = stderr(o);
        assert!(
            e.contains(&format!("process {}", first.id())),
            "names the holder's PID: {e}"
        );
    }
    // The first run's lock died with it: a third run takes over with --force.
    let o = hairsys(
        &[
            "simulate", "--frames", "1-2", "--cache", "w.mcap", "--force", "--quiet",
        ],
        &dir,
    );
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(dir.join("w.mcap").exists() && !pid_file.exists());
}

// One frame count everywhere.

/// `simulate --json`'s summary, the text summary and `cache info --json` for one run.
fn counts_of_a_run(dir: &Path, args: &[&str], cache: &str) -> (u64, u64, String, u64) {
    let mut json_args = vec!["simulate", "--cache", cache, "--json"];
    json_args.extend_from_slice(args);
    let o = hairsys(&json_args, dir);
    assert_eq!(code(&o), 0, "{args:?}: {}", stderr(&o));
    let text = stdout(&o);
    let done: serde_json::Value = serde_json::from_str(text.lines().last().unwrap()).unwrap();
    let summary = &done["summary"];
    assert_eq!(summary["frames"], summary["cache"]["frames"], "{summary}");
    let frame_events = text.lines().filter(|l| l.contains("\"frame\"")).count() as u64;
    let info = hairsys(&["cache", "info", cache, "--json"], dir);
    let info: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    (
        summary["frames"].as_u64().unwrap(),
        summary["stepped"].as_u64().unwrap(),
        format!("{frame_events}"),
        info["frames"].as_u64().unwrap(),
    )
}

#[test]
fn simulate_json_text_summary_and_cache_info_give_one_frame_count() {
    let dir = tempdir("frame-counts");
    let s = scene(&dir, "count = 10\nlength = 0.1\nsegments = 4", "");
    let s = s.to_str().unwrap();
    // The scene's own range (frames 1–3) and a --frames override (2–6): frames written, the
    // first (rest) frame included, are what the cache holds; `stepped` counts the steps.
    // One frame N (as `--help` says) writes the rest frame alone, without a step.
    for (args, frames) in [
        (vec![s], 3u64),
        (vec![s, "--frames", "2-6"], 5),
        (vec![s, "--frames", "4"], 1),
    ] {
        let cache = format!("c{frames}.mcap");
        let (written, stepped, events, info) = counts_of_a_run(&dir, &args, &cache);
        assert_eq!((written, info), (frames, frames), "{args:?}");
        assert_eq!(stepped, frames - 1);
        assert_eq!(
            events,
            (frames - 1).to_string(),
            "one event per stepped frame"
        );
        let mut text_args = vec!["simulate", "--cache", "t.mcap", "--force"];
        text_args.extend_from_slice(&args);
        let o = hairsys(&text_args, &dir);
        assert_eq!(code(&o), 0, "{}", stderr(&o));
        let text = stdout(&o);
        assert!(text.contains(&format!("{frames} frames written")), "{text}");
        assert!(text.ends_with('\n'), "{text:?}");
    }
    // A resumed run counts the frames it took over: a complete 1–3 cache as the partial of a
    // 1–6 run is continued from frame 3 and the result holds (and reports) 6 frames.
    std::fs::copy(dir.join("c3.mcap"), dir.join("r.mcap.partial")).unwrap();
    let (written, stepped, _, info) =
        counts_of_a_run(&dir, &[s, "--frames", "1-6", "--resume"], "r.mcap");
    assert_eq!((written, stepped, info), (6, 3, 6));
}

// --resume refuses a damaged last frame.

/// Byte offset of the first occurrence of `needle` in `hay` at or after `from`.
fn find(hay: &[u8], needle: &[u8], from: usize) -> Option<usize> {
    hay[from..]
        .windows(needle.len())
        .position(|w| w == needle)
        .map(|i| i + from)
}

#[test]
fn resume_from_a_partial_whose_last_frame_holds_nan_is_refused_by_frame() {
    let dir = tempdir("resume-nan");
    let s = scene(&dir, "count = 10\nlength = 0.1\nsegments = 4", "");
    let s = s.to_str().unwrap();
    let o = hairsys(&["simulate", s, "--cache", "a.mcap", "--quiet"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    // The tip of the last strand at the last frame (3), as f32 little-endian bytes in the
    // uncompressed cache: it moved, so its bytes differ from the earlier frames'.
    let mut reader = hair_cache::CacheReader::open(dir.join("a.mcap")).unwrap();
    let last = reader.read_frame(3).unwrap();
    let first = reader.read_frame(1).unwrap();
    let tip = *last.positions.last().unwrap();
    assert_ne!(tip, *first.positions.last().unwrap());
    let needle: Vec<u8> = tip.iter().flat_map(|c| c.to_le_bytes()).collect();
    let mut bytes = std::fs::read(dir.join("a.mcap")).unwrap();
    let at = find(&bytes, &needle, 0).expect("the tip's bytes are in the file");
    bytes[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    // Walk the MCAP records (magic, then opcode u8, length u64, body) to the chunk holding the
    // damaged bytes and mark its CRC "not computed" (0, as MCAP allows), so the chunk reads as
    // intact: a file a buggy writer or a hand edit could leave.
    let mut pos = 8;
    loop {
        let len = u64::from_le_bytes(bytes[pos + 1..pos + 9].try_into().unwrap()) as usize;
        let body = pos + 9;
        if bytes[pos] == 0x06 && (body..body + len).contains(&at) {
            // Chunk body: start time u64, end time u64, uncompressed size u64, CRC u32.
            bytes[body + 24..body + 28].copy_from_slice(&0u32.to_le_bytes());
            break;
        }
        pos = body + len;
        assert!(pos < bytes.len(), "no chunk holds the damaged bytes");
    }
    std::fs::write(dir.join("b.mcap.partial"), &bytes).unwrap();
    let o = hairsys(
        &[
            "simulate", s, "--frames", "1-6", "--cache", "b.mcap", "--resume",
        ],
        &dir,
    );
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("non-finite") && e.contains("frame 3") && !e.contains("diverge"),
        "{e}"
    );
    assert!(!dir.join("b.mcap").exists());
    assert!(dir.join("b.mcap.partial").exists(), "the partial is kept");
}

#[test]
fn ten_million_frames_given_by_frames_are_refused_by_the_work_budget_and_allow_large_lifts_it() {
    let dir = tempdir("budget-frames");
    // 4000 × 17 points (the default scene) × its 8 BDF2 substeps, each weighted as 3 explicit
    // ones, × 10⁷ frames is 1.6e13 point-substeps, over 10¹³ (10⁶ frames would be 1.6e12,
    // under); the scene's own 48 frames are not.
    let o = hairsys(
        &["simulate", "--frames", "1-10000000", "--cache", "f.mcap"],
        &dir,
    );
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("--frames 1-10000000") && e.contains("--allow-large"),
        "{e}"
    );
    assert!(!dir.join("f.mcap").exists() && !dir.join("f.mcap.partial").exists());
    // --allow-large lets the same run start (killed at once: it would take days).
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_hairsys"))
        .args([
            "simulate",
            "--frames",
            "1-10000000",
            "--cache",
            "f.mcap",
            "--allow-large",
            "--quiet",
        ])
        .current_dir(&dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = std::time::Instant::now();
    while !dir.join("f.mcap.partial").exists() {
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the run ended ({status}) instead of starting");
        }
        assert!(t0.elapsed().as_secs() < 120, "the run never started");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
}

#[test]
fn the_snap_distance_error_lists_the_causes_once_in_order_with_an_unapplied_transform_first() {
    let dir = tempdir("snap-message");
    // The Sintel groom (in centimetres, Y up, converted right) on a sphere far smaller than her
    // head: every root is far from the scalp.
    let tfx = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../data/sintel/sintel_hair.tfx"
    );
    std::fs::write(
        dir.join("far.toml"),
        format!(
            "[scene]\nframes = [1, 3]\n[scalp.mesh]\nkind = \"uv-sphere\"\nradius = 0.1\n\
             segments = 12\nrings = 8\n[guides]\nfile = \"{tfx}\"\nscale = 0.01\nup_axis = \
             \"y\"\n[sim_hairs]\ncount = 10\n"
        ),
    )
    .unwrap();
    let o = hairsys(&["scene", "check", "far.toml"], &dir);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    let e = stderr(&o);
    let at = |what: &str| {
        assert_eq!(e.matches(what).count(), 1, "`{what}` once: {e}");
        e.find(what).unwrap()
    };
    let order = [
        at("Apply › All Transforms"),
        at("`scale`"),
        at("`up_axis`"),
        at("another scalp"),
        at("`max_snap_distance`"),
    ];
    assert!(order.windows(2).all(|w| w[0] < w[1]), "{e}");
    assert!(e.starts_with("error: ") && e.contains("[guides]"), "{e}");
}

// `scene init` shows every section, commented, and each one works uncommented.

/// The scene with the commented block that starts at line `start` (`# [section]`) uncommented
/// up to the next blank line.
fn uncomment_block(lines: &[&str], start: usize) -> String {
    let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    let mut i = start;
    while i < lines.len() && !lines[i].trim().is_empty() {
        let l = lines[i];
        out[i] = l
            .strip_prefix("# ")
            .or_else(|| l.strip_prefix('#'))
            .unwrap_or(l)
            .to_string();
        i += 1;
    }
    out.join("\n") + "\n"
}

#[test]
fn scene_init_shows_every_optional_section_commented_and_each_uncommented_checks() {
    let dir = tempdir("init-sections");
    let o = hairsys(&["scene", "init"], &dir);
    assert_eq!(code(&o), 0);
    let text = stdout(&o);
    let lines: Vec<&str> = text.lines().collect();
    let headers: Vec<(usize, String)> = lines
        .iter()
        .enumerate()
        .filter_map(|(i, l)| {
            let h = l.strip_prefix("# [")?;
            let name = h.split(']').next()?.trim_start_matches('[');
            Some((i, name.to_string()))
        })
        .collect();
    let names: Vec<&str> = headers.iter().map(|(_, n)| n.as_str()).collect();
    // The default scene collides with its head and has hair–hair friction: those sections are
    // live, not commented.
    for live in ["\n[scalp.collider]", "\n[hair_hair]"] {
        assert!(text.contains(live), "{live} is not live in scene init");
    }
    for section in [
        "guides",
        "sim_hairs",
        "strands",
        "colliders",
        "contacts",
        "fields",
        "children",
        "rod",
        "strips",
    ] {
        assert!(
            names.contains(&section),
            "[{section}] missing from {names:?}"
        );
    }
    for (start, name) in &headers {
        // [sim_hairs] interpolates from [guides]: it is uncommented with the [guides] block.
        if name == "sim_hairs" {
            continue;
        }
        let mut scene = uncomment_block(&lines, *start);
        // Drops the section starting with `header` up to the next blank line.
        let drop = |scene: &mut String, header: &str| {
            let from = scene.find(header).unwrap();
            let to = from + 1 + scene[from + 1..].find("\n\n").unwrap();
            scene.replace_range(from..to, "");
        };
        if name == "rod" || name == "strips" {
            // As the comments say: hair–hair and sag-free are the mass-spring model's.
            drop(&mut scene, "\n[hair_hair]");
            scene = scene.replace("\nsag_free = true", "\n# sag_free = true");
            let model = if name == "rod" { "rod" } else { "strips" };
            scene = scene.replace("# model = \"mass-spring\"", &format!("model = \"{model}\""));
        }
        if name == "strips" {
            // Strips replace the strands of [hair]: drop it and its style.
            drop(&mut scene, "\n[hair]\n");
            drop(&mut scene, "\n[hair.style]");
        }
        std::fs::write(dir.join("s.toml"), &scene).unwrap();
        let o = hairsys(&["scene", "check", "s.toml"], &dir);
        assert_eq!(code(&o), 0, "[{name}] uncommented: {}", stderr(&o));
    }
}

// `scene check` prints everything the run will use.

#[test]
fn scene_check_reports_what_the_run_then_uses_colliders_model_substeps_components_budget() {
    let dir = tempdir("check-everything");
    let s = scene(
        &dir,
        "count = 20\nlength = 0.1\nsegments = 4",
        "\n[scalp.collider]\nfriction = 0.3\n\n[[colliders]]\nname = \"ball\"\nshape = { kind = \
         \"sphere\", radius = 0.05 }\nmotion = { keys = [{ frame = 1, translation = [0.0, 0.3, \
         0.0] }, { frame = 3, translation = [0.0, 0.2, 0.0] }] }\n\n[hair_hair]\ncell_size = \
         0.02\nfriction = 0.2\n\n[[fields]]\ntype = \"drag\"\nstrength = 1.0\n",
    );
    let s = s.to_str().unwrap();
    let o = hairsys(&["scene", "check", s, "--json"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let check: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let o = hairsys(&["simulate", s, "--cache", "c.mcap", "--json"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let text = stdout(&o);
    let done: serde_json::Value = serde_json::from_str(text.lines().last().unwrap()).unwrap();
    let run = &done["summary"];
    // What check promised is what the run used.
    for key in ["substeps", "model", "components", "strands", "points"] {
        assert_eq!(check[key], run[key], "{key}: check {check} run {run}");
    }
    assert_eq!(check["substeps_auto"], true);
    assert_eq!(check["dt_bound"], run["dt_bound"]);
    let names: Vec<&str> = check["colliders"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["scalp", "ball"]);
    let ball = &check["colliders"][1];
    assert!(ball["shape"]
        .as_str()
        .unwrap()
        .contains("sphere, radius 0.05 m"));
    assert!(ball["motion"].as_str().unwrap().contains("2 keys"));
    assert_eq!(check["hair_hair"]["cell_size"], 0.02);
    assert_eq!(check["fields"], serde_json::json!(["drag"]));
    // The budget figures: points × 256 bytes, points × substeps × the integrator's substep
    // weight (an implicit substep counts as `IMPLICIT_SUBSTEP_COST` explicit ones) × steps ×
    // frames stepped.
    let points = check["points"].as_f64().unwrap();
    let integrator = check["integrator"].as_str().unwrap();
    assert_eq!(integrator, run["integrator"].as_str().unwrap());
    let weight = match integrator {
        "bdf2" | "implicit-euler" => hairsys::scene::integrator::IMPLICIT_SUBSTEP_COST,
        _ => 1.0,
    };
    let substeps = check["substeps"].as_f64().unwrap();
    assert_eq!(
        check["budget"]["memory_bytes"].as_f64().unwrap(),
        points * 256.0
    );
    assert_eq!(
        check["budget"]["point_substeps"].as_f64().unwrap(),
        points * substeps * weight * 2.0
    );
    assert_eq!(
        check["budget"]["point_substeps_limit"].as_f64().unwrap(),
        1e13
    );
    // The text names the same things.
    let o = hairsys(&["scene", "check", s], &dir);
    let text = stdout(&o);
    for needle in [
        "model: mass-spring",
        &format!("substeps: {substeps} per step (\"auto\" resolved)"),
        "collider scalp",
        "collider ball: sphere, radius 0.05 m; motion: 2 keys",
        "hair-hair: 0.02 m cells",
        "force fields: drag",
        "components: ",
        "budget: memory",
    ] {
        assert!(text.contains(needle), "{needle}: {text}");
    }
    assert!(text.ends_with('\n'));
}

#[test]
fn an_absurd_scale_with_finite_coordinates_is_refused_naming_the_flag_and_a_fix() {
    let dir = tempdir("absurd-scale");
    let tfx = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../data/sintel/sintel_hair.tfx"
    );
    // The Sintel groom is in centimetres (strands of 3.8–20.6 units).
    for scale in ["1e12", "1e-12", "1"] {
        let o = hairsys(
            &["groom", "info", tfx, "--scale", scale, "--up-axis", "y"],
            &dir,
        );
        assert_eq!(code(&o), 2, "--scale {scale}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains(&format!("--scale {:e}", scale.parse::<f32>().unwrap()))
                && e.contains("sintel_hair.tfx"),
            "{e}"
        );
        // The suggestion is centimetres: 20.6 cm / 0.3 m rounds to 10^0.
        assert!(e.contains("try --scale 1e-2"), "{e}");
    }
    let o = hairsys(
        &["groom", "info", tfx, "--scale", "0.01", "--up-axis", "y"],
        &dir,
    );
    assert_eq!(code(&o), 0, "{}", stderr(&o));
}

#[test]
fn groom_info_reads_a_stage_in_its_own_units_and_informs_on_unitless_files() {
    let dir = tempdir("groom-info-units");
    // A Blender-style stage in centimetres: one 20 cm strand.
    let usda = "#usda 1.0\n(\n    metersPerUnit = 0.01\n    upAxis = \"Z\"\n)\n\
        def BasisCurves \"hair\"\n{\n    int[] curveVertexCounts = [3]\n    \
        point3f[] points = [(0, 0, 0), (0, 0, 10), (0, 0, 20)]\n    uniform token type = \"linear\"\n}\n";
    std::fs::write(dir.join("cm.usda"), usda).unwrap();
    let o = hairsys(&["groom", "info", "cm.usda", "--json"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let longest = doc["length_m"]["max"].as_f64().unwrap();
    assert!((longest - 0.2).abs() < 1e-6, "{longest} m, not 0.2 m");
    assert!((doc["units"]["meters_per_unit"].as_f64().unwrap() - 0.01).abs() < 1e-9);
    assert_eq!(doc["units"]["plausible"], true);
    // An explicit --scale replaces the stage's.
    let o = hairsys(
        &["groom", "info", "cm.usda", "--scale", "0.001", "--json"],
        &dir,
    );
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!((doc["length_m"]["max"].as_f64().unwrap() - 0.02).abs() < 1e-6);

    // Sintel's .hair is in centimetres with no units in the file: read as meters, it is
    // reported (not refused) with the scale that was likely meant.
    let hair = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../data/sintel/sintel_hair.hair"
    );
    let o = hairsys(&["groom", "info", hair, "--up-axis", "y"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("strands  228"), "{text}");
    assert!(
        text.contains("assumed") && text.contains("--scale 1e-2"),
        "{text}"
    );
    let o = hairsys(&["groom", "info", hair, "--up-axis", "y", "--json"], &dir);
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(doc["units"]["plausible"], false);
    assert!((doc["units"]["likely_scale"].as_f64().unwrap() - 0.01).abs() < 1e-12);
}
