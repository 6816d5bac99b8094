//! Budgets checked before work: a scene's memory and a run's time are estimated from the
//! scene's numbers before anything is allocated or stepped, and refused with the estimate, the
//! limit and the way to lift it. A typo (`count = 10000000` for `10000`, `steps = 1000000000`)
//! then costs an error message, not minutes of swapping or a run that never prints.
//!
//! The estimates are deliberately coarse upper bounds — orders of magnitude, not accounting:
//! memory is counted as points × [`BYTES_PER_POINT`] (positions, velocities, rest state, masses
//! and the solver's scratch, each a few 4- or 8-byte numbers per point, rounded up), children as
//! points × samples × [`BYTES_PER_CHILD_POINT`], and time as point-substeps (points × force
//! substeps × steps per frame × frames, each substep weighted by [`substep_weight`]: an
//! implicit substep counts as the explicit ones it costs), the unit `hairsys simulate` reports
//! its throughput in.
//! [`Budget::default`] lets through every scene in `scenes/` and the bench with room to spare;
//! a host that knows better sets its own [`Budget`] (or [`Budget::UNLIMITED`]) on the
//! [`SceneFile`](crate::scene::SceneFile) or the export options, and the command lifts it with
//! `--allow-large`.

use std::fmt;

use hair_core::Integrator;

use crate::scene::integrator::IMPLICIT_SUBSTEP_COST;

/// Explicit substeps one force substep of `integrator` costs in the work estimate: a banded solve
/// per strand for implicit Euler and BDF2 ([`IMPLICIT_SUBSTEP_COST`], measured), one force sweep
/// otherwise (XPBD's solve is counted as one, a lower bound).
pub fn substep_weight(integrator: Integrator) -> f64 {
    match integrator {
        Integrator::ImplicitEuler | Integrator::Bdf2 => IMPLICIT_SUBSTEP_COST,
        Integrator::SemiImplicitEuler | Integrator::ExplicitEuler | Integrator::Xpbd => 1.0,
    }
}

/// The numbers a run's work estimate is made of.
#[derive(Debug, Clone, Copy)]
pub struct RunWork {
    /// Simulated points.
    pub points: usize,
    /// Force substeps per collision step.
    pub substeps: f64,
    /// The integrator, which weighs each substep ([`substep_weight`]).
    pub integrator: Integrator,
    /// Collision steps per frame.
    pub steps: u32,
    /// Frames stepped.
    pub frames: f64,
}

impl RunWork {
    /// The estimate, point-substeps: points × substeps × their weight × steps × frames.
    pub fn point_substeps(&self) -> f64 {
        self.points as f64
            * self.substeps
            * substep_weight(self.integrator)
            * f64::from(self.steps)
            * self.frames
    }

    /// What the estimate is made of, in words.
    fn describe(&self) -> String {
        let weight = substep_weight(self.integrator);
        let note = if weight == 1.0 {
            String::new()
        } else {
            format!(" at {weight}× an explicit one")
        };
        format!(
            "{} points × {} substeps{note} × [solver] steps = {} × {} frames",
            self.points, self.substeps, self.steps, self.frames
        )
    }
}

/// Bytes counted per simulated point (an upper estimate, see the [module](self) docs).
pub const BYTES_PER_POINT: u64 = 256;

/// Bytes counted per child point and time sample: position (12), width (4), colour (12),
/// rounded up for the output buffers.
pub const BYTES_PER_CHILD_POINT: u64 = 32;

/// Largest force substep count per step, explicit or resolved from `substeps = "auto"`.
pub const MAX_SUBSTEPS: u32 = 1_000_000;

/// Limits on memory and time accepted before work starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Budget {
    /// Largest estimated memory, bytes.
    pub memory_bytes: u64,
    /// Largest estimated work of a run, point-substeps.
    pub point_substeps: f64,
}

impl Default for Budget {
    /// 8 GiB and 10¹³ point-substeps (the run's time is this over the `point_substeps_per_s`
    /// a run reports).
    fn default() -> Self {
        Budget {
            memory_bytes: 8 << 30,
            point_substeps: 1e13,
        }
    }
}

/// Something over budget: what, the estimate, the limit and the fix.
#[derive(Debug, Clone, PartialEq)]
pub struct OverBudget {
    /// What was estimated, naming the scene keys or flags it comes from.
    pub what: String,
    /// The estimate (bytes or point-substeps).
    pub estimate: f64,
    /// The limit it exceeds.
    pub limit: f64,
    /// The unit, `"bytes"` or `"point-substeps"`.
    pub unit: &'static str,
}

impl fmt::Display for OverBudget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} needs about {} {} (limit {}); lower it, or lift the limit with --allow-large \
             (library: `Budget::UNLIMITED`)",
            self.what,
            short(self.estimate, self.unit),
            self.unit,
            short(self.limit, self.unit),
        )
    }
}

impl std::error::Error for OverBudget {}

/// `x` readably: GiB for bytes, scientific notation otherwise.
fn short(x: f64, unit: &str) -> String {
    if unit == "bytes" && x >= (1u64 << 30) as f64 {
        format!("{:.1} Gi", x / (1u64 << 30) as f64)
    } else {
        format!("{x:.3e}")
    }
}

impl Budget {
    /// No limit: a host that has its own checks.
    pub const UNLIMITED: Budget = Budget {
        memory_bytes: u64::MAX,
        point_substeps: f64::INFINITY,
    };

    /// Checks `points` simulated points (a product of scene numbers, computed in f64 so it
    /// cannot overflow) against the memory limit.
    pub fn check_points(&self, what: &str, points: f64) -> Result<(), OverBudget> {
        self.check_bytes(what, points * BYTES_PER_POINT as f64)
    }

    /// Checks an estimate in bytes against the memory limit.
    pub fn check_bytes(&self, what: &str, bytes: f64) -> Result<(), OverBudget> {
        if bytes <= self.memory_bytes as f64 {
            return Ok(());
        }
        Err(OverBudget {
            what: what.to_string(),
            estimate: bytes,
            limit: self.memory_bytes as f64,
            unit: "bytes",
        })
    }

    /// Checks the work of a run against the time limit; `context` (a flag, or empty) leads the
    /// message.
    pub fn check_run(&self, context: &str, work: &RunWork) -> Result<(), OverBudget> {
        self.check_work(
            &format!("{context}the run ({})", work.describe()),
            work.point_substeps(),
        )
    }

    /// Checks a run's work, point-substeps, against the time limit.
    pub fn check_work(&self, what: &str, point_substeps: f64) -> Result<(), OverBudget> {
        if point_substeps <= self.point_substeps {
            return Ok(());
        }
        Err(OverBudget {
            what: what.to_string(),
            estimate: point_substeps,
            limit: self.point_substeps,
            unit: "point-substeps",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ten_million_strands_of_33_points_are_over_the_default_memory_budget() {
        let err = Budget::default()
            .check_points("[hair] count × (segments + 1)", 1e7 * 33.0)
            .unwrap_err();
        assert_eq!(err.estimate, 1e7 * 33.0 * BYTES_PER_POINT as f64);
        assert!(err.to_string().contains("--allow-large"), "{err}");
        assert!(Budget::UNLIMITED
            .check_points("[hair] count", 1e7 * 33.0)
            .is_ok());
    }

    #[test]
    fn a_billion_steps_are_over_the_default_work_budget_and_a_small_run_is_not() {
        let b = Budget::default();
        assert!(b.check_work("steps", 1e9 * 1e5).is_err());
        assert!(b.check_work("steps", 1e6 * 48.0).is_ok());
    }
}
