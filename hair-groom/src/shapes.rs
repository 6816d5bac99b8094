//! Procedural meshes in meters, Z up: a UV sphere (benchmark and test scalps) and the built-in
//! default head.
//!
//! Both are latitude–longitude grids of `hair-core` ([`TriMesh::lat_long`]): closed at each pole
//! by a triangle fan, outward-facing (counter-clockwise) triangles, with per-vertex UVs from an
//! azimuthal projection about the top pole (the crown at (0.5, 0.5), −Y, the front, towards
//! v = 0).

use hair_core::TriMesh;
use nalgebra::Vector3;

use crate::error::GroomError;

/// A sphere of `radius` (m) centred at the origin with `segments` vertices around each ring and
/// `rings` bands from pole to pole: `segments · (rings − 1) + 2` vertices and
/// `2 · segments · (rings − 1)` triangles, with UVs (see the module docs).
///
/// Needs a finite `radius` > 0, `segments` ≥ 3 and `rings` ≥ 2; very fine grids are refused if a
/// triangle would be numerically degenerate.
pub fn uv_sphere(radius: f32, segments: u32, rings: u32) -> Result<TriMesh, GroomError> {
    Ok(TriMesh::uv_sphere(radius, segments, rings)?)
}

/// Half width (X) of the built-in head, m.
const HEAD_HALF_WIDTH: f64 = 0.075;
/// Half depth (Y) of the built-in head's back half, m.
const HEAD_HALF_DEPTH: f64 = 0.1;
/// Half height (Z) of the built-in head, m.
const HEAD_HALF_HEIGHT: f64 = 0.11;
/// How much the face side (−Y) is flattened at its most forward point (fraction of depth).
const FACE_FLATTENING: f64 = 0.15;

/// The built-in default head: an ellipsoid 0.15 m wide (X), 0.185 m deep (Y) and 0.22 m tall
/// (Z), its face side (−Y, Blender's front) slightly flattened, its neck end at the origin and
/// its crown at z = 0.22 m. 64 × 32 grid: 1 986 vertices, 3 968 triangles, with UVs (crown at
/// (0.5, 0.5), see the module docs).
pub fn builtin_head() -> TriMesh {
    TriMesh::lat_long(64, 32, |theta, phi| {
        let y = HEAD_HALF_DEPTH * theta.sin() * phi.sin();
        // Scale the front smoothly: the factor is 1 at y = 0 and 1 − FACE_FLATTENING at the tip,
        // keeping the surface C¹ and the mapping monotone (no fold-over).
        let y = if y < 0.0 {
            y * (1.0 + FACE_FLATTENING * y / HEAD_HALF_DEPTH)
        } else {
            y
        };
        Vector3::new(
            HEAD_HALF_WIDTH * theta.sin() * phi.cos(),
            y,
            HEAD_HALF_HEIGHT * (1.0 + theta.cos()),
        )
    })
    .expect("the built-in head's fixed shape is a valid mesh (tested)")
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use nalgebra::Vector2;

    use super::*;

    fn bounds(mesh: &TriMesh) -> (Vector3<f32>, Vector3<f32>) {
        mesh.positions().iter().fold(
            (Vector3::repeat(f32::MAX), Vector3::repeat(f32::MIN)),
            |(lo, hi), p| (lo.inf(p), hi.sup(p)),
        )
    }

    /// Every edge is shared by exactly two triangles, once in each direction: closed and
    /// consistently oriented.
    fn assert_closed(mesh: &TriMesh) {
        let mut edges = HashMap::new();
        for t in mesh.triangles() {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        for (&(a, b), &n) in &edges {
            assert_eq!(n, 1, "edge {a}-{b} used {n} times in one direction");
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a}-{b} is open");
        }
    }

    /// Every face normal points away from `centre`.
    fn assert_outward(mesh: &TriMesh, centre: Vector3<f32>) {
        for t in 0..mesh.triangles().len() {
            let [a, b, c] = mesh.corners(t);
            let n = (b - a).cross(&(c - a));
            assert!(
                n.dot(&((a + b + c) / 3.0 - centre)) > 0.0,
                "triangle {t} faces in"
            );
        }
    }

    #[test]
    fn sphere_64_by_32() {
        let mesh = uv_sphere(0.5, 64, 32).unwrap();
        assert_eq!(mesh.positions().len(), 64 * 31 + 2);
        assert_eq!(mesh.triangles().len(), 2 * 64 * 31);
        assert!(mesh
            .positions()
            .iter()
            .all(|p| (p.norm() - 0.5).abs() < 1e-6));
        assert_closed(&mesh);
        assert_outward(&mesh, Vector3::zeros());
        let area: f32 = (0..mesh.triangles().len())
            .map(|t| mesh.triangle_area(t))
            .sum();
        let exact = 4.0 * std::f32::consts::PI * 0.25;
        assert!(area < exact && area > 0.99 * exact, "area {area}");
    }

    #[test]
    fn smallest_sphere_is_an_octahedron_like_bipyramid() {
        let mesh = uv_sphere(1.0, 3, 2).unwrap();
        assert_eq!(mesh.triangles().len(), 6);
        assert_closed(&mesh);
        assert_outward(&mesh, Vector3::zeros());
    }

    #[test]
    fn builtin_head_is_head_sized_and_closed() {
        let mesh = builtin_head();
        assert_eq!(mesh.triangles().len(), 3968);
        let (lo, hi) = bounds(&mesh);
        let size = hi - lo;
        assert!((size.x - 0.15).abs() < 1e-3, "width {}", size.x);
        assert!((size.y - 0.185).abs() < 1e-3, "depth {}", size.y);
        assert!(
            lo.z.abs() < 1e-6 && (hi.z - 0.22).abs() < 1e-6,
            "{lo:?} {hi:?}"
        );
        // The face side is the flatter one.
        assert!(-lo.y < hi.y);
        assert_closed(&mesh);
        assert_outward(&mesh, Vector3::new(0.0, 0.0, 0.11));
        let uvs = mesh.uvs().unwrap();
        assert!(uvs
            .iter()
            .flat_map(|uv| uv.iter())
            .all(|c| (0.0..=1.0).contains(c)));
        assert_eq!(uvs[0], Vector2::new(0.5, 0.5));
    }
}
