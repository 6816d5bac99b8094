//! Hair–head collision of the rod model as constraints (seed 002, "Hair-Head Collisions").
//!
//! After the unconstrained step, the set `P` of nodes that penetrate a collider (their centre
//! nearer than the hair radius plus the collider's thickness to its surface, or inside it) is
//! found with parry's point projection on each collider posed at the substep's end. Each node of
//! `P` gets one constraint for the rest of the substep: lie on the tangent plane at its
//! projection, grown by radius and thickness (the constraint value is the penetration depth).
//! The projection ([`super::project`]) then satisfies it together with inextensibility, so
//! nothing is pushed by a force and nothing bounces: the node's velocity, recomputed from the
//! projected position, keeps only the tangential part and the surface's own motion.
//!
//! Moving a node of `P` can pull a neighbour into the head; the solver detects again on the
//! projected strand and adds the new nodes to `P` (a few rounds at most), so the set only grows
//! within a substep.
//!
//! Limits: only solid colliders (spheres, capsules, closed meshes) have an inside; shells are
//! refused by [`super::RodSolver::step_frame_with_colliders`]. The plane is the surface's tangent
//! plane, exact for convex surfaces and a slight under-correction in concave creases, where the
//! next substep finds the node again. Candidates are screened by each collider's enclosing
//! sphere, then projected exactly; the cost is one projection per node near a collider.

use nalgebra::{Point3, Vector3};

use super::frames::V3;
use super::project::Contact;
use crate::contacts::collider_set::Surface;
use crate::contacts::math::{from_glam, to_glam};
use crate::contacts::Colliders;

/// Nodes nearer than this (m) to the surface take the normal from the enclosing sphere's
/// centre: the projection direction is not trusted there.
const NORMAL_EPS: f32 = 1e-7;

/// What a strand remembers of a node and one collider between substeps: a lower bound of the
/// node's signed distance to the collider's surface, measured at a body-space position. The
/// distance changes by at most how far the node moves in the collider's body space (it is
/// 1-Lipschitz), so while `bound − |p − at|` exceeds the hair radius plus thickness the node
/// cannot touch the collider and is not projected: hair away from the head costs a subtraction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clearance {
    /// Body-space position of the measurement, m.
    at: Vector3<f32>,
    /// Lower bound of the signed distance there, m (−∞: unknown).
    bound: f32,
}

impl Default for Clearance {
    fn default() -> Self {
        Self {
            at: Vector3::zeros(),
            bound: f32::NEG_INFINITY,
        }
    }
}

/// Finds the nodes of `x` (m, world) penetrating `colliders` posed at fraction `s` of the frame,
/// and adds a contact for each free node not yet in `contacts` (kept sorted by node). `memory`
/// holds the strand's [`Clearance`] per node and collider (node-major; resized and reset when
/// its length does not fit). Returns how many contacts were added.
pub(crate) fn penetrating(
    colliders: &Colliders,
    s: f32,
    x: &[V3],
    radius: &[f32],
    inv_mass: &[f64],
    memory: &mut Vec<Clearance>,
    contacts: &mut Vec<Contact>,
) -> usize {
    let before = contacts.len();
    let count = colliders.entries.len();
    if memory.len() != x.len() * count {
        memory.clear();
        memory.resize(x.len() * count, Clearance::default());
    }
    let poses: Vec<_> = colliders.entries.iter().map(|e| e.pose_at(s)).collect();
    for (i, xi) in x.iter().enumerate() {
        if inv_mass[i] == 0.0 || contacts.iter().any(|c| c.node == i) {
            continue;
        }
        let world = xi.cast::<f32>();
        let mut best: Option<(f32, Contact)> = None;
        for (c, (e, pose)) in colliders.entries.iter().zip(&poses).enumerate() {
            if e.surface != Surface::Solid {
                continue;
            }
            let reach = radius[i] + e.thickness;
            let local = pose.inverse_transform_point(&Point3::from(world)).coords;
            let m = &mut memory[i * count + c];
            if m.bound - (local - m.at).norm() >= reach {
                continue;
            }
            let (centre, enclosing) = e.bounding_sphere;
            let from_centre = (local - centre).norm();
            if from_centre > enclosing + reach {
                *m = Clearance {
                    at: local,
                    bound: from_centre - enclosing,
                };
                continue;
            }
            let proj = e.shape.project_local_point(to_glam(&local), false);
            let on = from_glam(proj.point);
            let delta = local - on;
            let dist = delta.norm();
            let signed = if proj.is_inside { -dist } else { dist };
            *m = Clearance {
                at: local,
                bound: signed,
            };
            if signed >= reach {
                continue;
            }
            let normal_local = if dist > NORMAL_EPS {
                if proj.is_inside {
                    -delta / dist
                } else {
                    delta / dist
                }
            } else {
                (local - centre).normalize()
            };
            if !normal_local.iter().all(|c| c.is_finite()) {
                continue;
            }
            let normal = (pose.rotation * normal_local).cast::<f64>().normalize();
            let surface = (pose * Point3::from(on)).coords.cast::<f64>();
            let contact = Contact {
                node: i,
                normal,
                offset: normal.dot(&surface) + reach as f64,
            };
            if best.as_ref().is_none_or(|(d, _)| signed - reach < *d) {
                best = Some((signed - reach, contact));
            }
        }
        if let Some((_, c)) = best {
            contacts.push(c);
        }
    }
    contacts.sort_by_key(|c| c.node);
    contacts.len() - before
}
