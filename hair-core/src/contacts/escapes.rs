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
//! So after a frame's last step every free point is checked against every collider, at the
//! colliders' end-of-frame poses. Detection's memory makes this nearly free: a
//! point at distance `≥ bound` from the surface at body-space position `at` is still at least
//! `bound − |p − at|` away at `p` (the distance is 1-Lipschitz), and for a point that kept to its
//! margin that exceeds its hair radius plus the collider's thickness. Only a point for which it
//! does not is projected exactly; if its centre is closer to the surface than radius plus
//! thickness (or inside a solid) it is moved to that distance along the surface normal, and its
//! velocity relative to the collider loses any part pointing into the surface. A point that
//! is not moved keeps its bits.
//!
//! **Points in contact** are checked too. The response lands them on the contact's local
//! surface model (a plane or sphere moving with the collider, see `penalty`), which at the
//! implicit integrators' long substeps can drift from the exact surface where hair slides over
//! a turning part of it or the collider moves within the step: on the shipped scenes at 7 BDF2
//! substeps per frame such points ended frames up to 0.26 mm inside, and a gust swept into the
//! head 0.85 mm. A point in contact is left alone within [`SETTLED_DEPTH`] (the model's own
//! error, which includes the smooth sphere lying below the facets of a mesh) plus whatever of
//! the depth found at detection the response has not yet eased out at the push speed (hair that
//! started inside leaves over several substeps, see `penalty`); deeper, it is moved back to that
//! depth. Hair resting on a collider costs a projection per point in contact per frame, on a
//! convex part of a mesh a plane test or two (the detection's shortcut).
//!
//! The move back is a correction, not motion: the point's velocity keeps its tangential and
//! outward parts and loses only what points into the surface, and the displacement is not
//! added to it (that would throw the point off the collider; see `penalty` on the push-out).
//!
//! **Segment lengths.** Moving a point out lengthens its two segments by up to the depth moved.
//! Where the strands have a length limit (the strain limit's `(1 + max_strain) ×` rest length,
//! or the inextensibility projection's rest length), each strand with a moved point is then
//! brought back within it: the limit's own projection (`integrate::strain_limit`) with the
//! moved points and the kinematic ones held, so their free neighbours follow them out, then a
//! pass from root to tip that shortens whatever segment is still too long by moving its far end
//! towards its near one. That pass moves a put-back point only where both ends of its segment are
//! held — next to a root, or between two put-back points — and then back towards the collider:
//! the length limit the artist set wins over the last fraction of a millimetre of depth. Like the
//! move out, these are corrections of position; velocities are left as they are.
//!
//! The length pass can itself pull a free point into a collider: held between two put-back
//! points, it is drawn towards their chord, which cuts into a convex surface by `L²/(8R)` for
//! points `L` apart on a radius `R` (on the parity scene's 1 m head with 9.4 cm segments, 4 mm;
//! with one round its deepest cached point was 7.9 mm). So put-back and length pass alternate, as
//! the substeps' coupling of contacts and lengths does, for at most [`ROUNDS`] rounds while the
//! put-back still moves a point; the last word is the length pass's. Without a
//! length limit the strand's springs take the lengthening up in the next step.
//!
//! On a shell (an open mesh, no inside) a point that crossed it is put back at the distance on
//! the side it ended on: the check keeps the distance, it does not undo a crossing.

use hair_par::prelude::*;
use nalgebra::{Point3, Vector3};

use super::collider_set::Colliders;
use super::detect::{step_colliders, Affine, NO_CONTACT};
use crate::integrate::inextensible::ProjectionScratch;
use crate::integrate::lanes::{splat, Baseline, V3};
use crate::integrate::strain_limit::limit_strain;

/// Points per parallel job.
const CHUNK: usize = 4096;

/// Most rounds of (put-back, length limit) per frame (module docs, "Segment lengths").
const ROUNDS: usize = 4;

/// Depth (m) a point that had a contact in the last step may keep at the frame's end beyond
/// what is left of the depth found at detection: the contact model's surface (a sphere from
/// smooth normals, see `penalty`) lies below a faceted mesh by up to the facets' sagitta, and
/// hair resting on it is left there; anything deeper is put back.
pub(crate) const SETTLED_DEPTH: f32 = 2.5e-5;

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
    /// The last step's contacts: depth found at detection per point, m (0 without a contact).
    pub found_depth: &'a [f32],
    /// Speed at which the response eases found depth out, m/s
    /// ([`super::ContactSettings::max_push_speed`]).
    pub max_push_speed: f32,
    /// The strands' length limit, which the points put back must keep (module docs); `None`
    /// where segments have none.
    pub lengths: Option<LengthLimit<'a>>,
}

