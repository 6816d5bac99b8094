//! The discrete elastic rod model: the second strand solver, [`RodSolver`], after seed 002
//! (Kmoch, Bonanni and Magnenat-Thalmann 2009, "Hair Simulation Model for Real-Time
//! Environments", built on Bergou et al. 2008, "Discrete Elastic Rods"; constraints by the fast
//! projection of Goldenthal et al. 2007).
//!
//! It works on the same [`StrandSet`] as the mass-spring [`crate::MassSpringSolver`] and has the
//! same shape (`new`, `step_frame`, `step_frame_with_colliders`, `components`), so scenes, caches
//! and render children work unchanged. It is the accurate alternative, not the fast path: it runs
//! in f64, strands in parallel (rayon; each strand's result does not depend on the thread count).
//!
//! # The model
//! - **Rod** ([`frames`]): nodes and segments; per segment a twist-free reference frame carried
//!   from the root frame by parallel transport along the current centreline, and the material
//!   frame (the cross-section's axes) as a scalar twist angle on it.
//! - **Elliptical cross-section** ([`stiffness`]): bending stiffness `E I₁ = E π a b³/4` over the
//!   major axis and `E I₂ = E π a³ b/4` over the minor axis (`a ≥ b`), twist stiffness `G J`.
//! - **Bending and twist energy** ([`forces`]): Bergou's discrete curvature binormal at each
//!   node, bending energy in the material frames of both adjacent segments against the rest
//!   curvature, twist energy `G J (m − m̄)² / (2 l̄)` of the twist `m` between neighbouring
//!   segments. Node 0 joins a **ghost segment** fixed in the root frame along the first
//!   segment's rest direction, with twist 0: the root is clamped in direction and in twist (as a
//!   follicle holds it; seed 002 left the twist free at the root). The tip is free.
//! - **Quasistatic elastic twist** ([`twist`]; Bergou et al. 2008, §"quasistatic material
//!   frame"): before every substep the twist angles minimise bending plus twist energy for the
//!   current centreline (Newton on a tridiagonal Hessian, warm-started from the last substep's
//!   angles, which are state: [`RodSolver::twist`]). An elliptical section twists to bend over
//!   its major axis where that costs less than bending the stiff way against `G J` and the
//!   clamped root (a twist-buckling criterion, not a rule); its rest shape bends over its major
//!   axes.
//! - **Forces** ([`forces`]): the gradient of bending plus twist energy at the quasistatic twist
//!   (envelope theorem): the bending gradient with the material axes carried by time-parallel
//!   transport, plus the twist's holonomy term `−Σ G J (m − m̄)/l̄ ∇m` (Bergou et al. 2010,
//!   "Discrete Viscous Threads"), so twist pushes on the centreline: a coil cannot trade its
//!   pitch for torsion for free.
//! - **Step** ([`strand`]): explicit (symplectic Euler) integration of the elastic forces,
//!   gravity and air drag with a short substep, then **projection** ([`project`]) to the
//!   nearest state, in the kinetic-energy metric, that keeps every segment at its rest length,
//!   the root (and any pinned node, kinematic: zero inverse mass) on the moving head and the
//!   penetrating nodes on the head's surface ([`collide`]); velocities are the projected
//!   displacement over the substep.
//!
//! Cost: roughly 20× the mass-spring kernel per point-substep (f64, frames and a twist
//! relaxation per substep, a banded solve per projection iteration, 1.5–2 iterations per
//! substep in hair-like motion); `cargo bench -p hair-core --bench rod_step` measures it.
//!
//! # Time stepping
//! A frame is `steps × substeps` substeps (the same [`SolverSettings`] as the mass-spring
//! solver; `damping_iterations`, `integrator` and `max_strain` do not apply: the rod is always
//! inextensible). Stretching is a constraint, so the substep is bounded by bending alone:
//! `dt < 2/ω` with `ω² = 32 E I₂ / (m_min l_min³)` (the zig-zag mode of the stiffest bending on
//! the lightest node and shortest segment, doubled for the root's half share). `substeps = auto`
//! takes half that bound.
//!
//! # Limits (what is not modelled)
//! - Goal springs, force fields, hair–hair interaction and the mass-spring stretch parameters are
//!   not used; gravity and air drag are taken from [`HairParams`].
//! - Twist has no inertia: it is at equilibrium with the centreline at every substep (a hair's
//!   torsional waves are much faster than its bending waves). Where the minimum of the energy in
//!   the twist jumps (an elliptical strand snapping between twisted branches, or twist-buckling
//!   off a stiff-axis bend) the force jumps with it, to a lower minimum: energy is lost. A
//!   relaxation that has not converged after 40 evaluations keeps the angles it reached.
//! - Explicit steps keep the elastic energy to first order in the substep: an undamped strand
//!   oscillates about its energy without drifting up (a released 24 cm helix, round or
//!   elliptical, never rose above its starting energy in 2 s: its highest was 0.002 % of
//!   `m g L` below it);
//!   the projection only removes kinetic energy. The stability bound counts bending only: twist
//!   adds a force proportional to the twist itself, small in hair.
//! - The twist angles are state ([`RodSolver::twist`], the relaxation's starting point) that a
//!   cache does not store: a run resumed from a cache (`hairsys simulate --resume`) restarts them
//!   from the rest twist. The relaxation finds the same minimum to round-off, so the resumed
//!   frames agree closely but not bit for bit, and an elliptical strand that had twist-buckled
//!   may settle on the other branch.
//! - Contacts are positional constraints without friction (the node keeps its tangential
//!   velocity) and only solid colliders are supported. They are detected every substep, so the
//!   fast-motion settings of [`crate::ContactSettings`] (`tolerance`, `max_steps`,
//!   `max_push_speed`) do not apply.
//! - A projection that does not reach its tolerance within `projection_iterations` is reported
//!   ([`ProjectionReport`]) with its residual; above 1 % strain, or non-finite, the run stops with
//!   [`HairError::Unstable`].

