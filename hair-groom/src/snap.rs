//! Guides attached to a scalp: each curve of a [`Groom`] gets the nearest point of the scalp
//! mesh as its root ([`MeshSample`], found by parry's point projection onto a triangle mesh) and
//! its rest shape in that root's frame, so it turns and moves with the deforming scalp.
//!
//! A curve's root rarely lies exactly on the scalp (the Sintel guides sit 1–23 mm off their
//! coarse bust): snapping moves the whole curve rigidly by its root's offset to the surface, which
//! keeps its shape and every segment length. The offsets are reported, and curves whose root is
//! farther than a threshold are refused, all of them named, rather than silently moved far.

use hair_core::{Anchor, HairError, MeshError, MeshSample, StrandInput, TriMesh};
use nalgebra::Vector3;
use parry3d::math::Vector;
use parry3d::query::PointQueryWithLocation;

use crate::error::{parameter, FarRoot, GroomError};
use crate::groom::Groom;

/// A guide hair: a root on the scalp and a rest shape in that root's frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Guide {
    /// Where the root sits on the scalp mesh.
    pub root: MeshSample,
    /// Rest shape in root-frame coordinates (local +z = smooth surface normal), m; point 0 is the
    /// root at the origin. At least 2 points.
    pub rest: Vec<Vector3<f32>>,
}

impl Guide {
    /// The guide's points in world space on `mesh` at its current vertex positions, m.
    pub fn world_points(&self, mesh: &TriMesh) -> Vec<Vector3<f32>> {
        let frame = mesh.evaluate(&self.root);
        self.rest.iter().map(|p| frame.to_world(p)).collect()
    }

    /// The guide as a simulation strand: anchored at its root, its rest shape, masses lumped from
    /// `mass_per_length` (kg/m), radius `radius` (m), goal weights linear from `goal_root` to
    /// `goal_tip` (see [`StrandInput::uniform`]).
    pub fn to_strand_input(
        &self,
        mass_per_length: f32,
        radius: f32,
        goal_root: f32,
        goal_tip: f32,
    ) -> StrandInput {
        StrandInput::uniform(
            Anchor::Surface(self.root),
            self.rest.clone(),
            mass_per_length,
            radius,
            goal_root,
            goal_tip,
        )
    }
}

/// The world-space groom of `guides` on `mesh` (e.g. to export them with [`crate::formats`]).
pub fn guides_to_groom(mesh: &TriMesh, guides: &[Guide]) -> Result<Groom, GroomError> {
    Groom::new(guides.iter().map(|g| g.world_points(mesh)).collect())
}

/// How to attach a groom to a scalp.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SnapOptions {
    /// Largest accepted distance from a curve's root to the scalp, m; finite and ≥ 0. Curves
    /// farther away are refused.
    pub max_distance: f32,
}

/// Guides snapped to a scalp, with how far each root was moved.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapped {
    /// One guide per curve of the groom, in the groom's order.
    pub guides: Vec<Guide>,
    /// Distance from each curve's root to its scalp point (how far the curve was moved), m.
    pub distances: Vec<f32>,
}

impl Snapped {
    /// Smallest, median and largest snap distance, m (zeros for no guide).
    pub fn distance_summary(&self) -> [f32; 3] {
        let mut d = self.distances.clone();
        d.sort_by(f32::total_cmp);
        match d.len() {
            0 => [0.0; 3],
            n => [d[0], d[n / 2], d[n - 1]],
        }
    }
}

/// The scalp as a parry triangle mesh, for nearest-point queries.
pub(crate) fn searchable(mesh: &TriMesh) -> Result<parry3d::shape::TriMesh, GroomError> {
    let vertices = mesh
        .positions()
        .iter()
        .map(|p| Vector::new(p.x, p.y, p.z))
        .collect();
    parry3d::shape::TriMesh::new(vertices, mesh.triangles().to_vec())
        .map_err(|e| HairError::from(MeshError::Unsearchable(e)).into())
}

