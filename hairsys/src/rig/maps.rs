//! Painted maps over the scalp: one value per hair root, painted by an artist as a
//! texture over the scalp's UVs or as per-vertex values of the scalp mesh, and sampled where
//! each hair grows.
//!
//! **Textures** are PNG images (8- or 16-bit, grey, grey + alpha, RGB, RGBA or palette), read
//! with the `png` crate; one channel is kept as values in [0, 1]. UV (0, 0) is the image's
//! lower-left corner and (1, 1) its upper-right (the OpenGL, Blender and USD `st` convention:
//! image row 0 is v = 1), pixel centres at ((i + ½)/width, 1 − (j + ½)/height). A root's value
//! is the bilinear blend of the four pixels around its UV, with edge pixels extended half a
//! pixel to the border (clamp to edge). A UV outside [0, 1]² (another tile, a scalp unwrapped
//! for another texture) is an error naming the root, not a silent wrap.
//!
//! **Vertex values** (an OBJ scalp's vertex colours `v x y z r g b`; one channel) are blended
//! with each root's barycentric weights on its scalp triangle, exactly as the root's position
//! is: a value painted on a vertex is the value of a root at that vertex. **Corner values** (a
//! USD scalp's primvar, whatever its interpolation: [`crate::scene::map_primvars`]) are three
//! values per triangle, blended the same way, so a `faceVarying` or `uniform` primvar keeps
//! each face's own values where a vertex is shared.
//!
//! Sampling costs O(1) per root and happens once, when a scene is built. A density map is used
//! as a [`hair_groom::RootDensity`] ([`MapDensity`]): roots are drawn by rejection against its
//! largest value (see [`hair_groom::sampling`]).

use std::io::Read;
use std::path::{Path, PathBuf};

use hair_core::{MeshSample, TriMesh};
use nalgebra::Vector2;

/// Largest texture read, pixels (64 Mpx: an 8k × 8k map), so a corrupt or hostile header cannot
/// make the reader allocate gigabytes.
pub const MAX_TEXTURE_PIXELS: u64 = 1 << 26;

/// A colour channel of a texture or of vertex colours.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Channel {
    /// Red (grey images: the grey value).
    #[default]
    R,
    /// Green.
    G,
    /// Blue.
    B,
    /// Alpha (1 for images without alpha).
    A,
}

impl Channel {
    /// The channel named `name` (`"r"`, `"g"`, `"b"`, `"a"`).
    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "r" => Some(Self::R),
            "g" => Some(Self::G),
            "b" => Some(Self::B),
            "a" => Some(Self::A),
            _ => None,
        }
    }

    fn index(self) -> usize {
        match self {
            Self::R => 0,
            Self::G => 1,
            Self::B => 2,
            Self::A => 3,
        }
    }
}

/// One channel of an image, values in [0, 1], rows from the top of the image.
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    width: usize,
    height: usize,
    values: Vec<f32>,
}

impl Texture {
    /// A texture of `width × height` values (rows from the top, each in [0, 1]); `None` when
    /// the sizes disagree or a size is 0.
    pub fn new(width: usize, height: usize, values: Vec<f32>) -> Option<Self> {
        (width > 0 && height > 0 && width.checked_mul(height) == Some(values.len())).then_some(
            Self {
                width,
                height,
                values,
            },
        )
    }

    /// Reads `channel` of the PNG file at `path`. Errors say what is wrong with the file.
    pub fn read_png(path: &Path, channel: Channel) -> Result<Self, MapError> {
        let file = std::fs::File::open(path).map_err(MapError::Open)?;
        Self::decode_png(std::io::BufReader::new(file), channel)
    }

