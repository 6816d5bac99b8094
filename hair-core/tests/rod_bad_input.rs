//! Rod model: bad input gives a clear error or a reported warning with the residual, never NaN.

use hair_core::model::rod::{RodStrand, Stiffness};
use hair_core::{
    Anchor, Collider, Colliders, HairError, HairParams, RodParams, RodSolver, RootFrame, Scalp,
    SolverSettings, StrandInput, StrandSet, Substeps, TriMesh,
};
use nalgebra::{Isometry3, UnitQuaternion, Vector3};

fn one_strand() -> StrandSet {
    let rest = (0..=10)
        .map(|i| Vector3::new(0.0, 0.0, 0.02 * i as f32))
        .collect();
    let anchor = Anchor::Body(RootFrame {
        origin: Vector3::zeros(),
        rotation: UnitQuaternion::rotation_between(&Vector3::z(), &Vector3::x()).unwrap(),
    });
    let mut set = StrandSet::new();
    set.push(StrandInput::uniform(anchor, rest, 1e-3, 1e-3, 0.0, 0.0))
        .unwrap();
    set
}

fn spinning(frame: u32) -> Scalp {
    Scalp {
        mesh: None,
        body: Isometry3::from_parts(
            Vector3::zeros().into(),
            UnitQuaternion::from_euler_angles(0.0, 0.0, 0.5 * frame as f32),
        ),
    }
}

#[test]
fn zero_length_segment_is_named() {
    let rest = vec![
        Vector3::zeros(),
        Vector3::new(0.0, 0.0, 0.01),
        Vector3::new(0.0, 0.0, 0.01),
        Vector3::new(0.0, 0.0, 0.02),
    ];
    let w = [0.0, 1.0, 1.0, 1.0];
    let err = RodStrand::new(&rest, &w, &[1e-3; 4], &Stiffness::isotropic(1e-6, 1e-6)).unwrap_err();
    assert_eq!(err, 1, "segment 1 joins the duplicate points");
}

#[test]
fn non_positive_cross_section_ratio_is_refused_by_name() {
    let set = one_strand();
    for ratio in [0.0, -0.3] {
        let rod = RodParams {
            axis_ratio: ratio,
            ..RodParams::default()
        };
        let err = RodSolver::new(
            SolverSettings::default(),
            HairParams::default(),
            rod,
            &set,
            &Scalp::fixed(),
            1,
        )
        .unwrap_err();
        let text = err.to_string();
        assert!(matches!(err, HairError::Parameter { .. }), "{text}");
        assert!(
            text.contains("rod.axis_ratio") && text.contains("(0, 1]"),
            "{text}"
        );
    }
}

#[test]
fn projection_at_its_iteration_limit_is_reported_with_its_residual() {
    let mut set = one_strand();
    let rod = RodParams {
        projection_iterations: 1,
        projection_tolerance: 1e-12,
        ..RodParams::default()
    };
    let mut solver = RodSolver::new(
        SolverSettings::default(),
        HairParams::default(),
        rod,
        &set,
        &spinning(1),
        1,
    )
    .unwrap();
    let mut warned = None;
    for frame in 2..6 {
        let report = solver.step_frame(&mut set, &spinning(frame)).unwrap();
        assert!(report.projection.residual.is_finite());
        if let Some(w) = report.projection.warning() {
            warned = Some((w, report.projection));
        }
    }
    let (warning, p) = warned.expect("one iteration cannot reach 1e-12 in a spinning strand");
    println!("{warning}");
    assert!(p.unconverged > 0 && p.residual > 1e-12);
    assert!(warning.contains("residual") && warning.contains("rod.projection_iterations"));
    assert!(set
        .positions
        .iter()
        .chain(&set.velocities)
        .all(|v| v.iter().all(|c| c.is_finite())));
}

#[test]
fn explicit_step_far_above_the_bound_stops_with_an_error_not_nan() {
    let mut set = one_strand();
    let settings = SolverSettings {
        substeps: Substeps::Fixed(1),
        ..SolverSettings::default()
    };
    let rod = RodParams {
        youngs_modulus: 1e12,
        ..RodParams::default()
    };
    let mut solver =
        RodSolver::new(settings, HairParams::default(), rod, &set, &spinning(1), 1).unwrap();
    assert!(solver.dt() > 10.0 * solver.dt_max());
    let mut failed = None;
    for frame in 2..30 {
        match solver.step_frame(&mut set, &spinning(frame)) {
            Ok(_) => {}
            Err(e) => {
                failed = Some(e);
                break;
            }
        }
    }
    let err = failed.expect("a substep 10× beyond the bound must fail");
    println!("{err}");
    assert!(matches!(err, HairError::Unstable { .. }), "{err}");
}

#[test]
fn open_mesh_collider_is_refused() {
    let mut set = one_strand();
    let mut solver = RodSolver::new(
        SolverSettings::default(),
        HairParams::default(),
        RodParams::default(),
        &set,
        &Scalp::fixed(),
        1,
    )
    .unwrap();
    let plate = TriMesh::new(
        vec![
            Vector3::new(-1.0, -1.0, -0.1),
            Vector3::new(1.0, -1.0, -0.1),
            Vector3::new(0.0, 1.0, -0.1),
        ],
        vec![[0, 1, 2]],
    )
    .unwrap();
    let mut colliders = Colliders::new();
    colliders
        .insert(Collider::mesh(plate), Isometry3::identity())
        .unwrap();
    let err = solver
        .step_frame_with_colliders(&mut set, &Scalp::fixed(), &mut colliders)
        .unwrap_err();
    assert!(
        matches!(err, HairError::Collider { collider: 0, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("mass-spring"), "{err}");
}
