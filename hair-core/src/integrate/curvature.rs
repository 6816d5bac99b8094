//! Bending of the mass-spring chain as discrete curvature: the energy, the meaning of
//! `bend_stiffness`, and the rest curvature a [`RestDirection`] describes.
//!
//! # The energy
//!
//! Joint `j` sits at point `j`, between the previous segment's unit tangent `a = t_{j−1}` (the
//! root frame's normal for `j = 0`) and `b = t_j`. Its **curvature binormal** (Bergou, Wardetzky,
//! Robinson, Audoly and Grinspun, "Discrete Elastic Rods", SIGGRAPH 2008) is
//!
//! `κ_j = 2 a × b / (1 + a·b)`, `|κ_j| = 2 tan(θ_j/2)` for a turn `θ_j` between the segments,
//!
//! and the bending energy is
//!
//! `E = Σ_j ½ k_j |κ_j − K_j|²`, `K_j = κ⁰_u u_{j−1} + κ⁰_w w_{j−1}`,
//!
//! where `(t_{j−1}, u_{j−1}, w_{j−1})` is the previous segment's frame, carried down the strand
//! from the root frame by parallel transport ([`crate::frames`]), and `(κ⁰_u, κ⁰_w)` the rest
//! curvature in that frame ([`rest_curvature`]). A straight rest shape has `K = 0` and
//! `E_j = 2 k_j tan²(θ_j/2)`: the moment `dE/dθ = 2 k_j tan(θ/2)/cos²(θ/2)` grows without bound
//! as the turn approaches 180° (`k θ` at small angles, `4 k` at 90°), so a joint gets stiffer,
//! not softer, the further it is bent, and a bend spreads over the joints instead of folding at
//! one of them.
//!
//! # Why not a chord spring
//!
//! The simpler *chord spring* per joint, `½ k_b |x_j + l_j d_j − x_{j+1}|²` (`d_j` the rest
//! direction in the same transported frame), has the energy `2 k_b l² sin²(θ/2)` and a moment
//! `k_b l² sin θ` that peaks at 90° and falls to zero at 180°: past 90° a joint softens, bends
//! concentrate at one vertex and a segment folded straight back is an equilibrium (with it the
//! parity scene folds into hairpins of up to 179°). It also acts along its segment like a second
//! stretch spring of stiffness `k_b`; the curvature energy has no along-segment part. The chain
//! bent with chord springs before this energy: `docs/design/bending-energy.md`.
//!
//! # The meaning of `bend_stiffness`
//!
//! At small turns a chord spring's joint stiffness is `k_b l²` (`E ≈ ½ k_b l² θ²`), the
//! curvature energy's `k_j` (`E ≈ ½ k_j θ²`). So that `bend_stiffness = k_b` (N/m) means what it
//! means for a chord spring, a strand gets the **bending rigidity**
//!
//! `EI = k_b l̄³` (N·m²), `l̄` = the strand's mean rest segment length,
//!
//! the same for all its joints, and joint `j` the stiffness `k_j = EI / l̄_j` (N·m) over its
//! Voronoi length `l̄_j = (l_{j−1} + l_j)/2` (`l_0` for the root joint, as if a ghost segment of
//! the same length preceded it). On a uniformly segmented strand `k_j = k_b l²`, the chord
//! spring's value, so small bends are the chord spring's; on a non-uniform one the rigidity does
//! not follow the local segment length (a chord spring's does: `EI_j = k_b l_j³`). The key
//! scales with the discretisation through `l̄³` — resampling a strand with twice the points at
//! the same `bend_stiffness` makes it 8× softer, as it does a chord spring.
//!
//! # The forces
//!
//! With the moment `m_j = k_j (κ_j − K_j)`, `χ = 1/(1 + a·b)` and `μ = χ m_j·κ_j`, the gradient of
//! `E_j` in the tangent plane of `b` and of `a` is
//!
//! `g_b = 2χ m_j × a − μ (a + b)`, `g_a = 2χ b × m_j − μ (a + b)`,
//!
//! applied as `−g_b / len_j` on point `j + 1` (`+` on point `j`) and `−g_a / len_{j−1}` on point
//! `j` (`+` on point `j − 1`; none on the kinematic root frame). `K_j` turns with the transported
//! frame; its torque `m_j × K_j = m_j × κ_j` lies along `a` (both vectors are ⟂ `a`), so only the
//! reference twist of parallel transport carries it (the kernel's `β`/`S` sums, which carry a
//! chord spring's torque the same way).
//!
//! **The root joint** (point 0) is the exception: its reference is the first segment's rest
//! direction `d_0` in the root frame itself, `κ_0 = 2 d_0 × t_0/(1 + d_0·t_0)` against zero rest
//! curvature, `E_0 = 2 k_0 tan²(φ/2)` with `φ` the angle between the first segment and its rest
//! direction. A strand defined hanging from an upright root frame turns 180° from the normal at
//! rest, which no curvature binormal can hold; the turn from the rest direction can. The forces
//! are those above with `a = d_0`; the root frame is kinematic, so nothing else changes.
//!
//! A segment folded exactly straight back (`a·b = −1`) has no curvature binormal and no
//! transport; it takes no bending force there (`χ` is set to 0), a set of measure zero that the
//! growing moment keeps joints away from.
//!
//! # Stability
//!
//! At small turns about a straight rest a joint's transverse stiffness on its points is
//! `k_j / (l_{j−1} l_j)` (`k_b` on a uniform strand), more about a curved rest
//! ([`transverse_stiffness`]), which [`super::stability`] takes into its bound. It grows with the turn
//! (`d²E/dθ² = 8 k` at 90°), so a strand forced into sharp turns (by a collider, say) needs more
//! substeps than the small-angle bound predicts; the runaway check stops a run that diverges.

