//! Cem Yuksel's HAIR format (`.hair`, from `cyHairFile.h`, little endian), read and written.
//!
//! A 128-byte header: `"HAIR"`, `u32 hair_count`, `u32 point_count`, `u32 arrays` (bit flags: 1
//! segments, 2 points, 4 thickness, 8 transparency, 16 colors), `u32 d_segments`,
//! `f32 d_thickness`, `f32 d_transparency`, `f32 d_color[3]`, `char info[88]`; then, each present
//! only if its bit is set, `u16 segments[hair_count]` (points per strand = segments + 1; if absent
//! every strand has `d_segments`), `f32 points[point_count · 3]`, then thickness, transparency
//! and colors, which this reader skips (it only checks that the file holds them).
//!
//! Every count is checked against the file's size before anything is allocated, so a header
//! that claims more data than the file holds is refused, never trusted. The writer writes the
//! segments and points arrays, `d_thickness` 1, `d_transparency` 0, `d_color` white and the info
//! string `hairsys`.

use std::path::Path;

use super::{
    bad, check_options, point_at, read_bytes, to_file, to_world, u32_at, write_bytes, ImportOptions,
};
use crate::error::{FileLocation, GroomError};
use crate::groom::Groom;

/// Size of the header, bytes.
const HEADER: usize = 128;
/// `arrays` bit: per-strand segment counts are present.
const HAS_SEGMENTS: u32 = 1;
/// `arrays` bit: point positions are present.
const HAS_POINTS: u32 = 2;
/// `arrays` bit: per-point thickness is present.
const HAS_THICKNESS: u32 = 4;
/// `arrays` bit: per-point transparency is present.
const HAS_TRANSPARENCY: u32 = 8;
/// `arrays` bit: per-point colors are present.
const HAS_COLORS: u32 = 16;

/// Reads the `.hair` file at `path` into a groom in meters, Z up (`opts`: the file's unit scale
/// and up axis). Errors name the file, the byte offset and the fix.
pub fn read_hair(path: &Path, opts: &ImportOptions) -> Result<Groom, GroomError> {
    check_options(opts)?;
    parse(&read_bytes(path)?, path, opts)
}

/// Writes `groom` to `path` as a `.hair` file, converting meters, Z up, back to file units and
/// up axis with `opts`. Refuses a curve of more than 65 536 points (the format's u16 segment
/// count) and more than 2³² − 1 points in all.
pub fn write_hair(path: &Path, groom: &Groom, opts: &ImportOptions) -> Result<(), GroomError> {
    check_options(opts)?;
    write_bytes(path, &encode(groom, opts)?)
}

