//! Hair points inside colliders: the depth of each free point's collision sphere inside the
//! thickened surface of its deepest collider, at the colliders' current poses.
//!
//! Depth is `radius + thickness − signed distance` of the point's centre from the collider's
//! surface (negative distance inside a solid; a shell, which has no inside, measures the
//! unsigned distance). This is the same gap the contact response keeps
//! ([`crate::contacts`]): a point the solver left exactly on the surface has depth 0. The
//! distance is parry's exact point projection on the collider's shape, in its body space at the
//! pose [`Colliders::pose`] reports (the end of the last stepped frame, or the pose set for the
//! next one); a collider's enclosing sphere screens out points that cannot reach it, so hair away
//! from colliders costs a subtraction per point and collider.

use hair_par::prelude::*;
use nalgebra::{Point3, Vector3};
use parry3d::query::{PointQuery, PointQueryWithLocation};
#[cfg(feature = "serde")]
use serde::Serialize;

use crate::contacts::collider_set::{Entry, Surface};
use crate::contacts::math::{from_glam, to_glam};
use crate::contacts::Colliders;

/// Points per parallel job.
const CHUNK: usize = 2048;

/// Hair points found inside colliders, merged over frames.
#[derive(Debug, Clone, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct Penetration {
    /// Depth below which a point counts as touching, not inside, m.
    pub tolerance: f32,
    /// Free points checked, summed over frames.
    pub checked: u64,
    /// Points deeper than `tolerance`, summed over frames.
    pub inside: u64,
    /// `inside / checked` over all frames (0 when nothing was checked).
    pub inside_fraction: f64,
    /// The largest fraction of points inside in any one frame.
    pub worst_frame_fraction: f64,
    /// The deepest penetration of any point deeper than `tolerance`, m (0 when none is).
    pub deepest: f32,
}

impl Penetration {
    /// Adds another frame's (or run's) counts.
    pub fn merge(&mut self, other: &Penetration) {
        self.tolerance = self.tolerance.max(other.tolerance);
        self.checked += other.checked;
        self.inside += other.inside;
        self.inside_fraction = if self.checked > 0 {
            self.inside as f64 / self.checked as f64
        } else {
            0.0
        };
        self.worst_frame_fraction = self.worst_frame_fraction.max(other.worst_frame_fraction);
        self.deepest = self.deepest.max(other.deepest);
    }
}

/// What a run's penetration measurement remembers from frame to frame to skip work: per point and
/// collider, a lower bound of the signed distance of the point's centre from the collider's
/// surface (m) and the body-space position it holds at. The signed distance is 1-Lipschitz in
/// the body-space position, so `bound − |moved|` still bounds it a frame later; a point whose
/// bound exceeds its radius plus the collider's thickness cannot be inside and is not projected.
/// Points that must be projected start from the mesh triangle they projected on last time: on a
/// convex part of a solid mesh that triangle (or one a short walk away) certifies the answer
/// without parry's BVH search (the contact detection's shortcut), elsewhere its distance bounds the
/// search. The distances are the memoryless measurement's (the same projection on the same
/// triangle, up to which of two equally near triangles is named), and points within the contact
/// tolerance count for nothing either way; hair away from colliders, or resting on them and
/// moving with them (a head), then costs a subtraction and a norm per point, and hair sliding
/// over a head a plane test or two. Bounds of a collider whose mesh was moved to other vertices
/// are dropped.
#[derive(Debug, Clone, Default)]
pub struct PenetrationMemory {
    /// Per collider, the shape version the bounds were measured on.
    versions: Vec<u64>,
    /// Point-major, one per point and collider.
    bounds: Vec<Remembered>,
}

/// No triangle remembered.
const NO_TRIANGLE: u32 = u32::MAX;

/// What [`PenetrationMemory`] keeps of one point and collider.
#[derive(Debug, Clone, Copy)]
struct Remembered {
    /// Lower bound of the signed distance of the point's centre from the surface, m.
    bound: f32,
    /// Body-space position it was measured at, m.
    at: Vector3<f32>,
    /// The mesh triangle the point projected on ([`NO_TRIANGLE`]: none, or not a mesh).
    triangle: u32,
}

impl Remembered {
    /// Nothing known: the next measurement projects.
    const UNKNOWN: Self = Self {
        bound: f32::NEG_INFINITY,
        at: Vector3::new(0.0, 0.0, 0.0),
        triangle: NO_TRIANGLE,
    };
}

impl PenetrationMemory {
    /// Empty memory: the first frame measured with it projects every point near a collider.
    pub fn new() -> Self {
        Self::default()
    }

    /// Forgets every bound that no longer applies: all of them when the point count or the
    /// colliders changed, a collider's when its mesh was moved to other vertices.
    fn prepare(&mut self, colliders: &Colliders, points: usize) {
        let e = colliders.entries.len();
        let unknown = Remembered::UNKNOWN;
        if self.versions.len() != e || self.bounds.len() != points * e {
            self.versions = colliders.entries.iter().map(|c| c.version).collect();
            self.bounds = vec![unknown; points * e];
            return;
        }
        for (c, entry) in colliders.entries.iter().enumerate() {
            if self.versions[c] != entry.version {
                self.versions[c] = entry.version;
                for i in 0..points {
                    self.bounds[i * e + c] = unknown;
                }
            }
        }
    }
}

