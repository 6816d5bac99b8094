//! Child generation: clumping, curl, determinism, level of detail, counts, attributes, bad input.

mod common;

use common::{bent, flatten, point, starts, straight};
use hair_core::{MeshSample, TriMesh};
use hair_render::{
    generate, ChildBuffers, ChildCount, ChildSettings, Clump, Curl, DisplayLod, Lod, Parents,
    Roughness, ScalpRoots, Shape,
};
use nalgebra::{Matrix3, Vector2, Vector3};

fn shaped() -> Shape {
    Shape {
        clump: Clump {
            factor: 0.7,
            shape: 0.8,
        },
        curl: Curl {
            radius: 0.003,
            frequency: 40.0,
        },
        roughness: Roughness {
            uniform: 2e-4,
            endpoint: 1e-3,
            smooth: 1e-3,
            ..Default::default()
        },
        length_variation: 0.2,
        ..Default::default()
    }
}

#[test]
fn clump_factor_one_puts_child_tips_on_the_parent_tip() {
    let strands = vec![
        bent(Vector3::zeros(), 9, 0.1),
        straight(Vector3::new(0.05, 0.0, 0.0), 6, 0.2),
    ];
    let (positions, offsets) = flatten(&strands);
    let parents = Parents::new(&positions, &offsets).unwrap();
    let settings = ChildSettings {
        count: ChildCount::PerParent(50),
        spread: 0.01,
        shape: Shape {
            clump: Clump {
                factor: 1.0,
                shape: 0.5,
            },
            ..Default::default()
        },
        ..Default::default()
    };
    let c = generate(&parents, &settings, Lod::Render).unwrap();
    let s = starts(&c);
    let mut worst = 0.0f32;
    let mut root_spread = 0.0f32;
    for k in 0..c.curve_count() {
        let p = c.parent[k] as usize;
        let tip = point(&c, s[k + 1] - 1);
        worst = worst.max((tip - strands[p].last().unwrap()).norm());
        root_spread = root_spread.max((point(&c, s[k]) - strands[p][0]).norm());
    }
    println!("clump 1: max |child tip − parent tip| = {worst:.3e} m (roots spread up to {root_spread:.4} m)");
    assert!(worst < 1e-6, "{worst}");
    assert!(
        root_spread > 0.005,
        "children must start spread out: {root_spread}"
    );
}

/// Least-squares circle (Kåsa) through the xy of `pts`: centre and radius.
fn fit_circle(pts: &[Vector3<f32>]) -> (Vector2<f64>, f64) {
    let mut a = Matrix3::<f64>::zeros();
    let mut b = nalgebra::Vector3::<f64>::zeros();
    for p in pts {
        let (x, y) = (f64::from(p.x), f64::from(p.y));
        let row = nalgebra::Vector3::new(x, y, 1.0);
        a += row * row.transpose();
        b += row * (x * x + y * y);
    }
    let sol = a.lu().solve(&b).unwrap();
    let c = Vector2::new(sol[0] / 2.0, sol[1] / 2.0);
    (c, (sol[2] + c.norm_squared()).sqrt())
}

#[test]
fn curl_radius_and_frequency_measured_on_the_curves_match_the_parameters() {
    let (radius, frequency, length) = (0.004f32, 50.0f32, 0.2f32);
    let (positions, offsets) = flatten(&[straight(Vector3::zeros(), 9, length)]);
    let parents = Parents::new(&positions, &offsets).unwrap();
    let settings = ChildSettings {
        count: ChildCount::PerParent(20),
        spread: 0.01,
        subdivisions: 32,
        shape: Shape {
            curl: Curl { radius, frequency },
            root_ramp: 0.05,
            ..Default::default()
        },
        ..Default::default()
    };
    let c = generate(&parents, &settings, Lod::Render).unwrap();
    let s = starts(&c);
    let (mut worst_r, mut worst_f) = (0.0f64, 0.0f64);
    for k in 0..c.curve_count() {
        let pts: Vec<_> = (s[k]..s[k + 1]).map(|i| point(&c, i)).collect();
        // Past the root ramp: a full-radius helix.
        let body: Vec<_> = pts
            .iter()
            .copied()
            .filter(|p| p.z > 0.06 * length)
            .collect();
        let (centre, r) = fit_circle(&body);
        let spread_r = (0..body.len())
            .map(|i| {
                let d = Vector2::new(f64::from(body[i].x), f64::from(body[i].y)) - centre;
                (d.norm() - r).abs()
            })
            .fold(0.0, f64::max);
        assert!(spread_r < 1e-5, "not a circle: {spread_r}");
        // Turns per meter from the unwrapped angle around the centre.
        let angle = |p: &Vector3<f32>| (f64::from(p.y) - centre.y).atan2(f64::from(p.x) - centre.x);
        let mut turns = 0.0;
        for w in body.windows(2) {
            let mut d = angle(&w[1]) - angle(&w[0]);
            d -= (d / std::f64::consts::TAU).round() * std::f64::consts::TAU;
            turns += d;
        }
        let dz = f64::from(body.last().unwrap().z - body[0].z);
        let f = turns.abs() / std::f64::consts::TAU / dz;
        worst_r = worst_r.max((r - f64::from(radius)).abs());
        worst_f = worst_f.max((f - f64::from(frequency)).abs());
        if k == 0 {
            println!("curl: measured radius {r:.6} m (parameter {radius}), {f:.3} turns/m (parameter {frequency})");
        }
    }
    println!("curl: worst radius error {worst_r:.3e} m, worst frequency error {worst_f:.3e} turns/m over 20 children");
    assert!(worst_r < 1e-6, "radius error {worst_r}");
    assert!(worst_f < 0.05, "frequency error {worst_f}");
}

