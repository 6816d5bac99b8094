//! Strands as anti-aliased thick lines, depth-tested against the meshes and blended back to front.
//!
//! **Coverage.** A segment is a 2D capsule whose half width is interpolated between its ends;
//! a pixel's coverage is the box-filtered overlap `clamp(h + ½ − d, 0, 1)` with `d` the distance
//! from the pixel centre to the segment (the usual distance-based line anti-aliasing, as in
//! Gupta & Sproull 1981, simplified to a box filter). Strands thinner than the minimum width are
//! drawn at that width with their opacity lowered by the ratio, so their average coverage stays
//! right.
//!
//! **Joins.** Consecutive segments of a strand would both cover the pixels around their shared
//! point and blend there twice (a bead at every vertex). Each joint is split by its screen-space
//! bisector (the line through the joint across the mean of the two directions) and a pixel is
//! drawn only by the segment on its side, so a strand is blended once per pixel with round joins
//! and round end caps.
//!
//! **Depth.** The meshes are drawn first into the depth buffer; a hair fragment is kept when its
//! front (depth minus the strand's radius, so roots sitting on the scalp are not lost to it) is
//! nearer. Hair does not write depth: segments are sorted far to near by their mid depth and
//! composited with "over", which is exact for non-intersecting segments and makes hair in front
//! cover hair behind (painter's algorithm).
//!
//! **Shading.** Kajiya–Kay at every point with the tangent averaged over its two segments and the
//! key light dimmed by the shadow map ([`super::shadow`]), then interpolated along the segment,
//! so highlights move smoothly along a bent strand.

use hair_par::prelude::*;
use nalgebra::Vector3;

use super::camera::Projection;
use super::canvas::Band;
use super::scene::{Highlight, Rgb, Strands};
use super::shading::{HairLook, WorldLight};
use super::shadow::ShadowMap;

/// Color of highlighted problems (linear red).
const MARK_COLOR: Rgb = [0.9, 0.0, 0.0];
/// Narrowest highlighted segment, pixels.
const MARK_LINE_PX: f32 = 2.5;
/// Diameter of a highlighted point, pixels.
const MARK_DOT_PX: f32 = 5.0;

/// A projected segment (or a dot, when both ends coincide).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ScreenSegment {
    /// Pixel positions of the ends.
    p: [[f32; 2]; 2],
    /// Inverse depths of the ends, 1/m.
    inv_z: [f32; 2],
    /// Half widths at the ends, pixels.
    half_width: [f32; 2],
    /// Radii at the ends (meters), for the depth test.
    radius: [f32; 2],
    /// Opacity at the ends.
    alpha: [f32; 2],
    /// Shaded colors at the ends.
    color: [Rgb; 2],
    /// Bisector normals: the segment owns pixels with `(x − p0)·n0 ≥ 0` and `(x − p1)·n1 < 0`.
    cut: [Option<[f32; 2]>; 2],
    /// Whether hidden parts behind meshes are skipped.
    depth_test: bool,
    /// Sort key: depth of the midpoint, meters.
    key: f32,
}

impl ScreenSegment {
    /// Inclusive pixel rows the segment may touch.
    pub fn rows(&self) -> (i64, i64) {
        let h = self.half_width[0].max(self.half_width[1]) + 1.0;
        let lo = self.p[0][1].min(self.p[1][1]) - h;
        let hi = self.p[0][1].max(self.p[1][1]) + h;
        (lo.floor() as i64, hi.ceil() as i64)
    }
}

/// A point of a strand after shading and projection.
#[derive(Clone, Copy)]
struct ShadedPoint {
    cam: Vector3<f32>,
    color: Rgb,
    radius: f32,
}

fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

fn lerp3(a: Rgb, b: Rgb, t: f32) -> Rgb {
    [
        lerp(a[0], b[0], t),
        lerp(a[1], b[1], t),
        lerp(a[2], b[2], t),
    ]
}

/// Projects and shades every segment of `strands`, sorted far to near.
pub(crate) fn project_strands(
    strands: &Strands,
    proj: &Projection,
    light: &WorldLight,
    look: &HairLook,
    shadows: Option<&ShadowMap>,
) -> Vec<ScreenSegment> {
    let mut segments: Vec<ScreenSegment> = (0..strands.len())
        .into_par_iter()
        .flat_map_iter(|s| strand_segments(strands, s, proj, light, look, shadows))
        .collect();
    // Far to near; ties keep strand order (the sort is stable), so the image is deterministic.
    segments.par_sort_by(|a, b| b.key.total_cmp(&a.key));
    segments
}

