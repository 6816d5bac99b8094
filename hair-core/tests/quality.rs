//! The quality report's measures on constructed cases with known answers.

use hair_core::quality::{
    measure, measure_remembered, Frame, PenetrationMemory, Previous, QualityInput, QualityOptions,
    Reference,
};
use hair_core::{Collider, Colliders, HairError};
use nalgebra::{Isometry3, Vector3};

/// A frame over borrowed arrays of one or more strands, every point free but the roots.
struct Strands {
    offsets: Vec<u32>,
    positions: Vec<Vector3<f32>>,
    velocities: Vec<Vector3<f32>>,
    rest: Vec<f32>,
    radii: Vec<f32>,
}

impl Strands {
    /// Strands given as point lists, at rest with their current segment lengths.
    fn new(strands: &[Vec<Vector3<f32>>]) -> Self {
        let mut s = Strands {
            offsets: vec![0],
            positions: Vec::new(),
            velocities: Vec::new(),
            rest: Vec::new(),
            radii: Vec::new(),
        };
        for points in strands {
            for w in points.windows(2) {
                s.rest.push((w[1] - w[0]).norm());
            }
            s.positions.extend(points);
            s.offsets.push(s.positions.len() as u32);
        }
        s.velocities = vec![Vector3::zeros(); s.positions.len()];
        s.radii = vec![1e-3; s.positions.len()];
        s
    }

    fn frame(&self) -> Frame<'_> {
        Frame {
            offsets: &self.offsets,
            positions: &self.positions,
            velocities: &self.velocities,
            rest_lengths: &self.rest,
            radii: &self.radii,
            inverse_masses: None,
        }
    }

    fn input(&self) -> QualityInput<'_> {
        QualityInput {
            frame: self.frame(),
            previous: None,
            colliders: None,
            reference: None,
        }
    }
}

/// `n + 1` points 1 cm apart along `dir` from `start`.
fn line(start: Vector3<f32>, dir: Vector3<f32>, n: usize) -> Vec<Vector3<f32>> {
    (0..=n).map(|i| start + dir * (0.01 * i as f32)).collect()
}

#[test]
fn one_fold_back_is_one_hairpin_of_180_degrees() {
    // Up 5 cm, then straight back down beside itself (a 180° turn at one point), and a straight
    // strand and one with a 60° bend that are not hairpins.
    let mut folded = line(Vector3::zeros(), Vector3::z(), 5);
    folded.extend((0..5).map(|i| Vector3::new(0.0, 0.0, 0.04 - 0.01 * i as f32)));
    let straight = line(Vector3::x(), Vector3::z(), 6);
    let mut bent = line(Vector3::y(), Vector3::z(), 3);
    let turn = Vector3::new(60f32.to_radians().sin(), 0.0, 60f32.to_radians().cos());
    let corner = bent[3];
    bent.extend((1..=3).map(|i| corner + turn * (0.01 * i as f32)));
    let s = Strands::new(&[folded, straight, bent]);
    let r = measure(&s.input(), &QualityOptions::default()).unwrap();
    assert_eq!(r.hairpins.count, 1);
    assert!(
        (r.hairpins.max_turn_deg - 180.0).abs() < 0.1,
        "{}",
        r.hairpins.max_turn_deg
    );
    // A turn of exactly 90° is not a hairpin, 91° is.
    for (deg, count) in [(60.0f32, 0), (89.0, 0), (91.0, 1)] {
        let mut p = line(Vector3::zeros(), Vector3::z(), 2);
        let t = Vector3::new(deg.to_radians().sin(), 0.0, deg.to_radians().cos());
        p.push(p[2] + t * 0.01);
        let r = measure(&Strands::new(&[p]).input(), &QualityOptions::default()).unwrap();
        assert_eq!(r.hairpins.count, count, "turn {deg}°");
        assert!((r.hairpins.max_turn_deg - deg).abs() < 0.05);
    }
}

