//! [`Colliders`]: the colliders of a scene in a rapier `ColliderSet` with its broad phase, and
//! their rigid poses at the start and end of the frame being stepped.
//!
//! A host inserts colliders once, then sets each one's pose for every frame
//! ([`Colliders::set_pose`], the pose at the frame's end instant) before
//! [`crate::MassSpringSolver::step_frame_with_colliders`]. Within a frame a collider moves from the
//! previous frame's pose to the new one, translation linear and rotation by normalised quaternion
//! interpolation (the shorter way round), as the hair roots do. A mesh collider's vertices may
//! also move ([`Colliders::set_vertices`], body space, linear per vertex within the frame; see
//! [`super::deforming`]). A collider inserted with [`Colliders::insert_scalp`] follows the
//! scalp's body transform and, if the scalp mesh is deformed, its vertices by itself.
//!
//! **Fast motion.** The contact model of a step (`contacts::penalty`) is the surface element at
//! the contact — its tangent plane or the sphere of its smallest curvature — moving linearly with
//! the collider's material point at the contact or at the sphere's centre. For a translating
//! collider that is exact for planes and spheres at any speed, and conservative elsewhere: hair
//! sliding over a curved surface within a step is at worst held slightly off it (see
//! [`super::collider`]), never let in. What it misses is rotation: a material point moves on an
//! arc while the model moves along the chord, which lies inside the arc by up to `R θ²/8` for a
//! rotation `θ` (`R` the largest distance of the shape from its body origin, about which poses
//! rotate; contact spheres are only used with centres within `R`). A frame is therefore split
//! into `k` times the scene's steps with the smallest `k` such that, for every collider,
//!
//! ```text
//! R (θ/k)² / 8 ≤ tolerance
//! ```
//!
//! ([`ContactSettings::tolerance`], by default half the smallest hair radius: the response keeps
//! a gap of one hair radius, so point centres stay outside; at most [`ContactSettings::max_steps`]
//! steps in all). The head turning at 10 rad/s at 24 fps (θ = 0.42 rad per frame, R = 0.22 m,
//! hair radius 2 mm) takes 3 steps per frame; translation alone, however fast (a plate or a ball
//! at 1 m per frame), takes none. The substeps per step shrink by the same factor (rounded up), so
//! the substep never gets longer and the integration cost stays about the same; only detection
//! runs more often.
//!
//! **Deformation.** On a deforming mesh a contact's plane or sphere moves with its material
//! point and turns with its triangle, which is exact where the surface around the contact moves
//! rigidly. Where it bends — its curvature changes by `Δκ` within the frame — a sphere that
//! slides `δ` with the surface misses the new bend by up to `Δκ δ²/2`. The frame error of a
//! deforming mesh adds the largest `Δκ δ²/2` over its edges (`Δκ` from the change of the angle
//! between the edge's two triangles over the distance of their centroids, `δ` the larger
//! displacement of the edge's vertices), so `k` steps bring it to `Δκ δ²/(2k²)`. A sphere
//! growing from 0.1 m by 5 cm in a frame (`Δκ` = 3.3 /m) takes 3–4 steps at the default 0.5 mm
//! tolerance, a shoulder rising 5 cm in two frames 3; a translation or a rigid turn done by
//! moving vertices takes none (the shear of a skinned neck counts as bending: the test head
//! turned by skinning at 10 rad/s takes up to 6 steps where its rigid turn takes 3).

use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use parry3d::bounding_volume::BoundingVolume;
use rapier3d::dynamics::RigidBodySet;
use rapier3d::geometry::{
    Aabb, BroadPhaseBvh, ColliderBuilder, ColliderHandle, ColliderSet, SharedShape, TriMeshFlags,
};

use crate::error::{HairError, Result};
use crate::mesh::TriMesh;
use crate::strands::Scalp;

use super::collider::{
    min_curvatures, prepare_mesh, smooth_normals, Collider, ColliderShape, MeshKind,
};
use super::deforming::Deformation;
use super::detect::Clearance;
use super::fast_projection::FastProjection;
use super::math::{from_glam, to_glam, to_pose};
use super::settings::ContactSettings;

