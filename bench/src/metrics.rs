//! What a bench run measures, against the case's truth ([`crate::truth`]), with the measures
//! of [`hairsys::accuracy`]:
//!
//! - **position error**: RMS over every free point and every sample frame of `|x − x_true|`, m;
//! - **tip error**: RMS over strands and sample frames of the tips' distance, m (silhouette);
//! - **length error**: largest `|L/L_rest − 1|` of a strand's total length at any sample frame;
//! - **curl kept**: mean curvature at the last sample over the truth's (1 = kept);
//! - **max stretch**: largest `len/rest − 1` of any segment at the end of any frame;
//! - **energy drift**: `(E(T) − E_true(T)) / Σ m g L` where the truth has an energy (the
//!   pendulum's is conserved; the rod truth's is its solver's);
//! - **max penetration**: deepest free point centre inside the closed scalp at any frame end, m
//!   (head cases), or inside the sphere (drape case, [`crate::drape::Ball`]);
//! - **cost**: wall-clock ms per frame of the solver alone, and point-substeps per second.
//!
//! Shape drift at rest is the position error of the chain-rest case.

use std::time::{Duration, Instant};

use hair_core::{
    Colliders, HairError, MassSpringSolver, ModelFigures, ProjectionReport, StrandSolver,
};
use nalgebra::Vector3;
use serde::Serialize;

use crate::cases::Case;
use crate::truth::Truth;
use hairsys::accuracy;

/// Wall-clock cost of a run (solver only).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Cost {
    /// Milliseconds per frame.
    pub ms_per_frame: f64,
    /// Points × substeps advanced per second.
    pub point_substeps_per_s: f64,
    /// Microseconds per frame per hair the case stands for (cases that count their hairs: a
    /// strand is one hair, a strip its `hairs_per_strip`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub us_per_represented_hair: Option<f64>,
}

/// The observed history of one run.
#[derive(Debug, Clone)]
pub struct Trace {
    /// Positions at each of the case's sample frames (m).
    pub samples: Vec<Vec<Vector3<f32>>>,
    /// Largest relative segment elongation at any frame end.
    pub max_stretch: f32,
    /// Total mechanical energy at the last frame, J.
    pub energy_end: f64,
    /// Deepest free point inside the head, or point inside the drape's sphere, at any frame
    /// end, m (0 without either).
    pub max_penetration: f32,
    /// Substeps per frame the solver used.
    pub substeps: u32,
    /// Cost.
    pub cost: Cost,
    /// The rod model's projection figures over the run (`None` for the other models).
    pub projection: Option<ProjectionReport>,
}

/// Runs `case` with the mass-spring `solver` (built for the case's first frame) to its last
/// frame.
pub fn drive(case: &Case, solver: MassSpringSolver) -> Result<Trace, HairError> {
    drive_model(case, solver.into())
}

/// Runs `case` with `solver` of any model (built for the case's first frame) to its last frame.
pub fn drive_model(case: &Case, mut solver: StrandSolver) -> Result<Trace, HairError> {
    let sim = &case.sim;
    let mut strands = sim.strands.clone();
    let mut colliders: Colliders = sim.colliders_at(sim.first_frame as f32)?;
    let mut samples = Vec::with_capacity(case.samples.len());
    let (mut max_stretch, mut max_penetration) = (0.0f32, 0.0f32);
    let mut solve = Duration::ZERO;
    let mut point_substeps = 0u64;
    let mut substeps = 0;
    let mut projection: Option<ProjectionReport> = None;
    for frame in sim.first_frame + 1..=sim.last_frame {
        let scalp = sim.scalp_at(frame as f32);
        sim.pose_colliders(&mut colliders, frame as f32)?;
        let t0 = Instant::now();
        let report = solver.step_frame(&mut strands, &scalp, Some(&mut colliders))?;
        solve += t0.elapsed();
        if let ModelFigures::Rod(p) = &report.figures {
            projection.get_or_insert_with(Default::default).merge(p);
        }
        point_substeps += report.point_substeps;
        substeps = substeps.max(report.substeps * report.steps);
        max_stretch = max_stretch.max(report.max_stretch);
        if let Some(head) = &case.head {
            max_penetration = max_penetration.max(head.max_depth(
                &scalp,
                &strands.positions,
                strands.inverse_masses(),
            ));
        }
        if let Some(ball) = &case.ball {
            max_penetration = max_penetration.max(ball.max_depth(&strands.positions));
        }
        if case.samples.contains(&frame) {
            samples.push(strands.positions.clone());
        }
    }
    let frames = (sim.last_frame - sim.first_frame) as f64;
    let seconds = solve.as_secs_f64().max(1e-9);
    let ms_per_frame = 1e3 * seconds / frames;
    Ok(Trace {
        samples,
        max_stretch,
        energy_end: solver.energy(&strands),
        max_penetration,
        substeps,
        cost: Cost {
            ms_per_frame,
            point_substeps_per_s: point_substeps as f64 / seconds,
            us_per_represented_hair: case
                .represented_hairs
                .map(|h| 1e3 * ms_per_frame / h.max(1) as f64),
        },
        projection,
    })
}

