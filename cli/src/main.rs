//! `hairsys`: simulate hair scenes into MCAP point caches.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use hairsys::progress::Progress;
use hairsys::scene::{SceneFile, DEFAULT_SCENE};
use hairsys::simulate::{simulate, SimulateOptions};
use serde_json::json;

/// A Blender-style hair system: guide hairs, mass-spring simulation, MCAP point caches.
#[derive(Parser)]
#[command(name = "hairsys", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a scene (the built-in default if none is given) into an MCAP point cache.
    Simulate {
        /// Scene file (TOML). Without it, the built-in default scene runs (see `hairsys scene init`).
        scene: Option<PathBuf>,
        /// Cache file to write (MCAP). Written as CACHE.partial and renamed when complete.
        #[arg(long, default_value = "out.mcap")]
        cache: PathBuf,
        /// Frame range FIRST-LAST overriding the scene's; the hair starts at rest at FIRST.
        #[arg(long, value_parser = parse_range)]
        frames: Option<(u32, u32)>,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Print nothing but errors.
        #[arg(long, conflicts_with = "json")]
        quiet: bool,
        /// Print one JSON object per frame and a JSON summary on stdout.
        #[arg(long)]
        json: bool,
    },
    /// Scene files.
    Scene {
        #[command(subcommand)]
        command: SceneCommand,
    },
    /// Point caches.
    Cache {
        #[command(subcommand)]
        command: CacheCommand,
    },
}

#[derive(Subcommand)]
enum SceneCommand {
    /// Print the built-in default scene, every key commented (redirect it to a file to start one).
    Init,
    /// Check a scene file and print what it builds, without simulating.
    Check {
        /// Scene file (TOML).
        scene: PathBuf,
    },
}

#[derive(Subcommand)]
enum CacheCommand {
    /// Print a cache's frames, time range, strands, points and bytes.
    Info {
        /// Cache file (MCAP).
        file: PathBuf,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
}

fn parse_range(s: &str) -> Result<(u32, u32), String> {
    let (a, b) = s
        .split_once('-')
        .ok_or_else(|| format!("`{s}` is not a range; write FIRST-LAST, e.g. 1-48"))?;
    let num = |t: &str| {
        t.trim()
            .parse::<u32>()
            .map_err(|_| format!("`{t}` is not a frame number (whole number ≥ 0)"))
    };
    Ok((num(a)?, num(b)?))
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let code = match cli.command {
        Command::Simulate {
            scene,
            cache,
            frames,
            threads,
            quiet,
            json,
        } => run_simulate(scene, cache, frames, threads, quiet, json),
        Command::Scene {
            command: SceneCommand::Init,
        } => {
            print!("{DEFAULT_SCENE}");
            0
        }
        Command::Scene {
            command: SceneCommand::Check { scene },
        } => match SceneFile::load(&scene).and_then(|s| s.build()) {
            Ok(sim) => {
                println!(
                    "{}: ok — {} strands, {} points, frames {}–{} at {} fps",
                    scene.display(),
                    sim.strands.len(),
                    sim.strands.point_count(),
                    sim.first_frame,
                    sim.last_frame,
                    sim.settings.fps
                );
                0
            }
            Err(e) => {
                eprintln!("error: {e}");
                2
            }
        },
        Command::Cache {
            command: CacheCommand::Info { file, json },
        } => match hair_cache::summarize(&file) {
            Ok(summary) => {
                if json {
                    println!(
                        "{}",
                        serde_json::to_string_pretty(&summary).expect("summaries serialise")
                    );
                } else {
                    println!("{}", file.display());
                    print!("{summary}");
                }
                0
            }
            Err(e) => {
                eprintln!("error: {e}");
                1
            }
        },
    };
    ExitCode::from(code as u8)
}

fn run_simulate(
    scene: Option<PathBuf>,
    cache: PathBuf,
    frames: Option<(u32, u32)>,
    threads: Option<usize>,
    quiet: bool,
    json: bool,
) -> i32 {
    let scene = match scene {
        Some(path) => match SceneFile::load(&path) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("error: {e}");
                return 2;
            }
        },
        None => SceneFile::builtin_default(),
    };
    let [first, last] = scene.scene.scene.frames;
    let (first, last) = frames.unwrap_or((first, last));
    let progress = Progress::new(last.saturating_sub(first) as u64, quiet, json, "simulating");
    let opts = SimulateOptions {
        scene,
        cache,
        frames,
        threads,
    };
    let result = simulate(&opts, |r| {
        progress.tick(&json!({
            "event": "frame",
            "frame": r.frame,
            "max_stretch": r.max_stretch,
            "ms": (r.times.roots + r.times.strands).as_secs_f64() * 1e3,
        }))
    });
    progress.finish();
    match result {
        Ok(summary) => {
            if json {
                println!("{}", json!({ "event": "done", "summary": summary }));
            } else if !quiet {
                println!("wrote {}", opts.cache.display());
                print!("{summary}");
            }
            0
        }
        Err(e) => {
            eprintln!("error: {e}");
            e.exit_code()
        }
    }
}
