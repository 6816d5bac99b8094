//! Width taper from root to tip.
//!
//! Width (a curve's diameter, as USD `widths` and Cycles take it) at normalized length `s` is
//! `root + (tip − root) · s^shape`.

use crate::error::{check_range, Result};

/// Root and tip widths (meters) and the taper exponent.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields, default))]
pub struct Taper {
    /// Width at the root, meters (diameter, ≥ 0).
    pub root: f32,
    /// Width at the tip, meters (diameter, ≥ 0).
    pub tip: f32,
    /// Exponent of the taper along the length (> 0; 1 linear, larger keeps the width longer).
    pub shape: f32,
}

impl Default for Taper {
    /// 80 µm at the root to 20 µm at the tip, linear (human scalp hair).
    fn default() -> Self {
        Self {
            root: 80e-6,
            tip: 20e-6,
            shape: 1.0,
        }
    }
}

impl Taper {
    /// Checks the ranges, naming the field.
    pub fn validate(&self) -> Result<()> {
        let width = "use a width (diameter) in meters in [0, 1], e.g. 8e-5";
        check_range("shape.taper.root", self.root, 0.0, 1.0, width)?;
        check_range("shape.taper.tip", self.tip, 0.0, 1.0, width)?;
        check_range(
            "shape.taper.shape",
            self.shape,
            1e-3,
            100.0,
            "use an exponent in [0.001, 100] (1 is linear)",
        )
    }

    /// Width (meters) at normalized length `s`.
    #[inline(always)]
    pub fn width(&self, s: f32) -> f32 {
        let p = if self.shape == 1.0 {
            s
        } else {
            s.powf(self.shape)
        };
        self.root + (self.tip - self.root) * p
    }
}
