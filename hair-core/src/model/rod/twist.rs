//! Elastic, quasistatic twist (Bergou et al. 2008, "Discrete Elastic Rods", §"Quasistatic
//! material frame"; Bergou et al. 2010, "Discrete Viscous Threads", for the twist's gradient in
//! the positions). Replaces the geometric twist of seed 002 (Kmoch et al. 2009), which turned
//! each segment's major axis onto its bending axis and let a round section keep its rest twist:
//! that twist exerted no torque, so a coil could trade its pitch for torsion at no cost.
//!
//! Twist propagates far faster than the centreline moves (a hair's torsional waves are much
//! faster than its bending waves), so it is not integrated in time: for the current centreline
//! the twist angles `θ_j` of the segments (against the space-parallel reference frames of
//! [`super::frames`], carried from the root's ghost segment) **minimise the elastic energy**
//!
//! ```text
//! E(θ) = Σ_i E_bend,i(θ_{i−1}, θ_i) + Σ_i G J (m_i − m̄_i)² / (2 l̄_i),    m_i = θ_i − θ_{i−1}
//! ```
//!
//! (the reference twist of a space-parallel frame is zero, so the discrete twist at node `i` is
//! the difference of its segments' angles; `m̄_i` the rest twist, `l̄_i` the node's share of the
//! rest length). The bending of node `i` seen from segment `j` depends on `θ_j` alone, the twist
//! couples neighbours, so the Hessian `∂²E/∂θ²` is tridiagonal and `∂E/∂θ = 0` is solved by
//! Newton's method ([`relax`]), warm-started from the previous substep's angles. Where the
//! Hessian is not positive definite (an elliptical section bent over its stiff axis sits on a
//! maximum of its bending energy in `θ`) the step uses the twist part plus the bending's
//! curvature taken positive, at most an eighth of a turn, and a backtracking line search on the
//! energy keeps such steps (and any exact step longer than 0.1 rad) downhill; a stationary point that is not a minimum (a strand bent
//! exactly over its stiff axis: twist buckling) is left along a direction of negative curvature.
//!
//! **Boundary conditions.** The root is **clamped in twist**: the follicle holds the ghost
//! segment's material frame (`θ_ghost = 0`), so node 0's twist is `θ_0` and its bending is
//! measured in the ghost's frame on the root side (seed 002's root held only the direction and
//! left the twist free). The tip is free: no twist beyond the last segment.
//!
//! **Force.** The centreline feels the twist through the gradient of the energy at the
//! minimising `θ`, which by the envelope theorem is the partial gradient at fixed `θ` for any
//! smooth way of carrying the frames with the positions. [`super::forces`] carries each
//! segment's material frame by time-parallel transport (its own minimal rotation): the bending
//! gradient is then that of `κb` with the axes held (`κb ⟂ t`, so the axes' turn along `t` does
//! not change `κb·m`), and the twist `m_i` gains the holonomy of the two segments' turns, whose
//! gradient is `κb_i / (2|e|)` at the far nodes ([`super::forces::twisting`]). This is the same
//! force as Bergou 2008's space-parallel form (bending gradient with `−J ω (∇ψ)ᵀ`, twist energy
//! independent of the positions): at `∂E/∂θ = 0` the two differ by `Σ_j ∂E/∂θ_j ∇ψ_j = 0`.
//!
//! **Elliptical sections** bend over their major axis because the minimisation finds it cheaper
//! to twist than to bend the stiff way, against the twist stiffness `G J` and the root's clamp;
//! the rest shape's material frame ([`rest_angles`]) puts each segment's major axis on its rest
//! bending axis (seed 002: hair bends over its major axis), so a curl at rest bends the easy way.
//! A round section at rest takes the reference frame itself (no rest twist).

use super::forces::NodeRest;
use super::frames::{material, EdgeFrames, V3};
use super::stiffness::Stiffness;

