//! Analytic answers the bench measures against where physics has one.
//!
//! - **Pendulum** (a point mass on a rigid massless link of length `L`, released from rest at
//!   `θ₀`): `θ'' = −(g/L) sin θ`. Its period is `T = 4 √(L/g) K(sin(θ₀/2))`, `K` the complete
//!   elliptic integral of the first kind, computed by the arithmetic–geometric mean
//!   `K(k) = π / (2 AGM(1, √(1 − k²)))` (Abramowitz & Stegun 17.6). The trajectory is integrated
//!   in f64 by classical Runge–Kutta at a step whose error is far below f32 round-off; the test
//!   checks its period against `T`.
//! - **Hanging chain** (`n` equal rigid links of length `l`, equal point masses `m` at the
//!   joints, both ends pinned at the same height `D` apart): at rest the horizontal tension `H`
//!   is the same in every link and the vertical one drops by `m g` at each joint, so link `j`
//!   points along `(H, V₀ − j m g)` with `V₀ = (n − 1) m g / 2` by symmetry; `H` is the root of
//!   `Σ l H / √(H² + V_j²) = D` (bisection). This is the exact rest shape of the discrete chain
//!   the cases simulate; as `n → ∞` it tends to the **catenary** `z = a (cosh(x/a) − 1)` with
//!   `L = 2 a sinh(D / 2a)` and sag `a (cosh(D / 2a) − 1)`.
//! - **Cantilever under a tip moment** (the elastica with a pure end couple `M`): the moment is
//!   the same everywhere along the rod, so an inextensible rod of bending rigidity `EI` bends
//!   into a circular arc of curvature `M/EI` at **any** deflection, its tip turned by
//!   `θ = M L / EI` and placed at `u = L (sin θ / θ − 1)` along the clamp and
//!   `v = (L/θ)(1 − cos θ)` across it; for small `θ`, `v → M L² / (2 EI)` (beam theory).

use nalgebra::Vector3;

/// Complete elliptic integral of the first kind `K(k)` (modulus `k`, `0 ≤ k < 1`).
pub fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    for _ in 0..40 {
        let (an, bn) = (0.5 * (a + b), (a * b).sqrt());
        (a, b) = (an, bn);
        if (a - b).abs() < 1e-16 * a {
            break;
        }
    }
    std::f64::consts::PI / (2.0 * a)
}

/// Period of a rigid pendulum of length `length` (m) released from rest at `theta0` (rad)
/// under gravity `g` (m/s²), s.
pub fn pendulum_period(length: f64, g: f64, theta0: f64) -> f64 {
    4.0 * (length / g).sqrt() * elliptic_k((0.5 * theta0).sin())
}

/// Angle from the vertical of a rigid pendulum (released from rest at `theta0`) at each of
/// `times` (s, increasing, ≥ 0), rad.
pub fn pendulum_angles(length: f64, g: f64, theta0: f64, times: &[f64]) -> Vec<f64> {
    let w2 = g / length;
    let f = |th: f64, om: f64| (om, -w2 * th.sin());
    let h = 1e-4 * (length / g).sqrt();
    let (mut t, mut th, mut om) = (0.0f64, theta0, 0.0f64);
    let mut out = Vec::with_capacity(times.len());
    for &target in times {
        while t < target {
            let dt = h.min(target - t);
            let (k1a, k1b) = f(th, om);
            let (k2a, k2b) = f(th + 0.5 * dt * k1a, om + 0.5 * dt * k1b);
            let (k3a, k3b) = f(th + 0.5 * dt * k2a, om + 0.5 * dt * k2b);
            let (k4a, k4b) = f(th + dt * k3a, om + dt * k3b);
            th += dt / 6.0 * (k1a + 2.0 * k2a + 2.0 * k3a + k4a);
            om += dt / 6.0 * (k1b + 2.0 * k2b + 2.0 * k3b + k4b);
            t += dt;
        }
        out.push(th);
    }
    out
}

