//! The one physical reference ("truth") of each case, which every method is measured against.
//!
//! - Where physics has an answer it is that answer ([`crate::analytic`]): the rigid pendulum's
//!   trajectory, the hanging chain's rest shape (the discrete catenary).
//! - Elsewhere it is a **converged inextensible elastic rod** of the same hair: seed 002's
//!   discrete rod ([`hair_core::RodSolver`], 20 projection iterations) on the case's strands
//!   refined [`Case::truth_subdivision`] times (2 on the cantilever, the curly, the drape and
//!   the head cases, 1 on the head strips), at [`crate::REFERENCE_FACTOR`] × the finest substep
//!   count charted (or more, to stay within half its stability bound). Cases that can be built
//!   at any segment count ([`Case::resegment`]: cantilever, curly, drape) are built again at
//!   that many times the segments (the curly helix sampled finer, not its 16-gon cut finer);
//!   the others are refined on a smooth curve through their points.
//!
//! **Refinement on a smooth curve** ([`smooth_rest`]): the new points lie on the C¹ Hermite
//! curve through the case's points, so a refined strand is a finer discretisation of one smooth
//! rest curve. Cutting each segment into straight parts instead keeps the case's kinks: the
//! whole rest curvature stays at the old points, twice as sharp at every refinement (a different
//! rest shape each time, not a finer one). The case's points are every `factor`-th refined
//! point, so the two are compared at the same material points.
//!
//! **The head.** Its truth converges at first order in the step because a round section keeps
//! its rest twist (`hair_core::model::rod::twist`): a twist that turned a round section's material
//! frame onto the plane the strand bends in would turn the styled groom's rest curvature with
//! it, set by round-off wherever a node straightens, and no step would converge (how that was
//! found: `docs/design/bench-truth.md`). The groom's 16 segments do not resolve the physical
//! wisp in this turn (32 segments move it 2.3 mm, quick size), so the head truth runs on 32,
//! checked against 64.
//! At 64 a wisp's 2 mm collision radius would put the new points of the first segment inside
//! the scalp at rest, where the strand leaves it: those collide as points ([`subdivide`]).
//!
//! **Why the rod.** Of the models in hair-core it is the only one whose energy is that of an
//! elastic rod (Kirchhoff: bending and twist of a material frame, Bergou et al. 2008) with
//! stretching as a constraint, held to a strain of about 10⁻⁶; the bench checks it against the
//! elastica ([`crate::tip_moment`]: a tip moment bends it into the analytic arc within 1.3 ×
//! 10⁻³ of its length). The mass-spring model with the inextensibility projection is also
//! inextensible, but its bending springs act towards rest directions in the previous segment's
//! frame, an energy that is not the rod's, and its velocity projection damps at first order in
//! the step; it stays one of the methods measured, not the yardstick.
//!
//! **Convergence is shown, not assumed**: the truth is run again at half its substeps (time)
//! and at twice its subdivision (space, compared at the case's points); both changes are
//! reported beside the smallest error charted against the truth, and the truth counts as
//! converged when both are below it.
//!
//! The truth gives positions at the case's points (every `truth_subdivision`-th point of the
//! subdivided strands), so every method is compared point for point.

use hair_core::{HairError, StrandInput, StrandSet};
use nalgebra::Vector3;
use serde::Serialize;

use crate::analytic;
use crate::cases::{Case, CaseError};
use crate::methods::{Method, Rod};
use crate::metrics::Trace;

/// Largest fraction of the rod's stability bound the truth's substep may take (the half-step
/// run then sits at half this).
const BOUND_FRACTION: f64 = 0.5;

/// Positions at each sample frame, m.
pub type Samples = Vec<Vec<Vector3<f32>>>;

/// What a case is measured against.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TruthKind {
    /// A rigid pendulum of the case's single segment, released from rest.
    Pendulum,
    /// The discrete catenary of the case's single strand, pinned at both ends.
    Catenary,
    /// The converged rod on the case's strands.
    Rod,
}

/// The truth of one case: positions at the case's sample frames and points.
#[derive(Debug, Clone)]
pub struct Truth {
    /// Positions at each sample frame, m.
    pub samples: Samples,
    /// Total energy at the last frame, J, where the truth has one comparable with the methods'
    /// (the pendulum's is its initial energy: the exact motion conserves it).
    pub energy_end: Option<f64>,
    /// How it was obtained and how converged it is.
    pub convergence: Convergence,
}

