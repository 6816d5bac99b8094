//! The mass-spring strand model: [`MassSpringSolver`] advances chains of point masses by
//! substepped semi-implicit Euler, or, with [`Integrator::ImplicitEuler`] and
//! [`Integrator::Bdf2`], by linearised backward Euler or BDF2 with a banded solve per strand
//! (`crate::integrate` module `implicit`: the same forces, contacts and projections; the damping
//! sub-loop is folded into the solve), or by XPBD. The kernels are in [`crate::integrate`]; this
//! module runs them over a frame.
//!
//! # The step loop (seed 001, "Solver")
//!
//! One **frame** (1/fps s) is split into `steps` **collision steps**. Once per step the roots are
//! evaluated on the scalp (the scalp given for the frame's end, interpolated from the previous
//! frame's), and the per-step work is done: force fields are evaluated in batch over all points
//! ([`MassSpringSolver::with_fields`], [`crate::fields`]) and the hair–hair voxel grid is built
//! ([`MassSpringSolver::with_hair_hair`], [`crate::volume`]): both give each point an acceleration
//! held constant over the step's substeps, and hair–hair friction blends velocities once, before
//! contact detection (whose margins follow the velocities); then, with colliders
//! ([`MassSpringSolver::step_frame_with_colliders`]), contact detection (see [`crate::contacts`]).
//! Then every strand, independently and in parallel (rayon), runs `substeps` **force substeps** of
//! semi-implicit Euler, `v += dt·a(x, v); x += dt·v`, with:
//!
//! - stretch springs between neighbours (N/m),
//! - bending: the discrete curvature at each point against its rest curvature in the previous
//!   segment's parallel-transported frame ([`crate::integrate::curvature`], [`crate::frames`]);
//!   the root frame precedes segment 0, holding it to the scalp,
//! - goal springs towards the animated rest position, weighted per point,
//! - gravity and linear air drag,
//! - the step's external acceleration (force fields, hair–hair repulsion), if any.
//!
//! The root and any pinned point are kinematic: they follow their animated rest position and get
//! the velocity that motion implies. After each substep's velocity update comes the **damping
//! sub-loop** on relative velocity along each segment (`damping`), then the **contact
//! response** of points with a contact this step (Choe et al. 2005, see [`crate::contacts`]),
//! then the position update, and, if the host switched it on
//! ([`MassSpringSolver::with_inextensibility`]), the **inextensibility projection** of seed 002
//! (segment lengths restored, stretching velocities removed; see
//! [`crate::integrate::inextensible`]), and with `max_strain` the **strain limit**
//! (`strain_limit`: over-long segments projected back to the limit, velocities moved by the same
//! displacement over dt, so the stored velocity is the one that moved the point). A frame whose
//! colliders turn fast runs more collision steps of fewer substeps each (the substep never gets
//! longer).
//!
//! # Stability
//! `substeps = auto` takes the count from [`StabilityBound`]. After every step each strand is
//! checked for non-finite values and runaway energy; either stops the run with
//! [`HairError::Unstable`] naming the frame, the strand and the bound, before a bad frame can be
//! written anywhere.
//!
//! # State and workspace
//! What the next frame starts from besides the strands is the solver's state
//! ([`MassSpringSolverState`]: the frame number, the root frames, and the parameters, fields,
//! per-strand scales and hair–hair settings a host may change between frames). Everything else
//! the solver holds is either fixed when it is built (settings, substeps, the blocks of strands)
//! or its workspace: the contacts of the current collision step, the external accelerations and
//! the hair–hair grid, which every step rebuilds before reading. No warm start carries over from
//! one frame to the next (BDF2's history lives within a collision step, see
//! `crate::integrate` module `implicit`), so [`MassSpringSolver::snapshot_state`] and
//! [`MassSpringSolver::restore_state`] are all a host needs to step on bit for bit from a saved
//! frame, with the strands' positions and velocities and the colliders.

use std::ops::Range;
use std::time::Instant;

use hair_par::prelude::*;
use nalgebra::{UnitQuaternion, Vector3};

