//! Bending and twisting forces of the discrete rod (Bergou et al. 2008), with the elliptical
//! cross-section's two bending stiffnesses.
//!
//! Node `i` (joining segment `i − 1`, or the ghost for `i = 0`, and segment `i`) stores bending
//! energy measured in the material frame of each of its two segments and averaged (node 0 in the
//! ghost's frame on the root side: the follicle clamps the root in direction and in twist, see
//! [`super::twist`]):
//!
//! ```text
//! E_i = 1/(4 l̄_i) Σ_{j ∈ {i−1, i}} [ E I₁ (κb_i·m1_j − κ̄1)² + E I₂ (κb_i·m2_j − κ̄2)² ]
//! ```
//!
//! with `κ̄` the rest curvature in that frame and `l̄_i` the node's share of the rest length
//! (half of each adjacent segment; node 0 only gets half of segment 0, so a uniform moment turns
//! the first segment by half the angle of the others and the nodes lie on the exact arc). For a
//! round section and a turn `φ` this is `E I (2 tan(φ/2))² / (2 l̄)`, the discrete
//! `½ ∫ E I κ² ds`. The twist energy of node `i` is `G J (m_i − m̄_i)² / (2 l̄_i)`.
//!
//! Forces are `−dE/dx` at the quasistatic twist ([`super::twist::relax`]: `∂E/∂θ = 0`), which is
//! the partial gradient with each segment's material frame carried by time-parallel transport
//! (the envelope theorem, see [`super::twist`]):
//! - **bending** ([`bending`]): the exact derivative of `κb`, with the axes held (their turn with
//!   the tangent is along `t`, and `κb ⟂ t`);
//! - **twisting** ([`twisting`]): the time-parallel frames' holonomy changes the twist,
//!   `∂m_i/∂e_{i−1} = ∂m_i/∂e_i = κb_i / (2|e|)` (Bergou et al. 2010), so
//!   `∇_{i−1} m_i = −κb_i/(2|e_{i−1}|)`, `∇_{i+1} m_i = κb_i/(2|e_i|)`, `∇_i m_i = −(both)` and the
//!   force is `−Σ_i G J (m_i − m̄_i)/l̄_i ∇m_i`.
//!
//! Their sum is the gradient of the energy with the twist re-minimised (a unit test of
//! [`super::strand`] checks it against finite differences), so an undamped strand conserves its
//! energy up to the integrator's bounded oscillation, in or out of its plane.

use super::frames::{EdgeFrames, Ghost, FOLD_CAP, V3};
use super::stiffness::Stiffness;

/// Rest curvature of a node, in the material frames of its two segments: `[κ̄1, κ̄2]` on side
/// `a` (segment `i − 1`; segment 0 for node 0) and side `b` (segment `i`), dimensionless.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct NodeRest {
    /// Rest curvature in the frame of segment `i − 1` (segment 0 for node 0).
    pub a: [f64; 2],
    /// Rest curvature in the frame of segment `i`.
    pub b: [f64; 2],
}

/// Bending energy (J) of one node seen from one segment's material axes `(m1, m2)`, with
/// weight `1/(4 l̄)` (`voronoi` = `l̄`, m).
#[inline]
pub fn side_energy(
    kb: &V3,
    m1: &V3,
    m2: &V3,
    rest: [f64; 2],
    voronoi: f64,
    stiffness: &Stiffness,
) -> f64 {
    let d1 = kb.dot(m1) - rest[0];
    let d2 = kb.dot(m2) - rest[1];
    (stiffness.major * d1 * d1 + stiffness.minor * d2 * d2) / (4.0 * voronoi)
}

/// The material axes of both sides of node `i`, from the axes per segment. Node 0 is measured
/// in the ghost's material frame (twist 0: the follicle holds it) on the root side.
#[inline]
pub fn node_axes(i: usize, axes: &[(V3, V3)], ghost: &Ghost) -> [(V3, V3); 2] {
    let a = if i == 0 {
        (ghost.u, ghost.v())
    } else {
        axes[i - 1]
    };
    [a, axes[i]]
}

/// Adds the bending forces (N) of every node to `force` and returns the bending energy (J).
/// `x` are the node positions (m), `frames` their frames (updated for `x`), `axes` the material
/// axes `(m1, m2)` per segment, `rest`/`voronoi` per bending node (`0..segments`).
#[allow(clippy::too_many_arguments)]
pub fn bending(
    x: &[V3],
    frames: &EdgeFrames,
    ghost: &Ghost,
    axes: &[(V3, V3)],
    rest: &[NodeRest],
    voronoi: &[f64],
    stiffness: &Stiffness,
    force: &mut [V3],
) -> f64 {
    let n = x.len() - 1;
    let mut energy = 0.0;
    for i in 0..n {
        let kb = frames.kb[i];
        let lbar = voronoi[i];
        let sides = node_axes(i, axes, ghost);
        let mut g = V3::zeros();
        for ((m1, m2), r) in sides.iter().zip([rest[i].a, rest[i].b]) {
            let d1 = kb.dot(m1) - r[0];
            let d2 = kb.dot(m2) - r[1];
            g += (m1 * (stiffness.major * d1) + m2 * (stiffness.minor * d2)) / (2.0 * lbar);
            energy += side_energy(&kb, m1, m2, r, lbar, stiffness);
        }
        let e_a = if i == 0 {
            ghost.t * ghost.length
        } else {
            x[i] - x[i - 1]
        };
        let e_b = x[i + 1] - x[i];
        let (la, lb) = (e_a.norm(), e_b.norm());
        let d = (la * lb + e_a.dot(&e_b)).max(FOLD_CAP * la * lb);
        let kg = kb.dot(&g);
        let d_ea = (e_b.cross(&g) * 2.0 - (e_a * (lb / la) + e_b) * kg) / d;
        let d_eb = (e_a.cross(&g) * -2.0 - (e_b * (la / lb) + e_a) * kg) / d;
        if i > 0 {
            force[i - 1] += d_ea;
            force[i] -= d_ea;
        }
        force[i] += d_eb;
        force[i + 1] -= d_eb;
    }
    energy
}

