//! The strain limit (`SolverSettings::max_strain`): after each substep's position update no
//! segment is longer than `(1 + max_strain) ×` its rest length (to a relative [`TOLERANCE`] of
//! 10⁻⁵), and the velocities are those that moved the points.
//!
//! # Method
//! Strain limiting after Provot 1995 ("Deformation constraints in a mass-spring model to
//! describe rigid cloth behavior"): over-stretched segments are shortened by moving their ends,
//! and the velocity change of every moved point is its displacement over the substep,
//! `Δv = Δx/dt`, as in position-based dynamics (Müller et al. 2007). Because every position
//! change of the substep (the integration and each correction) moves the velocity by the same
//! amount over `dt`, the stored velocity is exactly `(x_end − x_start)/dt` up to round-off: a
//! strand held at the limit and not moving has zero velocity, and cubic Hermite interpolation
//! between cached frames follows the path the solver took.
//!
//! The correction is the mass-weighted projection of the over-long segments onto the limit
//! (the fast projection of Goldenthal et al. 2007, see [`super::inextensible`]) restricted to the
//! **active set**, solved by Newton steps on the tridiagonal system `(G M⁻¹ Gᵀ) λ = C`
//! (inactive segments get λ = 0):
//!
//! - segments longer than the limit are constrained to `C_j = |x_{j+1} − x_j| − (1 + ε) l_j = 0`;
//! - segments that are stretched but within the limit (longer than `(1 + ε)(1 − ε) l_j`, about
//!   their rest length) are held at their present length, `C_j = 0` for this step.
//!
//! Why hold the stretched ones: shortening a segment pulls its ends in and so stretches its
//! neighbours, which on a taut strand (hair whipping round a head, every segment near the
//! limit) are themselves at the limit. With only the over-long segments in the set, each
//! iteration would push the excess one segment further along the strand and make the worst
//! segment *longer* (on the parity scene with its collider at 4 implicit substeps per frame, one
//! group's worst segment beyond its limit: 0.55 % → 1.07 % → 0.53 % → 0.46 %), so the
//! iterations nearly always run out (3.4 per call on average) and leave the excess to
//! follow-the-leader. Holding them, each step shortens the strand as a chain: 1.6 iterations per
//! call on the same run.
//! For a tridiagonal `G M⁻¹ Gᵀ` with non-positive off-diagonals (no joint folded past 90°) a
//! right-hand side `C ≥ 0` gives `λ ≥ 0`: the held segments resist being stretched by the
//! correction, never being shortened. With `ε = 0` (inextensible) the held set is empty. Impulses are equal and opposite along each segment,
//! so linear momentum is conserved and the correction only dissipates energy (an inelastic
//! constraint). Where the iterations run out before every segment is within [`TOLERANCE`] of
//! its limit, a last **follow-the-leader** pass root to tip moves far ends only (and their
//! velocities by the same displacement over dt) to guarantee the limit. Where they converge,
//! that pass does not run: it would move no point by more than the tolerance (a hundred
//! thousandth of a segment), and it costs a square root and a division per segment on every
//! call. Skipping it takes 12 % off the parity scene's strand phase with its collider (BDF2,
//! where the contacts call the limit three times a substep) and 14 % without (semi-implicit
//! Euler), 2 % off the default scene's; segments may then end the substep up to that tolerance
//! over their limit.
//!
//! Why a projection and not Gauss–Seidel sweeps (two Provot sweeps, then follow-the-leader on
//! positions only): on a long soft strand the sweeps remove little of the excess (they propagate
//! one segment per sweep), so follow-the-leader does nearly all the work, and as it does not
//! touch velocities the cached velocities of a strand hanging still at the limit read 0.25 m/s
//! (Sintel scene) to 2 m/s (60 segments of 3 mm) downward. Giving follow-the-leader's large
//! displacements to the velocities instead pumps energy into the strand (a one-sided correction
//! is not momentum-conserving: a point is yanked after its neighbour moved), which blows a
//! hanging strand up to 20 m/s; removing only the stretching rate of the far end does worse.
//! The projection leaves follow-the-leader far less to do, but not only round-off: when the
//! active set changes a lot within a substep (hair collapsing from its groom) four iterations
//! do not converge, and the follow-the-leader velocities that remain make the motion livelier
//! (see Limits). A velocity projection (`G v = 0` on the active set, as [`super::inextensible`]
//! does) does not fit either: the active set changes from substep to substep, and it leaves
//! 3–7 cm/s on a strand that does not move. The sweeps this projection replaces and the
//! variants measured beside it: `docs/design/strain-limit.md`.
//!
//! # Limits
//! Stale velocities (positions corrected, velocities not) would act as a strong numerical
//! damping; the velocities here follow the positions, so a strand held at the limit whose
//! bending springs cannot reach their rest shape (a strand combed out sideways hanging down,
//! 60 segments of 3 mm, `bend_stiffness` 0.05 N/m) keeps a small motion that air drag does not
//! remove: 2–3 cm/s at the tip at 69 substeps per frame, 1 cm/s at 1,000 (it shrinks with the
//! substep, so it is a discretisation effect, measured in the experiments behind
//! `tests/tests/velocity_consistency.rs`). A strand whose bending is satisfied, or without
//! bending, comes to rest (velocities at the f32 round-off of `Δx/dt`, ≈ 5·10⁻⁵ m/s).
//!
//! On the Sintel scene's first second (hair collapsing from its groom as the head turns) the
//! median velocity–position mismatch between frames is 0.03 m/s (0.27 m/s with stale
//! velocities), but the fastest 1 % of points move faster than with stale velocities (mismatch
//! p99 0.67 m/s against 0.47, largest 5.2 m/s against 0.85: motion 24 fps does not resolve).
//! Eight iterations lower that to p99 0.60, largest 3.3 m/s, at a cost above the sweeps';
//! follow-the-leader without velocities lowers it to p99 0.19 but brings stale velocities back
//! (4 cm/s on a still strand). Neither is used; more damping of fast bending motion is the open
//! question.

