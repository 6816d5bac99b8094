//! The reference cases of `hairsys bench`: small scenes whose motion is measured against the
//! same scene run at a very fine step.
//!
//! - **pendulum**: one 0.5 m segment released at 40° from the vertical, undamped (energy drift is
//!   meaningful here: the exact motion conserves energy);
//! - **hanging chain**: 20 segments, 1 m, pinned at both ends 0.8 m apart, released as a V and
//!   swinging towards its catenary (air drag 2/s: a chain of free joints is a multiple pendulum,
//!   chaotic when barely damped, and a chaotic case has no converged reference);
//! - **cantilever**: a stiff 0.2 m strand held horizontally at its root by the bending springs,
//!   released under gravity: it droops and rings down;
//! - **head turn**: the built-in default scene (its hair, physics and solver settings) with the
//!   head turned 80° and back within half a second, the scalp colliding with its own hair;
//! - **head strips**: the same head and turn with seed 000's strips instead of hair (its edge
//!   strands are the simulated strands), for the strip model against the mass-spring model on
//!   the same edges.
//!
//! The rod's cantilever under a tip moment is measured apart ([`super::tip_moment`]): it needs a
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

use hairsys::scene::motion::MotionKey;
use hairsys::scene::strips::StripsSection;
use hairsys::scene::{ScalpCollider, SceneError, SceneFile, Simulation};

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
}

impl Case {
    /// Frames the case advances.
    pub fn frames(&self) -> u32 {
        self.sim.last_frame - self.sim.first_frame
    }
}

/// A closed mesh whose inside can be queried, in the scalp's rest pose.
pub struct Solid {
    mesh: ParryMesh,
}