    /// Decodes `channel` of a PNG stream.
    pub fn decode_png(reader: impl Read, channel: Channel) -> Result<Self, MapError> {
        let mut decoder = png::Decoder::new_with_limits(
            reader,
            png::Limits {
                // 16-bit RGBA at the pixel limit.
                bytes: (MAX_TEXTURE_PIXELS * 8) as usize,
            },
        );
        // Palette images to RGB(A), low bit depths to 8 bits, tRNS to alpha.
        decoder.set_transformations(png::Transformations::EXPAND);
        let mut reader = decoder.read_info().map_err(MapError::NotPng)?;
        let (width, height) = {
            let info = reader.info();
            (info.width as u64, info.height as u64)
        };
        if width * height > MAX_TEXTURE_PIXELS {
            return Err(MapError::TooLarge { width, height });
        }
        let mut buf = vec![0u8; reader.output_buffer_size()];
        let frame = reader.next_frame(&mut buf).map_err(MapError::Pixels)?;
        let channels = match frame.color_type {
            png::ColorType::Grayscale => 1,
            png::ColorType::GrayscaleAlpha => 2,
            png::ColorType::Rgb => 3,
            png::ColorType::Rgba => 4,
            png::ColorType::Indexed => return Err(MapError::Palette),
        };
        let wide = frame.bit_depth == png::BitDepth::Sixteen;
        let bytes = if wide { 2 } else { 1 };
        // Which stored channel holds the one asked for; `None`: the image has no alpha (1).
        let source = match (channels, channel) {
            (1 | 2, Channel::R | Channel::G | Channel::B) => Some(0),
            (2, Channel::A) => Some(1),
            (3 | 4, c) if c != Channel::A => Some(c.index()),
            (4, Channel::A) => Some(3),
            _ => None,
        };
        let (w, h) = (width as usize, height as usize);
        let mut values = Vec::with_capacity(w * h);
        for row in buf[..frame.buffer_size()].chunks_exact(frame.line_size) {
            for x in 0..w {
                let v = match source {
                    None => 1.0,
                    Some(c) => {
                        let at = (x * channels + c) * bytes;
                        if wide {
                            f32::from(u16::from_be_bytes([row[at], row[at + 1]])) / 65535.0
                        } else {
                            f32::from(row[at]) / 255.0
                        }
                    }
                };
                values.push(v);
            }
        }
        Self::new(w, h, values).ok_or(MapError::Empty)
    }

    /// Width and height, pixels.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// The value at `uv` (bilinear, clamped to the edge; see the module docs), or `None` when
    /// `uv` lies outside [0, 1]² or is not finite.
    pub fn sample(&self, uv: Vector2<f32>) -> Option<f32> {
        if !(uv.iter().all(|c| c.is_finite() && (0.0..=1.0).contains(c))) {
            return None;
        }
        // Continuous pixel coordinates whose integers are pixel centres.
        let x = uv.x * self.width as f32 - 0.5;
        let y = (1.0 - uv.y) * self.height as f32 - 0.5;
        let clamp = |c: f32, n: usize| c.clamp(0.0, (n - 1) as f32);
        let (x, y) = (clamp(x, self.width), clamp(y, self.height));
        let (x0, y0) = (x.floor() as usize, y.floor() as usize);
        let (x1, y1) = ((x0 + 1).min(self.width - 1), (y0 + 1).min(self.height - 1));
        let (fx, fy) = (x - x0 as f32, y - y0 as f32);
        let at = |i: usize, j: usize| self.values[j * self.width + i];
        let top = at(x0, y0) + (at(x1, y0) - at(x0, y0)) * fx;
        let bottom = at(x0, y1) + (at(x1, y1) - at(x0, y1)) * fx;
        Some(top + (bottom - top) * fy)
    }
}

