//! Trimming a hair to a fraction of its length (painted length maps).
//!
//! A hair painted `f ∈ (0, 1]` keeps its groomed shape from the root up to the arc length
//! `f · L` and is resampled there to the **same point count**, uniform in arc length, so its
//! segments are `f` times as long on a straight hair. The point count is kept, not the segment
//! length, because everything that follows a hair does so by point index: goal weights and pins
//! per point, and animated guides, which re-pose every sim hair each frame point for point
//! ([`crate::GuideBlend`]); a hair with fewer points would need its own blend recipe, pins
//! renumbered and a varying point count per strand through the solver's SIMD lanes.
//!
//! The resampled points lie on the groomed curve, so on a curved groom their chords cut its
//! corners: the trimmed polyline's length is `f · L` on a straight hair and up to ~1 % shorter on
//! a curled one (never longer: a chord is never longer than the arc it spans).

use nalgebra::Vector3;

/// Writes into `out` the first `fraction` of `curve`'s arc length, resampled to `out.len()`
/// points uniform in arc length (`out[0] = curve[0]`, the last point at arc length
/// `fraction · L`). `fraction` is clamped to [0, 1]; a curve of zero length gives its first
/// point everywhere.
///
/// # Panics
/// If `curve` or `out` has fewer than 2 points.
pub fn trim_polyline(curve: &[Vector3<f32>], fraction: f32, out: &mut [Vector3<f32>]) {
    let (n, m) = (curve.len(), out.len());
    assert!(n >= 2 && m >= 2, "a hair has at least 2 points");
    let seg = |j: usize| (curve[j + 1] - curve[j]).norm();
    // Summed in the order the walk below accumulates, so the last arc equals `length` exactly.
    let length = (0..n - 1).fold(0.0f32, |acc, j| acc + seg(j));
    let target = fraction.clamp(0.0, 1.0) * length;
    // The walk's segment j spans arc lengths [a0, a1].
    let (mut j, mut a0, mut a1) = (0, 0.0f32, seg(0));
    for (k, o) in out.iter_mut().enumerate() {
        let t = target * k as f32 / (m - 1) as f32;
        while j + 2 < n && a1 < t {
            j += 1;
            a0 = a1;
            a1 = a0 + seg(j);
        }
        let span = a1 - a0;
        let a = if span > 0.0 { (t - a0) / span } else { 0.0 };
        *o = curve[j] + (curve[j + 1] - curve[j]) * a.clamp(0.0, 1.0);
    }
}

/// Checks painted length fractions: each finite and in (0, 1]. The error names the first bad
/// one by its index.
pub fn check_length_fractions(fractions: &[f32]) -> Result<(), (usize, f32)> {
    match fractions.iter().position(|f| !(*f > 0.0 && *f <= 1.0)) {
        Some(i) => Err((i, fractions[i])),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn polyline_length(p: &[Vector3<f32>]) -> f32 {
        p.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
    }

    #[test]
    fn a_straight_hair_trimmed_to_half_has_half_its_length_and_even_segments() {
        let curve: Vec<_> = (0..9)
            .map(|i| Vector3::new(0.0, 0.0, 0.01 * i as f32))
            .collect();
        let mut out = vec![Vector3::zeros(); 9];
        trim_polyline(&curve, 0.5, &mut out);
        assert_eq!(out[0], curve[0]);
        assert!((polyline_length(&out) - 0.04).abs() < 1e-7);
        for w in out.windows(2) {
            assert!(((w[1] - w[0]).norm() - 0.005).abs() < 1e-7);
        }
    }

    #[test]
    fn trimmed_points_lie_on_the_groomed_curve() {
        // A quarter circle of radius 0.1: every resampled point is on the polyline, so it is
        // within the chord's sagitta of the circle, and the tip sits at the fraction's angle.
        let r = 0.1f32;
        let curve: Vec<_> = (0..33)
            .map(|i| {
                let a = std::f32::consts::FRAC_PI_2 * i as f32 / 32.0;
                Vector3::new(r * a.cos(), r * a.sin(), 0.0)
            })
            .collect();
        let mut out = vec![Vector3::zeros(); 33];
        trim_polyline(&curve, 0.5, &mut out);
        let sagitta = r * (1.0 - (std::f32::consts::FRAC_PI_2 / 64.0).cos());
        for p in &out {
            assert!((p.norm() - r).abs() <= sagitta + 1e-6, "{p:?}");
        }
        let tip = out[32].y.atan2(out[32].x);
        assert!(
            (tip - std::f32::consts::FRAC_PI_4).abs() < 1e-4,
            "tip at {tip} rad"
        );
        let full = polyline_length(&curve);
        let ratio = polyline_length(&out) / full;
        assert!((0.5 * 0.99..=0.5 + 1e-6).contains(&ratio), "ratio {ratio}");
    }

    #[test]
    fn fraction_one_gives_back_a_uniform_curve_unchanged() {
        let curve: Vec<_> = (0..5)
            .map(|i| Vector3::new(0.02 * i as f32, 0.0, 0.0))
            .collect();
        let mut out = vec![Vector3::zeros(); 5];
        trim_polyline(&curve, 1.0, &mut out);
        for (a, b) in out.iter().zip(&curve) {
            assert!((a - b).norm() < 1e-7);
        }
    }

    #[test]
    fn bad_fractions_are_named_by_index() {
        assert_eq!(check_length_fractions(&[0.5, 1.0]), Ok(()));
        assert_eq!(check_length_fractions(&[0.5, 0.0, 2.0]), Err((1, 0.0)));
        assert_eq!(check_length_fractions(&[1.5]), Err((0, 1.5)));
        assert!(check_length_fractions(&[f32::NAN]).is_err());
    }
}
