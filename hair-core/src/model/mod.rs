//! The strand models side by side, and one strand-solver type over them: [`StrandSolver`].
//!
//! hair-core has three ways to advance a [`StrandSet`] by a frame, each with its own solver and
//! its own report: seed 001's mass-spring chain ([`mass_spring`]: [`MassSpringSolver`]), seed
//! 002's discrete elastic rod ([`rod`]: [`RodSolver`]) and seed 000's hair strips ([`strips`]:
//! [`StripSolver`], mass-spring edge strands with post-step passes). [`StrandModel`] names them
//! as a scene does. A host should not have to know which one a scene picked: [`StrandSolver`]
//! holds any of them and has one [`StrandSolver::step_frame`] with an optional collider set, one
//! [`FrameReport`] whose [`ModelFigures`] carry what only one model measures (the rod's
//! projection, the strips' post-step passes), and one [`ComponentSet`] naming what runs. The
//! model solvers stay public: they are the parts (like rapier's pipelines), this is the one door.
//! The numerics they share (kernels, integrators, banded solves, parameters, the stability
//! bound, sag-free rest shapes) are in [`crate::integrate`].
//!
//! Like the model solvers, a `StrandSolver` does not own the strands: it borrows them for one
//! frame (rapier's "pipeline borrows the sets" shape, see `STYLE.md`).
//!
//! # State and workspace
//! Each solver keeps apart what the next frame starts from — its **state**: the frame number
//! and root frames, the rod's twist angles, the parameters a host may change between frames —
//! from its **workspace**: contact lists, the hair–hair grid and other buffers that every step
//! rebuilds before reading, which can be dropped. [`StrandSolver::snapshot_state`] copies the
//! state alone ([`StrandSolverState`]) and [`StrandSolver::restore_state`] puts it back into a
//! solver of the same strands, whatever its workspace holds: with the strands' positions and
//! velocities and the colliders (all state, see [`Colliders`]), stepping on gives the same bits
//! as stepping on from where the state was taken.

mod components;
pub mod mass_spring;
pub mod rod;
pub mod strips;

use std::time::Duration;

pub use components::{Component, ComponentSet};
pub use mass_spring::{MassSpringSolver, MassSpringSolverState};
pub use rod::{ProjectionReport, RodSolver, RodSolverState};
pub use strips::StripSolver;

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::contacts::Colliders;
use crate::error::{HairError, Result};
use crate::mesh::RootFrame;
use crate::strands::{Scalp, StrandSet};

/// Which strand model a hair system runs (the scene's `[solver] model`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum StrandModel {
    /// The mass-spring chain of seed 001 ([`MassSpringSolver`]), the default.
    #[default]
    MassSpring,
    /// The discrete elastic rod of seed 002 ([`RodSolver`]).
    Rod,
    /// The hair strips of seed 000 ([`StripSolver`]): mass-spring edge strands in pairs, each
    /// pair bounding a ribbon that stands for many hairs.
    Strips,
}

impl StrandModel {
    /// True for the default, [`StrandModel::MassSpring`].
    pub fn is_mass_spring(&self) -> bool {
        *self == StrandModel::MassSpring
    }

    /// The model's name as written in scenes: `"mass-spring"`, `"rod"` or `"strips"`.
    pub fn name(&self) -> &'static str {
        match self {
            StrandModel::MassSpring => "mass-spring",
            StrandModel::Rod => "rod",
            StrandModel::Strips => "strips",
        }
    }
}

/// Wall-clock cost of one frame by phase.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PhaseTimes {
    /// Evaluating root frames on the scalp.
    pub roots: Duration,
    /// Force substeps, damping and position updates of all strands, with the blow-up checks
    /// (the contact response included).
    pub strands: Duration,
    /// Contact detection (zero without colliders).
    pub contacts: Duration,
    /// Hair–hair voxel grid: building it, friction and repulsion (zero when off).
    pub volume: Duration,
    /// Force fields, evaluated in batch over all points (zero without fields).
    pub fields: Duration,
}

/// What one frame did.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameReport {
    /// Frame number that was computed.
    pub frame: u32,
    /// Force substeps per collision step used.
    pub substeps: u32,
    /// Collision steps run: the scene's steps, times the fast-motion factor when colliders moved
    /// too far for the contact model's tolerance in the frame (see
    /// [`crate::contacts::collider_set`]).
    pub steps: u32,
    /// Points × substeps advanced in this frame.
    pub point_substeps: u64,
    /// Point contacts found, summed over the frame's collision steps (0 without colliders).
    pub contact_points: u64,
    /// Points that ended the frame closer to a collider than their radius plus its thickness
    /// without a contact in the last step — they outran detection's margin — and were put back
    /// on the surface by the frame-end check (see `contacts::escapes`; 0 without colliders).
    pub escaped_points: u64,
    /// Points that had a contact in the last step and ended the frame deeper inside a collider
    /// than the contact model's own error (25 µm), put back on its surface by the same check
    /// (see `contacts::escapes`; 0 without colliders).
    pub deep_contact_points: u64,
    /// Largest relative segment elongation `len/rest − 1` at the end of the frame (0 if none is
    /// longer than at rest).
    pub max_stretch: f32,
    /// Wall-clock cost by phase.
    pub times: PhaseTimes,
    /// What only this frame's model measures.
    pub figures: ModelFigures,
}

