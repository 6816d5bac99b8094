//! Shaded, z-buffered triangles.
//!
//! Each triangle is taken to camera space, clipped against the near plane (Sutherland–Hodgman,
//! one plane), projected, and filled at pixel centres inside its three edge functions. Depth and
//! the smooth (area-weighted vertex) normal are interpolated perspective-correctly: `1/z` and
//! `n/z` are linear in screen space. No back-face culling: a closed mesh's far side loses the
//! depth test anyway, and an open mesh (a scalp patch, a one-sided collider) is lit on the side
//! the camera sees (two-sided Lambert, see [`super::shading`]), its key light dimmed by the
//! shadow map ([`super::shadow`]).

use nalgebra::Vector3;

use super::camera::{Basis, Projection};
use super::canvas::Band;
use super::scene::{Mesh, Rgb};
use super::shading::WorldLight;
use super::shadow::ShadowMap;

/// A projected triangle ready to fill.
pub(crate) struct ScreenTriangle {
    /// Pixel positions of the corners.
    xy: [[f32; 2]; 3],
    /// Inverse depth of the corners, 1/m.
    inv_z: [f32; 3],
    /// World normals of the corners (not normalised), turned towards the eye.
    normal: [Vector3<f32>; 3],
    /// Camera-space positions of the corners, meters.
    cam: [Vector3<f32>; 3],
    color: Rgb,
}

impl ScreenTriangle {
    /// Inclusive pixel rows the triangle may touch.
    pub fn rows(&self) -> (i64, i64) {
        let lo = self.xy.iter().map(|p| p[1]).fold(f32::INFINITY, f32::min);
        let hi = self
            .xy
            .iter()
            .map(|p| p[1])
            .fold(f32::NEG_INFINITY, f32::max);
        (lo.floor() as i64 - 1, hi.ceil() as i64 + 1)
    }
}

/// Area-weighted vertex normals of `mesh` (zero for vertices no triangle uses).
fn vertex_normals(mesh: &Mesh) -> Vec<Vector3<f32>> {
    let p = mesh.positions();
    let mut n = vec![Vector3::zeros(); p.len()];
    for t in mesh.triangles() {
        let [a, b, c] = t.map(|v| v as usize);
        let face = (p[b] - p[a]).cross(&(p[c] - p[a]));
        for v in [a, b, c] {
            n[v] += face;
        }
    }
    n
}

/// A clipped polygon corner: camera-space position and world normal.
#[derive(Clone, Copy)]
struct Corner {
    cam: Vector3<f32>,
    normal: Vector3<f32>,
}

/// Projects every triangle of `meshes` that is at least partly in front of the near plane.
pub(crate) fn project_meshes(meshes: &[Mesh], proj: &Projection) -> Vec<ScreenTriangle> {
    let mut out = Vec::new();
    for mesh in meshes {
        let normals = vertex_normals(mesh);
        let cam: Vec<_> = mesh
            .positions()
            .iter()
            .map(|p| proj.camera_space(p))
            .collect();
        for t in mesh.triangles() {
            let [a, b, c] = t.map(|v| v as usize);
            // Two-sidedness is decided per face: if the face's geometric normal points away from
            // the eye, its smooth normals are turned around.
            let w = mesh.positions();
            let face = (w[b] - w[a]).cross(&(w[c] - w[a]));
            let sign = if face.dot(&(w[a] - proj.basis.eye)) > 0.0 {
                -1.0
            } else {
                1.0
            };
            let corners = [a, b, c].map(|v| Corner {
                cam: cam[v],
                normal: normals[v] * sign,
            });
            let poly = clip_near(&corners, proj.near);
            for k in 1..poly.len().saturating_sub(1) {
                let tri = [poly[0], poly[k], poly[k + 1]];
                let px = tri.map(|c| proj.pixels(&c.cam));
                out.push(ScreenTriangle {
                    xy: px.map(|p| [p[0], p[1]]),
                    inv_z: px.map(|p| 1.0 / p[2]),
                    normal: tri.map(|c| c.normal),
                    cam: tri.map(|c| c.cam),
                    color: mesh.color(),
                });
            }
        }
    }
    out
}

