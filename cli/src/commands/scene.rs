//! `hairsys scene`: print the built-in default scene; check a scene file and print what a run
//! of it will use.

use std::path::{Path, PathBuf};

use clap::Subcommand;
use hairsys::budget::Budget;
use hairsys::scene::{SceneFile, DEFAULT_SCENE};

use crate::error::CliError;
use crate::{output, Context};

#[derive(Subcommand)]
pub enum SceneCommand {
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

/// Runs a `scene` command.
pub fn run(command: SceneCommand, ctx: &Context) -> Result<(), CliError> {
    match command {
        SceneCommand::Init => {
            output::write(DEFAULT_SCENE);
            Ok(())
        }
        SceneCommand::Check { scene, json } => check_scene(&scene, json, ctx.budget),
    }
}

/// `scene check`: builds the scene and its solver and prints what a run will use.
fn check_scene(scene: &Path, json: bool, budget: Budget) -> Result<(), CliError> {
    let mut scene_file = SceneFile::load(scene)?;
    scene_file.budget = budget;
    let sim = scene_file.build()?;
    let report = crate::commands::scene_check::report(&scene.display().to_string(), &sim, budget)?;
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
