//! Curl: a helix around the clumped path.
//!
//! At arc length `a` along the parent's path (meters from the root) the point is moved by
//! `r(s) (cos θ u + sin θ w)`, `θ = 2π f a + φ`, where `(u, w)` is the parent's transported frame
//! there, `f` the frequency in turns per meter and `φ` a random phase per child. On a straight
//! stretch this is a circular helix of radius `r` and pitch `1/f` around the clumped path; the
//! radius ramps in from 0 at the root over the shape's root ramp so the root stays on the scalp.

use nalgebra::Vector3;

use crate::error::{check_range, Result};

/// Curl radius and frequency.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
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

    /// Curl offset (meters) at arc length `arc` (m) with `ramp` ∈ [0, 1] of the radius, phase
    /// `phase` (radians) and the frame's normal `u` and binormal `w`.
    #[inline(always)]
    pub fn offset(
        &self,
        arc: f32,
        ramp: f32,
        phase: f32,
        u: &Vector3<f32>,
        w: &Vector3<f32>,
    ) -> Vector3<f32> {
        let (s, c) = (std::f32::consts::TAU * self.frequency * arc + phase).sin_cos();
        (u * c + w * s) * (self.radius * ramp)
    }
}
