//! Triangle meshes whose vertices move every frame, stable points on them (mesh samples) and the
//! orthonormal root frames those points evaluate to.
//!
//! A [`MeshSample`] is a triangle index plus barycentric weights (seed 001, "Mesh Point Sampling"):
//! it names the same material point of the surface however the mesh deforms, so hair roots stay
//! put when the head moves, turns or squashes. Evaluating it on the current vertex positions gives a
//! [`RootFrame`]: the position plus an orthonormal frame whose local z axis is the smooth surface
//! normal, local x the tangent along the triangle's first edge and local y the bitangent.

use nalgebra::{Isometry3, Matrix3, Rotation3, UnitQuaternion, Vector2, Vector3};
#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::error::{MeshError, Result};

mod lat_long;

/// A triangle mesh in meters. Vertex positions may be replaced every frame
/// ([`TriMesh::set_positions`]); the topology (triangles) is fixed at construction.
#[derive(Debug, Clone)]
pub struct TriMesh {
    positions: Vec<Vector3<f32>>,
    triangles: Vec<[u32; 3]>,
    uvs: Option<Vec<Vector2<f32>>>,
    normals: Vec<Vector3<f32>>,
}

impl TriMesh {
    /// Builds a mesh from vertex positions (meters) and triangles (vertex indices).
    ///
    /// Refuses an empty mesh, an index out of range, a non-finite position and any triangle of
    /// (numerically) zero area, naming the triangle, because hair rooted there would have no normal.
    pub fn new(positions: Vec<Vector3<f32>>, triangles: Vec<[u32; 3]>) -> Result<Self> {
        if triangles.is_empty() {
            return Err(MeshError::NoTriangles.into());
        }
        check_positions(&positions)?;
        let n = positions.len() as u32;
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&vertex) = tri.iter().find(|&&i| i >= n) {
                return Err(MeshError::VertexIndex {
                    triangle: t,
                    vertex,
                    vertices: n,
                }
                .into());
            }
        }
        let scale = bounding_diagonal(&positions).max(f32::MIN_POSITIVE);
        let min_area = 1e-10 * scale * scale;
        for (t, tri) in triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|i| positions[i as usize]);
            let area = 0.5 * (b - a).cross(&(c - a)).norm();
            if area.is_nan() || area <= min_area {
                return Err(MeshError::Degenerate {
                    triangle: t,
                    corners: *tri,
                    area,
                }
                .into());
            }
        }
        let mut mesh = Self {
            normals: Vec::new(),
            positions,
            triangles,
            uvs: None,
        };
        mesh.update_normals();
        Ok(mesh)
    }

    /// Attaches per-vertex UV coordinates (one per vertex).
    pub fn with_uvs(mut self, uvs: Vec<Vector2<f32>>) -> Result<Self> {
        if uvs.len() != self.positions.len() {
            return Err(MeshError::UvCount {
                uvs: uvs.len(),
                vertices: self.positions.len(),
            }
            .into());
        }
        self.uvs = Some(uvs);
        Ok(self)
    }

    /// Replaces the vertex positions (meters), e.g. with this frame's deformed head.
    /// The count must match and every coordinate must be finite.
    pub fn set_positions(&mut self, positions: &[Vector3<f32>]) -> Result<()> {
        if positions.len() != self.positions.len() {
            return Err(MeshError::PositionCount {
                positions: positions.len(),
                vertices: self.positions.len(),
            }
            .into());
        }
        check_positions(positions)?;
        self.positions.copy_from_slice(positions);
        self.update_normals();
        Ok(())
    }

    /// Current vertex positions, meters.
    pub fn positions(&self) -> &[Vector3<f32>] {
        &self.positions
    }

    /// Triangles as vertex index triples.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Per-vertex UVs, if the mesh has them.
    pub fn uvs(&self) -> Option<&[Vector2<f32>]> {
        self.uvs.as_deref()
    }

    /// Area-weighted smooth vertex normals of the current positions (unit length).
    pub fn vertex_normals(&self) -> &[Vector3<f32>] {
        &self.normals
    }

    /// Area of triangle `t` at the current positions, m².
    pub fn triangle_area(&self, t: usize) -> f32 {
        let [a, b, c] = self.corners(t);
        0.5 * (b - a).cross(&(c - a)).norm()
    }

    /// Positions of the three corners of triangle `t`, meters.
    pub fn corners(&self, t: usize) -> [Vector3<f32>; 3] {
        self.triangles[t].map(|i| self.positions[i as usize])
    }

    /// Returns a copy moved rigidly by `iso` (positions transformed, topology and UVs kept).
    pub fn transformed(&self, iso: &Isometry3<f32>) -> Self {
        let mut out = self.clone();
        for p in &mut out.positions {
            *p = iso.transform_vector(p) + iso.translation.vector;
        }
        out.update_normals();
        out
    }

    /// Evaluates `sample` on the current positions: root position and orthonormal frame.
    pub fn evaluate(&self, sample: &MeshSample) -> RootFrame {
        let t = sample.triangle as usize;
        let tri = self.triangles[t];
        let [a, b, c] = self.corners(t);
        let w = sample.weights;
        let origin = a * w[0] + b * w[1] + c * w[2];
        let face = (b - a).cross(&(c - a));
        let smooth = tri.iter().zip(w).fold(Vector3::zeros(), |acc, (&i, wi)| {
            acc + self.normals[i as usize] * wi
        });
        let normal = unit_or(smooth, unit_or(face, Vector3::z()));
        RootFrame::from_normal_and_edge(origin, normal, b - a)
    }

    /// UV of `sample` interpolated from the vertex UVs, if the mesh has UVs.
    pub fn sample_uv(&self, sample: &MeshSample) -> Option<Vector2<f32>> {
        let uvs = self.uvs.as_ref()?;
        let tri = self.triangles[sample.triangle as usize];
        Some(
            tri.iter()
                .zip(sample.weights)
                .fold(Vector2::zeros(), |acc, (&i, w)| acc + uvs[i as usize] * w),
        )
    }

    fn update_normals(&mut self) {
        let mut normals = vec![Vector3::zeros(); self.positions.len()];
        for tri in &self.triangles {
            let [a, b, c] = tri.map(|i| self.positions[i as usize]);
            // The unnormalised cross product weights each face by its area.
            let n = (b - a).cross(&(c - a));
            for &i in tri {
                normals[i as usize] += n;
            }
        }
        for n in &mut normals {
            *n = unit_or(*n, Vector3::z());
        }
        self.normals = normals;
    }
}

