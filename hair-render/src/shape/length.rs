//! Length variation: each child is a random fraction of its parent's length.
//!
//! A child's length factor is `1 − variation · ξ`, `ξ` uniform in [0, 1) per child, so
//! `variation = 0` keeps every child at its parent's length and `0.3` makes them 70–100 % long.

use crate::error::{check_range, Result};
use crate::rng::{ChildRng, Purpose};

/// Checks a length variation, naming the field.
pub fn validate(variation: f32) -> Result<()> {
    check_range(
        "shape.length_variation",
        variation,
        0.0,
        0.99,
        "use a fraction in [0, 0.99] (0 keeps every child at its parent's length)",
    )
}

/// Length factor of the child drawn by `rng`, in `(1 − variation, 1]`.
#[inline(always)]
pub(crate) fn factor(variation: f32, rng: &ChildRng) -> f32 {
    1.0 - variation * rng.unit(Purpose::Length, 0)
}
