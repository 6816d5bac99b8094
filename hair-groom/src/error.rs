//! Typed errors of the guide level.
//!
//! Every message names what is at fault (the file, the option as spelled in the scene file under
//! `[hair]`, the sampling region) and says how to fix it, because a host shows it to an artist as
//! it is.

use std::fmt;
use std::path::PathBuf;

use hair_core::HairError;
use thiserror::Error;

use crate::formats::obj::ObjParseError;
use crate::input_file::InputFileError;
use crate::reinterpolate::PoseError;
use crate::sampling::{DensityError, Region};

/// Everything `hair-groom` can refuse.
#[derive(Debug, Error)]
pub enum GroomError {
    /// An input file could not be read: missing or unreadable, not a regular file (a
    /// directory, FIFO or device), or larger than the reader takes. The error names the file.
    #[error(transparent)]
    Input(#[from] InputFileError),
    /// The OBJ parser refused the file.
    #[error(
        "cannot parse OBJ file {}: {reason}; check that it is a Wavefront OBJ text file \
         (Blender: File > Export > Wavefront (.obj))",
        .path.display()
    )]
    ObjParse {
        /// The file being parsed.
        path: PathBuf,
        /// The parser's reason.
        #[source]
        reason: ObjParseError,
    },
    /// The OBJ file parsed but holds no triangle (no faces, or only points and lines).
    #[error(
        "OBJ file {} has no triangles (no faces, or only points and lines); export the scalp \
         as a mesh with faces",
        .path.display()
    )]
    ObjNoTriangles {
        /// The file that was read.
        path: PathBuf,
    },
    /// The mesh read from an OBJ file was refused by `hair-core` (degenerate triangle, non-finite
    /// coordinate, inconsistent UVs).
    #[error("OBJ file {}: {source}", .path.display())]
    ObjMesh {
        /// The file that was read.
        path: PathBuf,
        /// What `hair-core` refused, with its fix.
        source: HairError,
    },
    /// A sampling region holds no triangle area of the mesh.
    #[error(
        "the sampling region {region} holds no triangle of the mesh; widen `max_angle_deg` or \
         point `direction` at the part of the mesh that should grow hair"
    )]
    EmptyRegion {
        /// The region.
        region: Region,
    },
    /// A groom file (`.hair`, `.tfx`, OBJ curves, `.usda`) is malformed: wrong magic, truncated,
    /// counts that disagree with its size, a non-finite coordinate, a curve with fewer than 2
    /// points. `at` is the byte offset (binary formats) or line (text formats) of the fault.
    #[error("{}{at}: {message}", .path.display())]
    BadFile {
        /// The file being read.
        path: PathBuf,
        /// Where in the file.
        at: FileLocation,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// A groom file could not be written.
    #[error("cannot write {}: {source}; check that the directory exists and is writable", .path.display())]
    Write {
        /// The file being written.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// A curve of an in-memory groom is unusable (fewer than 2 points, non-finite point, too
    /// many points for the target format).
    #[error("curve {curve}: {message}")]
    Curve {
        /// Index of the curve in its groom.
        curve: usize,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// Guide roots lie farther from the scalp than the snap threshold. The message lists the
    /// likely causes, most likely first, then the threshold to raise; callers add where the
    /// groom came from, not more advice.
    #[error(
        "{} guide root(s) lie farther than {max_distance} m from the scalp: {}. Likely causes, \
         most likely first: (1) an object transform not applied before export, so the curves \
         and the scalp are in different spaces (Blender: select the hair and the scalp, Object › \
         Apply › All Transforms, export again); (2) the units: set the import `scale` to meters \
         per file unit (0.01 for centimetres); (3) the up axis: set `up_axis` to the file's \
         (\"y\" for Maya and most exporters); (4) a groom made for another scalp mesh. If the \
         roots sit just off this scalp, raise `max_snap_distance` (m) above the distances shown",
        .far.len(),
        list_far(.far)
    )]
    RootsTooFar {
        /// The refused strands with their distances.
        far: Vec<FarRoot>,
        /// The threshold, m.
        max_distance: f32,
    },
    /// Interpolation was asked for with no enabled guide.
    #[error("no guide is enabled: enable at least one guide to interpolate simulation hairs from")]
    NoEnabledGuides,
    /// A simulation hair's root lies on a piece of the mesh that no enabled guide is rooted on.
    #[error(
        "simulation hair {hair}: its root lies on a piece of the scalp mesh that no enabled guide \
         is rooted on (the mesh is in separate pieces); add or enable a guide there, or use the \
         Euclidean distance"
    )]
    NoGuideReachable {
        /// Index of the simulation hair (its root in the list of roots).
        hair: usize,
    },
    /// A root density ([`crate::RootDensity`]) refused the sampling: a value out of range, an
    /// error of its own (e.g. a texture that does not cover a root's UV), or too little density
    /// to grow the hair asked for.
    #[error(transparent)]
    Density(#[from] DensityError),
    /// An animated pose of the guides does not fit the groom ([`crate::GuideBlend::check_pose`]).
    #[error(transparent)]
    Pose(#[from] PoseError),
    /// An option or parameter is out of range, or `hair-core` refused the data built from it.
    #[error(transparent)]
    Core(#[from] HairError),
    /// The file is in a format this build leaves out: the crate was built without the Cargo
    /// feature that reads it (`usd` for `.usd`, `.usda`, `.usdc`, `.usdz`).
    #[error(
        "{} is a {format} file, and this build of hairsys reads no {format}: it was built \
         without the Cargo feature `{feature}`; use a build with it (the `hairsys` command has \
         it) or convert the file to .hair, .tfx or .obj",
        .path.display()
    )]
    NotBuilt {
        /// The file.
        path: PathBuf,
        /// The format, e.g. `"USD"`.
        format: &'static str,
        /// The Cargo feature that reads it, e.g. `"usd"`.
        feature: &'static str,
    },
}