use crate::contacts::detect::{detect, DetectInput, PointContacts};
use crate::contacts::escapes::{put_back_escapees, EscapeInput, LengthLimit, PutBack};
use crate::contacts::Colliders;
use crate::error::{Blowup, HairError, Result};
use crate::fields::{self, FieldInput, ForceField};
use crate::integrate::kernel::{
    self, ContactSlice, GroupKernel, Scratch, StepConstants, StrandView,
};
use crate::integrate::lanes::{self, Lane, LANES};
use crate::integrate::{
    implicit, resolve_substeps, xpbd, HairParams, Inextensibility, Integrator, SolverSettings,
    StabilityBound, StrandScales,
};
use crate::mesh::RootFrame;
use crate::model::{Component, ComponentSet, FrameReport, ModelFigures, PhaseTimes};
use crate::strands::{Scalp, StrandSet};
use crate::volume::{HairHair, HairHairSettings};

/// Points a parallel work item holds at most (about a few L2-sized blocks of strands).
const BLOCK_POINTS: usize = 4096;

/// Energy per unit mass that counts as runaway, as a multiple of the largest a sane strand has
/// (fall its own length, move its own length per frame, follow the root).
const RUNAWAY_FACTOR: f64 = 1e3;

/// A mass-spring strand solver: settings fixed when it is built, the state carried from frame to
/// frame ([`MassSpringSolverState`]) and a workspace that every step rebuilds (see the module
/// docs). It does not own the strands; [`MassSpringSolver::step_frame`] borrows them for one
/// frame.
#[derive(Debug, Clone)]
pub struct MassSpringSolver {
    settings: SolverSettings,
    bound: StabilityBound,
    /// Force substeps per collision step.
    substeps: u32,
    /// Contiguous ranges of strands, one parallel work item each.
    blocks: Vec<Range<usize>>,
    /// Smallest radius of a free point, m (∞ without free points).
    min_radius: f32,
    /// The inextensibility projection, if on.
    inextensible: Option<Inextensibility>,
    /// What the next frame starts from.
    state: MassSpringSolverState,
    /// Buffers rebuilt every step.
    workspace: Workspace,
}

/// What a [`MassSpringSolver`] carries from one frame to the next: with the strands' positions
/// and velocities (and the colliders), all it needs to step on bit for bit. Taken by
/// [`MassSpringSolver::snapshot_state`], put back by [`MassSpringSolver::restore_state`].
#[derive(Debug, Clone)]
pub struct MassSpringSolverState {
    /// Frame number of the state.
    frame: u32,
    /// Root frames at that frame, one per strand: where the next frame's roots start.
    roots: Vec<RootFrame>,
    /// Parameters, which a host may change between frames.
    params: HairParams,
    /// Force fields (validated), in evaluation order.
    fields: Vec<ForceField>,
    /// Each strand's multipliers of `params` (per-region physics); empty = all 1, the
    /// scene's material (see [`MassSpringSolver::with_strand_scales`]).
    scales: Vec<StrandScales>,
    /// Hair–hair settings, if hair–hair is on.
    hair_hair: Option<HairHairSettings>,
}

impl MassSpringSolverState {
    /// Frame number of the state.
    pub fn frame(&self) -> u32 {
        self.frame
    }

    /// Root frames of the state, one per strand.
    pub fn roots(&self) -> &[RootFrame] {
        &self.roots
    }
}

/// The buffers of a [`MassSpringSolver`] that each collision step fills before it reads them:
/// nothing in them reaches the next frame.
#[derive(Debug, Clone, Default)]
struct Workspace {
    /// Contacts of the current collision step.
    contacts: PointContacts,
    /// External acceleration per point of the current step, m/s² (empty when nothing adds one).
    external: Vec<Vector3<f32>>,
    /// The hair–hair pass (per-point volumes, the voxel grid and its buffers), if on.
    hair_hair: Option<HairHair>,
}

/// Outcome of one strand's step, folded per block in strand order.
#[derive(Debug, Clone, Default)]
struct BlockOutcome {
    max_stretch: f32,
    failure: Option<(usize, Blowup)>,
}