/// Rest positions (x along the span, z up, first pin at the origin) of a chain of `n` rigid
/// links of length `link` (m) with equal masses at its `n − 1` free joints, pinned at both ends
/// `span` apart at the same height. `None` if the chain cannot reach (`n · link ≤ span`) or
/// `n < 2`.
pub fn discrete_catenary(n: usize, link: f64, span: f64) -> Option<Vec<Vector3<f64>>> {
    if n < 2 || n as f64 * link <= span || span <= 0.0 {
        return None;
    }
    // Tensions in units of m g: V_j = (n − 1)/2 − j.
    let v = |j: usize| 0.5 * (n as f64 - 1.0) - j as f64;
    let reach = |h: f64| -> f64 {
        (0..n)
            .map(|j| link * h / (h * h + v(j) * v(j)).sqrt())
            .sum()
    };
    // reach(h) rises from 0 towards n·link as h grows.
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    while reach(hi) < span {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if reach(mid) < span {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let h = 0.5 * (lo + hi);
    let mut p = Vector3::zeros();
    let mut out = vec![p];
    for j in 0..n {
        let t = (h * h + v(j) * v(j)).sqrt();
        p += Vector3::new(link * h / t, 0.0, -link * v(j) / t);
        out.push(p);
    }
    Some(out)
}

/// Sag (m) of the continuous catenary of length `length` hung between two points `span` apart
/// at the same height (`length > span > 0`): `a (cosh(D / 2a) − 1)` with `a` the root of
/// `2 a sinh(D / 2a) = L`.
pub fn catenary_sag(length: f64, span: f64) -> f64 {
    let reach = |a: f64| 2.0 * a * (span / (2.0 * a)).sinh();
    // reach(a) falls from ∞ (a → 0) to span (a → ∞); bisect on log a.
    let (mut lo, mut hi) = (1e-6 * span, 1e6 * span);
    for _ in 0..300 {
        let mid = (lo * hi).sqrt();
        if reach(mid) > length {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let a = (lo * hi).sqrt();
    a * ((span / (2.0 * a)).cosh() - 1.0)
}

/// Tip of a clamped inextensible rod of length `length` (m) and bending rigidity `ei` (N m²)
/// under a pure end moment `moment` (N m): `(θ, u, v)`, the tip's turn (rad) and its
/// displacement along the clamp direction and across it (m).
pub fn elastica_tip(length: f64, ei: f64, moment: f64) -> (f64, f64, f64) {
    let t = moment * length / ei;
    if t.abs() < 1e-8 {
        return (t, -length * t * t / 6.0, 0.5 * length * t);
    }
    (
        t,
        length * (t.sin() / t - 1.0),
        length / t * (1.0 - t.cos()),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elliptic_k_matches_tabulated_values() {
        // A&S table 17.1: K(m = 0.5) = 1.854 074 677 3, K(0) = π/2.
        assert!((elliptic_k(0.5f64.sqrt()) - 1.854_074_677_3).abs() < 1e-10);
        assert!((elliptic_k(0.0) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    }

    #[test]
    fn integrated_pendulum_returns_after_the_elliptic_period() {
        let (l, g, th0) = (0.5, 9.81, 40f64.to_radians());
        let t = pendulum_period(l, g, th0);
        // 40°: T = T₀ (1 + θ₀²/16 + 11 θ₀⁴/3072 + …) = 1.0313 T₀.
        let t0 = 2.0 * std::f64::consts::PI * (l / g).sqrt();
        assert!((t / t0 - 1.0314).abs() < 2e-4, "{}", t / t0);
        let th = pendulum_angles(l, g, th0, &[0.5 * t, t, 3.0 * t]);
        assert!((th[0] + th0).abs() < 1e-9, "{th:?}");
        assert!((th[1] - th0).abs() < 1e-9, "{th:?}");
        assert!((th[2] - th0).abs() < 1e-9, "{th:?}");
    }

    #[test]
    fn discrete_catenary_tends_to_the_catenary_sag() {
        let (length, span) = (1.0, 0.8);
        let sag = catenary_sag(length, span);
        // a = 0.3382 m, sag = 0.2654 m for L = 1, D = 0.8 (solved independently), below the
        // 0.3 m of the two straight halves of a V.
        assert!((sag - 0.2654).abs() < 1e-4, "{sag}");
        let mut last = f64::INFINITY;
        for n in [10usize, 20, 40, 80] {
            let p = discrete_catenary(n, length / n as f64, span).unwrap();
            assert!((p[n].x - span).abs() < 1e-9 && p[n].z.abs() < 1e-9);
            let lowest = p.iter().map(|q| -q.z).fold(0.0, f64::max);
            let gap = (lowest - sag).abs();
            assert!(gap < last, "n = {n}: {gap} after {last}");
            last = gap;
        }
        assert!(last < 1e-3 * sag, "{last}");
    }

    #[test]
    fn elastica_tip_turn_is_ml_over_ei_and_small_deflection_is_beam_theory() {
        let (l, ei) = (0.4, 1e-3);
        let (t, u, v) = elastica_tip(l, ei, 1.5 * ei / l);
        assert!((t - 1.5).abs() < 1e-12);
        assert!((u - l * (1.5f64.sin() / 1.5 - 1.0)).abs() < 1e-12);
        assert!((v - l / 1.5 * (1.0 - 1.5f64.cos())).abs() < 1e-12);
        let m = 1e-3 * ei / l;
        let (_, _, v) = elastica_tip(l, ei, m);
        assert!((v / (m * l * l / (2.0 * ei)) - 1.0).abs() < 1e-6);
    }
}
