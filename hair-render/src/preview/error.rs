//! Typed errors of the preview renderer.
//!
//! Like [`crate::RenderError`], every message names the input, field or file at fault and says
//! what to do instead, because `hairsys preview` prints them to a user as they are.

use std::path::PathBuf;

use thiserror::Error;

/// Everything the preview renderer can refuse.
#[derive(Debug, Error)]
pub enum PreviewError {
    /// A setting is non-finite or out of its range.
    #[error("preview parameter `{name}` = {value}: {fix}")]
    Parameter {
        /// Name of the setting (field path, e.g. `settings.width`).
        name: &'static str,
        /// The offending value, printed.
        value: String,
        /// What to give instead.
        fix: &'static str,
    },
    /// There is nothing to draw: no strands and no meshes.
    #[error("empty frame: {0}")]
    Empty(String),
    /// A strand is unusable (a non-finite point, a bad radius or color).
    #[error("strand {strand}: {message}")]
    Strand {
        /// Index of the strand.
        strand: usize,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// A mesh is unusable (a vertex index out of range, a non-finite vertex).
    #[error("mesh {mesh}: {message}")]
    Mesh {
        /// Index of the mesh in the scene.
        mesh: usize,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// The inputs do not fit together (offsets, per-point or per-segment arrays, tile sizes).
    #[error("preview input: {0}")]
    Input(String),
    /// The camera cannot see the scene: inside a mesh's bounds, degenerate, or non-finite.
    #[error("camera: {problem}; {fix}")]
    Camera {
        /// What is wrong with the camera.
        problem: String,
        /// What to do instead.
        fix: &'static str,
    },
    /// Writing a PNG failed; the partial file was removed.
    #[error("cannot write {}: {source}", .path.display())]
    Write {
        /// The file that was being written.
        path: PathBuf,
        /// The underlying I/O or encoder error.
        source: PngWriteError,
    },
    /// Encoding a PNG to a caller's stream failed.
    #[error("cannot encode the PNG stream: {0}")]
    Encode(#[from] png::EncodingError),
}

/// Why a PNG file could not be written.
#[derive(Debug, Error)]
pub enum PngWriteError {
    /// The operating system refused to create, write, sync or rename the file.
    #[error(transparent)]
    Io(#[from] std::io::Error),
    /// The PNG encoder failed.
    #[error("cannot encode the PNG stream: {0}")]
    Encode(#[from] png::EncodingError),
}

/// Result with [`PreviewError`].
pub type Result<T> = std::result::Result<T, PreviewError>;

/// A [`PreviewError::Parameter`] for `name` = `value`.
pub(crate) fn parameter(
    name: &'static str,
    value: impl std::fmt::Display,
    fix: &'static str,
) -> PreviewError {
    PreviewError::Parameter {
        name,
        value: value.to_string(),
        fix,
    }
}