fn check_positions(positions: &[Vector3<f32>]) -> Result<()> {
    match positions
        .iter()
        .position(|p| !p.iter().all(|c| c.is_finite()))
    {
        Some(vertex) => Err(MeshError::NonFiniteVertex {
            vertex,
            position: positions[vertex].into(),
        }
        .into()),
        None => Ok(()),
    }
}

fn bounding_diagonal(positions: &[Vector3<f32>]) -> f32 {
    let mut lo = Vector3::repeat(f32::INFINITY);
    let mut hi = Vector3::repeat(f32::NEG_INFINITY);
    for p in positions {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    (hi - lo).norm()
}

fn unit_or(v: Vector3<f32>, fallback: Vector3<f32>) -> Vector3<f32> {
    let n = v.norm();
    if n > 1e-20 && n.is_finite() {
        v / n
    } else {
        fallback
    }
}

/// A stable point on a mesh surface: triangle index and barycentric weights (summing to 1).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct MeshSample {
    /// Index into [`TriMesh::triangles`].
    pub triangle: u32,
    /// Barycentric weights of the triangle's three corners, each in [0, 1], summing to 1.
    pub weights: [f32; 3],
}

impl MeshSample {
    /// Checks the sample against `mesh`: triangle in range, weights finite, in [0, 1], sum 1.
    pub fn validate(&self, mesh: &TriMesh) -> Result<()> {
        if self.triangle as usize >= mesh.triangles().len() {
            return Err(MeshError::SampleTriangle {
                triangle: self.triangle,
                triangles: mesh.triangles().len(),
            }
            .into());
        }
        let sum: f32 = self.weights.iter().sum();
        let in_range = self
            .weights
            .iter()
            .all(|w| w.is_finite() && (-1e-5..=1.0 + 1e-5).contains(w));
        if !in_range || (sum - 1.0).abs() > 1e-4 {
            return Err(MeshError::SampleWeights {
                weights: self.weights,
            }
            .into());
        }
        Ok(())
    }
}

/// Position and orientation of a hair root, meters. Local axes: x = surface tangent,
/// y = bitangent, z = surface normal (the direction hair grows by default).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RootFrame {
    /// Root position, meters (world space).
    pub origin: Vector3<f32>,
    /// Rotation from root-local to world coordinates.
    pub rotation: UnitQuaternion<f32>,
}

