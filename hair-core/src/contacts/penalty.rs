//! The contact response in the force substeps, after Choe et al. 2005, on eight strands at once
//! (lanes = strands, like the rest of the kernel).
//!
//! Within a collision step the collider near a contact is modelled by the contact's surface
//! element moving with the collider: either its tangent **plane**, moving along its normal with
//! the surface velocity `v_s` at the contact, `d(x, t) = n·x + c − (n·v_s)·t`, or, where the
//! surface is curved, a **sphere** of its smallest curvature tangent at the contact,
//! `d(x, t) = ±(|x − C − v_C t| − ρ)` (centre `C` moving with the collider's material point there,
//! `v_C`, so a spinning ball stands still and a flying one flies; radius `ρ` grown by thickness
//! and hair radius; `+` on convex, `−` on concave surfaces), whose normal turns as the point
//! slides. `d` is the signed distance of the point's sphere from the thickened
//! surface (`t` from the step's start, `c`, `C`, `ρ` from detection). In substep `k`, after the
//! velocity update and the damping sub-loop and before the position update, with
//! `d̃ = d(x_k, t_{k+1})` the distance at the substep's end if the point stayed put and `n` the
//! model's normal at `x_k`:
//!
//! - the normal velocity that brings the point exactly onto the surface at `t_{k+1}` is
//!   `v* = −d̃/dt`. A point whose normal velocity `v_n = n·v` is below `v*` (it would end up
//!   inside) is in contact; any other point is left alone. A point approaching from outside thus stops
//!   exactly on the surface within the substep;
//! - a contacting point is *moved* by `v*·dt` along `n` (so it ends on the surface, also when it
//!   started inside), but the normal velocity it *keeps* is `min(v*, max(v_n, n·v_s))`: no more
//!   than it needs to reach the surface, and never outward faster than the surface itself moves
//!   unless it already was. The push-out of a penetrating point is thus a position correction
//!   that leaves no outward velocity behind: no bounce and no ejection however deep the point
//!   started;
//! - the push-out removes at once whatever penetration the step itself made, and the depth the
//!   point already had at detection (`found_depth`) at most at `ContactSettings::max_push_speed`:
//!   `push = min(needed, max_push + max(0, needed − found_depth/dt))` in velocity units. Hair
//!   found deep inside (it started there, a collider was teleported) is eased out over several
//!   substeps instead of being torn apart, but depth a large step makes after detection is
//!   corrected within the substep, as a small step's contact would have prevented it. On the
//!   parity scene's hair at one BDF2 substep per frame such depth comes from the BDF2 substep
//!   (up to 93 mm; the backward Euler third before it makes under 1 mm), whose start
//!   extrapolates the previous substep's motion (`integrate::implicit`) and so carries on an
//!   approach that contact had stopped. Capping that too leaves tips 1–7 cm inside the head;
//!   with the found depth held apart the deepest point is 1.9 mm, as at 18 semi-implicit
//!   substeps;
//! - friction: with `Δ = v_n' − v_n ≥ 0` the normal velocity change kept, the tangential velocity
//!   relative to the surface, `v_t`, shrinks by at most `μ Δ` (Coulomb: the friction impulse is at
//!   most μ times the normal impulse), stopping at 0 (static friction) and never reversing.
//!
//! **Velocities and positions.** Everywhere else in the substep the stored velocity is the one
//! that moved the point (semi-implicit Euler, and the strain limit moves velocities by its
//! displacements over dt, see `integrate::strain_limit`). The push-out is the one deliberate
//! exception: storing its displacement over dt as velocity would launch a point found 5 mm
//! inside at 5 mm/dt outward — at 0.5 ms substeps, 10 m/s, exactly the bounce Choe et al.
//! exclude — and the next substep would see a point leaving the surface and let it fly. So the
//! push is a position correction of an earlier error (hair found inside), not motion: the
//! velocity–position mismatch it leaves is what the push moves over dt in the substeps in which
//! a point is pushed — at most `max_push_speed` for depth found at detection — and zero for
//! points that approach or rest on the surface (for them the push is 0 and the kept velocity is
//! exactly the one that lands them on it).
//!
//! This is a velocity-level penalty: it is the limit of Choe et al.'s penalty spring stiff enough
//! to stop the penetrating velocity in one substep, applied as the impulse it would deliver, so it
//! adds no stiffness to the stability bound.

use crate::integrate::lanes::{div_or_zero, splat, Baseline, Lane, V3};

