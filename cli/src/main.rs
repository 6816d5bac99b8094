//! `hairsys`: simulate hair scenes into MCAP point caches.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{CommandFactory, Parser, Subcommand, ValueEnum};
use hair_cache::foxglove::FoxgloveOptions;
use hair_cache::{CacheReader, Compression, Interpolation, Precision, Shutter, WriterOptions};
use hair_core::KernelChoice;
use hair_render::ChildCount;
use hairsys::budget::Budget;
use hairsys::output::children::{export, parse_shutter, ChildOverrides, ExportOptions, Format};
use hairsys::output::shot_export::{ShotChildren, ShotOptions};
use hairsys::run::{simulate, SimulateOptions};
use hairsys::scene::{SceneFile, DEFAULT_SCENE};
use hairsys_cli::output;
use hairsys_cli::progress::Progress;
use hairsys_cli::quality_text;
use serde_json::json;

/// A Blender-style hair system: guide hairs, mass-spring simulation, MCAP point caches.
#[derive(Parser)]
#[command(name = "hairsys", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Lift the memory and time budgets checked before work (hair points, children × points ×
    /// samples, points × substeps × steps × frames) for a run you know is large.
    #[arg(long, global = true)]
    allow_large: bool,
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
    /// Render children generated on request from the simulation level.
    RenderChildren {
        #[command(subcommand)]
        command: RenderCommand,
    },
    /// Pictures of a run on the CPU: cached frames or sub-frames (or a scene's rest state) with
    /// the scalp and colliders, from camera presets, as one PNG or a contact sheet.
    Preview(Box<PreviewArgs>),
    /// Groom files (guide curves): .hair, .tfx, .obj (polylines), .usda (BasisCurves).
    Groom {
        #[command(subcommand)]
        command: GroomCommand,
    },
    /// Print a shell completion script: `hairsys completions bash > /etc/bash_completion.d/hairsys`.
    Completions {
        /// The shell.
        shell: clap_complete::Shell,
    },
    /// Print the manual page (roff): `hairsys man > hairsys.1; man ./hairsys.1`.
    Man,
    /// Probe a scene for a few frames and choose the cheapest integrator, substeps, segments and
    /// sim-hair count whose error against a converged probe stays within a tolerance.
    Plan {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Largest accepted error (worst frame's RMS position error), e.g. 2mm, 0.5cm, 0.002.
        #[arg(long, value_parser = hairsys_cli::plan::parse_length)]
        tolerance: f32,
        /// Frames to probe FIRST-LAST [default: the scene's first frame and the 12 after it].
        #[arg(long, value_parser = parse_range)]
        frames: Option<(u32, u32)>,
        /// Write the scene with the chosen settings here (comments and layout kept).
        #[arg(long, value_name = "OUT.toml")]
        write: Option<PathBuf>,
        /// Also re-run the chosen scene on the whole groom against the reference, over the
        /// probed frames and over the whole shot (costs two full-groom reference runs).
        #[arg(long)]
        verify: bool,
        /// Instead of planning, the sim-hair study: render hairs interpolated from each of these
        /// sim-hair counts against every strand simulated, with the scene's settings, over
        /// --frames (default: the whole shot), e.g. --levels 50,100,200,500,1000,2000.
        #[arg(long, value_delimiter = ',', value_name = "COUNTS")]
        levels: Vec<usize>,
        /// Print nothing but errors.
        #[arg(long, conflicts_with = "json")]
        quiet: bool,
        /// Print the plan as JSON on stdout.
        #[arg(long)]
        json: bool,
    },
    /// Speed against accuracy: reference cases, the Pareto chart, the stability map.
    Bench {
        /// Small cases and grids: about a minute and a quarter on 2 cores instead of ten minutes.
        #[arg(long)]
        quick: bool,
        /// Directory for pareto.png, stability_map.png, bench.md and bench.json.
        #[arg(long)]
        out: PathBuf,
        /// Print nothing but errors.
        #[arg(long, conflicts_with = "json")]
        quiet: bool,
        /// Print one JSON object per run and the report as JSON on stdout.
        #[arg(long)]
        json: bool,
    },
}

