//! The bench's cases: small scenes, each with **one physical truth** ([`crate::truth`]) that
//! every method is measured against.
//!
//! - **pendulum**: one 0.5 m link with a 10 g bob released at 40° from the vertical, undamped;
//!   truth: the rigid pendulum (analytic);
//! - **chain**: a 1 m hair in 20 segments pinned at both ends 0.8 m apart, released as a V, air
//!   drag 6/s so that it settles in 3 s; truth at the last frame: the discrete catenary
//!   (analytic). Bending is left out: the hair's bending length `(EI/μg)^{1/3}` is 5 mm against
//!   5 cm segments, and the catenary has none;
//! - **chain-rest**: the same chain started on its catenary: whatever moves is **shape drift at
//!   rest** (a model that sags further, or creeps, shows it); truth: the catenary at every
//!   sample;
//! - **cantilever**: a 5 cm hair in 10 segments held horizontally at its root and released under
//!   gravity (load parameter `μ g L³ / EI` ≈ 1: a large deflection), air drag 5/s, 2 s; truth:
//!   the converged rod;
//! - **curly**: a 15 cm hair coiled as a helix (radius 1 cm, 2.2 turns) in 16 segments, root
//!   held, released under gravity, air drag 5/s, 2 s: a case that needs twist
//!   ([`crate::curly`]); truth: the converged rod;
//! - **drape**: a 25 cm hair in 16 segments whose root is held just above a fixed 5 cm sphere,
//!   released horizontally: it falls and drapes over the sphere (frictionless), 2 s: a case that
//!   needs collision ([`crate::drape`]); truth: the converged rod with the same sphere;
//! - **head**: the built-in default scene's groom (64 strands, 16 with `quick`) with the head
//!   turned 80° and back within half a second, the scalp colliding with its hair
//!   (frictionless: the rod's contacts are); truth: the converged rod;
//! - **head-strips**: the same head and turn with seed 000's strips instead of hair (its edge
//!   strands are the simulated strands); truth: the converged rod on the same edge strands.
//!
//! Every hair case takes its material from one physical hair ([`crate::physical`]): a strand of
//! `n` hairs (1 for the chain, cantilever, curly and drape cases; the default scene's 1 g/m wisp
//! is 151) has `n` times one hair's mass, stretch and bending rigidity, mapped to each model's
//! parameters as that module documents. The mass-spring springs of a case are **soft** (the default scene's
//! stiffness as a fraction of its physical `EA/l`, [`crate::physical::soft_fraction`]); the
//! methods that run the physical `EA/l` instead take [`Case::physical_stretch`].
//!
//! The rod's cantilever under a tip moment is measured apart ([`crate::tip_moment`]): it needs a
//! load no scene can express.
//!
//! Each case is a [`Simulation`] built through the scene schema, so it is checked exactly like a
//! scene file, and lists the frames at which positions are compared.

use std::path::PathBuf;

use hair_core::{Scalp, TriMesh};
use nalgebra::{Isometry3, Point3};
use parry3d::math::Vector as GlamVector;
use parry3d::query::PointQuery;
use parry3d::shape::{TriMesh as ParryMesh, TriMeshFlags};

use hair_core::StrandModel;

use hairsys::build::Simulation;
use hairsys::scene::motion::MotionKey;
use hairsys::scene::strips::StripsSection;
use hairsys::scene::{ScalpCollider, SceneError, SceneFile};

use crate::analytic;
pub use crate::curly::curly;
pub use crate::drape::{drape, Ball};
use crate::physical::{soft_fraction, Hair};
use crate::truth::TruthKind;