/// Bending below this angle (rad) at both nodes of a segment counts as straight when the rest
/// frame is aligned: its binormals give no reliable axis.
const STRAIGHT: f64 = 1e-4;

/// Newton stops when no angle changes by more than this, rad (the error left is its square).
const TOLERANCE: f64 = 1e-10;

/// Longest step of one Newton iteration, rad (a quarter turn aligns any axis).
const LONGEST_STEP: f64 = std::f64::consts::FRAC_PI_4;

/// Most energy evaluations of one relaxation.
const MAX_EVALUATIONS: u32 = 40;

/// A full Newton step on a positive-definite Hessian is taken without a line search up to
/// this largest angle change, rad.
const TRUSTED_STEP: f64 = 0.1;

/// Rest data the twist needs per segment and node.
#[derive(Debug, Clone, Copy)]
pub struct TwistRest<'a> {
    /// Rest curvature per bending node (`0..segments`).
    pub bend: &'a [NodeRest],
    /// Rest twist `m̄_j = θ̄_j − θ̄_{j−1}` per node `j`, rad (`θ̄_{−1} = 0`: the ghost).
    pub twist: &'a [f64],
    /// Share of the rest length per bending node `l̄_i`, m.
    pub voronoi: &'a [f64],
}

/// One node's bending as seen from one segment: the binormal's components `(p, q)` in the
/// segment's reference frame `(u, v)`, the rest curvature in its material frame and the weight
/// `1/(4 l̄)` (1/m).
#[derive(Debug, Clone, Copy, Default)]
struct Side {
    p: f64,
    q: f64,
    rest: [f64; 2],
    weight: f64,
}

/// The twist of every segment: its angle and the material axes it gives (workspace: the angles
/// are also the next relaxation's starting point).
#[derive(Debug, Clone, Default)]
pub struct Twist {
    /// Twist angle per segment, rad, against its reference frame.
    pub theta: Vec<f64>,
    /// Material axes `(m1, m2)` per segment (major, minor).
    pub axes: Vec<(V3, V3)>,
    sides: Vec<[Side; 2]>,
    grad: Vec<f64>,
    bend_h: Vec<f64>,
    trial: Vec<f64>,
    trial_grad: Vec<f64>,
    trial_h: Vec<f64>,
    step: Vec<f64>,
    pivot: Vec<f64>,
}

/// What one relaxation did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Relaxation {
    /// Energy evaluations (each gives the energy, gradient and Hessian).
    pub evaluations: u32,
    /// True when the last Newton step was below the tolerance (1e-10 rad).
    pub converged: bool,
}

/// The rest shape's twist angles `θ̄_j` (rad, against the reference frames `frames` of the rest
/// shape), into `out`: for a round section none; for an elliptical one each segment's major
/// axis on the mean bending axis of its two nodes (weighted by `1/l̄`), the representative (mod
/// π) nearest the previous segment's angle, and a straight segment keeps the previous angle.
pub fn rest_angles(
    frames: &EdgeFrames,
    voronoi: &[f64],
    stiffness: &Stiffness,
    out: &mut Vec<f64>,
) {
    let n = frames.t.len();
    out.clear();
    if stiffness.major == stiffness.minor {
        out.resize(n, 0.0);
        return;
    }
    let pi = std::f64::consts::PI;
    let mut prev = 0.0;
    for j in 0..n {
        // Σ (p + i q)² / l̄ over the segment's nodes: its argument is twice the axis minimising
        // the bending over the minor axis, Σ |κb|² sin²(η − θ) / l̄.
        let (mut re, mut im, mut weight) = (0.0, 0.0, 0.0);
        for i in (j..=j + 1).filter(|&i| i < n) {
            let kb = frames.kb[i];
            let (p, q) = (kb.dot(&frames.u[j]), kb.dot(&frames.v[j]));
            let w = 1.0 / voronoi[i];
            re += w * (p * p - q * q);
            im += w * 2.0 * p * q;
            weight += w;
        }
        let straight = STRAIGHT * STRAIGHT * weight;
        if re * re + im * im > straight * straight {
            let a = 0.5 * im.atan2(re);
            prev = a + pi * ((prev - a) / pi).round();
        }
        out.push(prev);
    }
}