/// A length limit on the strands' segments: none longer than `ratio ×` its rest length.
pub(crate) struct LengthLimit<'a> {
    /// Start of each strand's points, and the point count at the end (one more entry than
    /// strands).
    pub offsets: &'a [u32],
    /// Rest length per segment, m, strand after strand (a strand of `n` points has `n − 1`).
    pub rest_length: &'a [f32],
    /// Longest a segment may be, as a multiple of its rest length (≥ 1).
    pub ratio: f32,
}

/// How many points the frame-end check put back.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct PutBack {
    /// Points without a contact in the last step (they outran detection's margin).
    pub escaped: usize,
    /// Points with a contact in the last step, deeper than [`SETTLED_DEPTH`].
    pub deep: usize,
}

impl std::iter::Sum for PutBack {
    fn sum<I: Iterator<Item = Self>>(iter: I) -> Self {
        iter.fold(Self::default(), |a, b| Self {
            escaped: a.escaped + b.escaped,
            deep: a.deep + b.deep,
        })
    }
}

/// Puts back on the surface every free point that ends the frame closer to a collider than its
/// radius plus the collider's thickness: by any depth if it had no contact in the last step
/// (from fraction `a` to 1 of the frame, `step_dt` s long), by more than [`SETTLED_DEPTH`] if it
/// had one; with a length limit, in rounds with it (module docs). Returns how many points the
/// first round put back.
pub(crate) fn put_back_escapees(
    colliders: &mut Colliders,
    a: f32,
    step_dt: f32,
    input: EscapeInput,
) -> PutBack {
    // Deforming meshes stand at the frame's end, with the last step's motion.
    colliders.place_meshes(1.0, a, 1.0);
    let count = colliders.entries.len();
    let n = input.positions.len();
    let memory = &mut colliders.clearance.memory;
    if count == 0 || memory.len() != n * count {
        return PutBack::default();
    }
    let step = step_colliders(&colliders.entries, a, 1.0, true);
    let to_body: Vec<Affine> = step.iter().map(|c| Affine::from(c.end.inverse())).collect();
    let mut moved = vec![false; n];
    let mut first = PutBack::default();
    for round in 0..ROUNDS {
        moved.fill(false);
        let caught = input
            .positions
            .par_chunks_mut(CHUNK)
            .zip(input.velocities.par_chunks_mut(CHUNK))
            .zip(memory.par_chunks_mut(CHUNK * count))
            .zip(moved.par_chunks_mut(CHUNK))
            .enumerate()
            .map(|(k, (((x, v), memory), moved))| {
                let base = k * CHUNK;
                let mut caught = PutBack::default();
                for (j, ((x, v), moved)) in x.iter_mut().zip(v.iter_mut()).zip(moved).enumerate() {
                    let i = base + j;
                    if input.inv_mass[i] == 0.0 {
                        continue;
                    }
                    // Depth left alone: none for a point without a contact; for one with a contact,
                    // the contact model's own error plus what the response has not yet eased out of
                    // the depth found at detection (hair that started inside leaves at the push
                    // speed, not at once).
                    let allowed = if input.contact_size[i] == NO_CONTACT {
                        0.0
                    } else {
                        SETTLED_DEPTH
                            + (input.found_depth[i] - input.max_push_speed * step_dt).max(0.0)
                    };
                    for (c, col) in step.iter().enumerate() {
                        let m = &mut memory[j * count + c];
                        let local = to_body[c].apply(x);
                        let keep = input.radii[i] + col.thickness;
                        if m.clear_of(&local, keep - allowed) {
                            continue;
                        }
                        let Some(hit) = m.project(col, local, keep, m.hint) else {
                            continue;
                        };
                        if hit.signed >= keep - allowed {
                            continue;
                        }
                        // Back to the depth allowed (0: onto the surface), no farther.
                        let target = hit.local_point + hit.local_normal * (keep - allowed);
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
                        *moved = true;
                        if allowed == 0.0 {
                            caught.escaped += 1;
                        } else {
                            caught.deep += 1;
                        }
                    }
                }
                caught
            })
            .sum::<PutBack>();
        if round == 0 {
            first = caught;
        }
        match &input.lengths {
            Some(limit) if caught.escaped + caught.deep > 0 => {
                keep_lengths(input.positions, input.inv_mass, &moved, limit);
            }
            _ => break,
        }
    }
    first
}

