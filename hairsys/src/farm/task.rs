//! The Simulate and Export tasks of a farm job (`hairsys farm simulate`, `hairsys farm
//! export`): what a retried task does is decided from the files on disk alone (see the
//! [module](super) docs).

use std::path::PathBuf;

use hair_cache::{CacheReader, WriterOptions};
use hair_core::{FrameReport, KernelChoice};

use super::{create_dir, FarmError, OutputLayout};
use crate::budget::Budget;
use crate::output::shot_export::{export_shot, ShotChildren, ShotOptions, ShotSummary};
use crate::run::{simulate, RunSummary, SimulateOptions};
use crate::shot::{Character, ShotFile, UsdOutput};

/// How a Simulate task runs.
#[derive(Debug, Clone)]
pub struct SimulateTask {
    /// Worker threads (default: all cores); results do not depend on the count.
    pub threads: Option<usize>,
    /// Which compiled copy of the mass-spring kernel runs (same bits either way).
    pub kernel: KernelChoice,
    /// Memory and time limits checked before the run.
    pub budget: Budget,
    /// Measure every frame's quality into the run's summary (a few % of the run).
    pub quality: bool,
}

/// How a Simulate task began.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "kebab-case", tag = "start")]
pub enum Start {
    /// No earlier attempt: a new run.
    Fresh,
    /// Continued the run a killed attempt left, from this frame.
    Resumed {
        /// The last frame the killed attempt completed.
        from: u32,
    },
    /// The complete cache of this scene and frame range was already there: nothing to do.
    Complete,
    /// Started over, replacing what an earlier attempt or job left.
    Replaced {
        /// Why that could not be kept or continued.
        reason: String,
    },
}

/// What a Simulate task did.
#[derive(Debug, Clone, serde::Serialize)]
pub struct SimulateOutcome {
    /// The character.
    pub character: String,
    /// The cache.
    pub cache: PathBuf,
    /// How the task began.
    pub start: Start,
    /// The run's summary (`None` when the cache was already complete).
    pub summary: Option<RunSummary>,
}

/// The character `name` of `shot`, or an error listing the names there are.
fn character<'a>(
    shot: &'a ShotFile,
    name: &str,
) -> Result<(&'a Character, &'a crate::scene::SceneFile), FarmError> {
    shot.character(name).ok_or_else(|| FarmError::Character {
        path: shot.path.clone(),
        name: name.to_string(),
        problem: format!(
            "the shot has no such character; it has {}",
            names(shot.shot.characters.iter())
        ),
    })
}

fn names<'a>(characters: impl Iterator<Item = &'a Character>) -> String {
    let list: Vec<String> = characters.map(|c| format!("{:?}", c.name)).collect();
    if list.is_empty() {
        "none".into()
    } else {
        list.join(", ")
    }
}

/// Simulates character `name` of `shot` over the shot's frames into its cache under `layout`,
/// calling `on_frame` after each frame. A complete cache of the same scene and frames is kept
/// as it is; a `.partial` of the same scene and frames is continued; anything else is
/// replaced.
pub fn simulate_character(
    shot: &ShotFile,
    name: &str,
    layout: &OutputLayout,
    task: &SimulateTask,
    on_frame: impl FnMut(&FrameReport),
) -> Result<SimulateOutcome, FarmError> {
    let (_, scene) = character(shot, name)?;
    let failed = |e: crate::Error| FarmError::Simulate {
        character: name.to_string(),
        source: Box::new(e),
    };
    let mut scene = scene.clone();
    scene.budget = task.budget;
    let hash = scene.hash().map_err(|e| failed(e.into()))?;
    let (first, last) = shot.frames();
    let cache = layout.cache(name);
    create_dir(&layout.character_dir(name))?;
    let mut start = Start::Fresh;
    if cache.exists() {
        match CacheReader::open(&cache) {
            Ok(r)
                if r.header().scene_hash == hash
                    && r.frame_numbers().first() == Some(&first)
                    && r.frame_numbers().last() == Some(&last)
                    && r.frame_numbers().len() == (last - first + 1) as usize =>
            {
                return Ok(SimulateOutcome {
                    character: name.to_string(),
                    cache,
                    start: Start::Complete,
                    summary: None,
                });
            }
            Ok(_) => {
                start = Start::Replaced {
                    reason: format!("{} holds another scene or frame range", cache.display()),
                }
            }
            Err(e) => {
                start = Start::Replaced {
                    reason: format!("{} cannot be read ({e})", cache.display()),
                }
            }
        }
    }
    let partial = hair_cache::partial_path(&cache)?;
    let mut resume = false;
    if partial.exists() {
        match hair_cache::recover(&partial) {
            Ok(r) if r.header.scene_hash == hash && r.header.first_frame == first => {
                match r.frames.last().map(|f| f.frame) {
                    Some(from) if from < last && from >= first => {
                        resume = true;
                        start = Start::Resumed { from };
                    }
                    _ => {
                        start = Start::Replaced {
                            reason: format!(
                                "{} holds no frame to continue from",
                                partial.display()
                            ),
                        }
                    }
                }
            }
            Ok(_) => {
                start = Start::Replaced {
                    reason: format!(
                        "{} was left by another scene or frame range",
                        partial.display()
                    ),
                }
            }
            Err(e) => {
                start = Start::Replaced {
                    reason: format!("{} cannot be read ({e})", partial.display()),
                }
            }
        }
    }
    let opts = SimulateOptions {
        scene,
        cache: cache.clone(),
        frames: Some((first, last)),
        threads: task.threads,
        writer: WriterOptions::default(),
        resume,
        kernel: task.kernel,
        quality: task.quality,
    };
    let summary = simulate(&opts, on_frame).map_err(failed)?;
    Ok(SimulateOutcome {
        character: name.to_string(),
        cache,
        start,
        summary: Some(summary),
    })
}

