//! `hairsys`: simulate hair scenes into MCAP point caches.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use hair_cache::foxglove::FoxgloveOptions;
use hair_cache::{CacheReader, Compression, Interpolation, Precision, WriterOptions};
use hair_core::KernelChoice;
use hair_render::ChildCount;
use hairsys::children::{export, parse_shutter, ChildOverrides, ExportOptions, Format};
use hairsys::run::{simulate, SimulateOptions};
use hairsys::scene::{SceneFile, DEFAULT_SCENE};
use hairsys_cli::progress::Progress;
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
        /// Continue the interrupted run left in CACHE.partial from its last complete frame.
        #[arg(long)]
        resume: bool,
        /// Cache chunk compression.
        #[arg(long, value_enum, default_value_t = CompressionArg::None)]
        compression: CompressionArg,
        /// Store positions and velocities quantized to 16 bits over each frame's bounds: half the
        /// size, error at most (extent)/131070 per axis (about 23 µm over 3 m).
        #[arg(long)]
        quantize: bool,
        /// Also write a foxglove.SceneUpdate channel showing up to N strands per frame (default 500),
        /// to scrub the run in Foxglove.
        #[arg(long, value_name = "N", num_args = 0..=1, default_missing_value = "500")]
        foxglove: Option<usize>,
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
    /// Render children generated on request from the simulation level.
    RenderChildren {
        #[command(subcommand)]
        command: RenderCommand,
    },
    /// Groom files (guide curves): .hair, .tfx, .obj (polylines), .usda (BasisCurves).
    Groom {
        #[command(subcommand)]
        command: GroomCommand,
    },
    /// Speed against accuracy: reference cases, the Pareto chart, the stability map.
    Bench {
        /// Small cases and grids (seconds instead of minutes).
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
    /// Cache to read (the scene stored in it gives the roots); without it, the rest state.
    #[arg(long)]
    cache: Option<PathBuf>,
    /// Scene file: the rest state to export without --cache, or a scene overriding the cache's.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Frame to export (with --cache).
    #[arg(long)]
    frame: Option<u32>,
    /// Shutter interval OPEN,CLOSE in frames around the frame.
    #[arg(long, value_parser = parse_shutter, default_value = "-0.25,0.25", allow_hyphen_values = true)]
    shutter: (f64, f64),
    /// Motion samples over the shutter (USD time samples); 1 = no motion blur.
    #[arg(long, default_value_t = 1)]
    motion_samples: usize,
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
    /// Output format.
    #[arg(long, value_enum, default_value_t = FormatArg::Usd)]
    format: FormatArg,
    /// Output file (.usda for usd, .hair for hair).
    #[arg(short, long)]
    out: PathBuf,
    /// Print nothing but errors.
    #[arg(long, conflicts_with = "json")]
    quiet: bool,
    /// Print a JSON summary on stdout.
    #[arg(long)]
    json: bool,
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
#[derive(Clone, Copy, ValueEnum)]
enum FormatArg {
    /// USD BasisCurves (.usda).
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
    /// Print a groom file's strands, points, lengths and bounds (in meters, Z up, after --scale
    /// and --up-axis).
    Info {
        /// Groom file; the format comes from the extension.
        file: PathBuf,
        /// Meters per file unit (the Sintel sample: 0.01).
        #[arg(long, default_value_t = 1.0)]
        scale: f32,
        /// The file's up axis; Y-up files are turned to Z up.
        #[arg(long, value_enum, default_value_t = UpAxisArg::Z)]
        up_axis: UpAxisArg,
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
    /// Check a scene file and print what it builds, without simulating.
    Check {
        /// Scene file (TOML).
        scene: PathBuf,
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
    /// Recover every complete frame of a broken cache (e.g. the CACHE.partial of a killed run)
    /// into a complete cache, and say what was lost.
    Recover {
        /// The broken cache.
        broken: PathBuf,
        /// Where to write the recovered, complete cache.
        fixed: PathBuf,
    },
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
            compression,
            foxglove,
            quantize,
        } => {
            let writer = WriterOptions {
                compression: compression.into(),
                foxglove: foxglove.map(|max_strands| FoxgloveOptions { max_strands }),
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
                kernel,
            };
            run_simulate(run, quiet, json)
        }
        Command::Scene {
            command: SceneCommand::Init,
        } => {
            emit(DEFAULT_SCENE);
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
                if sim.model == hair_core::StrandModel::Rod {
                    println!(
                        "  model: {} (a = {} m, b/a = {}, E = {} Pa)",
                        sim.model.name(),
                        sim.rod.semi_major_axis,
                        sim.rod.axis_ratio,
                        sim.rod.youngs_modulus
                    );
                }
                if let Some(guides) = &sim.guides_report {
                    println!("  guides: {guides}");
                }
                if let Some(h) = &sim.hair_hair {
                    println!(
                        "  hair-hair: {} m cells, friction {}, repulsion {} m²/s² above volume fraction {}",
                        h.cell_size, h.friction, h.repulsion, h.target_density
                    );
                }
                if !sim.fields.is_empty() {
                    println!("  force fields: {}", sim.fields.len());
                }
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
        Command::RenderChildren {
            command: RenderCommand::Export(args),
        } => report(export_children(*args)),
        Command::RenderChildren {
            command: RenderCommand::Cards(args),
        } => report(hairsys_cli::cards::run(&args)),
        Command::Groom {
            command: GroomCommand::Export { scene, out },
        } => report(export_guides(&scene, &out)),
        Command::Groom {
            command:
                GroomCommand::Info {
                    file,
                    scale,
                    up_axis,
                    json,
                },
        } => report(groom_info(&file, scale, up_axis, json)),
        Command::Bench {
            quick,
            out,
            quiet,
            json,
        } => report(hairsys_cli::bench::cli(&hairsys_cli::bench::BenchOptions {
            quick,
            out,
            json,
            quiet,
        })),
    };
    ExitCode::from(code as u8)
}

/// What `simulate` was asked to run.
struct RunArgs {
    scene: Option<PathBuf>,
    cache: PathBuf,
    frames: Option<(u32, u32)>,
    threads: Option<usize>,
    writer: WriterOptions,
    resume: bool,
    kernel: KernelChoice,
}

/// Writes `text` to stdout; a reader that closed the pipe early (`| head`) is not an error.
fn emit(text: &str) {
    use std::io::Write;
    match std::io::stdout().lock().write_all(text.as_bytes()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            eprintln!("error: cannot write to stdout ({e})")
        }
        _ => {}
    }
}

/// Prints an error and gives the exit code (0 done, 1 failed).
fn report(result: Result<(), String>) -> i32 {
    match result {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {e}");
            1
        }
    }
}