fn scene() -> (Vec<Vector3<f32>>, Vec<u32>) {
    flatten(&[
        bent(Vector3::zeros(), 12, 0.1),
        straight(Vector3::new(0.03, 0.0, 0.0), 7, 0.15),
        bent(Vector3::new(0.0, 0.04, 0.0), 5, 0.05),
    ])
}

#[test]
fn same_seed_gives_identical_children_and_another_seed_others() {
    let (positions, offsets) = scene();
    let parents = Parents::new(&positions, &offsets).unwrap();
    let mut settings = ChildSettings {
        count: ChildCount::Total(1000),
        shape: shaped(),
        seed: 42,
        ..Default::default()
    };
    let a = generate(&parents, &settings, Lod::Render).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let b = pool.install(|| generate(&parents, &settings, Lod::Render).unwrap());
    let bits = |c: &ChildBuffers| c.points.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(
        bits(&a),
        bits(&b),
        "same seed, different thread count: must be bit-identical"
    );
    assert_eq!(a, b);
    settings.seed = 43;
    let c = generate(&parents, &settings, Lod::Render).unwrap();
    assert_eq!(a.vertex_counts, c.vertex_counts);
    let differ = a
        .points
        .iter()
        .zip(&c.points)
        .filter(|(x, y)| x != y)
        .count();
    println!(
        "seed 42 vs 43: {differ} of {} coordinates differ",
        a.points.len()
    );
    assert!(differ > a.points.len() / 2);
    assert_ne!(a.random, c.random);
}

#[test]
fn display_level_is_a_subset_of_render_level() {
    let (positions, offsets) = scene();
    let parents = Parents::new(&positions, &offsets).unwrap();
    let settings = ChildSettings {
        count: ChildCount::PerParent(40),
        subdivisions: 4,
        shape: shaped(),
        ..Default::default()
    };
    let render = generate(&parents, &settings, Lod::Render).unwrap();
    let display = generate(
        &parents,
        &settings,
        Lod::Display(DisplayLod {
            fraction: 0.25,
            subdivisions: 2,
        }),
    )
    .unwrap();
    assert_eq!(display.curve_count(), 30);
    assert!(display.point_count() * 6 < render.point_count());
    let (rs, ds) = (starts(&render), starts(&display));
    let mut worst = 0.0f32;
    for (d, &p) in display.parent.iter().enumerate() {
        // Display child d is child k of its parent; the render child of the same identity:
        let k = display.parent[..d].iter().filter(|&&q| q == p).count();
        let r = render.parent.iter().position(|&q| q == p).unwrap() + k;
        assert_eq!(render.parent[r], p);
        assert_eq!(render.random[r].to_bits(), display.random[d].to_bits());
        assert_eq!(
            point(&render, rs[r]),
            point(&display, ds[d]),
            "roots identical"
        );
        // Display point j lies where render point 2j does (render has twice the steps).
        for j in 0..display.vertex_counts[d] as usize {
            let e = (point(&render, rs[r] + 2 * j) - point(&display, ds[d] + j)).norm();
            worst = worst.max(e);
        }
    }
    println!(
        "display vs render: worst distance at shared parameters {worst:.3e} m (curl radius 3 mm)"
    );
    assert!(worst < 1e-3, "{worst}");
}

#[test]
fn counts_total_and_per_parent() {
    let (positions, offsets) = scene();
    let parents = Parents::new(&positions, &offsets).unwrap();
    let total = ChildSettings {
        count: ChildCount::Total(100),
        subdivisions: 1,
        ..Default::default()
    };
    let c = generate(&parents, &total, Lod::Render).unwrap();
    assert_eq!(c.curve_count(), 100);
    assert_eq!(c.parent.iter().filter(|&&p| p == 0).count(), 33);
    assert_eq!(
        c.vertex_counts[0], 12,
        "subdivisions 1 keeps the parent's points"
    );
    assert!(c.widths[0] > c.widths[11], "taper");
}