impl MassSpringSolver {
    /// Prepares a solver for `strands` rooted on `scalp` at frame `start_frame`. Validates the
    /// settings, the parameters and every anchor, and resolves `substeps = auto`.
    pub fn new(
        settings: SolverSettings,
        params: HairParams,
        strands: &StrandSet,
        scalp: &Scalp,
        start_frame: u32,
    ) -> Result<Self> {
        settings.validate()?;
        params.validate()?;
        strands.validate_anchors(scalp)?;
        let bound = StabilityBound::of(strands, &params);
        let substeps = resolve_substeps(&settings, &bound);
        Ok(Self {
            settings,
            bound,
            substeps,
            blocks: blocks_of(strands),
            min_radius: strands
                .radii()
                .iter()
                .zip(strands.inverse_masses())
                .filter(|(_, &w)| w > 0.0)
                .fold(f32::INFINITY, |a, (&r, _)| a.min(r)),
            inextensible: None,
            state: MassSpringSolverState {
                frame: start_frame,
                roots: strands.root_frames(scalp),
                params,
                fields: Vec::new(),
                scales: Vec::new(),
                hair_hair: None,
            },
            workspace: Workspace::default(),
        })
    }

    /// A copy of the state (see [`MassSpringSolverState`]), without the workspace.
    pub fn snapshot_state(&self) -> MassSpringSolverState {
        self.state.clone()
    }

    /// Puts the solver back in `state`, taken by [`MassSpringSolver::snapshot_state`] from a
    /// solver of the same strands built the same way: stepping on gives the same bits as
    /// stepping on from where the state was taken. The workspace is left as it is (every step
    /// rebuilds it). Refused for a state of another number of strands, or with hair–hair on
    /// where this solver has it off or the other way round.
    pub fn restore_state(&mut self, state: &MassSpringSolverState) -> Result<()> {
        if state.roots.len() != self.state.roots.len() {
            return Err(HairError::Parameter {
                name: "state".into(),
                value: format!("{} strands", state.roots.len()),
                fix: format!(
                    "restore a state of this solver's strands ({})",
                    self.state.roots.len()
                ),
            });
        }
        if state.hair_hair.is_some() != self.workspace.hair_hair.is_some() {
            return Err(HairError::Parameter {
                name: "state".into(),
                value: format!(
                    "hair-hair {}",
                    if state.hair_hair.is_some() {
                        "on"
                    } else {
                        "off"
                    }
                ),
                fix: "restore a state of a solver built with the same hair-hair switch".into(),
            });
        }
        self.state.clone_from(state);
        Ok(())
    }

    /// Gives every strand its own multipliers of the parameters (per-region physics):
    /// strand `s` runs with `scales[s].apply(params)` in every integrator (the mass-spring
    /// kernel, implicit Euler and XPBD; each lane of a SIMD group loads its own strand's
    /// values). The stability bound takes the stiffest strand, and `substeps = auto` is
    /// resolved again from it. An empty list, or all [`StrandScales::ONE`], is the scene's
    /// material, bit for bit.
    pub fn with_strand_scales(
        mut self,
        scales: Vec<StrandScales>,
        strands: &StrandSet,
    ) -> Result<Self> {
        self.set_strand_scales(scales, strands.len())?;
        self.bound = StabilityBound::of_scaled(strands, &self.state.params, &self.state.scales);
        self.substeps = resolve_substeps(&self.settings, &self.bound);
        Ok(self)
    }

    /// Changes the strands' multipliers between frames (an animated region), checked against
    /// `strand_count`. Like [`MassSpringSolver::params_mut`], this keeps the substep: stiffer
    /// strands than it was chosen for may make the next step unstable, which that step reports.
    pub fn set_strand_scales(
        &mut self,
        scales: Vec<StrandScales>,
        strand_count: usize,
    ) -> Result<()> {
        if !scales.is_empty() && scales.len() != strand_count {
            return Err(HairError::Parameter {
                name: "strand_scales".into(),
                value: format!("{} entries", scales.len()),
                fix: format!("give one per strand ({strand_count}), or none"),
            });
        }
        for (s, scale) in scales.iter().enumerate() {
            scale.validate(s)?;
        }
        self.state.scales = scales;
        Ok(())
    }

    /// Each strand's multipliers of the parameters (empty: all 1).
    pub fn strand_scales(&self) -> &[StrandScales] {
        &self.state.scales
    }

    /// Switches on voxel hair–hair interaction (friction and repulsion through a grid rebuilt
    /// every collision step, see [`crate::volume`]) for `strands`. Off by default, and then it
    /// costs nothing.
    pub fn with_hair_hair(
        mut self,
        settings: HairHairSettings,
        strands: &StrandSet,
    ) -> Result<Self> {
        self.workspace.hair_hair = Some(HairHair::new(&settings, strands)?);
        self.state.hair_hair = Some(settings);
        Ok(self)
    }