/// One step's contact data of a point, in lanes.
#[derive(Clone, Copy, Default)]
pub(crate) struct ContactLanes<L = Baseline> {
    /// Plane: outward unit normal (0 for points without a contact). Curved: the sphere's centre
    /// at the step's start, m.
    pub anchor: V3<L>,
    /// Plane: offset `c`, m. Curved: the radius the point's centre keeps to, m, positive to stay
    /// outside the sphere (convex surface), negative to stay inside it (concave).
    pub size: L,
    /// 1 where the contact is curved, 0 where it is a plane.
    pub curved: L,
    /// Velocity of the model: the collider's velocity at the sphere's centre (curved) or at the
    /// contact (plane; only its normal part matters), m/s.
    pub anchor_velocity: V3<L>,
    /// Surface velocity `v_s` at the contact, for friction, m/s.
    pub surface_velocity: V3<L>,
    /// Friction coefficient μ.
    pub friction: L,
    /// Depth (m, ≥ 0) the point was inside at detection: the part of a push-out held to the
    /// push speed.
    pub found_depth: L,
}

/// Applies the contact response to velocity `v` of a point at `x` for a substep ending `t_end`
/// (s, from the step's start). Returns the extra velocity (m/s, along the normal) the position
/// update must add so the point lands on the surface — of which the depth found at detection
/// (`c.found_depth`) is covered at most at `max_push` m/s; the velocity kept is updated in place.
#[inline(always)]
pub(crate) fn respond<L: Lane>(
    v: &mut V3<L>,
    x: &V3<L>,
    c: &ContactLanes<L>,
    t_end: L,
    inv_dt: L,
    max_push: L,
) -> V3<L> {
    let (zero, one) = (splat::<L>(0.0), splat::<L>(1.0));
    let (n, d_end) = surface_model(x, c, t_end);
    let vn = n.dot(v);
    let v_target = -d_end * inv_dt;
    let touching = vn.simd_lt(v_target);
    if !L::any(touching) {
        return V3::default();
    }
    let vn_surface = n.dot(&c.anchor_velocity);
    let vn_kept = v_target.min(vn.max(vn_surface));
    let dv = vn_kept - vn;
    // Friction on the velocity relative to the surface, tangential part.
    let rel = *v - c.surface_velocity;
    let rel_t = rel - n * n.dot(&rel);
    let speed_t = rel_t.dot(&rel_t).sqrt();
    let cut = div_or_zero(c.friction * dv, speed_t, 1e-12).min(one);
    let after = *v + n * dv - rel_t * cut;
    *v = V3::select(touching, &after, v);
    // The push: all of the penetration the step made, and the depth found at detection at most
    // at the push speed (see the module docs).
    let needed = v_target - vn_kept;
    let allowed = max_push + (needed - c.found_depth * inv_dt).max(zero);
    n * L::select(touching, needed.min(allowed), zero)
}

/// The contact's surface model at time `t_end` (s, from the step's start) seen from a point at
/// `x` (m): the model's outward unit normal there and the signed distance of the point's sphere
/// from the thickened surface, m (negative inside). Exact along the normal: moving the point by
/// `δ n` changes the distance by `δ` (plane, and sphere radially). Lanes without a contact get
/// a distance of about [`super::detect::NO_CONTACT`].
#[inline(always)]
pub(crate) fn surface_model<L: Lane>(x: &V3<L>, c: &ContactLanes<L>, t_end: L) -> (V3<L>, L) {
    let (zero, one) = (splat::<L>(0.0), splat::<L>(1.0));
    // The plane model, and where any lane is curved the sphere model, selected per lane.
    let plane_d = c.anchor.dot(x) + c.size - c.anchor.dot(&c.anchor_velocity) * t_end;
    let curved = c.curved.simd_gt(zero);
    if L::any(curved) {
        let w = *x - (c.anchor + c.anchor_velocity * t_end);
        let len = w.dot(&w).sqrt();
        let side = L::select(c.size.simd_lt(zero), -one, one);
        let sphere_n = w * div_or_zero(side, len, 1e-12);
        let sphere_d = (len - c.size.abs()) * side;
        (
            V3::select(curved, &sphere_n, &c.anchor),
            L::select(curved, sphere_d, plane_d),
        )
    } else {
        (c.anchor, plane_d)
    }
}

#[cfg(test)]
mod tests {
    use super::{respond, Baseline, ContactLanes, V3};
    use nalgebra::Vector3;

    /// `f` in every lane of the baseline lane type the tests use.
    fn splat(f: f32) -> Baseline {
        Baseline::splat(f)
    }

    /// The ground plane z = 0 (offset 0), static, friction μ.
    fn ground(mu: f32) -> ContactLanes {
        ContactLanes {
            anchor: V3::splat(&Vector3::z()),
            size: splat(0.0),
            curved: splat(0.0),
            anchor_velocity: V3::default(),
            surface_velocity: V3::default(),
            friction: splat(mu),
            found_depth: splat(0.0),
        }
    }

