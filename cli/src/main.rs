//! `hairsys`: simulate hair scenes into MCAP point caches, and make what a shot needs from them.
//!
//! This crate is the command only: argument handling (one module per subcommand under
//! `commands/`), progress, printing, and the exit codes ([`error`]). The work is the `hairsys`
//! library's; the bench is the `hairsys-bench` crate's.

use std::process::ExitCode;

use clap::{CommandFactory, Parser, Subcommand};
use hair_core::KernelChoice;
use hairsys::budget::Budget;

/// `println!` through [`output`]: a closed or full stdout ends the command cleanly.
macro_rules! outln {
    ($($arg:tt)*) => {
        $crate::output::line(&format!($($arg)*))
    };
}

mod args;
mod commands;
mod error;
mod output;
mod progress;
mod quality_text;

use commands::{bench, cache, farm, groom, plan, preview, render_children, scene, shot, simulate};
use error::CliError;

/// A Blender-style hair system: guide hairs, mass-spring simulation, MCAP point caches.
#[derive(Parser)]
#[command(name = "hairsys", version, long_about = None)]
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
    Simulate(simulate::SimulateArgs),
    /// Scene files.
    Scene {
        #[command(subcommand)]
        command: scene::SceneCommand,
    },
    /// Point caches.
    Cache {
        #[command(subcommand)]
        command: cache::CacheCommand,
    },
    /// Render children generated on request from the simulation level.
    RenderChildren {
        #[command(subcommand)]
        command: render_children::RenderCommand,
    },
    /// Pictures of a run on the CPU: cached frames or sub-frames (or a scene's rest state) with
    /// the scalp and colliders, from camera presets, as one PNG or a contact sheet.
    Preview(Box<preview::PreviewArgs>),
    /// Groom files (guide curves): .hair, .tfx, .obj (polylines), .usda (BasisCurves).
    Groom {
        #[command(subcommand)]
        command: groom::GroomCommand,
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
    Plan(plan::PlanArgs),
    /// Speed against accuracy: reference cases, the Pareto chart, the stability map.
    Bench(bench::BenchArgs),
    /// Shot files: several characters, one frame range, what to make of them.
    Shot {
        #[command(subcommand)]
        command: shot::ShotCommand,
    },
    /// A shot on a render farm: an Open Job Description job bundle, and the commands its tasks
    /// run.
    Farm {
        #[command(subcommand)]
        command: farm::FarmCommand,
    },
}

/// What every command may need beside its own arguments.
pub struct Context {
    /// Memory and time budgets checked before work (`--allow-large` lifts them).
    pub budget: Budget,
    /// The compiled copy of the strand kernel (`HAIRSYS_KERNEL`).
    pub kernel: KernelChoice,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = args::kernel_from_env().and_then(|kernel| {
        let ctx = Context {
            budget: if cli.allow_large {
                Budget::UNLIMITED
            } else {
                Budget::default()
            },
            kernel,
        };
        run(cli.command, &ctx)
    });
    let code = match result {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {e}");
            e.exit_code()
        }
    };
    ExitCode::from(output::finish(code))
}

/// Runs one command.
fn run(command: Command, ctx: &Context) -> Result<(), CliError> {
    match command {
        Command::Simulate(args) => simulate::run(args, ctx),
        Command::Scene { command } => scene::run(command, ctx),
        Command::Cache { command } => cache::run(command, ctx),
        Command::RenderChildren { command } => render_children::run(command, ctx),
        Command::Preview(args) => preview::run(&args),
        Command::Groom { command } => groom::run(command, ctx),
        Command::Completions { shell } => {
            let mut text = Vec::new();
            clap_complete::generate(shell, &mut Cli::command(), "hairsys", &mut text);
            output::write(&String::from_utf8_lossy(&text));
            Ok(())
        }
        Command::Man => {
            let mut text = Vec::new();
            clap_mangen::Man::new(Cli::command())
                .render(&mut text)
                .map_err(|e| CliError::failed(format!("cannot render the manual page ({e})")))?;
            output::write(&String::from_utf8_lossy(&text));
            Ok(())
        }
        Command::Plan(args) => plan::run(&args, ctx),
        Command::Bench(args) => bench::run(&args),
        Command::Shot { command } => shot::run(command, ctx),
        Command::Farm { command } => farm::run(command, ctx),
    }
}
