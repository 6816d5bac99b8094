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

use nalgebra::Vector3;

/// Runs `iterations` Jacobi damping iterations on `v` in place.
///
/// `tangent[j]` is segment `j`'s unit direction, `coef[j] = β / (w_j + w_{j+1})`, `impulse` a
/// buffer of one value per segment.
pub(crate) fn damp_segments(
    v: &mut [Vector3<f32>],
    inv_mass: &[f32],
    tangent: &[Vector3<f32>],
    coef: &[f32],
    impulse: &mut [f32],
    iterations: u32,
) {
    let segs = tangent.len();
    for _ in 0..iterations {
        for j in 0..segs {
            impulse[j] = coef[j] * tangent[j].dot(&(v[j + 1] - v[j]));
        }
        for j in 0..segs {
            let p = tangent[j] * impulse[j];
            v[j] += p * inv_mass[j];
            v[j + 1] -= p * inv_mass[j + 1];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn damping_conserves_momentum_and_reduces_stretch_rate() {
        let t = vec![Vector3::x(); 3];
        let w = [1.0, 2.0, 1.0, 0.5];
        let mut v = vec![
            Vector3::new(1.0, 0.3, 0.0),
            Vector3::new(-1.0, 0.0, 0.0),
            Vector3::new(2.0, 0.0, 1.0),
            Vector3::zeros(),
        ];
        let momentum =
            |v: &[Vector3<f32>]| v.iter().zip(w).map(|(v, w)| v / w).sum::<Vector3<f32>>();
        let before = momentum(&v);
        let coef: Vec<f32> = (0..3).map(|j| 0.3 / (w[j] + w[j + 1])).collect();
        let mut imp = vec![0.0; 3];
        let rate = |v: &[Vector3<f32>]| (0..3).map(|j| (v[j + 1] - v[j]).x.abs()).sum::<f32>();
        let r0 = rate(&v);
        damp_segments(&mut v, &w, &t, &coef, &mut imp, 10);
        assert!((momentum(&v) - before).norm() < 1e-5);
        assert!(rate(&v) < 0.2 * r0);
        // Velocity across the segments (y, z) is untouched.
        assert!((v[0].y - 0.3).abs() < 1e-6 && (v[2].z - 1.0).abs() < 1e-6);
    }
}
