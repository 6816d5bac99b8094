//! One strand-solver type over the three strand models: [`StrandSolver`].
//!
//! hair-core has three ways to advance a [`StrandSet`] by a frame, each with its own solver and
//! its own report: seed 001's mass-spring chain ([`Solver`]), seed 002's discrete elastic rod
//! ([`RodSolver`]) and seed 000's hair strips ([`StripSolver`]). A host should not have to know
//! which one a scene picked: [`StrandSolver`] holds any of them and has one
//! [`StrandSolver::step_frame`] with an optional collider set, one [`FrameReport`] whose
//! [`ModelFigures`] carry what only one model measures (the rod's projection, the strips'
//! post-step passes), and one [`ComponentSet`] naming what runs. The model solvers stay public:
//! they are the parts (like rapier's pipelines), this is the one door.
//!
//! Like the model solvers, a `StrandSolver` does not own the strands: it borrows them for one
//! frame (rapier's "pipeline borrows the sets" shape, see `STYLE.md`).

mod components;

pub use components::{Component, ComponentSet};

use crate::contacts::Colliders;
use crate::error::Result;
use crate::mesh::RootFrame;
use crate::rod::{ProjectionReport, RodSolver, StrandModel};
use crate::solver::{FrameReport, Solver};
use crate::strands::{Scalp, StrandSet};
use crate::strips::StripSolver;

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

/// What the strip model's post-step passes did in a frame (see [`crate::strips`]).
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
    MassSpring(Box<Solver>),
    /// Seed 002's discrete elastic rod.
    Rod(Box<RodSolver>),
    /// Seed 000's hair strips: mass-spring edge strands with the strip model's post-step passes.
    Strips(Box<StripSolver>),
}

impl From<Solver> for StrandSolver {
    fn from(s: Solver) -> Self {
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
    pub fn mass_spring(&self) -> Option<&Solver> {
        match self {
            StrandSolver::MassSpring(s) => Some(s),
            StrandSolver::Strips(s) => Some(s.solver()),
            StrandSolver::Rod(_) => None,
        }
    }

    /// The mass-spring solver for a host to change animatable parameters between frames
    /// (gravity, goal stiffness, fields, hair–hair), if this model has one.
    pub fn mass_spring_mut(&mut self) -> Option<&mut Solver> {
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