use crate::frames::RestDirection;

/// Rest curvature `(κ⁰_u, κ⁰_w)` (rad per joint, dimensionless) that a rest direction describes:
/// the curvature binormal `2 e_t × r̂ / (1 + e_t·r̂)` of the turn from the previous segment's
/// tangent `e_t` to `r̂ = r/|r|`, in the frame's (u, w) components. The length of `r` is ignored.
/// A rest direction pointing straight back (which no groom has) is taken as straight.
#[inline]
pub fn rest_curvature(r: &RestDirection) -> (f32, f32) {
    let (t, u, w) = (r.t as f64, r.u as f64, r.w as f64);
    let c = (t * t + u * u + w * w).sqrt() + t;
    if c > 1e-12 {
        ((-2.0 * w / c) as f32, (2.0 * u / c) as f32)
    } else {
        (0.0, 0.0)
    }
}

/// The unit vector along a rest direction (the root joint's reference, see the module docs); the
/// root frame's normal for a zero vector.
pub fn root_direction(r: &RestDirection) -> nalgebra::Vector3<f32> {
    let v = nalgebra::Vector3::new(r.t, r.u, r.w);
    let n = v.norm();
    if n > 0.0 {
        v / n
    } else {
        nalgebra::Vector3::x()
    }
}

/// The unit rest direction whose [`rest_curvature`] is `(k_u, k_w)`: the inverse of
/// `rest_curvature` (`tan(θ/2) = |κ|/2`, `r = (cos θ, κ_w cos²(θ/2), −κ_u cos²(θ/2))`).
pub fn direction_of_curvature(k_u: f64, k_w: f64) -> RestDirection {
    let half_tan2 = 0.25 * (k_u * k_u + k_w * k_w);
    let cos2_half = 1.0 / (1.0 + half_tan2);
    RestDirection {
        t: ((1.0 - half_tan2) * cos2_half) as f32,
        u: (k_w * cos2_half) as f32,
        w: (-k_u * cos2_half) as f32,
    }
}

/// Bending rigidity of a strand with rest segment lengths `rest_lengths` (m): `k_b l̄³`, N·m²,
/// with `l̄` their mean (see the module docs). Zero for a strand without segments.
pub fn rigidity(bend_stiffness: f32, rest_lengths: &[f32]) -> f64 {
    if rest_lengths.is_empty() {
        return 0.0;
    }
    let mean = rest_lengths.iter().map(|&l| l as f64).sum::<f64>() / rest_lengths.len() as f64;
    bend_stiffness as f64 * mean.powi(3)
}