/// Relaxes `twist.theta` (the starting point; the rest angles are a fine start when it has the
/// wrong length, which is then reset to zero) to the minimum of bending plus twist energy for
/// the centreline of `frames`, and sets `twist.axes`. `torque` (N·m per segment, or empty) adds
/// twisting moments about the segments' axes (work `Σ T_j θ_j`).
pub fn relax(
    frames: &EdgeFrames,
    rest: &TwistRest,
    stiffness: &Stiffness,
    torque: &[f64],
    twist: &mut Twist,
) -> Relaxation {
    let n = frames.t.len();
    if twist.theta.len() != n {
        twist.theta.clear();
        twist.theta.resize(n, 0.0);
    }
    twist.sides.clear();
    for j in 0..n {
        let (u, v) = (&frames.u[j], &frames.v[j]);
        let side = |i: usize, r: [f64; 2]| Side {
            p: frames.kb[i].dot(u),
            q: frames.kb[i].dot(v),
            rest: r,
            weight: 0.25 / rest.voronoi[i],
        };
        // Segment j is side b of node j and side a of node j + 1 (none past the tip).
        let own = side(j, rest.bend[j].b);
        let next = if j + 1 < n {
            side(j + 1, rest.bend[j + 1].a)
        } else {
            Side::default()
        };
        twist.sides.push([own, next]);
    }
    for buf in [
        &mut twist.grad,
        &mut twist.bend_h,
        &mut twist.trial,
        &mut twist.trial_grad,
        &mut twist.trial_h,
        &mut twist.step,
        &mut twist.pivot,
    ] {
        buf.clear();
        buf.resize(n, 0.0);
    }
    let mut out = Relaxation::default();
    let mut energy = evaluate(
        &twist.theta,
        &twist.sides,
        rest,
        stiffness,
        torque,
        &mut twist.grad,
        &mut twist.bend_h,
    );
    out.evaluations = 1;
    while n > 0 && out.evaluations < MAX_EVALUATIONS {
        // Newton step on the exact Hessian; where it is not positive definite, on the twist
        // part plus the bending's curvature taken positive (positive definite: the root is
        // clamped), no longer than LONGEST_STEP.
        let failed = newton_step(twist, rest, stiffness, false).err();
        if failed.is_some() {
            // Positive definite: the twist part is, with the root clamped.
            let _ = newton_step(twist, rest, stiffness, true);
        }
        let mut largest = twist.step.iter().fold(0.0f64, |a, d| a.max(d.abs()));
        if !largest.is_finite() {
            break;
        }
        if largest > LONGEST_STEP {
            let shrink = LONGEST_STEP / largest;
            twist.step.iter_mut().for_each(|d| *d *= shrink);
            largest = LONGEST_STEP;
        }
        if largest < TOLERANCE {
            // A stationary point. Where the exact Hessian has a clearly negative pivot it is a
            // saddle or a maximum (an elliptical strand bent exactly over its stiff axis):
            // leave it downhill along the negative curvature; otherwise it is the minimum.
            match failed {
                Some((j, pivot)) if pivot < -1e-9 * hessian_scale(twist, rest, stiffness, j) => {
                    negative_curvature(twist, rest, stiffness, j);
                    largest = LONGEST_STEP;
                }
                _ => {
                    for (th, d) in twist.theta.iter_mut().zip(&twist.step) {
                        *th += d;
                    }
                    out.converged = true;
                    break;
                }
            }
        }
        let trusted = failed.is_none() && largest <= TRUSTED_STEP;
        let slack = 1e-12 * energy.abs();
        let mut fraction = 1.0;
        let mut accepted = false;
        while out.evaluations < MAX_EVALUATIONS {
            for ((t, th), d) in twist.trial.iter_mut().zip(&twist.theta).zip(&twist.step) {
                *t = th + fraction * d;
            }
            let e = evaluate(
                &twist.trial,
                &twist.sides,
                rest,
                stiffness,
                torque,
                &mut twist.trial_grad,
                &mut twist.trial_h,
            );
            out.evaluations += 1;
            if trusted || e <= energy + slack {
                energy = e;
                accepted = true;
                break;
            }
            fraction *= 0.5;
        }
        if !accepted {
            break;
        }
        std::mem::swap(&mut twist.theta, &mut twist.trial);
        std::mem::swap(&mut twist.grad, &mut twist.trial_grad);
        std::mem::swap(&mut twist.bend_h, &mut twist.trial_h);
    }
    twist.axes.clear();
    for j in 0..n {
        twist
            .axes
            .push(material(&frames.u[j], &frames.v[j], twist.theta[j]));
    }
    out
}