/// Brings every strand with a put-back point (`moved`) back within `limit` (module docs,
/// "Segment lengths"): the strain limit's projection with the put-back and kinematic points
/// (`inv_mass` 0) held, then a root-to-tip pass moving the far end of any segment still too
/// long. Positions only, strand by strand in order, so the result does not depend on threads.
fn keep_lengths(
    positions: &mut [Vector3<f32>],
    inv_mass: &[f32],
    moved: &[bool],
    limit: &LengthLimit,
) {
    let mut scratch = ProjectionScratch::<Baseline>::default();
    let (mut x, mut v, mut w, mut rest) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (s, ends) in limit.offsets.windows(2).enumerate() {
        let points = ends[0] as usize..ends[1] as usize;
        if points.len() < 2 || !moved[points.clone()].iter().any(|&m| m) {
            continue;
        }
        // The strand in every lane of one SIMD group (the projection is written for groups).
        x.clear();
        x.extend(positions[points.clone()].iter().map(V3::<Baseline>::splat));
        v.clear();
        v.resize(points.len(), V3::<Baseline>::default());
        w.clear();
        w.extend(
            points
                .clone()
                .map(|i| splat::<Baseline>(if moved[i] { 0.0 } else { inv_mass[i] })),
        );
        let segments = points.start - s..points.end - s - 1;
        rest.clear();
        rest.extend(
            limit.rest_length[segments.clone()]
                .iter()
                .map(|&l| splat::<Baseline>(l)),
        );
        // Velocities move by 0 × the displacement: a correction, not motion.
        let ratio = splat::<Baseline>(limit.ratio);
        limit_strain(&mut x, &mut v, &w, &rest, ratio, splat(0.0), &mut scratch);
        let strand = &mut positions[points.clone()];
        for (p, lanes) in strand.iter_mut().zip(&x) {
            *p = lanes.lane(0);
        }
        // What the held points leave too long: the far end follows, unless it is kinematic.
        for (j, &l) in limit.rest_length[segments].iter().enumerate() {
            let d = strand[j + 1] - strand[j];
            let (len, longest) = (d.norm(), l * limit.ratio);
            if len > longest && inv_mass[points.start + j + 1] > 0.0 {
                strand[j + 1] = strand[j] + d * (longest / len);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A straight strand of `n` points 1 cm apart along +z from the origin, root kinematic.
    fn strand(n: usize) -> (Vec<Vector3<f32>>, Vec<f32>, Vec<f32>) {
        let x = (0..n)
            .map(|i| Vector3::new(0.0, 0.0, 0.01 * i as f32))
            .collect();
        let w = (0..n).map(|i| if i == 0 { 0.0 } else { 1.0 }).collect();
        (x, w, vec![0.01; n - 1])
    }

    fn lengths(x: &[Vector3<f32>]) -> Vec<f32> {
        x.windows(2).map(|p| (p[1] - p[0]).norm()).collect()
    }

    /// A point put back 2 mm sideways in the middle of a strand keeps its place, its free
    /// neighbours follow it, and no segment ends longer than the limit.
    #[test]
    fn a_put_back_point_keeps_its_place_and_the_strand_its_lengths() {
        let (mut x, w, rest) = strand(7);
        x[3].x += 0.002;
        let put = x[3];
        let mut moved = vec![false; 7];
        moved[3] = true;
        let limit = LengthLimit {
            offsets: &[0, 7],
            rest_length: &rest,
            ratio: 1.01,
        };
        keep_lengths(&mut x, &w, &moved, &limit);
        assert_eq!(x[3], put, "the put-back point is held");
        assert_eq!(x[0], Vector3::zeros(), "the root is kinematic");
        for (j, len) in lengths(&x).into_iter().enumerate() {
            assert!(len <= 0.0101 * (1.0 + 2e-5), "segment {j}: {len}");
        }
        assert!(x[2].x > 0.0 && x[4].x > 0.0, "the neighbours follow: {x:?}");
    }

    /// Next to the root both ends of the segment are held: the put-back point gives way, along
    /// the segment, to exactly the limit.
    #[test]
    fn next_to_the_root_the_length_limit_wins_over_the_depth() {
        let (mut x, w, rest) = strand(4);
        x[1].x += 0.003;
        let mut moved = vec![false; 4];
        moved[1] = true;
        let limit = LengthLimit {
            offsets: &[0, 4],
            rest_length: &rest,
            ratio: 1.01,
        };
        keep_lengths(&mut x, &w, &moved, &limit);
        let len = lengths(&x);
        assert!((len[0] - 0.0101).abs() < 1e-8, "{len:?}");
        assert!(len.iter().all(|&l| l <= 0.0101 * (1.0 + 1e-6)), "{len:?}");
        // Pulled back along the segment towards the root: the sideways offset shrinks.
        assert!(x[1].x > 0.0 && x[1].x < 0.003, "{:?}", x[1]);
    }

    /// Strands without a put-back point keep their bits, even when they are over the limit.
    #[test]
    fn strands_without_a_put_back_point_are_untouched() {
        let (mut a, wa, ra) = strand(4);
        let (mut b, wb, rb) = strand(4);
        b[3].z += 0.005; // too long, but not the check's doing
        a[2].y += 0.001;
        let mut x = [a, b].concat();
        let w = [wa, wb].concat();
        let rest = [ra, rb].concat();
        let mut moved = vec![false; 8];
        moved[2] = true;
        let before = x.clone();
        let limit = LengthLimit {
            offsets: &[0, 4, 8],
            rest_length: &rest,
            ratio: 1.01,
        };
        keep_lengths(&mut x, &w, &moved, &limit);
        assert_eq!(x[4..], before[4..]);
    }
}
