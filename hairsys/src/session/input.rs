//! What a host sets for the next frame: the scalp, collider poses and deformed vertices,
//! animatable parameters, the guides' pose and sim weights. Everything is checked here and held
//! until [`Session::step`].

use bytemuck::cast_slice;
use hair_core::{ColliderId, ForceField, HairHairSettings, HairParams, Scalp};
use nalgebra::{Isometry3, Vector3};

use crate::error::{Error, Result};
use crate::rig::animated_guides::GuideAnimation;

use super::{Guides, Session};

impl Session {
    /// Sets the scalp's rigid transform (body to world, m) for the frame to be stepped next:
    /// roots and the scalp collider follow it.
    pub fn set_scalp_transform(&mut self, body: Isometry3<f32>) -> Result<()> {
        check_isometry("scalp_transform", &body)?;
        let mesh = self.rest_scalp.as_ref().map(|m| m.transformed(&body));
        self.pending.scalp = Some(Scalp { mesh, body });
        self.pending.scalp_vertices = Some(None);
        Ok(())
    }

    /// Sets the deformed scalp for the frame to be stepped next: `vertices` (m, one per vertex
    /// of the rest scalp, in its order, in the scalp's body space) placed by `body` (body to
    /// world; identity when the vertices are already in world space). Roots follow their mesh
    /// samples on the deformed surface exactly.
    pub fn set_scalp_vertices(
        &mut self,
        vertices: &[[f32; 3]],
        body: Isometry3<f32>,
    ) -> Result<()> {
        check_isometry("scalp_transform", &body)?;
        let Some(rest) = &self.rest_scalp else {
            return Err(Error::argument(
                "scalp_vertices",
                "this session's scalp has no mesh to deform; set a transform instead",
            ));
        };
        let expected = rest.positions().len();
        if vertices.len() != expected {
            return Err(Error::argument(
                "scalp_vertices",
                format!(
                    "{} vertices given, the scalp mesh has {expected}: give an array of shape \
                     ({expected}, 3) in the rest mesh's vertex order (the topology cannot change)",
                    vertices.len()
                ),
            ));
        }
        if let Some(i) = vertices
            .iter()
            .position(|v| !v.iter().all(|c| c.is_finite()))
        {
            return Err(Error::argument(
                "scalp_vertices",
                format!("vertex {i} is not finite ({:?})", vertices[i]),
            ));
        }
        let mut mesh = rest.clone();
        let body_space: &[Vector3<f32>] = cast_slice(vertices);
        mesh.set_positions(body_space)
            .map_err(|e| Error::argument("scalp_vertices", e.to_string()))?;
        self.pending.scalp = Some(Scalp {
            mesh: Some(mesh.transformed(&body)),
            body,
        });
        self.pending.scalp_vertices = Some(Some(body_space.to_vec()));
        Ok(())
    }

    /// Poses collider `id` (body to world, m) at the end of the frame to be stepped next; it
    /// moves there from its current pose during the frame.
    pub fn set_collider_pose(&mut self, id: ColliderId, pose: Isometry3<f32>) -> Result<()> {
        self.check_collider(id)?;
        check_isometry(&format!("collider {} pose", id.0), &pose)?;
        self.colliders
            .set_pose(id, pose)
            .map_err(|e| Error::argument(format!("collider {}", id.0), e.to_string()))?;
        let i = id.0 as usize;
        if self.pending.posed.len() <= i {
            self.pending.posed.resize(i + 1, false);
        }
        self.pending.posed[i] = true;
        Ok(())
    }

    /// Deforms mesh collider `id`: `vertices` (m, one per vertex of the mesh it was inserted
    /// with, in that order, in its body space) are its shape at the end of the frame to be
    /// stepped next; within the frame each vertex moves in a straight line, and the surface
    /// velocity that gives acts on friction and the contact response (see
    /// `hair_core::contacts`). Place the mesh with [`Session::set_collider_pose`].
    pub fn set_collider_vertices(&mut self, id: ColliderId, vertices: &[[f32; 3]]) -> Result<()> {
        self.check_collider(id)?;
        let argument = format!("collider {} vertices", id.0);
        if let Some(i) = vertices
            .iter()
            .position(|v| !v.iter().all(|c| c.is_finite()))
        {
            return Err(Error::argument(
                argument,
                format!("vertex {i} is not finite ({:?})", vertices[i]),
            ));
        }
        self.colliders
            .set_vertices(id, cast_slice(vertices))
            .map_err(|e| Error::argument(argument, e.to_string()))?;
        let i = id.0 as usize;
        if self.pending.deformed.len() <= i {
            self.pending.deformed.resize(i + 1, false);
        }
        self.pending.deformed[i] = true;
        if self.pending.collider_vertices.len() <= i {
            self.pending.collider_vertices.resize(i + 1, None);
        }
        self.pending.collider_vertices[i] = Some(cast_slice(vertices).to_vec());
        Ok(())
    }