pub mod collide;
pub mod forces;
pub mod frames;
pub mod project;
pub mod stiffness;
pub mod strand;
pub mod twist;

use std::time::Instant;

use hair_par::prelude::*;
use nalgebra::{UnitQuaternion, Vector3};
#[cfg(feature = "serde")]
use serde::Serialize;

use crate::contacts::collider_set::Surface;
use crate::contacts::Colliders;
use crate::error::{Blowup, HairError, Result};
use crate::integrate::energy::Energy;
use crate::mesh::RootFrame;
use crate::model::{Component, ComponentSet, FrameReport, ModelFigures, PhaseTimes};
use crate::strands::{Scalp, StrandSet};
use crate::{HairParams, SolverSettings, Substeps};

pub use stiffness::{RodParams, Stiffness};
pub use strand::{RodState, RodStrand, Root, Substep, SubstepOutcome, Workspace};

use frames::V3;

/// Residual (relative strain) above which a projection that did not converge stops the run.
const FAILED_RESIDUAL: f64 = 1e-2;

/// Safety factor of `substeps = auto` on the bending bound.
const AUTO_SAFETY: f64 = 0.5;

/// What the projections of one frame did (the rod model's own figures for reports and benches).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct ProjectionReport {
    /// Projections run (strands × substeps, plus extra contact rounds).
    pub projections: u64,
    /// Projection iterations (linear solves) in all.
    pub iterations: u64,
    /// Most iterations one projection took.
    pub max_iterations: u32,
    /// Largest final residual of a projection (relative strain or depth over segment length).
    pub residual: f64,
    /// Projections that hit the iteration limit above the tolerance.
    pub unconverged: u64,
    /// Largest `|len/rest − 1|` over all segments at the frame's end, as stored (f32).
    pub max_strain: f64,
    /// Tolerance in use.
    pub tolerance: f64,
}