/// Parses a whole `.hair` file held in `bytes`; `path` names it in errors.
fn parse(bytes: &[u8], path: &Path, opts: &ImportOptions) -> Result<Groom, GroomError> {
    let whole = FileLocation::File;
    if bytes.len() < HEADER {
        return Err(bad(
            path,
            whole,
            format!(
                "is {} bytes, shorter than the {HEADER}-byte HAIR header: the file is truncated \
                 or not a .hair file",
                bytes.len()
            ),
        ));
    }
    if &bytes[..4] != b"HAIR" {
        return Err(bad(
            path,
            FileLocation::Byte(0),
            format!(
                "starts with {:?}, not the signature \"HAIR\": this is not a Cem Yuksel .hair file",
                String::from_utf8_lossy(&bytes[..4])
            ),
        ));
    }
    let hair_count = u64::from(u32_at(bytes, 4));
    let point_count = u64::from(u32_at(bytes, 8));
    let arrays = u32_at(bytes, 12);
    let d_segments = u64::from(u32_at(bytes, 16));
    if arrays & HAS_POINTS == 0 {
        return Err(bad(
            path,
            FileLocation::Byte(12),
            format!(
                "`arrays` = {arrays} has no point array (bit 2): there are no positions to import"
            ),
        ));
    }
    // Size the header claims, in u64 so no count can overflow it.
    let mut needed = HEADER as u64;
    if arrays & HAS_SEGMENTS != 0 {
        needed += 2 * hair_count;
    }
    let per_point: u64 = [
        (HAS_POINTS, 12),
        (HAS_THICKNESS, 4),
        (HAS_TRANSPARENCY, 4),
        (HAS_COLORS, 12),
    ]
    .iter()
    .filter(|(bit, _)| arrays & bit != 0)
    .map(|(_, size)| size)
    .sum();
    needed += per_point * point_count;
    if needed > bytes.len() as u64 {
        return Err(bad(
            path,
            whole,
            format!(
                "the header claims {hair_count} strands and {point_count} points (arrays = \
                 {arrays}), which need {needed} bytes, but the file has {}: it is truncated or \
                 its header is wrong",
                bytes.len()
            ),
        ));
    }
    // Point counts per strand, checked against point_count before any curve is allocated.
    let segments_at = |s: usize| HEADER + 2 * s;
    let segments = |s: usize| -> u64 {
        if arrays & HAS_SEGMENTS != 0 {
            u64::from(u16::from_le_bytes([
                bytes[segments_at(s)],
                bytes[segments_at(s) + 1],
            ]))
        } else {
            d_segments
        }
    };
    // Without a segments array every strand has `d_segments`: checked at once, not per strand
    // (a header may claim 4 billion strands).
    if arrays & HAS_SEGMENTS == 0 && hair_count > 0 && d_segments == 0 {
        return Err(bad(
            path,
            FileLocation::Byte(16),
            "d_segments = 0 (1 point per strand) and no segments array; a strand needs at least \
             2 points",
        ));
    }
    let (mut total, listed) = if arrays & HAS_SEGMENTS == 0 {
        (hair_count * (d_segments + 1), 0)
    } else {
        // The array lies inside the file (checked above): at most half its bytes.
        (0, hair_count as usize)
    };
    for s in 0..listed {
        let seg = segments(s);
        if seg == 0 {
            return Err(bad(
                path,
                FileLocation::Byte(segments_at(s) as u64),
                format!("strand {s} has 0 segments (1 point); a strand needs at least 2 points"),
            ));
        }
        total += seg + 1;
    }
    if total != point_count {
        return Err(bad(
            path,
            FileLocation::Byte(8),
            format!(
                "point_count = {point_count} but the strands' segment counts add up to {total} \
                 points: the header and the segments array disagree"
            ),
        ));
    }
    let points_start = HEADER
        + if arrays & HAS_SEGMENTS != 0 {
            2 * hair_count as usize
        } else {
            0
        };
    let mut curves = Vec::with_capacity(hair_count as usize);
    let mut at = points_start;
    for s in 0..hair_count as usize {
        let n = segments(s) as usize + 1;
        let mut curve = Vec::with_capacity(n);
        for i in 0..n {
            let p = point_at(bytes, at, path, &format!("strand {s} point {i}"))?;
            curve.push(to_world(p, opts));
            at += 12;
        }
        curves.push(curve);
    }
    Groom::new(curves)
}