/// What only one model measures in a frame, inside [`FrameReport::figures`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum ModelFigures {
    /// The mass-spring model has nothing beyond the common figures.
    #[default]
    MassSpring,
    /// The rod's projection (iterations, residual, strain).
    Rod(ProjectionReport),
    /// The strips' post-step passes.
    Strips(StripFigures),
}

/// What the strip model's post-step passes did in a frame (see [`strips`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StripFigures {
    /// Whether any edge point came within the head's bounding sphere, so the frame ran the
    /// precise contact pipeline.
    pub near_head: bool,
    /// Edge strands whose first segment the angle limiter turned back.
    pub angle_corrections: usize,
    /// Edge points the head's precise stage moved out of the head.
    pub pushed_out: usize,
    /// Largest segment strain found by the final Provot pass, before it corrected it
    /// (dimensionless).
    pub max_strain_before: f32,
}

/// A strand solver of any model: the one type a host steps. See the module docs.
#[derive(Debug, Clone)]
pub enum StrandSolver {
    /// Seed 001's mass-spring chain.
    MassSpring(Box<MassSpringSolver>),
    /// Seed 002's discrete elastic rod.
    Rod(Box<RodSolver>),
    /// Seed 000's hair strips: mass-spring edge strands with the strip model's post-step passes.
    Strips(Box<StripSolver>),
}

impl From<MassSpringSolver> for StrandSolver {
    fn from(s: MassSpringSolver) -> Self {
        StrandSolver::MassSpring(Box::new(s))
    }
}

impl From<RodSolver> for StrandSolver {
    fn from(s: RodSolver) -> Self {
        StrandSolver::Rod(Box::new(s))
    }
}

impl From<StripSolver> for StrandSolver {
    fn from(s: StripSolver) -> Self {
        StrandSolver::Strips(Box::new(s))
    }
}

impl StrandSolver {
    /// Which model this is.
    pub fn model(&self) -> StrandModel {
        match self {
            StrandSolver::MassSpring(_) => StrandModel::MassSpring,
            StrandSolver::Rod(_) => StrandModel::Rod,
            StrandSolver::Strips(_) => StrandModel::Strips,
        }
    }

    /// A copy of the solver's state, without its workspace (see the module docs).
    pub fn snapshot_state(&self) -> StrandSolverState {
        match self {
            StrandSolver::MassSpring(s) => StrandSolverState::MassSpring(s.snapshot_state()),
            StrandSolver::Rod(s) => StrandSolverState::Rod(s.snapshot_state()),
            StrandSolver::Strips(s) => StrandSolverState::Strips(s.solver().snapshot_state()),
        }
    }

    /// Puts the solver back in `state`, taken by [`StrandSolver::snapshot_state`] from a solver
    /// of the same model and strands: stepping on gives the same bits as stepping on from where
    /// it was taken, whatever the workspace holds. Refused for a state of another model or
    /// another number of strands.
    pub fn restore_state(&mut self, state: &StrandSolverState) -> Result<()> {
        match (self, state) {
            (StrandSolver::MassSpring(s), StrandSolverState::MassSpring(state)) => {
                s.restore_state(state)
            }
            (StrandSolver::Rod(s), StrandSolverState::Rod(state)) => s.restore_state(state),
            (StrandSolver::Strips(s), StrandSolverState::Strips(state)) => {
                s.solver_mut().restore_state(state)
            }
            (solver, state) => Err(HairError::Parameter {
                name: "state".into(),
                value: format!("a state of the {} model", state.model().name()),
                fix: format!(
                    "restore a state of this solver's model ({})",
                    solver.model().name()
                ),
            }),
        }
    }

    /// Advances `strands` by one frame, to the instant at which `scalp` is given, colliding
    /// with `colliders` (posed for the frame's end) when given. The report's
    /// [`FrameReport::figures`] carry the model's own figures.
    ///
    /// On an error the strands may hold a partly advanced state: do not write it anywhere.
    pub fn step_frame(
        &mut self,
        strands: &mut StrandSet,
        scalp: &Scalp,
        colliders: Option<&mut Colliders>,
    ) -> Result<FrameReport> {
        match self {
            StrandSolver::MassSpring(s) => match colliders {
                Some(c) => s.step_frame_with_colliders(strands, scalp, c),
                None => s.step_frame(strands, scalp),
            },
            StrandSolver::Rod(s) => {
                let report = match colliders {
                    Some(c) => s.step_frame_with_colliders(strands, scalp, c)?,
                    None => s.step_frame(strands, scalp)?,
                };
                Ok(FrameReport {
                    figures: ModelFigures::Rod(report.projection),
                    ..report.frame
                })
            }
            StrandSolver::Strips(s) => {
                let report = s.step_frame(strands, scalp, colliders)?;
                Ok(FrameReport {
                    figures: ModelFigures::Strips(StripFigures {
                        near_head: report.near_head,
                        angle_corrections: report.angle_corrections,
                        pushed_out: report.pushed_out,
                        max_strain_before: report.max_strain_before,
                    }),
                    ..report.solver
                })
            }
        }
    }

