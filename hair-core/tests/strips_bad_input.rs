//! Strip model bad input: coincident edge strands, zero-area or too small scalp triangles and an
//! angle limit outside (0, π) are refused with errors that name the item and the fix.

use std::f32::consts::PI;

use hair_core::model::strips::{RootAngleLimit, StripGrowth, StripSet};
use hair_core::{Anchor, HairError, RootFrame, Scalp, StrandInput, TriMesh};
use nalgebra::Vector3;

fn strand(origin: Vector3<f32>, points: usize) -> StrandInput {
    let rest = (0..points)
        .map(|i| Vector3::new(0.0, 0.0, 0.02 * i as f32))
        .collect();
    StrandInput::uniform(
        Anchor::Body(RootFrame::at(origin)),
        rest,
        1e-3,
        1e-3,
        0.0,
        0.0,
    )
}

#[test]
fn coincident_edge_strands_are_refused_naming_the_strip() {
    let a = Vector3::new(0.1, 0.0, 0.0);
    let pairs = vec![
        (strand(Vector3::zeros(), 5), strand(a, 5)),
        (strand(a, 5), strand(a, 5)),
    ];
    let err = StripSet::from_pairs(pairs, 10, &Scalp::fixed()).unwrap_err();
    let text = err.to_string();
    assert!(matches!(err, HairError::Strand { strand: 2, .. }), "{text}");
    assert!(
        text.contains("strip 1") && text.contains("coincident"),
        "{text}"
    );
}

#[test]
fn edges_with_different_point_counts_are_refused() {
    let pairs = vec![(strand(Vector3::zeros(), 5), strand(Vector3::x(), 6))];
    let text = StripSet::from_pairs(pairs, 10, &Scalp::fixed())
        .unwrap_err()
        .to_string();
    assert!(text.contains("same number of points"), "{text}");
}

#[test]
fn zero_area_scalp_triangle_is_refused_naming_the_triangle() {
    let positions = vec![
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(1.0, 0.0, 0.0),
        Vector3::new(0.0, 1.0, 0.0),
        Vector3::new(2.0, 0.0, 0.0),
    ];
    // Triangle 1 is a straight line (0, 1, 3): zero area.
    let text = TriMesh::new(positions, vec![[0, 1, 2], [0, 1, 3]])
        .unwrap_err()
        .to_string();
    assert!(
        text.contains("triangle 1") && text.contains("degenerate"),
        "{text}"
    );
}

#[test]
fn scalp_triangle_too_small_for_a_strip_is_refused() {
    // A valid mesh 3 µm across: every strip on it would be narrower than 10 µm.
    let s = 3e-6;
    let mesh = TriMesh::new(
        vec![
            Vector3::zeros(),
            Vector3::new(s, 0.0, 0.0),
            Vector3::new(0.0, s, 0.0),
        ],
        vec![[0, 1, 2]],
    )
    .unwrap();
    let text = StripSet::from_triangles(&mesh, &[0], &StripGrowth::default())
        .unwrap_err()
        .to_string();
    assert!(
        text.contains("scalp triangle 0") && text.contains("too small"),
        "{text}"
    );
    let text = StripSet::from_triangles(&mesh, &[4], &StripGrowth::default())
        .unwrap_err()
        .to_string();
    assert!(text.contains("out of range"), "{text}");
}

#[test]
fn angle_limit_outside_zero_to_pi_is_refused() {
    for bad in [0.0, -0.1, PI, 4.0, f32::NAN, f32::INFINITY] {
        let err = RootAngleLimit::new(bad).unwrap_err();
        assert!(
            err.to_string().contains("strictly between 0° and 180°"),
            "{bad}: {err}"
        );
    }
    for good in [1e-3, 1.0, PI - 1e-3] {
        assert_eq!(RootAngleLimit::new(good).unwrap().radians(), good);
    }
}
