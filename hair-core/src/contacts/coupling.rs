//! Contacts solved together with the length constraints (the strain limit, the inextensibility
//! projection) at the end of each force substep, in SIMD lanes (lanes = strands).
//!
//! # Why
//! The response (`penalty`) lands a point on the surface, or moves a point found inside out of
//! it, *before* the position update; the length constraints run *after* it and move points
//! wherever the segments need them, contacts or not. Where hair lies over a sharp feature — the
//! Sintel bust's ears, whose rims are a few millimetres thick against 5–10 mm segments — the
//! two, run one after the other, fight: the strain limit pulls a point back into the ear, the
//! next substep's response pushes it out again, and because the strain limit turns every
//! displacement it makes into velocity (`Δv = Δx/dt`, `integrate::strain_limit`), each push-out is
//! handed on to the point's neighbours as velocity towards it. At ~2,600 substeps a frame that
//! pumps energy into the strands: on the shipped Sintel scene without this coupling (and without
//! `detect`'s rule for narrow concave spheres), 89 strands around her ears move more than 1 cm in
//! the first frame (up to 9.4 cm: strands under the ear lobe flung up past their roots), 4 points
//! end the frame inside the bust by more than the response can catch, and the frame-end check that
//! puts them back stretches their segments by up to 12.8 %. Lowering `max_push_speed` to 0.02 m/s
//! alone (less push to hand on) cuts that motion to 1.7 cm, which singles out the push-out as the
//! source (`docs/design/contacts.md`).
//!
//! # Method
//! Projected Gauss–Seidel over the two kinds of constraint (Müller et al. 2007, "Position Based
//! Dynamics", §3.3: constraints projected one after another, a few rounds), with every
//! contact a one-sided constraint `d(x_i) ≥ floor_i` on the contact's surface model at the
//! substep's end (`penalty::surface_model`; projecting along its normal is exact). The
//! substep's corrections are split by what they correct:
//!
//! 1. **Motion** (velocities follow positions): after the position update, each contact's
//!    floor is where the response put the point, `min(0, d)`: on the surface, or as deep as it
//!    still is when it started inside. Then rounds of (length constraints, contact projection)
//!    with every displacement added to the velocity over dt, as the strain limit does, until
//!    no contact is pushed out by more than [`SLOP`]; the length constraints run last. A point
//!    the strain limit pulled into the surface is put back on it and the velocity that pull
//!    gave it is taken back, so the strand drapes over the surface like a rope over a pulley
//!    and the stored velocity is still the one that moved the point.
//! 2. **Recovery** (positions only): a point that started inside is moved out by the push the
//!    response allowed (`penalty`: the depth found at detection at most at
//!    `ContactSettings::max_push_speed`), its floor raised by that much,
//!    and the segments follow in more rounds — as position corrections that leave every
//!    velocity as it is. The push-out is the correction of an earlier error, not motion (see
//!    `penalty`); handing it to the neighbours as velocity would be the pump above.
//!
//! Without a contact in a group, or without a length constraint, nothing of this runs and the
//! substep is bit for bit the one without this pass.
//!
//! # Limits
//! - The rounds stop at [`ROUNDS`]: where they have not converged (a strand pulled taut across
//!   a rim), the last length correction may leave a contact inside by its pull, which the next
//!   substep's response and projection take out again (measured: see the constant).
//! - The recovery's displacements are not in the velocities: a strand being pushed out of a
//!   collider has a velocity–position mismatch of up to the push speed for the substeps it is
//!   pushed, as the response alone had (`penalty`).
//! - A contact's floor is fixed for the substep from where the point stood after the position
//!   update; the surface model is the step's (`detect`), so a point dragged along a sharp
//!   feature far within one collision step keeps to the plane or sphere of where detection
//!   found it.

use super::penalty::{surface_model, ContactLanes};
use crate::integrate::lanes::{splat, Lane, V3};

/// Most rounds of (contact projection, length constraints) per phase and substep.
pub(crate) const ROUNDS: u32 = 4;

/// Contact correction (m) below which a round counts as converged: f32 round-off of a position
/// half a metre from the origin is 3·10⁻⁸ m; a micrometre is ten times below a real hair's
/// radius and a hundred below the quality report's contact tolerance.
pub(crate) const SLOP: f32 = 1e-6;

/// Which correction the length constraints are asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Correction {
    /// Motion: displacements go into the velocities (phase 1).
    Motion,
    /// Recovery from penetration: positions only (phase 2).
    Recovery,
}

/// The contacts of a group in one substep.
pub(crate) struct SubstepContacts<'a, L: Lane> {
    /// Points with a contact in at least one lane.
    pub points: &'a [usize],
    /// Contact data per point (indexed by point; only `points` are read).
    pub contact: &'a [ContactLanes<L>],
    /// Push-out velocity the response asked for per point (m/s, along the normal).
    pub push: &'a [V3<L>],
    /// 1 for free points, 0 for kinematic ones (never moved).
    pub free: &'a [L],
    /// The substep's end, s from the step's start.
    pub t_end: L,
    /// Substep length, s.
    pub dt: f32,
}