/// Largest relative segment elongation a run may end a frame with and still count as stable:
/// beyond it (a segment twice its rest length) the run has blown up even if the solver's own
/// checks (non-finite values, runaway energy) have not caught it yet.
pub const BLOWN_UP_STRETCH: f32 = 1.0;

/// Why `trace` counts as blown up, if it does (see [`BLOWN_UP_STRETCH`]).
pub fn blown_up(trace: &Trace) -> Option<Stretched> {
    (trace.max_stretch > BLOWN_UP_STRETCH).then_some(Stretched {
        max_stretch: trace.max_stretch,
    })
}

/// A run whose segments stretched past what a stable run reaches.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("a segment reached {:.0}× its rest length", 1.0 + .max_stretch)]
pub struct Stretched {
    /// The largest strain reached (0 = the rest length).
    pub max_stretch: f32,
}

/// RMS distance between the free points of sample sets `a` and `b` over all sample frames, m.
pub fn rms_difference(case: &Case, a: &[Vec<Vector3<f32>>], b: &[Vec<Vector3<f32>>]) -> f64 {
    let free = case.sim.strands.inverse_masses();
    let sq: f64 = a
        .iter()
        .zip(b)
        .map(|(xa, xb)| accuracy::position_rms(xa, xb, free).powi(2))
        .sum();
    (sq / a.len().max(1) as f64).sqrt()
}

/// Errors of one stable run against the case's truth.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Errors {
    /// Position RMS error, m.
    pub position_rms: f64,
    /// Tip (silhouette) RMS error, m.
    pub tip_rms: f64,
    /// Largest strand length error `|L/L_rest − 1|` at the sample frames.
    pub length_error: f64,
    /// Mean curvature at the last sample over the truth's (`None` where the truth is straight).
    pub curl_kept: Option<f64>,
    /// Largest relative segment elongation (0.01 = 1 %).
    pub max_stretch: f32,
    /// Energy at the end against the truth's, as a fraction of `Σ m g L` (`None`: the truth
    /// has no energy comparable with the run's).
    pub energy_drift: Option<f64>,
    /// Deepest point inside the head, m.
    pub max_penetration: f32,
}

/// Compares `run` with the case's `truth`.
pub fn errors(case: &Case, run: &Trace, truth: &Truth) -> Errors {
    let strands = &case.sim.strands;
    let offsets = strands.offsets();
    let tip_sq: f64 = run
        .samples
        .iter()
        .zip(&truth.samples)
        .map(|(x, t)| accuracy::tip_rms(x, t, offsets).powi(2))
        .sum();
    let length_error = run
        .samples
        .iter()
        .map(|x| accuracy::length_error(x, offsets, strands.rest_lengths()))
        .fold(0.0, f64::max);
    let curl_kept = match (run.samples.last(), truth.samples.last()) {
        (Some(x), Some(t)) => accuracy::curl_kept(x, t, offsets),
        _ => None,
    };
    Errors {
        position_rms: rms_difference(case, &run.samples, &truth.samples),
        tip_rms: (tip_sq / run.samples.len().max(1) as f64).sqrt(),
        length_error,
        curl_kept,
        max_stretch: run.max_stretch,
        energy_drift: truth
            .energy_end
            .map(|e| (run.energy_end - e) / case.energy_scale.max(1e-30)),
        max_penetration: run.max_penetration,
    }
}
