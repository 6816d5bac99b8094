//! **Spatial resolution as an axis**: the same physical hair in 4, 8, 16, 32 and 64
//! segments per strand, every method at its own automatic substeps (`substeps = "auto"`: the
//! explicit methods half their stability bound, which shrinks as the segments do; implicit Euler
//! and XPBD their fixed step), against the case's one truth. It answers "what resolution does
//! each model need for a given error", and what that resolution costs.
//!
//! Only cases where a re-segmented strand is the same strand run it ([`Case::resegment`]): the
//! cantilever, the curly and the drape cases. The pendulum is one link, the catenary's truth is
//! for its 20 links, and the head's groom is styled segment by segment (another count is
//! another groom). Each count is the same material: masses `μ l`, bending `EI/l³`, soft springs
//! the same fraction of `EA/l`, physical springs `EA/l` ([`crate::physical`], through the case's
//! own builder).
//!
//! **Common points.** A run at `n` segments is compared with the truth at the charted case's
//! points, which sit at equal fractions `j / n₀` of each strand's rest arc length (the cases'
//! segments are equal): the run's polyline is sampled at the same fractions of its own rest
//! length by linear interpolation between its nodes, so a 4-segment strand is measured where a
//! renderer would draw it. Length error and stretch are the run's own (its polyline against its
//! rest lengths), penetration is its polyline's.
//!
//! **Where the truth limits it.** The truth is the rod at [`Case::truth_subdivision`] × the
//! charted segments (32 for the curly and drape cases, 20 for the cantilever); counts finer
//! than that are compared with a coarser truth, and their error cannot fall below the truth's
//! own spatial change (the Truths table's "segments halved again"), which the chart draws.
//! Counts above [`MAX_TRUTH_MULTIPLE`] × the truth's segments are not run: the truth says
//! nothing about them.

use hair_core::StrandSet;
use hairsys::accuracy;
use nalgebra::Vector3;
use serde::Serialize;

use crate::cases::Case;
use crate::methods::Method;
use crate::metrics::{errors, Trace};
use crate::truth::Truth;
use crate::Progress;
use crate::{timed_run, BenchError, Event, Outcome};

/// Segment counts per strand on the axis.
pub const COUNTS: [usize; 5] = [4, 8, 16, 32, 64];

/// Segment counts per strand with `--quick` (32 segments of the 5 cm cantilever cost the rod
/// about 4,700 substeps per frame, 15 s of the quick bench's minute).
pub const QUICK_COUNTS: [usize; 3] = [4, 8, 16];

/// Largest segment count run, as a multiple of the truth's segment count (2: one doubling beyond
/// it, where the truth's own spatial change is measured).
pub const MAX_TRUTH_MULTIPLE: usize = 2;

/// One run of one method on one case at one segment count, at the method's automatic substeps.
#[derive(Debug, Clone, Serialize)]
pub struct SegmentRun {
    /// Case name.
    pub case: String,
    /// Method name.
    pub method: String,
    /// Segments per strand.
    pub segments: usize,
    /// Substeps per frame the method chose (`auto`).
    pub substeps: u32,
    /// Result: cost and errors at the case's common points.
    pub outcome: Outcome,
}

/// Segment counts `case` runs on the axis (none if it cannot be re-segmented).
pub fn counts(case: &Case, quick: bool) -> Vec<usize> {
    let Some(r) = case.resegment else {
        return Vec::new();
    };
    let truth_segments = r.segments * case.truth_subdivision.max(1);
    let all: &[usize] = if quick { &QUICK_COUNTS } else { &COUNTS };
    all.iter()
        .copied()
        .filter(|&n| n <= MAX_TRUTH_MULTIPLE * truth_segments)
        .collect()
}

/// How many runs [`bench()`] makes on `case` (for the progress bar).
pub fn planned(case: &Case, methods: &[Box<dyn Method>], quick: bool) -> usize {
    let runnable = methods
        .iter()
        .filter(|m| m.cannot_run(case).is_none())
        .count();
    runnable * counts(case, quick).len()
}

/// Positions of every strand of `set` (laid out as its offsets) sampled at `n + 1` equal
/// fractions of each strand's rest arc length, root to tip, m.
pub fn at_fractions(set: &StrandSet, positions: &[Vector3<f32>], n: usize) -> Vec<Vector3<f32>> {
    let mut out = Vec::with_capacity(set.len() * (n + 1));
    for s in 0..set.len() {
        let p = &positions[set.points(s)];
        let lengths = &set.rest_lengths()[set.segments(s)];
        let total: f64 = lengths.iter().map(|&l| l as f64).sum();
        let (mut seg, mut start) = (0usize, 0.0f64);
        for j in 0..=n {
            let target = total * j as f64 / n.max(1) as f64;
            while seg + 1 < lengths.len() && start + lengths[seg] as f64 <= target {
                start += lengths[seg] as f64;
                seg += 1;
            }
            match (p.get(seg), p.get(seg + 1), lengths.get(seg)) {
                (Some(a), Some(b), Some(&l)) if l > 0.0 => {
                    let t = ((target - start) / l as f64).clamp(0.0, 1.0) as f32;
                    out.push(a + (b - a) * t);
                }
                (Some(a), _, _) => out.push(*a),
                _ => {}
            }
        }
    }
    out
}

/// Runs every method that can run `case` at each of its segment counts ([`counts`]) at the
/// method's automatic substeps, against `truth` at the case's points.
pub fn bench(
    case: &Case,
    truth: &Truth,
    methods: &[Box<dyn Method>],
    quick: bool,
    progress: &dyn Progress,
) -> Result<Vec<SegmentRun>, BenchError> {
    let (Some(r), counts) = (case.resegment, counts(case, quick)) else {
        return Ok(Vec::new());
    };
    let mut runs = Vec::new();
    for n in counts {
        let coarse = (r.build)(n)?;
        for m in methods.iter().filter(|m| m.cannot_run(&coarse).is_none()) {
            let (substeps, outcome) = match timed_run(m.as_ref(), &coarse, None)? {
                Ok((trace, cost)) => {
                    let common = Trace {
                        samples: trace
                            .samples
                            .iter()
                            .map(|x| at_fractions(&coarse.sim.strands, x, r.segments))
                            .collect(),
                        ..trace.clone()
                    };
                    let mut e = errors(case, &common, truth);
                    // Length is the run's own polyline against its own rest lengths.
                    let set = &coarse.sim.strands;
                    e.length_error = trace
                        .samples
                        .iter()
                        .map(|x| accuracy::length_error(x, set.offsets(), set.rest_lengths()))
                        .fold(0.0, f64::max);
                    (
                        trace.substeps,
                        Outcome::Stable {
                            cost,
                            errors: e,
                            projection: trace.projection,
                        },
                    )
                }
                Err(blowup) => (
                    0,
                    Outcome::Unstable {
                        message: blowup.to_string(),
                    },
                ),
            };
            progress.tick(&Event {
                event: "segments",
                case: case.name,
                method: &m.name(),
                substeps,
                status: if matches!(outcome, Outcome::Stable { .. }) {
                    "stable"
                } else {
                    "unstable"
                },
            });
            runs.push(SegmentRun {
                case: case.name.into(),
                method: m.name(),
                segments: n,
                substeps,
                outcome,
            });
        }
    }
    Ok(runs)
}
