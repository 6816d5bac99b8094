//! The rendered picture: 8-bit sRGB RGBA pixels in memory, and its PNG encoding (the `png`
//! crate; the file is written beside its target and renamed, so a failed write leaves no
//! half-written image).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use super::error::{parameter, PngWriteError, PreviewError, PreviewInputError, Result};

/// Largest image side, pixels (a 16k × 16k RGBA image is 1 GiB).
pub const MAX_SIDE: u32 = 16_384;

/// An RGBA image, 8 bits per channel, sRGB, row-major from the top-left pixel.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PreviewImage {
    width: u32,
    height: u32,
    pixels: Vec<u8>,
}

/// Checks an image size before anything is allocated from it.
pub(crate) fn check_size(name: &'static str, width: u32, height: u32) -> Result<()> {
    if (1..=MAX_SIDE).contains(&width) && (1..=MAX_SIDE).contains(&height) {
        Ok(())
    } else {
        Err(parameter(
            name,
            format!("{width} × {height}"),
            "give each side between 1 and 16384 pixels",
        ))
    }
}

impl PreviewImage {
    /// A `width` × `height` image filled with `rgba`; sides in 1..=[`MAX_SIDE`].
    pub fn filled(width: u32, height: u32, rgba: [u8; 4]) -> Result<Self> {
        check_size("image size", width, height)?;
        let n = width as usize * height as usize;
        Ok(Self {
            width,
            height,
            pixels: rgba.repeat(n),
        })
    }

    /// An image from raw RGBA bytes (`4 · width · height` of them).
    pub fn from_rgba(width: u32, height: u32, pixels: Vec<u8>) -> Result<Self> {
        check_size("image size", width, height)?;
        if pixels.len() != 4 * width as usize * height as usize {
            return Err(PreviewInputError::Pixels {
                bytes: pixels.len(),
                width,
                height,
            }
            .into());
        }
        Ok(Self {
            width,
            height,
            pixels,
        })
    }

    /// Width, pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height, pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// RGBA bytes, row-major from the top-left.
    pub fn pixels(&self) -> &[u8] {
        &self.pixels
    }

    /// Mutable RGBA bytes.
    pub(crate) fn pixels_mut(&mut self) -> &mut [u8] {
        &mut self.pixels
    }

    /// The pixel at column `x`, row `y` (from the top); `None` outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 4]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = 4 * (y as usize * self.width as usize + x as usize);
        Some([
            self.pixels[i],
            self.pixels[i + 1],
            self.pixels[i + 2],
            self.pixels[i + 3],
        ])
    }

    /// Encodes the image as an sRGB PNG into `out`.
    pub fn encode_png<W: Write>(&self, out: W) -> Result<()> {
        Ok(self.png(out)?)
    }

    /// [`Image::encode_png`] with the encoder's own error.
    fn png<W: Write>(&self, out: W) -> std::result::Result<(), png::EncodingError> {
        let mut encoder = png::Encoder::new(out, self.width, self.height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut writer = encoder.write_header()?;
        writer.write_image_data(&self.pixels)?;
        writer.finish()
    }

    /// Writes the image as a PNG file at `path`, through a temporary file beside it that is
    /// renamed when complete (and removed on failure).
    pub fn write_png(&self, path: &Path) -> Result<()> {
        let mut tmp = path.as_os_str().to_owned();
        tmp.push(".partial");
        let tmp = std::path::PathBuf::from(tmp);
        let written = (|| -> std::result::Result<(), PngWriteError> {
            let file = File::create(&tmp)?;
            let mut out = BufWriter::new(file);
            self.png(&mut out)?;
            out.into_inner().map_err(|e| e.into_error())?.sync_all()?;
            Ok(std::fs::rename(&tmp, path)?)
        })();
        written.map_err(|source| {
            let _ = std::fs::remove_file(&tmp);
            PreviewError::Write {
                path: path.to_path_buf(),
                source,
            }
        })
    }
}