/// The `.hair` bytes of `groom`.
fn encode(groom: &Groom, opts: &ImportOptions) -> Result<Vec<u8>, GroomError> {
    let mut segments = Vec::with_capacity(groom.len());
    for (c, curve) in groom.curves().iter().enumerate() {
        let seg = u16::try_from(curve.len() - 1).map_err(|_| GroomError::Curve {
            curve: c,
            message: format!(
                "has {} points; a .hair strand holds at most 65 536: resample or cut it",
                curve.len()
            ),
        })?;
        segments.push(seg);
    }
    let too_many = |what: &str, n: usize| GroomError::Curve {
        curve: 0,
        message: format!("the groom has {n} {what}; a .hair file holds at most 2³² − 1: split it"),
    };
    let hair_count = u32::try_from(groom.len()).map_err(|_| too_many("strands", groom.len()))?;
    let point_count =
        u32::try_from(groom.point_count()).map_err(|_| too_many("points", groom.point_count()))?;
    let mut out = Vec::with_capacity(HEADER + 2 * segments.len() + 12 * groom.point_count());
    out.extend_from_slice(b"HAIR");
    out.extend_from_slice(&hair_count.to_le_bytes());
    out.extend_from_slice(&point_count.to_le_bytes());
    out.extend_from_slice(&(HAS_SEGMENTS | HAS_POINTS).to_le_bytes());
    let d_segments = segments.first().copied().map_or(0, u32::from);
    out.extend_from_slice(&d_segments.to_le_bytes());
    for v in [1.0f32, 0.0, 1.0, 1.0, 1.0] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    let mut info = [0u8; 88];
    info[..7].copy_from_slice(b"hairsys");
    out.extend_from_slice(&info);
    for s in segments {
        out.extend_from_slice(&s.to_le_bytes());
    }
    for p in groom.curves().iter().flatten() {
        for c in to_file(p, opts) {
            out.extend_from_slice(&c.to_le_bytes());
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
            vec![Vector3::new(0.1, -0.2, 0.3), Vector3::new(1e-7, 2.5, -3.25)],
            vec![
                Vector3::new(1.0, 2.0, 3.0),
                Vector3::new(f32::MIN_POSITIVE, -0.0, 7.0),
                Vector3::new(0.333_333_34, 1e30, -1e-30),
            ],
        ])
        .unwrap()
    }

    #[test]
    fn write_then_read_is_bit_exact() {
        assert_round_trip(&groom(), |g, opts| {
            let bytes = encode(g, opts).unwrap();
            let back = parse(&bytes, Path::new("mem.hair"), opts).unwrap();
            // And the bytes of a second write are the same.
            assert_eq!(encode(&back, opts).unwrap(), bytes);
            back
        });
    }

    fn parse_err(bytes: &[u8]) -> String {
        parse(bytes, Path::new("bad.hair"), &ImportOptions::default())
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn bad_files_are_refused_with_file_and_offset() {
        let good = encode(&groom(), &ImportOptions::default()).unwrap();
        let msg = parse_err(&good[..100]);
        assert!(
            msg.contains("bad.hair") && msg.contains("truncated"),
            "{msg}"
        );
        let mut wrong = good.clone();
        wrong[..4].copy_from_slice(b"HAIX");
        let msg = parse_err(&wrong);
        assert!(
            msg.contains("at byte 0") && msg.contains("signature"),
            "{msg}"
        );
        // Truncated point data.
        let msg = parse_err(&good[..good.len() - 4]);
        assert!(msg.contains("need") && msg.contains("truncated"), "{msg}");
        // Counts claiming 4 billion strands: refused from the size, nothing allocated.
        let mut huge = good.clone();
        huge[4..8].copy_from_slice(&u32::MAX.to_le_bytes());
        huge[8..12].copy_from_slice(&u32::MAX.to_le_bytes());
        let msg = parse_err(&huge);
        assert!(msg.contains("4294967295 strands"), "{msg}");
        // Segment counts that disagree with point_count.
        let mut off = good.clone();
        off[HEADER..HEADER + 2].copy_from_slice(&2u16.to_le_bytes());
        let msg = parse_err(&off);
        assert!(msg.contains("disagree"), "{msg}");
        // A one-point strand.
        let mut one = good.clone();
        one[HEADER..HEADER + 2].copy_from_slice(&0u16.to_le_bytes());
        let msg = parse_err(&one);
        assert!(
            msg.contains("strand 0 has 0 segments") && msg.contains("byte 128"),
            "{msg}"
        );
        // NaN coordinate: strand 1 point 1, x.
        let mut nan = good.clone();
        let at = HEADER + 4 + 12 * 3;
        nan[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
        let msg = parse_err(&nan);
        assert!(
            msg.contains("strand 1 point 1") && msg.contains(&format!("byte {at}")),
            "{msg}"
        );
        // No point array.
        let mut none = good.clone();
        none[12..16].copy_from_slice(&HAS_SEGMENTS.to_le_bytes());
        assert!(parse_err(&none).contains("no point array"));
        // Garbage.
        assert!(parse_err(&[0x5a; 300]).contains("signature"));
        assert!(parse_err(&[]).contains("0 bytes"));
    }

    #[test]
    fn default_segments_apply_without_the_array() {
        let mut bytes = Vec::new();
        bytes.extend_from_slice(b"HAIR");
        for v in [2u32, 4, HAS_POINTS, 1] {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
        bytes.resize(HEADER, 0);
        for i in 0..12 {
            bytes.extend_from_slice(&(i as f32).to_le_bytes());
        }
        let g = parse(&bytes, Path::new("d.hair"), &ImportOptions::default()).unwrap();
        assert_eq!(g.len(), 2);
        assert_eq!(g.curves()[1][1], Vector3::new(9.0, 10.0, 11.0));
    }

    #[test]
    fn four_billion_strands_without_a_segments_array_are_refused_at_once() {
        // 2³² − 1 strands of `d_segments` = 1 and 2 points: the sum is checked without a loop
        // over the strands (which took seconds).
        let mut bytes = Vec::new();
        bytes.extend_from_slice(b"HAIR");
        for v in [u32::MAX, 2, HAS_POINTS, 1] {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
        bytes.resize(HEADER + 24, 0);
        let start = std::time::Instant::now();
        let msg = parse_err(&bytes);
        assert!(msg.contains("add up to 8589934590 points"), "{msg}");
        assert!(start.elapsed().as_secs_f64() < 0.1);
        bytes[16..20].copy_from_slice(&0u32.to_le_bytes());
        assert!(parse_err(&bytes).contains("d_segments = 0"));
    }

    #[test]
    fn every_truncation_and_byte_corruption_is_an_error_not_a_panic() {
        let good = encode(&groom(), &ImportOptions::default()).unwrap();
        let path = Path::new("fuzz.hair");
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
