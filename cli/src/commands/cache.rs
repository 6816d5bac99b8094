//! `hairsys cache`: a point cache's summary, positions at any time, the whole run as one
//! animated USD file, and recovery of a killed run's frames.

use std::path::{Path, PathBuf};

use clap::Subcommand;
use hair_cache::{CacheReader, Interpolation, Shutter, WriterOptions};
use hairsys::output::children::parse_shutter;
use hairsys::output::shot_export::{ShotChildren, ShotOptions};
use serde_json::json;

use crate::args::{parse_range, ChildArgs};
use crate::error::CliError;
use crate::{output, Context};

#[derive(Subcommand)]
pub enum CacheCommand {
    /// Print a cache's frames, time range, strands, points and bytes.
    Info {
        /// Cache file (MCAP).
        file: PathBuf,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Print the positions at any time between cached frames (cubic Hermite with the cached
    /// velocities), as JSON.
    Sample {
        /// Cache file (MCAP).
        file: PathBuf,
        /// Time in seconds (frame / fps); at a frame time the sample is that frame exactly.
        #[arg(long)]
        time: f64,
        /// Interpolate linearly instead of with cubic Hermite.
        #[arg(long)]
        linear: bool,
        /// Write the JSON to this file instead of stdout.
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Write a whole run (or `--frames A-B` of it) as ONE animated USD file: the strands as a
    /// BasisCurves with points and velocities per frame, widths, and the scalp mesh.
    Export {
        /// Cache file (MCAP).
        file: PathBuf,
        /// Output file: .usdc (binary) or .usda (text).
        #[arg(short, long)]
        out: PathBuf,
        /// Frames FIRST-LAST (or one frame N) to write; default every cached frame.
        #[arg(long, value_parser = parse_range)]
        frames: Option<(u32, u32)>,
        /// Sub-frame time samples (motion blur) OPEN,CLOSE in frames around each frame, e.g.
        /// -0.25,0.25; giving it without --motion-samples takes 3 samples.
        #[arg(long, value_parser = parse_shutter, allow_hyphen_values = true)]
        shutter: Option<(f64, f64)>,
        /// Samples over the shutter (with --shutter) [3].
        #[arg(long, requires = "shutter")]
        motion_samples: Option<usize>,
        /// Write render children generated at every time code from the cached parents (the
        /// scene's [children] section, overridden by the child options) instead of the strands.
        #[arg(long)]
        children: bool,
        #[command(flatten)]
        child: ChildArgs,
        /// Scene overriding the one stored in the cache (roots, scalp, [children]).
        #[arg(long)]
        scene: Option<PathBuf>,
        /// Frames added to every USD time code: --time-offset 1000 writes frame 1 at time
        /// code 1001 (a shot starting at 1001) [0].
        #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
        time_offset: f64,
        /// Print nothing but errors.
        #[arg(long, conflicts_with = "json")]
        quiet: bool,
        /// Print a JSON summary on stdout.
        #[arg(long)]
        json: bool,
    },
    /// Recover every complete frame of a broken cache (e.g. the CACHE.partial of a killed run)
    /// into a complete cache, and say what was lost.
    Recover {
        /// The broken cache.
        broken: PathBuf,
        /// Where to write the recovered, complete cache.
        fixed: PathBuf,
    },
}

/// Runs a `cache` command.
pub fn run(command: CacheCommand, ctx: &Context) -> Result<(), CliError> {
    match command {
        CacheCommand::Info { file, json } => {
            let summary =
                hair_cache::summarize(&file).map_err(|e| CliError::input(e.to_string()))?;
            if json {
                outln!(
                    "{}",
                    serde_json::to_string_pretty(&summary).expect("summaries serialise")
                );
            } else {
                outln!("{}", file.display());
                output::block(&summary.to_string());
            }
            Ok(())
        }
        CacheCommand::Sample {
            file,
            time,
            linear,
            out,
        } => sample(&file, time, linear, out.as_deref()),
        CacheCommand::Recover { broken, fixed } => recover(&broken, &fixed),
        CacheCommand::Export {
            file,
            out,
            frames,
            shutter,
            motion_samples,
            children,
            child,
            scene,
            time_offset,
            quiet,
            json,
        } => {
            let shot = ShotOptions {
                time_offset,
                ..cache_export_options(
                    frames,
                    shutter,
                    motion_samples,
                    children,
                    &child,
                    scene,
                    ctx.budget,
                )?
            };
            super::cache_export::run(&file, &out, &shot, quiet, json)
        }
    }
}

/// The options of `cache export`: child options only with `--children`.
fn cache_export_options(
    frames: Option<(u32, u32)>,
    shutter: Option<(f64, f64)>,
    motion_samples: Option<usize>,
    children: bool,
    child: &ChildArgs,
    scene: Option<PathBuf>,
    budget: hairsys::budget::Budget,
) -> Result<ShotOptions, CliError> {
    if let (false, Some(flag)) = (children, child.first_given()) {
        return Err(CliError::input(format!(
            "{flag} sets render children: add --children to export children instead of the strands"
        )));
    }
    Ok(ShotOptions {
        frames,
        shutter: shot_shutter(shutter, motion_samples)?,
        children: children.then(|| ShotChildren {
            overrides: child.overrides(),
            display: child.display,
        }),
        scene,
        budget,
        time_offset: 0.0,
        context: None,
    })
}

/// The sub-frame samples of `--shutter OPEN,CLOSE` and `--motion-samples N` (3 by default).
pub fn shot_shutter(
    shutter: Option<(f64, f64)>,
    samples: Option<usize>,
) -> Result<Option<Shutter>, CliError> {
    let Some((open, close)) = shutter else {
        return Ok(None);
    };
    Shutter::new(open, close, samples.unwrap_or(3))
        .map(Some)
        .map_err(|e| CliError::input(format!("--shutter {open},{close}: {e}")))
}

/// `cache sample`: positions at `time` as JSON.
fn sample(file: &Path, time: f64, linear: bool, out: Option<&Path>) -> Result<(), CliError> {
    let mut reader = CacheReader::open(file).map_err(|e| CliError::input(e.to_string()))?;
    let interpolation = if linear {
        Interpolation::Linear
    } else {
        Interpolation::Hermite
    };
    let (a, b) = reader
        .frames_around(time)
        .map_err(|e| CliError::input(e.to_string()))?;
    let sample = reader
        .sample(time, interpolation)
        .map_err(|e| CliError::input(e.to_string()))?;
    let offsets: Vec<u64> = reader.layout().offsets.iter().map(|&o| o as u64).collect();
    let doc = json!({
        "file": file.display().to_string(),
        "time": sample.time,
        "between_frames": [a, b],
        "interpolation": if linear { "linear" } else { "hermite" },
        "points": sample.positions.len(),
        "strand_offsets": offsets,
        "positions": sample.positions.iter().map(|p| [p.x, p.y, p.z]).collect::<Vec<_>>(),
        "velocities": sample.velocities.iter().map(|v| [v.x, v.y, v.z]).collect::<Vec<_>>(),
    });
    let text = serde_json::to_string(&doc).expect("samples serialise");
    match out {
        Some(path) => std::fs::write(path, text + "\n").map_err(|e| {
            CliError::failed(format!(
                "{}: cannot write the sample ({e}); check the directory",
                path.display()
            ))
        }),
        None => {
            output::line(&text);
            Ok(())
        }
    }
}

/// `cache recover`: every complete frame of `broken` into a complete cache at `fixed`.
fn recover(broken: &Path, fixed: &Path) -> Result<(), CliError> {
    if same_file(broken, fixed) {
        return Err(CliError::input(format!(
            "cache recover {} {}: both name the same file; write the recovered cache to another \
             path (recovering over the input would destroy it)",
            broken.display(),
            fixed.display()
        )));
    }
    let recovery = hair_cache::recover(broken).map_err(|e| CliError::input(e.to_string()))?;
    if recovery.frames.is_empty() {
        return Err(CliError::input(format!(
            "{}: no complete frame to recover",
            broken.display()
        )));
    }
    match &recovery.warning {
        Some(w) => eprintln!("warning: {}: {w}", broken.display()),
        None => eprintln!("{}: every frame was complete", broken.display()),
    }
    let summary = recovery
        .write(fixed, WriterOptions::default())
        .map_err(|e| CliError::failed(e.to_string()))?;
    outln!("wrote {}", fixed.display());
    output::block(&summary.to_string());
    Ok(())
}

/// Whether `a` and `b` are the same file (same device and inode, so also through different
/// paths or links); false when either does not exist.
fn same_file(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(x), Ok(y)) => x.dev() == y.dev() && x.ino() == y.ino(),
        _ => false,
    }
}