/// [`depth`] with `memory` (one entry per collider of this point): colliders the point cannot
/// reach by its bound are skipped, the others measured (warm-started from the triangle the point
/// projected on last time) and their bounds renewed.
fn depth_remembered(
    colliders: &Colliders,
    x: &Vector3<f32>,
    radius: f32,
    tolerance: f32,
    memory: &mut [Remembered],
) -> Option<f32> {
    colliders
        .entries
        .iter()
        .zip(memory)
        .filter_map(|(e, slot)| {
            let keep = radius + e.thickness;
            let local = e.end.inverse_transform_point(&Point3::from(*x)).coords;
            // Its depth is at most the tolerance: it does not count.
            if slot.bound - (local - slot.at).norm() >= keep - tolerance {
                return None;
            }
            let hint = (slot.triangle != NO_TRIANGLE).then_some(slot.triangle);
            let (bound, triangle) = distance_bound(e, &local, keep, hint);
            *slot = Remembered {
                bound,
                at: local,
                triangle: triangle.unwrap_or(NO_TRIANGLE),
            };
            (bound < keep).then_some(keep - bound)
        })
        .reduce(f32::max)
}

/// A lower bound of the signed distance (m) of body-space point `local` from the surface of
/// collider `e`, exact wherever it is below `keep`: the distance to the collider's enclosing
/// sphere when that exceeds `keep`, else the exact projection (negative inside a solid; a
/// shell, which has no inside, gives the unsigned distance) — with the mesh triangle it lies on,
/// which warm-starts the next search (`hint`).
fn distance_bound(
    e: &Entry,
    local: &Vector3<f32>,
    keep: f32,
    hint: Option<u32>,
) -> (f32, Option<u32>) {
    let (centre, enclosing) = e.bounding_sphere;
    let to_sphere = (local - centre).norm() - enclosing;
    if to_sphere > keep {
        return (to_sphere, None);
    }
    let Some(mesh) = e.shape.as_trimesh() else {
        return (surface_offset(e, local).0, None);
    };
    let pg = to_glam(local);
    let hint = hint.filter(|&t| (t as usize) < mesh.num_triangles());
    // Near a convex part of a solid mesh, the last triangle (or one a short walk away)
    // certifies that the nearest surface point lies on it, outside: the distance to that
    // triangle is the mesh's.
    if let (Some(fast), Some(t)) = (&e.fast, hint) {
        if let Some(hit) = fast.project(mesh, t, local) {
            let on = mesh.triangle(hit.triangle).project_local_point(pg, false);
            return ((local - from_glam(on.point)).norm(), Some(hit.triangle));
        }
    }
    // Otherwise parry's search, bounded by the hint triangle's distance (a little more keeps that
    // triangle findable: the search accepts only strictly nearer candidates).
    let limit = hint.map_or(f32::MAX, |t| {
        mesh.triangle(t).distance_to_local_point(pg, true) * (1.0 + 1e-4) + 1e-6
    });
    let found = mesh
        .project_local_point_and_get_location_with_max_dist(pg, false, limit)
        .or_else(|| mesh.project_local_point_and_get_location_with_max_dist(pg, false, f32::MAX));
    let Some((proj, (triangle, _))) = found else {
        // Only a non-finite point finds nothing; the memoryless projection says what it is.
        return (surface_offset(e, local).0, None);
    };
    let dist = (local - from_glam(proj.point)).norm();
    let signed = if e.surface == Surface::Solid && proj.is_inside {
        -dist
    } else {
        dist
    };
    (signed, Some(triangle))
}

/// Parry's exact projection of body-space point `local` on collider `e`: the signed distance (m,
/// negative inside a solid; a shell, which has no inside, gives the unsigned distance) and the
/// outward unit normal there (body space; zero on the surface itself).
fn surface_offset(e: &Entry, local: &Vector3<f32>) -> (f32, Vector3<f32>) {
    let proj = e.shape.project_local_point(to_glam(local), false);
    let offset = local - from_glam(proj.point);
    let dist = offset.norm();
    let outward = if dist < 1e-9 {
        Vector3::zeros()
    } else {
        offset / dist
    };
    if e.surface == Surface::Solid && proj.is_inside {
        (-dist, -outward)
    } else {
        (dist, outward)
    }
}

/// Depth (m) of a sphere of `radius` centred at `x` (world, m) inside the deepest of
/// `colliders`, or `None` when it reaches none of them.
pub(crate) fn depth(colliders: &Colliders, x: &Vector3<f32>, radius: f32) -> Option<f32> {
    colliders
        .entries
        .iter()
        .filter_map(|e| {
            let keep = radius + e.thickness;
            let local = e.end.inverse_transform_point(&Point3::from(*x)).coords;
            let (centre, enclosing) = e.bounding_sphere;
            let to_sphere = (local - centre).norm() - enclosing;
            let bound = if to_sphere > keep {
                to_sphere
            } else {
                surface_offset(e, &local).0
            };
            (bound < keep).then_some(keep - bound)
        })
        .reduce(f32::max)
}

