//! The guide level through a scene file (`scenes/sintel.toml`): the Sintel groom's 228 guides are
//! imported and snapped onto the bust (the snap report is printed), 3,000 simulation hairs are
//! interpolated from them (less those the report says pass through her ears), every hair's rest length stays within the guides' range, and the scene
//! simulates.

use std::path::PathBuf;

use hairsys::scene::SceneFile;

/// The sim hairs a guides report says were left out, summed over its reasons ("(87 left out:
/// …; 3 left out: …)").
fn left_out(report: &str) -> usize {
    report
        .split(" left out")
        .filter_map(|head| head.rsplit(['(', ';']).next())
        .filter_map(|n| n.trim().parse::<usize>().ok())
        .sum()
}

/// Regression: three sim hairs rooted above Sintel's right ear started with their
/// first point in the gap between ear and head, which is narrower than twice the clearance:
/// lifting could not clear them, and the bust collider held that point 0.7–1.1 mm inside for
/// the whole run (all of the run's inside point-frames). Such hair is left out and counted; no
/// sim hair of the shipped scene starts inside her bust by more than the contact tolerance.
#[test]
fn sintel_wisps_in_the_gap_between_ear_and_head_are_left_out() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../scenes/sintel.toml");
    let sim = SceneFile::load(&path).unwrap().build().unwrap();
    let report = sim.guides_report.clone().expect("the scene has guides");
    let gap = report
        .split(" left out: they start in a gap")
        .next()
        .and_then(|head| head.rsplit([';', '(']).next())
        .and_then(|n| n.trim().parse::<usize>().ok());
    assert!(
        gap.is_some_and(|n| (1..=10).contains(&n)),
        "the wisps in the gap are named: {report}"
    );
    let colliders = sim.colliders_at(sim.first_frame as f32).unwrap();
    let tolerance = hair_core::QualityOptions::default().contact_tolerance;
    let inside = hair_core::quality::inside_flags(
        &colliders,
        &sim.strands.positions,
        sim.strands.radii(),
        sim.strands.inverse_masses(),
        tolerance,
    );
    let first = inside.iter().position(|&i| i);
    assert!(
        first.is_none(),
        "{} points start inside the bust, the first {:?}",
        inside.iter().filter(|&&i| i).count(),
        first.map(|i| sim.strands.positions[i])
    );
}

/// Regression: a sim hair rooted on the rim of Sintel's right ear, at (84.2, 17.0,
/// 341.8) mm, beside guides rooted on the scalp just above it, had its guides' shapes turned by
/// 82° — interpolation carries a guide's shape by the rotation between the root normals — so a
/// guide combed down the head came out 40 mm off the bust behind the ear: the strand seen
/// sticking out there in the side and back pictures. Hair turned more than 60° off its guides
/// is left out and counted; no sim hair rooted within 15 mm of that rim stands farther off the
/// bust than the guides rooted within 30 mm of it (27.6 mm), plus 5 mm for the lift and layer.
#[test]
fn a_sim_hair_on_her_right_ear_rim_does_not_stand_out_behind_it() {
    use parry3d::query::PointQuery;
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../scenes/sintel.toml");
    let sim = SceneFile::load(&path).unwrap().build().unwrap();
    let report = sim.guides_report.clone().expect("the scene has guides");
    assert!(
        report.contains("left out: rooted where the scalp turns sharply"),
        "{report}"
    );
    let mesh = sim.scalp_at(sim.first_frame as f32).mesh.unwrap();
    let bust = parry3d::shape::TriMesh::new(
        mesh.positions()
            .iter()
            .map(|p| parry3d::math::Vector::new(p.x, p.y, p.z))
            .collect(),
        mesh.triangles().to_vec(),
    )
    .unwrap();
    let off = |points: &[nalgebra::Vector3<f32>]| {
        points
            .iter()
            .map(|p| bust.distance_to_local_point(parry3d::math::Vector::new(p.x, p.y, p.z), false))
            .fold(0.0f32, f32::max)
    };
    let rim = nalgebra::Vector3::new(0.0842, 0.0170, 0.3418);
    let guides_off = sim
        .guides
        .iter()
        .map(|g| g.world_points(&mesh))
        .filter(|w| (w[0] - rim).norm() < 0.03)
        .map(|w| off(&w))
        .fold(0.0f32, f32::max);
    assert!(guides_off > 0.0, "guides grow around the rim");
    let mut near = 0;
    for s in 0..sim.strands.len() {
        let points = &sim.strands.positions[sim.strands.points(s)];
        if (points[0] - rim).norm() < 0.015 {
            near += 1;
            let o = off(points);
            assert!(
                o <= guides_off + 0.005,
                "sim hair {s} rooted at {:?} stands {o} m off the bust (its guides {guides_off} m)",
                points[0]
            );
        }
    }
    assert!(near > 5, "{near} sim hairs around the rim");
}

#[test]
fn sintel_scene_snaps_guides_and_interpolates_sim_hairs() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../scenes/sintel.toml");
    let sim = SceneFile::load(&path).unwrap().build().unwrap();
    let report = sim.guides_report.clone().expect("the scene has guides");
    println!("sintel.toml: {report}");
    assert_eq!(sim.guides.len(), 228);
    // 3,000 drawn; those whose blended shape passes through her ears, and those starting in the
    // gap between ear and head, are left out and counted.
    let left_out = left_out(&report);
    assert_eq!(sim.strands.len() + left_out, 3000, "{report}");
    assert!(left_out < 150, "{left_out} of 3,000 left out: {report}");
    let length = |rest: &[nalgebra::Vector3<f32>]| {
        rest.windows(2).map(|w| (w[1] - w[0]).norm()).sum::<f32>()
    };
    let guide_lengths: Vec<f32> = sim.guides.iter().map(|g| length(&g.rest)).collect();
    let (lo, hi) = guide_lengths
        .iter()
        .fold((f32::MAX, 0.0f32), |(lo, hi), &l| (lo.min(l), hi.max(l)));
    for s in 0..sim.strands.len() {
        let l = sim.strands.rest_strand_length(s);
        assert!(
            l >= lo * 0.999 && l <= hi * 1.001,
            "sim hair {s} is {l} m long, guides span {lo}–{hi} m"
        );
    }
    // The scene simulates through the front door, as `hairsys simulate` runs it (regression:
    // the sim hairs left out kept their guide blends, and the session panicked binding 3,000
    // blends to 2,914 strands).
    let mut session = hairsys::Session::from_scene(&SceneFile::load(&path).unwrap()).unwrap();
    assert_eq!(session.strands().len(), sim.strands.len());
    // Her strain limit is 1 %; contacts are solved together with it and have the last word
    // (nothing is left inside the bust), which leaves the limit at the coupling's residual: a
    // few parts in 10⁴ of a segment at most.
    for _ in 2..=3 {
        let report = session.step().unwrap();
        assert!(
            report.max_stretch <= 0.01 + 3e-4,
            "stretch {}",
            report.max_stretch
        );
    }
}
