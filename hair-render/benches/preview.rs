//! Preview render time per frame (the target: ≤ 0.5 s for 1,000 strands × 17 points at
//! 800 × 800 with a head mesh): the built-in head (3,968 triangles) with hair generated on its
//! top, combed back and down, from the front and three-quarter views; and 10,000 strands to
//! show how the cost grows with the hair.
//!
//! `cargo bench -p hair-render --bench preview`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use hair_groom::guides::{generate_guides, GrowDirection, GuideOptions};
use hair_groom::{builtin_head, Region};
use hair_render::preview::{render_view, Mesh, RenderSettings, Scene, Strands, View};
use nalgebra::Vector3;

/// `count` combed strands of 17 points on the built-in head, world positions and offsets.
fn hair(head: &hair_core::TriMesh, count: usize) -> (Vec<Vector3<f32>>, Vec<u32>) {
    let guides = generate_guides(
        head,
        &GuideOptions {
            count,
            length: 0.2,
            segments: 16,
            seed: 7,
            region: Region::Cone {
                direction: Vector3::z(),
                max_angle_deg: 75.0,
            },
            direction: GrowDirection::Combed {
                direction: Vector3::new(0.0, 0.4, -1.0),
                angle_deg: 70.0,
            },
            curl: None,
        },
    )
    .unwrap();
    let mut positions = Vec::new();
    let mut offsets = vec![0u32];
    for g in &guides {
        positions.extend(g.world_points(head));
        offsets.push(positions.len() as u32);
    }
    (positions, offsets)
}

fn bench_preview(c: &mut Criterion) {
    let head = builtin_head();
    let settings = RenderSettings {
        width: 800,
        height: 800,
        ..Default::default()
    };
    let mut group = c.benchmark_group("preview_800x800_head");
    group.sample_size(20);
    for count in [1_000, 10_000] {
        let (positions, offsets) = hair(&head, count);
        let radii = vec![4e-4f32; positions.len()];
        let scene = Scene {
            strands: Some(
                Strands::new(&positions, &offsets)
                    .unwrap()
                    .with_radii(&radii)
                    .unwrap(),
            ),
            meshes: vec![Mesh::from_trimesh(0, &head, [0.6, 0.45, 0.36]).unwrap()],
            ..Default::default()
        };
        for (name, view) in [
            ("front", View::Front),
            ("three_quarter", View::ThreeQuarter),
        ] {
            group.bench_function(format!("{count}x17_{name}"), |b| {
                b.iter(|| black_box(render_view(&scene, view, None, &settings).unwrap()))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench_preview);
criterion_main!(benches);