impl Solid {
    /// Wraps a closed (oriented, manifold) mesh.
    fn new(mesh: &TriMesh) -> Result<Self, String> {
        let vertices = mesh
            .positions()
            .iter()
            .map(|p| GlamVector::new(p.x, p.y, p.z))
            .collect();
        let mesh =
            ParryMesh::with_flags(vertices, mesh.triangles().to_vec(), TriMeshFlags::ORIENTED)
                .map_err(|e| format!("the scalp mesh cannot be used as a solid: {e}"))?;
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
pub fn all(quick: bool) -> Result<Vec<Case>, SceneError> {
    Ok(vec![
        pendulum()?,
        hanging_chain()?,
        cantilever()?,
        head_turn(quick)?,
        head_strips(quick)?,
    ])
}

fn parse(name: &str, text: &str) -> Result<Simulation, SceneError> {
    SceneFile::parse(text, &format!("<bench case {name}>"), PathBuf::new())?.build()
}

fn every(first: u32, last: u32, stride: u32) -> Vec<u32> {
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

fn case(
    name: &'static str,
    title: &'static str,
    sim: Simulation,
    stride: u32,
    head: Option<Solid>,
) -> Case {
    let samples = every(sim.first_frame, sim.last_frame, stride);
    let energy_scale = energy_scale(&sim);
    Case {
        name,
        title,
        sim,
        samples,
        energy_scale,
        head,
        represented_hairs: None,
    }
}

/// An undamped pendulum: 0.5 m, 40° from the vertical, 10 g bob on a 100 N/m spring, 2 s.
pub fn pendulum() -> Result<Case, SceneError> {
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
    Ok(case(
        "pendulum",
        "pendulum, 0.5 m at 40°, undamped, 2 s",
        sim,
        6,
        None,
    ))
}

/// A chain of 20 segments (1 m, 50 g/m, 400 N/m) hung between pins 0.8 m apart, released as a V,
/// damped (air drag 2/s); 2 s.
pub fn hanging_chain() -> Result<Case, SceneError> {
    let n = 20;
    let (span, length) = (0.8f64, 1.0f64);
    let seg = length / n as f64;
    let dx = span / n as f64;
    let dz = (seg * seg - dx * dx).sqrt();
    let points: Vec<String> = (0..=n)
        .map(|i| {
            let down = if i <= n / 2 { i } else { n - i } as f64;
            format!("[{:.6}, 0.0, {:.6}]", i as f64 * dx, -down * dz)
        })
        .collect();
    let text = format!(
        r#"
[scene]
name = "bench hanging chain"
fps = 24.0
frames = [0, 48]
[physics]
stretch_stiffness = 400.0
bend_stiffness = 0.0
stretch_damping = 20.0
air_drag = 2.0
[[strands]]
pinned = [{n}]
mass_per_length = 0.05
points = [{}]
"#,
        points.join(", ")
    );
    let sim = parse("hanging chain", &text)?;
    Ok(case(
        "chain",
        "hanging chain, 20 segments between pins, released as a V, 2 s",
        sim,
        6,
        None,
    ))
}

/// A stiff cantilever: 10 segments over 0.2 m (10 g/m), bending 5 N/m, stretch 100 N/m, held
/// horizontally by its root frame and released under gravity; 2 s.
pub fn cantilever() -> Result<Case, SceneError> {
    let n = 10;
    let points: Vec<String> = (0..=n)
        .map(|i| format!("[{:.6}, 0.0, 0.0]", 0.02 * i as f64))
        .collect();
    let text = format!(
        r#"
[scene]
name = "bench cantilever"
fps = 24.0
frames = [0, 48]
[physics]
stretch_stiffness = 100.0
bend_stiffness = 5.0
stretch_damping = 50.0
air_drag = 1.0
[[strands]]
mass_per_length = 0.01
points = [{}]
"#,
        points.join(", ")
    );
    let sim = parse("cantilever", &text)?;
    Ok(case(
        "cantilever",
        "stiff cantilever, 0.2 m, released horizontally under gravity, 2 s",
        sim,
        6,
        None,
    ))
}

/// The default scene (its hair, physics and solver) with a fast head turn, 80° about the vertical
/// and back in half a second, then half a second to swing; the scalp collides with its hair.
/// 256 strands over 24 frames, or 16 strands over 12 frames with `quick`.
pub fn head_turn(quick: bool) -> Result<Case, SceneError> {
    let mut file = SceneFile::builtin_default();
    file.origin = "<bench case head turn (the built-in default scene)>".into();
    let strands = if quick { 16 } else { 256 };
    if let Some(hair) = file.scene.hair.as_mut() {
        hair.count = strands;
    }
    let mut case = turning_head(
        file,
        quick,
        "head",
        "default head scene, head turned 80° and back in 0.5 s",
    )?;
    case.represented_hairs = Some(case.sim.strands.len() as u64);
    Ok(case)
}

/// The head turn of [`head_turn`] with seed 000's strips (the `[strips]` defaults: edge strands
/// of 0.2 m in 8 segments, 100 hairs per strip) instead of the default hair: at most 64 strips,
/// or 8 with `quick`, on every 4th scalp triangle.
pub fn head_strips(quick: bool) -> Result<Case, SceneError> {
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
        "default head scene with strips instead of hair, the same turn",
    )?;
    case.represented_hairs = Some(case.sim.strands.len() as u64 / 2 * hairs_per_strip);
    Ok(case)
}

/// `file` over frames 1–24 (1–12 with `quick`) with the fast turn and the scalp collider.
fn turning_head(
    mut file: SceneFile,
    quick: bool,
    name: &'static str,
    title: &'static str,
) -> Result<Case, SceneError> {
    let scene = &mut file.scene;
    let last = if quick { 13 } else { 25 };
    scene.scene.frames = [1, last];
    let key = |frame: f32, yaw: f32| MotionKey {
        frame,
        translation: [0.0; 3],
        rotation_deg: [0.0, 0.0, yaw],
    };
    scene.scalp.motion.keys = vec![key(1.0, 0.0), key(7.0, 80.0), key(13.0, 0.0)];
    scene.scalp.collider = Some(ScalpCollider {
        thickness: 0.0,
        friction: 0.3,
    });
    // The bench measures time integration: the default scene's strain limit and hair–hair
    // friction correct positions and velocities by rules of their own, which set an error floor
    // (0.75 mm here) that no substep count lowers.
    scene.solver.max_strain = None;
    scene.hair_hair = None;
    // Every method starts from the same groom with its plain rest shape: sag-free rest data is
    // the mass-spring model's own (the rod and the strips have other energies).
    scene.solver.sag_free = false;
    let sim = file.build()?;
    let head = match sim.rest_mesh() {
        Some(mesh) => Some(Solid::new(mesh).map_err(|message| SceneError {
            file: file.origin.clone(),
            message,
        })?),
        None => None,
    };
    let stride = if quick { 2 } else { 3 };
    Ok(case(name, title, sim, stride, head))
}