#[test]
fn point_two_mm_inside_a_sphere_is_two_mm_deep() {
    // A ball of radius 0.1 m at (1, 0, 0) with 0.5 mm thickness; hair radius 1 mm. A point's
    // centre at 0.1 + 0.0015 − 0.002 from the centre is 2 mm inside the kept gap.
    let mut colliders = Colliders::new();
    let centre = Vector3::new(1.0, 0.0, 0.0);
    colliders
        .insert(
            Collider::sphere(0.1).with_thickness(5e-4),
            Isometry3::translation(centre.x, centre.y, centre.z),
        )
        .unwrap();
    let keep = 0.1 + 1e-3 + 5e-4;
    let dir = Vector3::new(0.3, -0.4, 0.5).normalize();
    let inside = centre + dir * (keep - 2e-3);
    let touching = centre + dir.yzx() * (keep - 5e-5); // within the 0.1 mm tolerance
    let outside = centre + dir.zxy() * (keep + 1e-3);
    let root = centre + Vector3::new(0.0, 0.0, 0.3);
    let s = Strands::new(&[
        vec![root, inside],
        vec![root + Vector3::x() * 0.01, touching],
        vec![root + Vector3::x() * 0.02, outside],
    ]);
    let mut input = s.input();
    input.colliders = Some(&colliders);
    let r = measure(&input, &QualityOptions::default()).unwrap();
    let p = r.penetration.unwrap();
    assert_eq!(p.checked, 3, "roots are kinematic and not checked");
    assert_eq!(p.inside, 1);
    assert!((p.inside_fraction - 1.0 / 3.0).abs() < 1e-12);
    // f32 positions near 1 m are exact to 6e-8 m; parry's projection on a ball is exact.
    assert!((p.deepest - 2e-3).abs() < 1e-6, "deepest {}", p.deepest);
    // Deep inside, 5 cm from the centre: 5 cm under the surface, plus the kept gap.
    let s = Strands::new(&[vec![root, centre + dir * 0.05]]);
    let mut input = s.input();
    input.colliders = Some(&colliders);
    let p = measure(&input, &QualityOptions::default())
        .unwrap()
        .penetration
        .unwrap();
    assert!((p.deepest - (0.05 + 1.5e-3)).abs() < 1e-6, "{}", p.deepest);
}

#[test]
fn one_percent_stretch_shows_in_p99_and_max() {
    // 100 segments of 1 cm; segments 10 and 70 stretched by 1 % (the points after them shifted
    // along the strand), segment 40 compressed by 2 %.
    let rest = line(Vector3::zeros(), Vector3::x(), 100);
    let mut s = Strands::new(&[rest]);
    let shift = |s: &mut Strands, from: usize, by: f32| {
        for p in &mut s.positions[from..] {
            p.x += by;
        }
    };
    shift(&mut s, 11, 1e-4);
    shift(&mut s, 71, 1e-4);
    shift(&mut s, 41, -2e-4);
    let r = measure(&s.input(), &QualityOptions::default()).unwrap();
    let (st, co) = (&r.strain.stretch, &r.strain.compression);
    assert_eq!(st.count(), 100);
    // Positions up to 1 m carry 6e-8 m of f32 error: strain 1e-2 ± 1e-5.
    assert!((st.max() - 0.01).abs() < 1e-5, "max {}", st.max());
    assert!(
        (st.p99() - 0.01).abs() < 1e-5,
        "rank 99 of 100 is a stretched one"
    );
    assert!(
        st.p50() < 1e-5,
        "the median segment is at rest: {}",
        st.p50()
    );
    assert!((co.max() - 0.02).abs() < 1e-5);
    assert!(
        co.p99() < 1e-5,
        "one compressed segment in 100 is above p99"
    );
}

#[test]
fn exact_motion_with_consistent_velocities_has_no_mismatch() {
    // Ballistic flight under gravity from two frames 1/24 s apart: positions and velocities
    // exact, so (x1 − x0)/Δt equals the mean of the end velocities.
    let g = Vector3::new(0.0, 0.0, -9.81f32);
    let dt = 1.0 / 24.0f32;
    let x0 = line(Vector3::new(0.0, 0.0, 1.0), Vector3::y(), 10);
    let v0: Vec<Vector3<f32>> = (0..=10)
        .map(|i| Vector3::new(0.5, -0.2 * i as f32, 1.0))
        .collect();
    let x1: Vec<Vector3<f32>> = x0
        .iter()
        .zip(&v0)
        .map(|(x, v)| x + v * dt + g * (0.5 * dt * dt))
        .collect();
    let v1: Vec<Vector3<f32>> = v0.iter().map(|v| v + g * dt).collect();
    let mut s = Strands::new(std::slice::from_ref(&x1));
    s.velocities = v1.clone();
    s.rest = vec![0.01; 10];
    let mut input = s.input();
    input.previous = Some(Previous {
        positions: &x0,
        velocities: &v0,
        dt,
    });
    let m = measure(&input, &QualityOptions::default())
        .unwrap()
        .velocity_mismatch
        .unwrap();
    // f32 positions near 1 m (6e-8 m) over 1/24 s: about 3e-6 m/s of round-off.
    assert!(m.max() < 1e-5, "mismatch {}", m.max());
    // A stale velocity of 0.25 m/s downward at both frames reads as 0.25 m/s.
    let stale = Vector3::new(0.0, 0.0, -0.25);
    s.velocities = v1.iter().map(|v| v + stale).collect();
    let v0_stale: Vec<_> = v0.iter().map(|v| v + stale).collect();
    let mut input = s.input();
    input.previous = Some(Previous {
        positions: &x0,
        velocities: &v0_stale,
        dt,
    });
    let m = measure(&input, &QualityOptions::default())
        .unwrap()
        .velocity_mismatch
        .unwrap();
    assert!((m.p50() - 0.25).abs() < 0.25 * 0.008 + 1e-5);
    assert!((m.max() - 0.25).abs() < 1e-5);
}