/// One reference case.
pub struct Case {
    /// Short name (file names, tables).
    pub name: &'static str,
    /// What it is, in words.
    pub title: &'static str,
    /// The scene, at rest at its first frame.
    pub sim: Simulation,
    /// Frames at which positions are compared with the reference.
    pub samples: Vec<u32>,
    /// Energy scale `Σ m g L` (J): drifts are reported as fractions of it.
    pub energy_scale: f64,
    /// The closed scalp as a solid, to measure how deep hair points go into it (head case only).
    pub head: Option<Solid>,
    /// Hairs the simulated strands stand for, for the cost per represented hair (head cases
    /// only: a strand is one hair, a strip `hairs_per_strip`).
    pub represented_hairs: Option<u64>,
    /// What the case is measured against.
    pub truth: TruthKind,
    /// How many times the rod truth cuts each of the case's segments (see [`crate::truth`]).
    pub truth_subdivision: usize,
    /// Linear density of its strands, kg/m (to subdivide them for the rod truth).
    pub mass_per_length: f32,
    /// The physical stretch stiffness `EA/l` of its springs, N/m (for a pendulum's link, a
    /// link 100× stiffer than the case's springs).
    pub physical_stretch: f32,
    /// How to build the same physical strand at another segment count (cases on the segments
    /// axis, [`crate::segments`]; their rod truth is built this way too instead of cutting the
    /// case's segments). `None`: the case's strands are a fixed discretisation.
    pub resegment: Option<Resegment>,
    /// A fixed sphere the hair collides with, for the penetration measure (drape case).
    pub ball: Option<Ball>,
}

/// A case that can be built at any segment count: the same physical hair (length, mass per
/// length, material, shape) sampled with `segments` equal segments per strand.
#[derive(Clone, Copy)]
pub struct Resegment {
    /// Segments per strand of the case as charted (the truth's count is this times
    /// [`Case::truth_subdivision`]).
    pub segments: usize,
    /// Builds the case with the given segments per strand.
    pub build: fn(usize) -> Result<Case, CaseError>,
}

impl Case {
    /// Frames the case advances.
    pub fn frames(&self) -> u32 {
        self.sim.last_frame - self.sim.first_frame
    }
}

/// Why a bench case cannot be built.
#[derive(Debug, thiserror::Error)]
pub enum CaseError {
    /// The case's scene does not build.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The case's chain has no catenary across its span.
    #[error("<bench case {case}>: the chain does not reach across its span")]
    NoCatenary {
        /// The case.
        case: &'static str,
    },
    /// The case's scalp mesh cannot be used as a solid (to measure how deep hair enters it).
    #[error("{file}: the scalp mesh cannot be used as a solid: {source}")]
    Solid {
        /// The case's scene.
        file: String,
        /// Parry's error.
        source: parry3d::shape::TriMeshBuilderError,
    },
}

/// A closed mesh whose inside can be queried, in the scalp's rest pose.
pub struct Solid {
    mesh: ParryMesh,
}

impl Solid {
    /// Wraps a closed (oriented, manifold) mesh.
    fn new(mesh: &TriMesh) -> Result<Self, parry3d::shape::TriMeshBuilderError> {
        let vertices = mesh
            .positions()
            .iter()
            .map(|p| GlamVector::new(p.x, p.y, p.z))
            .collect();
        let mesh =
            ParryMesh::with_flags(vertices, mesh.triangles().to_vec(), TriMeshFlags::ORIENTED)?;
        Ok(Self { mesh })
    }

    /// Deepest point centre inside the solid posed by `scalp.body`, m (0 if none is inside).
    /// Points with zero inverse mass (roots, pins) are skipped: they sit on the surface.
    pub fn max_depth(
        &self,
        scalp: &Scalp,
        positions: &[nalgebra::Vector3<f32>],
        inv_mass: &[f32],
    ) -> f32 {
        let to_rest: Isometry3<f32> = scalp.body.inverse();
        positions
            .iter()
            .zip(inv_mass)
            .filter(|(_, &w)| w > 0.0)
            .map(|(p, _)| {
                let local = to_rest * Point3::from(*p);
                let local = GlamVector::new(local.x, local.y, local.z);
                let hit = self.mesh.project_local_point(local, false);
                if hit.is_inside {
                    (hit.point - local).length()
                } else {
                    0.0
                }
            })
            .fold(0.0, f32::max)
    }
}