/// The length constraints the contacts are solved with: called with the positions (m), the
/// velocities (m/s) and what is corrected. Implementations mark `apply` `#[inline(always)]`
/// so it is compiled into the kernel's AVX2 copy (see `integrate::kernel`).
pub(crate) trait Lengths<L: Lane> {
    /// Applies the constraints to one group's `x` and `v`.
    fn apply(&mut self, x: &mut [V3<L>], v: &mut [V3<L>], correction: Correction);
}

/// Closures, as the tests write their constraints.
#[cfg(test)]
impl<L: Lane, F: FnMut(&mut [V3<L>], &mut [V3<L>], Correction)> Lengths<L> for F {
    fn apply(&mut self, x: &mut [V3<L>], v: &mut [V3<L>], correction: Correction) {
        self(x, v, correction)
    }
}

/// Work buffers: each contact's floor for the two phases, m, in the order of
/// [`SubstepContacts::points`].
#[derive(Default)]
pub(crate) struct CouplingScratch<L> {
    motion: Vec<L>,
    recovery: Vec<L>,
}

/// Solves the contacts of `c` together with the length constraints `lengths` (called with the
/// positions, the velocities and what is corrected) after the position update `x` (m) of a
/// substep; `v` (m/s) are the velocities that moved the points. See the module docs.
#[inline(always)]
pub(crate) fn solve<L: Lane>(
    x: &mut [V3<L>],
    v: &mut [V3<L>],
    c: &SubstepContacts<L>,
    s: &mut CouplingScratch<L>,
    lengths: &mut impl Lengths<L>,
) {
    let zero = splat::<L>(0.0);
    let dt = splat::<L>(c.dt);
    s.motion.clear();
    s.recovery.clear();
    let mut recovers = false;
    for &i in c.points {
        let (_, d) = surface_model(&x[i], &c.contact[i], c.t_end);
        let floor = d.min(zero);
        let push = c.push[i].dot(&c.push[i]).sqrt() * dt * c.free[i];
        recovers |= L::any(push.simd_gt(zero));
        s.motion.push(floor);
        s.recovery.push((floor + push).min(zero));
    }
    let inv_dt = splat::<L>(1.0 / c.dt);
    lengths.apply(x, v, Correction::Motion);
    for _ in 0..ROUNDS {
        if !project(x, Some((v, inv_dt)), c, &s.motion) {
            break;
        }
        lengths.apply(x, v, Correction::Motion);
    }
    if recovers {
        for _ in 0..ROUNDS {
            if !project(x, None, c, &s.recovery) {
                break;
            }
            lengths.apply(x, v, Correction::Recovery);
        }
    }
}