    /// Hair–hair settings in use, if on.
    pub fn hair_hair(&self) -> Option<&HairHairSettings> {
        self.state.hair_hair.as_ref()
    }

    /// Hair–hair settings for a host to change between frames (friction, repulsion…), if on;
    /// they are validated again at the next step.
    pub fn hair_hair_mut(&mut self) -> Option<&mut HairHairSettings> {
        self.state.hair_hair.as_mut()
    }

    /// Adds force fields (see [`crate::fields`]), evaluated in batch once per collision step.
    /// Each is validated (errors name `fields[i].parameter`); fields that move the air need
    /// `air_drag > 0`.
    pub fn with_fields(mut self, fields: Vec<ForceField>) -> Result<Self> {
        self.state.fields = fields;
        self.validate_fields()?;
        Ok(self)
    }

    /// The force fields, for a host to change between frames (strength per frame, position…);
    /// they are validated again at the next frame.
    pub fn fields_mut(&mut self) -> &mut [ForceField] {
        &mut self.state.fields
    }

    fn validate_fields(&mut self) -> Result<()> {
        let drag = self.state.params.air_drag;
        for (i, f) in self.state.fields.iter_mut().enumerate() {
            f.validate(i)?;
            if f.moves_air() && drag <= 0.0 {
                return Err(HairError::Parameter {
                    name: format!("fields[{i}]"),
                    value: format!("{:?} with air_drag = 0", f.kind),
                    fix: "wind, vortex and turbulence move the air, which pushes hair through \
                          the air drag: set [physics] air_drag > 0"
                        .into(),
                });
            }
        }
        Ok(())
    }

    /// Computes this step's external acceleration (fields and repulsion) into the workspace's
    /// `external` and applies hair–hair friction to the velocities; leaves the workspace's
    /// `external` empty when nothing acts.
    fn external_forces(
        &mut self,
        strands: &mut StrandSet,
        frame: f32,
        step_dt: f64,
        times: &mut PhaseTimes,
    ) -> Result<()> {
        self.workspace.external.clear();
        if self.state.fields.is_empty() && self.state.hair_hair.is_none() {
            return Ok(());
        }
        self.workspace
            .external
            .resize(strands.point_count(), Vector3::zeros());
        if !self.state.fields.is_empty() {
            let t = Instant::now();
            let input = FieldInput {
                positions: &strands.positions,
                velocities: &strands.velocities,
                frame,
                time: frame / self.settings.fps,
                air_drag: self.state.params.air_drag,
                step_dt: step_dt as f32,
            };
            fields::evaluate(&self.state.fields, &input, &mut self.workspace.external);
            times.fields += t.elapsed();
        }
        if let (Some(h), Some(settings)) = (&mut self.workspace.hair_hair, &self.state.hair_hair) {
            let t = Instant::now();
            h.step(
                settings,
                strands,
                &mut self.workspace.external,
                &self.blocks,
            )?;
            times.volume += t.elapsed();
        }
        Ok(())
    }

    /// Switches on the inextensibility projection of seed 002 ("Constraints") after every
    /// substep: segment lengths restored to within `projection.tolerance`, velocities corrected
    /// (see [`crate::integrate::inextensible`]). Off by default, and then it costs nothing.
    pub fn with_inextensibility(mut self, projection: Inextensibility) -> Result<Self> {
        projection.validate()?;
        self.inextensible = Some(projection);
        Ok(self)
    }

    /// The inextensibility projection in use, if on.
    pub fn inextensibility(&self) -> Option<Inextensibility> {
        self.inextensible
    }

    /// Force substeps per collision step in use.
    pub fn substeps(&self) -> u32 {
        self.substeps
    }

    /// Substep length in use, s.
    pub fn dt(&self) -> f64 {
        self.settings.step_dt() / self.substeps as f64
    }

    /// The predicted stability bound of this set and these parameters.
    pub fn bound(&self) -> StabilityBound {
        self.bound
    }

    /// Settings in use.
    pub fn settings(&self) -> &SolverSettings {
        &self.settings
    }

    /// Parameters in use.
    pub fn params(&self) -> &HairParams {
        &self.state.params
    }

    /// Frame number of the current state.
    pub fn frame(&self) -> u32 {
        self.state.frame
    }

    /// Root frames of the current state.
    pub fn roots(&self) -> &[RootFrame] {
        &self.state.roots
    }

