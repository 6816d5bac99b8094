//! Contact detection, once per collision step: every free hair point (a sphere of its radius)
//! against the colliders, through rapier's query pipeline (broad phase) and parry's point
//! projection on each candidate shape (narrow phase).
//!
//! Everything happens in each collider's body space at the step's start pose, where a rigid
//! collider stands still: a point's signed distance to it depends only on the point's body-space
//! position `p`, and changes by at most how far `p` moves.
//!
//! 1. **Query radius.** A point can reach collider `c` within the step only if it is within
//!    `q = radius + thickness + 2|v − v_c(x)|·Δt + |g|·Δt² + 1 mm` of its surface, with
//!    `v − v_c(x)` its velocity relative to the collider's material point where it is (so hair
//!    moving with a head has a small radius however fast the head moves; the factor 2 and the
//!    `|g|Δt²` cover acceleration within the step).
//! 2. **Clearance skip.** For every point and collider a lower bound of the signed distance is
//!    kept: the distance measured at an earlier step minus how far the point has moved in the
//!    collider's body space since. This is exact (the distance is 1-Lipschitz), not a heuristic.
//!    A point whose bound exceeds `q` skips the collider; hair away from every collider costs a
//!    few nanoseconds per point and step.
//! 3. **Broad phase.** The AABB of a strand's remaining points, each grown by its largest query
//!    radius, is intersected with the colliders' swept AABBs in rapier's BVH
//!    ([`rapier3d::pipeline::QueryPipeline::intersect_aabb_conservative`]).
//! 4. **Narrow phase.** Each remaining point is projected on each candidate shape. A point
//!    outside the shape's enclosing sphere by more than `q` is not projected (that distance is
//!    its new bound). Any other point is projected without a distance limit, so its exact distance
//!    renews its bound and a point deep inside a solid is found; a solid mesh says whether the
//!    point is inside by parry's pseudo-normal test. On a mesh the search is warm-started: the
//!    distance to the triangle the point projected on last time bounds the distance to the mesh,
//!    and parry's BVH search starting from that bound visits only the nodes nearer than it; near a
//!    convex part of a solid mesh that triangle often certifies the answer by itself
//!    ([`super::fast_projection`]) and no search runs; where a search runs, the shortcut is tried
//!    again from the triangle it found. The hint only saves work: the contact is recomputed from
//!    the feature found (face, edge or vertex, an edge or vertex named by its lowest-numbered
//!    triangle), so it is the same bits with or without the memory — a run resumed from a cache,
//!    which starts without it, continues exactly as the uninterrupted run (and results do not
//!    depend on the thread count). See the `contacts` module docs for the one case left.
//!
//! A contact keeps, for the nearest collider (smallest signed distance), the surface element the
//! response works with (see [`super::penalty`]): where the surface is flat (or the point is deeper
//! than half the radius of curvature) the tangent plane at the projection, as its outward normal
//! `n` and offset `c = d₀ − n·x₀` (`d₀` the signed distance of the point's sphere from the surface
//! grown by the thickness, negative = penetration); where it is curved, the sphere of its smallest
//! curvature `κ` tangent there (centre `p − n/κ`, radius `1/κ` grown by thickness and hair radius;
//! exact for sphere colliders and capsule caps, estimated per triangle for meshes, see
//! [`super::collider`]; on a mesh `n` is the smooth normal interpolated from the vertex normals,
//! not the facet's, see `smooth_normal`; a sphere whose centre lies farther from the body origin
//! than the shape itself becomes a plane). A concave sphere (the point inside it) is kept only
//! where it is wider than the point's query radius less the gap kept (radius plus thickness),
//! the farthest the point may move within the step: a narrower one confines the point to a
//! ball for the whole step. In the creases around the Sintel bust's ears the smallest
//! curvature gives concave radii of 1–4 mm, and such spheres would hold points there within a
//! millimetre of where detection found them for a whole frame (2,600 substeps) while their
//! strands swing around them — with them (and without `coupling`) 89 strands move more than 1 cm in
//! the first frame, up to 9.4 cm, folding up past their roots. There the tangent plane stands in: a
//! point sliding `s` along it within the step can enter a concave surface of curvature `κ` by
//! `κ s²/2`, which the next step's detection finds and pushes out. The sphere's centre moves with
//! the collider's material point there and the plane with the material point at the projection
//! (velocities from the start-of-step to the end-of-step pose); the projection's velocity is also
//! kept for friction, with the collider's friction coefficient. Points without a contact get a
//! plane offset so large that the response never acts on them.

use hair_par::prelude::*;
use nalgebra::{Isometry3, Matrix3, Point3, UnitQuaternion, Vector3};
use parry3d::query::{DefaultQueryDispatcher, PointQuery, PointQueryWithLocation};
use parry3d::shape::{Shape, TrianglePointLocation};
use rapier3d::geometry::Aabb;
use rapier3d::pipeline::QueryFilter;

use super::collider_set::{Colliders, Entry, MeshTopology, Surface};
use super::fast_projection::{FastProjection, Feature};
use super::math::{from_glam, to_glam};

/// Plane offset of a point without a contact, m: the response's distance test never passes.
pub(crate) const NO_CONTACT: f32 = 1e20;

/// Extra query distance covering what the margin's motion estimate leaves out, m.
const SLACK: f32 = 1e-3;

/// Below this distance (m) from the surface the projection direction is not trusted and the
/// surface normal of the feature is used.
const NORMAL_EPS: f32 = 1e-7;

/// Radius of curvature (m) beyond which a surface counts as flat.
const FLAT: f32 = 10.0;

