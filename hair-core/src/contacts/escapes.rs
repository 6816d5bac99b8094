//! The frame-end check: hair points that outran detection's margin and ended the frame inside a
//! collider are put back on its surface.
//!
//! Detection tests a point against a collider only within a query radius set by the point's
//! velocity at the step's start (see `detect`). A point that accelerates far beyond that within
//! the step — next to the root of a soft strand snapping taut, measured at 4–5 m/s from rest
//! within one step on the parity scene without a strain limit — gets no contact and can end the
//! frame inside the collider (2.2 cm on that scene). The next step's detection would find it and
//! push it out, but the frame would already be cached with it inside.
//!
//! So after a frame's last step every free point that had no contact is checked against every
//! collider, at the colliders' end-of-frame poses. Detection's memory makes this nearly free: a
//! point at distance `≥ bound` from the surface at body-space position `at` is still at least
//! `bound − |p − at|` away at `p` (the distance is 1-Lipschitz), and for a point that kept to its
//! margin that exceeds its hair radius plus the collider's thickness. Only a point for which it
//! does not is projected exactly; if its centre is closer to the surface than radius plus
//! thickness (or inside a solid) it is moved to that distance along the surface normal, and its
//! velocity relative to the collider loses any part pointing into the surface. A scene where no
//! point outruns the margin is bit-identical with or without this check.
//!
//! The move back is a correction, not motion: the point's velocity keeps its tangential and
//! outward parts and loses only what points into the surface, and the displacement is not
//! added to it (that would throw the point off the collider; see `penalty` on the push-out).
//!
//! On a shell (an open mesh, no inside) a point that crossed it is put back at the distance on
//! the side it ended on: the check keeps the distance, it does not undo a crossing.

use hair_par::prelude::*;
use nalgebra::{Point3, Vector3};

use super::collider_set::Colliders;
use super::detect::{step_colliders, Affine, NO_CONTACT};

/// Points per parallel job.
const CHUNK: usize = 4096;

/// What the check reads and changes of the strands.
pub(crate) struct EscapeInput<'a> {
    /// Positions at the frame's end, world, m (points put back are moved).
    pub positions: &'a mut [Vector3<f32>],
    /// Velocities, m/s (points put back lose their velocity into the surface).
    pub velocities: &'a mut [Vector3<f32>],
    /// Collision radius per point, m.
    pub radii: &'a [f32],
    /// Inverse mass per point, 1/kg (0: pinned, not checked).
    pub inv_mass: &'a [f32],
    /// The last step's contacts: plane offset or sphere radius per point, [`NO_CONTACT`] for
    /// none.
    pub contact_size: &'a [f32],
}

/// Puts back on the surface every free point without a contact in the last step (from fraction
/// `a` to 1 of the frame, `step_dt` s long) that ends the frame closer to a collider than its
/// radius plus the collider's thickness. Returns how many points were put back.
pub(crate) fn put_back_escapees(
    colliders: &mut Colliders,
    a: f32,
    step_dt: f32,
    input: EscapeInput,
) -> usize {
    // Deforming meshes stand at the frame's end, with the last step's motion.
    colliders.place_meshes(1.0, a, 1.0);
    let count = colliders.entries.len();
    let n = input.positions.len();
    let memory = &mut colliders.clearance.memory;
    if count == 0 || memory.len() != n * count {
        return 0;
    }
    let step = step_colliders(&colliders.entries, a, 1.0, true);
    let to_body: Vec<Affine> = step.iter().map(|c| Affine::from(c.end.inverse())).collect();
    input
        .positions
        .par_chunks_mut(CHUNK)
        .zip(input.velocities.par_chunks_mut(CHUNK))
        .zip(memory.par_chunks_mut(CHUNK * count))
        .enumerate()
        .map(|(k, ((x, v), memory))| {
            let base = k * CHUNK;
            let mut caught = 0;
            for (j, (x, v)) in x.iter_mut().zip(v.iter_mut()).enumerate() {
                let i = base + j;
                if input.inv_mass[i] == 0.0 || input.contact_size[i] != NO_CONTACT {
                    continue;
                }
                for (c, col) in step.iter().enumerate() {
                    let m = &mut memory[j * count + c];
                    let local = to_body[c].apply(x);
                    let keep = input.radii[i] + col.thickness;
                    if m.clear_of(&local, keep) {
                        continue;
                    }
                    let Some(hit) = m.project(col, local, keep, m.hint) else {
                        continue;
                    };
                    if hit.signed >= keep {
                        continue;
                    }
                    let target = hit.local_point + hit.local_normal * keep;
                    *x = (col.end * Point3::from(target)).coords;
                    let normal = col.end.rotation * hit.local_normal;
                    let surface = col.surface_velocity(&target, &hit.motion, step_dt);
                    let into = (*v - surface).dot(&normal);
                    if into < 0.0 {
                        *v -= normal * into;
                    }
                    // Forget the distance (its exact value is measured at the next step).
                    m.at = target;
                    m.bound = f32::NEG_INFINITY;
                    caught += 1;
                }
            }
            caught
        })
        .sum()
}