/// Attaches every curve of `groom` to the nearest point of `mesh`: the root becomes a
/// [`MeshSample`] there, the curve is moved rigidly by the root's offset, and its points are
/// expressed in the root frame (`rest = frame.to_local(moved point)`).
///
/// Refuses a `max_distance` that is not finite and ≥ 0, and every curve whose root is farther
/// than it ([`GroomError::RootsTooFar`] lists them with their distances).
pub fn snap_to_scalp(
    groom: &Groom,
    mesh: &TriMesh,
    opts: &SnapOptions,
) -> Result<Snapped, GroomError> {
    if !(opts.max_distance.is_finite() && opts.max_distance >= 0.0) {
        return Err(parameter(
            "max_snap_distance",
            opts.max_distance,
            "must be a finite distance ≥ 0 m (how far a guide root may lie from the scalp)",
        ));
    }
    let query = searchable(mesh)?;
    let mut guides = Vec::with_capacity(groom.len());
    let mut distances = Vec::with_capacity(groom.len());
    let mut far = Vec::new();
    for (s, curve) in groom.curves().iter().enumerate() {
        let root = curve[0];
        let (proj, (triangle, location)) =
            query.project_local_point_and_get_location(Vector::new(root.x, root.y, root.z), false);
        let distance = (Vector3::new(proj.point.x, proj.point.y, proj.point.z) - root).norm();
        if distance > opts.max_distance {
            far.push(FarRoot {
                strand: s,
                distance,
            });
            continue;
        }
        // The location is never `OnSolid` for a non-solid query; fall back to the first corner.
        let w = location
            .barycentric_coordinates()
            .unwrap_or([1.0, 0.0, 0.0])
            .map(|x| x.clamp(0.0, 1.0));
        let sum: f32 = w.iter().sum();
        let sample = MeshSample {
            triangle,
            weights: w.map(|x| x / sum),
        };
        let frame = mesh.evaluate(&sample);
        let offset = frame.origin - root;
        let rest = curve
            .iter()
            .map(|p| frame.to_local(&(p + offset)))
            .collect();
        guides.push(Guide { root: sample, rest });
        distances.push(distance);
    }
    if !far.is_empty() {
        return Err(GroomError::RootsTooFar {
            far,
            max_distance: opts.max_distance,
        });
    }
    Ok(Snapped { guides, distances })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::uv_sphere;

    #[test]
    fn roots_snap_onto_a_sphere_and_keep_their_shape() {
        let mesh = uv_sphere(0.1, 32, 16).unwrap();
        let dir = Vector3::new(0.3, -0.2, 0.9).normalize();
        let curve: Vec<Vector3<f32>> = (0..5)
            .map(|i| {
                dir * (0.105 + 0.01 * i as f32) + Vector3::new(0.0, 0.0, 0.002 * (i * i) as f32)
            })
            .collect();
        let groom = Groom::new(vec![curve.clone()]).unwrap();
        let snapped = snap_to_scalp(&groom, &mesh, &SnapOptions { max_distance: 0.01 }).unwrap();
        let d = snapped.distances[0];
        assert!((d - 0.005).abs() < 5e-4, "snap distance {d}");
        let g = &snapped.guides[0];
        assert_eq!(g.rest[0], Vector3::zeros());
        // Segment lengths kept; the world curve is the input moved by the root offset.
        let world = g.world_points(&mesh);
        let offset = world[0] - curve[0];
        assert!((offset.norm() - d).abs() < 1e-6);
        for (a, b) in world.iter().zip(&curve) {
            assert!((a - b - offset).norm() < 1e-6);
        }
        let strand = g.to_strand_input(1e-4, 1e-3, 1.0, 0.0);
        assert_eq!(strand.anchor, Anchor::Surface(g.root));
        // Too far: refused and named.
        let err = snap_to_scalp(
            &groom,
            &mesh,
            &SnapOptions {
                max_distance: 0.001,
            },
        )
        .unwrap_err()
        .to_string();
        assert!(
            err.contains("strand 0 (0.00") && err.contains("max_snap_distance"),
            "{err}"
        );
        let err = snap_to_scalp(
            &groom,
            &mesh,
            &SnapOptions {
                max_distance: f32::NAN,
            },
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("`max_snap_distance`"), "{err}");
    }
}
