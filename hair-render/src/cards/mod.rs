//! Hair cards: the ribbon surface of each strip of the seed-000 strip model
//! ([`hair_core::model::strips`]), as one quad mesh with UVs (u across the strip, 0 at the left
//! edge; v from root 0 to tip 1).
//!
//! # The surface
//! Along its length each edge strand is a cubic Hermite curve through its points with
//! Catmull–Rom tangents `(p[i+1] − p[i−1]) / 2` inside, the last chord at the tip and, **at the
//! root, the follicle direction** (the first segment's rest direction in the root frame) scaled by
//! the first segment's length. Across, the surface is linear between the two edges. Each segment
//! is sampled `rows_per_segment` times, each row at `columns` points across.
//!
//! # Keeping the root rows out of the head (seed 000's unsolved problem)
//! Between the root and the second point the seed's interpolated surface dipped into the head:
//! a chord-based tangent at the root follows the first segment even when it is bent over the
//! scalp, and the straight line across between two roots is a chord of the curved scalp, inside
//! it. Two measures fix it here:
//! 1. the root tangent is the follicle direction, so every edge leaves the scalp along its own
//!    growth direction, not along the chord; with the strip model's root angle limiter
//!    ([`hair_core::model::strips::RootAngleLimit`]) the first segment itself never lies flat;
//! 2. every sampled surface vertex — all rows, all columns, not only the edge strands — is
//!    tested against the head ([`HeadShape`]: bounding sphere first, then the mesh) and one
//!    inside or closer than `clearance` is moved out along the surface normal to `clearance`.
//!    The root row thus sits `clearance` above the scalp. With dense rows the triangles between
//!    vertices stay outside to within the sampling's sag.

use hair_core::model::strips::{HeadShape, StripSet};
use hair_core::Scalp;
use nalgebra::Vector3;

use crate::error::{parameter, InputError, RenderError, Result};

/// How strips are turned into card meshes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CardSettings {
    /// Rows of vertices per edge segment along the length (≥ 1).
    pub rows_per_segment: u32,
    /// Vertices across a strip (≥ 2).
    pub columns: u32,
    /// Gap (m, ≥ 0) kept between every surface vertex and the head when a head is given.
    pub clearance: f32,
}

impl Default for CardSettings {
    /// 4 rows per segment, 3 columns, 1 mm clearance.
    fn default() -> Self {
        Self {
            rows_per_segment: 4,
            columns: 3,
            clearance: 1e-3,
        }
    }
}

impl CardSettings {
    /// Checks the ranges, naming the field as in `--cards-*` options.
    pub fn validate(&self) -> Result<()> {
        if self.rows_per_segment == 0 {
            return Err(parameter(
                "cards.rows_per_segment",
                0,
                "use at least 1 row per segment",
            ));
        }
        if self.columns < 2 {
            return Err(parameter(
                "cards.columns",
                self.columns,
                "use at least 2 vertices across a strip (its two edges)",
            ));
        }
        if !(self.clearance.is_finite() && self.clearance >= 0.0) {
            return Err(parameter(
                "cards.clearance",
                self.clearance,
                "must be a finite number ≥ 0 m",
            ));
        }
        Ok(())
    }
}

/// A card mesh: one grid of quads per strip, vertex UVs.
#[derive(Debug, Clone, PartialEq)]
pub struct CardMesh {
    /// Vertex positions, m (world).
    pub positions: Vec<Vector3<f32>>,
    /// Per-vertex texture coordinates (u across, v root → tip), in [0, 1].
    pub uvs: Vec<[f32; 2]>,
    /// Quads, four vertex indices each, counter-clockwise seen from the side u × v points to.
    pub quads: Vec<[u32; 4]>,
    /// Number of cards (strips).
    pub cards: usize,
    /// Rows of vertices per card (root to tip).
    pub rows: usize,
    /// Vertices across a card.
    pub columns: usize,
}

impl CardMesh {
    /// Checks that `other` has this mesh's topology (a motion sample of it).
    pub fn check_same_topology(&self, other: &CardMesh) -> Result<()> {
        if self.quads != other.quads || self.positions.len() != other.positions.len() {
            return Err(InputError::CardTopology {
                other_vertices: other.positions.len(),
                other_quads: other.quads.len(),
                vertices: self.positions.len(),
                quads: self.quads.len(),
            }
            .into());
        }
        Ok(())
    }
}

