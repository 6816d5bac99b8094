//! # hairsys-bench
//!
//! The lab beside the product: speed against accuracy, and where each method fails. The
//! `hairsys bench` command runs [`run`]; the cross-method tests in `bench/tests` run its cases;
//! [`study`] is the accuracy study of the shipped default scene.
//!
//! Every [`Method`] ([`methods::all`]) runs every case ([`cases`]) at 1, 2, 4 … substeps per
//! frame; each run gives its cost (ms/frame, point-substeps/s) and its errors ([`metrics`])
//! against the case's **one physical truth** ([`truth`]): the analytic answer where physics has
//! one (the rigid pendulum, the catenary), otherwise a converged inextensible elastic rod of the
//! same hair, whose convergence in time and space the report states. Every model is made of the
//! same physical hair ([`physical`]), so the errors compare models. `substeps = "auto"` is run
//! too and marked on the chart.
//!
//! The **stability map** ([`stability`]) runs a probe strand over a grid of stretch stiffness
//! × substeps per method and draws the predicted bound `dt < 2/ω` on it (for the rod, whose
//! stretching is a constraint, the rows set its bending to the same frequency).
//!
//! **Segments per strand** ([`segments`]) is an axis of its own: the cases that can be built at
//! any segment count (cantilever, curly, drape) run every method at 4 … 64 segments at its own
//! `auto` substeps, against the same truth at common arc-length points.
//!
//! Beside the cases, [`tip_moment`] measures the rod's cantilever under a tip moment against
//! the elastica ([`analytic::elastica_tip`]), at a small and a large deflection.
//!
//! Output ([`report`], [`charts`]): `pareto.png` (error against cost, log–log, one panel per
//! case, one series per method), `stability_map.png`, `segments.png` (error against segments per
//! strand), `bench.md` (the tables) and `bench.json` (every number) in the output directory.

pub mod analytic;
pub mod cases;
pub mod charts;
pub mod curly;
pub mod drape;
pub mod methods;
pub mod metrics;
pub mod physical;
pub mod plan_points;
pub mod report;
pub mod segments;
pub mod stability;
pub mod study;
pub mod tip_moment;
pub mod truth;

use std::path::PathBuf;
use std::time::Instant;

use hair_core::{HairError, ProjectionReport};
use serde::Serialize;

use cases::Case;
use hairsys::scene::SceneError;
use methods::{MassSpring, Method};
use metrics::{blown_up, errors, Cost, Errors, Trace};
use plan_points::PlanPoint;
use stability::{Grid, MethodMap};
use truth::{Convergence, Truth};

/// The rod truth runs at (at least) this many times the finest substep count charted.
pub const REFERENCE_FACTOR: u32 = 8;

/// A stable run is repeated until the solver has spent this long on it (ms); its cost is the
/// fastest repetition.
const MIN_TIMED_MS: f64 = 20.0;

/// What `hairsys bench` was asked to do.
#[derive(Debug, Clone)]
pub struct BenchOptions {
    /// Small cases and grids: about a minute and a quarter on 2 cores instead of ten minutes.
    pub quick: bool,
    /// Directory for the charts and tables (created if missing).
    pub out: PathBuf,
}

