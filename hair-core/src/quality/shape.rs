//! Shape measures of one frame: segment strain, hairpin folds and drift from a reference shape.

use nalgebra::Vector3;
#[cfg(feature = "serde")]
use serde::Serialize;

use super::distribution::Distribution;
use super::Frame;

/// Cosine of the turn angle above which a point is a hairpin: turns of more than 90°.
const HAIRPIN_COS: f32 = 0.0;

/// Segment strain `len/rest − 1`, split into its two signs.
#[derive(Debug, Clone, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct Strain {
    /// Stretch of every segment, `max(0, len/rest − 1)` (dimensionless; 0.01 = 1 %).
    pub stretch: Distribution,
    /// Compression of every segment, `max(0, 1 − len/rest)` (dimensionless).
    pub compression: Distribution,
}

impl Strain {
    /// Adds another frame's (or run's) segments.
    pub fn merge(&mut self, other: &Strain) {
        self.stretch.merge(&other.stretch);
        self.compression.merge(&other.compression);
    }
}

/// Hairpin folds: interior points where the strand turns by more than 90° (the angle between
/// the segments before and after the point).
#[derive(Debug, Clone, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct Hairpins {
    /// Points turning by more than 90°, summed over frames.
    pub count: u64,
    /// The most hairpins in any one frame.
    pub worst_frame: u64,
    /// The largest turn at any interior point, degrees (0 for straight strands).
    pub max_turn_deg: f32,
}

impl Hairpins {
    /// Adds another frame's (or run's) hairpins.
    pub fn merge(&mut self, other: &Hairpins) {
        self.count += other.count;
        self.worst_frame = self.worst_frame.max(other.worst_frame);
        self.max_turn_deg = self.max_turn_deg.max(other.max_turn_deg);
    }
}

/// Distance of points from a reference shape (the groom or rest positions), for "does the shape
/// hold after settling".
#[derive(Debug, Clone, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct Drift {
    /// Root-mean-square distance of the free points from their reference, m.
    pub rms: f32,
    /// Largest distance of a free point from its reference, m.
    pub max: f32,
    /// Root-mean-square distance of the tips (last points) from their reference, m.
    pub tip_rms: f32,
    /// Largest distance of a tip from its reference, m.
    pub tip_max: f32,
    #[cfg_attr(feature = "serde", serde(skip))]
    sums: DriftSums,
}

/// Running sums behind [`Drift`]'s root-mean-squares.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct DriftSums {
    squares: f64,
    points: u64,
    tip_squares: f64,
    tips: u64,
}

impl Drift {
    fn finish(sums: DriftSums, max: f32, tip_max: f32) -> Self {
        let rms = |s: f64, n: u64| {
            if n > 0 {
                (s / n as f64).sqrt() as f32
            } else {
                0.0
            }
        };
        Self {
            rms: rms(sums.squares, sums.points),
            max,
            tip_rms: rms(sums.tip_squares, sums.tips),
            tip_max,
            sums,
        }
    }

    /// Adds another frame's (or run's) distances.
    pub fn merge(&mut self, other: &Drift) {
        let s = DriftSums {
            squares: self.sums.squares + other.sums.squares,
            points: self.sums.points + other.sums.points,
            tip_squares: self.sums.tip_squares + other.sums.tip_squares,
            tips: self.sums.tips + other.sums.tips,
        };
        *self = Self::finish(s, self.max.max(other.max), self.tip_max.max(other.tip_max));
    }
}

/// Strain of every segment of `frame`.
pub(crate) fn strain(frame: &Frame) -> Strain {
    let mut out = Strain::default();
    for s in 0..frame.strands() {
        let points = frame.points(s);
        let first_segment = points.start - s;
        for (k, i) in (points.start..points.end - 1).enumerate() {
            let len = (frame.positions[i + 1] - frame.positions[i]).norm();
            let e = len / frame.rest_lengths[first_segment + k] - 1.0;
            out.stretch.add(e.max(0.0));
            out.compression.add((-e).max(0.0));
        }
    }
    out
}

/// Hairpins of `frame`.
pub(crate) fn hairpins(frame: &Frame) -> Hairpins {
    let mut count = 0u64;
    let mut min_cos = 1.0f32;
    for s in 0..frame.strands() {
        let p = &frame.positions[frame.points(s)];
        for w in p.windows(3) {
            let (a, b) = (w[1] - w[0], w[2] - w[1]);
            let norms = a.norm() * b.norm();
            if norms <= 0.0 {
                continue;
            }
            let cos = (a.dot(&b) / norms).clamp(-1.0, 1.0);
            min_cos = min_cos.min(cos);
            if cos < HAIRPIN_COS {
                count += 1;
            }
        }
    }
    Hairpins {
        count,
        worst_frame: count,
        max_turn_deg: min_cos.acos().to_degrees(),
    }
}

/// Distances of `frame`'s free points from `reference` (same layout, m).
pub(crate) fn drift(frame: &Frame, reference: &[Vector3<f32>]) -> Drift {
    let mut sums = DriftSums::default();
    let (mut max, mut tip_max) = (0.0f32, 0.0f32);
    for s in 0..frame.strands() {
        let points = frame.points(s);
        for i in points.clone() {
            if !frame.is_free(i) {
                continue;
            }
            let d = (frame.positions[i] - reference[i]).norm();
            sums.squares += (d as f64).powi(2);
            sums.points += 1;
            max = max.max(d);
            if i + 1 == points.end {
                sums.tip_squares += (d as f64).powi(2);
                sums.tips += 1;
                tip_max = tip_max.max(d);
            }
        }
    }
    Drift::finish(sums, max, tip_max)
}