#[test]
fn root_uvs_and_colors_come_from_the_scalp() {
    let mesh = TriMesh::new(
        vec![
            Vector3::new(-1.0, -1.0, 0.0),
            Vector3::new(1.0, -1.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
        ],
        vec![[0, 1, 2]],
    )
    .unwrap()
    .with_uvs(vec![
        Vector2::new(0.0, 0.0),
        Vector2::new(1.0, 0.0),
        Vector2::new(0.5, 1.0),
    ])
    .unwrap();
    let sample = MeshSample {
        triangle: 0,
        weights: [0.5, 0.25, 0.25],
    };
    let root = mesh.evaluate(&sample).origin;
    // The parent leaves the surface at an angle: the root frame (surface normal) differs from
    // its first segment.
    let strand: Vec<_> = (0..5)
        .map(|i| root + Vector3::new(0.02, 0.0, 0.05) * i as f32)
        .collect();
    let (positions, offsets) = flatten(&[strand]);
    let colors = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let samples = [Some(sample)];
    let parents = Parents::new(&positions, &offsets)
        .unwrap()
        .with_scalp(ScalpRoots {
            mesh: &mesh,
            samples: &samples,
            colors: Some(&colors),
        })
        .unwrap();
    let c = generate(&parents, &ChildSettings::default(), Lod::Render).unwrap();
    let uv = c.root_uv.as_ref().unwrap();
    assert_eq!(&uv[..2], &[0.375, 0.25]);
    assert_eq!(&c.color.as_ref().unwrap()[..3], &[0.5, 0.25, 0.25]);
    // Roots sit on the scalp plane (z = 0), in the spread disc.
    for s in &starts(&c)[..c.curve_count()] {
        let p = point(&c, *s);
        assert!(
            p.z.abs() < 1e-7 && (p - root).norm() <= 0.005 + 1e-6,
            "{p:?}"
        );
    }
}

#[test]
fn bad_settings_name_the_parameter() {
    let (positions, offsets) = scene();
    let parents = Parents::new(&positions, &offsets).unwrap();
    let err = |s: ChildSettings| generate(&parents, &s, Lod::Render).unwrap_err().to_string();
    let base = ChildSettings::default();
    let e = err(ChildSettings {
        count: ChildCount::PerParent(0),
        ..base
    });
    assert!(
        e.contains("children_per_parent") && e.contains("at least 1"),
        "{e}"
    );
    let e = err(ChildSettings {
        count: ChildCount::Total(0),
        ..base
    });
    assert!(e.contains("`count`"), "{e}");
    let mut nan = base;
    nan.shape.curl.radius = f32::NAN;
    let e = err(nan);
    assert!(e.contains("shape.curl.radius") && e.contains("NaN"), "{e}");
    let mut neg = base;
    neg.spread = -1.0;
    assert!(err(neg).contains("spread"));
    let mut zero = base;
    zero.subdivisions = 0;
    assert!(err(zero).contains("subdivisions"));
    let e = Parents::new(&positions, &offsets)
        .unwrap()
        .with_spread_radii(&[0.01])
        .unwrap_err()
        .to_string();
    assert!(e.contains("1 spread radii for 3 parents"), "{e}");
}

#[test]
fn generate_into_reused_buffers_equals_generate() {
    let (positions, offsets) = scene();
    let parents = Parents::new(&positions, &offsets).unwrap();
    let big = ChildSettings {
        count: ChildCount::PerParent(30),
        shape: shaped(),
        ..Default::default()
    };
    let small = ChildSettings {
        count: ChildCount::PerParent(7),
        seed: 3,
        ..big
    };
    // Buffers left over from another export (more curves, and UVs the new parents lack).
    let mut out = ChildBuffers {
        root_uv: Some(vec![0.5; 4]),
        ..generate(&parents, &big, Lod::Render).unwrap()
    };
    hair_render::generate_into(&parents, &small, Lod::Render, &mut out).unwrap();
    assert_eq!(out, generate(&parents, &small, Lod::Render).unwrap());
    hair_render::generate_into(&parents, &big, Lod::Render, &mut out).unwrap();
    assert_eq!(out, generate(&parents, &big, Lod::Render).unwrap());
    // A refused request leaves the buffers as they were.
    let before = out.clone();
    let bad = ChildSettings {
        count: ChildCount::PerParent(0),
        ..big
    };
    assert!(hair_render::generate_into(&parents, &bad, Lod::Render, &mut out).is_err());
    assert_eq!(out, before);
}