/// Index of a collider in its [`Colliders`] set, in insertion order from 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ColliderId(pub u32);

/// How the narrow phase treats a collider's shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Surface {
    /// Sphere, capsule or solid mesh: has an inside.
    Solid,
    /// Open or non-manifold mesh: two-sided, no inside.
    Shell,
}

/// What contact detection needs of a mesh besides parry's shape (all empty for analytic shapes).
#[derive(Debug, Clone, Default)]
pub(crate) struct MeshTopology {
    /// Smooth unit normal per vertex, body space.
    pub vertex_normals: Vec<Vector3<f32>>,
    /// Per triangle and edge `k` (vertices `k`, `k + 1`): the smallest index of a triangle
    /// using that edge.
    pub edge_owner: Vec<[u32; 3]>,
    /// Per vertex: the smallest index of a triangle using it.
    pub vertex_owner: Vec<u32>,
}

/// One collider's data besides its rapier shape.
#[derive(Debug, Clone)]
pub(crate) struct Entry {
    pub handle: ColliderHandle,
    /// The shape, shared with the rapier collider.
    pub shape: SharedShape,
    /// Centre (body space, m) and radius (m) of a sphere enclosing the shape.
    pub bounding_sphere: (Vector3<f32>, f32),
    pub thickness: f32,
    pub friction: f32,
    pub surface: Surface,
    pub mesh_kind: Option<MeshKind>,
    /// Smallest curvature per mesh triangle, 1/m (empty for analytic shapes).
    pub curvature: Vec<f32>,
    /// Smooth normals and feature owners of a mesh (empty for analytic shapes).
    pub topology: MeshTopology,
    /// The narrow-phase shortcut of a solid mesh.
    pub fast: Option<FastProjection>,
    /// Largest distance of a shape point from the body origin, m.
    pub bounding_radius: f32,
    /// Pose at the start of the frame being stepped.
    pub start: Isometry3<f32>,
    /// Pose at the end of the frame being stepped (what the host set).
    pub end: Isometry3<f32>,
    pub follows_scalp: bool,
    /// A mesh's vertices over the frame (`None` for analytic shapes).
    pub deformation: Option<Box<Deformation>>,
    /// How many times the shape was moved to other vertices (0: it is the inserted mesh).
    pub version: u64,
}

impl Entry {
    /// Pose at fraction `s` ∈ [0, 1] of the frame.
    pub fn pose_at(&self, s: f32) -> Isometry3<f32> {
        let translation = self
            .start
            .translation
            .vector
            .lerp(&self.end.translation.vector, s);
        Isometry3::from_parts(
            translation.into(),
            self.start.rotation.nlerp(&self.end.rotation, s),
        )
    }

    /// The model error (m) of one step covering the whole frame (see the module docs); with `k`
    /// steps it is this divided by `k²`: rotation's `R θ²/8` plus deformation's `Δκ δ²/2`.
    fn frame_error(&self) -> f32 {
        let angle = self.start.rotation.angle_to(&self.end.rotation);
        let rotation = 0.125 * self.bounding_radius * angle * angle;
        match &self.deformation {
            Some(d) if d.frame_error > 0.0 => rotation + d.frame_error,
            _ => rotation,
        }
    }