/// Energy (J) of the angles `theta` (bending of every side that depends on them, twist, minus
/// the torques' work), with its gradient (J/rad) into `grad` and the bending's share of the
/// Hessian's diagonal (J/rad²) into `bend_h`.
fn evaluate(
    theta: &[f64],
    sides: &[[Side; 2]],
    rest: &TwistRest,
    s: &Stiffness,
    torque: &[f64],
    grad: &mut [f64],
    bend_h: &mut [f64],
) -> f64 {
    let (b1, b2) = (s.major, s.minor);
    let mut energy = 0.0;
    for (j, (th, pair)) in theta.iter().zip(sides).enumerate() {
        let (sn, cs) = th.sin_cos();
        let (mut g, mut h) = (0.0, 0.0);
        for side in pair {
            // κb·m1 and κb·m2; d(κb·m1)/dθ = κb·m2, d(κb·m2)/dθ = −κb·m1.
            let k1 = side.p * cs + side.q * sn;
            let k2 = side.q * cs - side.p * sn;
            let d1 = k1 - side.rest[0];
            let d2 = k2 - side.rest[1];
            energy += side.weight * (b1 * d1 * d1 + b2 * d2 * d2);
            g += 2.0 * side.weight * (b1 * d1 * k2 - b2 * d2 * k1);
            h += 2.0
                * side.weight
                * ((b1 - b2) * (k2 * k2 - k1 * k1)
                    + b1 * side.rest[0] * k1
                    + b2 * side.rest[1] * k2);
        }
        if let Some(t) = torque.get(j) {
            energy -= t * th;
            g -= t;
        }
        grad[j] = g;
        bend_h[j] = h;
    }
    let mut prev = 0.0;
    for (i, th) in theta.iter().enumerate() {
        let w = s.twist / rest.voronoi[i];
        let d = th - prev - rest.twist[i];
        energy += 0.5 * w * d * d;
        grad[i] += w * d;
        if i > 0 {
            grad[i - 1] -= w * d;
        }
        prev = *th;
    }
    energy
}

