//! Throughput of the strand step in point-substeps per second.
//!
//! 2,000 strands of 16 segments (34,000 points) hang from a fixed scalp; one frame of 32
//! substeps is timed, with stretch + bend + goal + gravity + drag, with and without the damping
//! sub-loop (10 Jacobi iterations), with the sub-loop and the inextensibility projection, and
//! with the sub-loop and a 1 % strain limit (soft springs that the limit holds), at 48 fps so dt
//! is half the stability bound; and implicit Euler and BDF2 (`integrate::implicit`) with the same
//! strain limit and substep, whose cost per substep is what their larger usable step must repay.
//! Run: `cargo bench -p hair-core --bench strand_step`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use hair_core::{
    Anchor, HairParams, Inextensibility, Integrator, MassSpringSolver, RootFrame, Scalp,
    SolverSettings, StrandInput, StrandSet, Substeps,
};
use nalgebra::Vector3;

const STRANDS: usize = 2_000;
const SEGMENTS: usize = 16;
const SUBSTEPS: u32 = 32;

fn strands() -> StrandSet {
    let mut set = StrandSet::new();
    for s in 0..STRANDS {
        let root = Vector3::new((s % 50) as f32 * 0.01, (s / 50) as f32 * 0.01, 0.0);
        // Slightly curved rest shape so the bending springs do real work.
        let rest = (0..=SEGMENTS)
            .map(|i| {
                let a = i as f32 * 0.15;
                Vector3::new(0.02 * a.sin(), 0.0, 0.015 * i as f32)
            })
            .collect();
        set.push(StrandInput::uniform(
            Anchor::Body(RootFrame::at(root)),
            rest,
            1e-2,
            1e-3,
            0.3,
            0.05,
        ))
        .expect("valid strand");
    }
    // `push` leaves every strand at the origin; on its root, at rest, the step is the steady
    // work of hanging hair, not the recoil of strands yanked to roots up to 0.6 m away.
    set.reset_to_rest(&Scalp::fixed());
    set
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("strand_step");
    let base = strands();
    group.throughput(Throughput::Elements(
        (base.point_count() as u64) * SUBSTEPS as u64,
    ));
    group.sample_size(20);
    let explicit = Integrator::SemiImplicitEuler;
    for (name, integrator, iterations, projection, max_strain) in [
        ("no damping", explicit, 0, false, None),
        ("damping 10 Jacobi", explicit, 10, false, None),
        (
            "damping 10 Jacobi + inextensibility projection",
            explicit,
            10,
            true,
            None,
        ),
        (
            "damping 10 Jacobi + strain limit 1 %",
            explicit,
            10,
            false,
            Some(0.01),
        ),
        (
            "implicit Euler + strain limit 1 %",
            Integrator::ImplicitEuler,
            0,
            false,
            Some(0.01),
        ),
        (
            "BDF2 + strain limit 1 %",
            Integrator::Bdf2,
            0,
            false,
            Some(0.01),
        ),
    ] {
        let params = HairParams {
            goal_stiffness: 0.5,
            stretch_stiffness: 40.0,
            bend_stiffness: 0.5,
            ..HairParams::default()
        };
        let settings = SolverSettings {
            substeps: Substeps::Fixed(SUBSTEPS),
            damping_iterations: iterations,
            integrator,
            fps: 48.0,
            max_strain,
            ..SolverSettings::default()
        };
        let scalp = Scalp::fixed();
        group.bench_function(BenchmarkId::from_parameter(name), |b| {
            let mut set = base.clone();
            let mut solver =
                MassSpringSolver::new(settings, params, &set, &scalp, 0).expect("valid setup");
            if projection {
                solver = solver
                    .with_inextensibility(Inextensibility::default())
                    .expect("valid projection");
            }
            b.iter(|| solver.step_frame(&mut set, &scalp).expect("stable"));
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
