//! Deforming mesh colliders: a mesh collider's vertex positions, set per frame by the host
//! ([`super::Colliders::set_vertices`]) or taken from a deformed scalp
//! ([`super::Colliders::insert_scalp`]), on top of its rigid pose.
//!
//! # Model
//! The host gives each mesh's vertices in its **body space** (the space of
//! [`super::Collider::mesh`]; the pose set by [`super::Colliders::set_pose`] places them in the
//! world) at the end of each frame. Within the frame every vertex moves linearly from its
//! previous position to the new one, so a point of the surface — a triangle and barycentric
//! weights — moves linearly too, at the barycentric blend of its vertices' velocities. At every
//! collision step the collider's shape (parry's mesh and BVH, smooth vertex normals, per-triangle
//! curvature, the narrow-phase shortcut) is put at the vertices of the step's start, and the
//! step's vertex displacements give each contact the motion of its material point: the contact
//! plane moves with it, the contact sphere moves with it and turns with its triangle (its centre
//! swings by the turn of the triangle's normal times the sphere's radius), and friction acts
//! against the point's velocity (rigid pose motion included). Between steps nothing is
//! interpolated: the shape at a step's start is exact.
//!
//! # What is exact, what is approximate
//! - Exact at every step's start: positions, normals, curvature and inside/outside of the
//!   linearly interpolated mesh. The frame-end check runs against the mesh at the frame's end.
//! - Exact within a step for the contact point itself: its path is the straight line its
//!   vertices' blend follows.
//! - Exact within a step where the surface around a contact moves rigidly (translates and turns
//!   with the contact's triangle): a sliding plate, a head turned by skinning.
//! - Approximate within a step where it bends: a sphere that slides `δ` with a surface whose
//!   curvature changes by `Δκ` misses the new bend by up to `Δκ δ²/2`. Frames are split into more
//!   steps until the largest such error over the mesh's edges, divided by `k²`, is below the
//!   contact tolerance (see [`super::collider_set`]). A plane does not turn within a step (as for
//!   rigid colliders). Triangles that degenerate while deforming are allowed; the shortcut skips
//!   them and parry's search handles them.
//! - Measured (tests `deforming_colliders`): hair resting on a sphere breathing from 0.10 to
//!   0.13 m, on a head turned by skinning at 10 rad/s and on a shoulder rising 5 cm in two frames
//!   keeps its point centres outside the mesh at every frame (smallest gap 0.80–0.85 mm for a
//!   1 mm hair radius, against 0.67–0.8 mm on the still head: the facets' sagitta); hair dragged
//!   by a slab sliding by deformation ends within 3e-7 m of the same slide done by a pose.
//! - Detection's margin grows by the largest vertex displacement of the step, and its
//!   remembered distance bounds shrink by how far the surface moved, so no contact is missed
//!   because the surface came towards a point.
//!
//! # Cost
//! Each step whose shape differs from the last one refits parry's BVH (its tree, built once at
//! insertion, is kept: `TriMesh::set_vertices`), recomputes parry's pseudo-normals, the smooth
//! normals, the curvatures and the shortcut's planes, and each deforming frame measures its
//! displacement and change of bending: linear in the mesh size, measured in
//! `benches/deforming.rs`. A frame of one step pays one reshape (at its end, which is the next
//! frame's start); a frame split into `k` steps pays `k`. A collider that does not deform in a
//! frame pays a comparison of its vertex arrays. The rod model (`crate::model::rod`) projects onto
//! the shape in every substep: it sees a deforming mesh at the frame's end for the whole frame, and
//! its distance memory is reset whenever the shape moved.
//!
//! # Resuming
//! The state of a deforming collider is its vertices at the current frame. A run resumed at
//! frame `k` inserts the collider from the same mesh as the uninterrupted run (its topology —
//! merged seam vertices, solid or shell, winding, the BVH's tree — comes from that mesh) and puts
//! it at frame `k`'s vertices with [`super::Colliders::place_vertices`] (or
//! [`super::Colliders::place_scalp`] for the scalp): the shape is then the same bits as the
//! uninterrupted run's at that frame, because everything the shape holds is recomputed from the
//! vertices alone and the refitted tree depends only on its leaves.

use std::collections::HashMap;

use hair_par::prelude::*;
use nalgebra::{Isometry3, Point3, Vector3};

use crate::error::{HairError, Result};
use crate::mesh::TriMesh;

/// Relative size (of the distance from the world origin, plus 1 m) below which a scalp vertex
/// that differs from its rest position moved by the body transform counts as rounding, not
/// deformation: 5 µm near the origin, 0.2 mm 40 m away. That is about 40 f32 ulps; the rounding
/// of a rigid transform there and back was measured at up to 5.2 (test
/// `a_rigidly_moved_scalp_keeps_the_rest_vertices_to_the_bit`).
const RIGID_ROUNDING: f32 = 5e-6;

