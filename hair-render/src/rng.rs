//! Counter-based random numbers: every value is a hash of (seed, parent, child, purpose, index).
//!
//! A child's randoms depend only on its identity (its parent and its index among that parent's
//! children), never on how many children were made before it or on which thread made it. So the
//! same seed gives bit-identical children at any thread count, and the display level (a prefix of
//! each parent's children) draws exactly the numbers of the same children at render level.
//! The hash is SplitMix64's finaliser applied to a chained mix of the inputs.

/// What a random number is for; each purpose is an independent stream.
#[derive(Debug, Clone, Copy)]
#[repr(u64)]
pub(crate) enum Purpose {
    /// Radius of the child's root in the parent's disc.
    DiscRadius = 1,
    /// Angle of the child's root in the parent's disc.
    DiscAngle,
    /// Length variation.
    Length,
    /// Phase of the curl helix.
    CurlPhase,
    /// The per-child random value handed to shaders.
    Value,
    /// Direction of the endpoint roughness (three components follow).
    Endpoint,
    /// Lattice of the uniform roughness noise.
    UniformNoise = 16,
    /// Lattice of the smooth roughness noise.
    SmoothNoise = 32,
}

/// SplitMix64's output function.
#[inline(always)]
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The random stream of one child: its key is fixed by (seed, parent, child).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ChildRng {
    key: u64,
}

impl ChildRng {
    /// The stream of child `child` of parent `parent` under `seed`.
    pub(crate) fn new(seed: u64, parent: u32, child: u32) -> Self {
        let k = mix(seed ^ 0x9e37_79b9_7f4a_7c15);
        let k = mix(k ^ u64::from(parent).wrapping_mul(0x9e37_79b9_7f4a_7c15));
        Self {
            key: mix(k ^ u64::from(child).wrapping_mul(0xd1b5_4a32_d192_ed03)),
        }
    }

    /// A uniform value in [0, 1) for `purpose` at `index` (24 random bits).
    #[inline(always)]
    pub(crate) fn unit(&self, purpose: Purpose, index: u64) -> f32 {
        // The key is already mixed: one more round over (purpose, index) decorrelates streams.
        let h =
            mix(self.key ^ ((purpose as u64) << 56) ^ index.wrapping_mul(0x9e37_79b9_7f4a_7c15));
        // Through i32: one conversion instruction (u64 → f32 is a branchy sequence on x86-64).
        ((h >> 40) as i32) as f32 * (1.0 / (1u64 << 24) as f32)
    }

    /// A uniform value in [−1, 1) for `purpose` at `index`.
    #[inline(always)]
    pub(crate) fn signed(&self, purpose: Purpose, index: u64) -> f32 {
        2.0 * self.unit(purpose, index) - 1.0
    }

    /// Two uniform values in [−1, 1) for `purpose` at `index` (24 bits each) from one multiply
    /// and shift of the already well-mixed key: the cheap draw of the per-point noise lattices
    /// (value noise needs no more than decorrelated neighbours).
    #[inline(always)]
    pub(crate) fn signed_pair(&self, purpose: Purpose, index: u64) -> (f32, f32) {
        let h = (self.key ^ ((purpose as u64) << 56) ^ index.wrapping_mul(0x9e37_79b9_7f4a_7c15))
            .wrapping_mul(0xd1b5_4a32_d192_ed03);
        let h = h ^ (h >> 29);
        let scale = 2.0 / (1u64 << 24) as f32;
        (
            ((h >> 40) as i32) as f32 * scale - 1.0,
            (((h >> 8) & 0xff_ffff) as i32) as f32 * scale - 1.0,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_uniform_and_independent() {
        let rng = ChildRng::new(7, 3, 11);
        let n = 20_000;
        let mean: f32 = (0..n).map(|i| rng.unit(Purpose::Value, i)).sum::<f32>() / n as f32;
        assert!((mean - 0.5).abs() < 0.01, "mean {mean}");
        let other = ChildRng::new(7, 3, 12);
        assert_ne!(rng.unit(Purpose::Value, 0), other.unit(Purpose::Value, 0));
        assert_ne!(rng.unit(Purpose::Value, 0), rng.unit(Purpose::Length, 0));
    }
}