/// Why a texture cannot be read or a map cannot be used on a scalp. Messages name the map (or
/// the image) and the fix.
#[derive(Debug, thiserror::Error)]
pub enum MapError {
    /// The image file cannot be opened.
    #[error("cannot open it ({0})")]
    Open(#[source] std::io::Error),
    /// The image is not a PNG this reader can decode.
    #[error("not a readable PNG ({0})")]
    NotPng(#[source] png::DecodingError),
    /// The image's pixels cannot be decoded.
    #[error("cannot decode its pixels ({0})")]
    Pixels(#[source] png::DecodingError),
    /// The image has more pixels than a map may have.
    #[error(
        "{width} × {height} pixels is more than the {MAX_TEXTURE_PIXELS} a map may have; scale \
         the image down"
    )]
    TooLarge {
        /// Width, pixels.
        width: u64,
        /// Height, pixels.
        height: u64,
    },
    /// A palette image was not expanded to colours.
    #[error("its palette was not expanded; save it as RGB or grey")]
    Palette,
    /// The image has no pixels.
    #[error("has no pixels")]
    Empty,
    /// A texture on a scalp without UVs.
    #[error(
        "[maps.{map}] texture {}: the scalp mesh has no UVs to place it with; give the scalp \
         UVs (OBJ `vt`, USD primvars:st) or paint vertex values",
        path.display()
    )]
    NoUvs {
        /// The map's name.
        map: String,
        /// The texture.
        path: PathBuf,
    },
    /// Vertex values of another mesh.
    #[error(
        "[maps.{map}] has {values} vertex values but the scalp mesh has {vertices} vertices: \
         paint the map on the scalp mesh the scene uses"
    )]
    VertexCount {
        /// The map's name.
        map: String,
        /// Values given.
        values: usize,
        /// The scalp's vertices.
        vertices: usize,
    },
    /// Corner values of another mesh.
    #[error(
        "[maps.{map}] has values on {values} triangles but the scalp mesh has {triangles}: \
         paint the map on the scalp mesh the scene uses"
    )]
    TriangleCount {
        /// The map's name.
        map: String,
        /// Triangles with values.
        values: usize,
        /// The scalp's triangles.
        triangles: usize,
    },
    /// A value that is not finite.
    #[error("[maps.{map}] {at} has the value{value}; paint finite values")]
    NotFinite {
        /// The map's name.
        map: String,
        /// Where: `vertex i` or `triangle i`.
        at: String,
        /// The value(s), printed with a leading space or `s ` for several.
        value: String,
    },
    /// A root whose UV lies outside the texture.
    #[error(
        "[maps.{map}] texture {}: {root} is at UV ({}, {}), outside the texture's [0, 1]²: \
         unwrap the scalp into one UV tile or paint vertex values",
        path.display(),
        uv.x,
        uv.y
    )]
    OutsideUv {
        /// The map's name.
        map: String,
        /// The texture.
        path: PathBuf,
        /// The hair, in words (`sim hair 12`).
        root: String,
        /// Its UV.
        uv: Vector2<f32>,
    },
    /// A density map with a negative value.
    #[error(
        "[maps.{map}] is {value} at {at}: a density is ≥ 0 (0 = no hair, the largest value = \
         the densest hair); paint values ≥ 0"
    )]
    NegativeDensity {
        /// The map's name.
        map: String,
        /// The value.
        value: f32,
        /// Where: `vertex i` or `a corner of triangle t`.
        at: String,
    },
    /// A density map that is zero everywhere.
    #[error(
        "[maps.{map}] is 0 everywhere: no hair would grow; paint values > 0 where hair grows \
         (the count is spread over the painted area by its value) or remove the map"
    )]
    NoDensity {
        /// The map's name.
        map: String,
    },
}

/// Where a map's values come from.
#[derive(Debug, Clone, PartialEq)]
pub enum MapSource {
    /// A texture over the scalp's UVs, read from `path`.
    Texture {
        /// The image file (for messages).
        path: PathBuf,
        /// Its values.
        texture: Texture,
    },
    /// One value per scalp vertex, in the scalp mesh's vertex order.
    Vertex(Vec<f32>),
    /// Values at the three corners of every scalp triangle, in the scalp mesh's triangle order
    /// (a USD primvar of any interpolation: see [`crate::scene::map_primvars`]).
    Corners(Vec<[f32; 3]>),
}

/// A painted map: a name (for messages and selections) and its values over the scalp.
#[derive(Debug, Clone, PartialEq)]
pub struct ScalpMap {
    name: String,
    source: MapSource,
}

