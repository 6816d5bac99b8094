//! Sag-free initialisation with hair resting on a collider (`make_sag_free_supported`): the
//! collider carries the outward part of the load at the points that rest on it, as a floor
//! carries a rope lying on it.
//!
//! Analytic case: a strand lying straight on a level floor (the top of a 100 m sphere: it falls
//! away by 0.3 mm and tilts by 0.15° over the strand). Its weight presses straight into the floor, so the floor carries all of
//! it and no bending is needed: the supported solve leaves every rest direction as groomed (turn
//! 0), where the unsupported one must pre-bend the strand against its whole weight, as a
//! cantilever. Simulated with the floor, the supported groom stays put.

mod common;

use common::*;
use hair_core::quality::resting_normals;
use hair_core::{
    make_sag_free, make_sag_free_supported, Collider, Colliders, HairParams, MassSpringSolver,
    SagFreeLimits, Scalp, SolverSettings, StrandInput,
};
use nalgebra::{Isometry3, Vector3};

const RADIUS: f32 = 0.002;
const FLOOR: f32 = 100.0;

fn params() -> HairParams {
    HairParams {
        bend_stiffness: 5.0,
        ..HairParams::default()
    }
}

/// A 25 cm strand of 16 segments lying along +x on the floor, touching it (centre one radius up).
fn lying() -> StrandInput {
    let anchor = anchor_along(Vector3::new(0.0, 0.0, RADIUS), Vector3::x());
    StrandInput::uniform(
        anchor,
        straight(16, 0.25 / 16.0, Vector3::z()),
        1e-3,
        RADIUS,
        0.0,
        0.0,
    )
}

fn floor() -> Colliders {
    let mut set = Colliders::new();
    set.insert(
        Collider::sphere(FLOOR),
        Isometry3::translation(0.0, 0.0, -FLOOR),
    )
    .unwrap();
    set
}

#[test]
fn a_strand_lying_on_a_floor_needs_no_bending_when_the_floor_carries_it() {
    let scalp = Scalp::fixed();
    let colliders = floor();
    let mut supported = set_on(&scalp, [lying()]);
    let roots = supported.root_frames(&scalp);
    let supports = resting_normals(
        &colliders,
        &supported.positions,
        supported.radii(),
        supported.inverse_masses(),
        RADIUS,
    );
    // Every free point rests on the floor, whose normal is up.
    for (n, &w) in supports.iter().zip(supported.inverse_masses()) {
        if w > 0.0 {
            assert!((n - Vector3::z()).norm() < 5e-3, "{n:?}");
        }
    }
    let report = make_sag_free_supported(
        &mut supported,
        &params(),
        &roots,
        &supports,
        SagFreeLimits::default(),
    )
    .unwrap();
    assert_eq!(report.balanced, 1);
    assert!(report.max_turn < 1e-3, "{report:?}");

    let mut unsupported = set_on(&scalp, [lying()]);
    let report = make_sag_free(
        &mut unsupported,
        &params(),
        &roots,
        SagFreeLimits::default(),
    )
    .unwrap();
    assert!(
        report.max_turn > 0.1,
        "a cantilever must be pre-bent: {report:?}"
    );

    // Simulated for a second on the floor: the supported groom stays within a fraction of the
    // strand radius (the contact response holds the points at the floor).
    let groom = supported.positions.clone();
    let mut colliders = floor();
    let mut solver =
        MassSpringSolver::new(SolverSettings::default(), params(), &supported, &scalp, 0).unwrap();
    for _ in 0..24 {
        solver
            .step_frame_with_colliders(&mut supported, &scalp, &mut colliders)
            .unwrap();
    }
    let drift = supported
        .positions
        .iter()
        .zip(&groom)
        .map(|(x, g)| (x - g).norm())
        .fold(0.0f32, f32::max);
    println!("lying strand: drift after 1 s {drift:.2e} m");
    assert!(drift < 0.5 * RADIUS, "drift {drift} m");
}
