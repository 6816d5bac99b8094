//! How a DCC plugin drives hair-core frame by frame: build strands rooted on a mesh, then each
//! frame set the deformed vertex positions, step, and read the positions back.
//!
//! Run: `cargo run --release -p hair-core --example host_loop`
//!
//! The "scalp" is a 1 m square patch of 2 × 8 × 8 triangles that waves up and down like a flag;
//! 64 strands of 0.3 m hang from it and follow the deformation.

use hair_core::{
    Anchor, HairParams, MassSpringSolver, MeshSample, Scalp, SolverSettings, StrandInput,
    StrandSet, TriMesh,
};
use nalgebra::{Isometry3, Vector3};

const N: usize = 8;

/// Vertex positions of the patch at time `t` (s): a travelling wave along x, m.
fn patch(t: f32) -> Vec<Vector3<f32>> {
    let mut p = Vec::with_capacity((N + 1) * (N + 1));
    for j in 0..=N {
        for i in 0..=N {
            let (x, y) = (i as f32 / N as f32, j as f32 / N as f32);
            let z = 0.05 * (6.0 * x - 8.0 * t).sin();
            p.push(Vector3::new(x, y, z));
        }
    }
    p
}

fn triangles() -> Vec<[u32; 3]> {
    let id = |i: usize, j: usize| (j * (N + 1) + i) as u32;
    let mut t = Vec::new();
    for j in 0..N {
        for i in 0..N {
            t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    t
}

fn main() -> Result<(), hair_core::HairError> {
    let fps = 24.0;
    let mut mesh = TriMesh::new(patch(0.0), triangles())?;

    // One strand at the centre of every other triangle, growing along the surface normal
    // (root-local +z), 12 segments of 2.5 cm.
    let mut strands = StrandSet::new();
    for tri in (0..mesh.triangles().len() as u32).step_by(2) {
        let anchor = Anchor::Surface(MeshSample {
            triangle: tri,
            weights: [1.0 / 3.0; 3],
        });
        let rest = (0..=12)
            .map(|i| Vector3::new(0.0, 0.0, 0.025 * i as f32))
            .collect();
        strands.push(StrandInput::uniform(anchor, rest, 2e-3, 1e-3, 0.0, 0.0))?;
    }
    let scalp = |mesh: &TriMesh| Scalp {
        mesh: Some(mesh.clone()),
        body: Isometry3::identity(),
    };
    strands.reset_to_rest(&scalp(&mesh));

    let settings = SolverSettings {
        fps,
        ..SolverSettings::default()
    };
    let params = HairParams {
        air_drag: 2.0,
        ..HairParams::default()
    };
    let mut solver = MassSpringSolver::new(settings, params, &strands, &scalp(&mesh), 1)?;
    println!(
        "{} strands, {} substeps per frame",
        strands.len(),
        solver.substeps()
    );

    for frame in 2..=48 {
        // The host deforms its mesh and hands over the new vertex positions.
        mesh.set_positions(&patch(frame as f32 / fps))?;
        let report = solver.step_frame(&mut strands, &scalp(&mesh))?;
        if frame % 8 == 0 {
            let tip = strands.positions[strands.points(0).end - 1];
            println!(
                "frame {frame:2}: tip of strand 0 at ({:+.3}, {:+.3}, {:+.3}) m, max stretch {:.2} %",
                tip.x,
                tip.y,
                tip.z,
                100.0 * report.max_stretch
            );
        }
    }
    Ok(())
}
