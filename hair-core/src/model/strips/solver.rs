//! [`StripSolver`]: one frame of the strip model (see the module docs of [`crate::model::strips`]).

use crate::contacts::Colliders;
use crate::error::{HairError, Result};
use crate::integrate::{HairParams, SolverSettings};
use crate::model::{FrameReport, MassSpringSolver};
use crate::strands::{Scalp, StrandSet};

use super::head::HeadShape;
use super::limits::{limit_root_angles, limit_strain, RootAngleLimit};

/// Settings of the strip model's post-step passes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StripSettings {
    /// Provot's strain limit: segments end every substep and every frame at most
    /// `(1 + max_strain) ×` their rest length (dimensionless, ≥ 0).
    pub max_strain: f32,
    /// Root angle limit; `None` switches the limiter off.
    pub root_angle: Option<RootAngleLimit>,
    /// Gap (m, ≥ 0) the head's precise stage keeps between edge points and the head surface.
    pub clearance: f32,
}

impl Default for StripSettings {
    fn default() -> Self {
        Self {
            max_strain: 0.05,
            root_angle: RootAngleLimit::new(60f32.to_radians()).ok(),
            clearance: 2e-3,
        }
    }
}

impl StripSettings {
    /// Checks `max_strain` and `clearance` (the angle limit is checked when it is made).
    pub fn validate(&self) -> Result<()> {
        crate::error::check_non_negative("strips.max_strain", self.max_strain)?;
        crate::error::check_non_negative("strips.clearance", self.clearance)
    }
}

/// What one frame of the strip model did.
#[derive(Debug, Clone)]
pub struct StripFrameReport {
    /// The mass-spring solver's report for the edge strands.
    pub solver: FrameReport,
    /// Whether any edge point came within the head's bounding sphere (first stage), so the
    /// frame ran the precise contact pipeline.
    pub near_head: bool,
    /// Edge strands whose first segment the angle limiter turned back.
    pub angle_corrections: usize,
    /// Edge points the precise stage moved out of the head after the post-step passes.
    pub pushed_out: usize,
    /// Largest segment strain found by the final Provot pass, before it corrected it.
    pub max_strain_before: f32,
}

/// Advances the edge strands of a [`super::StripSet`] (its `strands`): the mass-spring
/// [`MassSpringSolver`] with Provot's strain limit in every substep, then the root angle limiter,
/// the head's precise stage and a final Provot pass.
#[derive(Debug, Clone)]
pub struct StripSolver {
    solver: MassSpringSolver,
    settings: StripSettings,
    head: Option<HeadShape>,
}

impl StripSolver {
    /// Prepares the solver for the edge strands `strands` (a [`super::StripSet`]'s) on `scalp` at
    /// `start_frame`. `solver_settings.max_strain`
    /// is replaced by `settings.max_strain`. `head` (body space) enables the two-stage collision.
    pub fn new(
        mut solver_settings: SolverSettings,
        params: HairParams,
        strands: &StrandSet,
        scalp: &Scalp,
        start_frame: u32,
        settings: StripSettings,
        head: Option<HeadShape>,
    ) -> Result<Self> {
        settings.validate()?;
        if strands.is_empty() || !strands.len().is_multiple_of(2) {
            return Err(HairError::Parameter {
                name: "strips".into(),
                value: format!("{} edge strands", strands.len()),
                fix: "a strip set has two edge strands per strip and at least one strip; check \
                      the strip region and triangles"
                    .into(),
            });
        }
        solver_settings.max_strain = Some(settings.max_strain);
        let solver = MassSpringSolver::new(solver_settings, params, strands, scalp, start_frame)?;
        Ok(Self {
            solver,
            settings,
            head,
        })
    }

    /// The underlying mass-spring solver.
    pub fn solver(&self) -> &MassSpringSolver {
        &self.solver
    }

    /// The underlying mass-spring solver, for a host to change animatable parameters between
    /// frames.
    pub fn solver_mut(&mut self) -> &mut MassSpringSolver {
        &mut self.solver
    }

    /// The strip settings in use.
    pub fn settings(&self) -> &StripSettings {
        &self.settings
    }

    /// The head shape of the two-stage collision, if any.
    pub fn head(&self) -> Option<&HeadShape> {
        self.head.as_ref()
    }

    /// Advances the edge strands `strands` by one frame to the instant at which `scalp` is given.
    /// With `colliders` and a head, the frame runs the contact pipeline only when an edge point may
    /// reach the head's bounding sphere during the frame (first stage).
    pub fn step_frame(
        &mut self,
        strands: &mut StrandSet,
        scalp: &Scalp,
        colliders: Option<&mut Colliders>,
    ) -> Result<StripFrameReport> {
        let frame_dt = 1.0 / self.solver.settings().fps;
        let near_head = match &self.head {
            Some(head) => strands
                .positions
                .iter()
                .zip(&strands.velocities)
                .any(|(x, v)| {
                    let reach = v.norm() * frame_dt + self.settings.clearance;
                    head.near(&scalp.body, x, reach)
                }),
            None => true,
        };
        let solver = match colliders {
            Some(c) if near_head => self.solver.step_frame_with_colliders(strands, scalp, c)?,
            _ => self.solver.step_frame(strands, scalp)?,
        };
        let angle_corrections = match self.settings.root_angle {
            Some(limit) => {
                let roots = strands.root_frames(scalp);
                limit_root_angles(strands, &roots, limit)
            }
            None => 0,
        };
        let mut pushed_out = 0;
        if let Some(head) = &self.head {
            for i in 0..strands.point_count() {
                if strands.inverse_masses()[i] == 0.0 {
                    continue;
                }
                let x = strands.positions[i];
                if let Some(out) = head.push_out(&scalp.body, &x, self.settings.clearance) {
                    strands.positions[i] = out;
                    // No velocity left into the head along the push.
                    if let Some(n) = (out - x).try_normalize(1e-12) {
                        let v = &mut strands.velocities[i];
                        let into = v.dot(&n);
                        if into < 0.0 {
                            *v -= n * into;
                        }
                    }
                    pushed_out += 1;
                }
            }
        }
        let max_strain_before = limit_strain(strands, self.settings.max_strain);
        Ok(StripFrameReport {
            solver,
            near_head,
            angle_corrections,
            pushed_out,
            max_strain_before,
        })
    }
}
