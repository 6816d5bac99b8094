//! AMD TressFX `.tfx` (header from `TressFXFileFormat.h`, little endian), read and written.
//!
//! A 160-byte header: `f32 version`, `u32 numHairStrands`, `u32 numVerticesPerStrand`,
//! `u32 offsetVertexPosition`, `u32 offsetStrandUV`, `u32 offsetVertexUV`,
//! `u32 offsetStrandThickness`, `u32 offsetVertexColor`, `u32 reserved[32]`; positions are
//! `float4 (x, y, z, w = inverse mass)`, strand after strand, root first. Every strand has the same
//! number of points. The reader takes the positions only (`w` is dropped: roots are pinned by
//! the scalp); the other offsets must be 0 (absent) or lie inside the file.
//!
//! TressFX has no signature: a file whose `version` is not a finite number in [1, 16) is refused
//! as not TressFX. Counts and offsets are checked against the file size before anything is
//! allocated. The writer writes version 4.0, positions at byte 160, `w` 0 at roots and 1
//! elsewhere, and no other array.

use std::path::Path;

use super::{
    bad, check_options, f32_at, point_at, read_bytes, to_file, to_world, u32_at, write_bytes,
    ImportOptions,
};
use crate::error::{FileLocation, GroomError};
use crate::groom::Groom;

/// Size of the header, bytes.
const HEADER: usize = 160;
/// Version the writer writes.
const VERSION: f32 = 4.0;

/// Reads the `.tfx` file at `path` into a groom in meters, Z up (`opts`: the file's unit scale
/// and up axis). Errors name the file, the byte offset and the fix.
pub fn read_tfx(path: &Path, opts: &ImportOptions) -> Result<Groom, GroomError> {
    check_options(opts)?;
    parse(&read_bytes(path)?, path, opts)
}

/// Writes `groom` to `path` as a TressFX file, converting back to file units and up axis with
/// `opts`. Every curve must have the same number of points (TressFX's layout); a curve that
/// differs from the first is refused by its index.
pub fn write_tfx(path: &Path, groom: &Groom, opts: &ImportOptions) -> Result<(), GroomError> {
    check_options(opts)?;
    write_bytes(path, &encode(groom, opts)?)
}

/// Parses a whole `.tfx` file held in `bytes`; `path` names it in errors.
fn parse(bytes: &[u8], path: &Path, opts: &ImportOptions) -> Result<Groom, GroomError> {
    if bytes.len() < HEADER {
        return Err(bad(
            path,
            FileLocation::File,
            format!(
                "is {} bytes, shorter than the {HEADER}-byte TressFX header: the file is \
                 truncated or not a .tfx file",
                bytes.len()
            ),
        ));
    }
    let version = f32_at(bytes, 0);
    if !(1.0..16.0).contains(&version) {
        return Err(bad(
            path,
            FileLocation::Byte(0),
            format!("version {version} is not a TressFX version (expected 1–15, e.g. 4.0): this is not a .tfx file"),
        ));
    }
    let strands = u64::from(u32_at(bytes, 4));
    let per_strand = u64::from(u32_at(bytes, 8));
    let positions = u64::from(u32_at(bytes, 12));
    if per_strand < 2 {
        return Err(bad(
            path,
            FileLocation::Byte(8),
            format!("numVerticesPerStrand = {per_strand}; a strand needs at least 2 points"),
        ));
    }
    let len = bytes.len() as u64;
    if positions < HEADER as u64 {
        return Err(bad(
            path,
            FileLocation::Byte(12),
            format!("offsetVertexPosition = {positions} points into the {HEADER}-byte header: the offset is wrong"),
        ));
    }
    // u128: 16 · (2³²)² does not fit in u64.
    let end = u128::from(positions) + 16 * u128::from(strands) * u128::from(per_strand);
    if end > u128::from(len) {
        return Err(bad(
            path,
            FileLocation::Byte(12),
            format!(
                "{strands} strands × {per_strand} points at offsetVertexPosition = {positions} \
                 need the file to reach byte {end}, but it has {len} bytes: it is truncated or \
                 its header is wrong"
            ),
        ));
    }
    for (field, at) in [
        ("offsetStrandUV", 16),
        ("offsetVertexUV", 20),
        ("offsetStrandThickness", 24),
        ("offsetVertexColor", 28),
    ] {
        let offset = u64::from(u32_at(bytes, at));
        if offset != 0 && !(HEADER as u64..len).contains(&offset) {
            return Err(bad(
                path,
                FileLocation::Byte(at as u64),
                format!("{field} = {offset} lies outside the data (bytes {HEADER}..{len}): the offset is wrong"),
            ));
        }
    }
    let (strands, per_strand) = (strands as usize, per_strand as usize);
    let mut curves = Vec::with_capacity(strands);
    let mut at = positions as usize;
    for s in 0..strands {
        let mut curve = Vec::with_capacity(per_strand);
        for i in 0..per_strand {
            let p = point_at(bytes, at, path, &format!("strand {s} point {i}"))?;
            curve.push(to_world(p, opts));
            at += 16;
        }
        curves.push(curve);
    }
    Groom::new(curves)
}