/// What an Export task did.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ChunkOutcome {
    /// The character.
    pub character: String,
    /// The chunk file written.
    pub path: PathBuf,
    /// What it holds.
    pub summary: ShotSummary,
    /// Chunk files of other, overlapping ranges that were deleted (left by an earlier job with
    /// another chunk size).
    pub removed: Vec<PathBuf>,
}

/// The export options of `character`'s chunk `frames` of `shot` (`None`: the character gets
/// no USD).
pub fn chunk_options(
    shot: &ShotFile,
    character: &Character,
    frames: (u32, u32),
    budget: Budget,
) -> Option<ShotOptions> {
    let children = match shot.usd_of(character) {
        UsdOutput::None => return None,
        UsdOutput::Strands => None,
        UsdOutput::Children => Some(ShotChildren::default()),
    };
    Some(ShotOptions {
        frames: Some(frames),
        shutter: shot.shutter,
        children,
        scene: None,
        budget,
        time_offset: shot.shot.output.time_offset,
        context: Some(shot.frames()),
    })
}

/// Exports frames `frames` of character `name` of `shot` from its cache into its chunk file
/// under `layout` (atomically), then deletes its chunk files of other ranges that overlap.
pub fn export_chunk(
    shot: &ShotFile,
    name: &str,
    frames: (u32, u32),
    layout: &OutputLayout,
    budget: Budget,
) -> Result<ChunkOutcome, FarmError> {
    let (c, _) = character(shot, name)?;
    let (first, last) = shot.frames();
    if frames.1 < frames.0 || frames.0 < first || frames.1 > last {
        return Err(FarmError::Frames {
            first: frames.0,
            last: frames.1,
            shot_first: first,
            shot_last: last,
        });
    }
    let Some(opts) = chunk_options(shot, c, frames, budget) else {
        return Err(FarmError::Character {
            path: shot.path.clone(),
            name: name.to_string(),
            problem: format!(
                "this character gets no USD (usd = \"none\"); the characters with USD are {}",
                names(shot.usd_characters())
            ),
        });
    };
    let cache = layout.cache(name);
    if !cache.exists() {
        return Err(FarmError::MissingCache {
            path: cache,
            character: name.to_string(),
        });
    }
    let dir = layout.chunk_dir(name);
    create_dir(&dir)?;
    let path = layout.chunk(name, frames);
    let summary = export_shot(&cache, &path, &opts).map_err(|e| FarmError::Export {
        character: name.to_string(),
        source: Box::new(e),
    })?;
    let mut removed = Vec::new();
    for ChunkFile {
        frames: range,
        path: stale,
    } in chunk_files(&dir, name)?
    {
        let overlaps = range.0 <= frames.1 && frames.0 <= range.1;
        if overlaps && range != frames {
            std::fs::remove_file(&stale).map_err(|e| {
                FarmError::io(&stale, format!("cannot delete the stale chunk ({e})"))
            })?;
            removed.push(stale);
        }
    }
    Ok(ChunkOutcome {
        character: name.to_string(),
        path,
        summary,
        removed,
    })
}

/// A chunk file an Export task wrote.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct ChunkFile {
    /// Its first and last frame.
    pub frames: (u32, u32),
    /// The file.
    pub path: PathBuf,
}

/// The chunk files of character `name` in `dir`, by first frame.
pub fn chunk_files(dir: &std::path::Path, name: &str) -> Result<Vec<ChunkFile>, FarmError> {
    let entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(FarmError::io(dir, format!("cannot list the folder ({e})"))),
    };
    let mut out = Vec::new();
    for entry in entries {
        let entry =
            entry.map_err(|e| FarmError::io(dir, format!("cannot list the folder ({e})")))?;
        let file = entry.file_name();
        if let Some(range) = super::layout::parse_chunk_file_name(name, &file.to_string_lossy()) {
            out.push(ChunkFile {
                frames: range,
                path: entry.path(),
            });
        }
    }
    out.sort();
    Ok(out)
}
