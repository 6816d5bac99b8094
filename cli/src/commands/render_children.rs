//! `hairsys render-children`: children generated from a cached frame (with motion-blur
//! samples) or the rest state, as USD BasisCurves or `.hair`; hair cards of a strips scene.

use std::path::{Path, PathBuf};

use clap::{Subcommand, ValueEnum};
use hairsys::output::children::{export, parse_shutter, ExportOptions, Format};
use hairsys::output::shot_export::{ShotChildren, ShotOptions};

use crate::args::{parse_range, ChildArgs};
use crate::commands::cache::shot_shutter;
use crate::error::CliError;
use crate::progress::Progress;
use crate::Context;

#[derive(Subcommand)]
pub enum RenderCommand {
    /// Generate children from a cached frame (with motion-blur samples over a shutter) or from the
    /// scene's rest state, and write them as USD BasisCurves or .hair.
    Export(Box<ExportArgs>),
    /// Hair cards of a `model = "strips"` scene (seed 000) from a cached frame (with motion-blur
    /// samples) or the rest state, as a USD Mesh with st or OBJ with vt.
    Cards(Box<super::cards::CardsArgs>),
}

#[derive(clap::Args)]
pub struct ExportArgs {
    /// Cache to read (its rig gives the roots and the scalp: the scene's files are not read).
    /// One of --cache, --scene or --default-scene is required.
    #[arg(long, required_unless_present_any = ["scene", "default_scene"])]
    cache: Option<PathBuf>,
    /// Scene file: the rest state to export without --cache; with --cache, its [children]
    /// settings instead of those of the scene stored in the cache.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Export the rest state of the built-in default scene (see `hairsys scene init`).
    #[arg(long, conflicts_with_all = ["cache", "scene"])]
    default_scene: bool,
    /// Frame to export (with --cache).
    #[arg(long)]
    frame: Option<u32>,
    /// Frames FIRST-LAST to export into ONE animated USD file (with --cache): children at every
    /// frame (and shutter sample), as `cache export --children` writes them.
    #[arg(long, value_parser = parse_range, conflicts_with = "frame", requires = "cache")]
    frames: Option<(u32, u32)>,
    /// Shutter interval OPEN,CLOSE in frames around the frame [-0.25,0.25]; giving it without
    /// --motion-samples takes 3 samples.
    #[arg(long, value_parser = parse_shutter, allow_hyphen_values = true)]
    shutter: Option<(f64, f64)>,
    /// Motion samples over the shutter (USD time samples; 3 when only --shutter is given);
    /// 1 = no motion blur. Samples past the first or last cached frame are clamped to it.
    #[arg(long)]
    motion_samples: Option<usize>,
    #[command(flatten)]
    child: ChildArgs,
    /// Output format [from the extension of --out: .usdc, .usda, .hair]; must agree with it.
    #[arg(long, value_enum)]
    format: Option<FormatArg>,
    /// Output file: .usdc (binary USD BasisCurves), .usda (text) or .hair.
    #[arg(short, long)]
    out: PathBuf,
    /// USD: frames added to every time code written: --time-offset 1000 writes frame 12 at
    /// time code 1012 (a shot starting at 1001) [0].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    time_offset: f64,
    /// Print nothing but errors.
    #[arg(long, conflicts_with = "json")]
    quiet: bool,
    /// Print a JSON summary on stdout.
    #[arg(long)]
    json: bool,
}

/// Runs a `render-children` command.
pub fn run(command: RenderCommand, ctx: &Context) -> Result<(), CliError> {
    match command {
        RenderCommand::Export(args) => export_children(*args, ctx),
        RenderCommand::Cards(args) => super::cards::run(&args),
    }
}

/// Children output format.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum FormatArg {
    /// USD BasisCurves (.usdc binary or .usda text).
    Usd,
    /// Cem Yuksel's .hair.
    Hair,
}

/// The format `out`'s extension names, or `None` for another extension.
fn format_of(out: &Path) -> Option<FormatArg> {
    match out.extension()?.to_str()?.to_ascii_lowercase().as_str() {
        "usda" | "usdc" => Some(FormatArg::Usd),
        "hair" => Some(FormatArg::Hair),
        _ => None,
    }
}