    #[test]
    fn approaching_point_lands_exactly_on_the_surface() {
        let dt = 1e-3f32;
        let c = ground(0.0);
        let x = V3::splat(&Vector3::new(0.0, 0.0, 0.5e-3));
        let mut v = V3::splat(&Vector3::new(0.3, 0.0, -2.0));
        let push = respond(&mut v, &x, &c, splat(dt), splat(1.0 / dt), splat(1e9));
        let z_end = x.z + (v.z + push.z) * splat(dt);
        assert!(z_end.to_array()[0].abs() < 1e-7, "{:?}", z_end);
        // Kept normal velocity: exactly what reaches the surface (−0.5 m/s), no outward part;
        // tangential velocity untouched without friction.
        assert!((v.z.to_array()[0] + 0.5).abs() < 1e-5);
        assert_eq!(push.z.to_array()[0], 0.0);
        assert_eq!(v.x.to_array()[0], 0.3);
    }

    #[test]
    fn point_inside_is_moved_out_without_outward_velocity() {
        let dt = 1e-3f32;
        let c = ground(0.0);
        let x = V3::splat(&Vector3::new(0.0, 0.0, -0.05));
        let mut v = V3::splat(&Vector3::new(0.0, 0.0, -1.0));
        let push = respond(&mut v, &x, &c, splat(dt), splat(1.0 / dt), splat(1e9));
        let z_end = x.z + (v.z + push.z) * splat(dt);
        assert!(z_end.to_array()[0].abs() < 1e-6);
        assert_eq!(
            v.z.to_array()[0],
            0.0,
            "no velocity is kept from the push-out"
        );
    }

    /// A point 50 mm under the ground moving down at 1 m/s, found `found` m deep at detection,
    /// answered over a 1 ms substep with a push speed of 2 m/s: the push (m/s), the normal
    /// velocity kept (m/s) and where the point ends (m).
    fn deep_point(found: f32) -> (f32, f32, f32) {
        let dt = 1e-3f32;
        let x = V3::splat(&Vector3::new(0.0, 0.0, -0.05));
        let mut v = V3::splat(&Vector3::new(0.0, 0.0, -1.0));
        let c = ContactLanes {
            found_depth: splat(found),
            ..ground(0.0)
        };
        let push = respond(&mut v, &x, &c, splat(dt), splat(1.0 / dt), splat(2.0));
        let z_end = x.z + (v.z + push.z) * splat(dt);
        (push.z.to_array()[0], v.z.to_array()[0], z_end.to_array()[0])
    }

    #[test]
    fn depth_found_at_detection_is_pushed_out_at_most_at_the_push_speed() {
        let (push, kept, _) = deep_point(0.05);
        assert_eq!(push, 2.0);
        assert_eq!(kept, 0.0);
    }

    #[test]
    fn penetration_made_within_the_step_is_removed_at_once() {
        // Found 10 mm inside at detection, now 50 mm inside (a large step carried it 40 mm
        // deeper): the 40 mm go in this substep, the 10 mm found at the push speed (2 mm here).
        let (_, kept, z_end) = deep_point(0.01);
        assert!((z_end + 0.008).abs() < 1e-6, "{z_end}");
        assert_eq!(kept, 0.0);
        // Found outside: all of it goes.
        let (_, _, z_end) = deep_point(0.0);
        assert!(z_end.abs() < 1e-6, "{z_end}");
    }

    #[test]
    fn leaving_point_is_left_alone() {
        let dt = 1e-3f32;
        let c = ground(0.5);
        let x = V3::splat(&Vector3::new(0.0, 0.0, 1e-3));
        let before = V3::splat(&Vector3::new(0.4, 0.0, 0.2));
        let mut v = before;
        let push = respond(&mut v, &x, &c, splat(dt), splat(1.0 / dt), splat(1e9));
        assert_eq!(v, before);
        assert_eq!(push.z.to_array()[0], 0.0);
    }

    #[test]
    fn friction_takes_at_most_mu_times_the_normal_change() {
        let dt = 1e-3f32;
        let x = V3::splat(&Vector3::zeros());
        // Resting on the ground, pressed in by 1 m/s, sliding at 2 m/s: μ = 0.5 takes 0.5 m/s.
        let mut v = V3::splat(&Vector3::new(2.0, 0.0, -1.0));
        respond(
            &mut v,
            &x,
            &ground(0.5),
            splat(dt),
            splat(1.0 / dt),
            splat(1e9),
        );
        assert!((v.x.to_array()[0] - 1.5).abs() < 1e-6);
        assert_eq!(v.z.to_array()[0], 0.0);
        // μ = 5 would take 5 m/s: it stops the sliding and does not reverse it.
        let mut v = V3::splat(&Vector3::new(2.0, 0.0, -1.0));
        respond(
            &mut v,
            &x,
            &ground(5.0),
            splat(dt),
            splat(1.0 / dt),
            splat(1e9),
        );
        assert!(v.x.to_array()[0].abs() < 1e-6);
    }

