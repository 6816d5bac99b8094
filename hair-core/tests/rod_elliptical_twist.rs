//! Rod model: a strand with an elliptical cross-section bent sideways twists so that it bends
//! over its major axis (seed 002, "Hair twisting").
//!
//! A horizontal strand is clamped with its cross-section's major axis vertical, so gravity bends
//! it over its minor axis, the stiff way (`E I₂ = 4 E I₁` at `b/a = ½`). The quasistatic twist
//! turns each segment's major axis onto the bending axis: the bending over the minor axis must be
//! near zero, the segments' major axes horizontal (a quarter turn), and the strand must sag like
//! a round strand of stiffness `E I₁` (the easy one), not like one of `E I₂`.
//!
//! Reference: the same solver on round strands (`b/a = 1`) whose Young's modulus gives them the
//! ellipse's `E I₁` (`E r³`) and `E I₂` (`E r`); sags agree within 1 % with the first.

use hair_core::rod::Workspace;
use hair_core::{
    Anchor, HairParams, RodParams, RodSolver, RootFrame, Scalp, SolverSettings, StrandInput,
    StrandSet,
};
use nalgebra::{UnitQuaternion, Vector3};

const SEGMENTS: usize = 10;

fn strands() -> StrandSet {
    let rest = (0..=SEGMENTS)
        .map(|i| Vector3::new(0.0, 0.0, 0.02 * i as f32))
        .collect();
    // Root frame: local z (the rest direction) onto world x; local x (the ghost's reference
    // normal, the major axis at twist 0) onto world −z.
    let anchor = Anchor::Body(RootFrame {
        origin: Vector3::new(0.0, 0.0, 0.5),
        rotation: UnitQuaternion::rotation_between(&Vector3::z(), &Vector3::x()).unwrap(),
    });
    let mut set = StrandSet::new();
    set.push(StrandInput::uniform(anchor, rest, 1e-3, 1e-3, 0.0, 0.0))
        .unwrap();
    set.reset_to_rest(&Scalp::fixed());
    set
}

/// Runs one second and returns the solver and the strands at its end.
fn settle(rod: RodParams) -> (RodSolver, StrandSet) {
    let scalp = Scalp::fixed();
    let mut set = strands();
    let params = HairParams {
        air_drag: 25.0,
        ..HairParams::default()
    };
    let mut solver =
        RodSolver::new(SolverSettings::default(), params, rod, &set, &scalp, 1).unwrap();
    for _ in 0..24 {
        let report = solver.step_frame(&mut set, &scalp).unwrap();
        assert_eq!(report.projection.unconverged, 0, "{report:?}");
    }
    (solver, set)
}

fn sag(set: &StrandSet) -> f64 {
    0.5 - set.positions[SEGMENTS].z as f64
}

#[test]
fn elliptical_strand_bent_sideways_twists_to_bend_over_its_major_axis() {
    let e = 2e8f32;
    let ellipse = RodParams {
        youngs_modulus: e,
        semi_major_axis: 1e-3,
        axis_ratio: 0.5,
        ..RodParams::default()
    };
    let (solver, set) = settle(ellipse);
    let rod = solver.strand(0);
    let root = hair_core::rod::Root::of(&solver.roots()[0]);
    let x: Vec<_> = set.positions.iter().map(|p| p.cast::<f64>()).collect();
    let mut ws = Workspace::default();
    rod.update_twist(&x, &root, &solver.stiffness(), &mut ws);
    let minor = rod.minor_axis_bending(&ws);
    // Every bent segment's major axis is horizontal (along ±y).
    let worst_axis = (1..SEGMENTS)
        .map(|j| 1.0 - rod.material_axes(j, &ws).0.y.abs())
        .fold(0.0f64, f64::max);

    let round = |modulus: f32| RodParams {
        youngs_modulus: modulus,
        semi_major_axis: 1e-3,
        axis_ratio: 1.0,
        ..RodParams::default()
    };
    let (_, easy) = settle(round(e * 0.125));
    let (_, stiff) = settle(round(e * 0.5));
    println!(
        "sag: ellipse {:.5} m, round with E I₁ {:.5} m, round with E I₂ {:.5} m; minor-axis \
         bending / bending {minor:.2e}; worst |m1·y| deficit {worst_axis:.2e}",
        sag(&set),
        sag(&easy),
        sag(&stiff)
    );
    assert!(minor < 1e-6, "bending over the minor axis: {minor}");
    assert!(worst_axis < 1e-6, "major axes not horizontal: {worst_axis}");
    assert!(sag(&set) > 1.5 * sag(&stiff), "bent the stiff way");
    assert!(
        (sag(&set) / sag(&easy) - 1.0).abs() < 0.01,
        "sag {} vs round E I₁ {}",
        sag(&set),
        sag(&easy)
    );
}