impl ProjectionReport {
    /// Adds another frame's figures (sums counts, keeps the largest residual, strain and
    /// iteration count).
    pub fn merge(&mut self, other: &ProjectionReport) {
        self.projections += other.projections;
        self.iterations += other.iterations;
        self.max_iterations = self.max_iterations.max(other.max_iterations);
        self.residual = self.residual.max(other.residual);
        self.unconverged += other.unconverged;
        self.max_strain = self.max_strain.max(other.max_strain);
        self.tolerance = other.tolerance;
    }

    /// Mean iterations per projection.
    pub fn mean_iterations(&self) -> f64 {
        self.iterations as f64 / self.projections.max(1) as f64
    }

    /// A warning for a host to show when some projection did not converge, naming the residual.
    pub fn warning(&self) -> Option<String> {
        (self.unconverged > 0).then(|| {
            format!(
                "rod projection: {} of {} projections stopped at the iteration limit with \
                 residual up to {:.3e} (tolerance {:.1e}); raise rod.projection_iterations or \
                 the substeps",
                self.unconverged, self.projections, self.residual, self.tolerance
            )
        })
    }
}

/// What one frame of the rod model did.
#[derive(Debug, Clone, PartialEq)]
pub struct RodFrameReport {
    /// The figures both models report (`max_stretch` and `point_substeps` as for mass-spring;
    /// contacts are detected every substep, and `contact_points` is the frame's sum over substeps
    /// divided by the substeps per step: nodes in contact per substep, summed over the steps).
    pub frame: FrameReport,
    /// The projection's figures.
    pub projection: ProjectionReport,
}

/// The rod strand solver: settings, parameters and each strand's rest data, fixed when it is
/// built; the state carried from frame to frame ([`RodSolverState`]); and contact detection's
/// memory, its workspace. Like [`crate::MassSpringSolver`] it does not own the strands.
#[derive(Debug, Clone)]
pub struct RodSolver {
    settings: SolverSettings,
    params: HairParams,
    rod: RodParams,
    stiffness: Stiffness,
    strands: Vec<RodStrand>,
    substeps: u32,
    dt_max: f64,
    /// What the next frame starts from.
    state: RodSolverState,
    /// Contact detection's memory.
    workspace: DetectionMemory,
}

/// What a [`RodSolver`] carries from one frame to the next: with the strands' positions and
/// velocities (and the colliders), all it needs to step on bit for bit. Taken by
/// [`RodSolver::snapshot_state`], put back by [`RodSolver::restore_state`].
#[derive(Debug, Clone)]
pub struct RodSolverState {
    /// Frame number of the state.
    frame: u32,
    /// Root frames at that frame, one per strand: where the next frame's roots start.
    roots: Vec<RootFrame>,
    /// Twist angles per strand and segment at the last substep's start, rad: the next
    /// substep's relaxation starts from them, and where the energy has more than one minimum
    /// they choose the one it finds.
    theta: Vec<Vec<f64>>,
}

impl RodSolverState {
    /// Frame number of the state.
    pub fn frame(&self) -> u32 {
        self.frame
    }

    /// Root frames of the state, one per strand.
    pub fn roots(&self) -> &[RootFrame] {
        &self.roots
    }
}

/// Contact detection's memory per strand (see [`collide::Clearance`]): lower bounds of each
/// node's distance to each collider that let detection skip nodes far from them. A bound only
/// saves work (the distance is 1-Lipschitz), so the memory is workspace: a snapshot leaves it
/// out and a solver with none detects the same contacts.
#[derive(Debug, Clone, Default)]
struct DetectionMemory {
    /// Per strand, per node and collider.
    clearance: Vec<Vec<collide::Clearance>>,
    /// The colliders the memory belongs to (their shapes' addresses and versions: a deformed
    /// mesh invalidates it).
    key: Vec<usize>,
}

