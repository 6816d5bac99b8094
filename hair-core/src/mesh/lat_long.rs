//! Latitude–longitude meshes in meters, Z up: the UV sphere (test, benchmark and parity-scene
//! heads) and the grid other closed shapes (the built-in head of `hair-groom`) are built on.
//!
//! A grid is closed at each pole by a triangle fan, so no triangle is degenerate, and its
//! triangles face outward (counter-clockwise seen from outside) for any shape that is star-shaped
//! about its axis. Its per-vertex UVs are an azimuthal projection about the top pole, which needs
//! no seam: the top pole (the crown) maps to (0.5, 0.5), the polar angle θ to the distance
//! 0.5·θ/π from it, the azimuth to the direction (+X towards u = 1, −Y, the front, towards
//! v = 0). The bottom pole maps to (0.5, 0), so the UVs of the bottom fan (the neck) are
//! distorted.

use std::f64::consts::PI;

use nalgebra::{Vector2, Vector3};

use super::TriMesh;
use crate::error::{HairError, Result};

/// A parameter error naming `name` as the caller spells it.
fn parameter(name: &str, value: impl ToString, fix: &str) -> HairError {
    HairError::Parameter {
        name: name.to_string(),
        value: value.to_string(),
        fix: fix.to_string(),
    }
}

impl TriMesh {
    /// A sphere of `radius` (m) centred at the origin with `segments` vertices around each ring
    /// and `rings` bands from pole to pole: `segments · (rings − 1) + 2` vertices and
    /// `2 · segments · (rings − 1)` outward triangles, with UVs (see [`TriMesh::lat_long`]).
    ///
    /// Needs a finite `radius` > 0, `segments` ≥ 3 and `rings` ≥ 2; very fine grids are refused
    /// if a triangle would be numerically degenerate.
    pub fn uv_sphere(radius: f32, segments: u32, rings: u32) -> Result<TriMesh> {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(parameter("radius", radius, "must be a finite number > 0 m"));
        }
        let r = f64::from(radius);
        Self::lat_long(segments, rings, |theta, phi| {
            Vector3::new(
                r * theta.sin() * phi.cos(),
                r * theta.sin() * phi.sin(),
                r * theta.cos(),
            )
        })
    }

    /// A closed latitude–longitude mesh with UVs: `shape(θ, φ)` gives the position (m) at polar
    /// angle θ (0 at the top pole, π at the bottom) and azimuth φ (from +X towards +Y, radians).
    ///
    /// Vertex 0 is the top pole (θ = 0, φ = 0); then ring `i` = 1 … `rings` − 1 at θ = π·i/rings,
    /// each of `segments` vertices at φ = 2π·j/segments; last the bottom pole (θ = π, φ = −π/2).
    /// `shape` is called once per vertex, in that order. Triangles: the top fan, the bands ring
    /// by ring, then the bottom fan, counter-clockwise seen from outside.
    ///
    /// Needs `segments` ≥ 3 and `rings` ≥ 2, and refuses a grid whose vertices do not fit 32-bit
    /// indices or whose shape makes a triangle degenerate.
    pub fn lat_long(
        segments: u32,
        rings: u32,
        shape: impl Fn(f64, f64) -> Vector3<f64>,
    ) -> Result<TriMesh> {
        if segments < 3 {
            return Err(parameter(
                "segments",
                segments,
                "must be ≥ 3 (vertices around a ring)",
            ));
        }
        if rings < 2 {
            return Err(parameter(
                "rings",
                rings,
                "must be ≥ 2 (bands from pole to pole)",
            ));
        }
        let vertices = u64::from(segments) * u64::from(rings - 1) + 2;
        if vertices > u64::from(u32::MAX) {
            return Err(parameter(
                "segments",
                segments,
                "segments · (rings − 1) + 2 vertices must fit in 32-bit indices: use fewer",
            ));
        }
        let mut positions = Vec::with_capacity(vertices as usize);
        let mut uvs = Vec::with_capacity(vertices as usize);
        let mut push = |theta: f64, phi: f64| {
            positions.push(shape(theta, phi).cast::<f32>());
            let d = 0.5 * theta / PI;
            uvs.push(Vector2::new(0.5 + d * phi.cos(), 0.5 + d * phi.sin()).cast::<f32>());
        };
        push(0.0, 0.0);
        for i in 1..rings {
            let theta = PI * f64::from(i) / f64::from(rings);
            for j in 0..segments {
                push(theta, 2.0 * PI * f64::from(j) / f64::from(segments));
            }
        }
        push(PI, -0.5 * PI);

        let bottom = segments * (rings - 1) + 1;
        // Vertex j of ring i (1-based rings), wrapping around the ring.
        let ring = |i: u32, j: u32| 1 + (i - 1) * segments + j % segments;
        let mut triangles = Vec::with_capacity(2 * (segments * (rings - 1)) as usize);
        for j in 0..segments {
            triangles.push([0, ring(1, j), ring(1, j + 1)]);
        }
        for i in 1..rings - 1 {
            for j in 0..segments {
                let (a, b) = (ring(i, j), ring(i, j + 1));
                let (c, d) = (ring(i + 1, j), ring(i + 1, j + 1));
                triangles.push([a, c, d]);
                triangles.push([a, d, b]);
            }
        }
        for j in 0..segments {
            triangles.push([bottom, ring(rings - 1, j + 1), ring(rings - 1, j)]);
        }
        TriMesh::new(positions, triangles)?.with_uvs(uvs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_sphere_parameters_are_named() {
        for (r, s, n, name) in [
            (0.0, 8, 4, "radius"),
            (f32::NAN, 8, 4, "radius"),
            (1.0, 2, 4, "segments"),
            (1.0, 8, 1, "rings"),
            (1.0, u32::MAX, u32::MAX, "segments"),
        ] {
            let err = TriMesh::uv_sphere(r, s, n).unwrap_err();
            assert!(err.to_string().contains(&format!("`{name}`")), "{err}");
        }
    }
}
