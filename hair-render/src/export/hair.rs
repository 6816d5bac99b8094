//! Cem Yuksel's `.hair` (from `cyHairFile.h`, little endian), written with per-point thickness and,
//! when the children have colors, per-point colors.
//!
//! Layout: a 128-byte header (`"HAIR"`, `u32` hair count, `u32` point count, `u32` array flags,
//! `u32` default segments, `f32` default thickness, `f32` default transparency, `f32[3]` default
//! color, `char[88]` info), then `u16` segments per hair (points − 1), `f32[3]` points, `f32`
//! thickness per point (the child's width, meters) and, if present, `f32[3]` colors per point
//! (each child's root color repeated). Coordinates are meters, Z up, as generated; the reader in
//! `hair_groom::read_hair` reads them back with default options.

use std::io::Write;
use std::path::Path;

use super::write_atomically;
use crate::buffers::ChildBuffers;
use crate::error::{InputError, Result};

/// Header size, bytes.
const HEADER: usize = 128;
/// Array flags: segments, points, thickness, colors.
const SEGMENTS: u32 = 1;
const POINTS: u32 = 2;
const THICKNESS: u32 = 4;
const COLORS: u32 = 16;

/// Writes `children` to `out` as a `.hair` stream. Refuses a child of more than 65 536 points
/// (the format's `u16` segment count) or no children at all.
pub fn write_hair<W: Write>(mut out: W, children: &ChildBuffers) -> Result<()> {
    if children.curve_count() == 0 {
        return Err(InputError::NoChildren.into());
    }
    let mut segments = Vec::with_capacity(2 * children.curve_count());
    for (c, &n) in children.vertex_counts.iter().enumerate() {
        let s = u16::try_from(n.saturating_sub(1)).map_err(|_| InputError::HairStrandPoints {
            child: c,
            points: n,
        })?;
        segments.extend_from_slice(&s.to_le_bytes());
    }
    let points = u32::try_from(children.point_count()).map_err(|_| InputError::HairFilePoints)?;
    let mut flags = SEGMENTS | POINTS | THICKNESS;
    if children.color.is_some() {
        flags |= COLORS;
    }
    let mut header = Vec::with_capacity(HEADER);
    header.extend_from_slice(b"HAIR");
    header.extend_from_slice(&(children.curve_count() as u32).to_le_bytes());
    header.extend_from_slice(&points.to_le_bytes());
    header.extend_from_slice(&flags.to_le_bytes());
    header.extend_from_slice(&children.vertex_counts[0].saturating_sub(1).to_le_bytes());
    for v in [1.0f32, 0.0, 1.0, 1.0, 1.0] {
        header.extend_from_slice(&v.to_le_bytes());
    }
    let mut info = [0u8; 88];
    info[..16].copy_from_slice(b"hairsys children");
    header.extend_from_slice(&info);
    out.write_all(&header)?;
    out.write_all(&segments)?;
    write_f32s(&mut out, &children.points)?;
    write_f32s(&mut out, &children.widths)?;
    if let Some(colors) = &children.color {
        let mut per_point = Vec::with_capacity(3 * children.point_count());
        for (rgb, &n) in colors.chunks_exact(3).zip(&children.vertex_counts) {
            for _ in 0..n {
                per_point.extend_from_slice(rgb);
            }
        }
        write_f32s(&mut out, &per_point)?;
    }
    Ok(())
}

/// Writes `children` to the `.hair` file at `path` atomically (see [`crate::export`]).
pub fn export_hair(path: &Path, children: &ChildBuffers) -> Result<()> {
    write_atomically(path, |out| write_hair(out, children))
}

/// Writes `values` little endian in blocks.
fn write_f32s<W: Write>(out: &mut W, values: &[f32]) -> Result<()> {
    let mut buf = Vec::with_capacity(4 * 4096);
    for block in values.chunks(4096) {
        buf.clear();
        for v in block {
            buf.extend_from_slice(&v.to_le_bytes());
        }
        out.write_all(&buf)?;
    }
    Ok(())
}
