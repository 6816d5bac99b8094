//! Shape measures of one frame: segment strain, hairpin folds and drift from a reference shape.

#[cfg(feature = "serde")]
use serde::Serialize;

use super::distribution::Distribution;

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
pub(crate) struct DriftSums {
    pub squares: f64,
    pub points: u64,
    pub tip_squares: f64,
    pub tips: u64,
}

impl Drift {
    pub(crate) fn finish(sums: DriftSums, max: f32, tip_max: f32) -> Self {
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
