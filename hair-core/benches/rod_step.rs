//! Throughput of the rod model (seed 002) in point-substeps per second.
//!
//! 500 strands of 16 segments (8,500 points) on a head-sized body that turns at 2 rad/s, so the
//! projection has work; one frame of 64 substeps (about what `substeps = auto` takes) is timed,
//! f64 throughout, without colliders and with a solid sphere as head collider (contact detection
//! every substep). The projection's mean iteration count is printed once per case.
//! Run: `cargo bench -p hair-core --bench rod_step`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use hair_core::{
    Anchor, Collider, Colliders, HairParams, RodParams, RodSolver, RootFrame, Scalp,
    SolverSettings, StrandInput, StrandSet, Substeps,
};
use nalgebra::{Isometry3, UnitQuaternion, Vector3};

const STRANDS: usize = 500;
const SEGMENTS: usize = 16;
const SUBSTEPS: u32 = 64;
const HEAD: f32 = 0.1;

fn strands() -> StrandSet {
    let mut set = StrandSet::new();
    for k in 0..STRANDS {
        let z = 1.0 - (k as f32 + 0.5) / STRANDS as f32;
        let phi = k as f32 * 2.399_963;
        let r = (1.0 - z * z).sqrt();
        let normal = Vector3::new(r * phi.cos(), r * phi.sin(), z);
        let anchor = Anchor::Body(RootFrame {
            origin: normal * HEAD,
            rotation: UnitQuaternion::rotation_between(&Vector3::z(), &normal)
                .unwrap_or_else(UnitQuaternion::identity),
        });
        let rest = (0..=SEGMENTS)
            .map(|i| {
                let a = i as f32 * 0.15;
                Vector3::new(0.02 * a.sin(), 0.0, 0.015 * i as f32)
            })
            .collect();
        set.push(StrandInput::uniform(anchor, rest, 1e-3, 2e-3, 0.0, 0.0))
            .expect("valid strand");
    }
    set.reset_to_rest(&Scalp::fixed());
    set
}

fn scalp(frame: u32) -> Scalp {
    Scalp {
        mesh: None,
        body: Isometry3::from_parts(
            Vector3::zeros().into(),
            UnitQuaternion::from_euler_angles(0.0, 0.0, 2.0 * frame as f32 / 24.0),
        ),
    }
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("rod_step");
    let base = strands();
    group.throughput(Throughput::Elements(
        (base.point_count() as u64) * SUBSTEPS as u64,
    ));
    group.sample_size(10);
    let settings = SolverSettings {
        substeps: Substeps::Fixed(SUBSTEPS),
        ..SolverSettings::default()
    };
    let rod = RodParams {
        semi_major_axis: 1.5e-4,
        ..RodParams::default()
    };
    for (name, collide) in [("no colliders", false), ("sphere head", true)] {
        let mut colliders = Colliders::new();
        if collide {
            colliders
                .insert(Collider::sphere(HEAD), Isometry3::identity())
                .expect("valid sphere");
        }
        let mut set = base.clone();
        let mut solver = RodSolver::new(settings, HairParams::default(), rod, &set, &scalp(0), 0)
            .expect("valid setup");
        let mut frame = 0;
        let mut step = |set: &mut StrandSet| {
            frame += 1;
            solver
                .step_frame_with_colliders(set, &scalp(frame), &mut colliders)
                .expect("stable")
        };
        // Settle the first frames out of the timing, and report the projection's work.
        for _ in 0..12 {
            step(&mut set);
        }
        let report = step(&mut set);
        println!(
            "rod_step/{name}: {:.2} projection iterations per projection, at most {}; \
             {} nodes in contact",
            report.projection.mean_iterations(),
            report.projection.max_iterations,
            report.frame.contact_points
        );
        group.bench_function(BenchmarkId::from_parameter(name), |b| {
            b.iter(|| step(&mut set))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
