//! What a preview draws: strands (flat positions and offsets, as [`hair_core::StrandSet`], the
//! cache and [`crate::Parents`] hold them), triangle meshes (scalp, colliders) and highlights.
//!
//! Everything is borrowed from the caller and checked once when built, naming the strand, mesh or
//! array at fault, so the rasteriser never meets a bad index or a non-finite coordinate.

use hair_core::TriMesh;
use nalgebra::Vector3;

use super::error::{Nothing, PreviewError, PreviewInputError, Result};

/// Linear RGB color, each channel in [0, 1].
pub type Rgb = [f32; 3];

/// Strands to draw: strand `s` owns `positions[offsets[s]..offsets[s + 1]]`, root first.
#[derive(Debug, Clone, Copy)]
pub struct Strands<'a> {
    positions: &'a [Vector3<f32>],
    offsets: &'a [u32],
    radii: Option<&'a [f32]>,
    colors: Option<&'a [Rgb]>,
}

impl<'a> Strands<'a> {
    /// Strands from flat world positions (meters, Z up) and offsets (`offsets[0] = 0`, one more
    /// entry than strands, non-decreasing, the last equal to `positions.len()`). Every strand
    /// needs ≥ 2 points and finite coordinates; checked here, naming the strand.
    pub fn new(positions: &'a [Vector3<f32>], offsets: &'a [u32]) -> Result<Self> {
        if offsets.len() < 2 {
            return Err(PreviewError::Empty(Nothing::NoStrands));
        }
        if offsets[0] != 0 || offsets[offsets.len() - 1] as usize != positions.len() {
            return Err(PreviewInputError::Offsets {
                first: offsets[0],
                last: offsets[offsets.len() - 1],
                positions: positions.len(),
            }
            .into());
        }
        for s in 0..offsets.len() - 1 {
            let (a, b) = (offsets[s] as usize, offsets[s + 1] as usize);
            if b < a + 2 {
                return Err(PreviewError::Strand {
                    strand: s,
                    message: format!(
                        "has {} point(s); a strand needs at least 2 (offsets must increase by \
                         ≥ 2)",
                        b.saturating_sub(a)
                    ),
                });
            }
            if let Some(i) = positions[a..b]
                .iter()
                .position(|v| !v.iter().all(|c| c.is_finite()))
            {
                return Err(PreviewError::Strand {
                    strand: s,
                    message: format!(
                        "point {i} has a non-finite coordinate; the simulation blew up or the \
                         cache is damaged"
                    ),
                });
            }
        }
        Ok(Self {
            positions,
            offsets,
            radii: None,
            colors: None,
        })
    }

    /// Per-point radii (meters, finite, ≥ 0), e.g. `StrandSet::radii()`: the drawn width is the
    /// projected diameter (at least the settings' minimum width). Without radii every strand
    /// takes the settings' default radius.
    pub fn with_radii(mut self, radii: &'a [f32]) -> Result<Self> {
        self.check_per_point("radii", radii.len())?;
        if let Some(i) = radii.iter().position(|r| !(r.is_finite() && *r >= 0.0)) {
            return Err(PreviewError::Strand {
                strand: self.strand_of(i),
                message: format!(
                    "radius {} m at point {i}; give a finite value ≥ 0",
                    radii[i]
                ),
            });
        }
        self.radii = Some(radii);
        Ok(self)
    }

    /// Per-point colors (linear RGB in [0, 1]) replacing the settings' root-to-tip gradient.
    pub fn with_colors(mut self, colors: &'a [Rgb]) -> Result<Self> {
        self.check_per_point("colors", colors.len())?;
        if let Some(i) = colors
            .iter()
            .position(|c| !c.iter().all(|v| v.is_finite() && (0.0..=1.0).contains(v)))
        {
            return Err(PreviewError::Strand {
                strand: self.strand_of(i),
                message: format!(
                    "color {:?} at point {i}; give linear RGB with each channel in [0, 1]",
                    colors[i]
                ),
            });
        }
        self.colors = Some(colors);
        Ok(self)
    }

    /// Number of strands.
    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Always false: [`Strands::new`] refuses an empty set.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Total number of points.
    pub fn point_count(&self) -> usize {
        self.positions.len()
    }

    /// Total number of segments (points − strands); segment `j` of strand `s` has index
    /// `offsets[s] − s + j`, as [`hair_core::StrandSet::segments`] numbers them.
    pub fn segment_count(&self) -> usize {
        self.positions.len() - self.len()
    }