/// The contacts of one collision step, one (or none) per point, strand-contiguous like the
/// strand set.
#[derive(Debug, Clone, Default)]
pub(crate) struct PointContacts {
    /// Plane: outward unit normal, world. Curved: centre of the contact sphere at the step's
    /// start, world, m.
    pub anchor: Vec<Vector3<f32>>,
    /// Plane: `c` in `d(x) = n·x + c` (m) at the step's start. Curved: radius (m) the point's
    /// centre keeps to, > 0 outside the sphere, < 0 inside it.
    pub size: Vec<f32>,
    /// Is the contact a sphere (curved) rather than a plane?
    pub curved: Vec<bool>,
    /// Velocity of the model, m/s: of the collider's material point at the sphere's centre
    /// (curved) or at the contact (plane, where only its normal part matters).
    pub anchor_velocity: Vec<Vector3<f32>>,
    /// Velocity of the collider's surface at the contact, m/s.
    pub surface_velocity: Vec<Vector3<f32>>,
    /// Friction coefficient of the contact.
    pub friction: Vec<f32>,
    /// How deep the point's sphere was inside the thickened surface at detection, m (0 outside
    /// and without a contact): the error the response eases out at the push speed (see
    /// [`super::penalty`]).
    pub found_depth: Vec<f32>,
    /// Per strand: does any of its points have a contact?
    pub strand_active: Vec<bool>,
}

/// What detection remembers of a point and one collider between steps.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Memory {
    /// Body-space position at which `bound` was measured, m.
    pub(super) at: Vector3<f32>,
    /// Lower bound of the signed distance to the collider's surface there, m (−∞: unknown).
    pub(super) bound: f32,
    /// Mesh triangle the point projected on there (`u32::MAX`: none), a warm start.
    pub(super) hint: u32,
}

impl Memory {
    /// Projects body-space point `local` on `col` within `q` (m), warm-started from triangle
    /// `hint` (`u32::MAX`: none), and remembers what it learnt there: the distance (or its lower
    /// bound when farther than `q`) and the triangle. The hit, if the surface is within `q` or
    /// the point inside a solid.
    pub(super) fn project(
        &mut self,
        col: &StepCollider,
        local: Vector3<f32>,
        q: f32,
        hint: u32,
    ) -> Option<Hit> {
        self.at = local;
        match project(col, &local, q, (hint != u32::MAX).then_some(hint)) {
            Ok(hit) => {
                self.bound = hit.signed;
                if col.shape.as_trimesh().is_some() {
                    self.hint = hit.triangle;
                }
                Some(hit)
            }
            Err((far, triangle)) => {
                self.bound = far;
                self.hint = triangle.unwrap_or(self.hint);
                None
            }
        }
    }

    /// Is body-space point `local` certainly farther than `q` (m) from the surface? Its distance
    /// is at least `bound − |local − at|` (the distance is 1-Lipschitz); compared squared, without
    /// a square root.
    #[inline(always)]
    pub(super) fn clear_of(&self, local: &Vector3<f32>, q: f32) -> bool {
        let slack = self.bound - q;
        slack >= 0.0 && (local - self.at).norm_squared() <= slack * slack
    }
}

/// An affine map of points, `linear · x + offset`: a rigid pose (or the displacement it causes)
/// as a matrix, applied in 9 multiply–adds.
#[derive(Debug, Clone, Copy)]
pub(super) struct Affine {
    linear: Matrix3<f32>,
    offset: Vector3<f32>,
}

impl Affine {
    /// The displacement `pose · x − x` that `pose` causes at `x`, as `(R − I) x + t` with
    /// `R − I = 2w[v]× + 2(v vᵀ − |v|² I)` from the rotation's quaternion `(w, v)`: no
    /// cancellation against 1 on the diagonal nor between the moved point and the point, so a
    /// small motion keeps its relative precision.
    fn displacement(pose: Isometry3<f32>) -> Self {
        let q = pose.rotation.quaternion();
        let v = q.imag();
        Self {
            linear: v.cross_matrix() * (2.0 * q.w)
                + (v * v.transpose() - Matrix3::identity() * v.norm_squared()) * 2.0,
            offset: pose.translation.vector,
        }
    }

    /// The map applied to `x`.
    #[inline(always)]
    pub(super) fn apply(&self, x: &Vector3<f32>) -> Vector3<f32> {
        self.linear * x + self.offset
    }
}

impl From<Isometry3<f32>> for Affine {
    fn from(pose: Isometry3<f32>) -> Self {
        Self {
            linear: *pose.rotation.to_rotation_matrix().matrix(),
            offset: pose.translation.vector,
        }
    }
}

impl Default for Memory {
    fn default() -> Self {
        Self {
            at: Vector3::zeros(),
            bound: f32::NEG_INFINITY,
            hint: u32::MAX,
        }
    }
}

/// Per point and collider memory (see the module docs), point-major.
#[derive(Debug, Clone, Default)]
pub(crate) struct Clearance {
    pub(super) memory: Vec<Memory>,
}

impl Clearance {
    /// Forgets everything (colliders were added).
    pub fn reset(&mut self) {
        self.memory.clear();
    }
}

/// What detection reads of the strands.
pub(crate) struct DetectInput<'a> {
    pub offsets: &'a [u32],
    pub positions: &'a [Vector3<f32>],
    pub velocities: &'a [Vector3<f32>],
    pub radii: &'a [f32],
    pub inv_mass: &'a [f32],
    /// Strand ranges processed as one parallel job.
    pub blocks: &'a [std::ops::Range<usize>],
    /// Length of the collision step, s.
    pub step_dt: f32,
    /// Magnitude of gravity, m/s².
    pub gravity: f32,
}

/// A collider as detection sees it during one step.
pub(super) struct StepCollider<'a> {
    shape: &'a dyn Shape,
    /// Enclosing sphere, body space: centre (m) and radius (m).
    bounding_sphere: (Vector3<f32>, f32),
    surface: Surface,
    start: Isometry3<f32>,
    /// World to body space at the step's start (`start⁻¹` as a matrix: the per-point loops
    /// apply it to every point, where a quaternion costs half again as many flops).
    to_body: Affine,
    pub(super) end: Isometry3<f32>,
    /// Displacement of the world-space point `x` carried by the step's rigid motion
    /// (`end · start⁻¹ · x − x`), m.
    carry: Affine,
    pub(super) thickness: f32,
    friction: f32,
    /// Smallest curvature per mesh triangle, 1/m (empty for analytic shapes).
    curvature: &'a [f32],
    /// Smooth normals and feature owners of a mesh (empty for analytic shapes).
    topology: &'a MeshTopology,
    /// Largest distance of the shape from its body origin, m: contact spheres whose centre lies
    /// farther are replaced by planes (their linearised motion under rotation would err more).
    reach: f32,
    /// The narrow-phase shortcut of a solid mesh.
    fast: Option<&'a FastProjection>,
    /// A deforming mesh's displacement of each vertex over the step, body space, m (empty when
    /// it does not deform in this frame).
    deformation: &'a [Vector3<f32>],
    /// Largest `|deformation|`, m: how far the surface can come towards a point within the step.
    pub(super) motion_margin: f32,
    /// Does the shape stand at the step's end (the frame-end check) rather than its start?
    shape_at_end: bool,
}

