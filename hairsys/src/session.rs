//! [`Session`]: the one front door a host drives frame by frame.
//!
//! A session bundles what a simulation is made of — the strands ([`StrandSet`]), the strand
//! solver of the scene's model ([`StrandSolver`]), the colliders ([`Colliders`]) and the scalp
//! ([`Scalp`]) — with one [`Session::step`], like rapier's `PhysicsWorld`. The parts stay public
//! through accessors, so a host can borrow what it needs (read the strands, change a field's
//! strength, pose a collider) between steps.
//!
//! # A frame, as a host drives it
//! 1. Set the scalp for the frame being stepped to: a rigid transform
//!    ([`Session::set_scalp_transform`]) or deformed vertex positions
//!    ([`Session::set_scalp_vertices`], in the scalp's body space, with the body transform);
//!    both move the roots, and the scalp collider follows.
//! 2. Pose colliders ([`Session::set_collider_pose`]), deform mesh colliders
//!    ([`Session::set_collider_vertices`]) and change animatable parameters
//!    ([`Session::params_mut`], [`Session::fields_mut`], [`Session::hair_hair_mut`]).
//! 3. [`Session::step`] advances one frame (1/fps s).
//! 4. Read [`Session::positions`] and [`Session::velocities`] as flat `[f32; 3]` slices (no copy)
//!    with [`Session::strand_offsets`].
//!
//! Whatever the host does not set for a frame follows the scene's keyframes when the session
//! was built from a scene ([`Session::from_scene`]), and otherwise stays where it was.
//!
//! # State and scratch
//! The state a frame depends on is the strands' positions and velocities, the solver's state
//! ([`StrandSolverState`]: frame number, root frames, the rod's twist, the parameters a host
//! changes between frames), the colliders and the scalp; the solver's workspace (contact lists,
//! the hair–hair grid) is scratch rebuilt every step. [`Session::snapshot`] copies the state and
//! [`Session::restore`] puts it back, for scrubbing; stepping on from a restored snapshot gives
//! the same bits as stepping on from where it was taken.
//!
//! # Threads and failures
//! Steps run on the rayon pool the host gives ([`Session::set_thread_pool`]; a DCC sizes it so
//! it is not oversubscribed), else on rayon's global pool; the result does not depend on the
//! thread count. A step that fails (blow-up, bad collider) leaves the session failed: the next
//! step returns [`Error::Failed`] until a snapshot is restored. Nothing in a session panics on
//! host input; bad arguments are [`Error::Argument`]s naming the argument and what is expected.

use std::path::Path;
use std::sync::Arc;

use bytemuck::cast_slice;
use hair_cache::{
    CacheHeader, CacheLayout, CacheRig, CacheSummary, CacheWriter, ColliderState, RigFrame,
    RigScalp, WriterOptions,
};
use hair_core::frames::RestDirection;
use hair_core::{
    ColliderId, Colliders, ForceField, FrameReport, HairError, HairHairSettings, HairParams,
    RootFrame, Scalp, StrandSet, StrandSolver, StrandSolverState, TriMesh,
};
use nalgebra::{Isometry3, Vector3};
use sha2::{Digest, Sha256};

use crate::animated_guides::GuideAnimation;
use crate::error::{Error, Result};
use crate::scene::{SceneFile, Simulation};

mod regions;

/// The scene a session was built from: its keyframes drive what the host does not set.
#[derive(Debug, Clone)]
struct SceneAnimation {
    /// The built scene (scalp motion, collider motions).
    sim: Simulation,
    /// How the scene names itself in errors (its file).
    origin: String,
    /// The scene's text, hash and directory.
    source: SceneSource,
}

/// The scene file a session was built from, as caches the session writes record it.
#[derive(Debug, Clone)]
pub(crate) struct SceneSource {
    /// The scene text as read.
    text: String,
    /// The scene's hash ([`SceneFile::hash`]).
    hash: String,
}

