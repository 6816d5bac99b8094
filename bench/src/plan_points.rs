//! Where `hairsys plan` lands on the head panel, for two tolerances.
//!
//! [`hairsys::plan::plan`] is run on the bench's head case as a scene file (the same groom,
//! motion, collider and physical hair the methods run, [`crate::cases::head_turn_file`]) over
//! the case's whole frame range, for each tolerance of [`TOLERANCES`]. The plan measures its
//! candidates against **its own** reference — the inextensible mass-spring model at twice the
//! stability bound's substeps, on probe patches of the groom — and picks the cheapest within
//! the tolerance. The bench then runs the chosen setting on the whole case and measures it
//! against the case's **truth** (the converged rod): the chart shows the truth's verdict on the
//! plan's choice, beside the plan's own predicted error.
//!
//! The plan may choose fewer simulated hairs (the rest interpolated) or another segment count;
//! the head case simulates every strand at the groom's count, so such a choice is reported
//! with its settings but not measured against the truth (the note says why).

use hair_core::StrandModel;
use hairsys::plan::{plan, PlanOptions};
use serde::Serialize;

use crate::cases::{self, Case};
use crate::methods::{MassSpring, Method, Stretch};
use crate::metrics::errors;
use crate::truth::Truth;
use crate::BenchError;

/// The tolerances the plan is asked for on the head case, m: two that give different choices.
pub const TOLERANCES: [f32; 2] = [2e-3, 5e-3];

/// The plan's choice for one tolerance, and what the truth says of it.
#[derive(Debug, Clone, Serialize)]
pub struct PlanPoint {
    /// Case name.
    pub case: String,
    /// The tolerance asked for, m.
    pub tolerance: f64,
    /// The chosen setting in the plan's words (`None`: nothing met the tolerance).
    pub chosen: Option<String>,
    /// The bench method the choice runs as (`None` if it cannot be run on the case).
    pub method: Option<String>,
    /// Substeps per frame of the choice (the bound's count for `"auto"`).
    pub substeps: u32,
    /// Segments per strand of the choice.
    pub segments: u32,
    /// Simulated hairs of the choice.
    pub sim_hairs: usize,
    /// The plan's own error of the choice: worst frame's RMS position error against its
    /// reference, m.
    pub plan_error: f64,
    /// The plan's RMS error over every probed frame, m.
    pub plan_error_rms: f64,
    /// Position RMS error of the choice against the case's truth (the bench's measure), m.
    pub truth_error: Option<f64>,
    /// Tip RMS error against the truth, m.
    pub truth_tip_error: Option<f64>,
    /// Cost of the choice on the case: wall-clock ms per frame of the solver alone.
    pub ms_per_frame: Option<f64>,
    /// CPU time of the plan itself, s.
    pub plan_seconds: f64,
    /// Why the choice was not measured, or how its run failed.
    pub note: String,
}

/// Runs the plan on the head `case` for each of [`TOLERANCES`] and measures each choice against
/// `truth`; `tick` is called after each tolerance.
pub fn measure(
    case: &Case,
    quick: bool,
    truth: &Truth,
    mut tick: impl FnMut(),
) -> Result<Vec<PlanPoint>, BenchError> {
    let mut file = cases::head_turn_file(quick);
    // The case's material is set after its build (the physical hair): the plan builds the
    // file again, so it takes the same parameters.
    file.scene.physics = case.sim.params;
    let mut points = Vec::new();
    for tolerance in TOLERANCES {
        let mut opts = PlanOptions::new(tolerance);
        opts.frames = Some((case.sim.first_frame, case.sim.last_frame));
        let planned = plan(&file, &opts, &mut |_| {}).map_err(|e| BenchError::Plan {
            case: case.name.into(),
            message: format!("at a tolerance of {} mm: {e}", tolerance * 1e3),
        })?;
        let mut point = PlanPoint {
            case: case.name.into(),
            tolerance: tolerance as f64,
            chosen: None,
            method: None,
            substeps: 0,
            segments: 0,
            sim_hairs: 0,
            plan_error: 0.0,
            plan_error_rms: 0.0,
            truth_error: None,
            truth_tip_error: None,
            ms_per_frame: None,
            plan_seconds: planned.seconds,
            note: String::new(),
        };
        let Some(choice) = planned.choice() else {
            point.note = "no candidate met the tolerance".into();
            points.push(point);
            tick();
            continue;
        };
        point.chosen = Some(format!("{}, {} sim hairs", choice.method, choice.sim_hairs));
        point.substeps = choice.substeps_run;
        point.segments = choice.method.segments;
        point.sim_hairs = choice.sim_hairs;
        point.plan_error = choice.errors.rms_max as f64;
        point.plan_error_rms = choice.errors.rms as f64;
        let segments = (case.sim.strands.points(0).len() - 1) as u32;
        if choice.sim_hairs != case.sim.strands.len() || choice.method.segments != segments {
            point.note = format!(
                "the head case simulates all {} strands at {segments} segments; the choice is \
                 not measured against the truth",
                case.sim.strands.len()
            );
            points.push(point);
            tick();
            continue;
        }
        let method = MassSpring {
            integrator: choice.method.integrator,
            damping: true,
            projection: choice.method.inextensible,
            stretch: Stretch::Soft,
        };
        point.method = Some(method.name());
        match method.run(case, choice.method.substeps) {
            Ok(trace) => {
                let e = errors(case, &trace, truth);
                point.truth_error = Some(e.position_rms);
                point.truth_tip_error = Some(e.tip_rms);
                point.ms_per_frame = Some(trace.cost.ms_per_frame);
                point.substeps = trace.substeps;
            }
            Err(e) => point.note = format!("the chosen setting failed on the case: {e}"),
        }
        points.push(point);
        tick();
    }
    Ok(points)
}

/// Whether `case` gets plan points: the head case (a mass-spring scene the plan can probe).
pub fn applies(case: &Case) -> bool {
    case.name == "head" && case.sim.model == StrandModel::MassSpring
}
