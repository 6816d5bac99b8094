//! Typed errors of the render level.
//!
//! Messages name the parameter, parent or file at fault and the fix, because a host shows them to
//! an artist as they are.

use std::path::PathBuf;

use thiserror::Error;

/// Everything `hair-render` can refuse.
#[derive(Debug, Error)]
pub enum RenderError {
    /// A setting is non-finite or out of its range.
    #[error("parameter `{name}` = {value}: {fix}")]
    Parameter {
        /// Name of the setting (field path, e.g. `shape.clump.factor`).
        name: &'static str,
        /// The offending value, printed.
        value: String,
        /// What to give instead.
        fix: &'static str,
    },
    /// A parent strand is unusable (too few points, non-finite or coincident points).
    #[error("parent {parent}: {message}")]
    Parent {
        /// Index of the parent strand.
        parent: usize,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// The inputs do not fit together (offsets, counts, per-parent arrays, motion samples).
    #[error("input: {0}")]
    Input(String),
    /// Writing an export failed; the partial file was removed.
    #[error("cannot write {path}: {source}")]
    Write {
        /// The file that was being written.
        path: PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
    /// Writing to a caller's stream failed.
    #[error("cannot write the export stream: {0}")]
    Stream(#[from] std::io::Error),
}

/// Result with [`RenderError`].
pub type Result<T> = std::result::Result<T, RenderError>;

/// A [`RenderError::Parameter`] for `name` = `value`.
pub(crate) fn parameter(
    name: &'static str,
    value: impl std::fmt::Display,
    fix: &'static str,
) -> RenderError {
    RenderError::Parameter {
        name,
        value: value.to_string(),
        fix,
    }
}

/// Refuses `value` unless it is finite and within `lo..=hi`.
pub(crate) fn check_range(
    name: &'static str,
    value: f32,
    lo: f32,
    hi: f32,
    fix: &'static str,
) -> Result<()> {
    if value.is_finite() && (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(parameter(name, value, fix))
    }
}