/// How a truth was obtained and how well converged it is.
#[derive(Debug, Clone, Serialize)]
pub struct Convergence {
    /// Case name.
    pub case: String,
    /// What the truth is, in words.
    pub truth: String,
    /// Substeps per frame of the rod truth (0 for an analytic one).
    pub substeps: u32,
    /// Segments of the rod truth per segment of the case (0 for an analytic one).
    pub space_factor: usize,
    /// Position RMS change when the rod truth's substep is halved, m (0 for analytic).
    pub time_change: f64,
    /// Position RMS change when its segments are halved again, m (0 for analytic).
    pub space_change: f64,
    /// Smallest position error charted against this truth, m (filled in after the runs).
    pub smallest_error: f64,
    /// Both changes below the smallest error (always for an analytic truth).
    pub converged: bool,
    /// Deepest point of the truth inside the case's sphere at any frame end, m (drape case; 0
    /// elsewhere).
    pub penetration: f64,
}

/// `rest` (a polyline, m) refined `factor` times on the C¹ cubic Hermite curve through its
/// points: the old points are every `factor`-th new one, the tangent at an interior point
/// bisects its two segments (the discrete curve's own tangent there), at the root it is the
/// first segment's direction (the direction the root frame clamps), at the tip the last
/// segment's, each scaled by the segment's length. Each segment's turn is thus spread over its
/// length instead of sitting at its ends: the refined strand is a finer discretisation of one
/// smooth curve, not the same kinked polyline with straight nodes added (which concentrates
/// the whole rest curvature at the old points, a different rest shape at every refinement).
pub fn smooth_rest(rest: &[Vector3<f32>], factor: usize) -> Vec<Vector3<f32>> {
    let p: Vec<Vector3<f64>> = rest.iter().map(|v| v.cast()).collect();
    let n = p.len() - 1;
    let dir = |j: usize| (p[j + 1] - p[j]).normalize();
    let tangent: Vec<Vector3<f64>> = (0..=n)
        .map(|i| match i {
            0 => dir(0),
            i if i == n => dir(n - 1),
            i => {
                let t = dir(i - 1) + dir(i);
                if t.norm() > 1e-12 {
                    t.normalize()
                } else {
                    dir(i)
                }
            }
        })
        .collect();
    let mut out = Vec::with_capacity(n * factor + 1);
    for j in 0..n {
        let l = (p[j + 1] - p[j]).norm();
        let (m0, m1) = (tangent[j] * l, tangent[j + 1] * l);
        for k in 0..factor {
            let t = k as f64 / factor as f64;
            let (t2, t3) = (t * t, t * t * t);
            let x = p[j] * (2.0 * t3 - 3.0 * t2 + 1.0)
                + m0 * (t3 - 2.0 * t2 + t)
                + p[j + 1] * (3.0 * t2 - 2.0 * t3)
                + m1 * (t3 - t2);
            out.push(x.cast());
        }
    }
    out.push(rest[n]);
    out
}

/// `strands` refined `factor` times on smooth curves through their rest points
/// ([`smooth_rest`]; the old points are every `factor`-th new one): point masses lumped from
/// `mass_per_length` (kg/m), the pins of the original points kept, radii and goal weights of
/// the segment's start. Positions are reset to rest by the caller.
pub fn subdivide(
    strands: &StrandSet,
    factor: usize,
    mass_per_length: f32,
) -> Result<StrandSet, HairError> {
    let mut out = StrandSet::new();
    for s in 0..strands.len() {
        let pts = strands.points(s);
        let rest = &strands.rest_local()[pts.clone()];
        let inv = &strands.inverse_masses()[pts.clone()];
        let radii = &strands.radii()[pts.clone()];
        let mut input = StrandInput::uniform(
            strands.anchors()[s],
            smooth_rest(rest, factor),
            mass_per_length,
            radii[0],
            0.0,
            0.0,
        );
        for (i, &w) in inv.iter().enumerate() {
            input.pinned[i * factor] = w == 0.0;
            input.radius[i * factor] = radii[i];
        }
        // The new points of the first segment lie where the strand leaves the scalp: a wisp's
        // collision radius there would put them inside the collider at rest (the strand's first
        // point is on the scalp), an infeasible contact. The case has no point there; these
        // collide as points.
        for r in input.radius.iter_mut().take(factor).skip(1) {
            *r = 0.0;
        }
        out.push(input)?;
    }
    Ok(out)
}

