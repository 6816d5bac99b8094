//! [`FarmError`]: why a farm job could not be written or one of its tasks could not run.

use std::path::PathBuf;

use crate::output::OutputError;
use crate::shot::ShotError;

/// Why a farm job could not be written, or a task of one could not run. Every message names the
/// file or option and the fix; [`FarmError::is_bad_input`] tells bad input from failed work.
#[derive(Debug, thiserror::Error)]
pub enum FarmError {
    /// The shot file cannot be used.
    #[error("{0}")]
    Shot(#[from] ShotError),
    /// The shot file changed since the job was written: its characters, frames or outputs may
    /// no longer be the job's.
    #[error(
        "{}: the shot file changed since the job was written (digest {found} ≠ {expected}); \
         write the job again with `hairsys farm job` and submit it, or restore the shot file",
        path.display()
    )]
    ShotChanged {
        /// The shot file.
        path: PathBuf,
        /// The digest the job recorded (first 12 hex digits).
        expected: String,
        /// The digest of the file now (first 12 hex digits).
        found: String,
    },
    /// A task names a character the shot does not have (or one without USD output).
    #[error("{}: --character {name}: {problem}", path.display())]
    Character {
        /// The shot file.
        path: PathBuf,
        /// The name given.
        name: String,
        /// What is wrong, and the names that would do.
        problem: String,
    },
    /// A task's frames lie outside the shot.
    #[error(
        "--frames {first}-{last}: outside the shot's frames {shot_first}-{shot_last}; give a \
         range inside them (the job's chunks are)"
    )]
    Frames {
        /// First frame given.
        first: u32,
        /// Last frame given.
        last: u32,
        /// The shot's first frame.
        shot_first: u32,
        /// The shot's last frame.
        shot_last: u32,
    },
    /// `--chunk-size` is 0 or over what farm managers take.
    #[error(
        "--chunk-size {0}: give 1 to {max} frames per export task",
        max = super::MAX_CHUNK_SIZE
    )]
    ChunkSize(u32),
    /// The Simulate task of a character has not written its cache yet.
    #[error(
        "{}: no cache of character {character:?}; its Simulate task runs first (`hairsys farm \
         simulate … --character {character}`)", path.display()
    )]
    MissingCache {
        /// The cache expected.
        path: PathBuf,
        /// The character.
        character: String,
    },
    /// The Export tasks' chunk files do not cover the shot's frames once each.
    #[error(
        "{}: the chunk files of {character:?} {problem}; run the Export tasks of the missing \
         frames (or delete the stale chunk files left by an earlier job) and assemble again",
        dir.display()
    )]
    Chunks {
        /// The character's chunk folder.
        dir: PathBuf,
        /// The character.
        character: String,
        /// What is missing or overlapping.
        problem: String,
    },
    /// The character's simulation failed.
    #[error("[[characters]] {character:?}: {source}")]
    Simulate {
        /// The character.
        character: String,
        /// Why.
        source: Box<crate::Error>,
    },
    /// An export could not be made.
    #[error("[[characters]] {character:?}: {source}")]
    Export {
        /// The character.
        character: String,
        /// Why.
        source: Box<OutputError>,
    },
    /// The cache cannot be read.
    #[error("{0}")]
    Cache(#[from] hair_cache::CacheError),
    /// A file cannot be written, read or listed.
    #[error("{}: {reason}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// Why, as the system said, with what to check.
        reason: String,
    },
}

impl FarmError {
    /// A [`FarmError::Io`] of `path`.
    pub(crate) fn io(path: impl Into<PathBuf>, e: impl std::fmt::Display) -> Self {
        FarmError::Io {
            path: path.into(),
            reason: e.to_string(),
        }
    }

    /// Whether the error is about what was given (the shot, an option, a missing input), not
    /// about work that failed.
    pub fn is_bad_input(&self) -> bool {
        match self {
            FarmError::Shot(_)
            | FarmError::ShotChanged { .. }
            | FarmError::Character { .. }
            | FarmError::Frames { .. }
            | FarmError::ChunkSize(_)
            | FarmError::MissingCache { .. }
            | FarmError::Chunks { .. } => true,
            FarmError::Simulate { source, .. } => matches!(
                **source,
                crate::Error::Scene(_) | crate::Error::Usage(_) | crate::Error::Argument { .. }
            ),
            FarmError::Export { source, .. } => source.is_bad_input(),
            FarmError::Cache(_) | FarmError::Io { .. } => false,
        }
    }
}