/// Builds every case; `quick` makes the head case small and short.
pub fn all(quick: bool) -> Result<Vec<Case>, CaseError> {
    Ok(vec![
        pendulum()?,
        hanging_chain()?,
        chain_at_rest()?,
        cantilever()?,
        curly()?,
        drape()?,
        head_turn(quick)?,
        head_strips(quick)?,
    ])
}

pub(super) fn parse(name: &str, text: &str) -> Result<Simulation, SceneError> {
    SceneFile::parse(text, &format!("<bench case {name}>"), PathBuf::new())?.build()
}

pub(super) fn every(first: u32, last: u32, stride: u32) -> Vec<u32> {
    (first + stride..=last).step_by(stride as usize).collect()
}

fn energy_scale(sim: &Simulation) -> f64 {
    let g = sim.params.gravity().norm() as f64;
    (0..sim.strands.len())
        .map(|s| {
            let length: f64 = sim.strands.rest_lengths()[sim.strands.segments(s)]
                .iter()
                .map(|&l| l as f64)
                .sum();
            let mass: f64 = sim.strands.masses()[sim.strands.points(s)]
                .iter()
                .map(|&m| m as f64)
                .sum();
            mass * g * length
        })
        .sum()
}

/// Mass per length of strand 0 from its first free point's lumped mass, kg/m.
fn mass_per_length(sim: &Simulation) -> f32 {
    let l = sim.strands.rest_lengths();
    let m = sim.strands.masses();
    if l.len() < 2 || m.len() < 2 {
        return 0.0;
    }
    m[1] / (0.5 * (l[0] + l[1]))
}

/// Mean rest segment length over all strands, m.
fn mean_segment(sim: &Simulation) -> f64 {
    let l = sim.strands.rest_lengths();
    l.iter().map(|&x| x as f64).sum::<f64>() / l.len().max(1) as f64
}

/// Makes `sim` of `hair`: bending `EI/l̄³`, soft springs, the rod's material; returns the
/// physical stretch stiffness `EA/l̄`, N/m.
pub(super) fn of_hair(sim: &mut Simulation, hair: Hair, bending: bool) -> f32 {
    let l = mean_segment(sim);
    sim.params.bend_stiffness = if bending {
        hair.bend_stiffness(l) as f32
    } else {
        0.0
    };
    let physical = hair.stretch_stiffness(l);
    sim.params.stretch_stiffness = (physical * soft_fraction()) as f32;
    sim.rod = hair.rod(sim.rod);
    physical as f32
}

pub(super) fn case(
    name: &'static str,
    title: &'static str,
    sim: Simulation,
    samples: Vec<u32>,
    head: Option<Solid>,
    truth: TruthKind,
    physical_stretch: f32,
) -> Case {
    let energy_scale = energy_scale(&sim);
    Case {
        name,
        title,
        samples,
        energy_scale,
        represented_hairs: None,
        truth,
        truth_subdivision: if truth == TruthKind::Rod && head.is_none() {
            2
        } else {
            1
        },
        mass_per_length: mass_per_length(&sim),
        physical_stretch,
        head,
        resegment: None,
        ball: None,
        sim,
    }
}

/// An undamped pendulum: 0.5 m, 40° from the vertical, 10 g bob on a 100 N/m spring, 2 s.
pub fn pendulum() -> Result<Case, CaseError> {
    let (s, c) = 40f32.to_radians().sin_cos();
    let text = format!(
        r#"
[scene]
name = "bench pendulum"
fps = 24.0
frames = [0, 48]
[solver]
damping_iterations = 0
[physics]
stretch_stiffness = 100.0
bend_stiffness = 0.0
stretch_damping = 0.0
air_drag = 0.0
[[strands]]
points = [[0.0, 0.0, 0.0], [{}, 0.0, {}]]
masses = [0.0, 0.01]
"#,
        0.5 * s,
        -0.5 * c
    );
    let sim = parse("pendulum", &text)?;
    let stiff = 100.0 * sim.params.stretch_stiffness;
    let samples = every(sim.first_frame, sim.last_frame, 6);
    Ok(case(
        "pendulum",
        "pendulum, 0.5 m at 40°, 10 g bob, undamped, 2 s; truth: the rigid pendulum",
        sim,
        samples,
        None,
        TruthKind::Pendulum,
        stiff,
    ))
}