/// Outcome of one strand's frame.
#[derive(Debug, Clone, Default)]
struct StrandOutcome {
    projection: ProjectionReport,
    contacts: u64,
    failure: Option<Blowup>,
    /// The twist at the last substep's start (empty on failure).
    theta: Vec<f64>,
}

impl RodSolver {
    /// Prepares a rod solver for `strands` rooted on `scalp` at frame `start_frame`, with gravity
    /// and air drag from `params` and the material of `rod`. Validates everything and resolves
    /// `substeps = auto` from the bending bound.
    pub fn new(
        settings: SolverSettings,
        params: HairParams,
        rod: RodParams,
        strands: &StrandSet,
        scalp: &Scalp,
        start_frame: u32,
    ) -> Result<Self> {
        settings.validate()?;
        params.validate()?;
        rod.validate()?;
        strands.validate_anchors(scalp)?;
        let stiffness = Stiffness::of(&rod);
        let mut rods = Vec::with_capacity(strands.len());
        let (mut m_min, mut l_min) = (f64::INFINITY, f64::INFINITY);
        for s in 0..strands.len() {
            let p = strands.points(s);
            let rod_strand = RodStrand::new(
                &strands.rest_local()[p.clone()],
                &strands.inverse_masses()[p.clone()],
                &strands.radii()[p.clone()],
                &stiffness,
            )
            .map_err(|j| HairError::Strand {
                strand: s,
                message: format!(
                    "segment {j} (points {j}–{}) has zero length; merge or remove duplicate \
                     points",
                    j + 1
                ),
            })?;
            for &m in strands.masses()[p].iter().filter(|&&m| m > 0.0) {
                m_min = m_min.min(m as f64);
            }
            l_min = rod_strand
                .rest_lengths()
                .iter()
                .fold(l_min, |a, &l| a.min(l));
            rods.push(rod_strand);
        }
        let omega = (32.0 * stiffness.minor / (m_min * l_min.powi(3))).sqrt();
        let dt_max = if omega.is_finite() && omega > 0.0 {
            2.0 / omega
        } else {
            f64::INFINITY
        };
        let substeps = match settings.substeps {
            Substeps::Fixed(n) => n,
            Substeps::Auto => auto_substeps(settings.step_dt(), dt_max),
        };
        Ok(Self {
            settings,
            params,
            rod,
            stiffness,
            substeps,
            dt_max,
            state: RodSolverState {
                frame: start_frame,
                roots: strands.root_frames(scalp),
                theta: rods.iter().map(|r| r.rest_twist().to_vec()).collect(),
            },
            workspace: DetectionMemory {
                clearance: vec![Vec::new(); strands.len()],
                key: Vec::new(),
            },
            strands: rods,
        })
    }

    /// A copy of the state (see [`RodSolverState`]), without the workspace.
    pub fn snapshot_state(&self) -> RodSolverState {
        self.state.clone()
    }

    /// Puts the solver back in `state`, taken by [`RodSolver::snapshot_state`] from a solver of
    /// the same strands: stepping on gives the same bits as stepping on from where the state
    /// was taken. Contact detection's memory is left as it is (its bounds hold whenever the
    /// colliders are the same). Refused for a state of other strands.
    pub fn restore_state(&mut self, state: &RodSolverState) -> Result<()> {
        let fits = state.roots.len() == self.strands.len()
            && state
                .theta
                .iter()
                .zip(&self.strands)
                .all(|(theta, rod)| theta.len() == rod.rest_twist().len());
        if !fits {
            return Err(HairError::Parameter {
                name: "state".into(),
                value: format!("{} strands", state.roots.len()),
                fix: format!(
                    "restore a state of this solver's strands ({} strands)",
                    self.strands.len()
                ),
            });
        }
        self.state.clone_from(state);
        Ok(())
    }

    /// Time stepping in use.
    pub fn settings(&self) -> &SolverSettings {
        &self.settings
    }

    /// Substeps per collision step in use.
    pub fn substeps(&self) -> u32 {
        self.substeps
    }