    /// Model components this solver runs (a component whose coefficient is 0 costs nothing).
    pub fn components(&self, strands: &StrandSet) -> ComponentSet {
        let p = &self.state.params;
        let mut c = ComponentSet::new();
        let mut add = |on: bool, component| {
            if on {
                c.insert(component);
            }
        };
        add(p.stretch_stiffness > 0.0, Component::Stretch);
        add(p.bend_stiffness > 0.0, Component::Bend);
        add(
            p.goal_stiffness > 0.0 && strands.goal_weights().iter().any(|&w| w > 0.0),
            Component::Goal,
        );
        add(p.gravity().norm_squared() > 0.0, Component::Gravity);
        add(p.air_drag > 0.0, Component::AirDrag);
        add(
            p.stretch_damping > 0.0 && self.settings.damping_iterations > 0,
            Component::Damping,
        );
        add(
            self.settings.max_strain == Some(0.0),
            Component::Inextensibility,
        );
        add(
            self.settings.max_strain.is_some_and(|m| m > 0.0),
            Component::StrainLimit,
        );
        add(
            self.inextensible.is_some(),
            Component::InextensibilityProjection,
        );
        if let Some(h) = self.hair_hair() {
            add(h.friction > 0.0, Component::HairHairFriction);
            add(h.repulsion > 0.0, Component::HairHairRepulsion);
        }
        for f in &self.state.fields {
            c.insert(match f.kind {
                fields::FieldKind::Wind { .. } => Component::Wind,
                fields::FieldKind::Vortex => Component::Vortex,
                fields::FieldKind::Turbulence { .. } => Component::Turbulence,
                fields::FieldKind::Drag => Component::DragField,
                fields::FieldKind::Force => Component::ForceField,
            });
        }
        c
    }

    /// Parameters for a host to change between frames (gravity, goal stiffness, air drag…):
    /// animatable parameters. They are validated again at the next step; stiffer springs than
    /// the substep was chosen for may make the next step unstable, which it reports.
    pub fn params_mut(&mut self) -> &mut HairParams {
        &mut self.state.params
    }

    /// Advances `strands` by one frame, to the instant at which `scalp` is given, with no
    /// colliders.
    ///
    /// On [`HairError::Unstable`] the strands hold the failed state; do not write it anywhere.
    pub fn step_frame(&mut self, strands: &mut StrandSet, scalp: &Scalp) -> Result<FrameReport> {
        self.advance(strands, scalp, None)
    }

    /// Advances `strands` by one frame, to the instant at which `scalp` is given, colliding with
    /// `colliders` at the poses (and mesh vertices) set for this frame's end
    /// ([`Colliders::set_pose`], [`Colliders::set_vertices`]); colliders inserted with
    /// [`Colliders::insert_scalp`] follow `scalp.body` and a deformed `scalp.mesh`. See
    /// [`crate::contacts`].
    ///
    /// A frame whose colliders move too fast for the contact model's tolerance
    /// ([`crate::contacts::collider_set`]) runs more collision steps with proportionally fewer
    /// substeps each ([`FrameReport::steps`]). An empty set does exactly what
    /// [`MassSpringSolver::step_frame`] does.
    pub fn step_frame_with_colliders(
        &mut self,
        strands: &mut StrandSet,
        scalp: &Scalp,
        colliders: &mut Colliders,
    ) -> Result<FrameReport> {
        colliders.settings.validate()?;
        let colliders = (!colliders.is_empty()).then_some(colliders);
        self.advance(strands, scalp, colliders)
    }

