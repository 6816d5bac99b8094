//! The damping sub-loop: viscous damping of relative velocity along each segment.
//!
//! Seed 001 damps point velocities in a separate sub-loop of about ten iterations per substep,
//! because damping stiff stretch springs inside the force step destabilises them. A Gauss–Seidel
//! sweep down the strand is the obvious way to run it, but each point then waits for its
//! predecessor: a serial dependency chain that costs several times the rest of the substep.
//!
//! hairsys uses **Jacobi** iterations in segment-impulse space instead. Each iteration first
//! computes, for every segment `j` independently, the relative velocity along its direction
//! `r_j = t_j·(v_{j+1} − v_j)` and the impulse `p_j = β r_j / (w_j + w_{j+1})` (`w` inverse
//! masses), then applies all impulses at once (`v_j += w_j p_j t_j`, `v_{j+1} −= w_{j+1} p_j t_j`).
//! Both passes have no loop-carried dependency, so they vectorise across segments. `β` is the
//! exact exponential decay of an isolated segment over `dt/iterations`, capped at 1/2: a point
//! shared by two segments then receives at most the full correction, so the iteration matrix has
//! eigenvalues in [0, 1] and never overshoots (unconditionally stable for any damping rate).
//! Impulses are equal and opposite, so damping conserves linear momentum; pinned points
//! (`w = 0`) are not moved by it.

use super::lanes::{Lane, V3};

/// Runs `iterations` Jacobi damping iterations on the velocities `v` of a group in place.
///
/// Segment arrays are padded (segment `j` at index `j + 1`, zeros at `0` and `n`):
/// `tangent` holds unit directions, `coef` holds `β / (w_j + w_{j+1})`, `impulse` is a buffer.
#[inline(always)]
pub(crate) fn damp_segments<L: Lane>(
    v: &mut [V3<L>],
    inv_mass: &[L],
    tangent: &[V3<L>],
    coef: &[L],
    impulse: &mut [L],
    iterations: u32,
) {
    let n = v.len();
    for _ in 0..iterations {
        for j in 0..n - 1 {
            impulse[j + 1] = coef[j + 1] * tangent[j + 1].dot(&(v[j + 1] - v[j]));
        }
        for i in 0..n {
            v[i] += (tangent[i + 1] * impulse[i + 1] - tangent[i] * impulse[i]) * inv_mass[i];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::lanes::splat;
    use super::*;
    use nalgebra::Vector3;

    #[test]
    fn damping_conserves_momentum_and_reduces_stretch_rate() {
        // Four points along x, the same in every lane; padded tangents (zeros at both ends).
        let along: V3 = V3::splat(&Vector3::x());
        let t = [V3::default(), along, along, along, V3::default()];
        let w = [1.0, 2.0, 1.0, 0.5];
        let inv_mass = w.map(splat);
        let mut v = [[1.0, 0.3, 0.0], [-1.0, 0.0, 0.0], [2.0, 0.0, 1.0], [0.0; 3]]
            .map(|p| V3::splat(&Vector3::from(p)));
        let lane0 = |v: &[V3]| v.iter().map(|p| p.lane(0)).collect::<Vec<_>>();
        let momentum = |v: &[Vector3<f32>]| (0..4).map(|i| v[i].x / w[i]).sum::<f32>();
        let rate = |v: &[Vector3<f32>]| (0..3).map(|j| (v[j + 1].x - v[j].x).abs()).sum::<f32>();
        let before = lane0(&v);
        let mut coef = [splat(0.0); 5];
        for j in 0..3 {
            coef[j + 1] = splat(0.3 / (w[j] + w[j + 1]));
        }
        let mut imp = [splat(0.0); 5];
        damp_segments(&mut v, &inv_mass, &t, &coef, &mut imp, 10);
        let after = lane0(&v);
        assert!((momentum(&after) - momentum(&before)).abs() < 1e-5);
        assert!(rate(&after) < 0.2 * rate(&before));
        // Velocity across the segments (y, z) is untouched.
        assert!((after[0].y - 0.3).abs() < 1e-6 && (after[2].z - 1.0).abs() < 1e-6);
    }
}