    /// Substep length in use, s.
    pub fn dt(&self) -> f64 {
        self.settings.step_dt() / self.substeps as f64
    }

    /// Predicted stable limit of the substep, `2/ω` of the stiffest bending mode, s.
    pub fn dt_max(&self) -> f64 {
        self.dt_max
    }

    /// Stiffness of the cross-section in use.
    pub fn stiffness(&self) -> Stiffness {
        self.stiffness
    }

    /// Rod parameters in use.
    pub fn rod_params(&self) -> &RodParams {
        &self.rod
    }

    /// Frame number of the current state.
    pub fn frame(&self) -> u32 {
        self.state.frame
    }

    /// Rest data of strand `s`.
    pub fn strand(&self, s: usize) -> &RodStrand {
        &self.strands[s]
    }

    /// Root frames of the current state.
    pub fn roots(&self) -> &[RootFrame] {
        &self.state.roots
    }

    /// Twist angles of strand `s`'s segments (rad, against their reference frames) at the last
    /// substep's start.
    pub fn twist(&self, s: usize) -> &[f64] {
        &self.state.theta[s]
    }

    /// Mechanical energy of `strands` with the roots of the current state, J: kinetic and
    /// gravity of free points, and the rod's bending ([`Energy::bend`]) and twist
    /// ([`Energy::twist`]) energy at the quasistatic twist of the current shape (relaxed from the
    /// last substep's). Summed strand by strand in index order.
    pub fn energy(&self, strands: &StrandSet) -> Energy {
        let g: V3 = self.params.gravity().cast();
        let mut e = Energy::default();
        let mut ws = Workspace::default();
        for (s, rod) in self.strands.iter().enumerate() {
            let p = strands.points(s);
            let x: Vec<V3> = strands.positions[p.clone()]
                .iter()
                .map(|v| v.cast())
                .collect();
            for ((xi, vi), &m) in x
                .iter()
                .zip(&strands.velocities[p.clone()])
                .zip(&strands.masses()[p])
            {
                let m = m as f64;
                e.kinetic += 0.5 * m * vi.cast::<f64>().norm_squared();
                e.gravity -= m * g.dot(xi);
            }
            let root = Root::of(&self.state.roots[s]);
            ws.twist.theta.clone_from(&self.state.theta[s]);
            rod.update_twist(&x, &root, &self.stiffness, &[], &mut ws);
            let (bend, twist) = rod.energies(&x, &root, &self.stiffness, &mut ws);
            e.bend += bend;
            e.twist += twist;
        }
        e
    }

    /// Model components this solver runs.
    pub fn components(&self, _strands: &StrandSet) -> ComponentSet {
        let mut c: ComponentSet = [
            Component::RodBending,
            Component::QuasistaticTwist,
            Component::RodProjection,
        ]
        .into_iter()
        .collect();
        if self.params.gravity().norm_squared() > 0.0 {
            c.insert(Component::Gravity);
        }
        if self.params.air_drag > 0.0 {
            c.insert(Component::AirDrag);
        }
        c
    }

    /// Advances `strands` by one frame to the instant at which `scalp` is given, with no
    /// colliders. On [`HairError::Unstable`] the failed strand keeps its state at the frame's
    /// start and the others have advanced: do not write that state anywhere.
    pub fn step_frame(&mut self, strands: &mut StrandSet, scalp: &Scalp) -> Result<RodFrameReport> {
        self.advance(strands, scalp, None)
    }

