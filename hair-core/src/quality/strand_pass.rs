//! The measures taken strand by strand — strain, hairpins, drift from a reference shape and the
//! velocity–position mismatch — in one pass over each strand's points.
//!
//! A frame is a few arrays of points (positions, velocities, the previous frame's, the
//! reference), so these measures are bound by reading memory, not by arithmetic: one pass that
//! reads each point once and takes every measure from it costs about what reading the frame
//! costs. Each segment's vector and length serve its strain and the hairpin test at both of its
//! ends; a reference posed by root frames ([`Reference::Posed`]) is computed point by point,
//! never stored. Chunks of [`STRANDS_PER_CHUNK`] strands run in parallel and merge in order, so
//! the floating-point sums do not depend on the thread count.
//!
//! # Velocity–position mismatch
//! For each point, `|(x₁ − x₀)/Δt − (v₀ + v₁)/2|` (m/s): the mean velocity the positions imply
//! against the trapezoidal mean of the stored ones. It is exactly 0 for motion of constant
//! acceleration (the trapezoid rule integrates a linear velocity exactly), `Δt²/12 |x⁽³⁾|` for
//! smooth motion, and it reads any velocity the solver stores but the point did not move with
//! (a stale or missing correction) directly: a stored velocity off by `δ` at both frames gives
//! `δ`. Cubic Hermite sampling between the frames (how `hair-cache` samples sub-frames) then
//! leaves the path by up to about `0.1 Δt δ` (the largest value of the Hermite tangent basis
//! `h₁₀ + h₁₁ = s(1 − s)(1 − 2s)` on [0, 1] is 0.096).

use std::ops::Range;

use hair_par::prelude::*;
use nalgebra::{Matrix3, Vector3};

use super::distribution::Distribution;
use super::shape::{Drift, DriftSums, Hairpins, Strain};
use super::{merge_option, Frame, Previous, Reference};

/// Strands per chunk: fixed, so the chunks (and the order their sums merge in) do not depend on
/// the thread count.
const STRANDS_PER_CHUNK: usize = 1024;

/// A point where the strand turns by more than 90° (cosine below 0) is a hairpin.
const HAIRPIN_COS: f32 = 0.0;

/// The per-strand measures of one chunk of strands or, merged, of a frame.
#[derive(Default)]
pub(crate) struct StrandMeasures {
    pub strain: Strain,
    pub hairpins: Hairpins,
    pub drift: Option<Drift>,
    pub velocity_mismatch: Option<Distribution>,
}

impl StrandMeasures {
    /// Adds the next chunk of the same frame (hairpins add up within a frame).
    fn add_chunk(&mut self, chunk: StrandMeasures) {
        self.strain.merge(&chunk.strain);
        self.hairpins.count += chunk.hairpins.count;
        self.hairpins.worst_frame = self.hairpins.count;
        self.hairpins.max_turn_deg = self.hairpins.max_turn_deg.max(chunk.hairpins.max_turn_deg);
        merge_option(&mut self.drift, &chunk.drift, Drift::merge);
        merge_option(
            &mut self.velocity_mismatch,
            &chunk.velocity_mismatch,
            Distribution::merge,
        );
    }
}

/// Strain, hairpins, drift (with a `reference`) and velocity–position mismatch (with a
/// `previous` frame) of `frame`. The caller has checked every array against the frame's layout.
pub(crate) fn measure(
    frame: &Frame,
    previous: Option<&Previous>,
    reference: Option<&Reference>,
) -> StrandMeasures {
    let strands = frame.strands();
    let chunks: Vec<StrandMeasures> = (0..strands.div_ceil(STRANDS_PER_CHUNK))
        .into_par_iter()
        .map(|c| {
            let range = c * STRANDS_PER_CHUNK..((c + 1) * STRANDS_PER_CHUNK).min(strands);
            measure_chunk(frame, previous, reference, range)
        })
        .collect();
    let mut out = StrandMeasures::default();
    for chunk in chunks {
        out.add_chunk(chunk);
    }
    out
}

