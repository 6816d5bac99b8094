//! Level of detail: render and display from the same code path.
//!
//! The display level keeps a prefix of each parent's children (child `k` of a parent is shown when
//! `k < ⌈fraction · n⌉`, rounding error of the fraction aside) and subdivides parents less. Because a child's random numbers depend only
//! on its parent and its index (module `rng`), every displayed child is the render child of the
//! same identity (same root, random value, UV, color), drawn with fewer points along the same
//! parent path.

use crate::error::{parameter, Result};

/// Reduced counts and steps for the viewport.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields, default))]
pub struct DisplayLod {
    /// Fraction of each parent's children shown, in (0, 1].
    pub fraction: f32,
    /// Catmull–Rom pieces per parent segment at display level (≥ 1; 1 = the parent's points).
    pub subdivisions: u32,
}

impl Default for DisplayLod {
    /// 10 % of the children, the parent's own points.
    fn default() -> Self {
        Self {
            fraction: 0.1,
            subdivisions: 1,
        }
    }
}

/// Which level to generate.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Lod {
    /// Every child, the settings' subdivisions.
    #[default]
    Render,
    /// A fraction of the children with fewer points each.
    Display(DisplayLod),
}

impl Lod {
    /// Checks the display settings, naming the field.
    pub fn validate(&self) -> Result<()> {
        if let Lod::Display(d) = self {
            if !(d.fraction.is_finite() && d.fraction > 0.0 && d.fraction <= 1.0) {
                return Err(parameter(
                    "display.fraction",
                    d.fraction,
                    "use a fraction of the children in (0, 1], e.g. 0.1",
                ));
            }
            check_subdivisions("display.subdivisions", d.subdivisions)?;
        }
        Ok(())
    }

    /// Number of a parent's `n` children shown at this level.
    pub fn children_shown(&self, n: u32) -> u32 {
        match self {
            Lod::Render => n,
            Lod::Display(d) => {
                // The tolerance keeps 0.1 (as f32, a hair above 0.1) of 20 at 2, not 3.
                let shown = f64::from(n) * f64::from(d.fraction) * (1.0 - 1e-7);
                (shown.ceil() as u32).min(n)
            }
        }
    }

    /// Subdivisions at this level, given the render level's.
    pub fn subdivisions(&self, render: u32) -> u32 {
        match self {
            Lod::Render => render,
            Lod::Display(d) => d.subdivisions,
        }
    }
}

/// Refuses subdivisions outside [1, 64], naming `name`.
pub(crate) fn check_subdivisions(name: &'static str, steps: u32) -> Result<()> {
    if (1..=64).contains(&steps) {
        Ok(())
    } else {
        Err(parameter(
            name,
            steps,
            "use 1 to 64 pieces per parent segment (1 keeps the parent's points)",
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_shows_a_rounded_up_fraction() {
        let lod = Lod::Display(DisplayLod {
            fraction: 0.1,
            subdivisions: 1,
        });
        assert_eq!(lod.children_shown(20), 2);
        assert_eq!(lod.children_shown(3), 1);
        assert_eq!(Lod::Render.children_shown(3), 3);
        let bad = Lod::Display(DisplayLod {
            fraction: f32::NAN,
            subdivisions: 1,
        });
        assert!(bad
            .validate()
            .unwrap_err()
            .to_string()
            .contains("display.fraction"));
    }
}
