//! The frame buffer: linear color and depth per pixel, drawn in horizontal bands in parallel.
//!
//! Primitives are first binned by the rows they touch; each band of [`BAND_ROWS`] rows then draws
//! its primitives in order on one thread. Within a band the order is the same as a single-threaded
//! pass, so the image does not depend on the thread count.

use hair_par::prelude::*;

use super::scene::Rgb;
use super::shading::srgb8;

/// Rows per band.
pub(crate) const BAND_ROWS: usize = 16;

/// Color and depth buffers.
pub(crate) struct Canvas {
    pub width: usize,
    pub height: usize,
    /// Linear RGB per pixel, row-major from the top.
    pub color: Vec<Rgb>,
    /// Depth (meters along the view) of the nearest opaque surface per pixel, ∞ where none.
    pub depth: Vec<f32>,
}

/// One band's view of the buffers: rows `y0..y0 + color.len() / width`.
pub(crate) struct Band<'a> {
    pub width: usize,
    pub y0: usize,
    pub color: &'a mut [Rgb],
    pub depth: &'a mut [f32],
}

impl Band<'_> {
    /// Rows of this band, as pixel row indices.
    pub fn rows(&self) -> std::ops::Range<usize> {
        self.y0..self.y0 + self.color.len() / self.width
    }
}

impl Canvas {
    /// A canvas cleared to `background` and infinite depth (sizes already checked).
    pub fn new(width: usize, height: usize, background: Rgb) -> Self {
        Self {
            width,
            height,
            color: vec![background; width * height],
            depth: vec![f32::INFINITY; width * height],
        }
    }

    /// Number of bands.
    pub fn band_count(&self) -> usize {
        self.height.div_ceil(BAND_ROWS)
    }

    /// Runs `draw` on every band in parallel.
    pub fn for_each_band(&mut self, draw: impl Fn(&mut Band) + Sync + Send) {
        let w = self.width;
        self.color
            .par_chunks_mut(w * BAND_ROWS)
            .zip(self.depth.par_chunks_mut(w * BAND_ROWS))
            .enumerate()
            .for_each(|(b, (color, depth))| {
                draw(&mut Band {
                    width: w,
                    y0: b * BAND_ROWS,
                    color,
                    depth,
                })
            });
    }

    /// The image as 8-bit sRGB RGBA, opaque.
    pub fn to_rgba8(&self) -> Vec<u8> {
        // Linear values are quantised to 1/(N − 1) before the transfer function: below one
        // eighth of an 8-bit step even where sRGB is steepest (12.92 · 255 / 65535 ≈ 0.05).
        const N: usize = 1 << 16;
        let table: Vec<u8> = (0..N).map(|i| srgb8(i as f32 / (N - 1) as f32)).collect();
        let srgb8 = |c: f32| table[(c.clamp(0.0, 1.0) * (N - 1) as f32 + 0.5) as usize];
        let mut out = vec![255u8; 4 * self.color.len()];
        out.par_chunks_mut(4 * self.width)
            .zip(self.color.par_chunks(self.width))
            .for_each(|(row, src)| {
                for (px, c) in row.chunks_exact_mut(4).zip(src) {
                    px[0] = srgb8(c[0]);
                    px[1] = srgb8(c[1]);
                    px[2] = srgb8(c[2]);
                }
            });
        out
    }
}

/// Lists, per band, the primitives whose rows (inclusive pixel row range, possibly outside the
/// image) overlap it, in primitive order.
pub(crate) fn bin_by_band(
    rows: impl Iterator<Item = (i64, i64)>,
    height: usize,
    bands: usize,
) -> Vec<Vec<u32>> {
    let mut bins = vec![Vec::new(); bands];
    for (i, (y0, y1)) in rows.enumerate() {
        let y0 = y0.max(0);
        let y1 = y1.min(height as i64 - 1);
        if y0 > y1 {
            continue;
        }
        for bin in &mut bins[y0 as usize / BAND_ROWS..=y1 as usize / BAND_ROWS] {
            bin.push(i as u32);
        }
    }
    bins
}