/// Per point of `positions` (m, collision radii `radii` in m): the outward unit normal (world) of
/// the collider surface a free point (`inv_mass > 0`) rests on — its collision sphere within
/// `reach` (m) of touching the thickened surface, or inside it — or zero where it rests on
/// nothing. Where several colliders reach a point, the deepest contact's normal is taken. This is
/// the support [`crate::make_sag_free_supported`] lets carry weight.
pub fn resting_normals(
    colliders: &Colliders,
    positions: &[Vector3<f32>],
    radii: &[f32],
    inv_mass: &[f32],
    reach: f32,
) -> Vec<Vector3<f32>> {
    positions
        .par_iter()
        .enumerate()
        .map(|(i, x)| {
            let free = inv_mass.get(i).is_some_and(|&w| w > 0.0);
            let radius = radii.get(i).copied().unwrap_or(0.0);
            if !free {
                return Vector3::zeros();
            }
            let mut best: Option<(f32, Vector3<f32>)> = None;
            for e in &colliders.entries {
                let keep = radius + e.thickness;
                let local = e.end.inverse_transform_point(&Point3::from(*x)).coords;
                let (centre, enclosing) = e.bounding_sphere;
                if (local - centre).norm() > enclosing + keep + reach {
                    continue;
                }
                let (signed, normal) = surface_offset(e, &local);
                if signed > keep + reach || normal == Vector3::zeros() {
                    continue;
                }
                let depth = keep - signed;
                if best.is_none_or(|(d, _)| depth > d) {
                    best = Some((depth, e.end.rotation * normal));
                }
            }
            best.map_or_else(Vector3::zeros, |(_, n)| n)
        })
        .collect()
}

/// Per point of `positions` (m, collision radii `radii` in m): is it a free point (`inv_mass > 0`)
/// deeper than `tolerance` (m) inside any of `colliders` at their current poses? For marking
/// them in a picture (`hairsys preview --highlight`).
pub fn inside_flags(
    colliders: &Colliders,
    positions: &[Vector3<f32>],
    radii: &[f32],
    inv_mass: &[f32],
    tolerance: f32,
) -> Vec<bool> {
    positions
        .par_iter()
        .enumerate()
        .map(|(i, x)| {
            inv_mass.get(i).is_some_and(|&w| w > 0.0)
                && radii
                    .get(i)
                    .and_then(|&r| depth(colliders, x, r))
                    .is_some_and(|d| d > tolerance)
        })
        .collect()
}

/// Measures one frame: free points (`free[i]`) of `positions` (m) with collision radii `radii`
/// (m) against `colliders`.
pub(crate) fn measure(
    colliders: &Colliders,
    positions: &[Vector3<f32>],
    radii: &[f32],
    free: &(dyn Fn(usize) -> bool + Sync),
    tolerance: f32,
    memory: Option<&mut PenetrationMemory>,
) -> Penetration {
    // (checked, inside, deepest) of a run of points.
    let tally = |out: &mut (u64, u64, f32), depth: Option<f32>| {
        out.0 += 1;
        if let Some(d) = depth.filter(|&d| d > tolerance) {
            out.1 += 1;
            out.2 = out.2.max(d);
        }
    };
    let sum = |a: (u64, u64, f32), b: (u64, u64, f32)| (a.0 + b.0, a.1 + b.1, a.2.max(b.2));
    let (checked, inside, deepest) = match memory {
        Some(memory) if !colliders.entries.is_empty() => {
            memory.prepare(colliders, positions.len());
            let e = colliders.entries.len();
            let parts = positions
                .par_chunks(CHUNK)
                .zip(memory.bounds.par_chunks_mut(CHUNK * e))
                .enumerate()
                .map(|(k, (chunk, bounds))| {
                    let mut out = (0u64, 0u64, 0.0f32);
                    for (j, x) in chunk.iter().enumerate() {
                        let i = k * CHUNK + j;
                        if free(i) {
                            let slots = &mut bounds[j * e..(j + 1) * e];
                            let d = depth_remembered(colliders, x, radii[i], tolerance, slots);
                            tally(&mut out, d);
                        }
                    }
                    out
                });
            hair_par::reduce(parts, || (0, 0, 0.0), sum)
        }
        _ => hair_par::reduce(
            positions.par_chunks(CHUNK).enumerate().map(|(k, chunk)| {
                let mut out = (0u64, 0u64, 0.0f32);
                for (j, x) in chunk.iter().enumerate() {
                    let i = k * CHUNK + j;
                    if free(i) {
                        tally(&mut out, depth(colliders, x, radii[i]));
                    }
                }
                out
            }),
            || (0, 0, 0.0),
            sum,
        ),
    };
    let fraction = if checked > 0 {
        inside as f64 / checked as f64
    } else {
        0.0
    };
    Penetration {
        tolerance,
        checked,
        inside,
        inside_fraction: fraction,
        worst_frame_fraction: fraction,
        deepest,
    }
}
