//! Typed errors of the guide level.
//!
//! Every message names what is at fault (the file, the option as spelled in the scene file under
//! `[hair]`, the sampling region) and says how to fix it, because a host shows it to an artist as
//! it is.

use std::path::PathBuf;

use hair_core::HairError;
use thiserror::Error;

/// Everything `hair-groom` can refuse.
#[derive(Debug, Error)]
pub enum GroomError {
    /// A file could not be opened or read.
    #[error("cannot read {}: {source}; check that the path is right and the file is readable", .path.display())]
    Read {
        /// The file that was asked for.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
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
        reason: String,
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
        /// The region, printed.
        region: String,
    },
    /// An option or parameter is out of range, or `hair-core` refused the data built from it.
    #[error(transparent)]
    Core(#[from] HairError),
}

/// A parameter error naming `name` (the scene-file key), the offending value and the fix.
pub(crate) fn parameter(name: &str, value: impl ToString, fix: &str) -> GroomError {
    GroomError::Core(HairError::Parameter {
        name: name.to_string(),
        value: value.to_string(),
        fix: fix.to_string(),
    })
}
