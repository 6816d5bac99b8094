//! [`Simulation`]: everything a run needs, as the assembly ([`crate::build`]) made it, whichever
//! door it came through: the strands at rest, time stepping and physics, the scalp with its
//! motion, colliders, fields, hair–hair, the strand model, animated guides, regions and maps.
//! It evaluates the rig at a (possibly fractional) frame for the session that runs it.

use hair_core::model::strips::{HeadShape, StripSolver};
use hair_core::{
    Collider, ColliderId, ColliderShape, Colliders, ContactSettings, HairError, HairParams,
    MassSpringSolver, RodParams, RodSolver, Scalp, SolverSettings, StrandModel, StrandScales,
    StrandSet, StrandSolver, TriMesh,
};
use nalgebra::Vector3;

use crate::scene::deforming::{DeformingFrames, MeshAnimation};
use crate::scene::error::ColliderError;
use crate::scene::integrator::ResolvedIntegrator;
use crate::scene::{maps, regions};
use crate::scene::{ScalpCollider, SceneProblem};

use super::scene_file::named;

/// A collider of a simulation: its geometry, thickness, friction and rigid motion.
#[derive(Debug, Clone)]
pub struct SceneCollider {
    /// The name from the scene file (may be empty).
    pub name: String,
    /// Geometry (meshes loaded), thickness and friction.
    pub collider: Collider,
    /// Rigid motion: keyframed in a scene, fixed at a host's first-frame pose.
    pub motion: crate::rig::Motion,
    /// For a deforming mesh (`kind = "usd"` or `"obj-sequence"`): its body-space vertices at
    /// every frame.
    pub animation: Option<MeshAnimation>,
}

impl SceneCollider {
    /// The collider's mesh (body space) at (possibly fractional) `frame`: deformed for a
    /// deforming collider; `None` for analytic shapes.
    pub fn mesh_at(&self, frame: f32) -> Option<TriMesh> {
        let ColliderShape::Mesh(rest) = &self.collider.shape else {
            return None;
        };
        let mut mesh = rest.clone();
        if let Some(a) = &self.animation {
            // The vertices were checked (count, finite) when read.
            mesh.set_positions(&a.vertices_at(frame)).ok()?;
        }
        Some(mesh)
    }
}

/// Everything a run needs, built from a scene.
#[derive(Debug, Clone)]
pub struct Simulation {
    /// Strands at rest at the first frame.
    pub strands: StrandSet,
    /// Time stepping (`integrator` resolved: see [`Self::integrator`]).
    pub settings: SolverSettings,
    /// The integrator `settings` carries, whether `[solver] integrator = "auto"` chose it, and
    /// the substep counts it compared.
    pub integrator: ResolvedIntegrator,
    /// Physics parameters.
    pub params: HairParams,
    /// First frame (hair at rest).
    pub first_frame: u32,
    /// Last frame.
    pub last_frame: u32,
    pub(crate) rest_mesh: Option<TriMesh>,
    /// One RGB colour (0–1) per scalp vertex, if the scalp has vertex colours (an OBJ's
    /// `v x y z r g b`): the colours of the children's roots.
    pub scalp_colors: Option<Vec<[f32; 3]>>,
    /// For a deforming scalp: its vertices (body space) at every frame.
    pub(crate) scalp_animation: Option<MeshAnimation>,
    /// The scalp's rigid motion.
    pub(crate) motion: crate::rig::Motion,
    /// The `[[colliders]]`, in file order (their [`ColliderId`]s are 0, 1, …).
    pub colliders: Vec<SceneCollider>,
    /// `[scalp.collider]`, if the scalp collides with its hair.
    pub scalp_collider: Option<ScalpCollider>,
    /// `[contacts]`.
    pub contact_settings: ContactSettings,
    /// The `[guides]` on the scalp, if the scene has them.
    pub guides: Vec<hair_groom::Guide>,
    /// What `[guides]` and `[sim_hairs]` built, in words (snap distances included).
    pub guides_report: Option<String>,
    /// `[hair_hair]`, if on.
    pub hair_hair: Option<hair_core::HairHairSettings>,
    /// `[[fields]]`, validated, in file order.
    pub fields: Vec<hair_core::ForceField>,
    /// `[solver] model`: which strand solver runs.
    pub model: StrandModel,
    /// `[rod]` (the defaults when absent); used when `model` is the rod.
    pub rod: RodParams,
    /// `[solver] inextensibility`: the projection of the mass-spring model, if on.
    pub inextensibility: Option<hair_core::Inextensibility>,
    /// `[strips]` settings when `[solver] model = "strips"` (strip `k` = strands `2k`, `2k + 1`).
    pub strips: Option<hair_core::model::strips::StripSettings>,
    /// Animated guides (`[[guides.pose]]`, `[guides.sim_weight]`, pins, hold-outs), if keyed.
    pub guide_animation: Option<crate::rig::animated_guides::GuideAnimation>,
    /// `[[regions]]` and `[maps.stiffness]` resolved to strands (empty: one material).
    pub regions: regions::Regions,
    /// Per-strand factors of the material a host gave with its strands
    /// ([`crate::build::groom`]); `None` for a scene, whose factors come from `regions`.
    pub strand_scales: Option<Vec<StrandScales>>,
    /// `[maps.clump]` and `[maps.curl]` at each strand's root: factors of its render children's
    /// clump and curl.
    pub child_maps: maps::ChildMapFactors,
    /// The `[maps.NAME]` sections as built: source, purpose, values at the roots.
    pub maps: Vec<maps::MapSummary>,
}