/// A mesh collider's vertices: as inserted, at the start and end of the frame being stepped, and
/// where its shape stands now. Merged vertices (see `collider::prepare_mesh`), body space, m.
#[derive(Debug, Clone)]
pub(crate) struct Deformation {
    /// Per vertex the host gives (the inserted mesh's order): its merged index.
    remap: Vec<u32>,
    /// Per merged vertex: the first host vertex that maps to it.
    source: Vec<u32>,
    /// The inserted mesh's triangles (host order), to check a deformed scalp against.
    host_triangles: Vec<[u32; 3]>,
    /// Vertices as inserted.
    rest: Vec<Vector3<f32>>,
    /// At the start of the frame being stepped.
    start: Vec<Vector3<f32>>,
    /// At the end of the frame being stepped (what the host set).
    end: Vec<Vector3<f32>>,
    /// Where the collider's shape stands now.
    pub placed: Vec<Vector3<f32>>,
    /// Displacement of each vertex over the current collision step, m (empty when the mesh does
    /// not deform in this frame).
    pub step_motion: Vec<Vector3<f32>>,
    /// Largest `|step_motion|`, m.
    pub step_margin: f32,
    /// Does the mesh deform in this frame (start ≠ end)?
    moving: bool,
    /// Largest vertex displacement over this frame, m.
    pub frame_displacement: f32,
    /// The merged triangles (as parry holds them).
    merged_triangles: Vec<[u32; 3]>,
    /// Every edge between exactly two triangles: the two triangles and the edge's vertices.
    hinges: Vec<Hinge>,
    /// The contact model's error (m) over this frame in one step: over the hinges, `Δκ δ²/2`
    /// with `Δκ` the change of the hinge's bending (the angle between its triangles' normals
    /// over the distance of their centroids, 1/m: `1/R` on a fine sphere of radius `R`) and `δ`
    /// the larger displacement of the edge's vertices.
    pub frame_error: f32,
}

/// An edge between two triangles (indices into the merged triangles and vertices).
#[derive(Debug, Clone, Copy)]
struct Hinge {
    triangles: [u32; 2],
    edge: [u32; 2],
}

