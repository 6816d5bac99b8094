//! Mesh samples and simulation hairs across crates: Poisson-disk roots stay on the same material
//! point of a deforming mesh, and sim hairs interpolated from the real Sintel guides have rest
//! lengths within their guides' range and become solver strands.
//!
//! References: a sample's position is the barycentric combination of its triangle's corners, on
//! the deformed corners too (up to f32 rounding of that combination); a length-preserving blend
//! gives a length that is a weighted mean of the blended guides' lengths.

use std::path::Path;

use hair_core::{Scalp, StrandSet};
use hair_groom::{
    builtin_head, interpolate, load_obj, read_tfx, sample_poisson_disk, snap_to_scalp,
    ImportOptions, InterpolateOptions, Region, SnapOptions, UpAxis,
};
use nalgebra::Vector3;

const TFX: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../data/sintel/sintel_hair.tfx"
);
const BUST: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../data/sintel/sintel_bust.obj"
);

#[test]
fn samples_follow_a_deforming_mesh_exactly() {
    let mut mesh = builtin_head();
    let samples = sample_poisson_disk(&mesh, 0.012, 8, &Region::All, None).unwrap();
    let uvs: Vec<_> = samples.iter().map(|s| mesh.sample_uv(s).unwrap()).collect();
    // A non-rigid deformation: squash, twist about z and bulge.
    let deformed: Vec<Vector3<f32>> = mesh
        .positions()
        .iter()
        .map(|p| {
            let a = 2.0 * p.z;
            let (s, c) = a.sin_cos();
            Vector3::new(
                1.2 * (c * p.x - s * p.y),
                s * p.x + c * p.y,
                0.8 * p.z + 0.3 * p.x * p.x,
            )
        })
        .collect();
    mesh.set_positions(&deformed).unwrap();
    let mut worst = 0.0f32;
    for (s, uv) in samples.iter().zip(&uvs) {
        let [a, b, c] = mesh.corners(s.triangle as usize);
        let expect = a * s.weights[0] + b * s.weights[1] + c * s.weights[2];
        worst = worst.max((mesh.evaluate(s).origin - expect).norm());
        assert_eq!(
            mesh.sample_uv(s).unwrap(),
            *uv,
            "UVs do not move with the mesh"
        );
    }
    println!(
        "{} samples; largest deviation from the barycentric point: {worst:.1e} m",
        samples.len()
    );
    assert!(worst <= 1e-7);
}

#[test]
fn sintel_sim_hairs_stay_within_their_guides() {
    let opts = ImportOptions {
        scale: 0.01,
        up_axis: UpAxis::Y,
    };
    let groom = read_tfx(Path::new(TFX), &opts).unwrap();
    let bust = load_obj(Path::new(BUST), &opts).unwrap();
    let guides = snap_to_scalp(
        &groom,
        &bust,
        &SnapOptions {
            max_distance: 0.025,
        },
    )
    .unwrap()
    .guides;
    // Sim roots: Poisson-disk samples 6 mm apart over the bust, kept where a guide root is
    // within 15 mm (the hairline region).
    let roots: Vec<_> = sample_poisson_disk(&bust, 0.006, 3, &Region::All, None)
        .unwrap()
        .into_iter()
        .filter(|s| {
            let p = bust.evaluate(s).origin;
            guides
                .iter()
                .any(|g| (bust.evaluate(&g.root).origin - p).norm() < 0.015)
        })
        .collect();
    let on = vec![true; guides.len()];
    let hairs = interpolate(
        &bust,
        &guides,
        &on,
        &roots,
        &InterpolateOptions {
            k: 4,
            points: 32,
            distance: hair_groom::Distance::Surface,
        },
    )
    .unwrap();
    let length =
        |r: &[Vector3<f32>]| -> f64 { r.windows(2).map(|w| f64::from((w[1] - w[0]).norm())).sum() };
    let mut set = StrandSet::new();
    for h in &hairs {
        let used: Vec<f64> = h
            .sources
            .iter()
            .filter(|s| s.weight > 0.0)
            .map(|s| length(&guides[s.guide].rest))
            .collect();
        let lo = used.iter().copied().fold(f64::MAX, f64::min);
        let hi = used.iter().copied().fold(0.0, f64::max);
        let l = length(&h.rest);
        assert!(l >= lo - 1e-6 && l <= hi + 1e-6, "{l} outside {lo}..{hi}");
        set.push(hair_core::StrandInput::uniform(
            hair_core::Anchor::Surface(h.root),
            h.rest.clone(),
            1e-4,
            5e-4,
            1.0,
            0.2,
        ))
        .unwrap();
    }
    println!(
        "{} sim hairs from {} guides, {} points",
        hairs.len(),
        guides.len(),
        set.point_count()
    );
    assert!(hairs.len() > 500, "{} sim hairs", hairs.len());
    let scalp = Scalp {
        mesh: Some(bust),
        ..Scalp::fixed()
    };
    set.validate_anchors(&scalp).unwrap();
}