/// Links, length (m) and span (m) of the chain cases.
const CHAIN: (usize, f64, f64) = (20, 1.0, 0.8);

/// A chain of one hair between two pins, starting from `points`, over `frames` frames.
fn chain_sim(
    name: &str,
    points: &[[f64; 3]],
    frames: u32,
) -> Result<(Simulation, f32), SceneError> {
    let n = points.len() - 1;
    let points: Vec<String> = points
        .iter()
        .map(|p| format!("[{:.9}, {:.9}, {:.9}]", p[0], p[1], p[2]))
        .collect();
    let text = format!(
        r#"
[scene]
name = "bench {name}"
fps = 24.0
frames = [0, {frames}]
[physics]
stretch_damping = 20.0
air_drag = 6.0
[[strands]]
pinned = [{n}]
mass_per_length = {}
points = [{}]
"#,
        Hair::ONE.mass_per_length(),
        points.join(", ")
    );
    let mut sim = parse(name, &text)?;
    let physical = of_hair(&mut sim, Hair::ONE, false);
    Ok((sim, physical))
}

/// A hair of 1 m in 20 segments hung between pins 0.8 m apart, released as a V, air drag 6/s;
/// compared with its catenary at the end of 3 s.
pub fn hanging_chain() -> Result<Case, CaseError> {
    let (n, length, span) = CHAIN;
    let seg = length / n as f64;
    let dx = span / n as f64;
    let dz = (seg * seg - dx * dx).sqrt();
    let points: Vec<[f64; 3]> = (0..=n)
        .map(|i| {
            let down = if i <= n / 2 { i } else { n - i } as f64;
            [i as f64 * dx, 0.0, -down * dz]
        })
        .collect();
    let (sim, physical) = chain_sim("hanging chain", &points, 72)?;
    let samples = vec![sim.last_frame];
    Ok(case(
        "chain",
        "hanging chain: a 1 m hair in 20 segments between pins 0.8 m apart, released as a V, \
         at rest after 3 s; truth: the catenary",
        sim,
        samples,
        None,
        TruthKind::Catenary,
        physical,
    ))
}

/// The chain of [`hanging_chain`] started on its catenary, 2 s: its motion is drift at rest.
pub fn chain_at_rest() -> Result<Case, CaseError> {
    let (n, length, span) = CHAIN;
    let shape = analytic::discrete_catenary(n, length / n as f64, span)
        .ok_or(CaseError::NoCatenary { case: "chain-rest" })?;
    let points: Vec<[f64; 3]> = shape.iter().map(|p| [p.x, 0.0, p.z]).collect();
    let (sim, physical) = chain_sim("chain at rest", &points, 48)?;
    let samples = every(sim.first_frame, sim.last_frame, 6);
    Ok(case(
        "chain-rest",
        "the same chain started on its catenary, 2 s: shape drift at rest; truth: the catenary",
        sim,
        samples,
        None,
        TruthKind::Catenary,
        physical,
    ))
}

/// Segments of the cantilever case as charted.
const CANTILEVER_SEGMENTS: usize = 10;

/// A 5 cm hair in 10 segments held horizontally by its root frame and released under gravity,
/// air drag 5/s; 2 s.
pub fn cantilever() -> Result<Case, CaseError> {
    cantilever_at(CANTILEVER_SEGMENTS)
}

/// The cantilever of [`cantilever`] in `n` segments.
pub fn cantilever_at(n: usize) -> Result<Case, CaseError> {
    let length = 0.05;
    let points: Vec<[f64; 3]> = (0..=n)
        .map(|i| [length * i as f64 / n as f64, 0.0, 0.0])
        .collect();
    one_hair(
        OneHair {
            name: "cantilever",
            title: "cantilever: a 5 cm hair in 10 segments released horizontally under gravity, \
                    2 s; truth: the converged rod",
            air_drag: 5.0,
            radius: None,
            extra: String::new(),
        },
        &points,
        Resegment {
            segments: CANTILEVER_SEGMENTS,
            build: cantilever_at,
        },
    )
}

