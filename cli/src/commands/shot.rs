//! `hairsys shot check`: validate a shot file (and build every character's scene over the
//! shot's frames) and print the work a farm job of it implies.

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::Subcommand;
use hairsys::farm::{chunks, DEFAULT_CHUNK_SIZE, MAX_CHUNK_SIZE};
use hairsys::shot::ShotFile;
use serde::Serialize;

use crate::error::CliError;
use crate::{output, Context};

#[derive(Subcommand)]
pub enum ShotCommand {
    /// Check a shot file: its keys, every character's scene (built over the shot's frames,
    /// without simulating) and the frame rate they share; print the characters, their outputs
    /// and the tasks of a farm job (`hairsys farm job`).
    Check {
        /// Shot file (TOML).
        shot: PathBuf,
        /// Frames per Export task the task count is given for, 1–150.
        #[arg(long, default_value_t = DEFAULT_CHUNK_SIZE)]
        chunk_size: u32,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
}

/// One character as `shot check` reports it.
#[derive(Serialize)]
struct CharacterReport {
    name: String,
    scene: String,
    usd: &'static str,
    strands: usize,
    points: usize,
    export_tasks: usize,
}

/// What `shot check` prints.
#[derive(Serialize)]
struct ShotReport {
    shot: String,
    name: String,
    digest: String,
    frames: (u32, u32),
    fps: f32,
    shutter: Option<(f64, f64, usize)>,
    time_offset: f64,
    chunk_size: u32,
    characters: Vec<CharacterReport>,
    tasks: Vec<(&'static str, usize)>,
}

/// Runs a `shot` command.
pub fn run(command: ShotCommand, ctx: &Context) -> Result<(), CliError> {
    let ShotCommand::Check {
        shot,
        chunk_size,
        json,
    } = command;
    if !(1..=MAX_CHUNK_SIZE).contains(&chunk_size) {
        return Err(CliError::input(format!(
            "--chunk-size {chunk_size}: give 1 to {MAX_CHUNK_SIZE} frames per export task"
        )));
    }
    let file = ShotFile::load(&shot)?;
    let (first, last) = file.frames();
    let chunk_count = chunks((first, last), chunk_size).len();
    let mut characters = Vec::new();
    for (c, scene) in file.shot.characters.iter().zip(&file.scenes) {
        let mut scene = scene.clone();
        scene.budget = ctx.budget;
        let sim = scene.build()?;
        sim.check_deforming_frames(first, last).map_err(|e| {
            CliError::input(format!(
                "{}: [[characters]] {:?}: [shot] frames = [{first}, {last}]: {e}",
                shot.display(),
                c.name
            ))
        })?;
        let usd = file.usd_of(c);
        characters.push(CharacterReport {
            name: c.name.clone(),
            scene: scene.origin.clone(),
            usd: match usd {
                hairsys::shot::UsdOutput::Strands => "strands",
                hairsys::shot::UsdOutput::Children => "children",
                hairsys::shot::UsdOutput::None => "none",
            },
            strands: sim.strands.len(),
            points: sim.strands.point_count(),
            export_tasks: if usd.prim().is_some() { chunk_count } else { 0 },
        });
    }
    let exports: usize = characters.iter().map(|c| c.export_tasks).sum();
    let mut tasks = vec![("Simulate", characters.len())];
    if exports > 0 {
        tasks.extend([("Export", exports), ("Assemble", 1)]);
    }
    let report = ShotReport {
        shot: shot.display().to_string(),
        name: file.shot.shot.name.clone(),
        digest: file.digest.clone(),
        frames: (first, last),
        fps: file.fps(),
        shutter: file.shutter.map(|s| (s.open, s.close, s.samples)),
        time_offset: file.shot.output.time_offset,
        chunk_size,
        characters,
        tasks,
    };
    if json {
        outln!(
            "{}",
            serde_json::to_string(&report).expect("reports serialise")
        );
    } else {
        output::block(&text(&report));
    }
    Ok(())
}

/// The report as text.
fn text(r: &ShotReport) -> String {
    let mut t = String::new();
    let name = if r.name.is_empty() {
        "(unnamed)"
    } else {
        &r.name
    };
    let _ = writeln!(t, "shot {name}: {} (digest {})", r.shot, &r.digest[..12]);
    let _ = writeln!(
        t,
        "  frames {}-{} ({} frames) at {} fps",
        r.frames.0,
        r.frames.1,
        r.frames.1 - r.frames.0 + 1,
        r.fps
    );
    match r.shutter {
        Some((open, close, n)) => {
            let _ = writeln!(t, "  USD shutter {open}..{close} frames, {n} samples");
        }
        None => {
            let _ = writeln!(t, "  USD at the frames only (no shutter)");
        }
    }
    if r.time_offset != 0.0 {
        let _ = writeln!(t, "  USD time codes = frame + {}", r.time_offset);
    }
    let _ = writeln!(t, "characters:");
    for c in &r.characters {
        let _ = writeln!(
            t,
            "  {}: {} — {} strands, {} points; cache {}/{}.mcap; USD {}",
            c.name, c.scene, c.strands, c.points, c.name, c.name, c.usd
        );
    }
    let _ = writeln!(t, "farm job, {} frames per export task:", r.chunk_size);
    for (step, n) in &r.tasks {
        let what = match *step {
            "Simulate" => "one per character, each over every frame",
            "Export" => "characters with USD × frame chunks",
            _ => "the character layers and shot.usda",
        };
        let _ = writeln!(t, "  {step}: {n} task(s) ({what})");
    }
    t
}
