//! Contacts cost nothing when they do not act: stepping with an empty collider set, or with a
//! collider that no hair ever comes near, gives bit-identical strands to stepping without
//! colliders (the kernel's contact pass runs only for groups with a contact, and the moving head
//! with its hair is otherwise untouched).

mod common;

use common::solver_at_first_frame;
use hair_core::{Collider, Colliders};
use hairsys::build::Simulation;
use hairsys::scene::SceneFile;
use nalgebra::Isometry3;

const SCENE: &str = r#"
[scene]
frames = [1, 8]

[scalp.mesh]
kind = "builtin-head"

[scalp.motion]
keys = [
    { frame = 1, rotation_deg = [0.0, 0.0, 0.0] },
    { frame = 8, rotation_deg = [20.0, 0.0, 60.0] },
]

[hair]
count = 100
length = 0.2
segments = 10
seed = 5
length_variation = 0.3
"#;

/// Runs the scene; `colliders` decides how each frame is stepped. Returns positions and
/// velocities, and the point contacts found.
fn run(colliders: Option<Colliders>) -> (Vec<[u32; 6]>, u64) {
    let scene = SceneFile::parse(SCENE, "off.toml", ".".into()).unwrap();
    let mut sim: Simulation = scene.build().unwrap();
    let first = sim.first_frame;
    let mut solver = solver_at_first_frame(&sim);
    let mut set = colliders;
    let mut contacts = 0;
    for frame in first + 1..=sim.last_frame {
        let scalp = sim.scalp_at(frame as f32);
        match set.as_mut() {
            Some(c) => {
                contacts += solver
                    .step_frame_with_colliders(&mut sim.strands, &scalp, c)
                    .unwrap()
                    .contact_points;
            }
            None => {
                solver.step_frame(&mut sim.strands, &scalp).unwrap();
            }
        }
    }
    let bits = sim
        .strands
        .positions
        .iter()
        .zip(&sim.strands.velocities)
        .map(|(x, v)| {
            [
                x.x.to_bits(),
                x.y.to_bits(),
                x.z.to_bits(),
                v.x.to_bits(),
                v.y.to_bits(),
                v.z.to_bits(),
            ]
        })
        .collect();
    (bits, contacts)
}

#[test]
fn empty_or_untouched_colliders_leave_the_result_bit_identical() {
    let (plain, _) = run(None);
    let (empty, none) = run(Some(Colliders::new()));
    let mut far = Colliders::new();
    far.insert(
        Collider::capsule(0.5, 0.2).with_friction(0.5),
        Isometry3::translation(5.0, 0.0, 0.0),
    )
    .unwrap();
    let (untouched, found) = run(Some(far));
    println!(
        "{} points × 7 frames: empty set {} contacts, far capsule {} contacts; bit-identical: {} / {}",
        plain.len(),
        none,
        found,
        plain == empty,
        plain == untouched
    );
    assert_eq!(none, 0);
    assert_eq!(found, 0);
    assert!(plain == empty, "an empty collider set changed the result");
    assert!(
        plain == untouched,
        "a collider nobody touches changed the result"
    );
}
