//! The head as the strip model sees it: a bounding sphere for the cheap first test and a closed,
//! oriented triangle mesh (parry) for the precise second one (seed 000: "a sphere to check the
//! hair against, then a more specific test against the mesh").

use nalgebra::{Isometry3, Point3, Vector3};
use parry3d::query::{PointQuery, PointQueryWithLocation};
use parry3d::shape::{TriMesh as ParryMesh, TriMeshFlags};

use crate::contacts::math::{from_glam, to_glam};
use crate::error::{MeshError, Result};
use crate::mesh::TriMesh;

/// A closed head mesh in body space (m) with its bounding sphere; posed each frame by the
/// scalp's body transform.
#[derive(Clone)]
pub struct HeadShape {
    mesh: ParryMesh,
    centre: Vector3<f32>,
    radius: f32,
}

impl std::fmt::Debug for HeadShape {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HeadShape")
            .field("centre", &self.centre)
            .field("radius", &self.radius)
            .finish_non_exhaustive()
    }
}

impl HeadShape {
    /// The head from its rest mesh in body space (m). The mesh must be closed and consistently
    /// oriented (outward normals) for the inside test; refuses a mesh parry cannot orient.
    pub fn new(rest: &TriMesh) -> Result<Self> {
        let vertices = rest.positions().iter().map(to_glam).collect();
        let mesh =
            ParryMesh::with_flags(vertices, rest.triangles().to_vec(), TriMeshFlags::ORIENTED)
                .map_err(MeshError::Head)?;
        let n = rest.positions().len().max(1) as f32;
        let centre = rest.positions().iter().sum::<Vector3<f32>>() / n;
        let radius = rest
            .positions()
            .iter()
            .map(|p| (p - centre).norm())
            .fold(0.0f32, f32::max);
        Ok(Self {
            mesh,
            centre,
            radius,
        })
    }

    /// Centre (body space, m) and radius (m) of the bounding sphere.
    pub fn bounding_sphere(&self) -> (Vector3<f32>, f32) {
        (self.centre, self.radius)
    }

    /// First stage: true when world point `p` is within `margin` (m) of the bounding sphere of
    /// the head posed at `body`.
    pub fn near(&self, body: &Isometry3<f32>, p: &Vector3<f32>, margin: f32) -> bool {
        let local = body.inverse_transform_point(&Point3::from(*p)).coords;
        (local - self.centre).norm() <= self.radius + margin
    }

    /// Signed distance (m) from world point `p` to the head posed at `body`: negative inside.
    pub fn signed_distance(&self, body: &Isometry3<f32>, p: &Vector3<f32>) -> f32 {
        let local = body.inverse_transform_point(&Point3::from(*p)).coords;
        let proj = self.mesh.project_local_point(to_glam(&local), false);
        let d = (to_glam(&local) - proj.point).length();
        if proj.is_inside {
            -d
        } else {
            d
        }
    }

    /// Second stage: if world point `p` is inside the head posed at `body` or closer than
    /// `clearance` (m) to it, the point moved out along the surface normal to exactly `clearance`
    /// from the surface; `None` when it is already clear (including every point outside the
    /// bounding sphere, which is not tested further).
    pub fn push_out(
        &self,
        body: &Isometry3<f32>,
        p: &Vector3<f32>,
        clearance: f32,
    ) -> Option<Vector3<f32>> {
        if !self.near(body, p, clearance) {
            return None;
        }
        let local = body.inverse_transform_point(&Point3::from(*p)).coords;
        let (proj, (triangle, _)) = self
            .mesh
            .project_local_point_and_get_location(to_glam(&local), false);
        let on = from_glam(proj.point);
        let offset = local - on;
        let dist = offset.norm();
        if !proj.is_inside && dist >= clearance {
            return None;
        }
        // Outward normal: along the offset when clearly off the surface, else the face's normal
        // of the nearest triangle (or, failing that, the direction from the sphere's centre).
        let normal = if dist > 1e-6 {
            if proj.is_inside {
                -offset / dist
            } else {
                offset / dist
            }
        } else {
            self.mesh
                .triangle(triangle)
                .normal()
                .map(from_glam)
                .or_else(|| (on - self.centre).try_normalize(1e-12))
                .unwrap_or(Vector3::z())
        };
        Some(body * Point3::from(on + normal * clearance)).map(|q| q.coords)
    }
}