#[test]
fn drift_from_reference_and_merging_over_frames() {
    let rest = line(Vector3::zeros(), Vector3::z(), 4);
    let mut s = Strands::new(&[rest.clone(), rest.clone()]);
    // Strand 1's tip 3 mm off; everything else on its reference.
    s.positions[9].x += 3e-3;
    let mut reference = rest.clone();
    reference.extend(&rest);
    let mut input = s.input();
    input.reference = Some(Reference::Positions(&reference));
    let a = measure(&input, &QualityOptions::default()).unwrap();
    let d = a.drift.as_ref().unwrap();
    // 8 free points, one 3 mm off: RMS 3/√8 mm; 2 tips: RMS 3/√2 mm.
    assert!((d.max - 3e-3).abs() < 1e-7 && (d.tip_max - 3e-3).abs() < 1e-7);
    assert!((d.rms - 3e-3 / 8f32.sqrt()).abs() < 1e-7, "{}", d.rms);
    assert!((d.tip_rms - 3e-3 / 2f32.sqrt()).abs() < 1e-7);
    // A second frame with the hairpin-free, drift-free state: merged RMS over 16 points.
    let s2 = Strands::new(&[rest.clone(), rest.clone()]);
    let mut input = s2.input();
    input.reference = Some(Reference::Positions(&reference));
    let b = measure(&input, &QualityOptions::default()).unwrap();
    let mut run = a.clone();
    run.merge(&b);
    assert_eq!(run.frames, 2);
    assert_eq!(run.points, 20);
    assert_eq!(run.strain.stretch.count(), 16);
    let d = run.drift.as_ref().unwrap();
    assert!((d.rms - 3e-3 / 16f32.sqrt()).abs() < 1e-7);
    assert!((d.max - 3e-3).abs() < 1e-7);
    // The report serialises with its units' numbers, absent parts as null (with the `serde`
    // feature: `cargo test -p hair-core --features serde`; the workspace run has it on).
    #[cfg(feature = "serde")]
    {
        let json = serde_json::to_string(&run).unwrap();
        assert!(json.contains("\"penetration\":null"), "{json}");
        assert!(json.contains("\"p99\""), "{json}");
    }
}

#[test]
fn arrays_that_do_not_fit_the_layout_are_refused_by_name() {
    let s = Strands::new(&[line(Vector3::zeros(), Vector3::z(), 3)]);
    let short = vec![Vector3::zeros(); 2];
    let mut input = s.input();
    input.frame.velocities = &short;
    let name = |r: Result<_, HairError>| match r {
        Err(HairError::Parameter { name, .. }) => name,
        other => panic!("expected a parameter error, got {other:?}"),
    };
    assert_eq!(
        name(measure(&input, &QualityOptions::default())),
        "quality.frame.velocities"
    );
    let mut input = s.input();
    input.reference = Some(Reference::Positions(&short));
    assert_eq!(
        name(measure(&input, &QualityOptions::default())),
        "quality.reference"
    );
    let mut input = s.input();
    let offsets = [0, 1, 4];
    input.frame.offsets = &offsets;
    assert_eq!(
        name(measure(&input, &QualityOptions::default())),
        "quality.frame.offsets"
    );
    let mut input = s.input();
    let x0 = s.positions.clone();
    input.previous = Some(Previous {
        positions: &x0,
        velocities: &s.velocities,
        dt: 0.0,
    });
    assert_eq!(
        name(measure(&input, &QualityOptions::default())),
        "quality.previous.dt"
    );
}

