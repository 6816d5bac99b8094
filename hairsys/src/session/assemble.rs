//! Making a [`Session`]: from a scene file, from a built [`Simulation`], from a host's groom
//! arrays; every door ends in [`Session::assemble`].

use hair_cache::{CacheRig, RigScalp};
use hair_core::ColliderId;

use crate::build::Simulation;
use crate::error::{Error, Result};
use crate::scene::SceneFile;

use super::{Deformed, Guides, Pending, RigTrack, SceneAnimation, SceneSource, Session};
use crate::build::groom::{GroomArrays, GroomOptions};

impl Session {
    /// A session of `scene` at its first frame (hair at rest), with its model, colliders, fields
    /// and hair–hair; its keyframes drive the scalp and colliders for every frame the host does
    /// not set them.
    pub fn from_scene(scene: &SceneFile) -> Result<Self> {
        let sim = scene.build()?;
        let hash = scene.hash()?;
        Self::from_simulation(sim, scene, hash)
    }

    /// A session of an already built scene `sim` (e.g. restricted to other frames, or put in an
    /// interrupted run's state by resume); `scene` names it and `hash` is stored in caches.
    pub fn from_simulation(sim: Simulation, scene: &SceneFile, hash: String) -> Result<Self> {
        let source = SceneSource {
            text: scene.text.clone(),
            hash,
        };
        Self::assemble(sim, scene.origin.clone(), Some(source))
    }

    /// A session of the groom `input` on its scalp (see the module docs), at rest at
    /// `options.first_frame`. Bad arrays are [`Error::Argument`]s naming the argument and the
    /// expected shape; a root farther than `max_snap_distance` from the scalp is refused by
    /// curve index.
    pub fn from_groom(input: &GroomArrays<'_>, options: &GroomOptions) -> Result<Self> {
        Session::assemble(
            crate::build::groom::simulation(input, options)?,
            crate::build::groom::ORIGIN.into(),
            None,
        )
    }

    /// The session of `sim` (named `origin` in errors): the one constructor every door ends in
    /// ([`crate::build`]). With a `scene`, its keyframes drive what the host does not set;
    /// without one (a host's groom), whatever the host does not set stays where it was.
    pub(crate) fn assemble(
        sim: Simulation,
        origin: String,
        scene: Option<SceneSource>,
    ) -> Result<Self> {
        let solver_error = |source| Error::Solver {
            scene: origin.clone(),
            source,
        };
        let solver = sim.strand_solver().map_err(solver_error)?;
        let first = sim.first_frame as f32;
        let colliders = sim.colliders_at(first).map_err(|e| {
            Error::Scene(crate::scene::SceneError::new(
                origin.clone(),
                sim.collider_problem(e),
            ))
        })?;
        let scalp_collider = sim
            .scalp_collider
            .map(|_| ColliderId(sim.colliders.len() as u32));
        let mut strands = sim.strands.clone();
        // Rest shapes at the first frame's pose (a resumed run continues with its frame's pose).
        let guides = sim.guide_animation.clone().map(|mut animation| {
            animation.bind(&strands);
            let mut scratch = Default::default();
            let work = match animation.pose_at(first) {
                Some(pose) => animation.apply_pose(&pose, &mut strands, &mut scratch),
                None => 0,
            };
            Guides {
                animation,
                scratch,
                work,
                time: std::time::Duration::ZERO,
            }
        });
        let rig = RigTrack {
            rig: CacheRig {
                anchors: strands.anchors().to_vec(),
                rest_local: strands.rest_local().to_vec(),
                inverse_masses: strands.inverse_masses().to_vec(),
                scalp: sim.rest_mesh().map(|mesh| RigScalp {
                    mesh: mesh.clone(),
                    colors: sim.scalp_colors.clone(),
                }),
                scalp_collider: sim.scalp_collider.map(|c| (c.thickness, c.friction)),
                colliders: sim.colliders.iter().map(|c| c.collider.clone()).collect(),
                clump: sim.child_maps.clump.clone(),
                curl: sim.child_maps.curl.clone(),
            },
            deformed: Deformed {
                scalp: sim.scalp_vertices_at(first),
                colliders: sim
                    .colliders
                    .iter()
                    .map(|c| c.animation.as_ref().map(|a| a.vertices_at(first)))
                    .collect(),
            },
        };
        Ok(Self {
            strands,
            solver,
            colliders,
            scalp: sim.scalp_at(first),
            rest_scalp: sim.rest_mesh().cloned(),
            scalp_collider,
            fps: sim.settings.fps,
            animation: scene.map(|source| SceneAnimation {
                sim,
                origin,
                source,
            }),
            guides,
            pending: Pending::default(),
            rig,
            pool: None,
            recorder: None,
            cache_time: std::time::Duration::ZERO,
            failed: None,
        })
    }

    /// The scene's `[maps.clump]` and `[maps.curl]` per strand, for a session of a scene.
    pub(crate) fn scene_child_maps(&self) -> Option<&crate::scene::maps::ChildMapFactors> {
        self.animation.as_ref().map(|a| &a.sim.child_maps)
    }
}
