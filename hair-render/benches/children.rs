//! Child generation throughput (child points per second) and `.usda`/`.hair` export speed.
//!
//! 10 000 bent parents of 5 points, 100 children each, subdivided 4× → 1 M children × 17 points,
//! with clumping, curl and all three roughness kinds on (the target: ≥ 50 M points/s),
//! simple and interpolated (4 parents blended per child, roots in 3 mm discs).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use hair_render::export::hair::write_hair;
use hair_render::export::usd::{write_usda, Motion, UsdOptions};
use hair_render::{
    generate, generate_into, ChildCount, ChildMode, ChildSettings, Clump, Curl, Lod, Parents,
    Roughness, Shape,
};
use nalgebra::Vector3;

fn parents() -> (Vec<Vector3<f32>>, Vec<u32>) {
    let mut positions = Vec::new();
    let mut offsets = vec![0];
    for p in 0..10_000 {
        let root = Vector3::new((p % 100) as f32 * 0.003, (p / 100) as f32 * 0.003, 0.0);
        for i in 0..5 {
            let a = 0.4 * i as f32;
            positions.push(root + Vector3::new(0.05 * (1.0 - a.cos()), 0.0, 0.05 * a.sin()));
        }
        offsets.push(positions.len() as u32);
    }
    (positions, offsets)
}

fn settings(per_parent: u32) -> ChildSettings {
    ChildSettings {
        count: ChildCount::PerParent(per_parent),
        subdivisions: 4,
        shape: Shape {
            clump: Clump {
                factor: 0.8,
                shape: 0.7,
            },
            curl: Curl {
                radius: 0.002,
                frequency: 40.0,
            },
            roughness: Roughness {
                uniform: 1e-4,
                endpoint: 1e-3,
                smooth: 5e-4,
                ..Default::default()
            },
            length_variation: 0.2,
            ..Default::default()
        },
        ..Default::default()
    }
}

fn bench(c: &mut Criterion) {
    let (positions, offsets) = parents();
    let parents = Parents::new(&positions, &offsets).unwrap();
    let mut group = c.benchmark_group("children");
    group.sample_size(10);
    let s = settings(100);
    group.throughput(Throughput::Elements(1_000_000 * 17));
    group.bench_function("generate 1M x 17 points shaped", |b| {
        b.iter(|| black_box(generate(&parents, &s, Lod::Render).unwrap()))
    });
    let mut reused = generate(&parents, &s, Lod::Render).unwrap();
    group.bench_function("generate 1M x 17 points shaped into reused buffers", |b| {
        b.iter(|| {
            generate_into(&parents, &s, Lod::Render, &mut reused).unwrap();
            black_box(reused.points.len())
        })
    });
    let interpolated = ChildSettings {
        mode: ChildMode::Interpolated { neighbours: 4 },
        spread: 0.003,
        ..s
    };
    group.bench_function("generate 1M x 17 points shaped interpolated", |b| {
        b.iter(|| black_box(generate(&parents, &interpolated, Lod::Render).unwrap()))
    });
    let small = generate(&parents, &settings(10), Lod::Render).unwrap();
    group.throughput(Throughput::Elements(small.point_count() as u64));
    group.bench_function("write usda 100k children", |b| {
        // The writer takes the children by value: the copy is set-up, not timed.
        b.iter_batched(
            || small.clone(),
            |children| {
                let mut out = Vec::with_capacity(64 << 20);
                write_usda(&mut out, children, &Motion::None, &UsdOptions::default()).unwrap();
                black_box(out.len())
            },
            criterion::BatchSize::LargeInput,
        )
    });
    group.bench_function("write hair 100k children", |b| {
        b.iter(|| {
            let mut out = Vec::with_capacity(16 << 20);
            write_hair(&mut out, &small).unwrap();
            black_box(out.len())
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