/// Solves `H step = −grad` for the tridiagonal Hessian (twist part plus `bend_h`, or with
/// `modified` the bending's curvature taken positive) by an `L D Lᵀ` factorisation. The exact
/// Hessian fails at the first pivot `j` that is not positive: `Err((j, pivot))`, the pivots
/// before it kept (see [`negative_curvature`]), the step not to be used.
fn newton_step(
    twist: &mut Twist,
    rest: &TwistRest,
    s: &Stiffness,
    modified: bool,
) -> Result<(), (usize, f64)> {
    let n = twist.theta.len();
    let w = |i: usize| {
        if i < n {
            s.twist / rest.voronoi[i]
        } else {
            0.0
        }
    };
    // Forward: pivots d_j and the solution of L y = −grad in `step`.
    let mut prev_pivot = 0.0;
    let mut prev_y = 0.0;
    for j in 0..n {
        let bend = if modified {
            twist.bend_h[j].abs()
        } else {
            twist.bend_h[j]
        };
        let diag = w(j) + w(j + 1) + bend;
        // Off-diagonal H_{j−1,j} = −w_j.
        let (pivot, y) = if j == 0 {
            (diag, -twist.grad[0])
        } else {
            let l = -w(j) / prev_pivot;
            (diag + l * w(j), -twist.grad[j] - l * prev_y)
        };
        let floor = if modified {
            1e-12 * (diag.abs() + s.minor / rest.voronoi[j])
        } else {
            0.0
        };
        // NaN counts as not positive.
        if pivot > floor {
            twist.pivot[j] = pivot;
        } else if modified {
            twist.pivot[j] = floor.max(f64::MIN_POSITIVE);
        } else {
            return Err((j, pivot));
        }
        twist.step[j] = y;
        prev_pivot = twist.pivot[j];
        prev_y = y;
    }
    // Backward: D Lᵀ step = y.
    for j in (0..n).rev() {
        let mut x = twist.step[j] / twist.pivot[j];
        if j + 1 < n {
            // Lᵀ_{j,j+1} = −w_{j+1} / d_j.
            x += w(j + 1) / twist.pivot[j] * twist.step[j + 1];
        }
        twist.step[j] = x;
    }
    Ok(())
}

/// Size of the Hessian's diagonal at segment `j`, J/rad² (what a pivot is small against).
fn hessian_scale(twist: &Twist, rest: &TwistRest, s: &Stiffness, j: usize) -> f64 {
    let w = |i: usize| rest.voronoi.get(i).map_or(0.0, |l| s.twist / l);
    w(j) + if j + 1 < twist.theta.len() {
        w(j + 1)
    } else {
        0.0
    } + twist.bend_h[j].abs()
}

/// A direction of negative curvature of the exact Hessian whose factorisation failed at pivot
/// `j` (its `zᵀ H z` is that pivot): `Lᵀ z = e_j`, into `twist.step`, downhill (`grad·z ≤ 0`)
/// and scaled to a largest angle of [`LONGEST_STEP`].
fn negative_curvature(twist: &mut Twist, rest: &TwistRest, s: &Stiffness, j: usize) {
    let step = &mut twist.step;
    step.iter_mut().for_each(|z| *z = 0.0);
    step[j] = 1.0;
    for k in (0..j).rev() {
        // Lᵀ_{k,k+1} = −w_{k+1} / d_k.
        step[k] = s.twist / rest.voronoi[k + 1] / twist.pivot[k] * step[k + 1];
    }
    let slope: f64 = step.iter().zip(&twist.grad).map(|(z, g)| z * g).sum();
    let largest = step.iter().fold(0.0f64, |a, z| a.max(z.abs()));
    let scale = if slope > 0.0 { -1.0 } else { 1.0 } * LONGEST_STEP / largest;
    step.iter_mut().for_each(|z| *z *= scale);
}

