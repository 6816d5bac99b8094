//! The hair-strip model of seed 000 (after Koh & Huang 2001): a head of hair as **strips**, each
//! bounded by two simulated **edge strands** that control a textured ribbon, so the hundreds of
//! hairs a strip stands for cost two strands' work.
//!
//! # Data
//! A [`StripSet`] holds the edge strands in an ordinary [`StrandSet`] (strip `k` owns strands
//! `2k` (left) and `2k + 1` (right), same point count) and, per strip, how many hairs it
//! represents. Strips are generated on the scalp from mesh triangles as the seed does
//! ([`StripSet::from_triangles`]: one edge at the triangle's centre, the other towards one of its
//! corners) or from explicit pairs of strands ([`StripSet::from_pairs`]).
//!
//! # Simulation ([`StripSolver`])
//! The edge strands are mass-spring chains advanced by the project's [`crate::MassSpringSolver`].
//! In the seed's order, after the forces of each frame:
//! 1. **Provot's correction** (strain limiting, Provot 1996): a segment stretched beyond
//!    `(1 + max_strain) ×` its rest length is pulled back, root to tip. It runs inside every
//!    substep ([`crate::SolverSettings::max_strain`]) and once more as the frame's last pass, so
//!    every segment is within the limit when the frame is handed back.
//! 2. **The root angle limiter** (Daldegan et al. 1993): a first segment bent further than
//!    [`RootAngleLimit`] from its rest direction in the root frame is rotated back about the root
//!    onto the limit cone, keeping its length; velocity into the cone wall is removed.
//! 3. **Two-stage collision** against the head: a bounding sphere first ([`HeadShape`]); only
//!    when some edge point may reach it this frame does the frame run the project's contact
//!    pipeline ([`crate::Colliders`], precise against the mesh), and only points inside the sphere
//!    are projected out of the mesh after the post-step passes.
//!
//! The ribbon between the two edges is built by the render level (`hair-render`'s `cards`), which
//! also keeps the surface between root and second point out of the head (the seed's unsolved
//! problem) with the same [`HeadShape`].

mod head;
mod limits;
mod solver;

pub use head::HeadShape;
pub use limits::{limit_root_angles, limit_strain, RootAngleLimit};
pub use solver::{StripFrameReport, StripSettings, StripSolver};

use nalgebra::Vector3;

use crate::error::{HairError, MeshError, Result};
use crate::mesh::{MeshSample, TriMesh};
use crate::strands::{Anchor, Scalp, StrandInput, StrandSet};

/// Smallest distance between the two roots of a strip, m: closer edges are coincident.
pub const MIN_STRIP_WIDTH: f32 = 1e-5;

/// How strips are grown from scalp triangles ([`StripSet::from_triangles`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StripGrowth {
    /// Length of each edge strand, m (> 0).
    pub length: f32,
    /// Segments per edge strand (≥ 1).
    pub segments: u32,
    /// Hairs one strip stands for (≥ 1), for reports and cost per represented hair.
    pub hairs_per_strip: u32,
    /// Where the right edge sits on the way from the triangle's centre to its corner, in (0, 1].
    pub width_fraction: f32,
    /// Linear density of an edge strand, kg/m (> 0).
    pub mass_per_length: f32,
    /// Collision radius of edge points, m (≥ 0).
    pub radius: f32,
}

impl Default for StripGrowth {
    fn default() -> Self {
        Self {
            length: 0.2,
            segments: 8,
            hairs_per_strip: 100,
            width_fraction: 0.8,
            mass_per_length: 1e-3,
            radius: 2e-3,
        }
    }
}

impl StripGrowth {
    /// Checks every field's range, naming it as in the scene's `[strips]` section.
    pub fn validate(&self) -> Result<()> {
        crate::error::check_positive("strips.length", self.length)?;
        crate::error::check_positive("strips.mass_per_length", self.mass_per_length)?;
        crate::error::check_non_negative("strips.radius", self.radius)?;
        let bad = |name: &str, value: String, fix: &str| HairError::Parameter {
            name: name.into(),
            value,
            fix: fix.into(),
        };
        if self.segments == 0 {
            return Err(bad("strips.segments", "0".into(), "use at least 1 segment"));
        }
        if self.hairs_per_strip == 0 {
            return Err(bad(
                "strips.hairs_per_strip",
                "0".into(),
                "a strip stands for at least 1 hair",
            ));
        }
        let w = self.width_fraction;
        if !(w.is_finite() && w > 0.0 && w <= 1.0) {
            return Err(bad(
                "strips.width_fraction",
                w.to_string(),
                "must lie in (0, 1]: 1 puts the right edge on the triangle's corner",
            ));
        }
        Ok(())
    }
}

/// Strips: pairs of edge strands in one [`StrandSet`] (strip `k` = strands `2k`, `2k + 1`) and
/// the number of hairs each strip represents.
#[derive(Debug, Clone)]
pub struct StripSet {
    /// The edge strands, left and right of each strip in turn.
    pub strands: StrandSet,
    hairs: Vec<u32>,
}