/// What the host set for the next frame.
#[derive(Debug, Clone, Default)]
struct Pending {
    scalp: Option<Scalp>,
    /// Colliders the host posed for the next frame, by id.
    posed: Vec<bool>,
    /// Mesh colliders the host deformed for the next frame, by id.
    deformed: Vec<bool>,
    /// The guides' pose (root-local shapes) for the next frame.
    guide_pose: Option<Vec<Vec<Vector3<f32>>>>,
    /// The sim weight for the next frame, instead of the scene's curve.
    sim_weight: Option<f32>,
    /// The scalp's body-space vertices for the next frame, when the host set the scalp: the
    /// deformed vertices, or `None` for a rigid transform.
    scalp_vertices: Option<Option<Vec<Vector3<f32>>>>,
    /// Body-space vertices the host gave deformed mesh colliders for the next frame, by id.
    collider_vertices: Vec<Option<Vec<Vector3<f32>>>>,
}

/// What caches a session writes carry beside the hair ([`hair_cache::rig`]): the rig, and the
/// deformed scalp's and colliders' body-space vertices at the current frame.
#[derive(Debug, Clone)]
struct RigTrack {
    rig: CacheRig,
    deformed: Deformed,
}

/// The body-space vertices (m) of the deformed scalp and colliders at the current frame.
#[derive(Debug, Clone, Default)]
struct Deformed {
    /// The deformed scalp (`None`: the rest mesh, moved rigidly).
    scalp: Option<Vec<Vector3<f32>>>,
    /// Each rig collider's deformed vertices (`None`: its own mesh).
    colliders: Vec<Option<Vec<Vector3<f32>>>>,
}

/// Animated guides of a session: the animation and its scratch.
#[derive(Debug, Clone)]
struct Guides {
    animation: GuideAnimation,
    /// Workspace of the re-interpolation, kept between frames.
    scratch: crate::animated_guides::PoseScratch,
    /// Work of the last frame's re-interpolation (blend operations and points written).
    work: u64,
    /// Wall-clock time of the last frame's re-interpolation.
    time: std::time::Duration,
}

/// A copy of a session's state at one frame, for scrubbing ([`Session::snapshot`]).
#[derive(Debug, Clone)]
pub struct Snapshot {
    frame: u32,
    positions: Vec<Vector3<f32>>,
    velocities: Vec<Vector3<f32>>,
    solver: StrandSolverState,
    colliders: Colliders,
    scalp: Scalp,
    /// Animated rest shapes and rest directions, with animated guides.
    rest: Option<(Vec<Vector3<f32>>, Vec<RestDirection>)>,
    /// The deformed scalp's and colliders' vertices that caches record.
    rig: Deformed,
}

impl Snapshot {
    /// The frame the snapshot holds.
    pub fn frame(&self) -> u32 {
        self.frame
    }
}

/// A simulation a host drives frame by frame. See the module docs.
pub struct Session {
    strands: StrandSet,
    solver: StrandSolver,
    colliders: Colliders,
    scalp: Scalp,
    /// The scalp mesh at rest in its body space (vertex order of deformed scalps), if any.
    rest_scalp: Option<TriMesh>,
    /// The scalp collider, if the scalp collides with its hair.
    scalp_collider: Option<ColliderId>,
    fps: f32,
    animation: Option<SceneAnimation>,
    /// Animated guides, for sessions of guided scenes.
    guides: Option<Guides>,
    pending: Pending,
    /// What caches record beside the hair.
    rig: RigTrack,
    pool: Option<Arc<rayon::ThreadPool>>,
    recorder: Option<CacheWriter>,
    /// Time spent writing recorded frames.
    cache_time: std::time::Duration,
    failed: Option<(u32, String)>,
}