use super::inextensible::ProjectionScratch;
use super::lanes::{div_or_zero, splat, Lane, V3};

/// Newton iterations of the active-set projection per substep, at most.
const ITERATIONS: u32 = 4;

/// Relative excess `len/limit − 1` below which a segment counts as at the limit (the
/// iterations stop when every lane's segments are within it, and follow-the-leader is not
/// needed). Ten times the f32 round-off of a segment's length, which a tighter tolerance only
/// chases with wasted iterations.
const TOLERANCE: f32 = 1e-5;

/// Limits the group's segments to `ratio × rest_length` (m), moving the velocities `v` (m/s)
/// by each point's displacement over the substep (`inv_dt`, 1/s). `inv_mass` (1/kg) is 0 for
/// points that must not move.
#[inline(always)]
pub(crate) fn limit_strain<L: Lane>(
    x: &mut [V3<L>],
    v: &mut [V3<L>],
    inv_mass: &[L],
    rest_length: &[L],
    ratio: L,
    inv_dt: L,
    s: &mut ProjectionScratch<L>,
) {
    let (zero, one) = (splat::<L>(0.0), splat::<L>(1.0));
    let m = rest_length.len();
    s.fit(m);
    // Relative excess (−max_strain) above which a segment joins the active set: stretched
    // segments, longer than the limit less the allowed strain (about their rest length), are
    // held at their length while over-long ones are shortened (module docs).
    let hold_above = one - ratio;
    let mut converged = false;
    for _ in 0..ITERATIONS {
        // Active set and constraint values: over-long segments are brought to the limit,
        // stretched ones held at their length (right-hand side 0), the others are out of the
        // solve (λ = 0).
        let mut worst = zero;
        for j in 0..m {
            let d = x[j + 1] - x[j];
            let len = d.dot(&d).sqrt();
            let limit = rest_length[j] * ratio;
            let excess = len - limit;
            // A segment between two kinematic points (animated, held-out hair) cannot be
            // corrected: it stays out of the solve, whose row would be singular.
            let movable = L::select((inv_mass[j] + inv_mass[j + 1]).simd_gt(zero), one, zero);
            worst = worst.max(excess / limit * movable);
            let active = L::select(excess.simd_gt(limit * hold_above), one, zero) * movable;
            s.tangent[j] = d * div_or_zero(one, len, 1e-9);
            s.rhs[j] = excess.max(zero) * active;
            s.lambda[j] = active;
        }
        if worst.to_array().iter().all(|&e| e <= TOLERANCE) {
            // Follow-the-leader would move no end by more than the tolerance.
            converged = true;
            break;
        }
        masked_solve(s, inv_mass);
        for j in 0..m {
            let step = s.tangent[j] * s.lambda[j];
            let (near, far) = (step * inv_mass[j], step * inv_mass[j + 1]);
            x[j] += near;
            x[j + 1] -= far;
            v[j] += near * inv_dt;
            v[j + 1] -= far * inv_dt;
        }
    }
    if converged {
        return;
    }
    // Follow the leader: far ends only, for what the iterations left.
    for j in 0..m {
        let d = x[j + 1] - x[j];
        let len = d.dot(&d).sqrt();
        let excess = (len - rest_length[j] * ratio).max(zero);
        let w = inv_mass[j + 1];
        let shift = d * div_or_zero(excess * w, len * w, 0.0);
        x[j + 1] -= shift;
        v[j + 1] -= shift * inv_dt;
    }
}