    /// Advances `strands` by one frame with head collision against `colliders` posed for the
    /// frame's end (see [`collide`]). Only solid colliders are supported: a shell (open mesh) is
    /// refused with [`HairError::Collider`].
    pub fn step_frame_with_colliders(
        &mut self,
        strands: &mut StrandSet,
        scalp: &Scalp,
        colliders: &mut Colliders,
    ) -> Result<RodFrameReport> {
        colliders.settings.validate()?;
        if let Some(i) = colliders
            .entries
            .iter()
            .position(|e| e.surface != Surface::Solid)
        {
            return Err(HairError::Collider {
                collider: i,
                message: "is an open mesh (shell); the rod model collides with solid colliders \
                          only: close the mesh or use model = \"mass-spring\""
                    .into(),
            });
        }
        if colliders.is_empty() {
            return self.advance(strands, scalp, None);
        }
        colliders.begin_frame(scalp)?;
        // The rod projects onto each shape in every substep: a deforming mesh stands at the
        // frame's end for the whole frame.
        colliders.place_meshes(1.0, 0.0, 1.0);
        let report = self.advance(strands, scalp, Some(colliders));
        colliders.finish_frame();
        report
    }

    fn advance(
        &mut self,
        strands: &mut StrandSet,
        scalp: &Scalp,
        colliders: Option<&Colliders>,
    ) -> Result<RodFrameReport> {
        let frame = self.state.frame + 1;
        let t0 = Instant::now();
        let mut end_roots = strands.root_frames(scalp);
        for (end, prev) in end_roots.iter_mut().zip(&self.state.roots) {
            if end.rotation.coords.dot(&prev.rotation.coords) < 0.0 {
                end.rotation = UnitQuaternion::new_unchecked(-end.rotation.into_inner());
            }
        }
        let roots_time = t0.elapsed();
        let t1 = Instant::now();
        let total = self.settings.steps * self.substeps;
        let dt = self.dt();
        let gravity: V3 = self.params.gravity().cast();
        let drag = self.params.air_drag as f64;
        let offsets = strands.offsets().to_vec();
        if let Some(c) = colliders {
            let key: Vec<usize> = c
                .entries
                .iter()
                .flat_map(|e| {
                    [
                        std::sync::Arc::as_ptr(&e.shape.0) as *const u8 as usize,
                        e.version as usize,
                    ]
                })
                .collect();
            if key != self.workspace.key {
                self.workspace.clearance.iter_mut().for_each(Vec::clear);
                self.workspace.key = key;
            }
        }
        let mut clearance = std::mem::take(&mut self.workspace.clearance);
        clearance.resize(strands.len(), Vec::new());
        let mut jobs = Vec::with_capacity(strands.len());
        {
            let (mut x_rest, mut v_rest) = (
                strands.positions.as_mut_slice(),
                strands.velocities.as_mut_slice(),
            );
            for (s, memory) in clearance.iter_mut().enumerate() {
                let len = (offsets[s + 1] - offsets[s]) as usize;
                let (x, xr) = x_rest.split_at_mut(len);
                let (v, vr) = v_rest.split_at_mut(len);
                x_rest = xr;
                v_rest = vr;
                jobs.push((s, x, v, memory));
            }
        }
        let this = &*self;
        let outcomes: Vec<StrandOutcome> = jobs
            .into_par_iter()
            .map_init(Workspace::default, |ws, (s, xs, vs, memory)| {
                let rod = &this.strands[s];
                let mut state = RodState {
                    x: xs.iter().map(|p| p.cast()).collect(),
                    v: vs.iter().map(|p| p.cast()).collect(),
                    theta: this.state.theta[s].clone(),
                    clearance: std::mem::take(memory),
                };
                let mut out = StrandOutcome {
                    projection: ProjectionReport {
                        tolerance: this.rod.projection_tolerance as f64,
                        ..Default::default()
                    },
                    ..Default::default()
                };
                let (start, end) = (&this.state.roots[s], &end_roots[s]);
                for k in 0..total {
                    let a = k as f32 / total as f32;
                    let b = (k + 1) as f32 / total as f32;
                    let input = Substep {
                        dt,
                        gravity,
                        air_drag: drag,
                        stiffness: &this.stiffness,
                        root_start: Root::of(&start.interpolate(end, a)),
                        root_end: Root::of(&start.interpolate(end, b)),
                        max_iterations: this.rod.projection_iterations,
                        tolerance: this.rod.projection_tolerance as f64,
                        colliders: colliders.map(|c| (c, b)),
                        external: None,
                        torque: None,
                    };
                    let o = rod.substep(&mut state, &input, ws);
                    let p = &mut out.projection;
                    p.projections += o.projections as u64;
                    p.iterations += o.iterations as u64;
                    p.max_iterations = p.max_iterations.max(o.projection.iterations);
                    p.residual = p.residual.max(o.projection.residual);
                    out.contacts += o.contacts as u64;
                    let finite = state
                        .x
                        .iter()
                        .chain(&state.v)
                        .all(|v| v.iter().all(|c| c.is_finite()));
                    if !finite || !o.projection.residual.is_finite() {
                        out.failure = Some(Blowup::RodNonFinite { substep: k + 1 });
                        return out;
                    }
                    if !o.projection.converged {
                        p.unconverged += 1;
                        if o.projection.residual > FAILED_RESIDUAL {
                            out.failure = Some(Blowup::RodProjection {
                                residual: o.projection.residual,
                                iterations: o.projection.iterations,
                                limit: this.rod.projection_iterations,
                            });
                            return out;
                        }
                    }
                }
                *memory = std::mem::take(&mut state.clearance);
                for (dst, src) in xs.iter_mut().zip(&state.x) {
                    *dst = src.cast();
                }
                for (dst, src) in vs.iter_mut().zip(&state.v) {
                    *dst = src.cast();
                }
                out.projection.max_strain = max_strain(xs, rod.rest_lengths());
                out.theta = state.theta;
                out
            })
            .collect();
        self.workspace.clearance = clearance;
        for (theta, o) in self.state.theta.iter_mut().zip(&outcomes) {
            if o.failure.is_none() {
                theta.clone_from(&o.theta);
            }
        }
        let mut projection = ProjectionReport {
            tolerance: self.rod.projection_tolerance as f64,
            ..Default::default()
        };
        let mut contacts = 0;
        for (s, o) in outcomes.into_iter().enumerate() {
            if let Some(cause) = o.failure {
                return Err(HairError::Unstable {
                    frame,
                    strand: s,
                    cause,
                    dt,
                    bound: self.dt_max,
                    auto_substeps: auto_substeps(self.settings.step_dt(), self.dt_max),
                });
            }
            projection.merge(&o.projection);
            contacts += o.contacts;
        }
        self.state.roots = end_roots;
        self.state.frame = frame;
        Ok(RodFrameReport {
            frame: FrameReport {
                frame,
                substeps: self.substeps,
                steps: self.settings.steps,
                point_substeps: strands.point_count() as u64 * total as u64,
                contact_points: contacts / self.substeps as u64,
                // The rod projects its nodes out of colliders in every substep.
                escaped_points: 0,
                deep_contact_points: 0,
                max_stretch: strands.max_stretch(),
                times: PhaseTimes {
                    roots: roots_time,
                    strands: t1.elapsed(),
                    contacts: Default::default(),
                    ..Default::default()
                },
                figures: ModelFigures::Rod(projection),
            },
            projection,
        })
    }
}

/// Substeps per step of `step_dt` s that `substeps = auto` takes for the bound `dt_max` (s).
fn auto_substeps(step_dt: f64, dt_max: f64) -> u32 {
    let wanted = (step_dt / (AUTO_SAFETY * dt_max)).ceil();
    if wanted.is_finite() {
        (wanted as u32).max(1)
    } else {
        1
    }
}

/// Largest `|len/rest − 1|` of a strand's stored positions.
fn max_strain(x: &[Vector3<f32>], rest: &[f64]) -> f64 {
    x.windows(2)
        .zip(rest)
        .map(|(w, &l)| ((w[1] - w[0]).cast::<f64>().norm() / l - 1.0).abs())
        .fold(0.0, f64::max)
}
