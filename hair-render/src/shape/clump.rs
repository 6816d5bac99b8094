//! Clumping: children drawn towards their parent along the length.
//!
//! A child's offset from its parent is scaled by `1 − factor · s^shape` at normalized length
//! `s ∈ [0, 1]` (root 0, tip 1). `factor = 1` puts the child's tip on the parent's path (on the
//! parent's tip when the child has the parent's length); a negative factor spreads the tips out
//! instead. `shape` is the exponent of the profile: 1 linear, < 1 clumps early (tight wisps),
//! > 1 clumps only near the tip.

use crate::error::{check_range, Result};

/// Clump factor and shape (both dimensionless).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields, default))]
pub struct Clump {
    /// How far tips are drawn to the parent, in [−1, 1]: 1 on the parent, 0 none, −1 twice as far.
    pub factor: f32,
    /// Exponent of the clump profile along the length, in (0, 100]; 1 is linear.
    pub shape: f32,
}

impl Default for Clump {
    fn default() -> Self {
        Self {
            factor: 0.0,
            shape: 1.0,
        }
    }
}

impl Clump {
    /// Checks the ranges, naming the field.
    pub fn validate(&self) -> Result<()> {
        check_range(
            "shape.clump.factor",
            self.factor,
            -1.0,
            1.0,
            "use a value in [-1, 1] (1 draws the tips onto the parent)",
        )?;
        check_range(
            "shape.clump.shape",
            self.shape,
            1e-3,
            100.0,
            "use an exponent in [0.001, 100] (1 is linear)",
        )
    }

    /// Scale of the child's offset at normalized length `s`: `1 − factor · s^shape`.
    #[inline(always)]
    pub fn offset_scale(&self, s: f32) -> f32 {
        if self.factor == 0.0 {
            return 1.0;
        }
        let p = if self.shape == 1.0 {
            s
        } else {
            s.powf(self.shape)
        };
        1.0 - self.factor * p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn full_clump_reaches_zero_at_the_tip() {
        let c = Clump {
            factor: 1.0,
            shape: 0.5,
        };
        assert_eq!(c.offset_scale(1.0), 0.0);
        assert_eq!(c.offset_scale(0.0), 1.0);
        assert!(c.offset_scale(0.25) < 0.75, "shape < 1 clumps early");
        assert!(Clump {
            factor: f32::NAN,
            shape: 1.0
        }
        .validate()
        .is_err());
    }
}