impl RootFrame {
    /// The identity frame at `origin`: local axes equal world axes.
    pub fn at(origin: Vector3<f32>) -> Self {
        Self {
            origin,
            rotation: UnitQuaternion::identity(),
        }
    }

    /// Builds the frame from a unit normal and any vector along the surface (made orthogonal to
    /// the normal); falls back to a perpendicular of the normal if `edge` is parallel to it.
    pub fn from_normal_and_edge(
        origin: Vector3<f32>,
        normal: Vector3<f32>,
        edge: Vector3<f32>,
    ) -> Self {
        let mut tangent = edge - normal * normal.dot(&edge);
        if tangent.norm_squared() < 1e-20 * edge.norm_squared().max(1e-30)
            || tangent.norm_squared() == 0.0
        {
            tangent = any_perpendicular(&normal);
        }
        let tangent = tangent.normalize();
        let bitangent = normal.cross(&tangent);
        let m = Matrix3::from_columns(&[tangent, bitangent, normal]);
        let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m));
        Self { origin, rotation }
    }

    /// Maps a root-local point (meters) to world space.
    pub fn to_world(&self, local: &Vector3<f32>) -> Vector3<f32> {
        self.origin + self.rotation * local
    }

    /// Maps a world point (meters) to root-local coordinates.
    pub fn to_local(&self, world: &Vector3<f32>) -> Vector3<f32> {
        self.rotation.inverse() * (world - self.origin)
    }

    /// This frame moved by a rigid transform (e.g. a body frame carried by the head).
    pub fn moved_by(&self, iso: &Isometry3<f32>) -> Self {
        Self {
            origin: iso.rotation * self.origin + iso.translation.vector,
            rotation: iso.rotation * self.rotation,
        }
    }

    /// Interpolates between two frames: linear in position, spherical in rotation; `s` in [0, 1].
    pub fn interpolate(&self, other: &Self, s: f32) -> Self {
        Self {
            origin: self.origin.lerp(&other.origin, s),
            rotation: self.rotation.nlerp(&other.rotation, s),
        }
    }
}

/// Any unit vector perpendicular to the unit vector `n`.
pub fn any_perpendicular(n: &Vector3<f32>) -> Vector3<f32> {
    let helper = if n.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    n.cross(&helper).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad() -> TriMesh {
        let p = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(1.0, 1.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
        ];
        TriMesh::new(p, vec![[0, 1, 2], [0, 2, 3]]).unwrap()
    }

    #[test]
    fn frame_is_orthonormal_with_z_along_normal() {
        let mesh = quad();
        let f = mesh.evaluate(&MeshSample {
            triangle: 0,
            weights: [0.2, 0.3, 0.5],
        });
        assert!((f.origin - Vector3::new(0.8, 0.5, 0.0)).norm() < 1e-6);
        let m = f.rotation.to_rotation_matrix();
        assert!((m * Vector3::z() - Vector3::z()).norm() < 1e-6);
        assert!((m * Vector3::x() - Vector3::x()).norm() < 1e-6);
    }

    #[test]
    fn sample_follows_rigid_motion() {
        let mesh = quad();
        let s = MeshSample {
            triangle: 1,
            weights: [0.1, 0.6, 0.3],
        };
        let iso = Isometry3::new(Vector3::new(1.0, 2.0, 3.0), Vector3::new(0.3, -0.2, 1.1));
        let moved = mesh.transformed(&iso);
        let expect = mesh.evaluate(&s).moved_by(&iso);
        let got = moved.evaluate(&s);
        assert!((expect.origin - got.origin).norm() < 1e-5);
        assert!(expect.rotation.angle_to(&got.rotation) < 1e-4);
    }

    #[test]
    fn degenerate_triangle_is_named() {
        let p = vec![
            Vector3::zeros(),
            Vector3::x(),
            Vector3::x() * 2.0,
            Vector3::y(),
        ];
        let err = TriMesh::new(p, vec![[0, 1, 3], [0, 1, 2]]).unwrap_err();
        assert!(err.to_string().contains("triangle 1"), "{err}");
    }

    #[test]
    fn index_out_of_range_is_refused() {
        let err = TriMesh::new(vec![Vector3::zeros(); 3], vec![[0, 1, 5]]).unwrap_err();
        assert!(err.to_string().contains("vertex 5"), "{err}");
    }
}