    fn check_collider(&self, id: ColliderId) -> Result<()> {
        if Some(id) == self.scalp_collider {
            return Err(Error::argument(
                format!("collider {}", id.0),
                "is the scalp collider, which follows the scalp: set the scalp instead",
            ));
        }
        if id.0 as usize >= self.colliders.len() {
            return Err(Error::argument(
                format!("collider {}", id.0),
                format!(
                    "does not exist: this session has {} collider(s), ids 0 to {}",
                    self.colliders.len(),
                    self.colliders.len() as i64 - 1
                ),
            ));
        }
        Ok(())
    }

    /// The material and environment (gravity, goal stiffness, air drag…) to change between
    /// frames; checked again at the next step. `None` for the rod model, whose parameters are
    /// fixed at creation.
    pub fn params_mut(&mut self) -> Option<&mut HairParams> {
        self.solver.mass_spring_mut().map(|s| s.params_mut())
    }

    /// The force fields, to change between frames (strength, direction, position); checked
    /// again at the next step. Empty for the rod model.
    pub fn fields_mut(&mut self) -> &mut [ForceField] {
        match self.solver.mass_spring_mut() {
            Some(s) => s.fields_mut(),
            None => &mut [],
        }
    }

    /// Hair–hair settings to change between frames, if hair–hair is on.
    pub fn hair_hair_mut(&mut self) -> Option<&mut HairHairSettings> {
        self.solver.mass_spring_mut()?.hair_hair_mut()
    }

    /// The animated guides of a session of a guided scene (`[guides]`): their keys, sim
    /// weights and hold-outs.
    pub fn guide_animation(&self) -> Option<&GuideAnimation> {
        self.guides.as_ref().map(|g| &g.animation)
    }

    /// Work of the last step's guide re-interpolation: blend operations plus points written
    /// (0 when no pose was applied). Linear in the sim hairs' points.
    pub fn guide_pose_work(&self) -> u64 {
        self.guides.as_ref().map_or(0, |g| g.work)
    }

    /// Wall-clock time of the last step's guide pose: the keyed pose evaluated and the sim
    /// hairs re-interpolated (zero without guides).
    pub fn guide_pose_time(&self) -> std::time::Duration {
        self.guides.as_ref().map_or(Default::default(), |g| g.time)
    }

    fn guides_or_err(&self, argument: &str) -> Result<&Guides> {
        self.guides.as_ref().ok_or_else(|| {
            Error::argument(
                argument,
                "this session has no guides: build it from a scene with [guides] and [sim_hairs] \
                 (mass-spring model)",
            )
        })
    }

    /// Sets the guides' pose for the frame to be stepped next: `points` (m) are every guide's
    /// points, in the groom's guide order and point counts
    /// ([`GuideAnimation::guide_points`]), flat, in the scalp's body space at rest (the scene's
    /// space). The sim hairs' rest shapes are re-interpolated from it; roots stay where they
    /// grow (each guide is moved onto its root).
    pub fn set_guide_pose(&mut self, points: &[[f32; 3]]) -> Result<()> {
        let pose = self
            .guides_or_err("points")?
            .animation
            .pose_from_points(points)
            .map_err(|e| Error::argument("points", e.to_string()))?;
        self.pending.guide_pose = Some(pose);
        Ok(())
    }

    /// Sets the sim weight for the frame to be stepped next, instead of the scene's curve:
    /// 0 = simulation, 1 = exactly the animated guides, in between a blend (times each hair's
    /// factor, [`Session::set_strand_sim_weights`]).
    pub fn set_sim_weight(&mut self, weight: f32) -> Result<()> {
        self.guides_or_err("sim_weight")?;
        check_weight("sim_weight", weight)?;
        self.pending.sim_weight = Some(weight);
        Ok(())
    }

    /// Sets each sim hair's factor of the sim weight (one value in [0, 1] per sim hair, in
    /// order), kept until set again: a hair's weight is the curve's (or
    /// [`Session::set_sim_weight`]'s) times its factor.
    pub fn set_strand_sim_weights(&mut self, weights: &[f32]) -> Result<()> {
        let hairs = self.guides_or_err("weights")?.animation.strands().len();
        if weights.len() != hairs {
            return Err(Error::argument(
                "weights",
                format!(
                    "{} values for {hairs} sim hairs: give one per sim hair",
                    weights.len()
                ),
            ));
        }
        for (i, &w) in weights.iter().enumerate() {
            check_weight(&format!("weights[{i}]"), w)?;
        }
        if let Some(g) = &mut self.guides {
            g.animation.set_factors(weights.to_vec());
        }
        Ok(())
    }
}

/// A sim weight must be in [0, 1].
fn check_weight(argument: &str, w: f32) -> Result<()> {
    if w.is_finite() && (0.0..=1.0).contains(&w) {
        Ok(())
    } else {
        Err(Error::argument(
            argument,
            format!("{w} is not a sim weight: use a value in [0, 1] (0 = simulation, 1 = the animated guides)"),
        ))
    }
}

/// Refuses a non-finite transform, naming `argument`.
fn check_isometry(argument: &str, iso: &Isometry3<f32>) -> Result<()> {
    let finite = iso.translation.vector.iter().all(|c| c.is_finite())
        && iso.rotation.coords.iter().all(|c| c.is_finite());
    if finite {
        Ok(())
    } else {
        Err(Error::argument(
            argument,
            "is not finite: give a rigid transform with finite translation and rotation",
        ))
    }
}
