//! Cost of a deforming mesh collider per frame: the host sets a 50k-vertex mesh's vertices
//! (`Colliders::set_vertices`) and the solver steps one frame, which refits parry's BVH,
//! recomputes the pseudo-normals, smooth normals, curvatures and the narrow-phase shortcut, and
//! measures the frame's displacement and change of bending for fast-motion stepping.
//!
//! The mesh is a 250 × 200 UV sphere of radius 0.3 m (49,752 vertices, 99,500 triangles) that
//! breathes by ±0.1 % per frame (one collision step per frame, so one reshape); one strand far
//! from it keeps detection out of the figure. `deforming/rigid` is the same frame with the mesh
//! left where it is, the baseline the deformation adds to. Run:
//! `cargo bench -p hair-core --bench deforming`.

use criterion::{criterion_group, criterion_main, Criterion};
use hair_core::{
    Anchor, Collider, Colliders, HairParams, MassSpringSolver, RootFrame, Scalp, SolverSettings,
    StrandInput, StrandSet, TriMesh,
};
use nalgebra::{Isometry3, Vector3};

fn far_strand() -> StrandSet {
    let mut set = StrandSet::new();
    let rest = (0..=4).map(|i| Vector3::z() * (0.01 * i as f32)).collect();
    let anchor = Anchor::Body(RootFrame::at(Vector3::new(5.0, 0.0, 0.0)));
    set.push(StrandInput::uniform(anchor, rest, 1e-3, 1e-3, 0.0, 0.0))
        .expect("valid strand");
    set.reset_to_rest(&Scalp::fixed());
    set
}

fn bench(c: &mut Criterion) {
    let mesh = TriMesh::uv_sphere(0.3, 250, 200).expect("valid sphere");
    let vertices = mesh.positions().len();
    let frames: [Vec<Vector3<f32>>; 2] =
        [0.999, 1.001].map(|s| mesh.positions().iter().map(|p| p * s).collect());
    let scalp = Scalp::fixed();
    let mut group = c.benchmark_group("deforming");
    group.sample_size(20);
    for deform in [false, true] {
        let mut strands = far_strand();
        let mut solver = MassSpringSolver::new(
            SolverSettings::default(),
            HairParams::default(),
            &strands,
            &scalp,
            0,
        )
        .expect("valid solver");
        let mut colliders = Colliders::new();
        let id = colliders
            .insert(Collider::mesh(mesh.clone()), Isometry3::identity())
            .expect("valid collider");
        let mut frame = 0usize;
        let name = if deform {
            format!("frame_{vertices}_vertices")
        } else {
            "rigid".to_string()
        };
        group.bench_function(name, |b| {
            b.iter(|| {
                frame += 1;
                if deform {
                    colliders
                        .set_vertices(id, &frames[frame % 2])
                        .expect("same topology");
                }
                let report = solver
                    .step_frame_with_colliders(&mut strands, &scalp, &mut colliders)
                    .expect("stable");
                assert_eq!(report.steps, 1);
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