/// What sets one single-hair case apart from another (see [`one_hair`]).
pub(super) struct OneHair {
    /// Case name.
    pub name: &'static str,
    /// What it is, in words.
    pub title: &'static str,
    /// Air drag, 1/s.
    pub air_drag: f64,
    /// Hair radius, m (`None`: the scene default).
    pub radius: Option<f64>,
    /// Scene text appended after the strand (its colliders).
    pub extra: String,
}

/// One physical hair ([`Hair::ONE`], bending on) through `points` (m), its root frame held,
/// released under gravity over 2 s (frames 0–48 at 24 fps, stretch damping 50/s), compared with
/// the converged rod every 6 frames and buildable at any segment count (`resegment`): the
/// cantilever, curly and drape cases.
pub(super) fn one_hair(
    hair: OneHair,
    points: &[[f64; 3]],
    resegment: Resegment,
) -> Result<Case, CaseError> {
    let points: Vec<String> = points
        .iter()
        .map(|p| format!("[{:.9}, {:.9}, {:.9}]", p[0], p[1], p[2]))
        .collect();
    let radius = hair
        .radius
        .map_or(String::new(), |r| format!("radius = {r}\n"));
    let text = format!(
        r#"
[scene]
name = "bench {}"
fps = 24.0
frames = [0, 48]
[physics]
stretch_damping = 50.0
air_drag = {}
[[strands]]
mass_per_length = {}
{radius}points = [{}]
{}"#,
        hair.name,
        hair.air_drag,
        Hair::ONE.mass_per_length(),
        points.join(", "),
        hair.extra
    );
    let mut sim = parse(hair.name, &text)?;
    let physical = of_hair(&mut sim, Hair::ONE, true);
    let samples = every(sim.first_frame, sim.last_frame, 6);
    let mut case = case(
        hair.name,
        hair.title,
        sim,
        samples,
        None,
        TruthKind::Rod,
        physical,
    );
    case.resegment = Some(resegment);
    Ok(case)
}

/// The default scene's groom (its hair made of 151 physical hairs per strand, its solver
/// settings) with a fast head turn, 80° about the vertical and back in half a second, then half
/// a second to swing; the scalp collides with its hair, frictionless. 64 strands over 24 frames,
/// or 16 strands over 12 frames with `quick`.
pub fn head_turn(quick: bool) -> Result<Case, CaseError> {
    let mut case = turning_head(
        head_turn_file(quick),
        quick,
        "head",
        "default head scene's groom, head turned 80° and back in 0.5 s; truth: the converged rod",
    )?;
    case.represented_hairs = Some(case.sim.strands.len() as u64);
    // The groom's 16 segments do not resolve the physical wisp in this turn (the rod moves
    // 2–3 mm when they are halved): the truth runs on twice the segments, on smooth curves
    // through the groom's points (see `truth::smooth_rest`).
    case.truth_subdivision = 2;
    Ok(case)
}

/// The scene file of [`head_turn`] before its build: the default scene with 64 strands (16 with
/// `quick`), the fast turn, the frictionless collider, over frames 1–25 (1–13 with `quick`).
/// Its `[physics]` are still the default scene's: the case sets the physical hair's after the
/// build (copy `case.sim.params` into it to build the case's material).
pub fn head_turn_file(quick: bool) -> SceneFile {
    let mut file = SceneFile::builtin_default();
    file.origin = "<bench case head turn (the built-in default scene)>".into();
    let strands = if quick { 16 } else { 64 };
    if let Some(hair) = file.scene.hair.as_mut() {
        hair.count = strands;
    }
    turning_head_scene(&mut file, quick);
    file
}

