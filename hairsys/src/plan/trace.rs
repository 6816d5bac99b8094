//! What a probe records, and the error measure between two probes of the same strands.
//!
//! Strands of different segment counts are compared at the same material points: every strand
//! is resampled at `samples + 1` fixed fractions of its rest arc length (root, …, tip) by linear
//! interpolation along its polyline, so a 6-segment candidate and a 16-segment reference give
//! directly comparable points. The rest shape is kept in root-local coordinates, so
//! [`Trace::posed_rest`] places it with each frame's root frame (a turning or deforming scalp).
//!
//! The error of a candidate against the reference ([`errors`]) is the library's one accuracy
//! measure ([`crate::accuracy::shot_errors`]), taken per frame over every sample point (root
//! excluded: it is pinned) — the root mean square distance — and over the tips — the RMS tip
//! distance, the silhouette a TD sees. The plan's tolerance bounds the worst frame's position
//! RMS.

use hair_core::{RootFrame, StrandSet};
use nalgebra::Vector3;

use crate::accuracy::{shot_errors, ShotErrors};

/// Positions of a set of strands over a run of frames, resampled at fixed arc-length fractions.
#[derive(Debug, Clone)]
pub struct Trace {
    /// Sample points per strand (fractions `0, 1/(n−1), …, 1` of the rest length).
    pub points_per_strand: usize,
    /// Strand count.
    pub strands: usize,
    /// Root positions at the first frame, m (world), one per strand: neighbour search.
    pub roots: Vec<Vector3<f32>>,
    /// Rest shapes, root-local, m: `strands × points_per_strand` points.
    pub rest_local: Vec<Vector3<f32>>,
    /// Per stepped frame: sampled positions (m, world), `strands × points_per_strand`.
    pub frames: Vec<Vec<Vector3<f32>>>,
    /// Per stepped frame: the root frame of every strand.
    pub root_frames: Vec<Vec<RootFrame>>,
}

impl Trace {
    /// An empty trace of `strands` with `samples` segments between sampled points, with the
    /// rest shapes (and roots) of `set` at its current state (the first frame).
    pub fn new(set: &StrandSet, samples: usize) -> Self {
        let n = samples + 1;
        let mut rest_local = Vec::with_capacity(set.len() * n);
        let mut roots = Vec::with_capacity(set.len());
        for s in 0..set.len() {
            resample_into(set, s, &set.rest_local()[set.points(s)], n, &mut rest_local);
            roots.push(set.positions[set.points(s).start]);
        }
        Self {
            points_per_strand: n,
            strands: set.len(),
            roots,
            rest_local,
            frames: Vec::new(),
            root_frames: Vec::new(),
        }
    }

    /// Records the current state of `set` (the same strands) as the next frame.
    pub fn record(&mut self, set: &StrandSet, roots: &[RootFrame]) {
        let mut out = Vec::with_capacity(self.strands * self.points_per_strand);
        for s in 0..set.len() {
            resample_into(
                set,
                s,
                &set.positions[set.points(s)],
                self.points_per_strand,
                &mut out,
            );
        }
        self.frames.push(out);
        self.root_frames.push(roots.to_vec());
    }

    /// Sample `j` of strand `s`'s rest shape placed by its root frame at recorded frame `f`, m.
    pub fn posed_rest(&self, f: usize, s: usize, j: usize) -> Vector3<f32> {
        let rf = &self.root_frames[f][s];
        rf.origin + rf.rotation * self.rest_local[s * self.points_per_strand + j]
    }
}

/// Appends `n` points of strand `s` sampled at equal fractions of its rest length, taken from
/// `points` (the strand's positions, or its rest shape).
fn resample_into(
    set: &StrandSet,
    s: usize,
    points: &[Vector3<f32>],
    n: usize,
    out: &mut Vec<Vector3<f32>>,
) {
    let lengths = &set.rest_lengths()[set.segments(s)];
    let total: f32 = lengths.iter().sum();
    let mut seg = 0;
    let mut start = 0.0f32;
    for j in 0..n {
        let target = total * j as f32 / (n - 1) as f32;
        while seg + 1 < lengths.len() && start + lengths[seg] < target {
            start += lengths[seg];
            seg += 1;
        }
        let t = ((target - start) / lengths[seg]).clamp(0.0, 1.0);
        out.push(points[seg] + (points[seg + 1] - points[seg]) * t);
    }
}

/// Errors of `candidate` against `reference` (the same strands and frames): the shared
/// measure ([`crate::accuracy::shot_errors`]) over every sample point but the roots.
///
/// Panics if the traces do not describe the same strands and frames (a programming error: both
/// come from probes of one strand selection).
pub fn errors(candidate: &[Vec<Vector3<f32>>], reference: &Trace) -> ShotErrors {
    assert_eq!(candidate.len(), reference.frames.len(), "the same frames");
    let n = reference.points_per_strand;
    let offsets: Vec<u32> = (0..=reference.strands).map(|s| (s * n) as u32).collect();
    let free: Vec<f32> = (0..reference.strands * n)
        .map(|i| if i % n == 0 { 0.0 } else { 1.0 })
        .collect();
    for (a, b) in candidate.iter().zip(&reference.frames) {
        assert_eq!(a.len(), b.len(), "the same strands");
    }
    shot_errors(candidate, &reference.frames, &offsets, &free)
}