    fn advance(
        &mut self,
        strands: &mut StrandSet,
        scalp: &Scalp,
        mut colliders: Option<&mut Colliders>,
    ) -> Result<FrameReport> {
        let frame = self.state.frame + 1;
        self.state.params.validate()?;
        self.validate_fields()?;
        let t0 = Instant::now();
        let mut end_roots = strands.root_frames(scalp);
        // q and −q are the same rotation, but interpolating from the previous frame's quaternion
        // towards the one in the opposite hemisphere turns the roots the long way round (through
        // up to a full turn) within the frame, or through a zero quaternion (NaN) half-way. Take
        // the representative nearest the previous frame's.
        for (end, prev) in end_roots.iter_mut().zip(&self.state.roots) {
            if end.rotation.coords.dot(&prev.rotation.coords) < 0.0 {
                end.rotation = UnitQuaternion::new_unchecked(-end.rotation.into_inner());
            }
        }
        let mut times = PhaseTimes {
            roots: t0.elapsed(),
            ..Default::default()
        };
        // Fast colliders split the frame into more steps of fewer substeps each.
        let factor = match colliders.as_deref_mut() {
            Some(c) => {
                c.begin_frame(scalp)?;
                let tolerance = c
                    .settings
                    .tolerance
                    .unwrap_or((0.5 * self.min_radius).max(1e-4));
                c.step_factor(self.settings.steps, tolerance)
            }
            None => 1,
        };
        let steps = self.settings.steps * factor;
        let substeps = self.substeps.div_ceil(factor);
        let step_dt = self.settings.step_dt() / factor as f64;
        let mut consts = StepConstants::new(
            &self.state.params,
            (step_dt / substeps as f64) as f32,
            substeps,
            self.settings.damping_iterations,
            self.settings.integrator,
            self.settings.max_strain,
        );
        if let Some(c) = colliders.as_deref() {
            consts.max_push_speed = c.settings.max_push_speed;
        }
        consts.inextensible = self.inextensible;
        let mut max_stretch = 0.0f32;
        let mut contact_points = 0u64;
        for step in 0..steps {
            let t1 = Instant::now();
            let a = step as f32 / steps as f32;
            let b = (step + 1) as f32 / steps as f32;
            let starts: Vec<RootFrame> = self
                .state
                .roots
                .iter()
                .zip(&end_roots)
                .map(|(p, e)| p.interpolate(e, a))
                .collect();
            let ends: Vec<RootFrame> = self
                .state
                .roots
                .iter()
                .zip(&end_roots)
                .map(|(p, e)| p.interpolate(e, b))
                .collect();
            times.roots += t1.elapsed();
            // Hair–hair friction changes velocities, so it comes before contact detection,
            // whose margins follow them.
            self.external_forces(strands, self.state.frame as f32 + a, step_dt, &mut times)?;
            let contacts = match colliders.as_deref_mut() {
                Some(c) => {
                    let t3 = Instant::now();
                    let input = DetectInput {
                        offsets: strands.offsets(),
                        positions: &strands.positions,
                        velocities: &strands.velocities,
                        radii: strands.radii(),
                        inv_mass: strands.inverse_masses(),
                        blocks: &self.blocks,
                        step_dt: step_dt as f32,
                        gravity: self.state.params.gravity().norm(),
                    };
                    contact_points += detect(c, a, b, &input, &mut self.workspace.contacts) as u64;
                    times.contacts += t3.elapsed();
                    Some(&self.workspace.contacts)
                }
                None => None,
            };
            let t2 = Instant::now();
            let integrator = self.settings.integrator;
            let outcome = if kernel::wide_registers(self.settings.kernel) {
                let kernel: GroupKernel<lanes::F8> = match integrator {
                    Integrator::ImplicitEuler | Integrator::Bdf2 => {
                        implicit::step_group_implicit_avx2
                    }
                    Integrator::Xpbd => xpbd::step_group_xpbd_avx2,
                    Integrator::SemiImplicitEuler | Integrator::ExplicitEuler => {
                        kernel::step_group_avx2
                    }
                };
                self.step_strands(kernel, strands, &starts, &ends, &consts, contacts)
            } else {
                let kernel: GroupKernel<lanes::Baseline> = match integrator {
                    Integrator::ImplicitEuler | Integrator::Bdf2 => {
                        implicit::step_group_implicit::<lanes::Baseline>
                    }
                    Integrator::Xpbd => xpbd::step_group_xpbd::<lanes::Baseline>,
                    Integrator::SemiImplicitEuler | Integrator::ExplicitEuler => {
                        kernel::step_group::<lanes::Baseline>
                    }
                };
                self.step_strands(kernel, strands, &starts, &ends, &consts, contacts)
            };
            times.strands += t2.elapsed();
            if let Some((strand, cause)) = outcome.failure {
                return Err(HairError::Unstable {
                    frame,
                    strand,
                    cause,
                    dt: self.dt(),
                    bound: self.bound.dt_max,
                    auto_substeps: self.bound.auto_substeps(self.settings.step_dt()),
                });
            }
            max_stretch = outcome.max_stretch;
        }
        let mut put_back = PutBack::default();
        if let Some(c) = colliders {
            let t4 = Instant::now();
            let (positions, velocities, data) = strands.split_for_solver();
            // The length limit the put-back keeps: the strain limit's, or the rest length
            // under the inextensibility projection.
            let ratio = self
                .settings
                .max_strain
                .map(|e| 1.0 + e)
                .or(self.inextensible.map(|_| 1.0));
            let lengths = ratio.map(|ratio| LengthLimit {
                offsets: data.offsets,
                rest_length: data.rest_length,
                ratio,
            });
            put_back = put_back_escapees(
                c,
                (steps - 1) as f32 / steps as f32,
                step_dt as f32,
                EscapeInput {
                    positions,
                    velocities,
                    radii: data.radii,
                    inv_mass: data.inv_mass,
                    contact_size: &self.workspace.contacts.size,
                    found_depth: &self.workspace.contacts.found_depth,
                    max_push_speed: c.settings.max_push_speed,
                    lengths,
                },
            );
            times.contacts += t4.elapsed();
            c.finish_frame();
        }
        self.state.roots = end_roots;
        self.state.frame = frame;
        Ok(FrameReport {
            frame,
            substeps,
            steps,
            point_substeps: strands.point_count() as u64 * (substeps * steps) as u64,
            contact_points,
            escaped_points: put_back.escaped as u64,
            deep_contact_points: put_back.deep as u64,
            max_stretch,
            times,
            figures: ModelFigures::MassSpring,
        })
    }