/// The segments of strand `s`.
fn strand_segments(
    strands: &Strands,
    s: usize,
    proj: &Projection,
    light: &WorldLight,
    look: &HairLook,
    shadows: Option<&ShadowMap>,
) -> Vec<ScreenSegment> {
    let range = strands.points(s);
    let pos = &strands.positions()[range.clone()];
    let n = pos.len();
    let last = (n - 1) as f32;
    let shaded: Vec<ShadedPoint> = (0..n)
        .map(|i| {
            let before = if i > 0 {
                pos[i] - pos[i - 1]
            } else {
                Vector3::zeros()
            };
            let after = if i + 1 < n {
                pos[i + 1] - pos[i]
            } else {
                Vector3::zeros()
            };
            let tangent = (before.try_normalize(1e-12).unwrap_or_else(Vector3::zeros)
                + after.try_normalize(1e-12).unwrap_or_else(Vector3::zeros))
            .try_normalize(1e-12)
            .unwrap_or_else(Vector3::z);
            let base = match strands.colors() {
                Some(c) => c[range.start + i],
                None => lerp3(look.root_color, look.tip_color, i as f32 / last),
            };
            let to_eye = (proj.basis.eye - pos[i])
                .try_normalize(1e-12)
                .unwrap_or(-proj.basis.forward);
            // A strand does not shadow itself within about a texel.
            let lit = shadows.map_or(1.0, |m| m.light_at(&pos[i], m.texel_bias(1.5), 2));
            ShadedPoint {
                cam: proj.camera_space(&pos[i]),
                color: light.kajiya_kay(base, &tangent, &to_eye, look, lit),
                radius: strands.radius(range.start + i, look.default_radius) * look.radius_scale,
            }
        })
        .collect();
    // Screen positions of the points in front of the near plane, and segment directions.
    let screen: Vec<Option<[f32; 2]>> = shaded
        .iter()
        .map(|p| {
            (p.cam.z >= proj.near).then(|| {
                let [x, y, _] = proj.pixels(&p.cam);
                [x, y]
            })
        })
        .collect();
    let dirs: Vec<Option<[f32; 2]>> = (0..n - 1)
        .map(|j| match (screen[j], screen[j + 1]) {
            (Some(a), Some(b)) => normalised([b[0] - a[0], b[1] - a[1]]),
            _ => None,
        })
        .collect();
    // Bisector at joint i (between segments i − 1 and i).
    let cut = |i: usize| -> Option<[f32; 2]> {
        if i == 0 || i == n - 1 {
            return None;
        }
        let (a, b) = (dirs[i - 1]?, dirs[i]?);
        normalised([a[0] + b[0], a[1] + b[1]]).or(Some(b))
    };
    let mut out = Vec::with_capacity(n - 1);
    for j in 0..n - 1 {
        let (a, b) = (shaded[j], shaded[j + 1]);
        if a.cam.z < proj.near && b.cam.z < proj.near {
            continue;
        }
        // Clip the part behind the near plane; a clipped end gets a round cap.
        let (a, cut_a) = if a.cam.z < proj.near {
            (clip(&a, &b, proj.near), None)
        } else {
            (a, cut(j))
        };
        let (b, cut_b) = if b.cam.z < proj.near {
            (clip(&b, &a, proj.near), None)
        } else {
            (b, cut(j + 1))
        };
        let ends = [a, b].map(|q| end(&q, proj, look));
        out.push(ScreenSegment {
            p: ends.map(|e| e.xy),
            inv_z: [1.0 / a.cam.z, 1.0 / b.cam.z],
            half_width: ends.map(|e| e.half_width),
            radius: [a.radius, b.radius],
            alpha: ends.map(|e| e.alpha),
            color: [a.color, b.color],
            cut: [cut_a, cut_b],
            depth_test: true,
            key: 0.5 * (a.cam.z + b.cam.z),
        });
    }
    out
}

/// The point between `from` (behind the near plane) and `to` (in front) at depth `near`.
fn clip(from: &ShadedPoint, to: &ShadedPoint, near: f32) -> ShadedPoint {
    let t = (near - from.cam.z) / (to.cam.z - from.cam.z);
    ShadedPoint {
        cam: from.cam + (to.cam - from.cam) * t,
        color: lerp3(from.color, to.color, t),
        radius: lerp(from.radius, to.radius, t),
    }
}

/// Screen position, half width and opacity of a point in front of the near plane.
#[derive(Clone, Copy)]
struct End {
    xy: [f32; 2],
    half_width: f32,
    alpha: f32,
}

fn end(p: &ShadedPoint, proj: &Projection, look: &HairLook) -> End {
    let [x, y, z] = proj.pixels(&p.cam);
    let width = 2.0 * p.radius * proj.focal_px / z;
    let drawn = width.max(look.min_width_px);
    End {
        xy: [x, y],
        half_width: 0.5 * drawn,
        alpha: look.opacity * (width / drawn).min(1.0),
    }
}

fn normalised(v: [f32; 2]) -> Option<[f32; 2]> {
    let l = (v[0] * v[0] + v[1] * v[1]).sqrt();
    (l > 1e-6).then(|| [v[0] / l, v[1] / l])
}

