//! Interpolated children (between several parents): a child at a parent's root is that parent,
//! translated copies of one shape give translated children, parents of other point counts blend
//! by length fraction, roots and attributes come from the scalp, clumping draws tips onto the
//! home parent, determinism by seed.

mod common;

use common::{bent, flatten, point, starts, straight};
use hair_core::{MeshSample, TriMesh};
use hair_render::subdivide::catmull_rom;
use hair_render::{
    generate, ChildBuffers, ChildCount, ChildMode, ChildSettings, Clump, Curl, Lod, Parents,
    Roughness, ScalpRoots, Shape,
};
use nalgebra::{Vector2, Vector3};

fn interpolated(count: ChildCount, spread: f32, shape: Shape) -> ChildSettings {
    ChildSettings {
        count,
        spread,
        shape,
        mode: ChildMode::Interpolated { neighbours: 4 },
        ..Default::default()
    }
}

/// Three different parents a few centimetres apart.
fn mixed() -> Vec<Vec<Vector3<f32>>> {
    vec![
        bent(Vector3::zeros(), 9, 0.1),
        straight(Vector3::new(0.02, 0.0, 0.0), 6, 0.15),
        bent(Vector3::new(0.0, 0.03, 0.0), 5, 0.05),
        straight(Vector3::new(0.025, 0.025, 0.0), 7, 0.08),
    ]
}

#[test]
fn child_rooted_at_a_parent_root_reproduces_that_parent() {
    let strands = mixed();
    let (positions, offsets) = flatten(&strands);
    let parents = Parents::new(&positions, &offsets).unwrap();
    // Spread 0: every child sits on its home parent's root. Shaping off.
    let settings = interpolated(ChildCount::PerParent(3), 0.0, Shape::default());
    let c = generate(&parents, &settings, Lod::Render).unwrap();
    let s = starts(&c);
    let mut worst = 0.0f32;
    for (k, &p) in c.parent.iter().enumerate() {
        let p = p as usize;
        let mut want = Vec::new();
        catmull_rom(&strands[p], settings.subdivisions, &mut want);
        assert_eq!(c.vertex_counts[k] as usize, want.len());
        for (j, w) in want.iter().enumerate() {
            worst = worst.max((point(&c, s[k] + j) - w).norm());
        }
    }
    println!("child at a parent root vs that parent: worst {worst:.3e} m");
    assert!(worst < 1e-6, "{worst}");
}

#[test]
fn parents_identical_up_to_translation_give_translated_children() {
    // A 5 × 5 grid of the same bent parent, 1 cm apart; children spread over 8 mm discs blend
    // four of them each.
    let shape = bent(Vector3::zeros(), 8, 0.07);
    let strands: Vec<_> = (0..25)
        .map(|i| {
            let d = Vector3::new(0.01 * (i % 5) as f32, 0.01 * (i / 5) as f32, 0.0);
            shape.iter().map(|p| p + d).collect::<Vec<_>>()
        })
        .collect();
    let (positions, offsets) = flatten(&strands);
    let parents = Parents::new(&positions, &offsets).unwrap();
    let settings = ChildSettings {
        subdivisions: 1,
        ..interpolated(ChildCount::PerParent(8), 0.008, Shape::default())
    };
    let c = generate(&parents, &settings, Lod::Render).unwrap();
    let s = starts(&c);
    let mut worst = 0.0f32;
    let mut moved = 0.0f32;
    for k in 0..c.curve_count() {
        let root = point(&c, s[k]);
        let home = strands[c.parent[k] as usize][0];
        moved = moved.max((root - home).norm());
        for (j, p) in shape.iter().enumerate() {
            worst = worst.max((point(&c, s[k] + j) - root - (p - shape[0])).norm());
        }
    }
    println!("translated parents: worst deviation from the translated shape {worst:.3e} m (roots up to {moved:.4} m from home)");
    assert!(worst < 1e-6, "{worst}");
    assert!(moved > 0.004, "children spread between parents: {moved}");
}