impl Deformation {
    /// The deformation state of a mesh inserted as `mesh` (host order) whose merged vertices are
    /// `merged` and `remap` maps host to merged indices.
    pub fn new(
        mesh: &TriMesh,
        merged: &[Vector3<f32>],
        merged_triangles: &[[u32; 3]],
        remap: Vec<u32>,
    ) -> Self {
        let mut by_edge: HashMap<(u32, u32), Vec<u32>> = HashMap::new();
        for (t, tri) in merged_triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                by_edge
                    .entry((a.min(b), a.max(b)))
                    .or_default()
                    .push(t as u32);
            }
        }
        let mut hinges: Vec<Hinge> = by_edge
            .iter()
            .filter_map(|(&(a, b), tris)| match tris.as_slice() {
                &[t1, t2] => Some(Hinge {
                    triangles: [t1, t2],
                    edge: [a, b],
                }),
                _ => None,
            })
            .collect();
        hinges.sort_unstable_by_key(|h| h.edge);
        let mut source = vec![u32::MAX; merged.len()];
        for (i, &m) in remap.iter().enumerate() {
            let s = &mut source[m as usize];
            if *s == u32::MAX {
                *s = i as u32;
            }
        }
        Self {
            remap,
            source,
            host_triangles: mesh.triangles().to_vec(),
            rest: merged.to_vec(),
            start: merged.to_vec(),
            end: merged.to_vec(),
            placed: merged.to_vec(),
            step_motion: Vec::new(),
            step_margin: 0.0,
            moving: false,
            frame_displacement: 0.0,
            merged_triangles: merged_triangles.to_vec(),
            hinges,
            frame_error: 0.0,
        }
    }

    /// Checks host vertices (count, finiteness) for collider `collider`.
    fn check(&self, collider: usize, vertices: &[Vector3<f32>], what: &str) -> Result<()> {
        if vertices.len() != self.remap.len() {
            return Err(HairError::Collider {
                collider,
                message: format!(
                    "{what} has {} vertices, the mesh it was inserted with has {}: give one \
                     position per vertex of that mesh, in its order (a deforming mesh cannot \
                     change its topology)",
                    vertices.len(),
                    self.remap.len()
                ),
            });
        }
        if let Some(i) = vertices
            .iter()
            .position(|v| !v.iter().all(|c| c.is_finite()))
        {
            return Err(HairError::Collider {
                collider,
                message: format!(
                    "{what}: vertex {i} is not finite ({:?}); give finite positions",
                    vertices[i].as_slice()
                ),
            });
        }
        Ok(())
    }

    /// The merged vertices of host vertices `vertices`.
    fn gather(&self, vertices: &[Vector3<f32>]) -> Vec<Vector3<f32>> {
        self.source.iter().map(|&i| vertices[i as usize]).collect()
    }

    /// Sets the body-space vertices (host order, m) at the end of the next frame.
    pub fn set_end(&mut self, collider: usize, vertices: &[Vector3<f32>]) -> Result<()> {
        self.check(collider, vertices, "the vertex array")?;
        self.end = self.gather(vertices);
        Ok(())
    }

    /// Puts the mesh at body-space vertices `vertices` (host order, m) now: start and end of
    /// the next frame, no motion.
    pub fn place(&mut self, collider: usize, vertices: &[Vector3<f32>]) -> Result<()> {
        self.check(collider, vertices, "the vertex array")?;
        self.end = self.gather(vertices);
        self.start.clone_from(&self.end);
        Ok(())
    }

    /// Sets the end vertices from a scalp mesh `mesh` (world, m) with body transform `body`: its
    /// vertices brought to body space if any differs from the rest mesh moved by `body` by more
    /// than rounding, else exactly the rest vertices (so a rigid scalp never deforms the shape).
    pub fn follow_scalp(
        &mut self,
        collider: usize,
        mesh: &TriMesh,
        body: &Isometry3<f32>,
    ) -> Result<()> {
        let what = "the deformed scalp mesh";
        self.check(collider, mesh.positions(), what)?;
        if mesh.triangles() != self.host_triangles.as_slice() {
            return Err(HairError::Collider {
                collider,
                message: format!(
                    "{what} has other triangles than the scalp the collider was built from: \
                     a deforming scalp must keep its topology"
                ),
            });
        }
        let inverse = body.inverse();
        let local: Vec<Vector3<f32>> = mesh
            .positions()
            .iter()
            .map(|p| (inverse * Point3::from(*p)).coords)
            .collect();
        let deformed = mesh
            .positions()
            .iter()
            .zip(&local)
            .zip(&self.remap)
            .any(|((p, l), &m)| {
                (l - self.rest[m as usize]).norm() > RIGID_ROUNDING * (1.0 + p.norm())
            });
        if deformed {
            self.end = self.gather(&local);
        } else {
            self.end.clone_from(&self.rest);
        }
        Ok(())
    }

    /// The merged triangles (parry's indices).
    pub fn merged_triangles(&self) -> &[[u32; 3]] {
        &self.merged_triangles
    }

    /// Starts a frame: notes whether the mesh deforms in it and by how much (largest vertex
    /// displacement and largest change of bending).
    pub fn begin_frame(&mut self) {
        self.moving = self.start != self.end;
        if !self.moving {
            self.frame_displacement = 0.0;
            self.frame_error = 0.0;
            return;
        }
        self.frame_displacement = self
            .start
            .iter()
            .zip(&self.end)
            .map(|(a, b)| (b - a).norm())
            .fold(0.0f32, f32::max);
        // Per triangle: unit normal and centroid, at the frame's start and end.
        let faces = |v: &[Vector3<f32>]| -> Vec<(Vector3<f32>, Vector3<f32>)> {
            self.merged_triangles
                .par_iter()
                .map(|t| {
                    let [a, b, c] = t.map(|i| v[i as usize]);
                    ((b - a).cross(&(c - a)).normalize(), (a + b + c) / 3.0)
                })
                .collect()
        };
        let (before, after) = hair_par::join(|| faces(&self.start), || faces(&self.end));
        self.frame_error = hair_par::reduce(
            self.hinges
                .par_iter()
                .map(|h| {
                    let [t1, t2] = h.triangles.map(|t| t as usize);
                    let [a, b] = h.edge.map(|i| i as usize);
                    // The angle between the normals by its chord 2 sin(θ/2) (θ to within 5 % up to
                    // 60°), over the distance of the centroids.
                    let bend = |f: &[(Vector3<f32>, Vector3<f32>)]| {
                        (f[t2].0 - f[t1].0).norm() / (f[t2].1 - f[t1].1).norm()
                    };
                    let change = (bend(&after) - bend(&before)).abs();
                    let slide = (self.end[a] - self.start[a])
                        .norm()
                        .max((self.end[b] - self.start[b]).norm());
                    0.5 * change * slide * slide
                })
                .filter(|e| e.is_finite()),
            || 0.0f32,
            f32::max,
        );
    }

    /// Ends a frame: the end vertices become the next frame's start.
    pub fn finish_frame(&mut self) {
        self.start.clone_from(&self.end);
        self.moving = false;
        self.frame_displacement = 0.0;
        self.frame_error = 0.0;
    }

    /// Vertex `i` at fraction `s` of the frame.
    fn at(&self, i: usize, s: f32) -> Vector3<f32> {
        if !self.moving || s == 1.0 {
            self.end[i]
        } else if s == 0.0 {
            self.start[i]
        } else {
            self.start[i] + (self.end[i] - self.start[i]) * s
        }
    }

    /// Prepares the step whose shape stands at fraction `at` of the frame and which moves from
    /// fraction `from` to `to`: the step's vertex motion and margin, and the vertices the shape
    /// must stand at. Returns those vertices if they differ from where it stands.
    pub fn prepare_step(&mut self, at: f32, from: f32, to: f32) -> Option<Vec<Vector3<f32>>> {
        let n = self.end.len();
        if self.moving {
            self.step_motion = (0..n).map(|i| self.at(i, to) - self.at(i, from)).collect();
            self.step_margin = self
                .step_motion
                .iter()
                .map(|d| d.norm())
                .fold(0.0f32, f32::max);
        } else {
            self.step_motion.clear();
            self.step_margin = 0.0;
        }
        if !self.moving {
            return (self.placed != self.end).then(|| self.end.clone());
        }
        let target: Vec<Vector3<f32>> = (0..n).map(|i| self.at(i, at)).collect();
        (target != self.placed).then_some(target)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contacts::collider::prepare_mesh;

    fn state(mesh: &TriMesh) -> Deformation {
        let prepared = prepare_mesh(mesh);
        Deformation::new(
            mesh,
            &prepared.vertices,
            &prepared.triangles,
            prepared.remap,
        )
    }

    #[test]
    fn a_rigidly_moved_scalp_keeps_the_rest_vertices_to_the_bit() {
        // The host moves the rest mesh by the body transform (far from the origin, turned): the
        // rounding of that transform must not count as deformation, or shipped rigid scenes
        // would reshape their scalp collider and change their caches.
        let rest = TriMesh::uv_sphere(0.12, 32, 16).unwrap();
        let mut d = state(&rest);
        let mut worst = 0.0f32;
        for k in 0..200 {
            let f = k as f32;
            let body = Isometry3::new(
                Vector3::new(3.0 * f.sin(), -0.2 * f, 1.7),
                Vector3::new(0.3 * f, -1.1, 2.0 + f.cos()),
            );
            let mesh = rest.transformed(&body);
            let inverse = body.inverse();
            for (p, r) in mesh.positions().iter().zip(rest.positions()) {
                let back = (inverse * Point3::from(*p)).coords;
                worst = worst.max((back - r).norm() / (1.0 + p.norm()));
            }
            d.follow_scalp(0, &mesh, &body).unwrap();
            d.begin_frame();
            assert!(d.end == d.rest && !d.moving, "body {k}");
            assert_eq!(d.prepare_step(0.0, 0.0, 1.0), None);
        }
        // In f32 ulps of the distance from the origin (2⁻²³ relative).
        let ulps = worst * 8_388_608.0;
        assert!(ulps < 8.0, "rounding of {ulps} ulps");
        let body = Isometry3::new(Vector3::new(3.0, -40.0, 1.7), Vector3::new(0.3, -1.1, 2.0));
        // A 1 mm bulge 40 m from the origin is a deformation.
        let mut bulged = rest.positions().to_vec();
        bulged[5].z += 1e-3;
        let mut mesh = rest.clone();
        mesh.set_positions(&bulged).unwrap();
        d.follow_scalp(0, &mesh.transformed(&body), &body).unwrap();
        d.begin_frame();
        assert!(d.moving && d.frame_displacement > 0.9e-3);
    }

    #[test]
    fn vertices_in_between_are_linear_and_the_ends_exact() {
        let rest = TriMesh::uv_sphere(0.1, 8, 4).unwrap();
        let mut d = state(&rest);
        let grown: Vec<_> = rest.positions().iter().map(|p| p * 1.5).collect();
        d.set_end(0, &grown).unwrap();
        d.begin_frame();
        let half = d.prepare_step(0.5, 0.5, 1.0).expect("the shape moves");
        let at_end = d.prepare_step(1.0, 0.5, 1.0).expect("the shape moves");
        for (k, &source) in d.source.iter().enumerate() {
            let p = rest.positions()[source as usize];
            assert!((half[k] - p * 1.25).norm() < 1e-7);
            assert_eq!(at_end[k], grown[source as usize]);
            assert!((d.step_motion[k] - p * 0.25).norm() < 1e-7);
        }
        assert!((d.frame_displacement - 0.05).abs() < 1e-6);
    }
}
