//! Curl: a helix around the clumped path.
//!
//! At arc length `a` along the parent's path (meters from the root) the point is moved by
//! `r(s) (cos θ u + sin θ w)`, `θ = 2π f a + φ`, where `(u, w)` is the parent's transported frame
//! there, `f` the frequency in turns per meter and `φ` a random phase per child. On a straight
//! stretch this is a circular helix of radius `r` and pitch `1/f` around the clumped path; the
//! radius ramps in from 0 at the root over the shape's root ramp so the root stays on the scalp.

use crate::error::{check_range, Result};

/// Curl radius and frequency.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields, default))]
pub struct Curl {
    /// Helix radius, meters (≥ 0; 0 turns curl off).
    pub radius: f32,
    /// Turns per meter of hair length (≥ 0).
    pub frequency: f32,
}

impl Curl {
    /// Checks the ranges, naming the field.
    pub fn validate(&self) -> Result<()> {
        check_range(
            "shape.curl.radius",
            self.radius,
            0.0,
            1.0,
            "use a radius in meters in [0, 1] (e.g. 0.005 for 5 mm curls)",
        )?;
        check_range(
            "shape.curl.frequency",
            self.frequency,
            0.0,
            1e5,
            "use turns per meter in [0, 100000] (e.g. 40)",
        )
    }

    /// True when curl changes nothing.
    pub fn is_off(&self) -> bool {
        self.radius == 0.0
    }

    /// Curl offset in frame components `(u, w)`, meters, at arc length `arc` (m) with `ramp` ∈
    /// [0, 1] of the radius and the child's phase `phase` in turns (∈ [0, 1)).
    #[inline(always)]
    pub(crate) fn offset(&self, arc: f32, ramp: f32, phase: f32) -> (f32, f32) {
        let (s, c) = sin_cos_turns(self.frequency * arc + phase);
        let r = self.radius * ramp;
        (r * c, r * s)
    }
}

/// `(sin 2πt, cos 2πt)` to about 3e-7 absolute for |t| < 2²¹ turns: `t` reduced to a quarter
/// turn by the round-to-nearest of adding and removing 1.5 · 2²³ (float adds only: no libm
/// `roundf`, no saturating casts, no branch), then two short Taylor polynomials on [−π/4, π/4].
#[inline(always)]
pub(crate) fn sin_cos_turns(t: f32) -> (f32, f32) {
    const MAGIC: f32 = 12_582_912.0;
    let t = t - ((t + MAGIC) - MAGIC);
    // q = round(4t) ∈ [−2, 2]; its two low bits sit in the mantissa of 4t + MAGIC.
    let qm = 4.0 * t + MAGIC;
    let q = qm.to_bits();
    let r = (t - 0.25 * (qm - MAGIC)) * std::f32::consts::TAU;
    let r2 = r * r;
    let s = r * (1.0 + r2 * (-1.0 / 6.0 + r2 * (1.0 / 120.0 + r2 * (-1.0 / 5040.0))));
    let c = 1.0 + r2 * (-0.5 + r2 * (1.0 / 24.0 + r2 * (-1.0 / 720.0 + r2 * (1.0 / 40320.0))));
    // Quadrant q (mod 4) without branches (the quadrant is random per point):
    // 0 → (s, c), 1 → (c, −s), 2 → (−s, −c), 3 → (−c, s).
    let odd = (q & 1) as f32;
    let sign = 1.0 - 2.0 * ((q >> 1) & 1) as f32;
    (sign * (s + odd * (c - s)), sign * (c - odd * (s + c)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_sin_cos_matches_libm() {
        let mut worst = 0.0f64;
        for i in -20_000..=20_000 {
            let t = i as f32 * 1.37e-4;
            let (s, c) = sin_cos_turns(t);
            let (es, ec) = (std::f64::consts::TAU * f64::from(t)).sin_cos();
            worst = worst
                .max((f64::from(s) - es).abs())
                .max((f64::from(c) - ec).abs());
        }
        assert!(worst < 1e-6, "{worst}");
    }
}