/// The measures of strands `range` of `frame`.
fn measure_chunk(
    frame: &Frame,
    previous: Option<&Previous>,
    reference: Option<&Reference>,
    range: Range<usize>,
) -> StrandMeasures {
    let mut strain = Strain::default();
    let (mut pins, mut min_cos) = (0u64, 1.0f32);
    let mut mismatch = previous.map(|_| Distribution::new());
    let mut sums = DriftSums::default();
    let (mut drift_max, mut tip_max) = (0.0f32, 0.0f32);
    // Segments that neither stretch nor compress count as 0 in the other distribution; adding
    // those zeros in bulk saves a histogram update per segment.
    let (mut not_stretched, mut not_compressed) = (0u64, 0u64);
    let inv_dt = previous.map_or(0.0, |p| 1.0 / p.dt);
    let x = frame.positions;
    for s in range {
        let points = frame.points(s);
        let first_segment = points.start - s;
        // The reference of this strand: positions, or its root's rotation and origin.
        let posed = match reference {
            Some(Reference::Posed { roots, .. }) => {
                let r = &roots[s];
                Some((r.rotation.to_rotation_matrix().into_inner(), r.origin))
            }
            _ => None,
        };
        let mut last_segment: Option<(Vector3<f32>, f32)> = None;
        for (k, i) in points.clone().enumerate() {
            if let (Some(p), Some(out)) = (previous, mismatch.as_mut()) {
                let implied = (x[i] - p.positions[i]) * inv_dt;
                out.add((implied - (p.velocities[i] + frame.velocities[i]) * 0.5).norm());
            }
            let free = match frame.inverse_masses {
                Some(w) => w[i] > 0.0,
                None => k != 0,
            };
            if let (true, Some(r)) = (free, reference) {
                let target = match (r, &posed) {
                    (Reference::Positions(p), _) => p[i],
                    (Reference::Posed { rest_local, .. }, Some((m, origin))) => {
                        posed_point(m, origin, &rest_local[i])
                    }
                    (Reference::Posed { .. }, None) => unreachable!("posed is set for Posed"),
                };
                let d = (x[i] - target).norm();
                let d2 = f64::from(d) * f64::from(d);
                sums.squares += d2;
                sums.points += 1;
                drift_max = drift_max.max(d);
                if i + 1 == points.end {
                    sums.tip_squares += d2;
                    sums.tips += 1;
                    tip_max = tip_max.max(d);
                }
            }
            if i + 1 < points.end {
                let segment = x[i + 1] - x[i];
                let len = segment.norm();
                let e = len / frame.rest_lengths[first_segment + k] - 1.0;
                if e > 0.0 {
                    strain.stretch.add(e);
                    not_compressed += 1;
                } else {
                    strain.compression.add(-e);
                    not_stretched += 1;
                }
                if let Some((before, before_len)) = last_segment {
                    let norms = before_len * len;
                    let dot = before.dot(&segment);
                    // cos = dot / norms; divide only where it may lower the smallest so far.
                    if norms > 0.0 && dot < min_cos * norms {
                        min_cos = min_cos.min((dot / norms).clamp(-1.0, 1.0));
                    }
                    if norms > 0.0 && dot < HAIRPIN_COS * norms {
                        pins += 1;
                    }
                }
                last_segment = Some((segment, len));
            }
        }
    }
    strain.stretch.add_zeros(not_stretched);
    strain.compression.add_zeros(not_compressed);
    StrandMeasures {
        strain,
        hairpins: Hairpins {
            count: pins,
            worst_frame: pins,
            max_turn_deg: min_cos.acos().to_degrees(),
        },
        drift: reference.map(|_| Drift::finish(sums, drift_max, tip_max)),
        velocity_mismatch: mismatch,
    }
}

/// A rest point `local` (root frame, m) posed by rotation `m` and root `origin` (world, m).
fn posed_point(m: &Matrix3<f32>, origin: &Vector3<f32>, local: &Vector3<f32>) -> Vector3<f32> {
    origin + m * local
}