impl Simulation {
    /// The strand solver of the scene's `[solver] model` for its first frame: mass-spring with
    /// the scene's hair–hair, fields and inextensibility projection; the rod with `[rod]`; the
    /// strips with `[strips]` (with `[scalp.collider]` the rest scalp is the head of their
    /// two-stage collision).
    pub fn strand_solver(&self) -> Result<StrandSolver, HairError> {
        let scalp = self.scalp_at(self.first_frame as f32);
        Ok(match self.model {
            StrandModel::MassSpring => {
                let mut solver = MassSpringSolver::new(
                    self.settings,
                    self.params,
                    &self.strands,
                    &scalp,
                    self.first_frame,
                )?;
                if !self.regions.is_empty() {
                    let scales = self
                        .regions
                        .scales(&self.params, self.strands.len())
                        .map_err(|e| HairError::Parameter {
                            name: "regions".into(),
                            value: "their parameters".into(),
                            fix: e.to_string(),
                        })?;
                    solver = solver.with_strand_scales(scales, &self.strands)?;
                } else if let Some(scales) = &self.strand_scales {
                    solver = solver.with_strand_scales(scales.clone(), &self.strands)?;
                }
                self.with_inextensibility(self.with_interactions(solver)?)?
                    .into()
            }
            StrandModel::Rod => RodSolver::new(
                self.settings,
                self.params,
                self.rod,
                &self.strands,
                &scalp,
                self.first_frame,
            )?
            .into(),
            StrandModel::Strips => {
                let settings = self.strips.ok_or_else(|| HairError::Parameter {
                    name: "strips".into(),
                    value: "absent".into(),
                    fix: "[solver] model = \"strips\" needs a [strips] section".into(),
                })?;
                let head = match (self.scalp_collider.is_some(), self.rest_mesh()) {
                    (true, Some(mesh)) => Some(HeadShape::new(mesh)?),
                    _ => None,
                };
                StripSolver::new(
                    self.settings,
                    self.params,
                    &self.strands,
                    &scalp,
                    self.first_frame,
                    settings,
                    head,
                )?
                .into()
            }
        })
    }

