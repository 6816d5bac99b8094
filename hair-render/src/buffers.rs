//! Flat output that exporters and host renderers consume directly.
//!
//! Curves are stored one after another: curve `c` has `vertex_counts[c]` points, its points
//! follow those of curve `c − 1` in `points` (x, y, z interleaved, meters, world space, Z up) and
//! `widths` (one diameter per point, meters). Per-curve attributes: `parent` (index of the parent
//! strand), `random` (uniform in [0, 1), stable per child across frames and levels of detail),
//! `root_uv` (u, v interleaved, from the scalp's UVs) and `color` (linear RGB from the scalp's
//! vertex colors), the last two present only when the scalp has them.

use crate::error::{InputError, Result};

/// Children as flat arrays (see the module documentation for the layout).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ChildBuffers {
    /// Points per curve.
    pub vertex_counts: Vec<u32>,
    /// Point positions, x y z interleaved, meters.
    pub points: Vec<f32>,
    /// Width (diameter) per point, meters.
    pub widths: Vec<f32>,
    /// Parent strand index per curve.
    pub parent: Vec<u32>,
    /// Random value in [0, 1) per curve.
    pub random: Vec<f32>,
    /// Root UV per curve (u v interleaved), when the scalp has UVs.
    pub root_uv: Option<Vec<f32>>,
    /// Root color per curve (r g b interleaved, linear, 0–1), when the scalp has vertex colors.
    pub color: Option<Vec<f32>>,
}

/// Axis-aligned bounds of the curves padded by half the largest width, meters (as USD's
/// `UsdGeomCurves::ComputeExtent` defines a curves prim's extent).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extent {
    /// Minimum corner.
    pub min: [f32; 3],
    /// Maximum corner.
    pub max: [f32; 3],
}

impl ChildBuffers {
    /// Number of curves.
    pub fn curve_count(&self) -> usize {
        self.vertex_counts.len()
    }

    /// Number of points.
    pub fn point_count(&self) -> usize {
        self.widths.len()
    }

    /// Bounds of `points` padded by half the largest width; `None` with no points.
    pub fn extent(&self) -> Option<Extent> {
        extent_of(&self.points, &self.widths)
    }

    /// Checks that `other` has the same curves (counts), as motion samples of one export must.
    pub fn check_same_topology(&self, other: &ChildBuffers) -> Result<()> {
        if self.vertex_counts == other.vertex_counts {
            Ok(())
        } else {
            Err(InputError::ChildTopology {
                curves: self.curve_count(),
                other_curves: other.curve_count(),
                points: self.point_count(),
                other_points: other.point_count(),
            }
            .into())
        }
    }
}

/// Bounds of interleaved `points` padded by half the largest of `widths`.
pub fn extent_of(points: &[f32], widths: &[f32]) -> Option<Extent> {
    if widths.is_empty() {
        return None;
    }
    let h = 0.5 * widths.iter().fold(0.0f32, |a, &w| a.max(w));
    let mut min = [f32::INFINITY; 3];
    let mut max = [f32::NEG_INFINITY; 3];
    for p in points.chunks_exact(3) {
        for k in 0..3 {
            min[k] = min[k].min(p[k]);
            max[k] = max[k].max(p[k]);
        }
    }
    Some(Extent {
        min: min.map(|v| v - h),
        max: max.map(|v| v + h),
    })
}