    /// Moves a mesh's shape to `vertices` (merged, body space, m) and recomputes everything
    /// derived from them (parry's BVH by refit and pseudo-normals, smooth normals, curvature,
    /// the shortcut, the bounds). Returns how far (m) the farthest vertex moved.
    fn reshape(&mut self, vertices: Vec<Vector3<f32>>) -> f32 {
        let Some(d) = self.deformation.as_mut() else {
            return 0.0;
        };
        let shift = vertices
            .iter()
            .zip(&d.placed)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0f32, f32::max);
        let Some(mesh) = self.shape.make_mut().as_trimesh_mut() else {
            return 0.0;
        };
        let points: Vec<_> = vertices.iter().map(to_glam).collect();
        // parry's refit and pseudo-normals on one thread, the rest on another.
        let triangles = d.merged_triangles();
        let (curvature, topology, fast) = (&mut self.curvature, &mut self.topology, &mut self.fast);
        hair_par::join(
            || mesh.set_vertices(&points),
            || {
                let normals = smooth_normals(&vertices, triangles);
                *curvature = min_curvatures(&vertices, triangles, &normals);
                topology.vertex_normals = normals;
                if let Some(fast) = fast {
                    fast.refresh(&points, triangles);
                }
            },
        );
        let (sphere, radius) = mesh_bounds(&self.shape, &vertices);
        self.bounding_sphere = sphere;
        self.bounding_radius = radius;
        d.placed = vertices;
        self.version += 1;
        shift
    }

    /// The broad-phase box of a moved mesh over the step from pose `start` to pose `end`: its
    /// vertices' box at the step's start and end, at both poses.
    fn swept_mesh_aabb(&self, start: &Isometry3<f32>, end: &Isometry3<f32>) -> Option<Aabb> {
        let d = self.deformation.as_ref()?;
        let mut lo = Vector3::repeat(f32::INFINITY);
        let mut hi = Vector3::repeat(f32::NEG_INFINITY);
        for (i, v) in d.placed.iter().enumerate() {
            lo = lo.inf(v);
            hi = hi.sup(v);
            if let Some(m) = d.step_motion.get(i) {
                lo = lo.inf(&(v + m));
                hi = hi.sup(&(v + m));
            }
        }
        let local = Aabb::new(to_glam(&lo), to_glam(&hi));
        Some(
            local
                .transform_by(&to_pose(start))
                .merged(&local.transform_by(&to_pose(end))),
        )
    }
}

/// The colliders hair collides with, their rapier collider set and broad phase, and the settings
/// of fast-motion stepping. See the module docs.
///
/// All of it is state that a snapshot keeps, contact detection's memory included: its
/// warm-start triangles can choose between near-tied features inside a solid (see
/// [`crate::contacts`], "Resuming"), so a set without it is not certain to give the same bits.
#[derive(Clone)]
pub struct Colliders {
    pub(crate) set: ColliderSet,
    pub(crate) broad_phase: BroadPhaseBvh,
    pub(crate) bodies: RigidBodySet,
    pub(crate) entries: Vec<Entry>,
    pub(crate) clearance: Clearance,
    /// Fast-motion stepping and push-out speed.
    pub settings: ContactSettings,
}

impl std::fmt::Debug for Colliders {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Colliders")
            .field("entries", &self.entries)
            .field("settings", &self.settings)
            .finish_non_exhaustive()
    }
}

impl Default for Colliders {
    fn default() -> Self {
        Self::new()
    }
}

impl Colliders {
    /// An empty set with the default fast-motion settings.
    pub fn new() -> Self {
        Self {
            set: ColliderSet::new(),
            broad_phase: BroadPhaseBvh::new(),
            bodies: RigidBodySet::new(),
            entries: Vec::new(),
            clearance: Clearance::default(),
            settings: ContactSettings::default(),
        }
    }

    /// Number of colliders.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True when there is no collider (the solver then does no contact work at all).
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Adds a collider at `pose` (its pose at the current frame). Refuses bad sizes, thickness,
    /// friction or a non-finite pose, naming the collider by the index it would get.
    pub fn insert(&mut self, collider: Collider, pose: Isometry3<f32>) -> Result<ColliderId> {
        self.insert_entry(collider, pose, false)
    }

