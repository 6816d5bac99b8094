//! Cost of voxel hair–hair interaction and force fields per point and collision step, at three
//! sizes, against the force substeps of the same step.
//!
//! 500, 2,000 and 8,000 strands of 16 segments (8,500, 34,000 and 136,000 points) hang from a
//! 0.3 × 0.3 m patch of roots (spacing grows with the count's square root, so the grid's size
//! stays the same: 1 cm cells over the hair's box). Default hair parameters, `substeps = auto`
//! (as the default scene), one collision step per frame at 24 fps, 2 threads; hair-hair friction
//! 0.3 and repulsion on; three fields (wind with noise, turbulence, vortex). Each iteration is
//! one frame; the solver's own phase timers are summed with `iter_custom`:
//!
//! - `hair_hair/N`: grid build, friction and repulsion (throughput: points per step),
//! - `fields/N`: the three fields evaluated in batch (throughput: points per step),
//! - `substeps/N`: the strand substeps of the same step (throughput: points per step).
//!
//! Linear cost shows as a constant time per point across N. Run:
//! `cargo bench -p hair-core --bench volume`.

use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use hair_core::{
    Anchor, FieldKind, ForceField, FrameReport, HairHairSettings, HairParams, MassSpringSolver,
    RootFrame, Scalp, SolverSettings, StrandInput, StrandSet,
};
use nalgebra::Vector3;

const SEGMENTS: usize = 16;
const SIZES: [usize; 3] = [500, 2_000, 8_000];

fn strands(count: usize) -> StrandSet {
    let side = (count as f32).sqrt().ceil() as usize;
    let spacing = 0.3 / side as f32;
    let mut set = StrandSet::new();
    for s in 0..count {
        let root = Vector3::new((s % side) as f32, (s / side) as f32, 0.0) * spacing;
        let dir = Vector3::new(0.3, 0.1, -1.0).normalize();
        let rest = (0..=SEGMENTS)
            .map(|i| dir * (0.25 * i as f32 / SEGMENTS as f32))
            .collect();
        let input = StrandInput::uniform(
            Anchor::Body(RootFrame::at(root)),
            rest,
            1e-3,
            2e-3,
            0.0,
            0.0,
        );
        set.push(input).expect("valid strand");
    }
    set.reset_to_rest(&Scalp::fixed());
    set
}

fn fields() -> Vec<ForceField> {
    let mut wind = ForceField::new(
        FieldKind::Wind {
            noise: 0.3,
            seed: 1,
        },
        2.0,
    );
    wind.direction = Vector3::x();
    let turbulence = ForceField::new(
        FieldKind::Turbulence {
            size: 0.1,
            flow: 0.5,
            seed: 2,
        },
        1.0,
    );
    let mut vortex = ForceField::new(FieldKind::Vortex, 0.5);
    vortex.center = Vector3::new(0.15, 0.15, 0.0);
    vec![wind, turbulence, vortex]
}

fn bench(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("thread pool");
    let hh = HairHairSettings {
        cell_size: 0.01,
        friction: 0.3,
        repulsion: 0.3,
        target_density: 0.2,
    };
    let mut group = c.benchmark_group("volume");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(5));
    for &count in &SIZES {
        let scalp = Scalp::fixed();
        let mut set = strands(count);
        let mut solver = MassSpringSolver::new(
            SolverSettings::default(),
            HairParams::default(),
            &set,
            &scalp,
            1,
        )
        .and_then(|s| s.with_hair_hair(hh, &set))
        .and_then(|s| s.with_fields(fields()))
        .expect("valid setup");
        group.throughput(Throughput::Elements(set.point_count() as u64));
        let mut frame = |pick: fn(&FrameReport) -> Duration, iters: u64| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                let report = pool
                    .install(|| solver.step_frame(&mut set, &scalp))
                    .expect("stable");
                total += pick(&report);
            }
            total
        };
        group.bench_function(BenchmarkId::new("hair_hair", count), |b| {
            b.iter_custom(|n| frame(|r| r.times.volume, n))
        });
        group.bench_function(BenchmarkId::new("fields", count), |b| {
            b.iter_custom(|n| frame(|r| r.times.fields, n))
        });
        group.bench_function(BenchmarkId::new("substeps", count), |b| {
            b.iter_custom(|n| frame(|r| r.times.strands, n))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
