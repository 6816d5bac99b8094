//! File formats of the guide level, one module per format; each reads (and, where it applies,
//! writes) one format and converts it to meters, Z up.
//!
//! Groom formats read into a [`crate::Groom`]: [`hair`] (Cem Yuksel's `.hair`, read and write),
//! [`tfx`] (AMD TressFX `.tfx`, read and write), [`obj_curves`] (OBJ polylines, read and write)
//! and `usd` (USD `BasisCurves` from a composed `.usd`/`.usda`/`.usdc`/`.usdz` stage, read;
//! `.usda`/`.usdc`, written through `usd_write`). They all take
//! [`ImportOptions`]: meters per file unit and the file's up axis; writers apply the inverse, so
//! a groom written with the options it was read with gives back the file's numbers.
//! [`read_groom`] and [`write_groom`] pick the format from the file's extension.
//!
//! Meshes: [`obj`] (OBJ scalps and colliders, and numbered OBJ sequences of a deforming mesh
//! in [`obj_sequence`]) and `usd_mesh` (a USD `Mesh` prim read at any time code).
//!
//! The USD modules (`usd`, `usd_mesh`, `usd_write`) are the Cargo feature `usd` (on by default);
//! without it a USD file is still recognised by its extension and refused with
//! [`GroomError::NotBuilt`], which names the feature.

pub mod hair;
pub mod obj;
pub mod obj_curves;
pub mod obj_sequence;
pub mod tfx;
#[cfg(feature = "usd")]
pub mod usd;
#[cfg(feature = "usd")]
pub mod usd_mesh;
#[cfg(feature = "usd")]
pub mod usd_write;

use std::path::Path;

use nalgebra::Vector3;

use crate::error::{parameter, FileLocation, GroomError};
use crate::groom::Groom;
use crate::input_file;
use obj::{ObjOptions, UpAxis};

/// Unit scale and up axis of a groom file: the same options as OBJ meshes ([`ObjOptions`]).
/// The Sintel sample is `scale: 0.01, up_axis: UpAxis::Y`.
pub type ImportOptions = ObjOptions;

/// A groom file format, chosen from the file name's extension by [`GroomFormat::of`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GroomFormat {
    /// Cem Yuksel's `.hair`.
    Hair,
    /// AMD TressFX `.tfx`.
    Tfx,
    /// OBJ polylines `.obj`.
    ObjCurves,
    /// USD: `.usd`, `.usda`, `.usdc`, `.usdz` (read; `.usda` and `.usdc` written).
    Usd,
}

impl GroomFormat {
    /// The format of `path` by its extension (case-insensitive); refuses any other extension,
    /// naming the file and the ones read.
    pub fn of(path: &Path) -> Result<Self, GroomError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("hair") => Ok(Self::Hair),
            Some("tfx") => Ok(Self::Tfx),
            Some("obj") => Ok(Self::ObjCurves),
            Some("usd" | "usda" | "usdc" | "usdz") => Ok(Self::Usd),
            _ => Err(bad(
                path,
                FileLocation::File,
                "has an extension that names no groom format: use .hair, .tfx, .obj (polylines) \
                 or .usd/.usda/.usdc/.usdz (BasisCurves)",
            )),
        }
    }
}

/// Reads the groom file at `path` in the format its extension names ([`GroomFormat::of`]), in
/// meters, Z up (`opts`: the file's unit scale and up axis; for USD they replace the stage's
/// `metersPerUnit` and `upAxis`: use `usd::read_usd` to take the stage's, pick prims or a
/// time).
pub fn read_groom(path: &Path, opts: &ImportOptions) -> Result<Groom, GroomError> {
    // What the path is comes before what its name says: "is a directory" is the clearer error.
    input_file::check_regular_file(path)?;
    match GroomFormat::of(path)? {
        GroomFormat::Hair => hair::read_hair(path, opts),
        GroomFormat::Tfx => tfx::read_tfx(path, opts),
        GroomFormat::ObjCurves => obj_curves::read_obj_curves(path, opts),
        #[cfg(feature = "usd")]
        GroomFormat::Usd => usd::read_usda(path, opts),
        #[cfg(not(feature = "usd"))]
        GroomFormat::Usd => Err(GroomError::usd_not_built(path)),
    }
}

/// Writes `groom` to `path` in the format its extension names, in file units and up axis per
/// `opts`.
pub fn write_groom(path: &Path, groom: &Groom, opts: &ImportOptions) -> Result<(), GroomError> {
    match GroomFormat::of(path)? {
        GroomFormat::Hair => hair::write_hair(path, groom, opts),
        GroomFormat::Tfx => tfx::write_tfx(path, groom, opts),
        GroomFormat::ObjCurves => obj_curves::write_obj_curves(path, groom, opts),
        #[cfg(feature = "usd")]
        GroomFormat::Usd => usd::write_usda(path, groom, opts),
        #[cfg(not(feature = "usd"))]
        GroomFormat::Usd => Err(GroomError::usd_not_built(path)),
    }
}

/// Checks `opts.scale`: finite and > 0.
pub(crate) fn check_options(opts: &ImportOptions) -> Result<(), GroomError> {
    if opts.scale.is_finite() && opts.scale > 0.0 {
        Ok(())
    } else {
        Err(parameter(
            "scale",
            opts.scale,
            "must be a finite number > 0 (meters per file unit, e.g. 0.01 for centimeters)",
        ))
    }
}