impl StepCollider<'_> {
    /// Velocity (m/s) of the collider's material point at body-space `local` over a step of
    /// `dt` s.
    pub(super) fn velocity_at(&self, local: &Vector3<f32>, dt: f32) -> Vector3<f32> {
        let p = Point3::from(*local);
        self.velocity_from(local, &(self.start * p), dt)
    }

    /// [`Self::velocity_at`] given `start`, the point's world position at the step's start
    /// (`self.start * local`).
    fn velocity_from(&self, local: &Vector3<f32>, start: &Point3<f32>, dt: f32) -> Vector3<f32> {
        ((self.end * Point3::from(*local)) - start) / dt
    }

    /// Body-space direction `n` turned as mesh triangle `tri` turns over the step (the rotation
    /// taking its normal at the step's start to its normal at the end; `n` itself where the
    /// mesh does not deform or the triangle is degenerate or flips).
    fn turned(&self, tri: u32, n: &Vector3<f32>) -> Vector3<f32> {
        let Some(mesh) = self.shape.as_trimesh() else {
            return *n;
        };
        let (Some(idx), false) = (
            mesh.indices().get(tri as usize),
            self.deformation.is_empty(),
        ) else {
            return *n;
        };
        let corner = |k: usize| from_glam(mesh.vertices()[idx[k] as usize]);
        let moved = |k: usize| corner(k) + self.deformation[idx[k] as usize];
        let before = (corner(1) - corner(0)).cross(&(corner(2) - corner(0)));
        let after = (moved(1) - moved(0)).cross(&(moved(2) - moved(0)));
        UnitQuaternion::rotation_between(&before, &after).map_or(*n, |q| q * n)
    }

    /// Velocity (m/s) of the surface's material point at body-space `local` on the shape as it
    /// stands, which a deforming mesh displaces by `motion` (body space, m) over the step of
    /// `dt` s, on top of the pose's motion.
    pub(super) fn surface_velocity(
        &self,
        local: &Vector3<f32>,
        motion: &Vector3<f32>,
        dt: f32,
    ) -> Vector3<f32> {
        if self.deformation.is_empty() {
            return self.velocity_at(local, dt);
        }
        let (from, to) = if self.shape_at_end {
            (local - motion, *local)
        } else {
            (*local, local + motion)
        };
        ((self.end * Point3::from(to)) - (self.start * Point3::from(from))) / dt
    }
}

/// Per-block output slices.
struct BlockOut<'a> {
    anchor: &'a mut [Vector3<f32>],
    size: &'a mut [f32],
    curved: &'a mut [bool],
    anchor_velocity: &'a mut [Vector3<f32>],
    surface_velocity: &'a mut [Vector3<f32>],
    friction: &'a mut [f32],
    found_depth: &'a mut [f32],
    active: &'a mut [bool],
    memory: &'a mut [Memory],
}

/// A point to project on a collider: point index, collider, body-space position, query radius.
struct Query {
    point: usize,
    collider: usize,
    local: Vector3<f32>,
    radius: f32,
}

