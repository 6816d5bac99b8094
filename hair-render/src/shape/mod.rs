//! Shaping of children, one concern per file: [`clump`], [`curl`], [`roughness`], [`length`]
//! variation and width [`taper`]. [`Shape`] gathers them with the root ramp that keeps curl and
//! roughness from lifting a child's root off the scalp.
//!
//! Order of application at normalized length `s` of a child (its own length after variation):
//! the parent's point and frame at that length, plus the child's root offset carried by the frame
//! and scaled by the clump profile, plus curl around that clumped path, plus roughness.

pub mod clump;
pub mod curl;
pub mod length;
pub mod roughness;
pub mod taper;

pub use clump::Clump;
pub use curl::Curl;
pub use roughness::Roughness;
pub use taper::Taper;

use crate::error::{check_range, Result};

/// Every shaping setting of children.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shape {
    /// Clumping towards the parent.
    pub clump: Clump,
    /// Helical curl around the clumped path.
    pub curl: Curl,
    /// Seeded noise.
    pub roughness: Roughness,
    /// Random shortening per child, fraction in [0, 0.99].
    pub length_variation: f32,
    /// Width from root to tip.
    pub taper: Taper,
    /// Fraction of the length (in [0, 1)) over which curl and roughness grow from 0 at the root
    /// to full (smoothstep), so roots stay on the scalp.
    pub root_ramp: f32,
}

impl Default for Shape {
    /// No clump, curl, roughness or length variation; default taper; 5 % root ramp.
    fn default() -> Self {
        Self {
            clump: Clump::default(),
            curl: Curl::default(),
            roughness: Roughness::default(),
            length_variation: 0.0,
            taper: Taper::default(),
            root_ramp: 0.05,
        }
    }
}

impl Shape {
    /// Checks every field, naming the first bad one and its fix.
    pub fn validate(&self) -> Result<()> {
        self.clump.validate()?;
        self.curl.validate()?;
        self.roughness.validate()?;
        length::validate(self.length_variation)?;
        self.taper.validate()?;
        check_range(
            "shape.root_ramp",
            self.root_ramp,
            0.0,
            0.99,
            "use a fraction of the length in [0, 0.99] (e.g. 0.05)",
        )
    }

    /// Ramp factor in [0, 1] at normalized length `s`.
    #[inline(always)]
    pub(crate) fn ramp(&self, s: f32) -> f32 {
        if s >= self.root_ramp {
            1.0
        } else {
            let x = s / self.root_ramp;
            x * x * (3.0 - 2.0 * x)
        }
    }
}
