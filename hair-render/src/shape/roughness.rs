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

use crate::error::{check_range, Result};
use crate::rng::{ChildRng, Purpose};

/// Amplitudes (meters) and sizes of the three roughness kinds.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields, default))]
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

    /// Adds the roughness of the child drawn by `rng` at arc lengths `arc` (m) to the frame
    /// components `a` (along u) and `b` (along w), meters, scaled by the root ramp `ramp`;
    /// `end_profile` is [`Roughness::endpoint_profile`] at each point. One pass per kind, so each
    /// loop is short and free of the others' dependencies.
    #[inline(always)]
    pub(crate) fn add(
        &self,
        rng: &ChildRng,
        end_profile: &[f32],
        arc: &[f32],
        ramp: &[f32],
        a: &mut [f32],
        b: &mut [f32],
    ) {
        let n = a.len();
        let (arc, ramp, end_profile, b) = (&arc[..n], &ramp[..n], &end_profile[..n], &mut b[..n]);
        if self.endpoint > 0.0 {
            let (ea, eb) = self.endpoint_direction(rng);
            for i in 0..n {
                let k = end_profile[i] * ramp[i];
                a[i] += ea * k;
                b[i] += eb * k;
            }
        }
        if self.uniform > 0.0 {
            let inv = 1.0 / self.uniform_size;
            let amp = self.uniform;
            for i in 0..n {
                let (x, y) = linear_noise(rng, Purpose::UniformNoise, arc[i] * inv);
                a[i] += x * amp * ramp[i];
                b[i] += y * amp * ramp[i];
            }
        }
        if self.smooth > 0.0 {
            let inv = 1.0 / self.smooth_size;
            let amp = self.smooth;
            let mut lattice = Lattice::default();
            for i in 0..n {
                let (x, y) = lattice.smooth(rng, Purpose::SmoothNoise, arc[i] * inv);
                a[i] += x * amp * ramp[i];
                b[i] += y * amp * ramp[i];
            }
        }
    }
}

/// Two channels of linearly interpolated 1D value noise in [−1, 1] at lattice coordinate `x` in
/// [0, 2³¹). Short-wavelength noise moves to a new cell at almost every point, so both ends are
/// hashed every time, without a branch.
#[inline(always)]
fn linear_noise(rng: &ChildRng, purpose: Purpose, x: f32) -> (f32, f32) {
    // x ≥ 0: truncation is the floor (a 32-bit cast, no libm call, no range branch).
    let cell = x as i32;
    let f = x - cell as f32;
    let j = cell as u64;
    let lo = rng.signed_pair(purpose, j);
    let hi = rng.signed_pair(purpose, j + 1);
    (lo.0 + (hi.0 - lo.0) * f, lo.1 + (hi.1 - lo.1) * f)
}

/// Two channels of smoothstep-interpolated 1D value noise in [−1, 1] on the integer lattice,
/// keeping the values at the ends of the last cell looked up (a child's points walk up its length,
/// so each lattice value is hashed about once). The values depend only on the child and the
/// lattice index, so the result is the same whatever order points are asked in.
#[derive(Debug, Clone, Copy)]
struct Lattice {
    /// Index of the cell whose end values are held (`u64::MAX`: none yet).
    cell: u64,
    /// Values at `cell` and `cell + 1`.
    lo: (f32, f32),
    hi: (f32, f32),
}

impl Default for Lattice {
    fn default() -> Self {
        Self {
            cell: u64::MAX,
            lo: (0.0, 0.0),
            hi: (0.0, 0.0),
        }
    }
}

impl Lattice {
    /// Noise at lattice coordinate `x` in [0, 2³¹).
    #[inline(always)]
    fn smooth(&mut self, rng: &ChildRng, purpose: Purpose, x: f32) -> (f32, f32) {
        let cell = x as i32;
        let f = x - cell as f32;
        let f = f * f * (3.0 - 2.0 * f);
        let j = cell as u64;
        if j != self.cell {
            self.lo = if j == self.cell.wrapping_add(1) {
                self.hi
            } else {
                rng.signed_pair(purpose, j)
            };
            self.hi = rng.signed_pair(purpose, j + 1);
            self.cell = j;
        }
        (
            self.lo.0 + (self.hi.0 - self.lo.0) * f,
            self.lo.1 + (self.hi.1 - self.lo.1) * f,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_is_bounded_continuous_and_independent_of_the_order_of_points() {
        let rng = ChildRng::new(1, 2, 3);
        let r = Roughness {
            uniform: 0.001,
            smooth: 0.002,
            endpoint: 0.003,
            ..Default::default()
        };
        let arc: Vec<f32> = (0..=1000).map(|i| i as f32 * 1e-4).collect();
        let prof: Vec<f32> = arc.iter().map(|s| r.endpoint_profile(s / 0.1)).collect();
        let ramp = vec![1.0; arc.len()];
        let (mut a, mut b) = (vec![0.0; arc.len()], vec![0.0; arc.len()]);
        r.add(&rng, &prof, &arc, &ramp, &mut a, &mut b);
        for i in 0..arc.len() {
            assert!(a[i].hypot(b[i]) <= (0.006f32 * 2.0).sqrt() * 1.5);
            if i > 0 {
                assert!(
                    (a[i] - a[i - 1]).hypot(b[i] - b[i - 1]) < 2e-4,
                    "jump at {i}"
                );
            }
            // The point alone (nothing memoised) gives the same value.
            let (mut x, mut y) = ([0.0], [0.0]);
            r.add(&rng, &prof[i..], &arc[i..], &ramp[i..], &mut x, &mut y);
            assert_eq!((a[i], b[i]), (x[0], y[0]), "at {i}");
        }
    }
}