    /// All positions, meters.
    pub fn positions(&self) -> &'a [Vector3<f32>] {
        self.positions
    }

    /// Point range of strand `s`.
    pub fn points(&self, s: usize) -> std::ops::Range<usize> {
        self.offsets[s] as usize..self.offsets[s + 1] as usize
    }

    /// Radius of point `i` (meters), or `default` without per-point radii.
    pub(crate) fn radius(&self, i: usize, default: f32) -> f32 {
        self.radii.map_or(default, |r| r[i])
    }

    /// Per-point colors, if given.
    pub(crate) fn colors(&self) -> Option<&'a [Rgb]> {
        self.colors
    }

    /// The strand that owns point `i` (a valid point index).
    fn strand_of(&self, i: usize) -> usize {
        self.offsets.partition_point(|&o| o as usize <= i) - 1
    }

    fn check_per_point(&self, what: &'static str, n: usize) -> Result<()> {
        if n == self.positions.len() {
            Ok(())
        } else {
            Err(PreviewInputError::PerPoint {
                what,
                found: n,
                points: self.positions.len(),
            }
            .into())
        }
    }
}

/// Owned strand arrays, for hair that does not come as positions and offsets already (render
/// children); [`StrandBuffers::strands`] borrows them as [`Strands`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StrandBuffers {
    /// Point positions, meters.
    pub positions: Vec<Vector3<f32>>,
    /// Strand offsets (one more than strands).
    pub offsets: Vec<u32>,
    /// Per-point radii, meters.
    pub radii: Vec<f32>,
    /// Per-point colors (linear RGB), if any.
    pub colors: Option<Vec<Rgb>>,
}

impl StrandBuffers {
    /// Render children ([`crate::ChildBuffers`]) as strands: radius half their width, and their
    /// root color (from the scalp's vertex colors) on every point when they have one.
    pub fn from_children(children: &crate::ChildBuffers) -> Result<Self> {
        let points = children.point_count();
        if children.points.len() != 3 * points {
            return Err(PreviewInputError::ChildCoordinates {
                coordinates: children.points.len(),
                points,
            }
            .into());
        }
        let mut offsets = Vec::with_capacity(children.curve_count() + 1);
        offsets.push(0u32);
        let mut end = 0u64;
        for &n in &children.vertex_counts {
            end += u64::from(n);
            offsets.push(u32::try_from(end).unwrap_or(u32::MAX));
        }
        if end != points as u64 {
            return Err(PreviewInputError::ChildVertexCounts {
                counted: end,
                points,
            }
            .into());
        }
        let colors = match &children.color {
            Some(c) if c.len() == 3 * children.curve_count() => Some(
                children
                    .vertex_counts
                    .iter()
                    .zip(c.chunks_exact(3))
                    .flat_map(|(&n, rgb)| std::iter::repeat_n([rgb[0], rgb[1], rgb[2]], n as usize))
                    .collect(),
            ),
            Some(c) => {
                return Err(PreviewInputError::ChildColors {
                    values: c.len(),
                    curves: children.curve_count(),
                }
                .into())
            }
            None => None,
        };
        Ok(Self {
            positions: children
                .points
                .chunks_exact(3)
                .map(|p| Vector3::new(p[0], p[1], p[2]))
                .collect(),
            offsets,
            radii: children.widths.iter().map(|w| 0.5 * w).collect(),
            colors,
        })
    }

    /// The buffers as checked [`Strands`].
    pub fn strands(&self) -> Result<Strands<'_>> {
        let s = Strands::new(&self.positions, &self.offsets)?.with_radii(&self.radii)?;
        match &self.colors {
            Some(c) => s.with_colors(c),
            None => Ok(s),
        }
    }
}

/// A triangle mesh to draw shaded (scalp, collider), in world space at the drawn instant.
#[derive(Debug, Clone, Copy)]
pub struct Mesh<'a> {
    positions: &'a [Vector3<f32>],
    triangles: &'a [[u32; 3]],
    color: Rgb,
}

impl<'a> Mesh<'a> {
    /// A mesh of `positions` (meters) and `triangles` (vertex indices, any winding: both sides
    /// are lit, so open meshes such as a scalp patch look right from behind), drawn in `color`
    /// (linear RGB in [0, 1]). Checks indices and coordinates; `index` is the mesh's number in
    /// error messages.
    pub fn new(
        index: usize,
        positions: &'a [Vector3<f32>],
        triangles: &'a [[u32; 3]],
        color: Rgb,
    ) -> Result<Self> {
        let fail = |message: String| PreviewError::Mesh {
            mesh: index,
            message,
        };
        if triangles.is_empty() {
            return Err(fail(
                "has no triangles; leave it out of the scene or give its faces".into(),
            ));
        }
        if let Some(v) = positions
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(fail(format!("vertex {v} has a non-finite coordinate")));
        }
        if let Some(t) = triangles
            .iter()
            .position(|t| t.iter().any(|&v| v as usize >= positions.len()))
        {
            return Err(fail(format!(
                "triangle {t} {:?} indexes past its {} vertices",
                triangles[t],
                positions.len()
            )));
        }
        if !color
            .iter()
            .all(|c| c.is_finite() && (0.0..=1.0).contains(c))
        {
            return Err(fail(format!(
                "color {color:?}; give linear RGB with each channel in [0, 1]"
            )));
        }
        Ok(Self {
            positions,
            triangles,
            color,
        })
    }

    /// A [`TriMesh`] (already valid) drawn in `color`; `index` as in [`Mesh::new`].
    pub fn from_trimesh(index: usize, mesh: &'a TriMesh, color: Rgb) -> Result<Self> {
        Self::new(index, mesh.positions(), mesh.triangles(), color)
    }

    /// Vertex positions, meters.
    pub fn positions(&self) -> &'a [Vector3<f32>] {
        self.positions
    }

    /// Triangles (vertex indices).
    pub fn triangles(&self) -> &'a [[u32; 3]] {
        self.triangles
    }

    /// Color, linear RGB.
    pub fn color(&self) -> Rgb {
        self.color
    }

    /// Axis-aligned bounds of the vertices the triangles use.
    pub fn bounds(&self) -> Bounds {
        Bounds::of_points(
            self.triangles
                .iter()
                .flatten()
                .map(|&v| self.positions[v as usize]),
        )
        .expect("a checked mesh has at least one triangle")
    }
}

