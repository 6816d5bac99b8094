//! Typed errors of the render level.
//!
//! Messages name the parameter, parent or file at fault and the fix, because a host shows them to
//! an artist as they are.

use std::path::PathBuf;

use thiserror::Error;

/// How the inputs of a render-level call do not fit together.
#[derive(Debug, Error)]
pub enum InputError {
    /// No parent strand is given.
    #[error("no parent strands: give at least one parent (offsets needs ≥ 2 entries)")]
    NoParents,
    /// The parents' offsets do not span the positions.
    #[error(
        "offsets run from {first} to {last} but there are {positions} positions: offsets must \
         start at 0 and end at the number of positions"
    )]
    Offsets {
        /// The first offset.
        first: u32,
        /// The last offset.
        last: u32,
        /// Number of positions given.
        positions: usize,
    },
    /// Not one scalp colour per mesh vertex.
    #[error("{colors} scalp colors for {vertices} mesh vertices: give one color per vertex")]
    ScalpColors {
        /// Number of colours given.
        colors: usize,
        /// Number of scalp vertices.
        vertices: usize,
    },
    /// A per-parent array has not one entry per parent.
    #[error("{found} {what} for {parents} parents: give one per parent")]
    PerParent {
        /// The array ("root frames", "clump factors", …).
        what: &'static str,
        /// Number of entries given.
        found: usize,
        /// Number of parents.
        parents: usize,
    },
    /// Motion samples of children differ in their curves.
    #[error(
        "motion samples differ in their curves ({curves} vs {other_curves} curves, {points} vs \
         {other_points} points): generate every sample from the same parents' topology with the \
         same settings and seed"
    )]
    ChildTopology {
        /// Curves of the exported frame.
        curves: usize,
        /// Curves of the sample.
        other_curves: usize,
        /// Points of the exported frame.
        points: usize,
        /// Points of the sample.
        other_points: usize,
    },
    /// A motion sample of cards differs in its topology.
    #[error(
        "a motion sample has {other_vertices} vertices and {other_quads} quads, the exported frame \
         {vertices} and {quads}; sample the same strips with the same card settings"
    )]
    CardTopology {
        /// Vertices of the sample.
        other_vertices: usize,
        /// Quads of the sample.
        other_quads: usize,
        /// Vertices of the exported frame.
        vertices: usize,
        /// Quads of the exported frame.
        quads: usize,
    },
    /// A strip's edges have different point counts.
    #[error("strip {strip}: edges of {left} and {right} points; both edges need the same count")]
    StripEdges {
        /// The strip.
        strip: usize,
        /// Points of its left edge.
        left: usize,
        /// Points of its right edge.
        right: usize,
    },
    /// There is nothing to export.
    #[error("no children to export: raise the child count")]
    NoChildren,
    /// A child has more points than a `.hair` strand holds.
    #[error(
        "child {child} has {points} points; a .hair strand holds at most 65 536: lower the \
         subdivisions"
    )]
    HairStrandPoints {
        /// The child.
        child: usize,
        /// Its point count.
        points: u32,
    },
    /// The children have more points than a `.hair` file holds.
    #[error("more than 2³² − 1 points: a .hair file cannot hold them")]
    HairFilePoints,
    /// Motion blur by time samples is asked for without a sample.
    #[error("motion blur by time samples needs at least 1 sample")]
    NoMotionSamples,
    /// Motion samples are not in increasing time.
    #[error(
        "motion sample {sample} at time code {time_code} is not after the previous one \
         ({previous}); give samples in increasing time"
    )]
    MotionOrder {
        /// The sample.
        sample: usize,
        /// Its time code.
        time_code: f64,
        /// The previous sample's time code.
        previous: f64,
    },
    /// Not three velocity components per point.
    #[error("{components} velocity components for {points} points: give x y z per point")]
    Velocities {
        /// Number of components given.
        components: usize,
        /// Number of points.
        points: usize,
    },
    /// The USD encoder refused the layer.
    #[cfg(feature = "usd")]
    #[error(transparent)]
    Usd(#[from] hair_groom::formats::usd_write::UsdWriteError),
}

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
    Input(#[from] InputError),
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
