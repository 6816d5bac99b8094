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

#![allow(clippy::needless_range_loop)] // index loops over several lanes vectorise

use super::kernel::Lanes;

/// Runs `iterations` Jacobi damping iterations on the velocity lanes `v` in place.
///
/// Segment arrays are padded (segment `j` at index `j + 1`, zeros at `0` and `n`):
/// `tangent` holds unit directions, `coef` holds `β / (w_j + w_{j+1})`, `impulse` is a buffer.
pub(crate) fn damp_segments(
    v: &mut Lanes,
    inv_mass: &[f32],
    tangent: &Lanes,
    coef: &[f32],
    impulse: &mut [f32],
    iterations: u32,
) {
    let n = inv_mass.len();
    for _ in 0..iterations {
        for j in 0..n - 1 {
            let r = tangent.x[j + 1] * (v.x[j + 1] - v.x[j])
                + tangent.y[j + 1] * (v.y[j + 1] - v.y[j])
                + tangent.z[j + 1] * (v.z[j + 1] - v.z[j]);
            impulse[j + 1] = coef[j + 1] * r;
        }
        for i in 0..n {
            let (after, before) = (impulse[i + 1], impulse[i]);
            v.x[i] += inv_mass[i] * (after * tangent.x[i + 1] - before * tangent.x[i]);
            v.y[i] += inv_mass[i] * (after * tangent.y[i + 1] - before * tangent.y[i]);
            v.z[i] += inv_mass[i] * (after * tangent.z[i + 1] - before * tangent.z[i]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lanes(v: &[[f32; 3]]) -> Lanes {
        Lanes {
            x: v.iter().map(|p| p[0]).collect(),
            y: v.iter().map(|p| p[1]).collect(),
            z: v.iter().map(|p| p[2]).collect(),
        }
    }

    #[test]
    fn damping_conserves_momentum_and_reduces_stretch_rate() {
        // Four points along x; padded tangents (zeros at both ends).
        let t = lanes(&[
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0; 3],
        ]);
        let w = [1.0, 2.0, 1.0, 0.5];
        let mut v = lanes(&[[1.0, 0.3, 0.0], [-1.0, 0.0, 0.0], [2.0, 0.0, 1.0], [0.0; 3]]);
        let momentum = |v: &Lanes| (0..4).map(|i| v.x[i] / w[i]).sum::<f32>();
        let rate = |v: &Lanes| (0..3).map(|j| (v.x[j + 1] - v.x[j]).abs()).sum::<f32>();
        let (p0, r0) = (momentum(&v), rate(&v));
        let mut coef = vec![0.0; 5];
        for j in 0..3 {
            coef[j + 1] = 0.3 / (w[j] + w[j + 1]);
        }
        let mut imp = vec![0.0; 5];
        damp_segments(&mut v, &w, &t, &coef, &mut imp, 10);
        assert!((momentum(&v) - p0).abs() < 1e-5);
        assert!(rate(&v) < 0.2 * r0);
        // Velocity across the segments (y, z) is untouched.
        assert!((v.y[0] - 0.3).abs() < 1e-6 && (v.z[2] - 1.0).abs() < 1e-6);
    }
}