/// Detects the contacts of the step from fraction `a` to `b` of the frame. Returns the number of
/// points with a contact.
pub(crate) fn detect(
    colliders: &mut Colliders,
    a: f32,
    b: f32,
    input: &DetectInput,
    out: &mut PointContacts,
) -> usize {
    let n = input.positions.len();
    let strands = input.offsets.len() - 1;
    colliders.place_for_step(a, b);
    let count = colliders.entries.len();
    let step = step_colliders(&colliders.entries, a, b, false);
    let memory = &mut colliders.clearance.memory;
    if memory.len() != n * count {
        *memory = vec![Memory::default(); n * count];
    }
    out.anchor.resize(n, Vector3::zeros());
    out.size.resize(n, NO_CONTACT);
    out.curved.resize(n, false);
    out.anchor_velocity.resize(n, Vector3::zeros());
    out.surface_velocity.resize(n, Vector3::zeros());
    out.friction.resize(n, 0.0);
    out.found_depth.resize(n, 0.0);
    out.strand_active.resize(strands, false);

    let handles: Vec<_> = colliders.entries.iter().map(|e| e.handle).collect();

    // Disjoint output slices per block.
    let mut jobs = Vec::with_capacity(input.blocks.len());
    {
        let mut anchor = out.anchor.as_mut_slice();
        let mut size = out.size.as_mut_slice();
        let mut curved = out.curved.as_mut_slice();
        let mut anchor_velocity = out.anchor_velocity.as_mut_slice();
        let mut surface_velocity = out.surface_velocity.as_mut_slice();
        let mut friction = out.friction.as_mut_slice();
        let mut found_depth = out.found_depth.as_mut_slice();
        let mut active = out.strand_active.as_mut_slice();
        let mut memory = memory.as_mut_slice();
        for block in input.blocks {
            let len = (input.offsets[block.end] - input.offsets[block.start]) as usize;
            let o = BlockOut {
                anchor: take(&mut anchor, len),
                size: take(&mut size, len),
                curved: take(&mut curved, len),
                anchor_velocity: take(&mut anchor_velocity, len),
                surface_velocity: take(&mut surface_velocity, len),
                friction: take(&mut friction, len),
                found_depth: take(&mut found_depth, len),
                active: take(&mut active, block.len()),
                memory: take(&mut memory, len * count),
            };
            jobs.push((block.clone(), o));
        }
    }

    let dispatcher = DefaultQueryDispatcher;
    let (broad_phase, bodies, set) = (&colliders.broad_phase, &colliders.bodies, &colliders.set);
    let dt = input.step_dt;
    let inv_dt = 1.0 / dt;
    jobs.into_par_iter()
        .map(|(block, o)| {
            let pipeline =
                broad_phase.as_query_pipeline(&dispatcher, bodies, set, QueryFilter::default());
            let base = input.offsets[block.start] as usize;
            let mut found = 0usize;
            let mut candidates = vec![false; count];
            let mut queries: Vec<Query> = Vec::new();
            let mut best: Vec<Option<(f32, Hit, usize, f32)>> = Vec::new();
            let mut strand_hint = vec![u32::MAX; count];
            for (k, s) in block.clone().enumerate() {
                let points = input.offsets[s] as usize..input.offsets[s + 1] as usize;
                queries.clear();
                let mut lo = Vector3::repeat(f32::INFINITY);
                let mut hi = Vector3::repeat(f32::NEG_INFINITY);
                for i in points.clone() {
                    let j = i - base;
                    o.size[j] = NO_CONTACT;
                    o.anchor[j] = Vector3::zeros();
                    o.curved[j] = false;
                    o.anchor_velocity[j] = Vector3::zeros();
                    o.surface_velocity[j] = Vector3::zeros();
                    o.friction[j] = 0.0;
                    o.found_depth[j] = 0.0;
                    if input.inv_mass[i] == 0.0 {
                        continue;
                    }
                    let x = input.positions[i];
                    for (c, col) in step.iter().enumerate() {
                        let local = col.to_body.apply(&x);
                        let relative = input.velocities[i] - col.carry.apply(&x) * inv_dt;
                        let q = input.radii[i]
                            + col.thickness
                            + 2.0 * relative.norm() * dt
                            + input.gravity * dt * dt
                            + col.motion_margin
                            + SLACK;
                        if o.memory[j * count + c].clear_of(&local, q) {
                            continue;
                        }
                        queries.push(Query {
                            point: i,
                            collider: c,
                            local,
                            radius: q,
                        });
                        lo = lo.inf(&x.add_scalar(-q));
                        hi = hi.sup(&x.add_scalar(q));
                    }
                }
                o.active[k] = false;
                if queries.is_empty() {
                    continue;
                }
                candidates.iter_mut().for_each(|c| *c = false);
                let aabb = Aabb::new(to_glam(&lo), to_glam(&hi));
                for (h, _) in pipeline.intersect_aabb_conservative(aabb) {
                    if let Some(c) = handles.iter().position(|&e| e == h) {
                        candidates[c] = true;
                    }
                }
                best.clear();
                best.resize(points.len(), None);
                // A point without a hint of its own starts from its predecessor's triangle.
                strand_hint.iter_mut().for_each(|h| *h = u32::MAX);
                for query in &queries {
                    let (i, c) = (query.point, query.collider);
                    let j = i - base;
                    let m = &mut o.memory[j * count + c];
                    m.at = query.local;
                    if !candidates[c] {
                        // Outside the broad phase: farther than the query radius.
                        m.bound = query.radius;
                        continue;
                    }
                    let col = &step[c];
                    let own = if m.hint != u32::MAX {
                        m.hint
                    } else {
                        strand_hint[c]
                    };
                    let hit = m.project(col, query.local, query.radius, own);
                    strand_hint[c] = m.hint;
                    let Some(hit) = hit else {
                        continue;
                    };
                    let d0 = hit.signed - col.thickness - input.radii[i];
                    let slot = &mut best[i - points.start];
                    if slot.as_ref().is_none_or(|b| d0 < b.0) {
                        *slot = Some((d0, hit, c, query.radius));
                    }
                }
                for (offset, slot) in best.iter().enumerate() {
                    let Some((d0, hit, c, q)) = slot else {
                        continue;
                    };
                    let i = points.start + offset;
                    let j = i - base;
                    let col = &step[*c];
                    let x = input.positions[i];
                    o.surface_velocity[j] = col.surface_velocity(&hit.local_point, &hit.motion, dt);
                    o.friction[j] = col.friction;
                    o.found_depth[j] = (-*d0).max(0.0);
                    o.active[k] = true;
                    found += 1;
                    // The sphere of the surface's curvature, grown like the surface by thickness
                    // and hair radius; a plane where flat, too tight for the hair, or where the
                    // point is deep in the sphere.
                    let normal = col.start.rotation * hit.local_normal;
                    let grow = col.thickness + input.radii[i];
                    let rho = 1.0 / hit.curvature.abs();
                    let rho_grown = if hit.curvature > 0.0 {
                        rho + grow
                    } else {
                        rho - grow
                    };
                    let centre = if hit.curvature > 0.0 {
                        hit.local_point - hit.smooth_normal * rho
                    } else {
                        hit.local_point + hit.smooth_normal * rho
                    };
                    // A concave sphere holds the point inside it: only one wider than how far
                    // the point may move within the step (its query radius less the gap kept)
                    // leaves it free to slide (see the module docs).
                    let concave_ok = hit.curvature > 0.0 || rho_grown >= *q - grow;
                    if rho < FLAT
                        && rho_grown > 0.0
                        && *d0 > -0.5 * rho_grown
                        && centre.norm() <= col.reach
                        && concave_ok
                    {
                        let start = col.start * Point3::from(centre);
                        o.anchor[j] = start.coords;
                        o.size[j] = rho_grown.copysign(hit.curvature);
                        o.curved[j] = true;
                        o.anchor_velocity[j] = if col.deformation.is_empty() {
                            col.velocity_from(&centre, &start, dt)
                        } else {
                            // The sphere moves with the contact's material point and turns with
                            // its triangle.
                            let turned = col.turned(hit.triangle, &hit.smooth_normal);
                            let swing = (turned - hit.smooth_normal) * rho;
                            let motion = if hit.curvature > 0.0 {
                                hit.motion - swing
                            } else {
                                hit.motion + swing
                            };
                            col.surface_velocity(&centre, &motion, dt)
                        };
                    } else {
                        o.anchor[j] = normal;
                        o.size[j] = d0 - normal.dot(&x);
                        o.anchor_velocity[j] = o.surface_velocity[j];
                    }
                }
            }
            found
        })
        .sum()
}

