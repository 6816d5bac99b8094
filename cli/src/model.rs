//! The strand model a run uses (`[solver] model` in the scene): hair-core's mass-spring
//! [`Solver`] or its discrete-rod [`RodSolver`], behind one interface so `simulate` runs either
//! the same way (same strands, cache and children).

use hair_core::solver::Components;
use hair_core::{
    Colliders, FrameReport, HairError, ProjectionReport, RodSolver, Scalp, Solver, StrandModel,
    StrandSet,
};

use crate::scene::Simulation;
use hair_core::strips::{HeadShape, StripSolver};

/// A solver of either model.
#[derive(Debug)]
pub enum ModelSolver {
    /// Seed 001's mass-spring chain.
    MassSpring(Box<Solver>),
    /// Seed 002's discrete elastic rod, with its projection figures summed over the frames run.
    Rod(Box<RodSolver>, ProjectionReport),
    /// Seed 000's hair strips: mass-spring edge strands with the strip model's post-step passes.
    Strips(Box<StripSolver>),
}

impl ModelSolver {
    /// The rod solver of `sim` (its `[solver]`, `[physics]` and `[rod]` tables), for its first
    /// frame. The mass-spring solver is built by the caller, which may add components to it.
    pub fn rod(sim: &Simulation) -> Result<Self, HairError> {
        let solver = RodSolver::new(
            sim.settings,
            sim.params,
            sim.rod,
            &sim.strands,
            &sim.scalp_at(sim.first_frame as f32),
            sim.first_frame,
        )?;
        Ok(ModelSolver::Rod(
            Box::new(solver),
            ProjectionReport::default(),
        ))
    }

    /// The strip solver of `sim` (its `[solver]`, `[physics]` and `[strips]` tables), for its
    /// first frame; with `[scalp.collider]` the rest scalp is the head of the two-stage collision.
    pub fn strips(sim: &Simulation) -> Result<Self, HairError> {
        let settings = sim.strips.ok_or_else(|| HairError::Parameter {
            name: "strips".into(),
            value: "absent".into(),
            fix: "[solver] model = \"strips\" needs a [strips] section".into(),
        })?;
        let head = match (sim.scalp_collider.is_some(), sim.rest_mesh()) {
            (true, Some(mesh)) => Some(HeadShape::new(mesh)?),
            _ => None,
        };
        let solver = StripSolver::new(
            sim.settings,
            sim.params,
            &sim.strands,
            &sim.scalp_at(sim.first_frame as f32),
            sim.first_frame,
            settings,
            head,
        )?;
        Ok(ModelSolver::Strips(Box::new(solver)))
    }

    /// Which model this is.
    pub fn model(&self) -> StrandModel {
        match self {
            ModelSolver::MassSpring(_) => StrandModel::MassSpring,
            ModelSolver::Rod(..) => StrandModel::Rod,
            ModelSolver::Strips(_) => StrandModel::Strips,
        }
    }

    /// Advances one frame (see [`Solver::step_frame_with_colliders`] and
    /// [`RodSolver::step_frame_with_colliders`]).
    pub fn step_frame_with_colliders(
        &mut self,
        strands: &mut StrandSet,
        scalp: &Scalp,
        colliders: &mut Colliders,
    ) -> Result<FrameReport, HairError> {
        match self {
            ModelSolver::MassSpring(s) => s.step_frame_with_colliders(strands, scalp, colliders),
            ModelSolver::Rod(s, total) => {
                let report = s.step_frame_with_colliders(strands, scalp, colliders)?;
                total.merge(&report.projection);
                Ok(report.frame)
            }
            ModelSolver::Strips(s) => Ok(s.step_frame(strands, scalp, Some(colliders))?.solver),
        }
    }

    /// Substeps per collision step in use.
    pub fn substeps(&self) -> u32 {
        match self {
            ModelSolver::MassSpring(s) => s.substeps(),
            ModelSolver::Rod(s, _) => s.substeps(),
            ModelSolver::Strips(s) => s.solver().substeps(),
        }
    }

    /// Substep length in use, s.
    pub fn dt(&self) -> f64 {
        match self {
            ModelSolver::MassSpring(s) => s.dt(),
            ModelSolver::Rod(s, _) => s.dt(),
            ModelSolver::Strips(s) => s.solver().dt(),
        }
    }

    /// Predicted stable limit of the substep, s (stiffest spring, or stiffest bending for the
    /// rod, on the lightest point).
    pub fn dt_bound(&self) -> f64 {
        match self {
            ModelSolver::MassSpring(s) => s.bound().dt_max,
            ModelSolver::Rod(s, _) => s.dt_max(),
            ModelSolver::Strips(s) => s.solver().bound().dt_max,
        }
    }

    /// Model components the solver runs.
    pub fn components(&self, strands: &StrandSet) -> Components {
        match self {
            ModelSolver::MassSpring(s) => s.components(strands),
            ModelSolver::Rod(s, _) => s.components(strands),
            ModelSolver::Strips(s) => s.solver().components(strands),
        }
    }

    /// The rod's projection figures summed over the frames run (`None` for mass-spring).
    pub fn projection(&self) -> Option<ProjectionReport> {
        match self {
            ModelSolver::MassSpring(_) | ModelSolver::Strips(_) => None,
            ModelSolver::Rod(_, p) => Some(*p),
        }
    }
}