    /// `solver` with the scene's inextensibility projection (`[solver] inextensibility`) on, if
    /// the scene asks for it.
    pub fn with_inextensibility(
        &self,
        solver: hair_core::MassSpringSolver,
    ) -> Result<hair_core::MassSpringSolver, HairError> {
        match self.inextensibility {
            Some(p) => solver.with_inextensibility(p),
            None => Ok(solver),
        }
    }

    /// The scalp mesh at rest (before the scalp's motion), if the scene has one.
    pub fn rest_mesh(&self) -> Option<&TriMesh> {
        self.rest_mesh.as_ref()
    }

    /// True when the scene has any collider (scene colliders or the scalp).
    pub fn has_colliders(&self) -> bool {
        !self.colliders.is_empty() || self.scalp_collider.is_some()
    }

    /// The colliders placed at (possibly fractional) `frame`: the `[[colliders]]` in file order,
    /// then the scalp if `[scalp.collider]` is given.
    pub fn colliders_at(&self, frame: f32) -> Result<Colliders, HairError> {
        let mut set = Colliders::new();
        set.settings = self.contact_settings;
        for c in &self.colliders {
            let id = set.insert(c.collider.clone(), c.motion.at(frame))?;
            if let Some(a) = &c.animation {
                set.will_deform(id)?;
                set.place_vertices(id, &a.vertices_at(frame))?;
            }
        }
        if let Some(sc) = &self.scalp_collider {
            // From the rest mesh, so a resumed run builds the same shape bits.
            match &self.rest_mesh {
                Some(rest) => {
                    let id = set.insert_scalp_rest(
                        rest.clone(),
                        self.motion.at(frame),
                        sc.thickness,
                        sc.friction,
                    )?;
                    if self.scalp_animation.is_some() {
                        set.will_deform(id)?;
                        set.place_scalp(&self.scalp_at(frame))?;
                    }
                }
                None => {
                    set.insert_scalp(&self.scalp_at(frame), sc.thickness, sc.friction)?;
                }
            };
        }
        Ok(set)
    }

    /// Per point, the outward normal of the collider surface the hair rests on at the first
    /// frame, or zero (see [`hair_core::quality::resting_normals`]): what sag-free lets the
    /// colliders carry. A point rests on a collider when it is within two strand radii (the
    /// largest in the set) of touching it — a layered groom's lower layers.
    pub fn resting_supports(&self) -> Result<Vec<Vector3<f32>>, HairError> {
        let colliders = self.colliders_at(self.first_frame as f32)?;
        let reach = 2.0 * self.strands.radii().iter().fold(0.0f32, |a, &r| a.max(r));
        Ok(hair_core::quality::resting_normals(
            &colliders,
            &self.strands.positions,
            self.strands.radii(),
            self.strands.inverse_masses(),
            reach,
        ))
    }

    /// Sets every scene collider's pose, and a deforming collider's vertices, at the end of
    /// the frame to be stepped, (possibly fractional) `frame` (the scalp collider follows the
    /// scalp by itself).
    pub fn pose_colliders(&self, set: &mut Colliders, frame: f32) -> Result<(), HairError> {
        for i in 0..self.colliders.len() {
            self.pose_collider(set, i, frame)?;
        }
        Ok(())
    }

    /// Sets scene collider `i`'s pose, and its vertices if it deforms, at the end of the frame
    /// to be stepped, `frame`.
    pub fn pose_collider(
        &self,
        set: &mut Colliders,
        i: usize,
        frame: f32,
    ) -> Result<(), HairError> {
        let Some(c) = self.colliders.get(i) else {
            return Ok(());
        };
        let id = ColliderId(i as u32);
        set.set_pose(id, c.motion.at(frame))?;
        if let Some(a) = &c.animation {
            set.set_vertices(id, &a.vertices_at(frame))?;
        }
        Ok(())
    }