/// Where the bench reports how far it is: [`run`] says how many runs it will make, then one
/// [`Event`] per finished run (a bar, JSON lines, or nothing: the caller's choice).
pub trait Progress {
    /// The bench is about to make `total` runs.
    fn start(&self, total: u64);
    /// One run finished.
    fn tick(&self, event: &Event<'_>);
    /// The bench is done.
    fn finish(&self);
}

/// [`Progress`] that reports nothing.
pub struct Silent;

impl Progress for Silent {
    fn start(&self, _total: u64) {}
    fn tick(&self, _event: &Event<'_>) {}
    fn finish(&self) {}
}

/// Why the bench could not finish.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// A case's scene did not build.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A case could not be built.
    #[error(transparent)]
    Case(#[from] cases::CaseError),
    /// A run failed otherwise than by instability (which is a result, not an error).
    #[error("bench: {0}")]
    Solver(#[from] HairError),
    /// A case's truth could not be computed.
    #[error("bench: the truth of case {case} failed: {source}")]
    Truth {
        /// Case name.
        case: String,
        /// Which run failed, and why.
        source: truth::TruthError,
    },
    /// `hairsys plan` failed on a case's scene.
    #[error("bench: hairsys plan on case {case} failed: {message}")]
    Plan {
        /// Case name.
        case: String,
        /// The tolerance and the plan's error.
        message: String,
    },
    /// The output could not be written.
    #[error("cannot write {path}: {message}; check the --out directory is writable")]
    Write {
        /// File being written.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

/// How one run ended.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "status", rename_all = "lowercase")]
pub enum Outcome {
    /// It finished: its cost and its errors against the reference.
    Stable {
        /// Cost.
        cost: Cost,
        /// Errors against the case's truth.
        errors: Errors,
        /// The rod model's projection figures (rod methods only).
        #[serde(skip_serializing_if = "Option::is_none")]
        projection: Option<ProjectionReport>,
    },
    /// The solver stopped it (blow-up detected), or it ended a frame with a segment stretched
    /// beyond [`metrics::BLOWN_UP_STRETCH`].
    Unstable {
        /// The solver's message.
        message: String,
    },
}

/// One run of one method on one case.
#[derive(Debug, Clone, Serialize)]
pub struct Run {
    /// Case name.
    pub case: String,
    /// Method name.
    pub method: String,
    /// Substeps per frame (for `auto`: the count it chose).
    pub substeps: u32,
    /// Substep, s.
    pub dt: f64,
    /// True for the `substeps = "auto"` run.
    pub auto: bool,
    /// Result.
    pub outcome: Outcome,
}

impl Run {
    /// Cost and errors, if it was stable.
    pub fn stable(&self) -> Option<(&Cost, &Errors)> {
        match &self.outcome {
            Outcome::Stable { cost, errors, .. } => Some((cost, errors)),
            Outcome::Unstable { .. } => None,
        }
    }
}

/// A method left out of a case, and why.
#[derive(Debug, Clone, Serialize)]
pub struct NotRun {
    /// Case name.
    pub case: String,
    /// Method name.
    pub method: String,
    /// Why it cannot run the case.
    pub reason: String,
}

/// Everything the bench measured.
#[derive(Debug, Clone, Serialize)]
pub struct BenchReport {
    /// Quick mode.
    pub quick: bool,
    /// Cases: name and description.
    pub cases: Vec<(String, String)>,
    /// Methods: name and the model components each runs on the head case.
    pub methods: Vec<(String, String)>,
    /// Every run, `auto` ones included.
    pub runs: Vec<Run>,
    /// Each case's truth and its convergence.
    pub truths: Vec<Convergence>,
    /// Where `hairsys plan` lands on the head case for two tolerances, measured against the
    /// truth ([`plan_points`]).
    pub plan: Vec<PlanPoint>,
    /// The segments axis: methods at their automatic substeps over segment counts, on the
    /// cases that can be re-segmented ([`segments`]).
    pub segments: Vec<segments::SegmentRun>,
    /// Methods left out of cases they cannot run.
    pub not_run: Vec<NotRun>,
    /// The rod's cantilever under a tip moment against the analytic arc.
    pub tip_moment: Vec<tip_moment::TipMomentRun>,
    /// Stiffnesses of the stability map rows, N/m.
    pub stability_stiffness: Vec<f64>,
    /// Substeps per frame of the stability map columns (at [`stability::FPS`]).
    pub stability_substeps: Vec<u32>,
    /// The stability map of each method.
    pub stability: Vec<MethodMap>,
    /// Wall-clock time of the whole bench, s.
    pub seconds: f64,
}

/// Substeps per frame charted: 1, 2, 4 … 512 (… 256 with `quick`). Finer steps than these
/// reach the f32 floor of the positions: the reference itself changes by about 10⁻⁵ m when its
/// step is halved at 4096 substeps per frame, whatever the case.
pub fn ladder(quick: bool) -> Vec<u32> {
    let top = if quick { 8 } else { 9 };
    (0..=top).map(|e| 1 << e).collect()
}

/// One finished run of the bench, as [`Progress::tick`] reports it.
#[derive(Debug, Serialize)]
pub struct Event<'a> {
    /// What kind of run: `run`, `truth`, `plan`, `segments`, `tip-moment`, `stability-row`.
    pub event: &'a str,
    /// The case's name.
    pub case: &'a str,
    /// The method's name.
    pub method: &'a str,
    /// Substeps per frame of the run (0 where it does not apply).
    pub substeps: u32,
    /// `done`, `stable`, `unstable`, …
    pub status: &'a str,
}

/// Why a run is unstable: an outcome the bench records, not an error.
#[derive(Debug, thiserror::Error)]
pub enum Blowup {
    /// The solver found the run unstable.
    #[error("{0}")]
    Solver(HairError),
    /// A segment stretched past what a stable run reaches ([`metrics::blown_up`]).
    #[error("{0}")]
    Stretched(metrics::Stretched),
}

fn outcome(result: Result<Trace, HairError>) -> Result<Result<Trace, Blowup>, HairError> {
    match result {
        Ok(t) => Ok(blown_up(&t).map_or(Ok(t), |s| Err(Blowup::Stretched(s)))),
        Err(e @ HairError::Unstable { .. }) => Ok(Err(Blowup::Solver(e))),
        Err(e) => Err(e),
    }
}

/// Runs `m` on `case` at `substeps` (`None`: auto): its trace and its cost, or why it blew up.
/// Short runs are timed again, keeping the fastest: one run of a tiny case is mostly timer
/// noise.
pub fn timed_run(
    m: &dyn Method,
    case: &Case,
    substeps: Option<u32>,
) -> Result<Result<(Trace, Cost), Blowup>, HairError> {
    let trace = match outcome(m.run(case, substeps))? {
        Ok(trace) => trace,
        Err(blowup) => return Ok(Err(blowup)),
    };
    let mut cost = trace.cost;
    let mut spent = cost.ms_per_frame * case.frames() as f64;
    while spent < MIN_TIMED_MS {
        let again = m.run(case, substeps)?.cost;
        spent += again.ms_per_frame * case.frames() as f64;
        if again.ms_per_frame < cost.ms_per_frame {
            cost = again;
        }
    }
    Ok(Ok((trace, cost)))
}

/// Runs every method on `case` against its truth: the ladder, and `auto` for the default.
/// Returns the runs and the truth, its convergence completed with the smallest error charted.
pub fn bench_case(
    case: &Case,
    methods: &[Box<dyn Method>],
    ladder: &[u32],
    progress: &dyn Progress,
) -> Result<(Vec<Run>, Truth), BenchError> {
    let methods: Vec<&dyn Method> = methods
        .iter()
        .map(|m| m.as_ref())
        .filter(|m| m.cannot_run(case).is_none())
        .collect();
    let finest = *ladder.last().unwrap_or(&1);
    let step_dt = 1.0 / case.sim.settings.fps as f64;
    let mut truth =
        truth::truth(case, finest * REFERENCE_FACTOR).map_err(|source| BenchError::Truth {
            case: case.name.into(),
            source,
        })?;
    progress.tick(&Event {
        event: "truth",
        case: case.name,
        method: &truth.convergence.truth,
        substeps: truth.convergence.substeps,
        status: "done",
    });
    let mut runs = Vec::new();
    let mut record = |m: &dyn Method, substeps: Option<u32>| -> Result<(), BenchError> {
        let (n, outcome) = match timed_run(m, case, substeps)? {
            Ok((trace, cost)) => (
                trace.substeps,
                Outcome::Stable {
                    cost,
                    errors: errors(case, &trace, &truth),
                    projection: trace.projection,
                },
            ),
            Err(blowup) => (
                substeps.unwrap_or(0),
                Outcome::Unstable {
                    message: blowup.to_string(),
                },
            ),
        };
        progress.tick(&Event {
            event: "run",
            case: case.name,
            method: &m.name(),
            substeps: n,
            status: if matches!(outcome, Outcome::Stable { .. }) {
                "stable"
            } else {
                "unstable"
            },
        });
        runs.push(Run {
            case: case.name.into(),
            method: m.name(),
            substeps: n,
            dt: step_dt / n.max(1) as f64,
            auto: substeps.is_none(),
            outcome,
        });
        Ok(())
    };
    for m in &methods {
        for &s in ladder {
            record(*m, Some(s))?;
        }
    }
    if MassSpring::DEFAULT.cannot_run(case).is_none() {
        record(&MassSpring::DEFAULT, None)?;
    }
    let convergence = &mut truth.convergence;
    convergence.smallest_error = runs
        .iter()
        .filter(|r| !r.auto)
        .filter_map(|r| r.stable().map(|(_, e)| e.position_rms))
        .filter(|&e| e > 0.0)
        .fold(f64::INFINITY, f64::min);
    if convergence.substeps > 0 {
        convergence.converged = convergence.time_change < convergence.smallest_error
            && convergence.space_change < convergence.smallest_error;
    }
    Ok((runs, truth))
}

/// Runs the whole bench and writes its charts and tables into `opts.out`.
pub fn run(opts: &BenchOptions, progress: &dyn Progress) -> Result<BenchReport, BenchError> {
    let t0 = Instant::now();
    // Fail before minutes of work, not after.
    report::create_dir(&opts.out)?;
    let cases = cases::all(opts.quick)?;
    let methods = methods::all();
    let ladder = ladder(opts.quick);
    let grid = Grid::new(opts.quick);
    let probe = stability::probe_case(1.0, 1)?;
    let mapped: Vec<&dyn Method> = methods
        .iter()
        .map(|m| m.as_ref())
        .filter(|m| m.cannot_run(&probe).is_none())
        .collect();
    let mut not_run = Vec::new();
    let mut total = mapped.len() * grid.stiffness.len() + tip_moment::runs(opts.quick);
    for case in &cases {
        let runnable = methods
            .iter()
            .filter(|m| {
                let reason = m.cannot_run(case);
                if let Some(reason) = &reason {
                    not_run.push(NotRun {
                        case: case.name.into(),
                        method: m.name(),
                        reason: reason.clone(),
                    });
                }
                reason.is_none()
            })
            .count();
        total += runnable * ladder.len()
            + 1
            + usize::from(MassSpring::DEFAULT.cannot_run(case).is_none())
            + segments::planned(case, &methods, opts.quick);
        if plan_points::applies(case) {
            total += plan_points::TOLERANCES.len();
        }
    }
    progress.start(total as u64);
    let mut runs = Vec::new();
    let mut truths = Vec::new();
    let mut plan = Vec::new();
    let mut segment_runs = Vec::new();
    for case in &cases {
        let (r, truth) = bench_case(case, &methods, &ladder, progress)?;
        if plan_points::applies(case) {
            plan.extend(plan_points::measure(case, opts.quick, &truth, || {
                progress.tick(&Event {
                    event: "plan",
                    case: case.name,
                    method: "hairsys plan",
                    substeps: 0,
                    status: "done",
                })
            })?);
        }
        runs.extend(r);
        segment_runs.extend(segments::bench(
            case, &truth, &methods, opts.quick, progress,
        )?);
        truths.push(truth.convergence);
    }
    let tip_moment = tip_moment::bench(opts.quick, || {
        progress.tick(&Event {
            event: "tip-moment",
            case: "tip moment",
            method: "rod",
            substeps: 0,
            status: "done",
        })
    });
    let mut maps = Vec::new();
    for m in mapped {
        maps.push(stability::map(m, &grid, || {
            progress.tick(&Event {
                event: "stability-row",
                case: "probe",
                method: &m.name(),
                substeps: 0,
                status: "done",
            })
        })?);
    }
    progress.finish();
    // Components on the last case each method runs (the head, or the head with strips).
    let components = methods
        .iter()
        .filter_map(|m| {
            let case = cases.iter().rev().find(|c| m.cannot_run(c).is_none())?;
            Some(m.components(case).map(|c| (m.name(), c.join(", "))))
        })
        .collect::<Result<Vec<_>, HairError>>()?;
    let report = BenchReport {
        quick: opts.quick,
        methods: components,
        cases: cases
            .iter()
            .map(|c| (c.name.to_string(), c.title.to_string()))
            .collect(),
        runs,
        truths,
        plan,
        segments: segment_runs,
        not_run,
        tip_moment,
        stability_stiffness: grid.stiffness.clone(),
        stability_substeps: grid.substeps.clone(),
        stability: maps,
        seconds: t0.elapsed().as_secs_f64(),
    };
    report::write_all(&report, &grid, &opts.out)?;
    Ok(report)
}