#[derive(Subcommand)]
enum RenderCommand {
    /// Generate children from a cached frame (with motion-blur samples over a shutter) or from the
    /// scene's rest state, and write them as USD BasisCurves or .hair.
    Export(Box<ExportArgs>),
    /// Hair cards of a `model = "strips"` scene (seed 000) from a cached frame (with motion-blur
    /// samples) or the rest state, as a USD Mesh with st or OBJ with vt.
    Cards(Box<hairsys_cli::cards::CardsArgs>),
}

#[derive(clap::Args)]
struct ExportArgs {
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

/// Child settings overriding the scene's `[children]` section (render-children export, cache
/// export --children).
#[derive(clap::Args)]
struct ChildArgs {
    /// Children per parent strand [scene [children] per_parent, else 10].
    #[arg(long, conflicts_with = "count")]
    children_per_parent: Option<u32>,
    /// Total number of children, spread over the parents [scene [children] count].
    #[arg(long)]
    count: Option<u64>,
    /// Simple (around one parent) or interpolated (between parents) children [scene, else simple].
    #[arg(long, value_enum)]
    mode: Option<ChildModeArg>,
    /// Parents blended per interpolated child, 1–8 [scene, else 4].
    #[arg(long)]
    neighbours: Option<u32>,
    /// Display level of detail (the scene's [children] display, else 10 % of the children with
    /// the parents' points) instead of render.
    #[arg(long)]
    display: bool,
    /// Radius of the disc children are rooted in around their parent's root, m [scene, else 0.005].
    #[arg(long)]
    spread: Option<f32>,
    /// Clump factor: 1 draws child tips onto the parent's tip, 0 none [scene, else 0].
    #[arg(long, allow_hyphen_values = true)]
    clump: Option<f32>,
    /// Curl radius, m (0 = no curl) [scene, else 0].
    #[arg(long)]
    curl_radius: Option<f32>,
    /// Curl frequency, turns per meter of hair [scene, else 0].
    #[arg(long)]
    curl_frequency: Option<f32>,
    /// Seed of the children's random values [scene, else 0].
    #[arg(long)]
    seed: Option<u64>,
}

impl ChildArgs {
    /// The overrides given.
    fn overrides(&self) -> ChildOverrides {
        let count = match (self.children_per_parent, self.count) {
            (_, Some(n)) => Some(ChildCount::Total(n)),
            (Some(n), None) => Some(ChildCount::PerParent(n)),
            (None, None) => None,
        };
        ChildOverrides {
            count,
            interpolated: self.mode.map(|m| matches!(m, ChildModeArg::Interpolated)),
            neighbours: self.neighbours,
            spread: self.spread,
            clump: self.clump,
            curl_radius: self.curl_radius,
            curl_frequency: self.curl_frequency,
            seed: self.seed,
        }
    }

    /// The first child option given, as its flag (to refuse it where no children are made).
    fn first_given(&self) -> Option<&'static str> {
        [
            (self.children_per_parent.is_some(), "--children-per-parent"),
            (self.count.is_some(), "--count"),
            (self.mode.is_some(), "--mode"),
            (self.neighbours.is_some(), "--neighbours"),
            (self.display, "--display"),
            (self.spread.is_some(), "--spread"),
            (self.clump.is_some(), "--clump"),
            (self.curl_radius.is_some(), "--curl-radius"),
            (self.curl_frequency.is_some(), "--curl-frequency"),
            (self.seed.is_some(), "--seed"),
        ]
        .into_iter()
        .find_map(|(given, flag)| given.then_some(flag))
    }
}

/// Child distribution.
#[derive(Clone, Copy, ValueEnum)]
enum ChildModeArg {
    /// Grouped around one parent.
    Simple,
    /// Between several parents.
    Interpolated,
}

/// Children output format.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum FormatArg {
    /// USD BasisCurves (.usdc binary or .usda text).
    Usd,
    /// Cem Yuksel's .hair.
    Hair,
}

