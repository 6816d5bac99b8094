//! Cost of hair–object collision: contact detection per point and step, and what contacts add to
//! a frame.
//!
//! 2,000 strands of 16 segments (34,000 points) grow from a sphere of radius 1 m (the parity
//! scene's head: a 64 × 32 UV-sphere mesh of 4,032 triangles, or an analytic sphere) that swings
//! ±0.3 m along x, so hair falls onto it, drapes and slides. One frame at 24 fps, one collision
//! step, 2 threads. `detection/*` times detection alone (the solver's own phase timer, summed
//! over frames with `iter_custom`), with throughput in points per step; `frame/*` times whole
//! frames with and without the collider. Run: `cargo bench -p hair-core --bench contacts`.

use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use hair_core::{
    Anchor, Collider, Colliders, HairParams, MassSpringSolver, RootFrame, Scalp, SolverSettings,
    StrandInput, StrandSet, TriMesh,
};
use nalgebra::{Isometry3, UnitQuaternion, Vector3};

const STRANDS: usize = 2_000;
const SEGMENTS: usize = 16;

/// Strands growing straight out of the upper part of the unit sphere, 1.5 mm off its surface.
fn strands() -> StrandSet {
    let mut set = StrandSet::new();
    for s in 0..STRANDS {
        // A golden-angle spiral over the upper 3/4 of the sphere.
        let z = 1.0 - 1.5 * (s as f32 + 0.5) / STRANDS as f32;
        let phi = s as f32 * 2.399_963;
        let ring = (1.0 - z * z).sqrt();
        let normal = Vector3::new(ring * phi.cos(), ring * phi.sin(), z);
        let rotation = UnitQuaternion::rotation_between(&Vector3::z(), &normal)
            .unwrap_or_else(UnitQuaternion::identity);
        let anchor = Anchor::Body(RootFrame {
            origin: normal * 1.0015,
            rotation,
        });
        let rest = (0..=SEGMENTS)
            .map(|i| Vector3::new(0.0, 0.0, 0.09 * i as f32))
            .collect();
        set.push(StrandInput::uniform(anchor, rest, 1e-2, 5e-3, 0.0, 0.0))
            .expect("valid strand");
    }
    set
}

fn bench(c: &mut Criterion) {
    let params = HairParams {
        stretch_stiffness: 50.0,
        stretch_damping: 1000.0,
        air_drag: 2.0,
        ..HairParams::default()
    };
    let settings = SolverSettings {
        damping_iterations: 5,
        max_strain: Some(0.015),
        ..SolverSettings::default()
    };
    let base = strands();
    let scalp = Scalp::fixed();
    let pose = |frame: u32| Isometry3::translation(0.3 * (frame as f32 * 0.2).sin(), 0.0, 0.0);
    let mesh = TriMesh::uv_sphere(1.0, 64, 32).expect("valid sphere");
    let setups: Vec<(&str, Option<Collider>)> = vec![
        ("no collider", None),
        ("sphere mesh 4032 triangles", Some(Collider::mesh(mesh))),
        ("analytic sphere", Some(Collider::sphere(1.0))),
    ];

    let mut detection = c.benchmark_group("detection");
    detection.throughput(Throughput::Elements(base.point_count() as u64));
    detection.sample_size(20);
    for (name, collider) in setups.iter().skip(1) {
        detection.bench_function(BenchmarkId::from_parameter(name), |b| {
            let mut set = base.clone();
            set.reset_to_rest(&scalp);
            let mut solver =
                MassSpringSolver::new(settings, params, &set, &scalp, 0).expect("valid");
            let mut colliders = Colliders::new();
            let id = colliders
                .insert(collider.clone().expect("a collider"), pose(0))
                .expect("valid");
            // Let the hair fall onto the sphere first.
            for _ in 0..24 {
                let f = solver.frame() + 1;
                colliders.set_pose(id, pose(f)).expect("finite");
                solver
                    .step_frame_with_colliders(&mut set, &scalp, &mut colliders)
                    .expect("stable");
            }
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    let f = solver.frame() + 1;
                    colliders.set_pose(id, pose(f)).expect("finite");
                    let report = solver
                        .step_frame_with_colliders(&mut set, &scalp, &mut colliders)
                        .expect("stable");
                    total += report.times.contacts / report.steps;
                }
                total
            });
        });
    }
    detection.finish();

    let mut frame = c.benchmark_group("frame");
    frame.sample_size(10);
    for (name, collider) in &setups {
        frame.bench_function(BenchmarkId::from_parameter(name), |b| {
            let mut set = base.clone();
            set.reset_to_rest(&scalp);
            let mut solver =
                MassSpringSolver::new(settings, params, &set, &scalp, 0).expect("valid");
            let mut colliders = Colliders::new();
            let id = collider
                .clone()
                .map(|c| colliders.insert(c, pose(0)).expect("valid"));
            b.iter(|| {
                let f = solver.frame() + 1;
                if let Some(id) = id {
                    colliders.set_pose(id, pose(f)).expect("finite");
                }
                solver
                    .step_frame_with_colliders(&mut set, &scalp, &mut colliders)
                    .expect("stable")
            });
        });
    }
    frame.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