impl StripSet {
    /// Grows one strip per listed triangle of `mesh` (the scalp at rest, m), as seed 000 does:
    /// the left edge is rooted at the triangle's centre, the right edge on the way from the centre
    /// to corner `t mod 3` (so neighbouring strips turn different ways), both growing along the
    /// surface normal. Refuses a triangle index out of range, a triangle too small to carry a
    /// strip of width ≥ [`MIN_STRIP_WIDTH`], and bad growth settings.
    pub fn from_triangles(mesh: &TriMesh, triangles: &[u32], growth: &StripGrowth) -> Result<Self> {
        growth.validate()?;
        if triangles.is_empty() {
            return Err(MeshError::NoStripTriangle.into());
        }
        let n = growth.segments as usize;
        let rest: Vec<Vector3<f32>> = (0..=n)
            .map(|i| Vector3::new(0.0, 0.0, growth.length * i as f32 / n as f32))
            .collect();
        let mut strands = StrandSet::new();
        for &t in triangles {
            if t as usize >= mesh.triangles().len() {
                return Err(MeshError::StripTriangle {
                    triangle: t,
                    triangles: mesh.triangles().len(),
                }
                .into());
            }
            let corners = mesh.corners(t as usize);
            let area = mesh.triangle_area(t as usize);
            let corner = (t % 3) as usize;
            let centre = (corners[0] + corners[1] + corners[2]) / 3.0;
            let width = growth.width_fraction * (corners[corner] - centre).norm();
            if !(area.is_finite() && width >= MIN_STRIP_WIDTH && area >= MIN_STRIP_WIDTH.powi(2)) {
                return Err(MeshError::StripTooSmall {
                    triangle: t,
                    area,
                    width,
                }
                .into());
            }
            let third = 1.0 / 3.0;
            let left = MeshSample {
                triangle: t,
                weights: [third; 3],
            };
            let f = growth.width_fraction;
            let mut weights = [(1.0 - f) * third; 3];
            weights[corner] += f;
            let right = MeshSample {
                triangle: t,
                weights,
            };
            for sample in [left, right] {
                strands.push(StrandInput::uniform(
                    Anchor::Surface(sample),
                    rest.clone(),
                    growth.mass_per_length,
                    growth.radius,
                    0.0,
                    0.0,
                ))?;
            }
        }
        let scalp = Scalp {
            mesh: Some(mesh.clone()),
            body: nalgebra::Isometry3::identity(),
        };
        strands.reset_to_rest(&scalp);
        Ok(Self {
            strands,
            hairs: vec![growth.hairs_per_strip; triangles.len()],
        })
    }

    /// Builds strips from explicit (left, right) edge strands, e.g. pairs of guides, placed at
    /// rest on `scalp`. Refuses pairs whose strands differ in point count and pairs whose roots
    /// are coincident (closer than [`MIN_STRIP_WIDTH`]), naming the strip.
    pub fn from_pairs(
        pairs: Vec<(StrandInput, StrandInput)>,
        hairs_per_strip: u32,
        scalp: &Scalp,
    ) -> Result<Self> {
        if hairs_per_strip == 0 {
            return Err(HairError::Parameter {
                name: "strips.hairs_per_strip".into(),
                value: "0".into(),
                fix: "a strip stands for at least 1 hair".into(),
            });
        }
        let count = pairs.len();
        let mut strands = StrandSet::new();
        for (k, (left, right)) in pairs.into_iter().enumerate() {
            if left.rest.len() != right.rest.len() {
                return Err(HairError::Strand {
                    strand: 2 * k,
                    message: format!(
                        "strip {k}: the left edge has {} points and the right edge {}; give both \
                         edges of a strip the same number of points",
                        left.rest.len(),
                        right.rest.len()
                    ),
                });
            }
            strands.push(left)?;
            strands.push(right)?;
        }
        strands.validate_anchors(scalp)?;
        strands.reset_to_rest(scalp);
        for k in 0..count {
            let a = strands.positions[strands.points(2 * k).start];
            let b = strands.positions[strands.points(2 * k + 1).start];
            let width = (a - b).norm();
            if width.is_nan() || width < MIN_STRIP_WIDTH {
                return Err(HairError::Strand {
                    strand: 2 * k,
                    message: format!(
                        "strip {k}: the edge strands are coincident at the root ({width:.3e} m \
                         apart, < {MIN_STRIP_WIDTH:e} m); root the two edges of a strip at \
                         different scalp points"
                    ),
                });
            }
        }
        Ok(Self {
            strands,
            hairs: vec![hairs_per_strip; count],
        })
    }

    /// Number of strips.
    pub fn len(&self) -> usize {
        self.hairs.len()
    }

    /// True when there is no strip.
    pub fn is_empty(&self) -> bool {
        self.hairs.is_empty()
    }

    /// Hairs each strip stands for.
    pub fn hairs(&self) -> &[u32] {
        &self.hairs
    }

    /// Total number of hairs represented by all strips.
    pub fn represented_hairs(&self) -> u64 {
        self.hairs.iter().map(|&h| h as u64).sum()
    }

    /// World positions (m) of strip `k`'s left and right edge strands.
    pub fn edges(&self, k: usize) -> (&[Vector3<f32>], &[Vector3<f32>]) {
        let s = &self.strands;
        (
            &s.positions[s.points(2 * k)],
            &s.positions[s.points(2 * k + 1)],
        )
    }
}
