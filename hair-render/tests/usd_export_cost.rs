//! The cost of writing one frame of a million render children × 17 points as USD (the
//! target: `.usdc` in ≤ 1 s on the project's 2-core machine), measured in one process so the
//! children's generation is not in the figure: the layer is built from the children (moved in,
//! not copied) and written through a `.partial` file, fsync and rename included.
//!
//! Slow and machine-dependent, so ignored; run with
//! `cargo test --release -p hair-render --test usd_export_cost -- --ignored --nocapture`
//! (`USD_COST_RUNS=5`, `USD_COST_TEXT=1` to time `.usda` too). It prints, per format, the median
//! and range of the wall and CPU (user + system) seconds over the runs, the bytes written and
//! the machine's load average; BENCHMARKS.md quotes it.

use std::time::Instant;

use hair_render::export::usd::{export_usd, Motion, UsdOptions};
use hair_render::ChildBuffers;

/// `curves` children of `points` points each: a strand rising from a unit disc with a little
/// wave, tapered widths, a root UV and a random value per curve (the arrays a real export has).
fn children(curves: usize, points: usize) -> ChildBuffers {
    let mut c = ChildBuffers {
        vertex_counts: vec![points as u32; curves],
        points: Vec::with_capacity(curves * points * 3),
        widths: Vec::with_capacity(curves * points),
        parent: (0..curves as u32).map(|i| i / 250).collect(),
        random: (0..curves)
            .map(|i| (i as f32 * 0.618_034).fract())
            .collect(),
        root_uv: Some(
            (0..curves * 2)
                .map(|i| (i as f32 * 0.377).fract())
                .collect(),
        ),
        color: None,
    };
    for i in 0..curves {
        let a = i as f32 * 2.399_963;
        let r = (i as f32 / curves as f32).sqrt();
        for k in 0..points {
            let s = k as f32 / (points - 1) as f32;
            c.points.extend([
                r * a.cos() + 0.01 * (7.0 * s + a).sin(),
                r * a.sin(),
                0.3 * s,
            ]);
            c.widths.push(8e-5 + (2e-5 - 8e-5) * s);
        }
    }
    c
}

/// This process's CPU time so far (user + system), s, from `/proc/self/stat` (clock ticks of
/// 1/100 s); `None` where there is no `/proc`.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name in parentheses; utime and stime are fields 14 and 15.
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "?".into())
}

fn median_and_range(mut v: Vec<f64>) -> String {
    v.sort_by(f64::total_cmp);
    format!(
        "{:.3} s (range {:.3}–{:.3})",
        v[v.len() / 2],
        v[0],
        v[v.len() - 1]
    )
}

#[test]
#[ignore = "slow benchmark: cargo test --release -p hair-render --test usd_export_cost -- --ignored --nocapture"]
fn one_frame_of_a_million_children_written_as_usd() {
    let runs: usize = std::env::var("USD_COST_RUNS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(5);
    let mut exts = vec!["usdc"];
    if std::env::var_os("USD_COST_TEXT").is_some() {
        exts.push("usda");
    }
    let frame = children(1_000_000, 17);
    let dir = tempfile::tempdir_in(std::env::temp_dir()).unwrap();
    for ext in exts {
        let path = dir.path().join(format!("c.{ext}"));
        let (mut wall, mut cpu) = (Vec::new(), Vec::new());
        let mut bytes = 0;
        for _ in 0..runs {
            // The export consumes its children: the copy is made before the clock starts.
            let input = frame.clone();
            let (c0, t0) = (cpu_seconds(), Instant::now());
            export_usd(&path, input, &Motion::None, &UsdOptions::default()).unwrap();
            wall.push(t0.elapsed().as_secs_f64());
            if let (Some(a), Some(b)) = (c0, cpu_seconds()) {
                cpu.push(b - a);
            }
            bytes = std::fs::metadata(&path).unwrap().len();
            std::fs::remove_file(&path).unwrap();
        }
        println!(
            "1 M children × 17 points as .{ext}: {bytes} bytes; wall {}; CPU {}; {runs} runs; \
             load {}",
            median_and_range(wall),
            if cpu.is_empty() {
                "?".into()
            } else {
                median_and_range(cpu)
            },
            load_average()
        );
    }
}