    /// Adds the scalp mesh as a collider for the hair rooted on it: the shape is `scalp.mesh`
    /// brought back to body space by `scalp.body`, and at every frame it follows the scalp the
    /// solver is given: its body transform as the pose and, where `scalp.mesh` is deformed (a
    /// vertex differs from this mesh moved by `scalp.body` by more than f32 rounding, 5 µm
    /// near the origin), its vertices brought back to body space (see [`super::deforming`]). The scalp
    /// mesh must keep its vertex count and triangles. Hair roots and pinned points are never
    /// pushed by any collider.
    pub fn insert_scalp(
        &mut self,
        scalp: &Scalp,
        thickness: f32,
        friction: f32,
    ) -> Result<ColliderId> {
        let Some(mesh) = &scalp.mesh else {
            return Err(HairError::Collider {
                collider: self.len(),
                message: "the scalp has no mesh to collide with; give the scalp a mesh or \
                          switch scalp collision off"
                    .into(),
            });
        };
        check_pose(self.len(), &scalp.body)?;
        let body_space = mesh.transformed(&scalp.body.inverse());
        self.insert_scalp_rest(body_space, scalp.body, thickness, friction)
    }

    /// Adds the scalp as a collider from its rest mesh `rest` (body space, m), posed at `body`
    /// (the scalp's body transform at the current frame); otherwise like
    /// [`Colliders::insert_scalp`]. The shape is then the same bits whatever frame the set is
    /// built at (the posed mesh brought back to body space is rounded differently at every
    /// frame), so a run resumed from a later frame collides with exactly the shape of the
    /// uninterrupted run. Where the scalp is deformed at that frame, follow with
    /// [`Colliders::place_scalp`].
    pub fn insert_scalp_rest(
        &mut self,
        rest: TriMesh,
        body: Isometry3<f32>,
        thickness: f32,
        friction: f32,
    ) -> Result<ColliderId> {
        check_pose(self.len(), &body)?;
        let collider = Collider::mesh(rest)
            .with_thickness(thickness)
            .with_friction(friction);
        self.insert_entry(collider, body, true)
    }

    fn insert_entry(
        &mut self,
        collider: Collider,
        pose: Isometry3<f32>,
        follows_scalp: bool,
    ) -> Result<ColliderId> {
        let index = self.len();
        collider.validate(index)?;
        check_pose(index, &pose)?;
        let mut deformation = None;
        let (shape, surface, mesh_kind, bounding_radius, curvature, topology) = match &collider
            .shape
        {
            ColliderShape::Sphere { radius } => (
                SharedShape::ball(*radius),
                Surface::Solid,
                None,
                collider.shape.bounding_radius(),
                Vec::new(),
                MeshTopology::default(),
            ),
            ColliderShape::Capsule {
                half_height,
                radius,
            } => (
                SharedShape::capsule_z(*half_height, *radius),
                Surface::Solid,
                None,
                collider.shape.bounding_radius(),
                Vec::new(),
                MeshTopology::default(),
            ),
            ColliderShape::Mesh(mesh) => {
                let prepared = prepare_mesh(mesh);
                let (surface, flags) = match prepared.kind {
                    MeshKind::Solid { .. } => (Surface::Solid, TriMeshFlags::ORIENTED),
                    MeshKind::Shell { .. } => (Surface::Shell, TriMeshFlags::empty()),
                };
                let radius = prepared
                    .vertices
                    .iter()
                    .map(|v| v.norm())
                    .fold(0.0f32, f32::max);
                let vertices = prepared.vertices.iter().map(to_glam).collect();
                let shape =
                    SharedShape::trimesh_with_flags(vertices, prepared.triangles.clone(), flags)
                        .map_err(|e| HairError::Collider {
                            collider: index,
                            message: format!("the mesh was refused by parry: {e}"),
                        })?;
                deformation = Some(Box::new(Deformation::new(
                    mesh,
                    &prepared.vertices,
                    &prepared.triangles,
                    prepared.remap,
                )));
                (
                    shape,
                    surface,
                    Some(prepared.kind),
                    radius,
                    prepared.curvature,
                    MeshTopology {
                        vertex_normals: prepared.vertex_normals,
                        edge_owner: prepared.edge_owner,
                        vertex_owner: prepared.vertex_owner,
                    },
                )
            }
        };
        self.clearance.reset();
        let local = shape.compute_local_aabb();
        let centre = from_glam((local.mins + local.maxs) * 0.5);
        let enclosing = match &collider.shape {
            ColliderShape::Mesh(mesh) => mesh
                .positions()
                .iter()
                .map(|v| (v - centre).norm())
                .fold(0.0f32, f32::max),
            _ => bounding_radius,
        };
        let fast = match (surface, shape.as_trimesh()) {
            (Surface::Solid, Some(mesh)) => Some(FastProjection::new(mesh, 0.1 * bounding_radius)),
            _ => None,
        };
        let handle = self
            .set
            .insert(ColliderBuilder::new(shape.clone()).position(to_pose(&pose)));
        self.entries.push(Entry {
            handle,
            shape,
            bounding_sphere: (centre, enclosing),
            thickness: collider.thickness,
            friction: collider.friction,
            surface,
            mesh_kind,
            topology,
            fast,
            bounding_radius,
            start: pose,
            end: pose,
            follows_scalp,
            curvature,
            deformation,
            version: 0,
        });
        Ok(ColliderId(index as u32))
    }