    /// Runs one collision step of every strand with the kernel copy `kernel`.
    fn step_strands<L: Lane>(
        &self,
        kernel: GroupKernel<L>,
        strands: &mut StrandSet,
        starts: &[RootFrame],
        ends: &[RootFrame],
        consts: &StepConstants,
        contacts: Option<&PointContacts>,
    ) -> BlockOutcome {
        let step_dt = consts.dt as f64 * consts.substeps as f64;
        let g = self.state.params.gravity().norm() as f64;
        let fps = self.settings.fps as f64;
        let (x_all, v_all, data) = strands.split_for_solver();
        let mut jobs = Vec::with_capacity(self.blocks.len());
        let (mut x_rest, mut v_rest) = (x_all, v_all);
        for block in &self.blocks {
            let len = (data.offsets[block.end] - data.offsets[block.start]) as usize;
            let (x, xr) = x_rest.split_at_mut(len);
            let (v, vr) = v_rest.split_at_mut(len);
            x_rest = xr;
            v_rest = vr;
            jobs.push((block.clone(), x, v));
        }
        let outcomes: Vec<BlockOutcome> = jobs
            .into_par_iter()
            .map_init(Scratch::<L>::default, |scratch, (block, mut x, mut v)| {
                let mut out = BlockOutcome::default();
                for group in groups_in(data.offsets, block) {
                    // One view per strand of the group, over disjoint pieces of the block.
                    let mut views = Vec::with_capacity(group.len());
                    for s in group.clone() {
                        let p = data.offsets[s] as usize..data.offsets[s + 1] as usize;
                        let seg = p.start - s..p.end - s - 1;
                        let (xs, xr) = std::mem::take(&mut x).split_at_mut(p.len());
                        let (vs, vr) = std::mem::take(&mut v).split_at_mut(p.len());
                        x = xr;
                        v = vr;
                        views.push(StrandView {
                            x: xs,
                            v: vs,
                            rest_local: &data.rest_local[p.clone()],
                            inv_mass: &data.inv_mass[p.clone()],
                            goal_weight: &data.goal_weight[p.clone()],
                            rest_length: &data.rest_length[seg.clone()],
                            bend_rest: &data.bend_rest[seg],
                            contacts: contacts.filter(|c| c.strand_active[s]).map(|c| {
                                ContactSlice {
                                    anchor: &c.anchor[p.clone()],
                                    size: &c.size[p.clone()],
                                    curved: &c.curved[p.clone()],
                                    anchor_velocity: &c.anchor_velocity[p.clone()],
                                    surface_velocity: &c.surface_velocity[p.clone()],
                                    friction: &c.friction[p.clone()],
                                    found_depth: &c.found_depth[p.clone()],
                                }
                            }),
                            accel: (!self.workspace.external.is_empty())
                                .then(|| &self.workspace.external[p.clone()]),
                            scales: self.state.scales.get(s).copied().unwrap_or_default(),
                        });
                    }
                    kernel(
                        &mut views,
                        &starts[group.clone()],
                        &ends[group.clone()],
                        consts,
                        scratch,
                    );
                    for (view, s) in views.iter().zip(group) {
                        let p = data.offsets[s] as usize..data.offsets[s + 1] as usize;
                        let root_speed =
                            ((ends[s].origin - starts[s].origin).norm() as f64) / step_dt;
                        let length: f64 = view.rest_length.iter().map(|&l| l as f64).sum();
                        let limit = RUNAWAY_FACTOR
                            * (g * length + (length * fps).powi(2) + root_speed.powi(2));
                        match check_strand(
                            view,
                            &data.mass[p],
                            self.state.params.stretch_stiffness * view.scales.stretch,
                            limit,
                        ) {
                            Ok(stretch) => out.max_stretch = out.max_stretch.max(stretch),
                            Err(cause) => {
                                out.failure = Some((s, cause));
                                return out;
                            }
                        }
                    }
                }
                out
            })
            .collect();
        outcomes
            .into_iter()
            .fold(BlockOutcome::default(), |acc, o| BlockOutcome {
                max_stretch: acc.max_stretch.max(o.max_stretch),
                failure: acc.failure.or(o.failure),
            })
    }
}