/// The `.tfx` bytes of `groom`.
fn encode(groom: &Groom, opts: &ImportOptions) -> Result<Vec<u8>, GroomError> {
    let per_strand = groom.curves().first().map_or(0, Vec::len);
    if let Some(c) = groom.curves().iter().position(|c| c.len() != per_strand) {
        return Err(GroomError::Curve {
            curve: c,
            message: format!(
                "has {} points but curve 0 has {per_strand}; TressFX needs the same count on \
                 every strand: resample the groom",
                groom.curves()[c].len()
            ),
        });
    }
    let count = |n: usize| {
        u32::try_from(n).map_err(|_| GroomError::Curve {
            curve: 0,
            message: format!("the groom has {n} strands or points; a .tfx holds at most 2³² − 1"),
        })
    };
    let mut out = Vec::with_capacity(HEADER + 16 * groom.point_count());
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.extend_from_slice(&count(groom.len())?.to_le_bytes());
    out.extend_from_slice(&count(per_strand)?.to_le_bytes());
    out.extend_from_slice(&(HEADER as u32).to_le_bytes());
    out.resize(HEADER, 0);
    for curve in groom.curves() {
        for (i, p) in curve.iter().enumerate() {
            let w: f32 = if i == 0 { 0.0 } else { 1.0 };
            for c in to_file(p, opts).into_iter().chain([w]) {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;

    use super::*;
    use crate::formats::test_support::assert_round_trip;

    fn groom() -> Groom {
        Groom::new(vec![
            vec![
                Vector3::new(0.1, -0.2, 0.3),
                Vector3::new(1e-7, 2.5, -3.25),
                Vector3::new(-0.0, 1e-38, 3e38),
            ],
            vec![
                Vector3::new(1.0, 2.0, 3.0),
                Vector3::new(4.0, 5.0, 6.0),
                Vector3::new(0.1, 0.2, 0.3),
            ],
        ])
        .unwrap()
    }

    fn parse_err(bytes: &[u8]) -> String {
        parse(bytes, Path::new("bad.tfx"), &ImportOptions::default())
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn write_then_read_is_bit_exact() {
        assert_round_trip(&groom(), |g, opts| {
            let bytes = encode(g, opts).unwrap();
            let back = parse(&bytes, Path::new("mem.tfx"), opts).unwrap();
            // And the bytes of a second write are the same.
            assert_eq!(encode(&back, opts).unwrap(), bytes);
            back
        });
    }

    #[test]
    fn unequal_curves_cannot_be_written() {
        let g = Groom::new(vec![
            vec![Vector3::zeros(), Vector3::x()],
            vec![Vector3::zeros(), Vector3::x(), Vector3::y()],
        ])
        .unwrap();
        let err = encode(&g, &ImportOptions::default())
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("curve 1") && err.contains("same count"),
            "{err}"
        );
    }

    #[test]
    fn bad_files_are_refused_with_file_and_offset() {
        let good = encode(&groom(), &ImportOptions::default()).unwrap();
        assert!(parse_err(&good[..50]).contains("shorter than the 160-byte"));
        assert!(parse_err(&[0xff; 400]).contains("not a .tfx file"));
        let msg = parse_err(&good[..good.len() - 1]);
        assert!(
            msg.contains("at byte 12") && msg.contains("truncated"),
            "{msg}"
        );
        let mut huge = good.clone();
        huge[4..8].copy_from_slice(&u32::MAX.to_le_bytes());
        huge[8..12].copy_from_slice(&u32::MAX.to_le_bytes());
        assert!(parse_err(&huge).contains("4294967295 strands"));
        let mut into_header = good.clone();
        into_header[12..16].copy_from_slice(&8u32.to_le_bytes());
        assert!(parse_err(&into_header).contains("offsetVertexPosition = 8"));
        let mut uv = good.clone();
        uv[16..20].copy_from_slice(&1_000_000u32.to_le_bytes());
        let msg = parse_err(&uv);
        assert!(
            msg.contains("offsetStrandUV") && msg.contains("at byte 16"),
            "{msg}"
        );
        let mut one = good.clone();
        one[8..12].copy_from_slice(&1u32.to_le_bytes());
        assert!(parse_err(&one).contains("at least 2 points"));
        let mut nan = good.clone();
        let at = HEADER + 16 * 4 + 8;
        nan[at..at + 4].copy_from_slice(&f32::INFINITY.to_le_bytes());
        let msg = parse_err(&nan);
        assert!(
            msg.contains("strand 1 point 1") && msg.contains("non-finite"),
            "{msg}"
        );
    }

    #[test]
    fn every_truncation_and_byte_corruption_is_an_error_not_a_panic() {
        let good = encode(&groom(), &ImportOptions::default()).unwrap();
        let path = Path::new("fuzz.tfx");
        for n in 0..good.len() {
            assert!(
                parse(&good[..n], path, &ImportOptions::default()).is_err(),
                "prefix {n}"
            );
        }
        for i in 0..good.len() {
            for value in [0x00, 0x7f, 0xff] {
                let mut bad = good.clone();
                bad[i] = value;
                // Either a groom or a clear error; never a panic or a huge allocation.
                let _ = parse(&bad, path, &ImportOptions::default());
            }
        }
    }
}
