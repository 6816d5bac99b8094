//! The strip model's post-step passes on edge strands: Provot's strain limit and the root angle
//! limiter, each against the unlimited run that violates it.

use hair_core::model::strips::{
    limit_strain, RootAngleLimit, StripSet, StripSettings, StripSolver,
};
use hair_core::{
    Anchor, HairParams, MassSpringSolver, RootFrame, Scalp, SolverSettings, StrandInput, StrandSet,
};
use nalgebra::{UnitQuaternion, Vector3};

const SEGMENT: f32 = 0.02;

/// A straight strand of 10 segments growing along the root frame's z, rooted at `origin` with
/// that z turned onto world +x (horizontal: gravity pulls it beyond any small root angle).
fn horizontal(origin: Vector3<f32>) -> StrandInput {
    let rest = (0..=10)
        .map(|i| Vector3::new(0.0, 0.0, SEGMENT * i as f32))
        .collect();
    let anchor = Anchor::Body(RootFrame {
        origin,
        rotation: UnitQuaternion::rotation_between(&Vector3::z(), &Vector3::x()).unwrap(),
    });
    StrandInput::uniform(anchor, rest, 1e-3, 1e-3, 0.0, 0.0)
}

fn one_strip() -> StripSet {
    StripSet::from_pairs(
        vec![(
            horizontal(Vector3::zeros()),
            horizontal(Vector3::new(0.0, 0.02, 0.0)),
        )],
        50,
        &Scalp::fixed(),
    )
    .unwrap()
}

/// One strip under the strip solver with `settings`, and the same strip as plain mass-spring
/// hair (the reference without the strip passes), both on a fixed scalp from frame 1.
fn strip_and_reference(
    params: HairParams,
    settings: StripSettings,
) -> (StripSet, StripSolver, StripSet, MassSpringSolver) {
    let scalp = Scalp::fixed();
    let strips = one_strip();
    let free = one_strip();
    let solver = StripSolver::new(
        SolverSettings::default(),
        params,
        &strips.strands,
        &scalp,
        1,
        settings,
        None,
    )
    .unwrap();
    let reference =
        MassSpringSolver::new(SolverSettings::default(), params, &free.strands, &scalp, 1).unwrap();
    (strips, solver, free, reference)
}

fn strains(strands: &StrandSet) -> Vec<f32> {
    (0..strands.len())
        .flat_map(|s| {
            let p = &strands.positions[strands.points(s)];
            let rest = &strands.rest_lengths()[strands.segments(s)];
            p.windows(2)
                .zip(rest)
                .map(|(w, l)| (w[1] - w[0]).norm() / l - 1.0)
                .collect::<Vec<_>>()
        })
        .collect()
}

fn root_angle(strands: &StrandSet, s: usize) -> f32 {
    let p = strands.points(s).start;
    let d = (strands.positions[p + 1] - strands.positions[p]).normalize();
    d.dot(&Vector3::x()).clamp(-1.0, 1.0).acos()
}

#[test]
fn provot_correction_bounds_every_segment_strain_after_each_frame() {
    // Springs so soft that gravity alone would stretch segments by far more than the limit.
    let params = HairParams {
        stretch_stiffness: 0.05,
        bend_stiffness: 0.0,
        ..HairParams::default()
    };
    let limit = 0.02;
    let settings = StripSettings {
        max_strain: limit,
        root_angle: None,
        clearance: 0.0,
    };
    let scalp = Scalp::fixed();
    let (mut strips, mut solver, mut free, mut reference) = strip_and_reference(params, settings);
    for frame in 2..=25 {
        solver
            .step_frame(&mut strips.strands, &scalp, None)
            .unwrap();
        reference.step_frame(&mut free.strands, &scalp).unwrap();
        let worst = strains(&strips.strands)
            .into_iter()
            .fold(f32::NEG_INFINITY, f32::max);
        assert!(
            worst <= limit + 1e-5,
            "frame {frame}: a segment is strained {worst}, limit {limit}"
        );
    }
    let unlimited = free.strands.max_stretch();
    println!("unlimited strain after 1 s: {unlimited:.3}; limited ≤ {limit}");
    assert!(
        unlimited > 10.0 * limit,
        "the scene must stretch beyond the limit"
    );
}

#[test]
fn one_provot_pass_leaves_every_segment_within_the_limit() {
    let mut strips = one_strip();
    let s = &mut strips.strands;
    // Stretch every segment by 50% and zig-zag the points.
    for i in 0..s.point_count() {
        s.positions[i] *= 1.5;
        s.positions[i].z += if i % 2 == 0 { 0.01 } else { -0.01 };
        s.velocities[i] = Vector3::new(1.0, 0.0, 0.0);
    }
    let before = limit_strain(s, 0.1);
    assert!(before > 0.4);
    for strain in strains(s) {
        assert!(strain <= 0.1 + 1e-5, "strain {strain}");
    }
}

#[test]
fn root_angle_limiter_holds_the_root_at_its_limit_under_gravity() {
    // Air drag settles the swing of the hanging chain below the first segment.
    let params = HairParams {
        bend_stiffness: 0.0,
        air_drag: 4.0,
        ..HairParams::default()
    };
    let limit = 30f32.to_radians();
    let settings = StripSettings {
        max_strain: 0.05,
        root_angle: Some(RootAngleLimit::new(limit).unwrap()),
        clearance: 0.0,
    };
    let scalp = Scalp::fixed();
    let (mut strips, mut solver, mut free, mut reference) = strip_and_reference(params, settings);
    let mut corrections = 0;
    let mut settled = Vec::new();
    for frame in 2..=73 {
        corrections += solver
            .step_frame(&mut strips.strands, &scalp, None)
            .unwrap()
            .angle_corrections;
        reference.step_frame(&mut free.strands, &scalp).unwrap();
        for s in 0..2 {
            let a = root_angle(&strips.strands, s);
            assert!(
                a <= limit + 1e-4,
                "frame {frame}, edge {s}: root angle {}° beyond the limit",
                a.to_degrees()
            );
        }
        if frame > 61 {
            settled.push(root_angle(&strips.strands, 0));
        }
    }
    let held = settled.iter().fold(f32::INFINITY, |a, &b| a.min(b));
    let hanging = root_angle(&free.strands, 0);
    println!(
        "last half second: root angle ≥ {:.3}° (limit 30°), {:.1}° without the limiter; {corrections} \
         corrections",
        held.to_degrees(),
        hanging.to_degrees()
    );
    assert!(hanging > 2.0 * limit, "gravity must pull beyond the limit");
    assert!(
        (held - limit).abs() < 0.5f32.to_radians(),
        "the root fell back to {}° in the last half second; expected it held at the limit 30°",
        held.to_degrees()
    );
}