    #[test]
    fn moving_surface_carries_the_point_and_drags_it_along() {
        let dt = 1e-3f32;
        // The ground rising at 1 m/s and sliding along x at 3 m/s; the point rests on it.
        let c = ContactLanes {
            anchor_velocity: V3::splat(&Vector3::new(3.0, 0.0, 1.0)),
            surface_velocity: V3::splat(&Vector3::new(3.0, 0.0, 1.0)),
            ..ground(10.0)
        };
        let x = V3::splat(&Vector3::zeros());
        let mut v = V3::splat(&Vector3::zeros());
        let push = respond(&mut v, &x, &c, splat(dt), splat(1.0 / dt), splat(1e9));
        // Lands on the surface at t = dt (z = 1 mm), moving up with it and along with it.
        let z_end = (v.z + push.z) * splat(dt);
        assert!((z_end.to_array()[0] - 1e-3).abs() < 1e-7);
        assert!((v.z.to_array()[0] - 1.0).abs() < 1e-6);
        assert!((v.x.to_array()[0] - 3.0).abs() < 1e-5);
    }

    #[test]
    fn point_sliding_over_a_sphere_follows_its_curve() {
        // Resting on top of a sphere of radius 0.1 (centre at the origin, hair centre kept at
        // 0.1) and sliding along x at 1 m/s: over 100 substeps of 0.1 ms it stays on the sphere,
        // where the tangent plane would have let it rise by s²/2ρ = 0.5 mm.
        let dt = 1e-4f32;
        let c = ContactLanes {
            anchor: V3::default(),
            size: splat(0.1),
            curved: splat(1.0),
            anchor_velocity: V3::default(),
            surface_velocity: V3::default(),
            friction: splat(0.0),
            found_depth: splat(0.0),
        };
        let mut x = V3::splat(&Vector3::new(0.0, 0.0, 0.1));
        let mut v = V3::splat(&Vector3::new(1.0, 0.0, 0.0));
        let g = V3::splat(&Vector3::new(0.0, 0.0, -9.81));
        for k in 0..100 {
            v += g * splat(dt);
            let push = respond(
                &mut v,
                &x,
                &c,
                splat((k + 1) as f32 * dt),
                splat(1.0 / dt),
                splat(1e9),
            );
            x += (v + push) * splat(dt);
        }
        let r = x.dot(&x).sqrt().to_array()[0];
        assert!((r - 0.1).abs() < 2e-5, "|x| = {r}");
        assert!(x.x.to_array()[0] > 0.009);
    }

    #[test]
    fn concave_contact_keeps_the_point_inside_its_sphere() {
        // Inside a bowl of radius 0.1 (centre at the origin), moving outwards at 2 m/s from
        // 0.5 mm short of the wall: it stops on the wall.
        let dt = 1e-3f32;
        let c = ContactLanes {
            anchor: V3::default(),
            size: splat(-0.1),
            curved: splat(1.0),
            anchor_velocity: V3::default(),
            surface_velocity: V3::default(),
            friction: splat(0.0),
            found_depth: splat(0.0),
        };
        let x = V3::splat(&Vector3::new(0.0995, 0.0, 0.0));
        let mut v = V3::splat(&Vector3::new(2.0, 0.0, 0.0));
        let push = respond(&mut v, &x, &c, splat(dt), splat(1.0 / dt), splat(1e9));
        let end = (x.x + (v.x + push.x) * splat(dt)).to_array()[0];
        assert!((end - 0.1).abs() < 1e-6, "{end}");
        assert!(v.x.to_array()[0] <= 0.5 + 1e-4);
    }

    #[test]
    fn points_without_contact_are_untouched() {
        let c = ContactLanes {
            size: splat(super::super::detect::NO_CONTACT),
            ..ContactLanes::default()
        };
        let x = V3::splat(&Vector3::new(1.0, 2.0, 3.0));
        let before = V3::splat(&Vector3::new(-100.0, 5.0, 7.0));
        let mut v = before;
        let push = respond(&mut v, &x, &c, splat(1e-2), splat(1e6), splat(1.0));
        assert_eq!(v, before);
        assert_eq!(push.z.to_array()[0], 0.0);
    }
}