impl ScalpMap {
    /// The map `name` from `source`, checked against `mesh` (the scalp at rest): a texture
    /// needs the scalp's UVs, vertex values one finite value per vertex. Errors name the map
    /// and the fix.
    pub fn new(name: &str, source: MapSource, mesh: &TriMesh) -> Result<Self, MapError> {
        let map = name.to_string();
        match &source {
            MapSource::Texture { path, .. } => {
                if mesh.uvs().is_none() {
                    return Err(MapError::NoUvs {
                        map,
                        path: path.clone(),
                    });
                }
            }
            MapSource::Vertex(values) => {
                let n = mesh.positions().len();
                if values.len() != n {
                    return Err(MapError::VertexCount {
                        map,
                        values: values.len(),
                        vertices: n,
                    });
                }
                if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                    return Err(MapError::NotFinite {
                        map,
                        at: format!("vertex {i}"),
                        value: format!(" {}", values[i]),
                    });
                }
            }
            MapSource::Corners(values) => {
                let n = mesh.triangles().len();
                if values.len() != n {
                    return Err(MapError::TriangleCount {
                        map,
                        values: values.len(),
                        triangles: n,
                    });
                }
                if let Some(i) = values.iter().position(|v| !v.iter().all(|x| x.is_finite())) {
                    return Err(MapError::NotFinite {
                        map,
                        at: format!("triangle {i}"),
                        value: format!("s {:?}", values[i]),
                    });
                }
            }
        }
        Ok(Self {
            name: name.to_string(),
            source,
        })
    }

    /// The map's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Where its values come from.
    pub fn source(&self) -> &MapSource {
        &self.source
    }

    /// The map's value at a root (`sample` on `mesh`, the mesh the map was checked against).
    /// `root` names the hair in an error: a texture where the root's UV lies outside [0, 1]².
    pub fn at(&self, mesh: &TriMesh, sample: &MeshSample, root: &str) -> Result<f32, MapError> {
        match &self.source {
            MapSource::Vertex(values) => {
                let tri = mesh.triangles()[sample.triangle as usize];
                Ok(tri
                    .iter()
                    .zip(sample.weights)
                    .map(|(&i, w)| values[i as usize] * w)
                    .sum())
            }
            MapSource::Corners(values) => Ok(values[sample.triangle as usize]
                .iter()
                .zip(sample.weights)
                .map(|(v, w)| v * w)
                .sum()),
            MapSource::Texture { path, texture } => {
                let uv = mesh
                    .sample_uv(sample)
                    .unwrap_or_else(|| Vector2::repeat(f32::NAN));
                texture.sample(uv).ok_or_else(|| MapError::OutsideUv {
                    map: self.name.clone(),
                    path: path.clone(),
                    root: root.to_string(),
                    uv,
                })
            }
        }
    }

    /// The least and largest value the map can take anywhere on the scalp: over the texture's
    /// pixels (bilinear blends stay between them) or the vertex values.
    pub fn bounds(&self) -> [f32; 2] {
        let values = match &self.source {
            MapSource::Vertex(values) => values.as_slice(),
            MapSource::Texture { texture, .. } => texture.values.as_slice(),
            MapSource::Corners(corners) => corners.as_flattened(),
        };
        values
            .iter()
            .fold([f32::INFINITY, f32::NEG_INFINITY], |[lo, hi], &v| {
                [lo.min(v), hi.max(v)]
            })
    }

    /// The map at every sample of `samples` (one per hair; `what` names the hairs, e.g.
    /// "sim hair").
    pub fn at_roots(
        &self,
        mesh: &TriMesh,
        samples: &[MeshSample],
        what: &str,
    ) -> Result<Vec<f32>, MapError> {
        samples
            .iter()
            .enumerate()
            .map(|(i, s)| self.at(mesh, s, &format!("{what} {i}")))
            .collect()
    }
}

/// A map as the density of roots on the scalp it was checked against ([`hair_groom::RootDensity`]):
/// roots grow ∝ area × the map, relative to its largest value.
pub struct MapDensity<'a> {
    map: &'a ScalpMap,
    mesh: &'a TriMesh,
    max: f32,
}

impl<'a> MapDensity<'a> {
    /// The density of `map` on `mesh` (the mesh the map was checked against). Errors name the
    /// map: a negative value (naming the vertex, or the texture), or 0 everywhere (no hair would
    /// grow).
    pub fn new(map: &'a ScalpMap, mesh: &'a TriMesh) -> Result<Self, MapError> {
        let negative = match &map.source {
            MapSource::Vertex(values) => values
                .iter()
                .position(|v| *v < 0.0)
                .map(|i| (values[i], format!("vertex {i}"))),
            MapSource::Corners(corners) => corners
                .iter()
                .position(|c| c.iter().any(|v| *v < 0.0))
                .map(|t| {
                    let v = corners[t].iter().copied().fold(f32::INFINITY, f32::min);
                    (v, format!("a corner of triangle {t}"))
                }),
            // PNG values are in [0, 1].
            MapSource::Texture { .. } => None,
        };
        if let Some((v, at)) = negative {
            return Err(MapError::NegativeDensity {
                map: map.name.clone(),
                value: v,
                at,
            });
        }
        let [_, max] = map.bounds();
        if max.is_nan() || max <= 0.0 {
            return Err(MapError::NoDensity {
                map: map.name.clone(),
            });
        }
        Ok(Self { map, mesh, max })
    }
}

