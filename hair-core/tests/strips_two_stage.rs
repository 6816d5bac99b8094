//! The strip model's two-stage collision: edge strands far from the head's bounding sphere skip
//! the contact pipeline; strands falling onto the head run it and end every frame outside.

use hair_core::model::strips::{HeadShape, StripSet, StripSettings, StripSolver};
use hair_core::{
    Anchor, Collider, Colliders, HairParams, RootFrame, Scalp, SolverSettings, StrandInput, TriMesh,
};
use nalgebra::{Isometry3, UnitQuaternion, Vector3};

/// A closed cube of half-size `h` centred at `c`, outward-facing triangles.
fn cube(c: Vector3<f32>, h: f32) -> TriMesh {
    let v = (0..8)
        .map(|i| {
            let s = |bit: u32| if i & bit != 0 { h } else { -h };
            c + Vector3::new(s(1), s(2), s(4))
        })
        .collect();
    let t = vec![
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    TriMesh::new(v, t).unwrap()
}

fn strips() -> StripSet {
    let edge = |y: f32| {
        let rest = (0..=8)
            .map(|i| Vector3::new(0.0, 0.0, 0.025 * i as f32))
            .collect();
        let anchor = Anchor::Body(RootFrame {
            origin: Vector3::new(0.0, y, 0.0),
            rotation: UnitQuaternion::rotation_between(&Vector3::z(), &Vector3::x()).unwrap(),
        });
        StrandInput::uniform(anchor, rest, 1e-3, 2e-3, 0.0, 0.0)
    };
    StripSet::from_pairs(vec![(edge(0.0), edge(0.02))], 100, &Scalp::fixed()).unwrap()
}

/// Runs 24 frames against `head`; returns (frames near the head, contact points, smallest
/// signed distance of a free point to the head at a frame end).
fn run(head: TriMesh) -> (u32, u64, f32) {
    let shape = HeadShape::new(&head).unwrap();
    let mut colliders = Colliders::new();
    colliders
        .insert(
            Collider::mesh(head).with_friction(0.3),
            Isometry3::identity(),
        )
        .unwrap();
    let mut set = strips();
    let scalp = Scalp::fixed();
    let settings = StripSettings {
        root_angle: None,
        ..StripSettings::default()
    };
    let mut solver = StripSolver::new(
        SolverSettings::default(),
        HairParams::default(),
        &set.strands,
        &scalp,
        1,
        settings,
        Some(shape.clone()),
    )
    .unwrap();
    let (mut near, mut contacts, mut gap) = (0, 0, f32::INFINITY);
    for _ in 2..=25 {
        let report = solver
            .step_frame(&mut set.strands, &scalp, Some(&mut colliders))
            .unwrap();
        near += report.near_head as u32;
        contacts += report.solver.contact_points;
        for (x, &w) in set
            .strands
            .positions
            .iter()
            .zip(set.strands.inverse_masses())
        {
            if w > 0.0 {
                gap = gap.min(shape.signed_distance(&Isometry3::identity(), x));
            }
        }
    }
    (near, contacts, gap)
}

#[test]
fn strands_far_from_the_bounding_sphere_skip_the_contact_pipeline() {
    let (near, contacts, gap) = run(cube(Vector3::new(0.0, 0.0, -10.0), 0.1));
    assert_eq!(near, 0);
    assert_eq!(contacts, 0);
    assert!(gap > 9.0);
}

#[test]
fn strands_falling_onto_the_head_run_the_precise_stage_and_stay_outside() {
    let (near, contacts, gap) = run(cube(Vector3::new(0.12, 0.01, -0.08), 0.05));
    println!("{near} frames near the head, {contacts} contact points, smallest gap {gap:.4} m");
    assert!(near > 0 && contacts > 0);
    assert!(
        gap >= 0.0,
        "a free point ended a frame {gap} m inside the head"
    );
}