#[test]
fn interpolated_children_blend_between_parents() {
    // Two straight parents of different lengths 1 cm apart: a child halfway is as long as their
    // mean, and every child lies within their lengths.
    let strands = vec![
        straight(Vector3::zeros(), 5, 0.1),
        straight(Vector3::new(0.01, 0.0, 0.0), 5, 0.2),
    ];
    let (positions, offsets) = flatten(&strands);
    let parents = Parents::new(&positions, &offsets).unwrap();
    let settings = ChildSettings {
        mode: ChildMode::Interpolated { neighbours: 2 },
        ..interpolated(ChildCount::PerParent(50), 0.01, Shape::default())
    };
    let c = generate(&parents, &settings, Lod::Render).unwrap();
    let s = starts(&c);
    let (mut shortest, mut longest) = (f32::MAX, 0.0f32);
    for k in 0..c.curve_count() {
        let len = (point(&c, s[k + 1] - 1) - point(&c, s[k])).norm();
        shortest = shortest.min(len);
        longest = longest.max(len);
    }
    println!("blend of 0.1 m and 0.2 m parents: child lengths {shortest:.4}–{longest:.4} m");
    assert!(shortest >= 0.1 - 1e-5 && longest <= 0.2 + 1e-5);
    assert!(
        longest - shortest > 0.03,
        "lengths vary between the parents"
    );
}

#[test]
fn parents_with_other_point_counts_blend_by_length_fraction() {
    // Two straight 10 cm parents 1 cm apart, of 5 and 9 points: resampled by point index to the
    // home parent's count, both are the same straight line, so every child (short or not) is a
    // straight vertical line from its root with evenly spaced points.
    let strands = vec![
        straight(Vector3::zeros(), 5, 0.1),
        straight(Vector3::new(0.01, 0.0, 0.0), 9, 0.1),
    ];
    let (positions, offsets) = flatten(&strands);
    let parents = Parents::new(&positions, &offsets).unwrap();
    for variation in [0.0, 0.3] {
        let settings = ChildSettings {
            mode: ChildMode::Interpolated { neighbours: 2 },
            subdivisions: 1,
            ..interpolated(
                ChildCount::PerParent(40),
                0.01,
                Shape {
                    length_variation: variation,
                    ..Shape::default()
                },
            )
        };
        let c = generate(&parents, &settings, Lod::Render).unwrap();
        let s = starts(&c);
        let (mut worst, mut shortest, mut longest) = (0.0f32, f32::MAX, 0.0f32);
        for k in 0..c.curve_count() {
            let n = s[k + 1] - s[k];
            let (root, tip) = (point(&c, s[k]), point(&c, s[k + 1] - 1));
            shortest = shortest.min(tip.z - root.z);
            longest = longest.max(tip.z - root.z);
            for i in 0..n {
                let want = root + (tip - root) * (i as f32 / (n - 1) as f32);
                worst = worst.max((point(&c, s[k] + i) - want).norm());
                worst = worst.max((point(&c, s[k] + i).xy() - root.xy()).norm());
            }
        }
        println!(
            "5- and 9-point parents, length variation {variation}: off the line {worst:.3e} m, \
             lengths {shortest:.4}–{longest:.4} m"
        );
        assert!(worst < 1e-6, "{worst}");
        assert!(longest <= 0.1 + 1e-6, "{longest}");
        if variation == 0.0 {
            assert!(shortest >= 0.1 - 1e-6, "{shortest}");
        } else {
            assert!(shortest >= 0.07 - 1e-6 && longest - shortest > 0.01);
        }
    }
}

/// A flat 10 cm square scalp at z = 0 whose UV is (x, y) / 0.1 and whose color is red in x,
/// green in y; `n × n` parents on it.
fn square_scalp(n: usize) -> (TriMesh, Vec<Option<MeshSample>>) {
    let mesh = TriMesh::new(
        vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(0.1, 0.0, 0.0),
            Vector3::new(0.1, 0.1, 0.0),
            Vector3::new(0.0, 0.1, 0.0),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    )
    .unwrap()
    .with_uvs(vec![
        Vector2::new(0.0, 0.0),
        Vector2::new(1.0, 0.0),
        Vector2::new(1.0, 1.0),
        Vector2::new(0.0, 1.0),
    ])
    .unwrap();
    let mut samples = Vec::new();
    for i in 0..n * n {
        let (u, v) = (
            (0.5 + (i % n) as f32) / n as f32,
            (0.5 + (i / n) as f32) / n as f32,
        );
        // Barycentric weights in triangle 0 (below the diagonal) or 1.
        samples.push(Some(if u >= v {
            MeshSample {
                triangle: 0,
                weights: [1.0 - u, u - v, v],
            }
        } else {
            MeshSample {
                triangle: 1,
                weights: [1.0 - v, u, v - u],
            }
        }));
    }
    (mesh, samples)
}