/// Problems to mark in red on top of everything (`hairsys preview --highlight`).
#[derive(Debug, Clone, Copy, Default)]
pub struct Highlight<'a> {
    /// Per point, true where the point is inside a collider (drawn as a red dot).
    pub points: Option<&'a [bool]>,
    /// Per segment (numbered as [`Strands::segment_count`] says), true where the segment is
    /// over-stretched (drawn as a red line).
    pub segments: Option<&'a [bool]>,
}

/// Everything one preview image shows.
#[derive(Debug, Clone, Default)]
pub struct Scene<'a> {
    /// The strands, if any.
    pub strands: Option<Strands<'a>>,
    /// Shaded meshes (scalp, colliders), drawn first and hiding the hair behind them.
    pub meshes: Vec<Mesh<'a>>,
    /// Red marks drawn last, on top of everything; needs `strands`.
    pub highlight: Highlight<'a>,
}

impl Scene<'_> {
    /// Bounds of every strand point and mesh vertex drawn; `None` for an empty scene.
    pub fn bounds(&self) -> Option<Bounds> {
        let strands = self.strands.iter().flat_map(|s| s.positions().iter());
        let meshes = self.meshes.iter().flat_map(|m| {
            m.triangles()
                .iter()
                .flatten()
                .map(|&v| &m.positions()[v as usize])
        });
        Bounds::of_points(strands.chain(meshes).copied())
    }

    /// Checks that the highlight arrays fit the strands and that there is something to draw.
    pub(crate) fn validate(&self) -> Result<()> {
        if self.strands.is_none() && self.meshes.is_empty() {
            return Err(PreviewError::Empty(Nothing::NoStrandsOrMeshes));
        }
        let h = &self.highlight;
        if h.points.is_none() && h.segments.is_none() {
            return Ok(());
        }
        let Some(strands) = &self.strands else {
            return Err(PreviewInputError::HighlightsWithoutStrands.into());
        };
        if let Some(p) = h.points {
            if p.len() != strands.point_count() {
                return Err(PreviewInputError::HighlightPoints {
                    flags: p.len(),
                    points: strands.point_count(),
                }
                .into());
            }
        }
        if let Some(s) = h.segments {
            if s.len() != strands.segment_count() {
                return Err(PreviewInputError::HighlightSegments {
                    flags: s.len(),
                    segments: strands.segment_count(),
                }
                .into());
            }
        }
        Ok(())
    }
}

/// Axis-aligned box, meters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    /// Minimum corner.
    pub min: Vector3<f32>,
    /// Maximum corner.
    pub max: Vector3<f32>,
}

impl Bounds {
    /// The smallest box holding every point; `None` without points.
    pub fn of_points(points: impl IntoIterator<Item = Vector3<f32>>) -> Option<Self> {
        points.into_iter().fold(None, |b, p| {
            Some(match b {
                None => Bounds { min: p, max: p },
                Some(b) => Bounds {
                    min: b.min.inf(&p),
                    max: b.max.sup(&p),
                },
            })
        })
    }

    /// The smallest box holding both.
    pub fn union(&self, other: &Bounds) -> Bounds {
        Bounds {
            min: self.min.inf(&other.min),
            max: self.max.sup(&other.max),
        }
    }

    /// Centre, meters.
    pub fn centre(&self) -> Vector3<f32> {
        0.5 * (self.min + self.max)
    }

    /// True when `p` lies inside or on the box.
    pub fn contains(&self, p: &Vector3<f32>) -> bool {
        (0..3).all(|k| self.min[k] <= p[k] && p[k] <= self.max[k])
    }

    /// The eight corners.
    pub(crate) fn corners(&self) -> [Vector3<f32>; 8] {
        std::array::from_fn(|i| {
            Vector3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            )
        })
    }
}