/// A file position (file units, file up axis) in meters, Z up: Y up maps (x, y, z) to
/// (x, −z, y), so the file's front (+Z) faces −Y as in Blender.
pub(crate) fn to_world(p: [f32; 3], opts: &ImportOptions) -> Vector3<f32> {
    let v = match opts.up_axis {
        UpAxis::Y => Vector3::new(p[0], -p[2], p[1]),
        UpAxis::Z => Vector3::new(p[0], p[1], p[2]),
    };
    v * opts.scale
}

/// The inverse of [`to_world`]: a position in meters, Z up, in file units and axes.
pub(crate) fn to_file(v: &Vector3<f32>, opts: &ImportOptions) -> [f32; 3] {
    let v = v / opts.scale;
    match opts.up_axis {
        UpAxis::Y => [v.x, v.z, -v.y],
        UpAxis::Z => [v.x, v.y, v.z],
    }
}

/// A [`GroomError::BadFile`] for `path` at `at`.
pub(crate) fn bad(path: &Path, at: FileLocation, message: impl Into<String>) -> GroomError {
    GroomError::BadFile {
        path: path.to_path_buf(),
        at,
        message: message.into(),
    }
}

/// Reads the whole groom file at `path`: a regular file of at most
/// [`MAX_GROOM_FILE_BYTES`](crate::input_file::MAX_GROOM_FILE_BYTES).
pub(crate) fn read_bytes(path: &Path) -> Result<Vec<u8>, GroomError> {
    Ok(input_file::read_regular_file(
        path,
        input_file::MAX_GROOM_FILE_BYTES,
    )?)
}

/// Writes `bytes` to `path`.
pub(crate) fn write_bytes(path: &Path, bytes: &[u8]) -> Result<(), GroomError> {
    std::fs::write(path, bytes).map_err(|source| GroomError::Write {
        path: path.to_path_buf(),
        source,
    })
}

/// Little-endian reads from a byte slice whose bounds the caller has checked.
pub(crate) fn u32_at(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
}

/// The little-endian f32 at byte `at` (bounds checked by the caller).
pub(crate) fn f32_at(bytes: &[u8], at: usize) -> f32 {
    f32::from_bits(u32_at(bytes, at))
}

/// Three little-endian f32 at byte `at`, refused with the byte offset if one is not finite.
pub(crate) fn point_at(
    bytes: &[u8],
    at: usize,
    path: &Path,
    what: &str,
) -> Result<[f32; 3], GroomError> {
    let p = [
        f32_at(bytes, at),
        f32_at(bytes, at + 4),
        f32_at(bytes, at + 8),
    ];
    if p.iter().all(|c| c.is_finite()) {
        Ok(p)
    } else {
        Err(bad(
            path,
            FileLocation::Byte(at as u64),
            format!(
                "{what} has a non-finite coordinate {p:?}; fix the exporter or remove the strand"
            ),
        ))
    }
}

/// Shared by the formats' round-trip tests.
#[cfg(test)]
pub(crate) mod test_support {
    use nalgebra::Vector3;

    use super::ImportOptions;
    use crate::formats::obj::UpAxis;
    use crate::groom::Groom;

    /// Two curves of 2 and 3 points with values a text format must print exactly: −0.0, 1e−30,
    /// 1e30, an f32 with no short decimal form.
    pub fn tricky_groom() -> Groom {
        Groom::new(vec![
            vec![
                Vector3::new(0.1, -0.2, 1e-30),
                Vector3::new(1e30, 2.5, 0.333_333_34),
            ],
            vec![
                Vector3::new(1.0, 2.0, 3.0),
                Vector3::new(-0.0, 5.0, 6.0),
                Vector3::new(7.0, 8.0, 9.0),
            ],
        ])
        .unwrap()
    }

    /// Every coordinate's bits, curve by curve.
    pub fn bits(g: &Groom) -> Vec<u32> {
        g.curves()
            .iter()
            .flatten()
            .flat_map(|p| p.iter().map(|c| c.to_bits()).collect::<Vec<_>>())
            .collect()
    }

    /// Asserts that `round_trip` (write, then read back) returns `groom` bit for bit, for both up
    /// axes.
    pub fn assert_round_trip(groom: &Groom, round_trip: impl Fn(&Groom, &ImportOptions) -> Groom) {
        for up_axis in [UpAxis::Z, UpAxis::Y] {
            let back = round_trip(
                groom,
                &ImportOptions {
                    scale: 1.0,
                    up_axis,
                },
            );
            assert_eq!(bits(&back), bits(groom), "up axis {up_axis:?}");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extensions_choose_the_format() {
        let dir = tempfile::tempdir().unwrap();
        let groom = Groom::new(vec![vec![Vector3::zeros(), Vector3::new(0.0, 0.01, 0.1)]]).unwrap();
        let opts = ImportOptions {
            scale: 0.01,
            up_axis: UpAxis::Y,
        };
        for name in ["g.hair", "g.TFX", "g.obj", "g.usda", "g.usdc"] {
            let path = dir.path().join(name);
            write_groom(&path, &groom, &opts).unwrap();
            let back = read_groom(&path, &opts).unwrap();
            let err = (back.curves()[0][1] - groom.curves()[0][1]).norm();
            assert!(err < 1e-8, "{name}: {err}");
        }
        let abc = dir.path().join("g.abc");
        std::fs::write(&abc, b"curves").unwrap();
        let err = read_groom(&abc, &opts).unwrap_err().to_string();
        assert!(err.contains("g.abc") && err.contains(".usda"), "{err}");
    }
}
