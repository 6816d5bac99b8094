//! Helpers shared by the collision tests: the turning-head scene, hanging strands, a collider run
//! from a scene's first frame, the free (non-pinned) points of a strand set, and the independent
//! inside/outside reference, a head mesh queried with parry.

use std::path::PathBuf;

use hair_core::{Colliders, FrameReport, Scalp, StrandSet, TriMesh};
use hairsys::build::Simulation;
use hairsys::scene::SceneFile;
use nalgebra::{Isometry3, Point3, Vector3};
use parry3d::math::Vector;
use parry3d::query::PointQuery;
use parry3d::shape::{TriMesh as ParryMesh, TriMeshFlags};
use rayon::prelude::*;

use super::solver_at_first_frame;

/// `[physics]` of the mass-spring collision scenes: stretch stiffness 40, bending 0.5, stretch
/// damping 1000 and air drag 2, in the scene file's units.
pub const SPRING_PHYSICS: &str = "stretch_stiffness = 40.0
bend_stiffness = 0.5
stretch_damping = 1000.0
air_drag = 2.0";

/// The turning-head scene, frames 1 to `last_frame` at 24 fps: the built-in head as its own
/// collider (thickness 0, friction 0.3) turning from rest about the vertical at 10 rad/s
/// (572.96° over frames 1 to 25, 24° per frame), with `count` strands of 0.2 m (±20 %, 12
/// segments, radius 2 mm, 1 g/m, seed 3) grown over the crown and back (up to 95° from
/// (0, 0.3, 1)) that fall onto it and are flung around it. `physics` is the body of the
/// `[physics]` table.
pub fn turning_head_scene(name: &str, last_frame: u32, count: u32, physics: &str) -> SceneFile {
    let text = format!(
        r#"
[scene]
name = "{name}"
fps = 24.0
frames = [1, {last_frame}]

[physics]
{physics}

[scalp.mesh]
kind = "builtin-head"

[scalp.collider]
thickness = 0.0
friction = 0.3

[scalp.motion]
interpolation = "linear"
keys = [
    {{ frame = 1,  rotation_deg = [0.0, 0.0, 0.0] }},
    {{ frame = 25, rotation_deg = [0.0, 0.0, 572.9578] }},
]

[hair]
count = {count}
length = 0.2
segments = 12
seed = 3
radius = 0.002
mass_per_length = 0.001
length_variation = 0.2
region = {{ direction = [0.0, 0.3, 1.0], max_angle_deg = 95.0 }}
"#
    );
    SceneFile::parse(&text, "turning_head.toml", PathBuf::from(".")).unwrap()
}

/// A `[[strands]]` table: a strand hanging straight down from (`x`, `y`, 0) m, 16 segments of
/// 25 mm (0.4 m), radius 2 mm.
pub fn hanging_strand(x: f32, y: f32) -> String {
    let points: Vec<String> = (0..=16)
        .map(|i| format!("[{x}, {y}, {}]", -0.025 * i as f32))
        .collect();
    format!(
        "\n[[strands]]\npoints = [{}]\nradius = 0.002\n",
        points.join(", ")
    )
}

/// Runs `sim` with a fresh mass-spring solver and a fresh collider set from its first frame to
/// `last`, posing the scene's colliders at every frame, and calls `each(frame, sim, scalp,
/// report)` after each frame is stepped.
pub fn run_with_colliders(
    sim: &mut Simulation,
    last: u32,
    each: impl FnMut(u32, &Simulation, &Scalp, FrameReport),
) {
    let mut solver = solver_at_first_frame(sim);
    run_posed(
        sim,
        last,
        |strands, scalp, colliders| {
            solver
                .step_frame_with_colliders(strands, scalp, colliders)
                .unwrap()
        },
        each,
    );
}

