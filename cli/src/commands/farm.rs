//! `hairsys farm`: a shot as an Open Job Description job bundle (`farm job`), and the three
//! task commands its steps run (`farm simulate`, `farm export`, `farm assemble`; see
//! [`hairsys::farm`]).

use std::path::PathBuf;

use clap::Subcommand;
use hairsys::farm::assemble::assemble;
use hairsys::farm::job::{write_job, JobOptions};
use hairsys::farm::task::{export_chunk, simulate_character, SimulateTask, Start};
use hairsys::farm::{check_digest, OutputLayout, DEFAULT_CHUNK_SIZE};
use hairsys::shot::ShotFile;
use serde_json::json;

use crate::args::parse_range;
use crate::error::CliError;
use crate::progress::Progress;
use crate::{output, Context};

/// Options every task command takes.
#[derive(clap::Args)]
pub struct TaskArgs {
    /// Shot file (TOML).
    shot: PathBuf,
    /// The job's output folder.
    #[arg(long)]
    out_dir: PathBuf,
    /// The shot's SHA-256 (hex, or its first 12 digits or more) the job was written from: a
    /// shot file that changed since is refused.
    #[arg(long, value_name = "HEX")]
    shot_digest: Option<String>,
    /// Print nothing but errors.
    #[arg(long, conflicts_with = "json")]
    quiet: bool,
    /// Print a JSON summary on stdout.
    #[arg(long)]
    json: bool,
}

impl TaskArgs {
    /// The shot, checked against the job's digest.
    fn shot(&self) -> Result<ShotFile, CliError> {
        let shot = ShotFile::load(&self.shot)?;
        check_digest(&shot, self.shot_digest.as_deref())?;
        Ok(shot)
    }
}

#[derive(Subcommand)]
pub enum FarmCommand {
    /// Write the Open Job Description job bundle of a shot into a folder: template.yaml
    /// (Simulate per character, Export per frame chunk, Assemble), parameter_values.yaml,
    /// asset_references.yaml (for `deadline bundle submit DIR`) and commands.txt (every task as
    /// one command line, for other farm managers).
    Job {
        /// Shot file (TOML).
        shot: PathBuf,
        /// The bundle folder to write (created if needed).
        #[arg(short, long)]
        out: PathBuf,
        /// Where the job's tasks write (the OutputDir job parameter) [the shot's folder/out].
        #[arg(long)]
        output_dir: Option<PathBuf>,
        /// Frames per Export task (the ChunkSize job parameter), 1–150.
        #[arg(long, default_value_t = DEFAULT_CHUNK_SIZE)]
        chunk_size: u32,
        /// The command that runs hairsys on a worker (the Hairsys job parameter) [hairsys].
        #[arg(long, default_value = "hairsys")]
        hairsys: String,
        /// Print nothing but errors.
        #[arg(long, conflicts_with = "json")]
        quiet: bool,
        /// Print a JSON summary on stdout.
        #[arg(long)]
        json: bool,
    },
    /// The Simulate task: one character over the shot's frames into OUT/NAME/NAME.mcap. Keeps a
    /// complete cache of the same scene and frames, continues a killed attempt's .partial
    /// (as `simulate --resume`), and starts over otherwise.
    Simulate {
        #[command(flatten)]
        task: TaskArgs,
        /// The character (its `name` in the shot).
        #[arg(long)]
        character: String,
        /// Worker threads (default: all cores); results do not depend on the count.
        #[arg(long)]
        threads: Option<usize>,
    },
    /// The Export task: frames FIRST-LAST of one character from its cache into
    /// OUT/NAME/chunks/NAME.FIRST-LAST.usdc, written atomically.
    Export {
        #[command(flatten)]
        task: TaskArgs,
        /// The character (its `name` in the shot).
        #[arg(long)]
        character: String,
        /// The frames FIRST-LAST of this chunk (inside the shot's).
        #[arg(long, value_parser = parse_range)]
        frames: (u32, u32),
    },
    /// The Assemble task: per character a layer stitching its chunks by USD value clips
    /// (OUT/NAME/NAME.usda), and OUT/shot.usda referencing every character.
    Assemble {
        #[command(flatten)]
        task: TaskArgs,
    },
}

