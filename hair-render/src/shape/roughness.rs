//! Roughness: seeded noise that breaks up the regularity of children.
//!
//! Three kinds, each a per-child random offset in the plane of the parent's frame `(u, w)`:
//! - **uniform**: value noise along the length with a short wavelength (`uniform_size`, m) and
//!   linear interpolation between lattice values, the same amplitude all along the hair (frizz);
//! - **endpoint**: one random direction per child, amplitude `endpoint · s^endpoint_shape`
//!   (0 at the root, full at the tip: splayed ends);
//! - **smooth**: value noise with a long wavelength (`smooth_size`, m) and smoothstep
//!   interpolation (slow waves).
//!
//! The noise is a function of the child's identity and its arc length, not of the point index,
//! so the display level's fewer points lie on the render level's curve.

use nalgebra::Vector3;

use crate::error::{check_range, Result};
use crate::rng::{ChildRng, Purpose};

/// Amplitudes (meters) and sizes of the three roughness kinds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Roughness {
    /// Amplitude of the uniform noise, meters (≥ 0).
    pub uniform: f32,
    /// Wavelength of the uniform noise, meters (> 0).
    pub uniform_size: f32,
    /// Tip amplitude of the endpoint roughness, meters (≥ 0).
    pub endpoint: f32,
    /// Exponent of the endpoint roughness along the length (> 0; 1 linear).
    pub endpoint_shape: f32,
    /// Amplitude of the smooth noise, meters (≥ 0).
    pub smooth: f32,
    /// Wavelength of the smooth noise, meters (> 0).
    pub smooth_size: f32,
}

impl Default for Roughness {
    fn default() -> Self {
        Self {
            uniform: 0.0,
            uniform_size: 0.002,
            endpoint: 0.0,
            endpoint_shape: 1.0,
            smooth: 0.0,
            smooth_size: 0.05,
        }
    }
}

impl Roughness {
    /// Checks the ranges, naming the field.
    pub fn validate(&self) -> Result<()> {
        let amp = "use an amplitude in meters in [0, 1]";
        let size = "use a wavelength in meters in [1e-6, 100]";
        check_range("shape.roughness.uniform", self.uniform, 0.0, 1.0, amp)?;
        check_range(
            "shape.roughness.uniform_size",
            self.uniform_size,
            1e-6,
            100.0,
            size,
        )?;
        check_range("shape.roughness.endpoint", self.endpoint, 0.0, 1.0, amp)?;
        check_range(
            "shape.roughness.endpoint_shape",
            self.endpoint_shape,
            1e-3,
            100.0,
            "use an exponent in [0.001, 100] (1 is linear)",
        )?;
        check_range("shape.roughness.smooth", self.smooth, 0.0, 1.0, amp)?;
        check_range(
            "shape.roughness.smooth_size",
            self.smooth_size,
            1e-6,
            100.0,
            size,
        )
    }

    /// True when roughness changes nothing.
    pub fn is_off(&self) -> bool {
        self.uniform == 0.0 && self.endpoint == 0.0 && self.smooth == 0.0
    }

    /// Endpoint profile at normalized length `s`: `s^endpoint_shape` (the same for every child,
    /// so callers tabulate it per point).
    #[inline(always)]
    pub fn endpoint_profile(&self, s: f32) -> f32 {
        if self.endpoint_shape == 1.0 {
            s
        } else {
            s.powf(self.endpoint_shape)
        }
    }

    /// The child's endpoint offset at the tip in frame components `(u, w)`, meters.
    #[inline(always)]
    pub(crate) fn endpoint_direction(&self, rng: &ChildRng) -> (f32, f32) {
        (
            rng.signed(Purpose::Endpoint, 0) * self.endpoint,
            rng.signed(Purpose::Endpoint, 1) * self.endpoint,
        )
    }

    /// Offset (meters) of a child (`rng`, endpoint direction `end` from
    /// [`Roughness::endpoint_direction`]) at arc length `arc` (m), with endpoint profile
    /// `end_profile`, `ramp` ∈ [0, 1] near the root and the frame's `u`, `w`.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(crate) fn offset(
        &self,
        rng: &ChildRng,
        end: (f32, f32),
        end_profile: f32,
        arc: f32,
        ramp: f32,
        u: &Vector3<f32>,
        w: &Vector3<f32>,
    ) -> Vector3<f32> {
        let (mut a, mut b) = (end.0 * end_profile, end.1 * end_profile);
        if self.uniform > 0.0 {
            let (x, y) = noise(rng, Purpose::UniformNoise, arc / self.uniform_size, false);
            a += x * self.uniform;
            b += y * self.uniform;
        }
        if self.smooth > 0.0 {
            let (x, y) = noise(rng, Purpose::SmoothNoise, arc / self.smooth_size, true);
            a += x * self.smooth;
            b += y * self.smooth;
        }
        (u * a + w * b) * ramp
    }
}

/// Two channels of 1D value noise in [−1, 1] at lattice coordinate `x ≥ 0`, interpolated
/// linearly or by smoothstep.
#[inline(always)]
fn noise(rng: &ChildRng, purpose: Purpose, x: f32, smooth: bool) -> (f32, f32) {
    let j = x.floor();
    let mut f = x - j;
    if smooth {
        f = f * f * (3.0 - 2.0 * f);
    }
    let j = j as u64;
    let v = |k: u64| rng.signed(purpose, k);
    let a = v(2 * j) + (v(2 * j + 2) - v(2 * j)) * f;
    let b = v(2 * j + 1) + (v(2 * j + 3) - v(2 * j + 1)) * f;
    (a, b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_is_bounded_and_continuous() {
        let rng = ChildRng::new(1, 2, 3);
        let r = Roughness {
            uniform: 0.001,
            smooth: 0.002,
            endpoint: 0.003,
            ..Default::default()
        };
        let (u, w) = (Vector3::x(), Vector3::y());
        let end = r.endpoint_direction(&rng);
        let mut prev = r.offset(&rng, end, 0.0, 0.0, 1.0, &u, &w);
        for i in 1..=1000 {
            let arc = i as f32 * 1e-4;
            let o = r.offset(&rng, end, r.endpoint_profile(arc / 0.1), arc, 1.0, &u, &w);
            assert!(o.norm() <= (0.006f32 * 2.0).sqrt() * 1.5);
            assert!((o - prev).norm() < 2e-4, "jump at {i}");
            prev = o;
        }
    }
}
