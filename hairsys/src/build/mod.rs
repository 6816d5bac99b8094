//! The one assembly path: from what a door hands over to a [`Simulation`] ready to run.
//!
//! Every door builds the same simulation from the same inputs:
//!
//! | door | what it reads | module |
//! |---|---|---|
//! | a scene file (`hairsys simulate`, [`crate::Session::from_scene`]) | the TOML schema of [`crate::scene`] and the files it names | [`SceneFile::build`](crate::scene::SceneFile::build) in `scene_file` |
//! | a host's arrays (Python, the Blender add-on, a C++ plugin) | a groom and a scalp as flat arrays | [`groom`] |
//!
//! Each door turns its input into strands at rest on the scalp (generated, snapped guides,
//! interpolated simulation hairs, explicit point lists) with their per-strand material
//! factors, and says what will press on the hair over the shot ([`ContactLoad`]). From there
//! both go through the same steps, in this order:
//!
//! 1. [`choose_integrator`]: `"auto"` picks the integrator by one rule (module
//!    [`crate::scene::integrator`]) from the strands' stability bound, their sharpest rest joint
//!    and the contact load; a named integrator is taken as it is.
//! 2. [`Simulation::settle`]: the roots are checked against the scalp, the strands are put at
//!    rest, sag-free rest shapes are solved if asked for (so a groom holds its shape at the
//!    first frame), the hair–hair grid and every collider are checked once.
//! 3. [`crate::Session::from_simulation`] makes the solver of the chosen model and the session.
//!
//! Each door reports the same failures in its own words: a scene names its sections and keys,
//! a host its arguments ([`SettleError`] carries the facts, not the wording).

use hair_core::{
    HairError, HairParams, SolverSettings, StabilityBound, StrandModel, StrandScales, StrandSet,
};

use crate::scene::integrator::{self, ContactLoad, IntegratorChoice, ResolvedIntegrator};
pub mod groom;
mod scene_file;
mod simulation;

pub use simulation::{SceneCollider, Simulation};

/// Resolves `choice` for `strands` of `model` run with `params` (strand `s` with
/// `scales[s]`, empty for one material) under the contact load `contact`, and writes the
/// integrator (and, for BDF2 on sharply bent hair, the finer substep count) into `settings`.
/// The same rule for every door: see [`crate::scene::integrator`].
pub fn choose_integrator(
    choice: IntegratorChoice,
    model: StrandModel,
    settings: &mut SolverSettings,
    strands: &StrandSet,
    params: &HairParams,
    scales: &[StrandScales],
    contact: &ContactLoad,
) -> (ResolvedIntegrator, StabilityBound) {
    let bound = StabilityBound::of_scaled(strands, params, scales);
    let resolved = choice.resolve(
        model,
        settings,
        &bound,
        integrator::max_rest_turn(strands),
        contact,
    );
    settings.integrator = resolved.integrator;
    if let Some(n) = resolved.substeps_override {
        settings.substeps = hair_core::Substeps::Fixed(n);
    }
    (resolved, bound)
}

/// Why [`Simulation::settle`] refused a simulation; each door words it for its user.
#[derive(Debug, thiserror::Error)]
pub enum SettleError {
    /// A strand's root does not sit on the scalp it is anchored to.
    #[error("{0}")]
    Anchor(HairError),
    /// Sag-free rest shapes are solved for one material, but strands have their own factors.
    #[error("sag-free rest shapes are solved for one material, but strands have their own")]
    SagFreeWithFactors,
    /// Sag-free rest shapes are for the mass-spring model.
    #[error("sag-free rest shapes are for the mass-spring model")]
    SagFreeModel,
    /// The sag-free solve failed.
    #[error("{0}")]
    SagFree(HairError),
    /// Some strands cannot be held in their groomed shape by their bending springs.
    #[error(
        "{count} of {total} strands (first: strand {first}) cannot be held in their groomed \
         shape by the bending springs without turning a rest direction more than 60°"
    )]
    Unbalanced {
        /// Strands that cannot be held.
        count: usize,
        /// Strands in the simulation.
        total: usize,
        /// Index of the first of them.
        first: usize,
    },
    /// The hair–hair grid cannot hold the strands (cell size against extent).
    #[error("{0}")]
    HairHairGrid(HairError),
    /// A collider cannot be built; the message names it in the scene's terms.
    #[error("{message}")]
    Collider {
        /// The collider error in the scene's terms (`[[colliders]] #i`, `[scalp.collider]`).
        message: String,
        /// The solver's error.
        source: HairError,
    },
}

impl Simulation {
    /// Checks the roots against the scalp at the first frame, puts the strands at rest, solves
    /// sag-free rest shapes when `sag_free` is set (mass-spring, one material), and checks the
    /// hair–hair grid and every collider once, so each error shows before a run starts.
    pub fn settle(&mut self, sag_free: bool) -> Result<(), SettleError> {
        let scalp = self.scalp_at(self.first_frame as f32);
        self.strands
            .validate_anchors(&scalp)
            .map_err(SettleError::Anchor)?;
        self.strands.reset_to_rest(&scalp);
        if sag_free {
            if !self.regions.is_empty() || self.strand_scales.is_some() {
                return Err(SettleError::SagFreeWithFactors);
            }
            if self.model != StrandModel::MassSpring {
                return Err(SettleError::SagFreeModel);
            }
            let roots = self.strands.root_frames(&scalp);
            let supports = self
                .resting_supports()
                .map_err(|e| self.collider_error(e))?;
            let report = hair_core::make_sag_free_supported(
                &mut self.strands,
                &self.params,
                &roots,
                &supports,
                hair_core::SagFreeLimits::default(),
            )
            .map_err(SettleError::SagFree)?;
            if let Some(&first) = report.unbalanced.first() {
                return Err(SettleError::Unbalanced {
                    count: report.unbalanced.len(),
                    total: self.strands.len(),
                    first,
                });
            }
        }
        if let Some(h) = &self.hair_hair {
            hair_core::VoxelGrid::check(h.cell_size, &self.strands.positions)
                .map_err(SettleError::HairHairGrid)?;
        }
        self.colliders_at(self.first_frame as f32)
            .map_err(|e| self.collider_error(e))?;
        Ok(())
    }

    fn collider_error(&self, source: HairError) -> SettleError {
        SettleError::Collider {
            message: self.collider_message(&source),
            source,
        }
    }
}
