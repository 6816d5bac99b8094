//! Contact sheets: several rendered frames of one size in a grid, each with a label (its frame
//! number, a time, a view name) drawn above it.
//!
//! Layout, in pixels: tiles of `w × h` in `columns` columns and `ceil(n / columns)` rows, each
//! with a [`LABEL_HEIGHT`] strip above it, separated and surrounded by [`GAP`]:
//! `width = columns · w + (columns + 1) · GAP`, `height = rows · (h + LABEL_HEIGHT) + (rows + 1) · GAP`
//! (with `columns` capped at the tile count). Text is DejaVu Sans (bundled in `assets/`, Bitstream
//! Vera licence beside it) rasterised by `ab_glyph`, so no system font is needed.

use ab_glyph::{point, Font, FontRef, PxScale, ScaleFont};

use super::error::{parameter, Nothing, PreviewError, PreviewInputError, Result};
use super::image::{check_size, PreviewImage};

/// Space between tiles and around the sheet, pixels.
pub const GAP: u32 = 6;
/// Height of the label strip above each tile, pixels.
pub const LABEL_HEIGHT: u32 = 20;
/// Label text size, pixels.
const TEXT_PX: f32 = 15.0;
/// Sheet background (sRGB).
const SHEET_RGBA: [u8; 4] = [32, 32, 36, 255];
/// Label color (sRGB).
const TEXT_RGB: [u8; 3] = [235, 235, 235];

/// DejaVu Sans (TrueType), bundled in `hair-render/assets/` with its Bitstream Vera licence:
/// the one font the labels of previews and the bench's charts are drawn in.
pub static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

/// One tile of a contact sheet.
#[derive(Debug, Clone, Copy)]
pub struct Tile<'a> {
    /// The rendered frame.
    pub image: &'a PreviewImage,
    /// Text drawn above it (e.g. `"frame 12"`); cut at the tile's width.
    pub label: &'a str,
}

/// Composes `tiles` (all the same size) into a grid of `columns` columns, row by row.
pub fn contact_sheet(tiles: &[Tile], columns: u32) -> Result<PreviewImage> {
    let Some(first) = tiles.first() else {
        return Err(PreviewError::Empty(Nothing::NoFrames));
    };
    if columns == 0 {
        return Err(parameter("columns", columns, "give at least 1 column"));
    }
    let (tw, th) = (first.image.width(), first.image.height());
    if let Some((i, t)) = tiles
        .iter()
        .enumerate()
        .find(|(_, t)| (t.image.width(), t.image.height()) != (tw, th))
    {
        return Err(PreviewInputError::TileSize {
            tile: i,
            width: t.image.width(),
            height: t.image.height(),
            first_width: tw,
            first_height: th,
        }
        .into());
    }
    let n = tiles.len() as u64;
    let cols = u64::from(columns).min(n);
    let rows = n.div_ceil(cols);
    let width = cols * u64::from(tw) + (cols + 1) * u64::from(GAP);
    let height = rows * u64::from(th + LABEL_HEIGHT) + (rows + 1) * u64::from(GAP);
    let (width, height) = (
        u32::try_from(width).unwrap_or(u32::MAX),
        u32::try_from(height).unwrap_or(u32::MAX),
    );
    check_size("contact sheet size (columns × tiles)", width, height)?;
    let mut sheet = PreviewImage::filled(width, height, SHEET_RGBA)?;
    let font = FontRef::try_from_slice(FONT).expect("the bundled font parses (tested)");
    for (i, tile) in tiles.iter().enumerate() {
        let (c, r) = (i as u32 % cols as u32, i as u32 / cols as u32);
        let x0 = GAP + c * (tw + GAP);
        let y0 = GAP + r * (th + LABEL_HEIGHT + GAP);
        blit(&mut sheet, tile.image, x0, y0 + LABEL_HEIGHT);
        draw_text(&mut sheet, &font, tile.label, x0 + 2, y0, x0 + tw);
    }
    Ok(sheet)
}

/// Copies `src` into `dst` with its top-left corner at (`x0`, `y0`) (it fits: checked by layout).
fn blit(dst: &mut PreviewImage, src: &PreviewImage, x0: u32, y0: u32) {
    let dw = dst.width() as usize;
    let row_bytes = 4 * src.width() as usize;
    for y in 0..src.height() as usize {
        let from = &src.pixels()[y * row_bytes..(y + 1) * row_bytes];
        let at = 4 * ((y0 as usize + y) * dw + x0 as usize);
        dst.pixels_mut()[at..at + row_bytes].copy_from_slice(from);
    }
}

/// Draws `text` in the label strip whose top-left is (`x0`, `y0`), clipped at column `x_end`.
fn draw_text(img: &mut PreviewImage, font: &FontRef, text: &str, x0: u32, y0: u32, x_end: u32) {
    let scaled = font.as_scaled(PxScale::from(TEXT_PX));
    let baseline = y0 as f32 + 0.5 * (LABEL_HEIGHT as f32 + scaled.ascent() + scaled.descent());
    let mut x = x0 as f32;
    let mut previous = None;
    let (w, h) = (img.width(), img.height());
    for ch in text.chars() {
        let id = scaled.glyph_id(ch);
        if let Some(p) = previous {
            x += scaled.kern(p, id);
        }
        previous = Some(id);
        let glyph = id.with_scale_and_position(scaled.scale(), point(x, baseline));
        x += scaled.h_advance(id);
        let Some(outline) = font.outline_glyph(glyph) else {
            continue;
        };
        let bounds = outline.px_bounds();
        outline.draw(|gx, gy, coverage| {
            let px = bounds.min.x as i64 + i64::from(gx);
            let py = bounds.min.y as i64 + i64::from(gy);
            if px < 0 || py < 0 || px >= i64::from(x_end.min(w)) || py >= i64::from(h) {
                return;
            }
            let i = 4 * (py as usize * w as usize + px as usize);
            let a = coverage.clamp(0.0, 1.0);
            let pixels = img.pixels_mut();
            for k in 0..3 {
                let d = f32::from(pixels[i + k]);
                pixels[i + k] = (d + (f32::from(TEXT_RGB[k]) - d) * a).round() as u8;
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bundled_font_parses_and_has_digits() {
        let font = FontRef::try_from_slice(FONT).unwrap();
        for c in "0123456789 frame".chars() {
            assert_ne!(font.glyph_id(c).0, 0, "no glyph for {c:?}");
        }
    }
}