/// The colliders as detection sees them during the step from fraction `a` to `b` of the frame,
/// their shapes standing at the step's start (or at its end, `shape_at_end`; see
/// [`Colliders::place_meshes`]).
pub(super) fn step_colliders(
    entries: &[Entry],
    a: f32,
    b: f32,
    shape_at_end: bool,
) -> Vec<StepCollider<'_>> {
    entries
        .iter()
        .map(|e| {
            let start = e.pose_at(a);
            StepCollider {
                shape: &*e.shape,
                bounding_sphere: e.bounding_sphere,
                surface: e.surface,
                start,
                to_body: Affine::from(start.inverse()),
                end: e.pose_at(b),
                carry: Affine::displacement(e.pose_at(b) * start.inverse()),
                thickness: e.thickness,
                friction: e.friction,
                curvature: &e.curvature,
                topology: &e.topology,
                reach: e.bounding_radius,
                fast: e.fast.as_ref(),
                deformation: e
                    .deformation
                    .as_ref()
                    .map_or(&[][..], |d| d.step_motion.as_slice()),
                motion_margin: e.deformation.as_ref().map_or(0.0, |d| d.step_margin),
                shape_at_end,
            }
        })
        .collect()
}

/// Splits the first `len` items off `rest`.
fn take<'a, T>(rest: &mut &'a mut [T], len: usize) -> &'a mut [T] {
    let (head, tail) = std::mem::take(rest).split_at_mut(len);
    *rest = tail;
    head
}

/// A point projected on a collider surface, in the collider's body space.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Hit {
    /// Signed distance from the (unthickened) surface, m; negative inside a solid.
    pub(super) signed: f32,
    /// Outward unit normal, body space.
    pub(super) local_normal: Vector3<f32>,
    /// Unit normal of the smooth surface the shape stands for at the projection, on the point's
    /// side, body space: on a mesh interpolated from its vertex normals (a facet's own normal
    /// tilts away from the surface it approximates by up to half the angle between neighbouring
    /// facets, and a contact sphere tangent to the facet would cut into the surface by that angle
    /// times the distance slid, see [`smooth_normal`]); `local_normal` elsewhere.
    smooth_normal: Vector3<f32>,
    /// The projection, body space, m.
    pub(super) local_point: Vector3<f32>,
    /// Smallest curvature of the surface there, 1/m: > 0 bending away from the point's side
    /// (convex), < 0 towards it, 0 flat.
    curvature: f32,
    /// Triangle of a mesh the point projected on (0 for analytic shapes).
    triangle: u32,
    /// Displacement over the step of the surface's material point at the projection, body
    /// space, m: the barycentric blend of a deforming mesh's vertex motion (0 otherwise).
    pub(super) motion: Vector3<f32>,
}

/// Projects body-space point `p` on collider `col` if its surface lies within `q` (m), or if the
/// point is inside a solid. Otherwise returns a lower bound (> q, m) of its distance to the
/// surface — the distance itself, or to the shape's enclosing sphere when that is beyond `q` —
/// with the mesh triangle nearest to it if one was found. `hint` is a mesh triangle the point was
/// near before, which warm-starts the search.
fn project(
    col: &StepCollider,
    p: &Vector3<f32>,
    q: f32,
    hint: Option<u32>,
) -> Result<Hit, (f32, Option<u32>)> {
    let p = Point3::from(*p);
    let pg = to_glam(&p.coords);
    let (centre, enclosing) = col.bounding_sphere;
    let far = (p.coords - centre).norm() - enclosing;
    if far > q {
        return Err((far, None));
    }
    if let Some(mesh) = col.shape.as_trimesh() {
        // Near a convex part of a solid mesh, the last triangle may certify the answer.
        if let (Some(fast), Some(t)) = (col.fast, hint) {
            if let Some(f) = fast.project(mesh, t, &p.coords) {
                return mesh_hit(col, mesh, &p.coords, f.triangle, f.feature, false, q);
            }
        }
        // The hint triangle's distance bounds the mesh's; a little more keeps that triangle
        // itself findable (the search only accepts strictly nearer candidates).
        let limit = hint
            .filter(|&t| (t as usize) < mesh.num_triangles())
            .map(|t| {
                let d = mesh.triangle(t).distance_to_local_point(pg, true);
                d * (1.0 + 1e-4) + 1e-6
            })
            .unwrap_or(f32::MAX);
        // Rounding can put the hint triangle itself just beyond the limit; then search without
        // one. Only a non-finite point finds nothing at all.
        let found = mesh
            .project_local_point_and_get_location_with_max_dist(pg, false, limit)
            .or_else(|| {
                mesh.project_local_point_and_get_location_with_max_dist(pg, false, f32::MAX)
            });
        let Some((proj, (tri, location))) = found else {
            return Err((q, None));
        };
        let feature = match location {
            TrianglePointLocation::OnEdge(e, _) => Feature::Edge(e),
            TrianglePointLocation::OnVertex(v) => Feature::Vertex(v),
            _ => Feature::Face,
        };
        let inside = col.surface == Surface::Solid && proj.is_inside;
        // Where the shortcut certifies an answer from the triangle found, take it: the walk
        // from the hint and the walk from here end on the same feature, where parry's search and
        // the walk may name different ones for near-ties (the two halves of a flat quad, a face
        // against its edge within the fold tolerance), so the answer depends on where the point
        // is, not on the memory a resumed run does not have.
        if let (Some(fast), false) = (col.fast, inside) {
            if let Some(f) = fast.project(mesh, tri, &p.coords) {
                return mesh_hit(col, mesh, &p.coords, f.triangle, f.feature, false, q);
            }
        }
        return mesh_hit(col, mesh, &p.coords, tri, feature, inside, q);
    }
    // Analytic shapes: exact and cheap, no distance limit needed.
    let proj = col.shape.project_local_point(pg, false);
    let mut curvature = 0.0;
    let point = from_glam(proj.point);
    let delta = p.coords - point;
    let dist = delta.norm();
    if !proj.is_inside && dist > q {
        return Err((dist, None));
    }
    let local_normal = if dist > NORMAL_EPS {
        if proj.is_inside {
            -delta / dist
        } else {
            delta / dist
        }
    } else {
        // On the surface: away from the sphere's centre or the capsule's axis.
        unit_or_z(point - axis_point(col.shape, &point))
    };
    // A sphere is curved everywhere; a capsule on its caps, flat along its cylinder (its
    // smallest curvature).
    if let Some(ball) = col.shape.as_ball() {
        curvature = 1.0 / ball.radius;
    } else if let Some(capsule) = col.shape.as_capsule() {
        let (a, b) = (from_glam(capsule.segment.a), from_glam(capsule.segment.b));
        let ab = b - a;
        let t = (point - a).dot(&ab) / ab.norm_squared().max(f32::MIN_POSITIVE);
        if !(0.0..=1.0).contains(&t) || ab.norm_squared() == 0.0 {
            curvature = 1.0 / capsule.radius;
        }
    }
    Ok(Hit {
        signed: if proj.is_inside { -dist } else { dist },
        local_normal,
        smooth_normal: local_normal,
        local_point: point,
        curvature,
        triangle: 0,
        motion: Vector3::zeros(),
    })
}