    /// Puts every scene collider (pose and, if it deforms, vertices) and the scalp collider at
    /// `frame` now, with no motion into it: for measuring frames out of order.
    pub fn place_colliders(&self, set: &mut Colliders, frame: f32) -> Result<(), HairError> {
        for (i, c) in self.colliders.iter().enumerate() {
            let id = ColliderId(i as u32);
            set.set_pose(id, c.motion.at(frame))?;
            if let Some(a) = &c.animation {
                set.place_vertices(id, &a.vertices_at(frame))?;
            }
        }
        set.place_scalp(&self.scalp_at(frame))
    }

    /// Refuses a run over frames `first..=last` that leaves the frames a deforming scalp or
    /// collider was read for (see [`crate::scene::deforming`]).
    pub fn check_deforming_frames(&self, first: u32, last: u32) -> Result<(), DeformingFrames> {
        let scalp = self
            .scalp_animation
            .iter()
            .map(|a| ("[scalp.mesh]".to_string(), a));
        let colliders = self.colliders.iter().enumerate().filter_map(|(i, c)| {
            let a = c.animation.as_ref()?;
            Some((format!("[[colliders]] #{i}{}", named(&c.name)), a))
        });
        for (field, a) in scalp.chain(colliders) {
            a.check_covers(first, last)
                .map_err(|source| DeformingFrames { field, source })?;
        }
        Ok(())
    }

    /// True when the scalp mesh deforms (a USD or OBJ-sequence scalp).
    pub fn scalp_deforms(&self) -> bool {
        self.scalp_animation.is_some()
    }

    /// A collider error as a scene problem: [`SceneProblem::Collider`] naming
    /// `[[colliders]] #i (name)`, or [`SceneProblem::ScalpCollider`] (the solver's collider
    /// after the scene's, or another error of the colliders).
    pub fn collider_problem(&self, e: HairError) -> SceneProblem {
        match &e {
            HairError::Collider { collider, .. } => match self.colliders.get(*collider) {
                Some(c) => SceneProblem::Collider {
                    index: *collider,
                    name: c.name.clone(),
                    source: ColliderError::Invalid(e),
                },
                None => SceneProblem::ScalpCollider(e),
            },
            _ => SceneProblem::Colliders(e),
        }
    }

    /// A collider error in the scene's terms: `[[colliders]] #i (name)` or `[scalp.collider]`.
    pub fn collider_message(&self, e: &HairError) -> String {
        match e {
            HairError::Collider { collider, message } => match self.colliders.get(*collider) {
                Some(c) => format!("[[colliders]] #{collider}{}: {message}", named(&c.name)),
                None => format!("[scalp.collider]: {message}"),
            },
            other => other.to_string(),
        }
    }

    /// The deformed scalp's vertices (body space, m) at (possibly fractional) `frame`, for a
    /// deforming scalp; `None` for a rigid one.
    pub fn scalp_vertices_at(&self, frame: f32) -> Option<Vec<Vector3<f32>>> {
        self.scalp_animation.as_ref().map(|a| a.vertices_at(frame))
    }

    /// The scalp at (possibly fractional) `frame`: the rest mesh, deformed to the frame's
    /// vertices for a deforming scalp, moved by the rigid motion.
    pub fn scalp_at(&self, frame: f32) -> Scalp {
        let body = self.motion.at(frame);
        let mesh = self
            .rest_mesh
            .as_ref()
            .map(|rest| match &self.scalp_animation {
                Some(a) => {
                    let mut m = rest.clone();
                    // The vertices were checked (count, finite) when read; keep the rest otherwise.
                    if m.set_positions(&a.vertices_at(frame)).is_err() {
                        m = rest.clone();
                    }
                    m.transformed(&body)
                }
                None => rest.transformed(&body),
            });
        Scalp { mesh, body }
    }

    /// Restricts the run to frames `first..=last` (the hair starts at rest at `first`).
    pub fn set_frames(&mut self, first: u32, last: u32) {
        self.first_frame = first;
        self.last_frame = last;
        let scalp = self.scalp_at(first as f32);
        self.strands.reset_to_rest(&scalp);
    }
}
