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
    Empty(Nothing),
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
    Input(#[from] PreviewInputError),
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

/// What is missing for there to be something to draw.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
pub enum Nothing {
    /// Strands were given as offsets with fewer than 2 entries.
    #[error(
        "no strands: offsets needs at least 2 entries (one strand); pass no strands to draw only \
         the meshes"
    )]
    NoStrands,
    /// Neither strands nor meshes were given.
    #[error("no strands and no meshes to draw; give the frame's strands or a scalp")]
    NoStrandsOrMeshes,
    /// A contact sheet was asked for without frames.
    #[error("a contact sheet needs at least one frame")]
    NoFrames,
}

/// How the inputs of a preview do not fit together.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum PreviewInputError {
    /// Not 4 bytes per pixel.
    #[error("{bytes} bytes for a {width} × {height} RGBA image: give 4 per pixel")]
    Pixels {
        /// Number of bytes given.
        bytes: usize,
        /// Image width, pixels.
        width: u32,
        /// Image height, pixels.
        height: u32,
    },
    /// The strand offsets do not span the positions.
    #[error(
        "strand offsets run from {first} to {last} but there are {positions} positions: offsets \
         must start at 0 and end at the number of positions"
    )]
    Offsets {
        /// The first offset.
        first: u32,
        /// The last offset.
        last: u32,
        /// Number of positions given.
        positions: usize,
    },
    /// A per-point array has not one entry per point.
    #[error("{found} strand {what} for {points} points: give one per point")]
    PerPoint {
        /// The array ("radii", "colors").
        what: &'static str,
        /// Number of entries given.
        found: usize,
        /// Number of points.
        points: usize,
    },
    /// Children have not 3 coordinates per point.
    #[error("children have {coordinates} coordinates for {points} widths: give 3 per point")]
    ChildCoordinates {
        /// Number of coordinates given.
        coordinates: usize,
        /// Number of points (widths).
        points: usize,
    },
    /// Children's vertex counts do not add up to their points.
    #[error("children's vertex counts add up to {counted} points but there are {points}")]
    ChildVertexCounts {
        /// Sum of the vertex counts.
        counted: u64,
        /// Number of points.
        points: usize,
    },
    /// Children have not 3 colour values per curve.
    #[error("children have {values} color values for {curves} curves: give 3 per curve")]
    ChildColors {
        /// Number of colour values given.
        values: usize,
        /// Number of curves.
        curves: usize,
    },
    /// Highlights were given without strands.
    #[error("highlights were given but no strands: highlights mark strand points and segments")]
    HighlightsWithoutStrands,
    /// Not one highlight flag per point.
    #[error("{flags} highlight point flags for {points} points: give one per point")]
    HighlightPoints {
        /// Number of flags given.
        flags: usize,
        /// Number of points.
        points: usize,
    },
    /// Not one highlight flag per segment.
    #[error(
        "{flags} highlight segment flags for {segments} segments (points − strands): give one \
         per segment"
    )]
    HighlightSegments {
        /// Number of flags given.
        flags: usize,
        /// Number of segments.
        segments: usize,
    },
    /// Contact sheet tiles differ in size.
    #[error(
        "contact sheet tile {tile} is {width} × {height} but tile 0 is {first_width} × \
         {first_height}: render every frame at one size"
    )]
    TileSize {
        /// The tile.
        tile: usize,
        /// Its width, pixels.
        width: u32,
        /// Its height, pixels.
        height: u32,
        /// Tile 0's width, pixels.
        first_width: u32,
        /// Tile 0's height, pixels.
        first_height: u32,
    },
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