impl GroomError {
    /// A [`GroomError::NotBuilt`] for the USD file `path`.
    pub fn usd_not_built(path: &std::path::Path) -> Self {
        GroomError::NotBuilt {
            path: path.to_path_buf(),
            format: "USD",
            feature: "usd",
        }
    }
}

/// Where in a file a fault lies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileLocation {
    /// The file as a whole (e.g. its size).
    File,
    /// A byte offset from the start of a binary file.
    Byte(u64),
    /// A 1-based line of a text file.
    Line(usize),
}

impl fmt::Display for FileLocation {
    /// Empty, ` at byte N` or ` line N`, appended to the file name.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FileLocation::File => Ok(()),
            FileLocation::Byte(b) => write!(f, " at byte {b}"),
            FileLocation::Line(l) => write!(f, " line {l}"),
        }
    }
}

/// A guide root refused by snapping: its strand and its distance to the scalp.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FarRoot {
    /// Index of the strand in the groom.
    pub strand: usize,
    /// Distance from the root to the nearest scalp point, m.
    pub distance: f32,
}

/// The first ten far roots as `strand 3 (0.025 m), …`.
fn list_far(far: &[FarRoot]) -> String {
    let mut s = far
        .iter()
        .take(10)
        .map(|r| format!("strand {} ({:.4} m)", r.strand, r.distance))
        .collect::<Vec<_>>()
        .join(", ");
    if far.len() > 10 {
        s.push_str(&format!(" and {} more", far.len() - 10));
    }
    s
}

/// A parameter error naming `name` (the scene-file key), the offending value and the fix.
pub(crate) fn parameter(name: &str, value: impl ToString, fix: &str) -> GroomError {
    GroomError::Core(HairError::Parameter {
        name: name.to_string(),
        value: value.to_string(),
        fix: fix.to_string(),
    })
}