    /// The mass-spring solver (also the strips' edge-strand solver), if this model has one.
    pub fn mass_spring(&self) -> Option<&MassSpringSolver> {
        match self {
            StrandSolver::MassSpring(s) => Some(s),
            StrandSolver::Strips(s) => Some(s.solver()),
            StrandSolver::Rod(_) => None,
        }
    }

    /// The mass-spring solver for a host to change animatable parameters between frames
    /// (gravity, goal stiffness, fields, hair–hair), if this model has one.
    pub fn mass_spring_mut(&mut self) -> Option<&mut MassSpringSolver> {
        match self {
            StrandSolver::MassSpring(s) => Some(s),
            StrandSolver::Strips(s) => Some(s.solver_mut()),
            StrandSolver::Rod(_) => None,
        }
    }

    /// Force substeps per collision step in use.
    pub fn substeps(&self) -> u32 {
        match self {
            StrandSolver::MassSpring(s) => s.substeps(),
            StrandSolver::Rod(s) => s.substeps(),
            StrandSolver::Strips(s) => s.solver().substeps(),
        }
    }

    /// Substep length in use, s.
    pub fn dt(&self) -> f64 {
        match self {
            StrandSolver::MassSpring(s) => s.dt(),
            StrandSolver::Rod(s) => s.dt(),
            StrandSolver::Strips(s) => s.solver().dt(),
        }
    }

    /// Predicted stable limit of the substep, s: the stiffest spring on the lightest point
    /// (mass-spring, strips) or the stiffest bending mode (rod).
    pub fn dt_bound(&self) -> f64 {
        match self {
            StrandSolver::MassSpring(s) => s.bound().dt_max,
            StrandSolver::Rod(s) => s.dt_max(),
            StrandSolver::Strips(s) => s.solver().bound().dt_max,
        }
    }

    /// Frame number of the current state.
    pub fn frame(&self) -> u32 {
        match self {
            StrandSolver::MassSpring(s) => s.frame(),
            StrandSolver::Rod(s) => s.frame(),
            StrandSolver::Strips(s) => s.solver().frame(),
        }
    }

    /// Root frames of the current state, one per strand.
    pub fn roots(&self) -> &[RootFrame] {
        match self {
            StrandSolver::MassSpring(s) => s.roots(),
            StrandSolver::Rod(s) => s.roots(),
            StrandSolver::Strips(s) => s.solver().roots(),
        }
    }

    /// Model components this solver runs (colliders are the host's: add
    /// [`Component::Contacts`] when it steps with a non-empty set).
    pub fn components(&self, strands: &StrandSet) -> ComponentSet {
        match self {
            StrandSolver::MassSpring(s) => s.components(strands),
            StrandSolver::Rod(s) => s.components(strands),
            StrandSolver::Strips(s) => {
                let mut c = s.solver().components(strands);
                c.insert(Component::StripLimits);
                c
            }
        }
    }

    /// Total mechanical energy of `strands` in this model (J): kinetic, gravity and the model's
    /// elastic terms (see [`crate::energy`] and [`RodSolver::energy`]).
    pub fn energy(&self, strands: &StrandSet) -> f64 {
        match self {
            StrandSolver::MassSpring(s) => crate::energy(strands, s.params(), s.roots()).total(),
            StrandSolver::Strips(s) => {
                crate::energy(strands, s.solver().params(), s.solver().roots()).total()
            }
            StrandSolver::Rod(s) => s.energy(strands).total(),
        }
    }
}

/// The state of a [`StrandSolver`] at one frame, without its workspace
/// ([`StrandSolver::snapshot_state`]; see the module docs).
#[derive(Debug, Clone)]
pub enum StrandSolverState {
    /// The state of a [`MassSpringSolver`].
    MassSpring(MassSpringSolverState),
    /// The state of a [`RodSolver`].
    Rod(RodSolverState),
    /// The state of a [`StripSolver`]: its edge strands' mass-spring solver's (the post-step
    /// passes keep nothing between frames).
    Strips(MassSpringSolverState),
}

impl StrandSolverState {
    /// Which model the state is of.
    pub fn model(&self) -> StrandModel {
        match self {
            StrandSolverState::MassSpring(_) => StrandModel::MassSpring,
            StrandSolverState::Rod(_) => StrandModel::Rod,
            StrandSolverState::Strips(_) => StrandModel::Strips,
        }
    }

    /// Frame number of the state.
    pub fn frame(&self) -> u32 {
        match self {
            StrandSolverState::MassSpring(s) | StrandSolverState::Strips(s) => s.frame(),
            StrandSolverState::Rod(s) => s.frame(),
        }
    }

    /// Root frames of the state, one per strand.
    pub fn roots(&self) -> &[RootFrame] {
        match self {
            StrandSolverState::MassSpring(s) | StrandSolverState::Strips(s) => s.roots(),
            StrandSolverState::Rod(s) => s.roots(),
        }
    }
}