/// The part of a triangle with depth ≥ `near`: 0, 3 or 4 corners.
fn clip_near(tri: &[Corner; 3], near: f32) -> Vec<Corner> {
    let mut out = Vec::with_capacity(4);
    for i in 0..3 {
        let (a, b) = (tri[i], tri[(i + 1) % 3]);
        let (ina, inb) = (a.cam.z >= near, b.cam.z >= near);
        if ina {
            out.push(a);
        }
        if ina != inb {
            let s = (near - a.cam.z) / (b.cam.z - a.cam.z);
            out.push(Corner {
                cam: a.cam + (b.cam - a.cam) * s,
                normal: a.normal + (b.normal - a.normal) * s,
            });
        }
    }
    out
}

/// Fills `tri` into the rows of `band` where it is nearer than what is there.
pub(crate) fn fill(
    band: &mut Band,
    tri: &ScreenTriangle,
    light: &WorldLight,
    basis: &Basis,
    shadows: Option<&ShadowMap>,
) {
    let [p0, p1, p2] = tri.xy;
    let area = (p1[0] - p0[0]) * (p2[1] - p0[1]) - (p1[1] - p0[1]) * (p2[0] - p0[0]);
    if area.abs() <= 1e-12 || area.is_nan() {
        return;
    }
    let inv_area = 1.0 / area;
    let xs = [p0[0], p1[0], p2[0]];
    let x_lo = (xs
        .iter()
        .copied()
        .fold(f32::INFINITY, f32::min)
        .floor()
        .max(0.0)) as usize;
    let x_hi = xs.iter().copied().fold(f32::NEG_INFINITY, f32::max).ceil();
    if x_hi < 0.0 {
        return;
    }
    let x_hi = (x_hi as usize).min(band.width - 1);
    let (y_lo, y_hi) = tri.rows();
    let rows = band.rows();
    let y_lo = (y_lo.max(rows.start as i64)) as usize;
    let y_hi = y_hi.min(rows.end as i64 - 1);
    if y_hi < y_lo as i64 || x_lo > x_hi {
        return;
    }
    // Edge function of the edge opposite corner k, scaled so the corner's own weight is 1 there.
    let edge = |a: [f32; 2], b: [f32; 2], x: f32, y: f32| {
        ((b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0])) * inv_area
    };
    for y in y_lo..=y_hi as usize {
        let py = y as f32 + 0.5;
        let row = (y - band.y0) * band.width;
        for x in x_lo..=x_hi {
            let px = x as f32 + 0.5;
            let w0 = edge(p1, p2, px, py);
            let w1 = edge(p2, p0, px, py);
            let w2 = edge(p0, p1, px, py);
            if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                continue;
            }
            let iz = w0 * tri.inv_z[0] + w1 * tri.inv_z[1] + w2 * tri.inv_z[2];
            let z = 1.0 / iz;
            let i = row + x;
            if z >= band.depth[i] {
                continue;
            }
            let n = (tri.normal[0] * (w0 * tri.inv_z[0])
                + tri.normal[1] * (w1 * tri.inv_z[1])
                + tri.normal[2] * (w2 * tri.inv_z[2]))
                * z;
            let n = n.try_normalize(1e-20).unwrap_or(-basis.forward);
            let lit = shadows.map_or(1.0, |m| {
                let c = (tri.cam[0] * (w0 * tri.inv_z[0])
                    + tri.cam[1] * (w1 * tri.inv_z[1])
                    + tri.cam[2] * (w2 * tri.inv_z[2]))
                    * z;
                let world = basis.eye + basis.right * c.x + basis.up * c.y + basis.forward * c.z;
                m.light_at(&world, m.texel_bias(3.0), 4)
            });
            band.depth[i] = z;
            // The normal already faces the eye; pass it as its own viewer direction.
            band.color[i] = light.lambert(tri.color, &n, &n, lit);
        }
    }
}