impl std::fmt::Debug for Session {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Session")
            .field("frame", &self.frame())
            .field("strands", &self.strands.len())
            .field("points", &self.strands.point_count())
            .field("model", &self.solver.model())
            .field("colliders", &self.colliders.len())
            .finish_non_exhaustive()
    }
}

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
            Error::Scene(crate::scene::SceneError {
                file: origin.clone(),
                message: sim.collider_message(&e),
            })
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

    /// Runs steps on `pool` (a DCC sizes it so it is not oversubscribed); without one, steps
    /// run on rayon's global pool. Results do not depend on the pool's size.
    pub fn set_thread_pool(&mut self, pool: Arc<rayon::ThreadPool>) {
        self.pool = Some(pool);
    }

    /// Frame number of the current state.
    pub fn frame(&self) -> u32 {
        self.solver.frame()
    }

    /// Frames per second (a step advances 1/fps s).
    pub fn fps(&self) -> f32 {
        self.fps
    }

    /// The strands (positions, velocities, layout, rest data).
    pub fn strands(&self) -> &StrandSet {
        &self.strands
    }

    /// The strand solver.
    pub fn solver(&self) -> &StrandSolver {
        &self.solver
    }

    /// The colliders (poses, settings).
    pub fn colliders(&self) -> &Colliders {
        &self.colliders
    }

    /// The scalp mesh at rest in its body space (the vertex order of
    /// [`Session::set_scalp_vertices`]), if the scalp has a mesh.
    pub fn rest_scalp(&self) -> Option<&TriMesh> {
        self.rest_scalp.as_ref()
    }

    /// The scalp of the current state.
    pub fn scalp(&self) -> &Scalp {
        &self.scalp
    }

    /// Positions of every point, m, strand after strand (see [`Session::strand_offsets`]),
    /// borrowed without a copy.
    pub fn positions(&self) -> &[[f32; 3]] {
        cast_slice(&self.strands.positions)
    }

    /// Velocities of every point, m/s, in the order of [`Session::positions`].
    pub fn velocities(&self) -> &[[f32; 3]] {
        cast_slice(&self.strands.velocities)
    }

    /// Strand `s`'s points are `offsets[s]..offsets[s + 1]` (strands + 1 entries).
    pub fn strand_offsets(&self) -> &[u32] {
        self.strands.offsets()
    }

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

    /// Advances one frame with what the host set (and the scene's keyframes for the rest);
    /// writes the frame to the cache being recorded, if any.
    pub fn step(&mut self) -> Result<FrameReport> {
        let report = self.advance()?;
        self.write_frame()?;
        Ok(report)
    }

    /// [`Session::step`], then `beside` on the new frame, run at the same time as the frame is
    /// written to the cache being recorded (encoding and writing keep one thread busy): a host
    /// that inspects every frame — the quality report of `hairsys simulate` — pays only for
    /// what outlasts the write. `beside` runs on the session's thread pool. Returns the frame's
    /// report, what `beside` returned and how much longer than the write it took (zero when it
    /// finished first): what it added to the frame's time.
    pub fn step_with<R: Send>(
        &mut self,
        beside: impl FnOnce(&FrameView) -> R + Send,
    ) -> Result<(FrameReport, R, std::time::Duration)> {
        let report = self.advance()?;
        let mut recorder = self.recorder.take();
        let state = recorder.as_ref().map(|_| self.rig_frame());
        let view = FrameView {
            frame: self.frame(),
            strands: &self.strands,
            colliders: &self.colliders,
            roots: self.solver.roots(),
        };
        let start = std::time::Instant::now();
        let both = || {
            rayon::join(
                || {
                    let t = std::time::Instant::now();
                    let written = recorder
                        .as_mut()
                        .zip(state.as_ref())
                        .map(|(w, state)| record_frame(w, view.frame, view.strands, state));
                    (written, t.elapsed())
                },
                || beside(&view),
            )
        };
        let ((written, took), result) = match &self.pool {
            Some(pool) => pool.install(both),
            None => both(),
        };
        let added = start.elapsed().saturating_sub(took);
        self.recorder = recorder;
        if let Some(written) = written {
            self.cache_time += took;
            written?;
        }
        Ok((report, result, added))
    }

    /// Writes the current frame to the cache being recorded, if any.
    fn write_frame(&mut self) -> Result<()> {
        let frame = self.frame();
        if self.recorder.is_none() {
            return Ok(());
        }
        let t = std::time::Instant::now();
        let state = self.rig_frame();
        if let Some(w) = &mut self.recorder {
            record_frame(w, frame, &self.strands, &state)?;
        }
        self.cache_time += t.elapsed();
        Ok(())
    }

    /// The scalp and the colliders at the current frame, as caches record them.
    fn rig_frame(&self) -> RigFrame {
        RigFrame {
            scalp_body: self.scalp.body,
            scalp_vertices: self.rig.deformed.scalp.clone(),
            colliders: self
                .rig
                .deformed
                .colliders
                .iter()
                .enumerate()
                .map(|(i, vertices)| ColliderState {
                    pose: self
                        .colliders
                        .pose(ColliderId(i as u32))
                        .unwrap_or_else(Isometry3::identity),
                    vertices: vertices.clone(),
                })
                .collect(),
        }
    }

    /// Solves one frame (see [`Session::step`]) without writing it.
    fn advance(&mut self) -> Result<FrameReport> {
        if let Some((frame, cause)) = &self.failed {
            return Err(Error::Failed {
                frame: *frame,
                cause: cause.clone(),
            });
        }
        let frame = self.frame() + 1;
        let pending = std::mem::take(&mut self.pending);
        let scalp = match (pending.scalp, &self.animation) {
            (Some(s), _) => s,
            (None, Some(a)) => a.sim.scalp_at(frame as f32),
            (None, None) => self.scalp.clone(),
        };
        if let Some(a) = &self.animation {
            for (i, c) in a.sim.colliders.iter().enumerate() {
                let id = ColliderId(i as u32);
                if !pending.posed.get(i).copied().unwrap_or(false) {
                    self.colliders
                        .set_pose(id, c.motion.at(frame as f32))
                        .map_err(|e| Error::Scene(a.scene_error(&e)))?;
                }
                // A deforming collider of the scene (USD, OBJ sequence) takes the frame's
                // vertices unless the host deformed it.
                if let (Some(anim), false) = (
                    &c.animation,
                    pending.deformed.get(i).copied().unwrap_or(false),
                ) {
                    self.colliders
                        .set_vertices(id, &anim.vertices_at(frame as f32))
                        .map_err(|e| Error::Scene(a.scene_error(&e)))?;
                }
            }
        }
        let blend = self.pose_guides(frame, pending.guide_pose, pending.sim_weight);
        let (solver, strands, colliders) =
            (&mut self.solver, &mut self.strands, &mut self.colliders);
        let mut step = || solver.step_frame(strands, &scalp, Some(colliders));
        let result = match &self.pool {
            Some(pool) => pool.install(step),
            None => step(),
        };
        let report = match result {
            Ok(r) => r,
            Err(source) => {
                self.failed = Some((frame, source.to_string()));
                return Err(self.solver_error(source));
            }
        };
        self.scalp = scalp;
        self.track_rig(frame, pending.scalp_vertices, pending.collider_vertices);
        if let (Some((before, weights)), Some(g)) = (blend, &self.guides) {
            g.animation.blend_onto(
                &mut self.strands,
                self.solver.roots(),
                &before,
                &weights,
                self.fps,
            );
        }
        Ok(report)
    }

    /// After stepping to `frame`: the deformed scalp's and colliders' vertices caches record,
    /// from what the host set (`scalp`, `colliders`) or else the scene's keyframes; what
    /// neither sets stays as it was.
    fn track_rig(
        &mut self,
        frame: u32,
        scalp: Option<Option<Vec<Vector3<f32>>>>,
        colliders: Vec<Option<Vec<Vector3<f32>>>>,
    ) {
        let sim = self.animation.as_ref().map(|a| &a.sim);
        match (scalp, sim) {
            (Some(v), _) => self.rig.deformed.scalp = v,
            (None, Some(sim)) => self.rig.deformed.scalp = sim.scalp_vertices_at(frame as f32),
            (None, None) => {}
        }
        for (i, slot) in self.rig.deformed.colliders.iter_mut().enumerate() {
            let keyed = sim
                .and_then(|s| s.colliders.get(i))
                .and_then(|c| c.animation.as_ref());
            match (colliders.get(i).cloned().flatten(), keyed) {
                (Some(v), _) => *slot = Some(v),
                (None, Some(a)) => *slot = Some(a.vertices_at(frame as f32)),
                (None, None) => {}
            }
        }
    }

    /// Before stepping to `frame`: the animated positions of the frame before, when any hair
    /// will be blended onto the guides after the step, with each hair's weight; then the sim
    /// hairs' rest shapes set to the host's `pose` or the scene's keyed pose at `frame`.
    #[allow(clippy::type_complexity)]
    fn pose_guides(
        &mut self,
        frame: u32,
        pose: Option<Vec<Vec<Vector3<f32>>>>,
        weight: Option<f32>,
    ) -> Option<(Vec<Vector3<f32>>, Vec<f32>)> {
        let g = self.guides.as_mut()?;
        let weights = g.animation.weights(frame as f32, weight);
        let blend = weights.iter().any(|&w| w > 0.0).then(|| {
            let before = g
                .animation
                .animated_positions(&self.strands, self.solver.roots());
            (before, weights)
        });
        let t = std::time::Instant::now();
        g.work = 0;
        if let Some(pose) = pose.or_else(|| g.animation.pose_at(frame as f32)) {
            g.work = g
                .animation
                .apply_pose(&pose, &mut self.strands, &mut g.scratch);
        }
        g.time = t.elapsed();
        blend
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
            .map_err(|m| Error::argument("points", m))?;
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

    fn solver_error(&self, source: HairError) -> Error {
        let scene = match &self.animation {
            Some(a) => a.origin.clone(),
            None => "session".into(),
        };
        Error::Solver { scene, source }
    }

    /// A copy of the state at the current frame (see the module docs).
    pub fn snapshot(&self) -> Snapshot {
        Snapshot {
            frame: self.frame(),
            positions: self.strands.positions.clone(),
            velocities: self.strands.velocities.clone(),
            solver: self.solver.snapshot_state(),
            colliders: self.colliders.clone(),
            scalp: self.scalp.clone(),
            rest: self.guides.as_ref().map(|_| {
                (
                    self.strands.rest_local().to_vec(),
                    self.strands.bend_rest().to_vec(),
                )
            }),
            rig: self.rig.deformed.clone(),
        }
    }

    /// Puts the session back in the state of `snapshot` (taken from this session) and clears
    /// a failure. Refused while a cache is being recorded (its frames must increase) and for a
    /// snapshot of other strands.
    pub fn restore(&mut self, snapshot: &Snapshot) -> Result<()> {
        if self.recorder.is_some() {
            return Err(Error::argument(
                "snapshot",
                "cannot go back in time while recording a cache: finish the cache first",
            ));
        }
        if snapshot.positions.len() != self.strands.point_count()
            || snapshot.solver.roots().len() != self.strands.len()
        {
            return Err(Error::argument(
                "snapshot",
                format!(
                    "holds {} points of {} strands, this session {} of {}: restore a snapshot of \
                     this session",
                    snapshot.positions.len(),
                    snapshot.solver.roots().len(),
                    self.strands.point_count(),
                    self.strands.len()
                ),
            ));
        }
        self.solver
            .restore_state(&snapshot.solver)
            .map_err(|e| Error::argument("snapshot", e.to_string()))?;
        self.strands.positions.clone_from(&snapshot.positions);
        self.strands.velocities.clone_from(&snapshot.velocities);
        self.colliders = snapshot.colliders.clone();
        self.scalp = snapshot.scalp.clone();
        self.rig.deformed.clone_from(&snapshot.rig);
        if let Some((rest, bend)) = &snapshot.rest {
            self.strands.rest_local_mut().copy_from_slice(rest);
            self.strands.bend_rest_mut().copy_from_slice(bend);
        }
        self.pending = Pending::default();
        self.failed = None;
        Ok(())
    }

    /// Starts recording to the MCAP cache at `path` (written as `path.partial`, renamed by
    /// [`Session::finish_recording`]): the current frame now, then every step.
    ///
    /// A cache names the scene that made it by a hash (`--resume` compares it). A session a host
    /// assembled without a scene file ([`Session::from_groom`]) is named by
    /// what it starts from instead: SHA-256 of the strand layout (offsets, rest lengths, radii),
    /// the current positions and velocities, the fps and the frame number.
    pub fn record(&mut self, path: &Path, options: WriterOptions) -> Result<()> {
        let mut header = self.cache_header();
        let layout = CacheLayout::of(&self.strands);
        if header.scene_hash.is_empty() {
            header.scene_hash = self.state_hash(&layout);
        }
        let writer = CacheWriter::create(path, &header, &layout, options)?;
        self.record_into(writer)
    }

    /// SHA-256 (hex) of the layout and the current state (see [`Session::record`]).
    fn state_hash(&self, layout: &CacheLayout) -> String {
        let mut h = Sha256::new();
        for o in &layout.offsets {
            h.update(o.to_le_bytes());
        }
        for x in layout.rest_lengths.iter().chain(&layout.radii) {
            h.update(x.to_le_bytes());
        }
        for p in self.positions().iter().chain(self.velocities()) {
            for c in p {
                h.update(c.to_le_bytes());
            }
        }
        h.update(self.fps.to_le_bytes());
        h.update(self.frame().to_le_bytes());
        h.finalize().iter().map(|b| format!("{b:02x}")).collect()
    }

    /// Records into `writer` (already holding any earlier frames, e.g. those a resumed run
    /// takes over): the current frame now, then every step. A new cache gets the session's
    /// rig ([`hair_cache::rig`]), so outputs need nothing but the cache; a writer that already
    /// holds frames keeps whether it has one.
    pub fn record_into(&mut self, mut writer: CacheWriter) -> Result<()> {
        if self.recorder.is_some() {
            return Err(Error::argument(
                "cache",
                "this session is already recording a cache: finish it first",
            ));
        }
        if writer.frame_count() == 0 && !writer.has_rig() {
            writer.attach_rig(&self.rig.rig)?;
        }
        self.recorder = Some(writer);
        let written = self.write_frame();
        if written.is_err() {
            self.recorder = None;
        }
        written
    }

    /// The rig the caches of this session carry ([`hair_cache::rig`]).
    pub fn cache_rig(&self) -> &CacheRig {
        &self.rig.rig
    }

    /// Finishes the cache being recorded (index, summary, rename to its final name).
    pub fn finish_recording(&mut self) -> Result<CacheSummary> {
        match self.recorder.take() {
            Some(w) => Ok(w.finish()?),
            None => Err(Error::argument(
                "cache",
                "this session is not recording a cache",
            )),
        }
    }

    /// The header of a cache of this session: the fps and current frame, the scene (text and
    /// hash; empty for a session a host assembled) and the model's description.
    pub fn cache_header(&self) -> CacheHeader {
        let mut components = self.solver.components(&self.strands);
        if !self.colliders.is_empty() {
            components.insert(hair_core::Component::Contacts);
        }
        let mut extra = std::collections::BTreeMap::new();
        extra.insert("components".to_string(), components.names().join(","));
        extra.insert("substeps".to_string(), self.solver.substeps().to_string());
        extra.insert("model".to_string(), self.solver.model().name().to_string());
        if let Some(s) = self.solver.mass_spring() {
            extra.insert(
                "integrator".to_string(),
                format!("{:?}", s.settings().integrator),
            );
        }
        let (scene_toml, scene_hash) = match &self.animation {
            Some(a) => (a.source.text.clone(), a.source.hash.clone()),
            None => (String::new(), String::new()),
        };
        CacheHeader {
            fps: self.fps as f64,
            first_frame: self.frame(),
            scene_toml,
            scene_hash,
            extra,
        }
    }

    /// Wall-clock time spent writing the recorded frames so far (part of [`Session::step`]'s).
    pub fn cache_write_time(&self) -> std::time::Duration {
        self.cache_time
    }

    /// Root frames of the current state (one per strand).
    pub fn root_frames(&self) -> &[RootFrame] {
        self.solver.roots()
    }
}

/// One stepped frame of a [`Session`], borrowed for [`Session::step_with`].
pub struct FrameView<'a> {
    /// The frame number.
    pub frame: u32,
    /// The strands at the frame (positions m, velocities m/s).
    pub strands: &'a StrandSet,
    /// The colliders at the frame's pose.
    pub colliders: &'a Colliders,
    /// The strands' root frames at the frame.
    pub roots: &'a [RootFrame],
}

impl SceneAnimation {
    fn scene_error(&self, e: &HairError) -> crate::scene::SceneError {
        crate::scene::SceneError {
            file: self.origin.clone(),
            message: self.sim.collider_message(e),
        }
    }
}

/// Writes frame `frame` of `strands` into `writer`, with the rig's `state` when the cache has
/// a rig.
fn record_frame(
    writer: &mut CacheWriter,
    frame: u32,
    strands: &StrandSet,
    state: &RigFrame,
) -> std::result::Result<(), hair_cache::CacheError> {
    let (x, v) = (&strands.positions, &strands.velocities);
    if writer.has_rig() {
        writer.write_frame_with_rig(frame, x, v, state)
    } else {
        writer.write_frame(frame, x, v)
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