/// Stiffness of joint `j` (point `j`, before segment `j`) of a strand with rigidity `ei` (N·m²):
/// `ei / l̄_j`, N·m, with `l̄_j` the joint's Voronoi length (see the module docs).
pub fn joint_stiffness(ei: f64, rest_lengths: &[f32], j: usize) -> f64 {
    let voronoi = if j == 0 {
        rest_lengths[0] as f64
    } else {
        0.5 * (rest_lengths[j - 1] as f64 + rest_lengths[j] as f64)
    };
    ei / voronoi
}

/// Largest small-angle transverse stiffness of any joint of a strand, N/m:
/// `k_j (1 + |κ⁰_j|²/4)² / min(l_{j−1}, l_j)²` (`k_b` on a uniformly segmented straight strand),
/// for the stability bound. About a rest turn `θ₀` the curvature changes by
/// `δ|κ| = δθ / cos²(θ₀/2) = δθ (1 + |κ⁰|²/4)`, so the joint is stiffer by the square of that
/// (1.69× at 1 rad per joint); the root joint measures the turn from its rest direction itself
/// (factor 1).
pub fn transverse_stiffness(
    bend_stiffness: f32,
    rest_lengths: &[f32],
    rest: &[RestDirection],
) -> f64 {
    let ei = rigidity(bend_stiffness, rest_lengths);
    (0..rest_lengths.len())
        .map(|j| {
            let (shortest, curved) = if j == 0 {
                (rest_lengths[0], 1.0)
            } else {
                let (k_u, k_w) = rest_curvature(&rest[j]);
                let quarter = 0.25 * (k_u as f64 * k_u as f64 + k_w as f64 * k_w as f64);
                (
                    rest_lengths[j - 1].min(rest_lengths[j]),
                    (1.0 + quarter).powi(2),
                )
            };
            let shortest = shortest as f64;
            joint_stiffness(ei, rest_lengths, j) * curved / (shortest * shortest)
        })
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rest_direction_and_curvature_round_trip() {
        for (k_u, k_w) in [(0.0, 0.0), (0.3, -0.1), (-1.5, 2.0), (5.0, 0.5)] {
            let r = direction_of_curvature(k_u, k_w);
            let norm = (r.t * r.t + r.u * r.u + r.w * r.w).sqrt();
            assert!((norm - 1.0).abs() < 1e-6);
            let (a, b) = rest_curvature(&r);
            assert!((a as f64 - k_u).abs() < 1e-5 * (1.0 + k_u.abs()));
            assert!((b as f64 - k_w).abs() < 1e-5 * (1.0 + k_w.abs()));
        }
    }

    #[test]
    fn curvature_is_twice_the_tangent_of_half_the_turn() {
        let theta = 2.0f32;
        // Turn by θ from t towards u: binormal along t × u = w, magnitude 2 tan(θ/2).
        let r = RestDirection {
            t: theta.cos(),
            u: theta.sin(),
            w: 0.0,
        };
        let (k_u, k_w) = rest_curvature(&r);
        assert!(k_u.abs() < 1e-6);
        assert!((k_w - 2.0 * (theta / 2.0).tan()).abs() < 1e-5);
    }

    #[test]
    fn uniform_strand_keeps_the_chord_springs_small_angle_stiffness() {
        let l = [0.02f32; 8];
        let l2 = (l[0] as f64).powi(2);
        let ei = rigidity(5.0, &l);
        for j in 0..8 {
            let k = joint_stiffness(ei, &l, j);
            assert!((k / (5.0 * l2) - 1.0).abs() < 1e-12, "{k}");
        }
        let straight = [RestDirection {
            t: 1.0,
            u: 0.0,
            w: 0.0,
        }; 8];
        assert!((transverse_stiffness(5.0, &l, &straight) / 5.0 - 1.0).abs() < 1e-12);
    }
}