    /// Sets the pose of collider `id` at the end of the next frame to be stepped (m, rotation).
    pub fn set_pose(&mut self, id: ColliderId, pose: Isometry3<f32>) -> Result<()> {
        let index = id.0 as usize;
        check_pose(index, &pose)?;
        let entry = self
            .entries
            .get_mut(index)
            .ok_or_else(|| HairError::Collider {
                collider: index,
                message: "no such collider in this set".into(),
            })?;
        entry.end = pose;
        Ok(())
    }

    /// Sets the vertex positions of mesh collider `id` at the end of the next frame to be
    /// stepped: body space (the space of [`Collider::mesh`], placed by the pose of
    /// [`Colliders::set_pose`]), m, one per vertex of the mesh it was inserted with, in that
    /// order. Within the frame each vertex moves linearly from its previous position, and
    /// contacts get the surface's velocity from that motion (see [`super::deforming`]).
    ///
    /// Refuses an unknown id, an analytic shape, the scalp collider (it follows the scalp given
    /// to the solver), another vertex count (the topology is fixed at insertion) and non-finite
    /// positions, naming the collider and the vertex.
    pub fn set_vertices(&mut self, id: ColliderId, vertices: &[Vector3<f32>]) -> Result<()> {
        let index = id.0 as usize;
        self.deformation_mut(index)?.set_end(index, vertices)
    }

    /// Says that mesh collider `id` will deform (a scene or host animates its vertices): the
    /// projection shortcut skips its per-triangle clearances from the start. A clearance holds
    /// for one shape only and costs a few hundred projections, so on a mesh that deforms within
    /// a few steps computing it is a loss (see `fast_projection`, "Deforming meshes"); the
    /// answers are the same features either way. Without the call a mesh drops them at its
    /// first deformation. For the scalp's collider too. Refuses an id that is not a mesh
    /// collider.
    pub fn will_deform(&mut self, id: ColliderId) -> Result<()> {
        let index = id.0 as usize;
        let not_a_mesh = || HairError::Collider {
            collider: index,
            message: "no mesh collider with this id in this set".into(),
        };
        let entry = self.entries.get_mut(index).ok_or_else(not_a_mesh)?;
        if entry.deformation.is_none() {
            return Err(not_a_mesh());
        }
        if let Some(fast) = entry.fast.as_mut() {
            fast.drop_clearances();
        }
        Ok(())
    }

    /// Puts mesh collider `id` at vertex positions `vertices` now (body space, m, as for
    /// [`Colliders::set_vertices`]): at the start and the end of the next frame, with no motion
    /// into it. Use it for a set built at a later frame than its mesh's rest shape (a resumed
    /// run, which then collides with the same shape, to the bit, as the uninterrupted run) or
    /// for a cut. Same checks as [`Colliders::set_vertices`].
    pub fn place_vertices(&mut self, id: ColliderId, vertices: &[Vector3<f32>]) -> Result<()> {
        let index = id.0 as usize;
        self.deformation_mut(index)?.place(index, vertices)?;
        // The shape stands there at once, so queries between frames (a quality report of a
        // cached frame) see it; the next step then finds it in place.
        self.place_mesh(index, 1.0, 1.0, 1.0);
        Ok(())
    }