/// Moves every free contact point below its `floor` (m) onto it along the surface model's
/// normal, and its velocity by the displacement over dt where `velocity` is given (the
/// velocities and 1/dt). Returns whether any point moved by more than [`SLOP`].
#[inline(always)]
fn project<L: Lane>(
    x: &mut [V3<L>],
    mut velocity: Option<(&mut [V3<L>], L)>,
    c: &SubstepContacts<L>,
    floor: &[L],
) -> bool {
    let zero = splat::<L>(0.0);
    let slop = splat::<L>(SLOP);
    let mut moved = false;
    for (&i, &floor) in c.points.iter().zip(floor) {
        let (n, d) = surface_model(&x[i], &c.contact[i], c.t_end);
        let deficit = (floor - d).max(zero) * c.free[i];
        moved |= L::any(deficit.simd_gt(slop));
        let step = n * deficit;
        x[i] += step;
        if let Some((v, inv_dt)) = velocity.as_mut() {
            v[i] += step * *inv_dt;
        }
    }
    moved
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contacts::detect::NO_CONTACT;
    use crate::integrate::lanes::Baseline;
    use nalgebra::Vector3;

    /// The ground z = 0 under every lane, static, frictionless.
    fn ground() -> ContactLanes<Baseline> {
        ContactLanes {
            anchor: V3::splat(&Vector3::z()),
            size: splat(0.0),
            curved: splat(0.0),
            anchor_velocity: V3::default(),
            surface_velocity: V3::default(),
            friction: splat(0.0),
            found_depth: splat(0.0),
        }
    }

    fn lanes(p: &[Vector3<f32>]) -> Vec<V3<Baseline>> {
        p.iter().map(V3::splat).collect()
    }

    /// An inextensible pair of free points of equal mass: the pull back towards each other by
    /// `excess` (m) of their overlength, as a strain limit would, moving velocities by the
    /// displacement over dt for motion only.
    fn pair_limit(
        rest: f32,
        dt: f32,
    ) -> impl FnMut(&mut [V3<Baseline>], &mut [V3<Baseline>], Correction) {
        move |x, v, correction| {
            let d = (x[1] - x[0]).lane(0);
            let excess = d.norm() - rest;
            if excess <= 0.0 {
                return;
            }
            let half = V3::splat(&(d.normalize() * (0.5 * excess)));
            x[0] += half;
            x[1] -= half;
            if correction == Correction::Motion {
                let dv = half * splat(1.0 / dt);
                v[0] += dv;
                v[1] -= dv;
            }
        }
    }

    /// A rope over a rigid edge: point 0 rests on the ground and the strain limit pulls it
    /// towards point 1, which hangs below the ground's level beside it. Alone, the limit drags
    /// point 0 into the ground; solved together, point 0 ends on the ground, the segment at its
    /// length (within a round's pull), and the velocities are the displacements over dt.
    #[test]
    fn strain_limit_no_longer_pulls_a_contact_into_the_surface() {
        let dt = 1e-4f32;
        let start = [
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(0.012, 0.0, -0.004),
        ];
        let mut x = lanes(&start);
        let mut v = lanes(&[Vector3::zeros(); 2]);
        let contact = [
            ground(),
            ContactLanes {
                size: splat(NO_CONTACT),
                ..ContactLanes::default()
            },
        ];
        let c = SubstepContacts {
            points: &[0],
            contact: &contact,
            push: &[V3::default(); 2],
            free: &[splat(1.0); 2],
            t_end: splat(dt),
            dt,
        };
        solve(
            &mut x,
            &mut v,
            &c,
            &mut CouplingScratch::default(),
            &mut pair_limit(0.01, dt),
        );
        let (p0, p1) = (x[0].lane(0), x[1].lane(0));
        assert!(p0.z > -1e-5, "point 0 pulled {} m into the ground", -p0.z);
        let stretch = (p1 - p0).norm() / 0.01 - 1.0;
        assert!(stretch.abs() < 1e-3, "segment strain {stretch}");
        // Point 0 slid along the ground towards point 1 instead.
        assert!(p0.x > 1e-3);
        for (k, s) in start.iter().enumerate() {
            let moved = (x[k].lane(0) - s) / dt;
            assert!((moved - v[k].lane(0)).norm() < 1e-3 * moved.norm().max(1.0));
        }
    }

    /// A point found 2 mm inside the ground, pushed out by 0.5 mm this substep, drags its
    /// neighbour along by the strain limit: both move, but neither velocity changes, so the
    /// push-out is not handed on as motion.
    #[test]
    fn push_out_moves_neighbours_without_giving_them_velocity() {
        let dt = 1e-3f32;
        let start = [
            Vector3::new(0.0, 0.0, -0.002),
            Vector3::new(0.01, 0.0, -0.002),
        ];
        let mut x = lanes(&start);
        let v0 = [Vector3::new(0.1, 0.0, 0.0), Vector3::new(0.1, 0.0, 0.0)];
        let mut v = lanes(&v0);
        let contact = [
            ground(),
            ContactLanes {
                size: splat(NO_CONTACT),
                ..ContactLanes::default()
            },
        ];
        let push = [V3::splat(&Vector3::new(0.0, 0.0, 0.5)), V3::default()];
        let c = SubstepContacts {
            points: &[0],
            contact: &contact,
            push: &push,
            free: &[splat(1.0); 2],
            t_end: splat(dt),
            dt,
        };
        solve(
            &mut x,
            &mut v,
            &c,
            &mut CouplingScratch::default(),
            &mut pair_limit(0.01, dt),
        );
        let (p0, p1) = (x[0].lane(0), x[1].lane(0));
        // Out by the push (within what the last pull left), the segment at its length.
        assert!((p0.z - (-0.0015)).abs() < 5e-5, "z = {}", p0.z);
        assert!(((p1 - p0).norm() - 0.01).abs() < 1e-5);
        // The neighbour followed (pulled towards the lifted point by the overlength, 6 µm).
        assert!(p1.x < 0.01 - 3e-6, "the neighbour stayed at {p1:?}");
        assert_eq!(v[0].lane(0), v0[0]);
        assert_eq!(v[1].lane(0), v0[1]);
    }

    /// Kinematic points are never moved, and lanes without a contact are left alone.
    #[test]
    fn kinematic_points_and_lanes_without_contact_are_not_moved() {
        let dt = 1e-3f32;
        let below = [Vector3::new(0.0, 0.0, -0.001)];
        let mut x = lanes(&below);
        let mut v = lanes(&[Vector3::zeros()]);
        let none = [ContactLanes {
            size: splat(NO_CONTACT),
            ..ContactLanes::default()
        }];
        for (contact, free) in [(&[ground()], splat(0.0)), (&none, splat(1.0))] {
            let c = SubstepContacts {
                points: &[0],
                contact,
                push: &[V3::splat(&Vector3::new(0.0, 0.0, 1.0))],
                free: &[free],
                t_end: splat(dt),
                dt,
            };
            solve(
                &mut x,
                &mut v,
                &c,
                &mut CouplingScratch::default(),
                &mut |_: &mut [V3<Baseline>], _: &mut [V3<Baseline>], _| {},
            );
            assert_eq!(x[0].lane(0), below[0]);
            assert_eq!(v[0].lane(0), Vector3::zeros());
        }
    }
}