/// The head turn of [`head_turn`] with seed 000's strips (the `[strips]` defaults: edge strands
/// of 0.2 m in 8 segments, 100 hairs per strip) instead of the default hair: at most 64 strips,
/// or 8 with `quick`, on every 4th scalp triangle. The strips keep their own spring settings;
/// the rod truth takes the physical hair of the edge strands' mass.
pub fn head_strips(quick: bool) -> Result<Case, CaseError> {
    let mut file = SceneFile::builtin_default();
    file.origin = "<bench case head strips (the built-in default scene with [strips])>".into();
    let scene = &mut file.scene;
    scene.hair = None;
    scene.guides = None;
    scene.sim_hairs = None;
    scene.strands.clear();
    scene.solver.model = StrandModel::Strips;
    let section = StripsSection {
        every: 4,
        max_strips: Some(if quick { 8 } else { 64 }),
        ..StripsSection::default()
    };
    let hairs_per_strip = section.hairs_per_strip as u64;
    scene.strips = Some(section);
    let mut case = turning_head(
        file,
        quick,
        "head-strips",
        "default head scene with strips instead of hair, the same turn; truth: the converged \
         rod on the edge strands",
    )?;
    case.represented_hairs = Some(case.sim.strands.len() as u64 / 2 * hairs_per_strip);
    Ok(case)
}

/// `file` over frames 1–24 (1–12 with `quick`) with the fast turn and the frictionless scalp
/// collider, made of the physical hair of its strands' mass per length.
fn turning_head(
    mut file: SceneFile,
    quick: bool,
    name: &'static str,
    title: &'static str,
) -> Result<Case, CaseError> {
    let strips = file.scene.solver.model == StrandModel::Strips;
    turning_head_scene(&mut file, quick);
    let mut sim = file.build()?;
    let hair = Hair {
        hairs: mass_per_length(&sim) as f64 / Hair::ONE.mass_per_length(),
    };
    let physical = if strips {
        // The strips keep their springs; only the truth's material follows the hair.
        sim.rod = hair.rod(sim.rod);
        hair.stretch_stiffness(mean_segment(&sim)) as f32
    } else {
        let soft = sim.params.stretch_stiffness;
        let physical = of_hair(&mut sim, hair, true);
        // The head keeps the default scene's springs: they are what "soft" stands for.
        sim.params.stretch_stiffness = soft;
        physical
    };
    let head = match sim.rest_mesh() {
        Some(mesh) => Some(Solid::new(mesh).map_err(|source| CaseError::Solid {
            file: file.origin.clone(),
            source,
        })?),
        None => None,
    };
    let samples = every(sim.first_frame, sim.last_frame, if quick { 2 } else { 3 });
    Ok(case(
        name,
        title,
        sim,
        samples,
        head,
        TruthKind::Rod,
        physical,
    ))
}

/// Sets `file` to the turn: frames 1–25 (1–13 with `quick`), 80° about the vertical and back in
/// half a second, the frictionless scalp collider, no strain limit, hair–hair or sag-free rest.
fn turning_head_scene(file: &mut SceneFile, quick: bool) {
    let scene = &mut file.scene;
    let last = if quick { 13 } else { 25 };
    scene.scene.frames = [1, last];
    let key = |frame: f32, yaw: f32| MotionKey {
        frame,
        translation: [0.0; 3],
        rotation_deg: [0.0, 0.0, yaw],
    };
    scene.scalp.motion.keys = vec![key(1.0, 0.0), key(7.0, 80.0), key(13.0, 0.0)];
    // Frictionless: the rod's contacts are, and every method meets the same contact law.
    scene.scalp.collider = Some(ScalpCollider {
        thickness: 0.0,
        friction: 0.0,
    });
    // The bench measures the models: the default scene's strain limit and hair–hair friction
    // correct positions and velocities by rules of their own, which set an error floor (0.75 mm
    // here) that no substep count lowers.
    scene.solver.max_strain = None;
    scene.hair_hair = None;
    // Every method starts from the same groom with its plain rest shape: sag-free rest data is
    // the mass-spring model's own (the rod and the strips have other energies).
    scene.solver.sag_free = false;
}