/// Every `factor`-th point of each strand of `fine` (laid out as `coarse_offsets` subdivided
/// `factor` times).
pub fn coarsen(fine: &[Vector3<f32>], coarse_offsets: &[u32], factor: usize) -> Vec<Vector3<f32>> {
    let mut out = Vec::with_capacity(*coarse_offsets.last().unwrap_or(&0) as usize);
    let mut start = 0usize;
    for w in coarse_offsets.windows(2) {
        let n = (w[1] - w[0]) as usize;
        out.extend((0..n).map(|i| fine[start + i * factor]));
        start += (n - 1) * factor + 1;
    }
    out
}

/// Why a case's truth cannot be computed; each variant says which run failed.
#[derive(Debug, thiserror::Error)]
pub enum TruthError {
    /// The case cannot be built again at more segments.
    #[error("{0}")]
    Case(#[from] CaseError),
    /// The case's strands cannot be subdivided.
    #[error("{0}")]
    Subdivide(#[source] HairError),
    /// The rod reference run failed.
    #[error("the rod at {factor}× the segments, {substeps} substeps/frame: {source}")]
    Rod {
        /// Subdivisions of the case's segments.
        factor: usize,
        /// Substeps per frame.
        substeps: u32,
        /// The solver's error.
        source: HairError,
    },
    /// The rod's stability bound cannot be computed.
    #[error("{0}")]
    Bound(#[source] HairError),
    /// The chain cannot hang across its span.
    #[error("{links} links of {link} m cannot hang across {span} m")]
    Catenary {
        /// Links of the chain.
        links: usize,
        /// Length of a link, m.
        link: f64,
        /// Distance between the pinned ends, m.
        span: f64,
    },
}

/// `case` with its strands subdivided `factor` times, or built again at `factor` times its
/// segments where it can be ([`Case::resegment`]). No head solid: the truth's penetration of the
/// head is not measured (the drape's sphere is analytic and kept).
fn refined(case: &Case, factor: usize) -> Result<Case, TruthError> {
    let mut sim = case.sim.clone();
    if let (Some(r), true) = (case.resegment, factor > 1) {
        // The same physical strand sampled finer (a helix stays a helix, not the polygon of
        // the case's points cut finer).
        sim = (r.build)(r.segments * factor)?.sim;
    } else if factor > 1 {
        sim.strands = subdivide(&case.sim.strands, factor, case.mass_per_length)
            .map_err(TruthError::Subdivide)?;
        sim.strands
            .reset_to_rest(&sim.scalp_at(sim.first_frame as f32));
    }
    Ok(Case {
        name: case.name,
        title: case.title,
        sim,
        samples: case.samples.clone(),
        energy_scale: case.energy_scale,
        head: None,
        represented_hairs: case.represented_hairs,
        truth: case.truth,
        truth_subdivision: case.truth_subdivision,
        mass_per_length: case.mass_per_length,
        physical_stretch: case.physical_stretch,
        resegment: case.resegment,
        ball: case.ball,
    })
}

/// Runs the rod truth of `case` at `factor` subdivisions and `substeps`, at the case's points.
fn rod_run(case: &Case, factor: usize, substeps: u32) -> Result<(Trace, Samples), TruthError> {
    let fine = refined(case, factor)?;
    let trace = Rod::REFERENCE
        .run(&fine, Some(substeps))
        .map_err(|source| TruthError::Rod {
            factor,
            substeps,
            source,
        })?;
    let offsets = case.sim.strands.offsets();
    let samples = trace
        .samples
        .iter()
        .map(|x| coarsen(x, offsets, factor))
        .collect();
    Ok((trace, samples))
}

fn rms(case: &Case, a: &Samples, b: &Samples) -> f64 {
    let w = case.sim.strands.inverse_masses();
    let sq: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| hairsys::accuracy::position_rms(x, y, w).powi(2))
        .sum();
    (sq / a.len().max(1) as f64).sqrt()
}

/// The truth of `case`; `min_substeps` is the rod truth's least substep count per frame. The
/// error says which run failed.
pub fn truth(case: &Case, min_substeps: u32) -> Result<Truth, TruthError> {
    match case.truth {
        TruthKind::Pendulum => Ok(pendulum(case)),
        TruthKind::Catenary => catenary(case),
        TruthKind::Rod => {
            let step = 1.0 / case.sim.settings.fps as f64;
            let factor = case.truth_subdivision.max(1);
            let fine = refined(case, factor)?;
            let bound = Rod::REFERENCE.bound(&fine).map_err(TruthError::Bound)?;
            let needed = (step / (BOUND_FRACTION * bound)).ceil() as u32;
            let n = min_substeps.max(needed).next_power_of_two();
            let (trace, samples) = rod_run(case, factor, n)?;
            let (_, half) = rod_run(case, factor, n / 2)?;
            // Twice the subdivision needs up to four times the substeps to keep the same
            // fraction of its (bending) bound.
            let finer_bound = Rod::REFERENCE
                .bound(&refined(case, 2 * factor)?)
                .map_err(TruthError::Bound)?;
            let finer_n =
                n.max(((step / (BOUND_FRACTION * finer_bound)).ceil() as u32).next_power_of_two());
            let (_, finer) = rod_run(case, 2 * factor, finer_n)?;
            let time_change = rms(case, &samples, &half);
            let space_change = rms(case, &samples, &finer);
            Ok(Truth {
                samples,
                energy_end: Some(trace.energy_end),
                convergence: Convergence {
                    case: case.name.into(),
                    truth: format!(
                        "rod, {} projection iterations, {factor}× the case's segments",
                        Rod::REFERENCE_ITERATIONS
                    ),
                    substeps: n,
                    space_factor: factor,
                    time_change,
                    space_change,
                    smallest_error: f64::INFINITY,
                    converged: false,
                    penetration: trace.max_penetration as f64,
                },
            })
        }
    }
}

fn analytic_convergence(case: &Case, what: &str) -> Convergence {
    Convergence {
        case: case.name.into(),
        truth: what.into(),
        substeps: 0,
        space_factor: 0,
        time_change: 0.0,
        space_change: 0.0,
        smallest_error: f64::INFINITY,
        converged: true,
        penetration: 0.0,
    }
}

/// The rigid pendulum of the case's single segment (root pinned, bob free), released from rest.
fn pendulum(case: &Case) -> Truth {
    let sim = &case.sim;
    let (root, bob) = (sim.strands.positions[0], sim.strands.positions[1]);
    let arm = (bob - root).cast::<f64>();
    let g = sim.params.gravity().cast::<f64>();
    let down = g.normalize();
    let length = arm.norm();
    let theta0 = arm.angle(&down);
    // The swing plane: `down` and the horizontal part of the arm.
    let side = (arm - down * arm.dot(&down)).normalize();
    let fps = sim.settings.fps as f64;
    let times: Vec<f64> = case
        .samples
        .iter()
        .map(|&f| (f - sim.first_frame) as f64 / fps)
        .collect();
    let angles = analytic::pendulum_angles(length, g.norm(), theta0, &times);
    let samples = angles
        .iter()
        .map(|&th| {
            let p = root.cast::<f64>() + length * (down * th.cos() + side * th.sin());
            vec![root, p.cast::<f32>()]
        })
        .collect();
    let mass = sim.strands.masses()[1] as f64;
    // Kinetic energy 0 at release; potential −m g·x, the solver's convention.
    let energy = -mass * g.dot(&bob.cast::<f64>());
    Truth {
        samples,
        energy_end: Some(energy),
        convergence: analytic_convergence(
            case,
            &format!(
                "analytic: rigid pendulum, period {:.4} s (elliptic integral)",
                analytic::pendulum_period(length, g.norm(), theta0)
            ),
        ),
    }
}

/// The discrete catenary between the case's single strand's two pinned ends.
fn catenary(case: &Case) -> Result<Truth, TruthError> {
    let strands = &case.sim.strands;
    let p = &strands.positions;
    let n = p.len() - 1;
    let link = strands.rest_lengths()[0] as f64;
    let (a, b) = (p[0].cast::<f64>(), p[n].cast::<f64>());
    let span = (b - a).norm();
    let shape = analytic::discrete_catenary(n, link, span).ok_or(TruthError::Catenary {
        links: n,
        link,
        span,
    })?;
    let along = (b - a) / span;
    let up = Vector3::new(0.0, 0.0, 1.0);
    let rest: Vec<Vector3<f32>> = shape
        .iter()
        .map(|q| (a + along * q.x + up * q.z).cast::<f32>())
        .collect();
    let sag = -shape.iter().map(|q| q.z).fold(0.0, f64::min);
    let length = n as f64 * link;
    Ok(Truth {
        samples: vec![rest; case.samples.len()],
        energy_end: None,
        convergence: analytic_convergence(
            case,
            &format!(
                "analytic: discrete catenary of {n} links, sag {sag:.4} m (continuous catenary {:.4} m)",
                analytic::catenary_sag(length, span)
            ),
        ),
    })
}
