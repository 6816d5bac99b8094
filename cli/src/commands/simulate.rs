//! `hairsys simulate`: a scene (the built-in default if none is given) into an MCAP point cache,
//! with a progress bar, `--json` events and the run's summary.

use std::path::{Path, PathBuf};

use hair_cache::foxglove::FoxgloveOptions;
use hair_cache::{Precision, WriterOptions};
use hairsys::run::{simulate, SimulateOptions};
use hairsys::scene::SceneFile;
use serde_json::json;

use crate::args::{parse_range, CompressionArg};
use crate::error::CliError;
use crate::output;
use crate::progress::Progress;
use crate::Context;

/// Arguments of `simulate`.
#[derive(clap::Args)]
pub struct SimulateArgs {
    /// Scene file (TOML). Without it, the built-in default scene runs (see `hairsys scene init`).
    scene: Option<PathBuf>,
    /// Cache file to write (MCAP). Written as CACHE.partial and renamed when complete.
    #[arg(long, default_value = "out.mcap")]
    cache: PathBuf,
    /// Frame range FIRST-LAST (or one frame N, the rest frame alone) overriding the scene's;
    /// the hair starts at rest at FIRST.
    #[arg(long, value_parser = parse_range)]
    frames: Option<(u32, u32)>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Continue the interrupted run left in CACHE.partial from its last complete frame.
    #[arg(long)]
    resume: bool,
    /// Replace an existing complete CACHE, or discard a killed run's CACHE.partial.
    #[arg(long, conflicts_with = "resume")]
    force: bool,
    /// Cache chunk compression.
    #[arg(long, value_enum, default_value_t = CompressionArg::None)]
    compression: CompressionArg,
    /// Store positions and velocities quantized to 16 bits over each frame's bounds: half the
    /// size, error at most (extent)/131070 per axis (about 23 µm over 3 m).
    #[arg(long)]
    quantize: bool,
    /// Also write a foxglove.SceneUpdate channel showing some strands per frame, to scrub the
    /// run in Foxglove.
    #[arg(long)]
    foxglove: bool,
    /// Strands the Foxglove channel shows per frame (implies --foxglove).
    #[arg(long, value_name = "N", default_value_t = 500)]
    foxglove_strands: usize,
    /// Print nothing but errors (and skip the quality report, which only the summary shows).
    #[arg(long, conflicts_with = "json")]
    quiet: bool,
    /// Print one JSON object per frame and a JSON summary on stdout.
    #[arg(long)]
    json: bool,
}

impl SimulateArgs {
    /// How the cache is written.
    fn writer(&self) -> WriterOptions {
        let foxglove = self.foxglove || self.foxglove_strands != 500;
        WriterOptions {
            compression: self.compression.into(),
            foxglove: foxglove.then_some(FoxgloveOptions {
                max_strands: self.foxglove_strands,
            }),
            precision: if self.quantize {
                Precision::Quantized16
            } else {
                Precision::F32
            },
            ..WriterOptions::default()
        }
    }
}

/// Refuses to start a run over a complete cache or a killed run's `.partial` without `--force`.
fn check_overwrite(cache: &Path, resume: bool, force: bool) -> Result<(), CliError> {
    if resume || force {
        return Ok(());
    }
    if cache.exists() {
        return Err(CliError::input(format!(
            "{} already exists; give --force to replace it, or another --cache path",
            cache.display()
        )));
    }
    if let Ok(partial) = hair_cache::partial_path(cache) {
        if partial.exists() {
            return Err(CliError::input(format!(
                "{} is left by a run that was killed (or is still running): continue it with \
                 --resume, keep its frames with `hairsys cache recover {} FIXED.mcap`, or \
                 discard it with --force",
                partial.display(),
                partial.display()
            )));
        }
    }
    Ok(())
}

/// `simulate`: runs the scene into the cache, showing progress and the summary.
pub fn run(run: SimulateArgs, ctx: &Context) -> Result<(), CliError> {
    let (quiet, json) = (run.quiet, run.json);
    check_overwrite(&run.cache, run.resume, run.force)?;
    let mut scene = match &run.scene {
        Some(path) => SceneFile::load(path)?,
        None => SceneFile::builtin_default(),
    };
    scene.budget = ctx.budget;
    let frames = run.frames;
    let [first, last] = scene.scene.scene.frames;
    let (first, last) = frames.unwrap_or((first, last));
    // The bar counts frames written, the first (rest) frame included, as the summary and
    // `cache info` do; the first is written before the first step.
    let progress = Progress::new(
        u64::from(last.saturating_sub(first)) + 1,
        quiet,
        json,
        "simulating",
    );
    let opts = SimulateOptions {
        scene,
        writer: run.writer(),
        cache: run.cache,
        frames,
        threads: run.threads,
        resume: run.resume,
        kernel: ctx.kernel,
        // The report is part of the summary: a quiet run prints none, so it skips the cost.
        quality: !quiet,
    };
    let result = simulate(&opts, |r| {
        let written = u64::from(r.frame.saturating_sub(first)) + 1;
        progress.frame_written(r.frame, written, &json!({
            "event": "frame",
            "frame": r.frame,
            "max_stretch": r.max_stretch,
            "ms": (r.times.roots + r.times.strands + r.times.contacts + r.times.volume + r.times.fields)
                .as_secs_f64()
                * 1e3,
            "hair_hair_ms": r.times.volume.as_secs_f64() * 1e3,
            "fields_ms": r.times.fields.as_secs_f64() * 1e3,
            "escaped_points": r.escaped_points,
            "deep_contact_points": r.deep_contact_points,
        }))
    });
    progress.finish();
    let summary = result?;
    if let (Some(warning), false) = (&summary.recovery_warning, quiet || json) {
        eprintln!("warning: the interrupted run kept {warning}");
    }
    if let (Some(warning), false) = (&summary.integrator_warning, quiet || json) {
        eprintln!("warning: {warning}");
    }
    if json {
        outln!("{}", json!({ "event": "done", "summary": summary }));
    } else if !quiet {
        outln!("wrote {}", opts.cache.display());
        output::block(&summary.to_string());
    }
    Ok(())
}