/// Hermite point at parameter `t` of the segment from `p0` to `p1` with tangents `m0`, `m1`.
fn hermite(
    p0: &Vector3<f32>,
    m0: &Vector3<f32>,
    p1: &Vector3<f32>,
    m1: &Vector3<f32>,
    t: f32,
) -> Vector3<f32> {
    let (t2, t3) = (t * t, t * t * t);
    p0 * (2.0 * t3 - 3.0 * t2 + 1.0)
        + m0 * (t3 - 2.0 * t2 + t)
        + p1 * (-2.0 * t3 + 3.0 * t2)
        + m1 * (t3 - t2)
}

/// Samples one edge: `rows_per_segment` points per segment plus the tip, with the root tangent
/// along `root_direction` (unit).
fn sample_edge(
    points: &[Vector3<f32>],
    root_direction: &Vector3<f32>,
    rows_per_segment: usize,
    out: &mut Vec<Vector3<f32>>,
) {
    let n = points.len();
    let tangent = |i: usize| -> Vector3<f32> {
        if i == 0 {
            root_direction * (points[1] - points[0]).norm()
        } else if i == n - 1 {
            points[n - 1] - points[n - 2]
        } else {
            (points[i + 1] - points[i - 1]) * 0.5
        }
    };
    out.clear();
    for i in 0..n - 1 {
        let (m0, m1) = (tangent(i), tangent(i + 1));
        for k in 0..rows_per_segment {
            let t = k as f32 / rows_per_segment as f32;
            out.push(hermite(&points[i], &m0, &points[i + 1], &m1, t));
        }
    }
    out.push(points[n - 1]);
}

/// Builds the card mesh of `strips` at their current positions, rooted on `scalp` (which gives
/// the follicle directions and, with `head`, the head's pose). `head` (body space) switches on
/// the push-out of every surface vertex. Refuses bad settings and strips with non-finite points.
pub fn build_cards(
    strips: &StripSet,
    scalp: &Scalp,
    settings: &CardSettings,
    head: Option<&HeadShape>,
) -> Result<CardMesh> {
    settings.validate()?;
    let strands = &strips.strands;
    let roots = strands.root_frames(scalp);
    let rows_per_segment = settings.rows_per_segment as usize;
    let columns = settings.columns as usize;
    let mut mesh = CardMesh {
        positions: Vec::new(),
        uvs: Vec::new(),
        quads: Vec::new(),
        cards: strips.len(),
        rows: 0,
        columns,
    };
    let (mut left, mut right) = (Vec::new(), Vec::new());
    for k in 0..strips.len() {
        let (l, r) = strips.edges(k);
        if l.len() != r.len() {
            return Err(InputError::StripEdges {
                strip: k,
                left: l.len(),
                right: r.len(),
            }
            .into());
        }
        if !l.iter().chain(r).all(|p| p.iter().all(|c| c.is_finite())) {
            return Err(RenderError::Parent {
                parent: k,
                message: "an edge point is not finite; re-simulate or check the cache".into(),
            });
        }
        for (s, points, out) in [(2 * k, l, &mut left), (2 * k + 1, r, &mut right)] {
            let p = strands.points(s).start;
            let rest = strands.rest_local()[p + 1] - strands.rest_local()[p];
            let dir = (roots[s].rotation * rest)
                .try_normalize(1e-12)
                .unwrap_or_else(Vector3::z);
            sample_edge(points, &dir, rows_per_segment, out);
        }
        let rows = left.len();
        mesh.rows = rows;
        let base = mesh.positions.len() as u32;
        for (row, (a, b)) in left.iter().zip(&right).enumerate() {
            let v = row as f32 / (rows - 1) as f32;
            for c in 0..columns {
                let u = c as f32 / (columns - 1) as f32;
                let mut x = a.lerp(b, u);
                if let Some(head) = head {
                    if let Some(out) = head.push_out(&scalp.body, &x, settings.clearance) {
                        x = out;
                    }
                }
                mesh.positions.push(x);
                mesh.uvs.push([u, v]);
            }
        }
        let at = |row: usize, c: usize| base + (row * columns + c) as u32;
        for row in 0..rows - 1 {
            for c in 0..columns - 1 {
                mesh.quads.push([
                    at(row, c),
                    at(row, c + 1),
                    at(row + 1, c + 1),
                    at(row + 1, c),
                ]);
            }
        }
    }
    Ok(mesh)
}
