//! [`OutputError`]: why an output could not be made.

use std::path::{Path, PathBuf};

use super::ShotError;
use crate::scene::SceneError;

/// Why an output (children, the shot export, cards, a preview, a quality report) could not be
/// made. Every variant but [`OutputError::Write`] is about what was asked or read; `Write` is
/// about the file being written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The cache cannot be opened for output.
    #[error("{0}")]
    Shot(#[from] ShotError),
    /// A frame or a rig frame of the cache cannot be read.
    #[error("{0}")]
    Cache(#[from] hair_cache::CacheError),
    /// The scene given for the rest state (or over the cache's) cannot be used.
    #[error("{0}")]
    Scene(#[from] SceneError),
    /// What was asked cannot be made: names the option and the fix.
    #[error("{0}")]
    Request(String),
    /// The scene's `[strips]` cannot be grown into cards.
    #[error("{0}")]
    Strips(#[from] crate::scene::strips::StripsError),
    /// The children cannot be generated from the parents given.
    #[error("{0}")]
    Children(#[from] hair_render::RenderError),
    /// A preview picture cannot be drawn.
    #[cfg(feature = "preview")]
    #[error("{0}")]
    Preview(#[from] hair_render::preview::PreviewError),
    /// One view of a preview frame cannot be drawn.
    #[cfg(feature = "preview")]
    #[error("{at}: {source}")]
    View {
        /// The frame and the view.
        at: String,
        /// Why.
        source: hair_render::preview::PreviewError,
    },
    /// The scalp or a collider cannot be placed at a time of the shot.
    #[error("{0}")]
    Geometry(#[from] hair_core::HairError),
    /// A frame could not be measured for the quality report.
    #[error("the quality report, frame {frame}: {source}")]
    Quality {
        /// The frame.
        frame: u32,
        /// Why.
        source: hair_core::HairError,
    },
    /// The work asked for is over the memory or time budget.
    #[error("{0}")]
    Budget(crate::budget::OverBudget),
    /// A USD output was asked of a build without the Cargo feature `usd`.
    #[error(
        "{} is a USD file, and this build of hairsys writes no USD: it was built without the \
         Cargo feature `usd`; use a build with it (the `hairsys` command has it), or write \
         children as .hair and cards as .obj",
        path.display()
    )]
    UsdNotBuilt {
        /// The output asked for.
        path: PathBuf,
    },
    /// The output file cannot be written.
    #[error("cannot write {}: {reason}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// Why, as the writer reported it.
        reason: String,
    },
}

impl From<crate::budget::OverBudget> for OutputError {
    fn from(e: crate::budget::OverBudget) -> Self {
        OutputError::Budget(e)
    }
}

impl OutputError {
    /// A [`OutputError::Request`] with its message.
    pub fn request(message: impl Into<String>) -> Self {
        OutputError::Request(message.into())
    }

    /// A [`OutputError::Write`] of `path`, for `reason`.
    pub fn write(path: impl Into<PathBuf>, reason: impl std::fmt::Display) -> Self {
        OutputError::Write {
            path: path.into(),
            reason: reason.to_string(),
        }
    }

    /// The error of a `hair_render` exporter writing `path`: a failed write is an
    /// [`OutputError::Write`], anything else (buffers that do not fit) [`OutputError::Children`].
    pub(crate) fn export(path: &Path, e: hair_render::RenderError) -> Self {
        match e {
            hair_render::RenderError::Write { source, .. }
            | hair_render::RenderError::Stream(source) => OutputError::write(path, source),
            other => OutputError::Children(other),
        }
    }

    /// Whether the error is about what was asked or read (bad input), not about writing the
    /// output.
    pub fn is_bad_input(&self) -> bool {
        !matches!(self, OutputError::Write { .. })
    }
}
