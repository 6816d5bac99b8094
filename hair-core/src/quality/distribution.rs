//! [`Distribution`]: count, maximum and quantiles of a non-negative quantity, accumulated in a
//! fixed log-spaced histogram so that reports of many frames merge by adding counts.
//!
//! Bins follow the bits of the `f32` value: the exponent and the top [`MANTISSA_BITS`] bits of
//! the mantissa, so each bin spans a relative width of 2⁻⁷ (0.8 %) from [`SMALLEST`] (2⁻³⁰ ≈
//! 9.3·10⁻¹⁰) to 2¹⁰ (1,024). A quantile is reported as the upper edge of the bin holding it
//! (never below the true value, at most 0.8 % above it), capped at the exact maximum; values
//! below [`SMALLEST`] (including 0) count as 0, and a quantile above 2¹⁰ reads 2¹⁰ (the
//! maximum stays exact). Binning costs a few integer operations per value.

#[cfg(feature = "serde")]
use serde::ser::SerializeStruct;
#[cfg(feature = "serde")]
use serde::{Serialize, Serializer};

/// Mantissa bits kept by a bin (relative bin width 2⁻⁷).
const MANTISSA_BITS: u32 = 7;
/// Exponents covered by the histogram: 2⁻³⁰ … 2¹⁰.
const EXPONENTS: u32 = 40;
/// Smallest value with a bin of its own; anything below counts as 0.
pub const SMALLEST: f32 = 1.0 / (1u64 << 30) as f32;
/// Bins: one for zero (and anything below [`SMALLEST`]), then `EXPONENTS × 2^MANTISSA_BITS`.
const BINS: usize = 1 + (EXPONENTS << MANTISSA_BITS) as usize;

/// Count, maximum and quantiles of a non-negative quantity (units those of the quantity).
/// Serialises as `{count, p50, p99, max}`.
#[derive(Clone, Default, PartialEq)]
pub struct Distribution {
    count: u64,
    max: f32,
    /// Counts per bin; empty until the first value.
    bins: Vec<u64>,
}

fn bin_of(value: f32) -> usize {
    if value.is_nan() || value < SMALLEST {
        return 0;
    }
    let shift = 23 - MANTISSA_BITS;
    let index = (value.to_bits() - SMALLEST.to_bits()) >> shift;
    1 + (index as usize).min(BINS - 2)
}

fn upper_edge(bin: usize) -> f32 {
    if bin == 0 {
        return 0.0;
    }
    let shift = 23 - MANTISSA_BITS;
    f32::from_bits(SMALLEST.to_bits() + ((bin as u32) << shift))
}

impl Distribution {
    /// An empty distribution.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds one value (negative values and NaN count as 0).
    pub fn add(&mut self, value: f32) {
        if self.bins.is_empty() {
            self.bins = vec![0; BINS];
        }
        self.bins[bin_of(value)] += 1;
        self.count += 1;
        if value > self.max {
            self.max = value;
        }
    }

    /// Adds `n` values of 0.
    pub fn add_zeros(&mut self, n: u64) {
        if n == 0 {
            return;
        }
        if self.bins.is_empty() {
            self.bins = vec![0; BINS];
        }
        self.bins[0] += n;
        self.count += n;
    }

    /// Adds every value of `other`.
    pub fn merge(&mut self, other: &Distribution) {
        if other.count == 0 {
            return;
        }
        if self.bins.is_empty() {
            self.bins = vec![0; BINS];
        }
        for (a, b) in self.bins.iter_mut().zip(&other.bins) {
            *a += b;
        }
        self.count += other.count;
        self.max = self.max.max(other.max);
    }

    /// Values added.
    pub fn count(&self) -> u64 {
        self.count
    }

    /// Largest value added (exact; 0 when empty).
    pub fn max(&self) -> f32 {
        self.max
    }

    /// The `q` quantile (`q` in [0, 1], clamped): the upper edge of the bin holding the value of
    /// rank `⌈q·count⌉`, capped at [`Distribution::max`]; 0 when empty.
    pub fn quantile(&self, q: f64) -> f32 {
        if self.count == 0 {
            return 0.0;
        }
        let rank = ((q.clamp(0.0, 1.0) * self.count as f64).ceil() as u64).max(1);
        let mut seen = 0;
        for (bin, &n) in self.bins.iter().enumerate() {
            seen += n;
            if seen >= rank {
                return upper_edge(bin).min(self.max);
            }
        }
        self.max
    }

    /// The median ([`Distribution::quantile`] 0.5).
    pub fn p50(&self) -> f32 {
        self.quantile(0.5)
    }

    /// The 99th percentile ([`Distribution::quantile`] 0.99).
    pub fn p99(&self) -> f32 {
        self.quantile(0.99)
    }
}

impl std::fmt::Debug for Distribution {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Distribution")
            .field("count", &self.count)
            .field("p50", &self.p50())
            .field("p99", &self.p99())
            .field("max", &self.max)
            .finish()
    }
}

#[cfg(feature = "serde")]
impl Serialize for Distribution {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut s = serializer.serialize_struct("Distribution", 4)?;
        s.serialize_field("count", &self.count)?;
        s.serialize_field("p50", &self.p50())?;
        s.serialize_field("p99", &self.p99())?;
        s.serialize_field("max", &self.max)?;
        s.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_are_within_one_bin_above_the_true_value() {
        let mut d = Distribution::new();
        // 1,000 values 1e-4 … 0.1 (spread over 3 decades), in a scrambled order.
        let values: Vec<f32> = (0..1000)
            .map(|i| 1e-4 * 10f32.powf(3.0 * ((i * 379) % 1000) as f32 / 999.0))
            .collect();
        for &v in &values {
            d.add(v);
        }
        let mut sorted = values.clone();
        sorted.sort_by(f32::total_cmp);
        for (q, rank) in [(0.5, 500), (0.99, 990)] {
            let truth = sorted[rank - 1];
            let got = d.quantile(q);
            assert!(
                got >= truth && got <= truth * 1.008,
                "q{q}: {got} vs {truth}"
            );
        }
        assert_eq!(d.max(), sorted[999]);
        assert_eq!(d.count(), 1000);
    }

    #[test]
    fn zeros_and_merging() {
        let mut a = Distribution::new();
        for _ in 0..60 {
            a.add(0.0);
        }
        let mut b = Distribution::new();
        for _ in 0..40 {
            b.add(0.01);
        }
        assert_eq!(a.p50(), 0.0);
        a.merge(&b);
        assert_eq!(a.count(), 100);
        assert_eq!(a.p50(), 0.0);
        assert_eq!(a.p99(), 0.01, "capped at the exact maximum");
        assert_eq!(Distribution::new().p99(), 0.0);
    }
}