/// Runs a `farm` command.
pub fn run(command: FarmCommand, ctx: &Context) -> Result<(), CliError> {
    match command {
        FarmCommand::Job {
            shot,
            out,
            output_dir,
            chunk_size,
            hairsys,
            quiet,
            json,
        } => {
            let file = ShotFile::load(&shot)?;
            let output_dir = output_dir.unwrap_or_else(|| {
                shot.parent()
                    .map(|p| p.join("out"))
                    .unwrap_or_else(|| PathBuf::from("out"))
            });
            let s = write_job(
                &file,
                &out,
                &JobOptions {
                    chunk_size,
                    output_dir,
                    hairsys,
                },
            )?;
            if json {
                outln!(
                    "{}",
                    serde_json::to_string(&s).expect("summaries serialise")
                );
            } else if !quiet {
                let tasks: Vec<String> = s.tasks.iter().map(|(k, n)| format!("{k} {n}")).collect();
                outln!(
                    "wrote {} ({}): tasks {} with {} frames per export; output {}",
                    s.bundle.display(),
                    s.name,
                    tasks.join(", "),
                    s.chunk_size,
                    s.output_dir.display()
                );
                outln!(
                    "run it: deadline bundle submit {}   (or openjd run {}/template.yaml --step \
                     Simulate, then Export, then Assemble; or the lines of commands.txt)",
                    s.bundle.display(),
                    s.bundle.display()
                );
            }
            Ok(())
        }
        FarmCommand::Simulate {
            task,
            character,
            threads,
        } => {
            let shot = task.shot()?;
            let (first, last) = shot.frames();
            let progress = Progress::new(
                u64::from(last - first) + 1,
                task.quiet,
                task.json,
                "simulating",
            );
            let layout = OutputLayout::new(&task.out_dir);
            let opts = SimulateTask {
                threads,
                kernel: ctx.kernel,
                budget: ctx.budget,
                quality: !task.quiet,
            };
            let outcome = simulate_character(&shot, &character, &layout, &opts, |r| {
                let written = u64::from(r.frame.saturating_sub(first)) + 1;
                progress.frame_written(
                    r.frame,
                    written,
                    &json!({"event": "frame", "character": character, "frame": r.frame}),
                )
            });
            progress.finish();
            let outcome = outcome?;
            if task.json {
                outln!("{}", json!({ "event": "done", "outcome": outcome }));
            } else if !task.quiet {
                let how = match &outcome.start {
                    Start::Fresh => "simulated".to_string(),
                    Start::Resumed { from } => format!("resumed from frame {from}"),
                    Start::Complete => "already complete, kept".to_string(),
                    Start::Replaced { reason } => format!("simulated anew ({reason})"),
                };
                outln!("{}: {} {how}", outcome.character, outcome.cache.display());
                if let Some(summary) = &outcome.summary {
                    output::block(&summary.to_string());
                }
            }
            Ok(())
        }
        FarmCommand::Export {
            task,
            character,
            frames,
        } => {
            let shot = task.shot()?;
            let layout = OutputLayout::new(&task.out_dir);
            let outcome = export_chunk(&shot, &character, frames, &layout, ctx.budget)?;
            if task.json {
                outln!(
                    "{}",
                    serde_json::to_string(&outcome).expect("summaries serialise")
                );
            } else if !task.quiet {
                let s = &outcome.summary;
                outln!(
                    "wrote {}: frames {}–{} ({} time samples), {} {} curves, {} points",
                    outcome.path.display(),
                    s.frames.0,
                    s.frames.1,
                    s.time_samples,
                    s.curves,
                    s.prim,
                    s.points
                );
                for stale in &outcome.removed {
                    outln!("deleted the stale chunk {}", stale.display());
                }
            }
            Ok(())
        }
        FarmCommand::Assemble { task } => {
            let shot = task.shot()?;
            let layout = OutputLayout::new(&task.out_dir);
            let s = assemble(&shot, &layout)?;
            if task.json {
                outln!(
                    "{}",
                    serde_json::to_string(&s).expect("summaries serialise")
                );
            } else if !task.quiet {
                for c in &s.characters {
                    outln!(
                        "wrote {}: {} chunk(s) as value clips of {}",
                        c.path.display(),
                        c.chunks.len(),
                        c.prims.join(", ")
                    );
                }
                outln!(
                    "wrote {}: {} character(s), time codes {}–{}",
                    s.stage.display(),
                    s.characters.len(),
                    s.time_codes.0,
                    s.time_codes.1
                );
            }
            Ok(())
        }
    }
}