impl hair_groom::RootDensity for MapDensity<'_> {
    fn at(&self, sample: &MeshSample) -> Result<f32, hair_groom::DensityValueError> {
        Ok(self.map.at(self.mesh, sample, "a candidate root")?)
    }

    fn max(&self) -> f32 {
        self.max
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2 × 2 texture with distinct corners: (0,0) top-left.
    fn corners() -> Texture {
        Texture::new(2, 2, vec![0.0, 1.0, 0.25, 0.5]).unwrap()
    }

    #[test]
    fn pixel_centres_give_their_pixel_and_the_middle_the_mean() {
        let t = corners();
        // Row 0 is the top of the image, v = 1.
        assert_eq!(t.sample(Vector2::new(0.25, 0.75)), Some(0.0));
        assert_eq!(t.sample(Vector2::new(0.75, 0.75)), Some(1.0));
        assert_eq!(t.sample(Vector2::new(0.25, 0.25)), Some(0.25));
        assert_eq!(t.sample(Vector2::new(0.75, 0.25)), Some(0.5));
        let mid = t.sample(Vector2::new(0.5, 0.5)).unwrap();
        assert!((mid - (0.0 + 1.0 + 0.25 + 0.5) / 4.0).abs() < 1e-6);
        // Clamped to the edge: the corner of the image is its corner pixel.
        assert_eq!(t.sample(Vector2::new(0.0, 1.0)), Some(0.0));
    }

    #[test]
    fn uv_outside_the_unit_square_is_refused() {
        let t = corners();
        assert_eq!(t.sample(Vector2::new(1.01, 0.5)), None);
        assert_eq!(t.sample(Vector2::new(0.5, -0.1)), None);
        assert_eq!(t.sample(Vector2::new(f32::NAN, 0.5)), None);
    }

    #[test]
    fn a_texture_whose_size_does_not_match_its_values_is_refused() {
        assert!(Texture::new(3, 2, vec![0.0; 5]).is_none());
        assert!(Texture::new(0, 0, vec![]).is_none());
    }

    #[test]
    fn sixteen_bit_grey_and_rgba_pngs_decode_to_their_values() {
        let mut bytes = Vec::new();
        {
            let mut enc = png::Encoder::new(&mut bytes, 2, 1);
            enc.set_color(png::ColorType::Grayscale);
            enc.set_depth(png::BitDepth::Sixteen);
            let mut w = enc.write_header().unwrap();
            w.write_image_data(&[0x00, 0x00, 0xff, 0xff]).unwrap();
        }
        let t = Texture::decode_png(&bytes[..], Channel::G).unwrap();
        assert_eq!(t.values, vec![0.0, 1.0]);
        assert_eq!(
            Texture::decode_png(&bytes[..], Channel::A).unwrap().values,
            vec![1.0, 1.0]
        );
        let mut bytes = Vec::new();
        {
            let mut enc = png::Encoder::new(&mut bytes, 1, 1);
            enc.set_color(png::ColorType::Rgba);
            enc.set_depth(png::BitDepth::Eight);
            let mut w = enc.write_header().unwrap();
            w.write_image_data(&[0, 51, 102, 255]).unwrap();
        }
        let t = Texture::decode_png(&bytes[..], Channel::B).unwrap();
        assert_eq!(t.values, vec![102.0 / 255.0]);
    }

    #[test]
    fn a_file_that_is_not_png_is_a_clear_error() {
        let e = Texture::decode_png(&b"P6 not a png"[..], Channel::R)
            .unwrap_err()
            .to_string();
        assert!(e.contains("not a readable PNG"), "{e}");
    }
}
