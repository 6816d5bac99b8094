//! Material of the rod model: the elliptical cross-section, its bending and twisting stiffness,
//! and the projection's settings ([`RodParams`], the scene's `[rod]` table).
//!
//! A hair's cross-section is an ellipse with semi-axes `a ≥ b` (`a` along the material axis
//! `m1`, `b` along `m2`). Its second moments of area are
//!
//! ```text
//! I₁ = π a b³ / 4   about the major axis m1 (the easy way: the hair bends over its major axis)
//! I₂ = π a³ b / 4   about the minor axis m2 (stiffer by (a/b)²)
//! J  = π a³ b³ / (a² + b²)   torsion constant
//! ```
//!
//! so the bending stiffnesses are `E I₁ ≤ E I₂` and the twist stiffness is `G J` (N·m²).

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::error::{HairError, Result};

/// Material and projection settings of the rod model (the scene's `[rod]` table). Gravity and
/// air drag come from the hair system's [`crate::HairParams`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields, default))]
pub struct RodParams {
    /// Young's modulus of the strand, Pa (keratin: about 3.9e9).
    pub youngs_modulus: f32,
    /// Shear modulus of the strand, Pa (keratin: about 1.5e9).
    pub shear_modulus: f32,
    /// Semi-major axis `a` of the elliptical cross-section, m. A simulated strand stands for a
    /// wisp, so this is an effective size, not one hair's.
    pub semi_major_axis: f32,
    /// Cross-section ratio `b/a` in (0, 1]: 1 is round, human hair is about 0.6–0.9.
    pub axis_ratio: f32,
    /// Iteration limit of the projection onto the constraints per substep.
    pub projection_iterations: u32,
    /// Tolerance of the projection: largest relative segment strain `|len/rest − 1|` (and
    /// penetration depth over the shortest segment) accepted as converged.
    pub projection_tolerance: f32,
}

impl Default for RodParams {
    fn default() -> Self {
        Self {
            youngs_modulus: 3.9e9,
            shear_modulus: 1.5e9,
            semi_major_axis: 2.5e-4,
            axis_ratio: 0.8,
            projection_iterations: 20,
            projection_tolerance: 1e-7,
        }
    }
}

impl RodParams {
    /// Checks moduli and the semi-major axis are finite and > 0, the ratio is in (0, 1], the
    /// iteration limit is ≥ 1 and the tolerance is finite and > 0.
    pub fn validate(&self) -> Result<()> {
        for (name, value, unit) in [
            ("rod.youngs_modulus", self.youngs_modulus, "Pa"),
            ("rod.shear_modulus", self.shear_modulus, "Pa"),
            ("rod.semi_major_axis", self.semi_major_axis, "m"),
            ("rod.projection_tolerance", self.projection_tolerance, ""),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(HairError::Parameter {
                    name: name.into(),
                    value: value.to_string(),
                    fix: format!("must be a finite number > 0 {unit}")
                        .trim_end()
                        .to_string(),
                });
            }
        }
        let r = self.axis_ratio;
        if !(r.is_finite() && r > 0.0 && r <= 1.0) {
            return Err(HairError::Parameter {
                name: "rod.axis_ratio".into(),
                value: r.to_string(),
                fix: "the cross-section ratio b/a must be in (0, 1]: 1 is a round strand, human \
                      hair is about 0.6–0.9"
                    .into(),
            });
        }
        if self.projection_iterations == 0 {
            return Err(HairError::Parameter {
                name: "rod.projection_iterations".into(),
                value: "0".into(),
                fix: "use at least 1 (about 3–5 are needed per substep, 20 is a safe limit)".into(),
            });
        }
        Ok(())
    }
}

/// Stiffness of the cross-section, N·m².
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stiffness {
    /// `E I₁`: bending over the major axis `m1` (the easy way), N·m².
    pub major: f64,
    /// `E I₂`: bending over the minor axis `m2` (stiff), N·m².
    pub minor: f64,
    /// `G J`: twisting, N·m².
    pub twist: f64,
}

impl Stiffness {
    /// The stiffness of an elliptical cross-section with `params`' size, ratio and moduli.
    pub fn of(params: &RodParams) -> Self {
        let a = params.semi_major_axis as f64;
        let b = a * params.axis_ratio as f64;
        let e = params.youngs_modulus as f64;
        let g = params.shear_modulus as f64;
        let pi = std::f64::consts::PI;
        Self {
            major: e * pi * a * b.powi(3) / 4.0,
            minor: e * pi * a.powi(3) * b / 4.0,
            twist: g * pi * a.powi(3) * b.powi(3) / (a * a + b * b),
        }
    }

    /// A round cross-section's stiffness with bending stiffness `ei` and twist stiffness `gj`
    /// (N·m²), for tests and hosts that give stiffnesses directly.
    pub fn isotropic(ei: f64, gj: f64) -> Self {
        Self {
            major: ei,
            minor: ei,
            twist: gj,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ellipse_bends_easily_over_its_major_axis() {
        let params = RodParams {
            axis_ratio: 0.5,
            ..RodParams::default()
        };
        let s = Stiffness::of(&params);
        assert!((s.minor / s.major - 4.0).abs() < 1e-9, "(a/b)² = 4");
        let round = Stiffness::of(&RodParams {
            axis_ratio: 1.0,
            ..RodParams::default()
        });
        // Round: J = 2I, and I = π a⁴ / 4.
        let a = params.semi_major_axis as f64;
        let i = std::f64::consts::PI * a.powi(4) / 4.0;
        assert!((round.major / (params.youngs_modulus as f64 * i) - 1.0).abs() < 1e-6);
        assert!((round.twist / (params.shear_modulus as f64 * 2.0 * i) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn non_positive_ratio_is_refused_by_name() {
        for ratio in [0.0, -0.5, 1.5, f32::NAN] {
            let err = RodParams {
                axis_ratio: ratio,
                ..RodParams::default()
            }
            .validate()
            .unwrap_err();
            assert!(err.to_string().contains("rod.axis_ratio"), "{err}");
        }
    }
}