#[derive(Subcommand)]
enum GroomCommand {
    /// Write a scene's guides (imported and snapped, or generated) to a groom file, e.g. .hair.
    Export {
        /// Scene file with a [guides] section.
        scene: PathBuf,
        /// Output file; the format comes from the extension (.hair, .tfx, .obj, .usda).
        #[arg(short, long)]
        out: PathBuf,
    },
    /// Print a groom file's strands, points, lengths and bounds (in meters, Z up) and the units
    /// they were read in: a USD stage's own `metersPerUnit` and `upAxis`; for files without
    /// units (.hair, .tfx, .obj) 1 m per unit, Z up, unless --scale and --up-axis say otherwise,
    /// with the likely right --scale when the strands come out implausible for hair.
    Info {
        /// Groom file; the format comes from the extension.
        file: PathBuf,
        /// Meters per file unit (the Sintel sample: 0.01), replacing a USD stage's. A given
        /// scale that makes the longest strand shorter than 1 mm or longer than 10 m is refused
        /// as implausible for hair.
        #[arg(long)]
        scale: Option<f32>,
        /// The file's up axis (Y-up files are turned to Z up), replacing a USD stage's
        /// [default: the stage's; z for other files].
        #[arg(long, value_enum)]
        up_axis: Option<UpAxisArg>,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
}

/// Up axis of a file.
#[derive(Clone, Copy, ValueEnum)]
enum UpAxisArg {
    /// Y up (Maya, most exporters); converted to Z up.
    Y,
    /// Z up (Blender).
    Z,
}

#[derive(Subcommand)]
enum SceneCommand {
    /// Print the built-in default scene, every key commented (redirect it to a file to start one).
    Init,
    /// Check a scene file and print everything a run of it will use, without simulating:
    /// strands, frames, the model, the substeps (what "auto" resolves to), the components,
    /// colliders (name, shape, motion), hair–hair, force fields, guides and the budget figures.
    Check {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
}

/// Chunk compression of the cache.
#[derive(Clone, Copy, ValueEnum)]
enum CompressionArg {
    /// No compression: fastest to write and read; simulated hair barely compresses.
    None,
    /// LZ4: about 1 % smaller on moving hair, half the size for still hair; 2.7× slower writes.
    Lz4,
    /// Zstandard: about 9 % smaller on moving hair, slower to write.
    Zstd,
}

impl From<CompressionArg> for Compression {
    fn from(c: CompressionArg) -> Self {
        match c {
            CompressionArg::None => Compression::None,
            CompressionArg::Lz4 => Compression::Lz4,
            CompressionArg::Zstd => Compression::Zstd,
        }
    }
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

/// `println!` through [`output`]: a closed or full stdout ends the command cleanly.
macro_rules! outln {
    ($($arg:tt)*) => {
        output::line(&format!($($arg)*))
    };
}

/// Environment variable choosing the compiled copy of the mass-spring kernel: `baseline` runs
/// the portable copy on any CPU (to compare speeds, or to check on one machine that both copies
/// give the same bits); unset or `auto`, the fastest copy the CPU has.
const KERNEL_ENV: &str = "HAIRSYS_KERNEL";

/// The kernel copy [`KERNEL_ENV`] asks for; an error names the variable, its value and the
/// accepted values.
fn kernel_from_env() -> Result<KernelChoice, String> {
    match std::env::var(KERNEL_ENV) {
        Err(std::env::VarError::NotPresent) => Ok(KernelChoice::Auto),
        Ok(v) if v == "auto" => Ok(KernelChoice::Auto),
        Ok(v) if v == "baseline" => Ok(KernelChoice::Baseline),
        other => Err(format!(
            "{KERNEL_ENV} = {:?}: set it to `baseline` (the portable kernel copy) or `auto` (the \
             fastest copy this CPU runs), or unset it",
            other.unwrap_or_else(|e| e.to_string())
        )),
    }
}

/// Parses `--frames FIRST-LAST`, or `N` as the range of one frame `N-N`.
fn parse_range(s: &str) -> Result<(u32, u32), String> {
    let num = |t: &str| {
        t.trim().parse::<u32>().map_err(|_| {
            format!("`{t}` is not a frame number (whole number ≥ 0); write FIRST-LAST, e.g. 1-48, or one frame N")
        })
    };
    match s.split_once('-') {
        Some((a, b)) => Ok((num(a)?, num(b)?)),
        None => num(s).map(|n| (n, n)),
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let budget = if cli.allow_large {
        Budget::UNLIMITED
    } else {
        Budget::default()
    };
    let kernel = match kernel_from_env() {
        Ok(k) => k,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let code = match cli.command {
        Command::Simulate {
            scene,
            cache,
            frames,
            threads,
            quiet,
            json,
            resume,
            force,
            compression,
            foxglove,
            foxglove_strands,
            quantize,
        } => {
            let foxglove = foxglove || foxglove_strands != 500;
            let writer = WriterOptions {
                compression: compression.into(),
                foxglove: foxglove.then_some(FoxgloveOptions {
                    max_strands: foxglove_strands,
                }),
                precision: if quantize {
                    Precision::Quantized16
                } else {
                    Precision::F32
                },
                ..WriterOptions::default()
            };
            let run = RunArgs {
                scene,
                cache,
                frames,
                threads,
                writer,
                resume,
                force,
                kernel,
                budget,
            };
            run_simulate(run, quiet, json)
        }
        Command::Scene {
            command: SceneCommand::Init,
        } => {
            output::write(DEFAULT_SCENE);
            0
        }
        Command::Scene {
            command: SceneCommand::Check { scene, json },
        } => report(check_scene(&scene, json, budget)),
        Command::Cache {
            command: CacheCommand::Info { file, json },
        } => match hair_cache::summarize(&file) {
            Ok(summary) => {
                if json {
                    outln!(
                        "{}",
                        serde_json::to_string_pretty(&summary).expect("summaries serialise")
                    );
                } else {
                    outln!("{}", file.display());
                    output::block(&summary.to_string());
                }
                0
            }
            Err(e) => {
                eprintln!("error: {e}");
                2
            }
        },
        Command::Cache {
            command:
                CacheCommand::Sample {
                    file,
                    time,
                    linear,
                    out,
                },
        } => report(sample(&file, time, linear, out.as_deref())),
        Command::Cache {
            command: CacheCommand::Recover { broken, fixed },
        } => report(recover(&broken, &fixed)),
        Command::Cache {
            command:
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
                },
        } => report(
            cache_export_options(
                frames,
                shutter,
                motion_samples,
                children,
                &child,
                scene,
                budget,
            )
            .map(|shot| ShotOptions {
                time_offset,
                ..shot
            })
            .and_then(|shot| {
                hairsys_cli::cache_export::run(&file, &out, &shot, quiet, json)
                    .map_err(Failure::input)
            }),
        ),
        Command::RenderChildren {
            command: RenderCommand::Export(args),
        } => report(export_children(*args, budget)),
        Command::RenderChildren {
            command: RenderCommand::Cards(args),
        } => report(hairsys_cli::cards::run(&args).map_err(Failure::from)),
        Command::Preview(args) => report(run_preview(&args)),
        Command::Groom {
            command: GroomCommand::Export { scene, out },
        } => report(export_guides(&scene, &out, budget)),
        Command::Groom {
            command:
                GroomCommand::Info {
                    file,
                    scale,
                    up_axis,
                    json,
                },
        } => report(groom_info(&file, scale, up_axis, json)),
        Command::Completions { shell } => {
            let mut text = Vec::new();
            clap_complete::generate(shell, &mut Cli::command(), "hairsys", &mut text);
            output::write(&String::from_utf8_lossy(&text));
            0
        }
        Command::Man => {
            let mut text = Vec::new();
            match clap_mangen::Man::new(Cli::command()).render(&mut text) {
                Ok(()) => {
                    output::write(&String::from_utf8_lossy(&text));
                    0
                }
                Err(e) => {
                    eprintln!("error: cannot render the manual page ({e})");
                    1
                }
            }
        }
        Command::Plan {
            scene,
            tolerance,
            frames,
            write,
            verify,
            levels,
            quiet,
            json,
        } => report(
            hairsys_cli::plan::run(&hairsys_cli::plan::PlanArgs {
                scene,
                tolerance,
                frames,
                write,
                verify,
                levels,
                json,
                quiet,
                budget,
            })
            .map_err(|(code, message)| Failure { code, message }),
        ),
        Command::Bench {
            quick,
            out,
            quiet,
            json,
        } => report(
            hairsys_cli::bench::cli(&hairsys_cli::bench::BenchOptions {
                quick,
                out,
                json,
                quiet,
            })
            .map_err(Failure::run),
        ),
    };
    ExitCode::from(output::finish(code) as u8)
}

/// What `simulate` was asked to run.
struct RunArgs {
    scene: Option<PathBuf>,
    cache: PathBuf,
    frames: Option<(u32, u32)>,
    threads: Option<usize>,
    writer: WriterOptions,
    resume: bool,
    force: bool,
    kernel: KernelChoice,
    budget: Budget,
}

/// A command's failure with its exit code: 2 for bad input (files, options), 1 for work that
/// failed (writing an output, a run).
struct Failure {
    code: i32,
    message: String,
}

impl Failure {
    /// Bad input (exit code 2).
    fn input(message: impl Into<String>) -> Self {
        Failure {
            code: 2,
            message: message.into(),
        }
    }

    /// Failed work (exit code 1).
    fn run(message: impl Into<String>) -> Self {
        Failure {
            code: 1,
            message: message.into(),
        }
    }
}

impl From<hairsys::Error> for Failure {
    fn from(e: hairsys::Error) -> Self {
        Failure {
            code: e.exit_code(),
            message: e.to_string(),
        }
    }
}

/// Prints an error and gives the exit code (0 done, 1 failed, 2 bad input).
/// Arguments of `preview`.
#[derive(clap::Args)]
struct PreviewArgs {
    /// Cache to draw frames of (its rig places the scalp and colliders as the run saw them).
    #[arg(long)]
    cache: Option<PathBuf>,
    /// Scene file: its rest state, drawn without --cache.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Frames to draw, comma-separated; fractional frames are sub-frame samples (cubic Hermite
    /// with the cached velocities) [default: the cache's first frame].
    #[arg(long, value_delimiter = ',')]
    frames: Vec<f64>,
    /// Camera presets, comma-separated: front, side, back, three-quarter.
    #[arg(long, value_delimiter = ',', default_value = "three-quarter")]
    views: Vec<String>,
    /// Tile width, pixels.
    #[arg(long, default_value_t = 800)]
    width: u32,
    /// Tile height, pixels.
    #[arg(long, default_value_t = 800)]
    height: u32,
    /// Mark points inside colliders and segments stretched beyond --stretch-limit in red.
    #[arg(long)]
    highlight: bool,
    /// Relative elongation --highlight marks (0.01 = 1 %).
    #[arg(long, default_value_t = 0.01)]
    stretch_limit: f32,
    /// Tiles per row of a contact sheet [default: one per view].
    #[arg(long)]
    columns: Option<u32>,
    /// The PNG to write.
    #[arg(short, long)]
    out: PathBuf,
    /// Also measure every frame of --cache and print its quality report: points inside
    /// colliders and the deepest, stretch and compression (p50/p99/max), hairpins, drift from
    /// the groom at the first stepped and the last frame, velocity–position mismatch.
    #[arg(long)]
    report: bool,
    /// Print the summary as JSON.
    #[arg(long)]
    json: bool,
}

/// `preview`: draws the frames and writes the PNG.
fn run_preview(a: &PreviewArgs) -> Result<(), Failure> {
    let views = a
        .views
        .iter()
        .map(|v| {
            hair_render::preview::View::parse(v)
                .map_err(|e| Failure::input(format!("--views {v}: {e}")))
        })
        .collect::<Result<Vec<_>, _>>()?;
    hairsys::output::preview::check_output(&a.out).map_err(Failure::input)?;
    if a.report && a.cache.is_none() {
        return Err(Failure::input(
            "--report measures the frames of a run: give --cache",
        ));
    }
    let opts = hairsys::output::preview::PreviewOptions {
        cache: a.cache.clone(),
        scene: a.scene.clone(),
        frames: a.frames.clone(),
        views,
        width: a.width,
        height: a.height,
        highlight: a.highlight,
        stretch_limit: a.stretch_limit,
        columns: a.columns,
        out: a.out.clone(),
    };
    let summary = hairsys::output::preview::preview(&opts).map_err(Failure::input)?;
    let quality = match (&a.cache, a.report) {
        (Some(cache), true) => {
            Some(hairsys::output::quality::cache_quality(cache).map_err(Failure::input)?)
        }
        _ => None,
    };
    if a.json {
        let mut value = serde_json::to_value(&summary).expect("summaries serialise");
        if let Some(q) = &quality {
            value["quality"] = serde_json::to_value(q).expect("reports serialise");
        }
        output::line(&value.to_string());
    } else {
        output::line(&format!(
            "wrote {}: {} tile(s), {}×{} px, {:.0} ms per tile{}",
            summary.out,
            summary.tiles,
            summary.width,
            summary.height,
            summary.ms_per_tile,
            if a.highlight {
                format!(
                    "; marked {} point(s) inside colliders, {} stretched segment(s)",
                    summary.points_inside, summary.stretched_segments
                )
            } else {
                String::new()
            }
        ));
        if let Some(q) = &quality {
            output::line(&quality_text::describe(q));
        }
    }
    Ok(())
}

fn report(result: Result<(), Failure>) -> i32 {
    match result {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {}", e.message);
            e.code
        }
    }
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
fn export_format(format: Option<FormatArg>, out: &Path) -> Result<Format, Failure> {
    let ext = out
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let from_ext = format_of(out);
    let chosen = match (format, from_ext) {
        (Some(f), Some(e)) if f != e => {
            return Err(Failure::input(format!(
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
            return Err(Failure::input(format!(
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
            return Err(Failure::input(format!(
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

/// `scene check`: builds the scene and its solver and prints what a run will use.
fn check_scene(scene: &Path, json: bool, budget: Budget) -> Result<(), Failure> {
    let sim = SceneFile::load(scene)
        .and_then(|mut s| {
            s.budget = budget;
            s.build()
        })
        .map_err(|e| Failure::input(e.to_string()))?;
    let report = hairsys_cli::scene_check::report(&scene.display().to_string(), &sim, budget)
        .map_err(Failure::input)?;
    if json {
        outln!(
            "{}",
            serde_json::to_string(&report).expect("reports serialise")
        );
    } else {
        output::block(&report.to_string());
    }
    Ok(())
}

/// The options of `cache export`: child options only with `--children`.
fn cache_export_options(
    frames: Option<(u32, u32)>,
    shutter: Option<(f64, f64)>,
    motion_samples: Option<usize>,
    children: bool,
    child: &ChildArgs,
    scene: Option<PathBuf>,
    budget: Budget,
) -> Result<ShotOptions, Failure> {
    if let (false, Some(flag)) = (children, child.first_given()) {
        return Err(Failure::input(format!(
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
    })
}

/// The sub-frame samples of `--shutter OPEN,CLOSE` and `--motion-samples N` (3 by default).
fn shot_shutter(
    shutter: Option<(f64, f64)>,
    samples: Option<usize>,
) -> Result<Option<Shutter>, Failure> {
    let Some((open, close)) = shutter else {
        return Ok(None);
    };
    Shutter::new(open, close, samples.unwrap_or(3))
        .map(Some)
        .map_err(|e| Failure::input(format!("--shutter {open},{close}: {e}")))
}

/// `render-children export`.
fn export_children(a: ExportArgs, budget: Budget) -> Result<(), Failure> {
    let format = export_format(a.format, &a.out)?;
    let motion_samples = match (a.motion_samples, a.shutter) {
        (Some(n), _) => n,
        (None, Some(_)) => 3,
        (None, None) => 1,
    };
    if let (Some(frames), Some(cache)) = (a.frames, &a.cache) {
        if format != Format::Usd {
            return Err(Failure::input(
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
        };
        return hairsys_cli::cache_export::run(cache, &a.out, &shot, a.quiet, a.json)
            .map_err(Failure::input);
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

/// `groom export`: a scene's guides, in world space at rest, to a groom file.
fn export_guides(scene: &Path, out: &Path, budget: Budget) -> Result<(), Failure> {
    let sim = SceneFile::load(scene)
        .and_then(|mut s| {
            s.budget = budget;
            s.build()
        })
        .map_err(|e| Failure::input(e.to_string()))?;
    let (Some(mesh), false) = (sim.rest_mesh(), sim.guides.is_empty()) else {
        return Err(Failure::input(format!(
            "{}: the scene has no [guides] to export",
            scene.display()
        )));
    };
    let groom = hair_groom::guides_to_groom(mesh, &sim.guides)
        .map_err(|e| Failure::input(format!("{}: {e}", scene.display())))?;
    let opts = hair_groom::ImportOptions {
        scale: 1.0,
        up_axis: hair_groom::UpAxis::Z,
    };
    hair_groom::write_groom(out, &groom, &opts).map_err(|e| Failure::run(e.to_string()))?;
    outln!(
        "wrote {}: {} guides, {} points (meters, Z up)",
        out.display(),
        groom.len(),
        groom.point_count()
    );
    Ok(())
}

/// `groom info`: a groom file's summary, with the units it was read in.
fn groom_info(
    file: &Path,
    scale: Option<f32>,
    up_axis: Option<UpAxisArg>,
    json: bool,
) -> Result<(), Failure> {
    let up = up_axis.map(|a| match a {
        UpAxisArg::Y => hair_groom::UpAxis::Y,
        UpAxisArg::Z => hair_groom::UpAxis::Z,
    });
    let named = |e: hair_groom::GroomError| {
        let e = e.to_string();
        // Name the file even when the reader's message does not.
        let name = file.display().to_string();
        Failure::input(if e.contains(&name) {
            e
        } else {
            format!("{name}: {e}")
        })
    };
    let is_usd = matches!(
        hair_groom::GroomFormat::of(file),
        Ok(hair_groom::GroomFormat::Usd)
    );
    let (groom, units) = if is_usd {
        // The stage's own units, replaced only where a flag is given.
        let stage =
            hair_groom::read_usd(file, &hair_groom::UsdReadOptions::default()).map_err(named)?;
        if scale.is_none() && up.is_none() {
            let units = Units {
                meters_per_unit: stage.meters_per_unit,
                up_axis: stage.up_axis,
                source: "the stage's metersPerUnit and upAxis",
            };
            (stage.groom, units)
        } else {
            let opts = hair_groom::ImportOptions {
                scale: scale.unwrap_or(stage.meters_per_unit as f32),
                up_axis: up.unwrap_or(stage.up_axis),
            };
            let groom = hair_groom::read_groom(file, &opts).map_err(named)?;
            let units = Units {
                meters_per_unit: f64::from(opts.scale),
                up_axis: opts.up_axis,
                source: "--scale and --up-axis over the stage's",
            };
            (groom, units)
        }
    } else {
        let opts = hair_groom::ImportOptions {
            scale: scale.unwrap_or(1.0),
            up_axis: up.unwrap_or(hair_groom::UpAxis::Z),
        };
        let groom = hair_groom::read_groom(file, &opts).map_err(named)?;
        let source = match scale {
            Some(_) => "--scale and --up-axis",
            None => "assumed: the file has no units",
        };
        let units = Units {
            meters_per_unit: f64::from(opts.scale),
            up_axis: opts.up_axis,
            source,
        };
        (groom, units)
    };
    let info = hair_groom::groom_info(&groom);
    // A scale the user gave is a claim to check; an assumed one is only reported on.
    if let Some(scale) = scale {
        check_scale(file, scale, info.length_max).map_err(Failure::input)?;
    }
    let likely = likely_scale(units.meters_per_unit, info.length_max);
    let up_name = match units.up_axis {
        hair_groom::UpAxis::Y => "y",
        hair_groom::UpAxis::Z => "z",
    };
    if json {
        let (lo, hi) = info.bounds;
        let doc = json!({
            "file": file.display().to_string(),
            "strands": info.strands,
            "points": info.points,
            "points_per_strand": [info.points_min, info.points_max],
            "length_m": { "min": info.length_min, "mean": info.length_mean, "max": info.length_max },
            "bounds_m": [[lo.x, lo.y, lo.z], [hi.x, hi.y, hi.z]],
            "units": {
                "meters_per_unit": units.meters_per_unit,
                "up_axis": up_name,
                "source": units.source,
                "plausible": likely.is_none(),
                "likely_scale": likely,
            },
        });
        outln!(
            "{}",
            serde_json::to_string_pretty(&doc).expect("summaries serialise")
        );
    } else {
        outln!("{}", file.display());
        outln!("{}", info.to_string().trim_end());
        outln!(
            "units    {} m per unit, {} up ({})",
            units.meters_per_unit,
            up_name.to_uppercase(),
            units.source
        );
        if let Some(s) = likely {
            outln!(
                "note     the longest strand is {:.3e} m, implausible for hair (1 mm – 10 m): \
                 the file's units are likely {s:e} m (read it with --scale {s:e})",
                info.length_max
            );
        }
    }
    Ok(())
}

/// The units a groom was read in, and where they came from.
struct Units {
    /// Meters per file unit.
    meters_per_unit: f64,
    /// The up axis converted from.
    up_axis: hair_groom::UpAxis,
    /// Where they came from, in words.
    source: &'static str,
}

/// The meters per unit (a power of ten times `scale`) that make the longest strand about 30 cm,
/// when at `scale` it (`longest`, m) is implausible for hair; `None` when it is plausible.
fn likely_scale(scale: f64, longest: f64) -> Option<f64> {
    let (lo, hi) = PLAUSIBLE_LONGEST_STRAND;
    if (lo..=hi).contains(&longest) || !(longest > 0.0 && longest.is_finite()) {
        return None;
    }
    let decades = (longest / 0.3).log10().round() as i32;
    Some(scale * 10f64.powi(-decades))
}

/// Shortest and longest plausible length of the longest strand of a groom, m: from stubble
/// (1 mm) to far beyond floor-length hair (10 m). A longest strand outside this range means the
/// `--scale` is off, by far more than any real groom differs (1e12 or 1e-12 still give finite
/// coordinates, so nothing else catches it).
const PLAUSIBLE_LONGEST_STRAND: (f64, f64) = (1e-3, 10.0);

/// Refuses a `--scale` that makes the longest strand (`longest`, m after scaling) implausible
/// for hair, naming the flag, the length and the scale that would make it about 30 cm.
fn check_scale(file: &Path, scale: f32, longest: f64) -> Result<(), String> {
    let (lo, hi) = PLAUSIBLE_LONGEST_STRAND;
    if (lo..=hi).contains(&longest) {
        return Ok(());
    }
    let hint = match likely_scale(f64::from(scale), longest) {
        Some(s) => {
            let decades = (f64::from(scale) / s).log10().round() as i32;
            format!("; the file's units are likely off by 10^{decades}: try --scale {s:.0e}")
        }
        None => String::new(),
    };
    Err(format!(
        "{}: --scale {scale:e} makes the longest strand {longest:e} m, outside the {lo} m – \
         {hi} m of real hair; give --scale in meters per file unit (1 for meters, 0.01 for \
         centimetres){hint}",
        file.display()
    ))
}

/// `cache sample`: positions at `time` as JSON.
fn sample(file: &Path, time: f64, linear: bool, out: Option<&Path>) -> Result<(), Failure> {
    let mut reader = CacheReader::open(file).map_err(|e| Failure::input(e.to_string()))?;
    let interpolation = if linear {
        Interpolation::Linear
    } else {
        Interpolation::Hermite
    };
    let (a, b) = reader
        .frames_around(time)
        .map_err(|e| Failure::input(e.to_string()))?;
    let sample = reader
        .sample(time, interpolation)
        .map_err(|e| Failure::input(e.to_string()))?;
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
            Failure::run(format!(
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
fn recover(broken: &Path, fixed: &Path) -> Result<(), Failure> {
    if same_file(broken, fixed) {
        return Err(Failure::input(format!(
            "cache recover {} {}: both name the same file; write the recovered cache to another \
             path (recovering over the input would destroy it)",
            broken.display(),
            fixed.display()
        )));
    }
    let recovery = hair_cache::recover(broken).map_err(|e| Failure::input(e.to_string()))?;
    if recovery.frames.is_empty() {
        return Err(Failure::input(format!(
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
        .map_err(|e| Failure::run(e.to_string()))?;
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

/// Refuses to start a run over a complete cache or a killed run's `.partial` without `--force`.
fn check_overwrite(cache: &Path, resume: bool, force: bool) -> Result<(), String> {
    if resume || force {
        return Ok(());
    }
    if cache.exists() {
        return Err(format!(
            "{} already exists; give --force to replace it, or another --cache path",
            cache.display()
        ));
    }
    if let Ok(partial) = hair_cache::partial_path(cache) {
        if partial.exists() {
            return Err(format!(
                "{} is left by a run that was killed (or is still running): continue it with \
                 --resume, keep its frames with `hairsys cache recover {} FIXED.mcap`, or \
                 discard it with --force",
                partial.display(),
                partial.display()
            ));
        }
    }
    Ok(())
}

fn run_simulate(run: RunArgs, quiet: bool, json: bool) -> i32 {
    if let Err(e) = check_overwrite(&run.cache, run.resume, run.force) {
        eprintln!("error: {e}");
        return 2;
    }
    let scene = match run.scene {
        Some(path) => match SceneFile::load(&path) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("error: {e}");
                return 2;
            }
        },
        None => SceneFile::builtin_default(),
    };
    let mut scene = scene;
    scene.budget = run.budget;
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
        cache: run.cache,
        frames,
        threads: run.threads,
        writer: run.writer,
        resume: run.resume,
        kernel: run.kernel,
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
        }))
    });
    progress.finish();
    match result {
        Ok(summary) => {
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
            0
        }
        Err(e) => {
            eprintln!("error: {e}");
            e.exit_code()
        }
    }
}