/// Adds the twisting forces (N) of every node to `force` and returns the twist energy (J):
/// `theta` the twist angles per segment (rad, the quasistatic ones), `rest_twist` and `voronoi`
/// per node (rad, m); the root's ghost has twist 0 and is fixed, so node 0's twist depends on
/// segment 0 alone.
pub fn twisting(
    frames: &EdgeFrames,
    theta: &[f64],
    rest_twist: &[f64],
    voronoi: &[f64],
    stiffness: &Stiffness,
    force: &mut [V3],
) -> f64 {
    let mut energy = 0.0;
    let mut prev = 0.0;
    for (i, &th) in theta.iter().enumerate() {
        let d = th - prev - rest_twist[i];
        prev = th;
        let torque = stiffness.twist * d / voronoi[i];
        energy += 0.5 * torque * d;
        let kb = frames.kb[i];
        // ∇_{i+1} m_i = κb/(2|e_i|) from segment i; −(it) at node i.
        let g_next = kb * (0.5 / frames.length[i]);
        force[i + 1] -= g_next * torque;
        force[i] += g_next * torque;
        if i > 0 {
            // ∇_{i−1} m_i = −κb/(2|e_{i−1}|) from segment i − 1; −(it) at node i.
            let g_prev = kb * (0.5 / frames.length[i - 1]);
            force[i - 1] += g_prev * torque;
            force[i] -= g_prev * torque;
        }
    }
    energy
}

#[cfg(test)]
mod tests {
    use super::super::frames::{curvature_binormal, material, perpendicular};
    use super::*;

    /// Bending energy with the material axes frozen at `axes` and κb recomputed from `x`.
    fn frozen_energy(
        x: &[V3],
        ghost: &Ghost,
        axes: &[[(V3, V3); 2]],
        rest: &[NodeRest],
        voronoi: &[f64],
        s: &Stiffness,
    ) -> f64 {
        let n = x.len() - 1;
        (0..n)
            .map(|i| {
                let ta = if i == 0 {
                    ghost.t
                } else {
                    (x[i] - x[i - 1]).normalize()
                };
                let tb = (x[i + 1] - x[i]).normalize();
                let kb = curvature_binormal(&ta, &tb);
                side_energy(&kb, &axes[i][0].0, &axes[i][0].1, rest[i].a, voronoi[i], s)
                    + side_energy(&kb, &axes[i][1].0, &axes[i][1].1, rest[i].b, voronoi[i], s)
            })
            .sum()
    }

    #[test]
    fn forces_are_the_gradient_of_the_frozen_frame_energy() {
        let x: Vec<V3> = (0..7)
            .map(|i| {
                let a = 0.5 * i as f64;
                V3::new(0.3 * a.sin(), 0.2 * a.cos() - 0.2, 0.1 * i as f64)
            })
            .collect();
        let t0 = V3::new(0.1, 0.0, 1.0).normalize();
        let ghost = Ghost {
            t: t0,
            u: perpendicular(&t0),
            length: 0.1,
        };
        let mut frames = EdgeFrames::default();
        frames.update(&x, &ghost);
        let theta: Vec<f64> = (0..6).map(|j| 0.3 * j as f64 - 0.4).collect();
        let rest: Vec<NodeRest> = (0..6)
            .map(|i| NodeRest {
                a: [0.1 * i as f64, -0.05],
                b: [0.02, 0.1],
            })
            .collect();
        let voronoi = vec![0.05, 0.1, 0.1, 0.1, 0.1, 0.1];
        let s = Stiffness {
            major: 1.0,
            minor: 3.0,
            twist: 0.5,
        };
        let per_segment: Vec<_> = (0..6)
            .map(|j| material(&frames.u[j], &frames.v[j], theta[j]))
            .collect();
        let axes: Vec<_> = (0..6).map(|i| node_axes(i, &per_segment, &ghost)).collect();
        let mut force = vec![V3::zeros(); 7];
        let e = bending(
            &x,
            &frames,
            &ghost,
            &per_segment,
            &rest,
            &voronoi,
            &s,
            &mut force,
        );
        let e0 = frozen_energy(&x, &ghost, &axes, &rest, &voronoi, &s);
        assert!((e - e0).abs() < 1e-12 * e0.abs().max(1.0));
        let h = 1e-6;
        for k in 1..7 {
            for c in 0..3 {
                let mut xp = x.clone();
                let mut xm = x.clone();
                xp[k][c] += h;
                xm[k][c] -= h;
                let fd = -(frozen_energy(&xp, &ghost, &axes, &rest, &voronoi, &s)
                    - frozen_energy(&xm, &ghost, &axes, &rest, &voronoi, &s))
                    / (2.0 * h);
                assert!(
                    (fd - force[k][c]).abs() < 1e-5 * (1.0 + fd.abs()),
                    "node {k} axis {c}: finite difference {fd}, force {}",
                    force[k][c]
                );
            }
        }
    }
}