/// Largest bending over the minor axis relative to the bending over the major axis, over the
/// interior nodes `from..segments`: `max |κb·m2| / max |κb|` on both sides of each node (0 for
/// a straight strand). Near 0 when every segment bends over its major axis.
pub fn minor_axis_bending(frames: &EdgeFrames, twist: &Twist, from: usize) -> f64 {
    let n = frames.t.len();
    let (mut minor, mut total) = (0.0f64, 0.0f64);
    for i in from.max(1)..n {
        let kb: V3 = frames.kb[i];
        for j in [i - 1, i] {
            minor = minor.max(kb.dot(&twist.axes[j].1).abs());
        }
        total = total.max(kb.norm());
    }
    if total > 0.0 {
        minor / total
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::super::frames::Ghost;
    use super::*;

    fn frames_of(x: &[V3], ghost: &Ghost) -> EdgeFrames {
        let mut frames = EdgeFrames::default();
        frames.update(x, ghost);
        frames
    }

    #[test]
    fn a_straight_rod_twisted_at_the_tip_takes_a_uniform_twist() {
        // Root clamped, a moment T about the axis on the last segment: the twist per length is
        // T / G J everywhere, so the angle at the centre of segment j is T (j + ½) l / G J
        // (node 0 sits at the root, half a segment before segment 0's centre). Start from an
        // arbitrary, uneven twist: the relaxation must forget it.
        let n = 12;
        let l = 0.02;
        let x: Vec<V3> = (0..=n).map(|i| V3::new(0.0, 0.0, l * i as f64)).collect();
        let ghost = Ghost {
            t: V3::z(),
            u: V3::x(),
            length: l,
        };
        let frames = frames_of(&x, &ghost);
        let bend = vec![NodeRest::default(); n];
        let rest_twist = vec![0.0; n];
        let mut voronoi = vec![l; n];
        voronoi[0] = 0.5 * l;
        let rest = TwistRest {
            bend: &bend,
            twist: &rest_twist,
            voronoi: &voronoi,
        };
        for s in [
            Stiffness::isotropic(2e-3, 1.5e-3),
            Stiffness {
                major: 1e-3,
                minor: 4e-3,
                twist: 1.5e-3,
            },
        ] {
            let t = 2e-4;
            let mut torque = vec![0.0; n];
            torque[n - 1] = t;
            let mut twist = Twist {
                theta: (0..n).map(|j| (j as f64 * 1.7).sin()).collect(),
                ..Twist::default()
            };
            let r = relax(&frames, &rest, &s, &torque, &mut twist);
            assert!(r.converged, "{r:?}");
            for (j, th) in twist.theta.iter().enumerate() {
                let want = t * (j as f64 + 0.5) * l / s.twist;
                assert!(
                    (th - want).abs() < 1e-12,
                    "segment {j}: {th} against {want}"
                );
            }
        }
    }

    #[test]
    fn an_elliptical_strand_twists_its_major_axis_onto_its_bend() {
        // Straight along x for two segments, then a planar arc in the x–y plane (binormal z);
        // the ghost's u is y, so at θ = 0 the arc bends over the minor axis (stiff). With a
        // soft twist the relaxation turns the arc's segments a quarter turn, from any start;
        // with a stiff twist it cannot turn far from the clamped root.
        let x: Vec<V3> = (0..12)
            .map(|i| {
                let a = 0.25 * (i as f64 - 2.0).max(0.0);
                let s = 0.2 * (i as f64).min(2.0);
                V3::new(s + a.sin(), 1.0 - a.cos(), 0.0)
            })
            .collect();
        let ghost = Ghost {
            t: V3::x(),
            u: V3::y(),
            length: 0.2,
        };
        let frames = frames_of(&x, &ghost);
        let n = frames.t.len();
        let bend = vec![NodeRest::default(); n];
        let rest_twist = vec![0.0; n];
        let voronoi = vec![0.2; n];
        let rest = TwistRest {
            bend: &bend,
            twist: &rest_twist,
            voronoi: &voronoi,
        };
        let soft = Stiffness {
            major: 1.0,
            minor: 4.0,
            twist: 1e-5,
        };
        for start in [0.01, -0.02, 1.0] {
            let mut twist = Twist {
                theta: vec![start; n],
                ..Twist::default()
            };
            let r = relax(&frames, &rest, &soft, &[], &mut twist);
            assert!(r.converged, "{r:?}");
            let minor = minor_axis_bending(&frames, &twist, 4);
            assert!(minor < 0.01, "start {start}: minor-axis bending {minor}");
        }
        let stiff = Stiffness { twist: 1e3, ..soft };
        let mut twist = Twist::default();
        relax(&frames, &rest, &stiff, &[], &mut twist);
        assert!(
            twist.theta.iter().all(|t| t.abs() < 0.01),
            "{:?}",
            twist.theta
        );
    }
}