#[test]
fn interpolated_roots_lie_on_the_scalp_with_its_uv_and_color() {
    let (mesh, samples) = square_scalp(4);
    let strands: Vec<_> = samples
        .iter()
        .map(|s| bent(mesh.evaluate(&s.unwrap()).origin, 6, 0.05))
        .collect();
    let (positions, offsets) = flatten(&strands);
    let colors = [
        [0.0, 0.0, 0.5],
        [1.0, 0.0, 0.5],
        [1.0, 1.0, 0.5],
        [0.0, 1.0, 0.5],
    ];
    let parents = Parents::new(&positions, &offsets)
        .unwrap()
        .with_scalp(ScalpRoots {
            mesh: &mesh,
            samples: &samples,
            colors: Some(&colors),
        })
        .unwrap();
    let settings = interpolated(ChildCount::Total(400), 0.02, Shape::default());
    let c = generate(&parents, &settings, Lod::Render).unwrap();
    let (uv, rgb) = (c.root_uv.as_ref().unwrap(), c.color.as_ref().unwrap());
    let s = starts(&c);
    let mut distinct_uvs = std::collections::BTreeSet::new();
    for k in 0..c.curve_count() {
        let r = point(&c, s[k]);
        // On the square (snapped onto it, clamped at its border), UV and color from the mesh.
        assert!(r.z.abs() < 1e-7, "root off the scalp: {r:?}");
        assert!((-1e-6..=0.1 + 1e-6).contains(&r.x) && (-1e-6..=0.1 + 1e-6).contains(&r.y));
        let want_uv = [r.x / 0.1, r.y / 0.1];
        assert!(
            (uv[2 * k] - want_uv[0]).abs() < 1e-4 && (uv[2 * k + 1] - want_uv[1]).abs() < 1e-4,
            "child {k}: uv {:?} at {r:?}",
            &uv[2 * k..2 * k + 2]
        );
        assert!(
            (rgb[3 * k] - want_uv[0]).abs() < 1e-4 && (rgb[3 * k + 1] - want_uv[1]).abs() < 1e-4
        );
        distinct_uvs.insert((uv[2 * k].to_bits(), uv[2 * k + 1].to_bits()));
    }
    assert!(distinct_uvs.len() > 390, "every child has its own root UV");
}

#[test]
fn clump_one_puts_interpolated_tips_on_the_home_parent_tip() {
    let strands = mixed();
    let (positions, offsets) = flatten(&strands);
    let parents = Parents::new(&positions, &offsets).unwrap();
    let shape = Shape {
        clump: Clump {
            factor: 1.0,
            shape: 1.0,
        },
        ..Default::default()
    };
    let c = generate(
        &parents,
        &interpolated(ChildCount::PerParent(20), 0.01, shape),
        Lod::Render,
    )
    .unwrap();
    let s = starts(&c);
    let mut worst = 0.0f32;
    for k in 0..c.curve_count() {
        let tip = point(&c, s[k + 1] - 1);
        worst = worst.max((tip - strands[c.parent[k] as usize].last().unwrap()).norm());
    }
    assert!(worst < 1e-6, "{worst}");
}

#[test]
fn interpolated_children_are_identical_for_the_same_seed_and_differ_for_another() {
    let strands = mixed();
    let (positions, offsets) = flatten(&strands);
    let parents = Parents::new(&positions, &offsets).unwrap();
    let shape = Shape {
        curl: Curl {
            radius: 0.002,
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
    };
    let mut settings = ChildSettings {
        seed: 7,
        ..interpolated(ChildCount::Total(500), 0.01, shape)
    };
    let a = generate(&parents, &settings, Lod::Render).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let b = pool.install(|| generate(&parents, &settings, Lod::Render).unwrap());
    let bits = |c: &ChildBuffers| c.points.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a), bits(&b), "same seed, other thread count");
    settings.seed = 8;
    let c = generate(&parents, &settings, Lod::Render).unwrap();
    let differ = a
        .points
        .iter()
        .zip(&c.points)
        .filter(|(x, y)| x != y)
        .count();
    assert!(
        differ > a.points.len() / 2,
        "{differ} of {}",
        a.points.len()
    );
}

#[test]
fn bad_neighbour_count_is_named() {
    let strands = mixed();
    let (positions, offsets) = flatten(&strands);
    let parents = Parents::new(&positions, &offsets).unwrap();
    let settings = ChildSettings {
        mode: ChildMode::Interpolated { neighbours: 0 },
        ..Default::default()
    };
    let e = generate(&parents, &settings, Lod::Render)
        .unwrap_err()
        .to_string();
    assert!(e.contains("neighbours") && e.contains("1 to 8"), "{e}");
}