/// Red marks for the flagged points and segments, drawn without depth test.
pub(crate) fn project_marks(
    strands: &Strands,
    highlight: &Highlight,
    proj: &Projection,
    look: &HairLook,
) -> Vec<ScreenSegment> {
    let pos = strands.positions();
    let mut out = Vec::new();
    let mut mark = |a: usize, b: usize, width_px: f32| {
        let (ca, cb) = (proj.camera_space(&pos[a]), proj.camera_space(&pos[b]));
        if ca.z < proj.near || cb.z < proj.near {
            return;
        }
        let point = |c: &Vector3<f32>, r: f32| {
            let [x, y, z] = proj.pixels(c);
            let w = (2.0 * r * look.radius_scale * proj.focal_px / z).max(width_px);
            ([x, y], 0.5 * w)
        };
        let (pa, ha) = point(&ca, strands.radius(a, look.default_radius));
        let (pb, hb) = point(&cb, strands.radius(b, look.default_radius));
        out.push(ScreenSegment {
            p: [pa, pb],
            inv_z: [1.0 / ca.z, 1.0 / cb.z],
            half_width: [ha, hb],
            radius: [0.0; 2],
            alpha: [1.0; 2],
            color: [MARK_COLOR; 2],
            cut: [None; 2],
            depth_test: false,
            key: 0.0,
        });
    };
    if let Some(flags) = highlight.segments {
        for s in 0..strands.len() {
            let points = strands.points(s);
            for i in points.start..points.end - 1 {
                if flags[i - s] {
                    mark(i, i + 1, MARK_LINE_PX);
                }
            }
        }
    }
    if let Some(flags) = highlight.points {
        for (i, _) in flags.iter().enumerate().filter(|(_, f)| **f) {
            mark(i, i, MARK_DOT_PX);
        }
    }
    out
}

/// Blends `seg` into the rows of `band`.
pub(crate) fn draw(band: &mut Band, seg: &ScreenSegment) {
    let (y_lo, y_hi) = seg.rows();
    let rows = band.rows();
    let y_lo = y_lo.max(rows.start as i64);
    let y_hi = y_hi.min(rows.end as i64 - 1);
    let h = seg.half_width[0].max(seg.half_width[1]) + 1.0;
    let x_lo = (seg.p[0][0].min(seg.p[1][0]) - h).floor().max(0.0);
    let x_hi = (seg.p[0][0].max(seg.p[1][0]) + h)
        .ceil()
        .min(band.width as f32 - 1.0);
    if y_lo > y_hi || x_lo > x_hi {
        return;
    }
    let [a, b] = seg.p;
    let d = [b[0] - a[0], b[1] - a[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let inv_len2 = if len2 > 1e-12 { 1.0 / len2 } else { 0.0 };
    // Half width at which coverage reaches 0.
    let reach = seg.half_width[0].max(seg.half_width[1]) + 0.5;
    for y in y_lo as usize..=y_hi as usize {
        let py = y as f32 + 0.5;
        let row = (y - band.y0) * band.width;
        // Columns this row can cover: the part of the segment within `reach` of the row, widened
        // by `reach` (a long diagonal segment's bounding box is mostly empty).
        let (t0, t1) = if d[1].abs() > 1e-6 {
            let ta = (py - reach - a[1]) / d[1];
            let tb = (py + reach - a[1]) / d[1];
            (ta.min(tb).clamp(0.0, 1.0), ta.max(tb).clamp(0.0, 1.0))
        } else {
            (0.0, 1.0)
        };
        let (xa, xb) = (a[0] + t0 * d[0], a[0] + t1 * d[0]);
        let span_lo = ((xa.min(xb) - reach).floor()).max(x_lo) as usize;
        let span_hi = ((xa.max(xb) + reach).ceil()).min(x_hi);
        if span_hi < span_lo as f32 {
            continue;
        }
        for x in span_lo..=span_hi as usize {
            let px = x as f32 + 0.5;
            let v = [px - a[0], py - a[1]];
            let t = ((v[0] * d[0] + v[1] * d[1]) * inv_len2).clamp(0.0, 1.0);
            let (ex, ey) = (v[0] - t * d[0], v[1] - t * d[1]);
            let dist = (ex * ex + ey * ey).sqrt();
            let half = lerp(seg.half_width[0], seg.half_width[1], t);
            let coverage = (half + 0.5 - dist).min(1.0);
            if coverage <= 0.0 {
                continue;
            }
            if let Some(n) = seg.cut[0] {
                if v[0] * n[0] + v[1] * n[1] < 0.0 {
                    continue;
                }
            }
            if let Some(n) = seg.cut[1] {
                if (px - b[0]) * n[0] + (py - b[1]) * n[1] >= 0.0 {
                    continue;
                }
            }
            let i = row + x;
            if seg.depth_test {
                let z = 1.0 / lerp(seg.inv_z[0], seg.inv_z[1], t);
                if z - lerp(seg.radius[0], seg.radius[1], t) >= band.depth[i] {
                    continue;
                }
            }
            let alpha = coverage * lerp(seg.alpha[0], seg.alpha[1], t);
            let c = lerp3(seg.color[0], seg.color[1], t);
            let dst = &mut band.color[i];
            for k in 0..3 {
                dst[k] += (c[k] - dst[k]) * alpha;
            }
        }
    }
}