/// Checks a strand after a step: finite, and energy per unit mass (kinetic + stretch) below
/// `limit` (J/kg). Returns the strand's largest relative elongation (≥ 0).
fn check_strand(s: &StrandView, mass: &[f32], stretch_k: f32, limit: f64) -> Result<f32, Blowup> {
    let n = s.x.len();
    let mut kinetic = 0.0f64;
    let mut total_mass = 0.0f64;
    let finite = |i: usize| s.x[i].iter().chain(s.v[i].iter()).all(|c| c.is_finite());
    if let Some(bad) = (0..n).find(|&i| !finite(i)) {
        // Name the first free point: a pinned root turns non-finite only through its neighbours.
        let point = (0..n).find(|&i| mass[i] > 0.0 && !finite(i)).unwrap_or(bad);
        return Err(Blowup::NonFinite { point });
    }
    for (v, &m) in s.v.iter().zip(mass) {
        kinetic += 0.5 * m as f64 * v.cast::<f64>().norm_squared();
        total_mass += m as f64;
    }
    let mut elastic = 0.0f64;
    let mut stretch = 0.0f32;
    for j in 0..n - 1 {
        let len = (s.x[j + 1] - s.x[j]).norm();
        stretch = stretch.max(len / s.rest_length[j] - 1.0);
        elastic += 0.5 * stretch_k as f64 * ((len - s.rest_length[j]) as f64).powi(2);
    }
    // A strand pinned at every point (hold-out hair on animated guides) is kinematic: its
    // energy is the animation's, not the solver's, and it has no mass to divide by.
    if total_mass == 0.0 {
        return Ok(stretch);
    }
    let specific = (kinetic + elastic) / total_mass;
    if specific > limit {
        return Err(Blowup::Energy { specific, limit });
    }
    Ok(stretch)
}

/// The groups of a block: runs of at most [`LANES`] consecutive strands with equal point counts,
/// advanced together by the kernel.
fn groups_in(offsets: &[u32], block: std::ops::Range<usize>) -> Vec<std::ops::Range<usize>> {
    let len = |s: usize| offsets[s + 1] - offsets[s];
    let mut groups = Vec::new();
    let mut start = block.start;
    for s in block.clone() {
        if s - start == LANES || len(s) != len(start) {
            groups.push(start..s);
            start = s;
        }
    }
    if start < block.end {
        groups.push(start..block.end);
    }
    groups
}

/// Splits the strands into contiguous blocks of about [`BLOCK_POINTS`] points.
fn blocks_of(strands: &StrandSet) -> Vec<std::ops::Range<usize>> {
    let offsets = strands.offsets();
    let mut blocks = Vec::new();
    let mut start = 0;
    for s in 0..strands.len() {
        if (offsets[s + 1] - offsets[start]) as usize >= BLOCK_POINTS {
            blocks.push(start..s + 1);
            start = s + 1;
        }
    }
    if start < strands.len() {
        blocks.push(start..strands.len());
    }
    blocks
}
