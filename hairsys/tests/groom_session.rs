//! `Session::from_groom` (a groom and scalp given as arrays) and `Session::children`.

use hair_core::{Anchor, HairParams};
use hair_render::{ChildCount, ChildSettings, Lod};
use hairsys::build::groom::{GroomArrays, GroomOptions, SimHairs};
use hairsys::{Error, Session};
use nalgebra::{Isometry3, Vector3};

/// A groom as owned arrays: scalp vertices, scalp triangles, curve points, points per curve.
struct Groom(Vec<[f32; 3]>, Vec<[u32; 3]>, Vec<[f32; 3]>, Vec<u32>);

/// A UV sphere of radius 0.1 m as arrays, and `n` straight curves of `points` points along the
/// outward normal at vertices of its upper half (roots exactly on the surface).
fn sphere_groom(n: usize, points: usize) -> Groom {
    let mesh = hair_groom::uv_sphere(0.1, 16, 8).unwrap();
    let vertices: Vec<[f32; 3]> = mesh.positions().iter().map(|p| [p.x, p.y, p.z]).collect();
    let triangles = mesh.triangles().to_vec();
    let mut curve_points = Vec::new();
    let mut counts = Vec::new();
    for p in mesh
        .positions()
        .iter()
        .filter(|p| p.z > 0.02 && p.z < 0.099)
        .take(n)
    {
        let normal = p.normalize();
        for j in 0..points {
            let q = p + normal * (0.02 * j as f32);
            curve_points.push([q.x, q.y, q.z]);
        }
        counts.push(points as u32);
    }
    assert_eq!(
        counts.len(),
        n,
        "the sphere has enough vertices for the test"
    );
    Groom(vertices, triangles, curve_points, counts)
}

fn arrays<'a>(g: &'a Groom, weights: Option<&'a [f32]>) -> GroomArrays<'a> {
    GroomArrays {
        scalp_vertices: &g.0,
        scalp_triangles: &g.1,
        scalp_uvs: None,
        curve_points: &g.2,
        curve_counts: &g.3,
        goal_weights: weights,
        pinned: None,
        strand_scales: None,
    }
}

#[test]
fn groom_session_starts_at_the_curves_rest_shape() {
    let g = sphere_groom(12, 5);
    let s = Session::from_groom(&arrays(&g, None), &GroomOptions::default()).unwrap();
    assert_eq!(s.strands().len(), 12);
    assert_eq!(s.strand_offsets().len(), 13);
    for (p, q) in s.positions().iter().zip(&g.2) {
        let d = (Vector3::from(*p) - Vector3::from(*q)).norm();
        assert!(d < 1e-5, "point moved by {d} m at rest");
    }
}

#[test]
fn roots_follow_a_deforming_scalp_by_their_barycentric_weights() {
    let g = sphere_groom(12, 5);
    let mut s = Session::from_groom(&arrays(&g, None), &GroomOptions::default()).unwrap();
    for frame in 1..=6 {
        // Squash and shear the sphere a little more every frame.
        let t = frame as f32 * 0.05;
        let deformed: Vec<[f32; 3]> =
            g.0.iter()
                .map(|v| [v[0] + t * v[2], v[1] * (1.0 + t), v[2] * (1.0 - 0.5 * t)])
                .collect();
        s.set_scalp_vertices(&deformed, Isometry3::identity())
            .unwrap();
        s.step().unwrap();
        let offsets = s.strand_offsets().to_vec();
        for (k, anchor) in s.strands().anchors().iter().enumerate() {
            let Anchor::Surface(sample) = anchor else {
                panic!("groom strands are rooted on the scalp")
            };
            let tri = g.1[sample.triangle as usize];
            let expected: Vector3<f32> = (0..3)
                .map(|c| Vector3::from(deformed[tri[c] as usize]) * sample.weights[c])
                .sum();
            let root = Vector3::from(s.positions()[offsets[k] as usize]);
            assert!(
                (root - expected).norm() < 1e-6,
                "frame {frame}: root of strand {k} is {} m off its barycentric point",
                (root - expected).norm()
            );
        }
    }
}