    /// Puts every collider that follows the scalp ([`Colliders::insert_scalp`]) at `scalp` now:
    /// its pose and, where the scalp mesh is deformed, its vertices, at the start and the end of
    /// the next frame, with no motion into it. A resumed run calls it with the scalp of the frame
    /// it resumes from, after [`Colliders::insert_scalp_rest`]. Refuses a non-finite transform,
    /// another vertex count or other triangles, and non-finite vertices.
    pub fn place_scalp(&mut self, scalp: &Scalp) -> Result<()> {
        for (index, e) in self.entries.iter_mut().enumerate() {
            if !e.follows_scalp {
                continue;
            }
            check_pose(index, &scalp.body)?;
            if let (Some(d), Some(mesh)) = (e.deformation.as_mut(), &scalp.mesh) {
                d.follow_scalp(index, mesh, &scalp.body)?;
                d.finish_frame();
            }
            e.start = scalp.body;
            e.end = scalp.body;
        }
        // Deformed shapes stand there at once (see `place_vertices`).
        for c in 0..self.entries.len() {
            if self.entries[c].follows_scalp {
                self.place_mesh(c, 1.0, 1.0, 1.0);
            }
        }
        Ok(())
    }

    /// The deformation state of mesh collider `index`, or the error a host gets for it.
    fn deformation_mut(&mut self, index: usize) -> Result<&mut Deformation> {
        let entry = self
            .entries
            .get_mut(index)
            .ok_or_else(|| HairError::Collider {
                collider: index,
                message: "no such collider in this set".into(),
            })?;
        if entry.follows_scalp {
            return Err(HairError::Collider {
                collider: index,
                message: "follows the scalp: give the deformed scalp mesh as the solver's \
                          Scalp.mesh instead of setting its vertices"
                    .into(),
            });
        }
        entry
            .deformation
            .as_deref_mut()
            .ok_or_else(|| HairError::Collider {
                collider: index,
                message: "is a sphere or a capsule: only mesh colliders have vertices to set; \
                          insert a Collider::mesh to deform it"
                    .into(),
            })
    }

    /// Pose of collider `id` at the end of the next (or last) stepped frame, if it exists.
    pub fn pose(&self, id: ColliderId) -> Option<Isometry3<f32>> {
        self.entries.get(id.0 as usize).map(|e| e.end)
    }

    /// How a mesh collider is treated (solid or shell, see [`MeshKind`]); `None` for analytic
    /// shapes and unknown ids.
    pub fn mesh_kind(&self, id: ColliderId) -> Option<&MeshKind> {
        self.entries.get(id.0 as usize)?.mesh_kind.as_ref()
    }

    /// Starts a frame: scalp-following colliders take the scalp's body transform as their end
    /// pose and, where the scalp mesh is deformed, its vertices; every end rotation is taken in
    /// the hemisphere of its start (the shorter way). Fails on a deformed scalp whose topology
    /// differs from the collider's or whose vertices are not finite.
    pub(crate) fn begin_frame(&mut self, scalp: &Scalp) -> Result<()> {
        for (index, e) in self.entries.iter_mut().enumerate() {
            if e.follows_scalp {
                if let (Some(d), Some(mesh)) = (e.deformation.as_mut(), &scalp.mesh) {
                    d.follow_scalp(index, mesh, &scalp.body)?;
                }
                e.end = scalp.body;
            }
            if e.end.rotation.coords.dot(&e.start.rotation.coords) < 0.0 {
                e.end.rotation = UnitQuaternion::new_unchecked(-e.end.rotation.into_inner());
            }
            if let Some(d) = e.deformation.as_mut() {
                d.begin_frame();
            }
        }
        Ok(())
    }

    /// Stands every deforming mesh's shape at fraction `at` of the frame, with the motion of the
    /// step from fraction `from` to `to`, and lowers detection's remembered distance bounds by
    /// how far each surface moved. Meshes already standing there (every rigid one) are left
    /// alone.
    pub(crate) fn place_meshes(&mut self, at: f32, from: f32, to: f32) {
        for c in 0..self.entries.len() {
            self.place_mesh(c, at, from, to);
        }
    }