#[test]
fn remembering_bounds_between_frames_changes_no_figure() {
    // A mesh head (solid) and a ball, both moving; 400 strands of 12 points swept from far
    // outside through both over 30 frames. The memory may skip points, never change a figure.
    let head = hair_core::mesh::TriMesh::uv_sphere(0.1, 24, 12).unwrap();
    let mut colliders = Colliders::new();
    colliders
        .insert(
            Collider::mesh(head).with_thickness(5e-4),
            Isometry3::identity(),
        )
        .unwrap();
    colliders
        .insert(
            Collider::sphere(0.05),
            Isometry3::translation(0.3, 0.0, 0.0),
        )
        .unwrap();
    let mut memory = PenetrationMemory::new();
    let mut inside_seen = 0;
    for f in 0..30 {
        let t = f as f32 / 29.0;
        colliders
            .set_pose(
                hair_core::ColliderId(0),
                Isometry3::new(Vector3::new(0.0, 0.02 * t, 0.0), Vector3::z() * (0.5 * t)),
            )
            .unwrap();
        colliders
            .set_pose(
                hair_core::ColliderId(1),
                Isometry3::translation(0.3 - 0.4 * t, 0.0, 0.0),
            )
            .unwrap();
        let strands: Vec<Vec<Vector3<f32>>> = (0..400)
            .map(|k| {
                let a = k as f32 * 0.7;
                let start =
                    Vector3::new(a.cos(), a.sin(), 0.1 * (a * 0.3).sin()) * (0.5 - 0.45 * t);
                line(start, Vector3::new(0.2, -0.3, 1.0).normalize(), 11)
            })
            .collect();
        let s = Strands::new(&strands);
        let mut input = s.input();
        input.colliders = Some(&colliders);
        let exact = measure(&input, &QualityOptions::default()).unwrap();
        let remembered =
            measure_remembered(&input, &QualityOptions::default(), &mut memory).unwrap();
        assert_eq!(exact.penetration, remembered.penetration, "frame {f}");
        inside_seen += exact.penetration.unwrap().inside;
    }
    assert!(inside_seen > 0, "the sweep must pass through the colliders");
}

/// The groom posed point by point from root frames ([`Reference::Posed`]) is the same reference
/// as the posed positions stored ([`rest_positions`]): the same drift to f32 rounding, on
/// strands whose roots are turned and moved.
#[test]
fn posed_reference_measures_the_drift_of_the_stored_rest_positions() {
    use hair_core::quality::rest_positions;
    use hair_core::{Anchor, RootFrame, Scalp, StrandInput, StrandSet};
    use nalgebra::{Translation3, UnitQuaternion};

    let mut strands = StrandSet::new();
    for s in 0..3 {
        let rotation = UnitQuaternion::from_euler_angles(0.3 * s as f32, -0.7, 1.1);
        let root = RootFrame {
            origin: Vector3::new(0.01 * s as f32, 0.02, -0.03),
            rotation,
        };
        let rest = (0..6)
            .map(|i| Vector3::new(0.001 * i as f32, 0.0, 0.02 * i as f32))
            .collect();
        strands
            .push(StrandInput::uniform(
                Anchor::Body(root),
                rest,
                1e-3,
                1e-4,
                0.0,
                0.0,
            ))
            .unwrap();
    }
    let mut scalp = Scalp::fixed();
    scalp.body = Isometry3::from_parts(
        Translation3::new(0.1, -0.2, 0.3),
        UnitQuaternion::from_euler_angles(0.4, 0.2, -0.9),
    );
    let stored = rest_positions(&strands, &scalp);
    let roots = strands.root_frames(&scalp);
    // Every free point 1 mm off its posed rest position, tips 4 mm off.
    let positions: Vec<Vector3<f32>> = stored
        .iter()
        .enumerate()
        .map(|(i, p)| p + Vector3::new(0.0, if i % 6 == 5 { 4e-3 } else { 1e-3 }, 0.0))
        .collect();
    let velocities = vec![Vector3::zeros(); positions.len()];
    let frame = Frame {
        offsets: strands.offsets(),
        positions: &positions,
        velocities: &velocities,
        rest_lengths: strands.rest_lengths(),
        radii: strands.radii(),
        inverse_masses: Some(strands.inverse_masses()),
    };
    let measure_with = |reference| {
        let input = QualityInput {
            frame,
            previous: None,
            colliders: None,
            reference: Some(reference),
        };
        measure(&input, &QualityOptions::default())
            .unwrap()
            .drift
            .unwrap()
    };
    let a = measure_with(Reference::Positions(&stored));
    let b = measure_with(Reference::Posed {
        roots: &roots,
        rest_local: strands.rest_local(),
    });
    let expected_rms = ((4.0 * 1e-6 + 16e-6) / 5.0f32).sqrt();
    for d in [&a, &b] {
        assert!((d.tip_max - 4e-3).abs() < 1e-6, "{d:?}");
        assert!((d.rms - expected_rms).abs() < 1e-6, "{d:?}");
    }
    assert!((a.max - b.max).abs() < 1e-6 && (a.rms - b.rms).abs() < 1e-6);
}