#[test]
fn wrong_curve_counts_are_refused_by_name() {
    let mut g = sphere_groom(3, 4);
    g.3[1] = 7;
    let e = Session::from_groom(&arrays(&g, None), &GroomOptions::default()).unwrap_err();
    assert!(
        matches!(&e, Error::Argument { argument, .. } if argument == "curve_counts"),
        "{e}"
    );
    let g = sphere_groom(3, 4);
    let bad = vec![0.5; g.2.len() - 1];
    let e = Session::from_groom(&arrays(&g, Some(&bad)), &GroomOptions::default()).unwrap_err();
    assert!(
        matches!(&e, Error::Argument { argument, .. } if argument == "goal_weights"),
        "{e}"
    );
    let bad = vec![1.5; g.2.len()];
    let e = Session::from_groom(&arrays(&g, Some(&bad)), &GroomOptions::default()).unwrap_err();
    assert!(e.to_string().contains("from 0 to 1"), "{e}");
}

#[test]
fn roots_far_from_the_scalp_are_refused() {
    let mut g = sphere_groom(3, 4);
    for p in &mut g.2[4..8] {
        p[2] += 0.5;
    }
    let e = Session::from_groom(&arrays(&g, None), &GroomOptions::default()).unwrap_err();
    assert!(
        matches!(&e, Error::Argument { argument, .. } if argument == "curve_points"),
        "{e}"
    );
}

#[test]
fn per_point_goal_weights_reach_the_strands_and_pin_them() {
    let g = sphere_groom(6, 5);
    let weights: Vec<f32> = (0..g.2.len())
        .map(|i| if i % 5 == 4 { 1.0 } else { 0.25 })
        .collect();
    let options = GroomOptions {
        physics: HairParams {
            goal_stiffness: 50.0,
            ..HairParams::default()
        },
        ..GroomOptions::default()
    };
    let s = Session::from_groom(&arrays(&g, Some(&weights)), &options).unwrap();
    assert_eq!(s.strands().goal_weights(), &weights[..]);

    // Interpolated hairs blend their guides' weights: constant guide weights stay constant.
    let constant = vec![0.75; g.2.len()];
    let options = GroomOptions {
        sim_hairs: SimHairs::Interpolated {
            count: 40,
            k: 3,
            points: Some(9),
            seed: 7,
        },
        ..GroomOptions::default()
    };
    let s = Session::from_groom(&arrays(&g, Some(&constant)), &options).unwrap();
    assert_eq!(s.strands().len(), 40);
    assert_eq!(s.strands().point_count(), 40 * 9);
    for w in s.strands().goal_weights() {
        assert!((w - 0.75).abs() < 1e-6, "blended weight {w}");
    }
}

#[test]
fn children_of_a_session_follow_its_strands() {
    let g = sphere_groom(8, 5);
    let mut s = Session::from_groom(&arrays(&g, None), &GroomOptions::default()).unwrap();
    s.step().unwrap();
    let settings = ChildSettings {
        count: ChildCount::PerParent(3),
        subdivisions: 1,
        ..ChildSettings::default()
    };
    let c = s.children(&settings, Lod::Render, None).unwrap();
    assert_eq!(c.curve_count(), 8 * 3);
    // Each child's root lies within the spread disc of its parent's root.
    let offsets = s.strand_offsets();
    let mut start = 0usize;
    for (i, &n) in c.vertex_counts.iter().enumerate() {
        let root = Vector3::new(
            c.points[3 * start],
            c.points[3 * start + 1],
            c.points[3 * start + 2],
        );
        let parent = c.parent[i] as usize;
        let proot = Vector3::from(s.positions()[offsets[parent] as usize]);
        assert!((root - proot).norm() <= settings.spread * 1.01 + 1e-6);
        start += n as usize;
    }
    let e = s
        .children(&settings, Lod::Render, Some(&[[1.0, 0.0, 0.0]]))
        .unwrap_err();
    assert!(
        matches!(&e, Error::Argument { argument, .. } if argument == "colors"),
        "{e}"
    );
}

#[test]
fn a_groom_session_records_a_readable_cache_named_by_its_start() {
    let dir = tempfile::tempdir().unwrap();
    let g = sphere_groom(5, 4);
    let mut hashes = Vec::new();
    for name in ["a.mcap", "b.mcap"] {
        let mut s = Session::from_groom(&arrays(&g, None), &GroomOptions::default()).unwrap();
        s.record(&dir.path().join(name), Default::default())
            .unwrap();
        s.step().unwrap();
        let summary = s.finish_recording().unwrap();
        assert_eq!(summary.frames, 2);
        let reader = hair_cache::CacheReader::open(dir.path().join(name)).unwrap();
        hashes.push(reader.header().scene_hash.clone());
    }
    assert_eq!(hashes[0], hashes[1], "the same start gives the same hash");
    assert_eq!(hashes[0].len(), 64);
}