    /// [`Colliders::place_meshes`] for collider `c` alone.
    fn place_mesh(&mut self, c: usize, at: f32, from: f32, to: f32) {
        let count = self.entries.len();
        let e = &mut self.entries[c];
        let Some(d) = e.deformation.as_mut() else {
            return;
        };
        let Some(target) = d.prepare_step(at, from, to) else {
            return;
        };
        let shift = e.reshape(target);
        for m in self.clearance.memory.iter_mut().skip(c).step_by(count) {
            m.bound -= shift;
        }
    }

    /// Collision steps the frame needs per scene step (see the module docs): the smallest `k`
    /// with every collider's frame error / (steps·k)² ≤ `tolerance` (m), at least 1, with
    /// `steps × k ≤ max_steps`.
    pub(crate) fn step_factor(&self, steps: u32, tolerance: f32) -> u32 {
        let error = self
            .entries
            .iter()
            .map(Entry::frame_error)
            .fold(0.0f32, f32::max);
        let steps = steps.max(1) as f32;
        let wanted = ((error / tolerance).sqrt() / steps).ceil();
        let cap = (self.settings.max_steps as f32 / steps).floor().max(1.0);
        if wanted.is_finite() && wanted >= 1.0 {
            wanted.min(cap) as u32
        } else {
            1
        }
    }

    /// Places every collider at fraction `a` of the frame (the step's start) in the rapier set and
    /// puts its AABB swept to fraction `b` (the step's end) in the broad phase.
    pub(crate) fn place_for_step(&mut self, a: f32, b: f32) {
        self.place_meshes(a, a, b);
        let params = rapier3d::dynamics::IntegrationParameters::default();
        for e in &self.entries {
            let (start_pose, end_pose) = (e.pose_at(a), e.pose_at(b));
            let start = to_pose(&start_pose);
            let end = to_pose(&end_pose);
            let Some(co) = self.set.get_mut(e.handle) else {
                continue;
            };
            co.set_position(start);
            // A moved mesh's box comes from its vertices (rapier's collider keeps the inserted
            // shape).
            let moved = (e.version > 0)
                .then(|| e.swept_mesh_aabb(&start_pose, &end_pose))
                .flatten();
            let aabb = moved.unwrap_or_else(|| co.compute_swept_aabb(&end));
            self.broad_phase.set_aabb(&params, e.handle, aabb);
        }
        // Nothing consumes rapier's change tracking here; keep it from accumulating.
        let _ = self.set.take_modified();
    }

    /// Ends a frame: the end poses become the next frame's start poses.
    pub(crate) fn finish_frame(&mut self) {
        for e in &mut self.entries {
            e.start = e.end;
            if let Some(d) = e.deformation.as_mut() {
                d.finish_frame();
            }
        }
    }
}

/// A mesh shape's enclosing sphere (body space: centre at its box's centre, m; radius, m) and
/// the largest distance of its `vertices` from the body origin, m.
fn mesh_bounds(shape: &SharedShape, vertices: &[Vector3<f32>]) -> ((Vector3<f32>, f32), f32) {
    let local = shape.compute_local_aabb();
    let centre = from_glam((local.mins + local.maxs) * 0.5);
    let enclosing = vertices
        .iter()
        .map(|v| (v - centre).norm())
        .fold(0.0f32, f32::max);
    let radius = vertices.iter().map(|v| v.norm()).fold(0.0f32, f32::max);
    ((centre, enclosing), radius)
}

fn check_pose(collider: usize, pose: &Isometry3<f32>) -> Result<()> {
    let finite = pose.translation.vector.iter().all(|c| c.is_finite())
        && pose.rotation.coords.iter().all(|c| c.is_finite());
    if finite {
        Ok(())
    } else {
        Err(HairError::Collider {
            collider,
            message: format!(
                "pose has a non-finite value (translation {:?}); give finite keyframes",
                pose.translation.vector.as_slice()
            ),
        })
    }
}