/// The export format: `--format` if given (it must agree with the extension of `out`), else
/// the extension's.
fn export_format(format: Option<FormatArg>, out: &Path) -> Result<Format, CliError> {
    let ext = out
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let from_ext = format_of(out);
    let chosen = match (format, from_ext) {
        (Some(f), Some(e)) if f != e => {
            return Err(CliError::input(format!(
                "-o {}: the extension says {} but --format {} was given; use .{} for --format {}, \
                 or drop --format",
                out.display(),
                e.name(),
                f.name(),
                f.extension(),
                f.name()
            )))
        }
        (_, Some(e)) => e,
        (Some(f), None) => {
            return Err(CliError::input(format!(
                "-o {}: give the file the extension .{} for --format {}",
                out.display(),
                f.extension(),
                f.name()
            )))
        }
        (None, None) => {
            let hint = match ext.as_deref() {
                Some("usd" | "usdz") => " (write .usdc for binary USD, or .usda text)",
                Some("abc") => " (Alembic is not supported: write .usdc or .usda)",
                _ => "",
            };
            return Err(CliError::input(format!(
                "-o {}: unknown output extension{hint}; use .usdc/.usda (USD BasisCurves) or .hair",
                out.display()
            )));
        }
    };
    Ok(match chosen {
        FormatArg::Usd => Format::Usd,
        FormatArg::Hair => Format::Hair,
    })
}

impl FormatArg {
    /// The `--format` value.
    fn name(self) -> &'static str {
        match self {
            FormatArg::Usd => "usd",
            FormatArg::Hair => "hair",
        }
    }

    /// The file extension.
    fn extension(self) -> &'static str {
        match self {
            FormatArg::Usd => "usda",
            FormatArg::Hair => "hair",
        }
    }
}

/// `render-children export`.
fn export_children(a: ExportArgs, ctx: &Context) -> Result<(), CliError> {
    let budget = ctx.budget;
    let format = export_format(a.format, &a.out)?;
    let motion_samples = match (a.motion_samples, a.shutter) {
        (Some(n), _) => n,
        (None, Some(_)) => 3,
        (None, None) => 1,
    };
    if let (Some(frames), Some(cache)) = (a.frames, &a.cache) {
        if format != Format::Usd {
            return Err(CliError::input(
                "--frames writes one animated USD file: use -o NAME.usdc or NAME.usda",
            ));
        }
        let shot = ShotOptions {
            frames: Some(frames),
            shutter: shot_shutter(a.shutter, a.motion_samples)?,
            children: Some(ShotChildren {
                overrides: a.child.overrides(),
                display: a.child.display,
            }),
            scene: a.scene,
            budget,
            time_offset: a.time_offset,
            context: None,
        };
        return crate::commands::cache_export::run(cache, &a.out, &shot, a.quiet, a.json);
    }
    let opts = ExportOptions {
        cache: a.cache,
        scene: a.scene,
        frame: a.frame,
        shutter: a.shutter.unwrap_or((-0.25, 0.25)),
        motion_samples,
        children: a.child.overrides(),
        display: a.child.display,
        format,
        out: a.out,
        budget,
        time_offset: a.time_offset,
    };
    let progress = Progress::new(opts.motion_samples as u64, a.quiet, false, "children");
    let summary = export(&opts, || progress.tick(&()));
    progress.finish();
    let summary = summary?;
    if !summary.clamped_samples.is_empty() && !a.quiet {
        eprintln!(
            "note: motion sample(s) at frame(s) {} lie outside the cached frames and were \
             clamped to the nearest cached frame (the hair holds still there)",
            summary
                .clamped_samples
                .iter()
                .map(|f| format!("{f}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    if a.json {
        outln!(
            "{}",
            serde_json::to_string(&summary).expect("summaries serialise")
        );
    } else if !a.quiet {
        outln!(
            "wrote {}: {} children, {} points, {} time sample(s)",
            summary.out,
            summary.curves,
            summary.points,
            summary.time_samples
        );
    }
    Ok(())
}