/// Runs `sim` from its first frame to `last` with a fresh collider set: at every frame poses the
/// scene's colliders, steps the strands with `step(strands, scalp, colliders)` (any solver) and
/// calls `each(frame, sim, scalp, what step returned)`.
pub fn run_posed<R>(
    sim: &mut Simulation,
    last: u32,
    mut step: impl FnMut(&mut StrandSet, &Scalp, &mut Colliders) -> R,
    mut each: impl FnMut(u32, &Simulation, &Scalp, R),
) {
    let first = sim.first_frame;
    let mut colliders = sim.colliders_at(first as f32).unwrap();
    for frame in first + 1..=last {
        let scalp = sim.scalp_at(frame as f32);
        sim.pose_colliders(&mut colliders, frame as f32).unwrap();
        let report = step(&mut sim.strands, &scalp, &mut colliders);
        each(frame, sim, &scalp, report);
    }
}

/// Positions (m) of the points of `strands` that move freely (inverse mass > 0, not pinned).
pub fn free_points(strands: &StrandSet) -> impl Iterator<Item = &Vector3<f32>> {
    strands
        .positions
        .iter()
        .zip(strands.inverse_masses())
        .filter(|(_, &w)| w > 0.0)
        .map(|(x, _)| x)
}

/// Where a set of points lies relative to a head: the smallest signed distance (m, negative
/// inside) and how many points are inside.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gap {
    /// Smallest signed distance of a point centre to the surface, m (+∞ for no point).
    pub smallest: f32,
    /// Points inside the head.
    pub inside: usize,
}

impl Gap {
    /// No point at all: smallest distance +∞, none inside.
    pub const NONE: Gap = Gap {
        smallest: f32::INFINITY,
        inside: 0,
    };

    /// Both sets of points together.
    pub fn merge(self, other: Gap) -> Gap {
        Gap {
            smallest: self.smallest.min(other.smallest),
            inside: self.inside + other.inside,
        }
    }
}

/// The independent reference of the collision tests: a closed head mesh as an oriented parry
/// `TriMesh`, whose point projection gives each point's distance and, by the pseudo-normal test,
/// whether it is inside. Points are queried in the head's rest frame.
pub struct ParryHead {
    /// The head in its rest frame, m.
    pub mesh: ParryMesh,
}

impl ParryHead {
    /// The reference for `head` (its rest pose, m).
    pub fn new(head: &TriMesh) -> Self {
        let vertices = head.positions().iter().map(to_parry).collect();
        let mesh =
            ParryMesh::with_flags(vertices, head.triangles().to_vec(), TriMeshFlags::ORIENTED)
                .unwrap();
        Self { mesh }
    }

    /// The gap of one world point `x` (m) to the head whose inverse pose is `inverse`.
    fn point_gap(&self, inverse: &Isometry3<f32>, x: &Vector3<f32>) -> Gap {
        let local = to_parry(&(inverse * Point3::from(*x)).coords);
        let proj = self.mesh.project_local_point(local, false);
        let d = (local - proj.point).length();
        Gap {
            smallest: if proj.is_inside { -d } else { d },
            inside: usize::from(proj.is_inside),
        }
    }

    /// The gap of world `points` (m) to the head posed at `body`.
    pub fn gap(&self, body: &Isometry3<f32>, points: &[Vector3<f32>]) -> Gap {
        let inverse = body.inverse();
        points
            .par_iter()
            .map(|x| self.point_gap(&inverse, x))
            .reduce(|| Gap::NONE, Gap::merge)
    }

    /// The gap of the free points (inverse mass > 0) of `strands` to the head posed at `body`.
    pub fn free_point_gap(&self, body: &Isometry3<f32>, strands: &StrandSet) -> Gap {
        let inverse = body.inverse();
        strands
            .positions
            .par_iter()
            .zip(strands.inverse_masses())
            .filter(|(_, &w)| w > 0.0)
            .map(|(x, _)| self.point_gap(&inverse, x))
            .reduce(|| Gap::NONE, Gap::merge)
    }
}

/// A nalgebra vector as a parry one.
fn to_parry(v: &Vector3<f32>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}
