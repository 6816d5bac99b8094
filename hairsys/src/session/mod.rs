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
//! ([`StrandSolverState`](hair_core::StrandSolverState): frame number, root frames, the rod's
//! twist, the parameters a host changes between frames), the colliders and the scalp; the
//! solver's workspace (contact lists,
//! the hair–hair grid) is scratch rebuilt every step. [`Session::snapshot`] copies the state and
//! [`Session::restore`] puts it back, for scrubbing; stepping on from a restored snapshot gives
//! the same bits as stepping on from where it was taken.
//!
//! # Threads and failures
//! Steps run on the rayon pool the host gives ([`Session::set_thread_pool`]; a DCC sizes it so
//! it is not oversubscribed), else on rayon's global pool; the result does not depend on the
//! thread count. A step that fails (blow-up, bad collider) leaves the session failed: the next
//! step returns [`Error::Failed`](crate::Error::Failed) until a snapshot is restored. Nothing in a session panics on
//! host input; bad arguments are [`Error::Argument`](crate::Error::Argument)s naming the argument and what is expected.

use std::sync::Arc;

use bytemuck::cast_slice;
use hair_cache::{CacheRig, CacheWriter};
use hair_core::{
    ColliderId, Colliders, HairError, RootFrame, Scalp, StrandSet, StrandSolver, TriMesh,
};
use nalgebra::Vector3;

use crate::build::Simulation;
use crate::rig::animated_guides::GuideAnimation;

mod assemble;
mod children;
mod input;
mod record;
mod regions;
mod snapshot;
mod step;

pub use snapshot::Snapshot;

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
    scratch: crate::rig::animated_guides::PoseScratch,
    /// Work of the last frame's re-interpolation (blend operations and points written).
    work: u64,
    /// Wall-clock time of the last frame's re-interpolation.
    time: std::time::Duration,
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
    pool: Option<Arc<hair_par::ThreadPool>>,
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
    /// Runs steps on `pool` (a DCC sizes it so it is not oversubscribed); without one, steps
    /// run on rayon's global pool. Results do not depend on the pool's size.
    pub fn set_thread_pool(&mut self, pool: Arc<hair_par::ThreadPool>) {
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
    fn scene_error(&self, e: HairError) -> crate::scene::SceneError {
        crate::scene::SceneError::new(self.origin.clone(), self.sim.collider_problem(e))
    }
}