/// `render-children export`.
fn export_children(a: ExportArgs) -> Result<(), String> {
    let count = match (a.children_per_parent, a.count) {
        (_, Some(n)) => Some(ChildCount::Total(n)),
        (Some(n), None) => Some(ChildCount::PerParent(n)),
        (None, None) => None,
    };
    let opts = ExportOptions {
        cache: a.cache,
        scene: a.scene,
        frame: a.frame,
        shutter: a.shutter,
        motion_samples: a.motion_samples,
        children: ChildOverrides {
            count,
            interpolated: a.mode.map(|m| matches!(m, ChildModeArg::Interpolated)),
            neighbours: a.neighbours,
            spread: a.spread,
            clump: a.clump,
            curl_radius: a.curl_radius,
            curl_frequency: a.curl_frequency,
            seed: a.seed,
        },
        display: a.display,
        format: match a.format {
            FormatArg::Usd => Format::Usd,
            FormatArg::Hair => Format::Hair,
        },
        out: a.out,
    };
    let progress = Progress::new(opts.motion_samples as u64, a.quiet, false, "children");
    let summary = export(&opts, || progress.tick(&()));
    progress.finish();
    let summary = summary?;
    if a.json {
        println!(
            "{}",
            serde_json::to_string(&summary).expect("summaries serialise")
        );
    } else if !a.quiet {
        println!(
            "wrote {}: {} children, {} points, {} time sample(s)",
            summary.out, summary.curves, summary.points, summary.time_samples
        );
    }
    Ok(())
}