/// Solves `(G M⁻¹ Gᵀ) λ = rhs` restricted to the segments whose mask (in `s.lambda` on entry:
/// 1 or 0) is set: the others are identity rows with no coupling, and `rhs` must be 0 there.
#[inline(always)]
fn masked_solve<L: Lane>(s: &mut ProjectionScratch<L>, inv_mass: &[L]) {
    let one = splat::<L>(1.0);
    let m = s.rhs.len();
    for j in 0..m {
        let active = s.lambda[j];
        s.diag[j] = (inv_mass[j] + inv_mass[j + 1]) * active + (one - active);
        s.upper[j] = if j + 1 < m {
            -(inv_mass[j + 1] * s.tangent[j].dot(&s.tangent[j + 1])) * (active * s.lambda[j + 1])
        } else {
            splat(0.0)
        };
    }
    s.thomas();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::lanes::Baseline;
    use nalgebra::Vector3;

    /// A chain whose segments are all within the limit (some compressed, one exactly at it)
    /// is left as it was, positions and velocities bit for bit.
    #[test]
    fn a_chain_within_the_limit_is_not_touched() {
        let n = 6;
        let p0: Vec<Vector3<f32>> = (0..n)
            .map(|i| Vector3::new(0.01 * i as f32, 0.002 * (i % 2) as f32, 0.0))
            .collect();
        let rest: Vec<f32> = (0..n - 1)
            .map(|j| {
                let len = (p0[j + 1] - p0[j]).norm();
                if j == 2 {
                    len / 1.01
                } else {
                    len * 1.05
                }
            })
            .collect();
        let x0: Vec<V3<Baseline>> = p0.iter().map(V3::splat).collect();
        let v0: Vec<V3<Baseline>> = (0..n)
            .map(|i| V3::splat(&Vector3::new(-0.3, 0.1 * i as f32, 0.0)))
            .collect();
        let (mut x, mut v) = (x0.clone(), v0.clone());
        let w: Vec<Baseline> = (0..n)
            .map(|i| splat(if i == 0 { 0.0 } else { 100.0 }))
            .collect();
        let rest_l: Vec<Baseline> = rest.iter().map(|&r| splat(r)).collect();
        let mut s = ProjectionScratch::default();
        limit_strain(&mut x, &mut v, &w, &rest_l, splat(1.01), splat(1e3), &mut s);
        let bits = |p: &[V3<Baseline>]| -> Vec<[u32; 3]> {
            p.iter()
                .map(|q| q.lane(0).map(f32::to_bits).into())
                .collect()
        };
        assert_eq!(bits(&x), bits(&x0));
        assert_eq!(bits(&v), bits(&v0));
    }

    /// A zig-zag chain pinned at its root, every segment stretched by 5 %, moving: after the
    /// limit of 1 %, every segment is within it, the root has not moved, and each velocity
    /// changed by exactly the point's displacement over dt.
    #[test]
    fn limit_holds_and_velocities_change_by_the_displacement() {
        let n = 12;
        let dt = 1e-3f32;
        let p0: Vec<Vector3<f32>> = (0..n)
            .map(|i| {
                let i = i as f32;
                Vector3::new(
                    0.0105 * i,
                    0.0,
                    if (i as usize).is_multiple_of(2) {
                        0.0
                    } else {
                        0.003
                    },
                )
            })
            .collect();
        let rest: Vec<f32> = (0..n - 1)
            .map(|j| (p0[j + 1] - p0[j]).norm() / 1.05)
            .collect();
        let lanes = |p: &[Vector3<f32>]| -> Vec<V3<Baseline>> { p.iter().map(V3::splat).collect() };
        let mut x = lanes(&p0);
        let v0: Vec<Vector3<f32>> = (0..n)
            .map(|i| Vector3::new(0.1 * i as f32, -0.2, 0.05))
            .collect();
        let mut v = lanes(&v0);
        let w: Vec<Baseline> = (0..n)
            .map(|i| splat(if i == 0 { 0.0 } else { 300.0 }))
            .collect();
        let rest_l: Vec<Baseline> = rest.iter().map(|&r| splat(r)).collect();
        let mut s = ProjectionScratch::default();
        limit_strain(
            &mut x,
            &mut v,
            &w,
            &rest_l,
            splat(1.01),
            splat(1.0 / dt),
            &mut s,
        );
        for j in 0..n - 1 {
            let len = (x[j + 1] - x[j]).lane(0).norm();
            assert!(
                len <= rest[j] * 1.01 * (1.0 + 1e-6),
                "segment {j}: {}",
                len / rest[j]
            );
            assert!(
                len >= rest[j] * 1.01 * (1.0 - 1e-4),
                "segment {j} over-corrected"
            );
        }
        assert_eq!(x[0].lane(0), p0[0]);
        for i in 0..n {
            let moved = (x[i].lane(0) - p0[i]) / dt;
            let dv = v[i].lane(0) - v0[i];
            assert!((moved - dv).norm() < 1e-3, "point {i}: {moved:?} vs {dv:?}");
        }
    }
}