/// The hit of body-space point `p` projecting on `feature` of triangle `tri` (found by the
/// shortcut or by parry's search; `inside`: parry found it inside a solid), or, if it is not
/// inside and farther than `q` (m), its distance with the triangle as a hint.
///
/// The answer depends only on the feature, never on how it was found: the projection is
/// recomputed here by one formula per kind of feature (an edge from its lower-numbered vertex),
/// and a point nearest to an edge or a vertex is given to its owner triangle (the smallest index
/// using it, see `collider::feature_owners`), whose curvature and smooth normal the contact then
/// uses. The search is warm-started from per-point memory a resumed run does not have; this keeps
/// a resumed run's contacts, and so its frames, bit-identical to an uninterrupted run's.
fn mesh_hit(
    col: &StepCollider,
    mesh: &parry3d::shape::TriMesh,
    p: &Vector3<f32>,
    tri: u32,
    feature: Feature,
    inside: bool,
    q: f32,
) -> Result<Hit, (f32, Option<u32>)> {
    let idx = mesh.indices()[tri as usize];
    let vertex = |i: u32| from_glam(mesh.vertices()[i as usize]);
    let topology = col.topology;
    let moving = |i: u32| col.deformation.get(i as usize).copied().unwrap_or_default();
    let (point, owner, motion) = match feature {
        Feature::Face => {
            let a = vertex(idx[0]);
            // The shortcut keeps each triangle's unit normal: the same bits as computed here.
            let n = col
                .fast
                .and_then(|f| f.unit_normal(tri))
                .unwrap_or_else(|| {
                    let [b, c] = [idx[1], idx[2]].map(vertex);
                    unit_or_z((b - a).cross(&(c - a)))
                });
            let point = p - n * n.dot(&(p - a));
            let motion = if col.deformation.is_empty() {
                Vector3::zeros()
            } else {
                let [u, v, w] = barycentric(&idx.map(vertex), &point);
                moving(idx[0]) * u + moving(idx[1]) * v + moving(idx[2]) * w
            };
            (point, tri, motion)
        }
        Feature::Edge(k) => {
            let (u, v) = (idx[k as usize], idx[(k as usize + 1) % 3]);
            let (a, b) = (vertex(u.min(v)), vertex(u.max(v)));
            let ab = b - a;
            let length2 = ab.norm_squared();
            let s = if length2 > 0.0 {
                ((p - a).dot(&ab) / length2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let owner = topology
                .edge_owner
                .get(tri as usize)
                .map_or(tri, |o| o[k as usize]);
            let motion = moving(u.min(v)) * (1.0 - s) + moving(u.max(v)) * s;
            (a + ab * s, owner, motion)
        }
        Feature::Vertex(k) => {
            let v = idx[k as usize];
            let owner = topology.vertex_owner.get(v as usize).copied();
            (vertex(v), owner.unwrap_or(tri), moving(v))
        }
    };
    let delta = p - point;
    let dist = delta.norm();
    if !inside && dist > q {
        return Err((dist, Some(owner)));
    }
    let face = from_glam(mesh.triangle(owner).scaled_normal());
    let local_normal = if dist > NORMAL_EPS {
        if inside {
            -delta / dist
        } else {
            delta / dist
        }
    } else {
        // On the surface: the feature's (pseudo-)normal.
        let pseudo = mesh
            .pseudo_normals_if_oriented()
            .and_then(|pn| match feature {
                Feature::Edge(k) => pn
                    .edges_pseudo_normal
                    .get(tri as usize)
                    .map(|n| from_glam(n[k as usize])),
                Feature::Vertex(k) => pn
                    .vertices_pseudo_normal
                    .get(idx[k as usize] as usize)
                    .map(|n| from_glam(*n)),
                Feature::Face => None,
            });
        unit_or_z(pseudo.unwrap_or(face))
    };
    // Triangle curvature is along the winding normal; from the back of a shell it flips.
    let kappa = col.curvature.get(owner as usize).copied().unwrap_or(0.0);
    let curvature = if face.dot(&local_normal) < 0.0 {
        -kappa
    } else {
        kappa
    };
    Ok(Hit {
        signed: if inside { -dist } else { dist },
        local_normal,
        smooth_normal: smooth_normal(col, mesh, owner, &point, &local_normal),
        local_point: point,
        curvature,
        triangle: owner,
        motion,
    })
}

/// The smooth normal at `point` (body space, on triangle `tri` of `mesh`): the triangle's vertex
/// normals interpolated with the point's barycentric coordinates, on the side of `side` (the
/// projection's normal, pointing to the hair point). Falls back to `side` where the vertex normals
/// give no direction.
///
/// This is the normal of the contact sphere (see the module docs). A facet of a tessellated
/// curved surface is tilted against that surface by up to half the angle between neighbouring
/// facets (2.8° on a 64 × 32 UV sphere); a sphere tangent to the facet lets hair that slides a
/// distance `s` within the step reach up to that angle × `s` into the surface (measured: tips
/// whipping 30 cm per step ended 3 mm inside the parity head). The sphere through the projection
/// with the interpolated normal follows the surface the facets approximate instead; it lies below
/// the facets by at most their sagitta near the vertices, which the hair radius covers.
fn smooth_normal(
    col: &StepCollider,
    mesh: &parry3d::shape::TriMesh,
    tri: u32,
    point: &Vector3<f32>,
    side: &Vector3<f32>,
) -> Vector3<f32> {
    let (Some(idx), false) = (
        mesh.indices().get(tri as usize),
        col.topology.vertex_normals.is_empty(),
    ) else {
        return *side;
    };
    let [a, b, c] = idx.map(|i| from_glam(mesh.vertices()[i as usize]));
    let [na, nb, nc] = idx.map(|i| col.topology.vertex_normals[i as usize]);
    let (e0, e1, e2) = (b - a, c - a, point - a);
    let (d00, d01, d11) = (e0.dot(&e0), e0.dot(&e1), e1.dot(&e1));
    let (d20, d21) = (e2.dot(&e0), e2.dot(&e1));
    let det = d00 * d11 - d01 * d01;
    if det.is_nan() || det <= 0.0 {
        return *side;
    }
    let v = ((d11 * d20 - d01 * d21) / det).clamp(0.0, 1.0);
    let w = ((d00 * d21 - d01 * d20) / det).clamp(0.0, 1.0 - v);
    let n = na * (1.0 - v - w) + nb * v + nc * w;
    let len = n.norm();
    if len.is_nan() || len <= 1e-6 {
        return *side;
    }
    let n = n / len;
    if n.dot(side) < 0.0 {
        -n
    } else {
        n
    }
}

/// Barycentric weights of `point` (in the plane of `corners`, m) in that triangle; a degenerate
/// triangle gives all weight to its first corner.
fn barycentric(corners: &[Vector3<f32>; 3], point: &Vector3<f32>) -> [f32; 3] {
    let [a, b, c] = corners;
    let (e0, e1, e2) = (b - a, c - a, point - a);
    let (d00, d01, d11) = (e0.dot(&e0), e0.dot(&e1), e1.dot(&e1));
    let (d20, d21) = (e2.dot(&e0), e2.dot(&e1));
    let det = d00 * d11 - d01 * d01;
    if det.is_nan() || det <= 0.0 {
        return [1.0, 0.0, 0.0];
    }
    let v = (d11 * d20 - d01 * d21) / det;
    let w = (d00 * d21 - d01 * d20) / det;
    [1.0 - v - w, v, w]
}

/// Nearest point of a capsule's axis segment to `point` (body space), or the origin for other
/// shapes (a sphere's centre).
fn axis_point(shape: &dyn Shape, point: &Vector3<f32>) -> Vector3<f32> {
    match shape.as_capsule() {
        Some(c) => {
            let (a, b) = (from_glam(c.segment.a), from_glam(c.segment.b));
            let ab = b - a;
            let t =
                ((point - a).dot(&ab) / ab.norm_squared().max(f32::MIN_POSITIVE)).clamp(0.0, 1.0);
            a + ab * t
        }
        None => Vector3::zeros(),
    }
}

fn unit_or_z(v: Vector3<f32>) -> Vector3<f32> {
    let n = v.norm();
    if n > 0.0 && n.is_finite() {
        v / n
    } else {
        Vector3::z()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contacts::Collider;
    use crate::mesh::TriMesh;

    #[test]
    fn affine_maps_agree_with_the_poses_they_stand_for() {
        let pose = Isometry3::new(Vector3::new(0.3, -1.2, 0.5), Vector3::new(0.4, -0.7, 1.1));
        let small = Isometry3::new(Vector3::new(1e-4, 0.0, 2e-4), Vector3::new(0.0, 1e-3, 0.0));
        for k in 0..50 {
            let t = k as f32 * 0.37;
            let x = Vector3::new(t.sin(), (1.3 * t).cos(), 0.2 * t - 4.0);
            let exact = (pose * Point3::from(x)).coords;
            assert!((Affine::from(pose).apply(&x) - exact).norm() <= 1e-6 * exact.norm());
            // The reference in f64: in f32, `small · x − x` itself loses digits to cancellation.
            let x64 = x.cast::<f64>();
            let moved = ((small.cast::<f64>() * Point3::from(x64)).coords - x64).cast::<f32>();
            let d = Affine::displacement(small).apply(&x);
            assert!(
                (d - moved).norm() <= 1e-5 * moved.norm(),
                "{k}: {d} {moved}"
            );
        }
    }

    #[test]
    fn the_clearance_test_is_the_lipschitz_bound() {
        let m = Memory {
            at: Vector3::new(1.0, 0.0, 0.0),
            bound: 0.5,
            hint: u32::MAX,
        };
        // Moved 0.3 from where 0.5 was measured: at least 0.2 away.
        let p = Vector3::new(1.0, 0.3, 0.0);
        assert!(m.clear_of(&p, 0.19));
        assert!(!m.clear_of(&p, 0.21));
        // Farther than the bound: nothing is known.
        assert!(!m.clear_of(&Vector3::new(1.0, 0.6, 0.0), 0.0));
        // Unknown (−∞) and NaN bounds never skip.
        let unknown = Memory::default();
        assert!(!unknown.clear_of(&Vector3::zeros(), 0.0));
        let nan = Memory {
            bound: f32::NAN,
            ..m
        };
        assert!(!nan.clear_of(&m.at, 0.0));
    }

    /// 300 two-point strands (a kinematic root and a free point at the same place) 0.2 m above
    /// a faceted unit sphere in directions spread over it, moving at 3 m/s so that each is
    /// within its query radius; returns their contacts.
    fn contacts_above(colliders: &mut Colliders) -> PointContacts {
        let count = 300;
        let mut positions = Vec::new();
        for s in 0..count {
            let z = 1.0 - 2.0 * (s as f32 + 0.5) / count as f32;
            let phi = s as f32 * 2.399_963;
            let ring = (1.0 - z * z).sqrt();
            let x = Vector3::new(ring * phi.cos(), ring * phi.sin(), z) * 1.2;
            positions.extend([x, x]);
        }
        let offsets: Vec<u32> = (0..=count as u32).map(|s| 2 * s).collect();
        let velocities = vec![Vector3::new(3.0, 0.0, 0.0); positions.len()];
        let radii = vec![5e-3; positions.len()];
        let inv_mass: Vec<f32> = (0..positions.len()).map(|i| (i % 2) as f32).collect();
        let blocks = [0..count / 2, count / 2..count];
        let input = DetectInput {
            offsets: &offsets,
            positions: &positions,
            velocities: &velocities,
            radii: &radii,
            inv_mass: &inv_mass,
            blocks: &blocks,
            step_dt: 1.0 / 24.0,
            gravity: 0.0,
        };
        let mut out = PointContacts::default();
        let found = detect(colliders, 0.0, 1.0, &input, &mut out);
        assert_eq!(found, count);
        out
    }

    #[test]
    fn contact_sphere_on_a_faceted_sphere_holds_the_mesh_within_its_sagitta() {
        // Every vertex lies within the contact sphere (radius less the hair radius) up to the
        // facets' sagitta, wherever on a facet the point projects. A sphere tangent to the facet
        // itself, tilted against the surface it approximates, left vertices up to 4× farther
        // out, which let hair sliding 30 cm in a step into the parity scene's head.
        let mesh = TriMesh::uv_sphere(1.0, 32, 16).unwrap();
        let sagitta = mesh
            .triangles()
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| mesh.positions()[i as usize]);
                1.0 - (b - a).cross(&(c - a)).normalize().dot(&a).abs()
            })
            .fold(0.0f32, f32::max);
        let mut colliders = Colliders::new();
        colliders
            .insert(Collider::mesh(mesh.clone()), Isometry3::identity())
            .unwrap();
        let out = contacts_above(&mut colliders);
        let mut worst = f32::NEG_INFINITY;
        for i in (1..out.size.len()).step_by(2) {
            assert!(out.curved[i], "point {i}: a curved contact");
            let reach = out.size[i] - 5e-3;
            for v in mesh.positions() {
                worst = worst.max((v - out.anchor[i]).norm() - reach);
            }
        }
        assert!(
            worst <= sagitta * 1.01,
            "a vertex lies {worst} m outside the contact sphere (sagitta {sagitta} m)"
        );
    }

    /// A collider set holding a UV-sphere mesh of radius 1 m at the origin.
    fn sphere_mesh(segments: u32, rings: u32) -> Colliders {
        let mut colliders = Colliders::new();
        colliders
            .insert(
                Collider::mesh(TriMesh::uv_sphere(1.0, segments, rings).unwrap()),
                Isometry3::identity(),
            )
            .unwrap();
        colliders
    }

    #[test]
    fn contacts_do_not_depend_on_the_warm_start() {
        // The first detection has no memory (parry's search), the second starts from the
        // triangles found (the shortcut): the same bits.
        let mut colliders = sphere_mesh(32, 16);
        let cold = contacts_above(&mut colliders);
        let warm = contacts_above(&mut colliders);
        let bits = |c: &PointContacts| {
            let v = |x: &Vector3<f32>| x.map(f32::to_bits);
            (
                c.anchor.iter().map(v).collect::<Vec<_>>(),
                c.size.iter().map(|s| s.to_bits()).collect::<Vec<_>>(),
                c.anchor_velocity.iter().map(v).collect::<Vec<_>>(),
                c.found_depth
                    .iter()
                    .map(|d| d.to_bits())
                    .collect::<Vec<_>>(),
            )
        };
        assert!(bits(&cold) == bits(&warm));
    }

    /// Warm-started and cold projections name the same feature, to the bit, for points on both
    /// sides of a faceted sphere's surface, hinted from triangles up to 10 cm away: the
    /// shortcut's walk and parry's search disagree on near-ties (the two halves of a flat quad, a
    /// face against its edge within the fold tolerance), so a search result is walked from too.
    /// (Before that, 116 of 200,000 such points differed by a few µm.)
    #[test]
    fn projections_do_not_depend_on_the_hint() {
        let mut colliders = sphere_mesh(64, 32);
        colliders.place_for_step(0.0, 1.0);
        let step = step_colliders(&colliders.entries, 0.0, 1.0, false);
        let mut seed = 12345u64;
        let mut uniform = || {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 40) as f32 / (1u64 << 24) as f32
        };
        let bits = |h: &Hit| {
            (
                h.signed.to_bits(),
                h.local_point.map(f32::to_bits),
                h.smooth_normal.map(f32::to_bits),
                h.triangle,
            )
        };
        let (mut compared, mut inside) = (0, 0);
        for _ in 0..50_000 {
            let z = 2.0 * uniform() - 1.0;
            let phi = std::f32::consts::TAU * uniform();
            let ring = (1.0 - z * z).sqrt();
            let p = Vector3::new(ring * phi.cos(), ring * phi.sin(), z) * (0.97 + 0.06 * uniform());
            let before = p + Vector3::new(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5) * 0.2;
            let hint = project(&step[0], &before, f32::MAX, None).unwrap().triangle;
            let warm = project(&step[0], &p, 0.05, Some(hint));
            let cold = project(&step[0], &p, 0.05, None);
            match (warm, cold) {
                (Ok(w), Ok(c)) => {
                    assert_eq!(bits(&w), bits(&c), "point {p:?}, hint {hint}");
                    compared += 1;
                    inside += usize::from(c.signed < 0.0);
                }
                (Err(w), Err(c)) => assert_eq!(w.0.to_bits(), c.0.to_bits(), "point {p:?}"),
                _ => panic!("point {p:?}: found with one start and not the other"),
            }
        }
        assert!(
            compared > 40_000 && inside > 10_000,
            "{compared} compared, {inside} inside"
        );
    }
}