/// `groom export`: a scene's guides, in world space at rest, to a groom file.
fn export_guides(scene: &Path, out: &Path) -> Result<(), String> {
    let sim = SceneFile::load(scene)
        .and_then(|s| s.build())
        .map_err(|e| e.to_string())?;
    let (Some(mesh), false) = (sim.rest_mesh(), sim.guides.is_empty()) else {
        return Err(format!(
            "{}: the scene has no [guides] to export",
            scene.display()
        ));
    };
    let groom = hair_groom::guides_to_groom(mesh, &sim.guides).map_err(|e| e.to_string())?;
    let opts = hair_groom::ImportOptions {
        scale: 1.0,
        up_axis: hair_groom::UpAxis::Z,
    };
    hair_groom::write_groom(out, &groom, &opts).map_err(|e| e.to_string())?;
    println!(
        "wrote {}: {} guides, {} points (meters, Z up)",
        out.display(),
        groom.len(),
        groom.point_count()
    );
    Ok(())
}

/// `groom info`: a groom file's summary.
fn groom_info(file: &Path, scale: f32, up_axis: UpAxisArg, json: bool) -> Result<(), String> {
    let up_axis = match up_axis {
        UpAxisArg::Y => hair_groom::UpAxis::Y,
        UpAxisArg::Z => hair_groom::UpAxis::Z,
    };
    let groom = hair_groom::read_groom(file, &hair_groom::ImportOptions { scale, up_axis })
        .map_err(|e| e.to_string())?;
    let info = hair_groom::groom_info(&groom);
    if json {
        let (lo, hi) = info.bounds;
        let doc = json!({
            "file": file.display().to_string(),
            "strands": info.strands,
            "points": info.points,
            "points_per_strand": [info.points_min, info.points_max],
            "length_m": { "min": info.length_min, "mean": info.length_mean, "max": info.length_max },
            "bounds_m": [[lo.x, lo.y, lo.z], [hi.x, hi.y, hi.z]],
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&doc).expect("summaries serialise")
        );
    } else {
        println!("{}", file.display());
        println!("{info}");
    }
    Ok(())
}

/// `cache sample`: positions at `time` as JSON.
fn sample(file: &Path, time: f64, linear: bool, out: Option<&Path>) -> Result<(), String> {
    let mut reader = CacheReader::open(file).map_err(|e| e.to_string())?;
    let interpolation = if linear {
        Interpolation::Linear
    } else {
        Interpolation::Hermite
    };
    let (a, b) = reader.frames_around(time).map_err(|e| e.to_string())?;
    let sample = reader
        .sample(time, interpolation)
        .map_err(|e| e.to_string())?;
    let doc = json!({
        "file": file.display().to_string(),
        "time": sample.time,
        "between_frames": [a, b],
        "interpolation": if linear { "linear" } else { "hermite" },
        "points": sample.positions.len(),
        "positions": sample.positions.iter().map(|p| [p.x, p.y, p.z]).collect::<Vec<_>>(),
        "velocities": sample.velocities.iter().map(|v| [v.x, v.y, v.z]).collect::<Vec<_>>(),
    });
    let text = serde_json::to_string(&doc).expect("samples serialise");
    match out {
        Some(path) => std::fs::write(path, text + "\n").map_err(|e| {
            format!(
                "{}: cannot write the sample ({e}); check the directory",
                path.display()
            )
        }),
        None => {
            emit(&(text + "\n"));
            Ok(())
        }
    }
}

/// `cache recover`: every complete frame of `broken` into a complete cache at `fixed`.
fn recover(broken: &Path, fixed: &Path) -> Result<(), String> {
    let recovery = hair_cache::recover(broken).map_err(|e| e.to_string())?;
    if recovery.frames.is_empty() {
        return Err(format!(
            "{}: no complete frame to recover",
            broken.display()
        ));
    }
    match &recovery.warning {
        Some(w) => eprintln!("warning: {}: {w}", broken.display()),
        None => eprintln!("{}: every frame was complete", broken.display()),
    }
    let summary = recovery
        .write(fixed, WriterOptions::default())
        .map_err(|e| e.to_string())?;
    println!("wrote {}", fixed.display());
    print!("{summary}");
    Ok(())
}

fn run_simulate(run: RunArgs, quiet: bool, json: bool) -> i32 {
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
    let frames = run.frames;
    let [first, last] = scene.scene.scene.frames;
    let (first, last) = frames.unwrap_or((first, last));
    let progress = Progress::new(last.saturating_sub(first) as u64, quiet, json, "simulating");
    let opts = SimulateOptions {
        scene,
        cache: run.cache,
        frames,
        threads: run.threads,
        writer: run.writer,
        resume: run.resume,
        kernel: run.kernel,
    };
    let result = simulate(&opts, |r| {
        progress.tick(&json!({
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
