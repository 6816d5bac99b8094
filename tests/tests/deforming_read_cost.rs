//! Cost per frame of a deforming 50k-vertex mesh read from a file and handed to a collider:
//! `UsdMeshSource::positions_at` on a `.usdc` with time-sampled points, `ObjSequence` on an OBJ
//! sequence, and `Colliders::set_vertices` followed by one solver frame (which reshapes the
//! collider: BVH refit, normals, curvature; see `hair_core::contacts::deforming`).
//!
//! A measurement, not a check: ignored by default. Run:
//! `cargo test --release -p hairsys-tests --test deforming_read_cost -- --ignored --nocapture`.

use std::fmt::Write as _;
use std::time::Instant;

use hair_core::{
    Anchor, Collider, Colliders, HairParams, MassSpringSolver, RootFrame, Scalp, SolverSettings,
    StrandInput, StrandSet, TriMesh,
};
use hair_groom::formats::usd_write::{Samples, UsdLayer, UsdMeshPrim, UsdStageInfo};
use hair_groom::{ObjOptions, ObjSequence, UpAxis, UsdMeshOptions, UsdMeshSource};
use nalgebra::{Isometry3, Vector3};

const FRAMES: u32 = 12;

/// The 250 × 200 UV sphere of radius 0.3 m (49,752 vertices) breathing by ±1 % over the frames.
fn frames(mesh: &TriMesh) -> Vec<Vec<Vector3<f32>>> {
    (1..=FRAMES)
        .map(|f| {
            let s = 1.0 + 0.01 * (f as f32 * 0.7).sin();
            mesh.positions().iter().map(|p| p * s).collect()
        })
        .collect()
}

fn ms_per_frame(t: Instant, frames: u32) -> f64 {
    t.elapsed().as_secs_f64() * 1e3 / f64::from(frames)
}

#[test]
#[ignore = "a measurement: run with --release --ignored --nocapture"]
fn deforming_50k_vertex_mesh_read_and_collider_update_per_frame() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = TriMesh::uv_sphere(0.3, 250, 200).unwrap();
    let n = mesh.positions().len();
    let frames = frames(&mesh);
    let flat = |p: &[Vector3<f32>]| p.iter().flat_map(|v| [v.x, v.y, v.z]).collect::<Vec<_>>();

    // .usdc with one time sample of `points` per frame.
    let mut layer = UsdLayer::new(&UsdStageInfo {
        up_axis: UpAxis::Z,
        meters_per_unit: 1.0,
        time_codes_per_second: Some(24.0),
        time_range: Some((1.0, f64::from(FRAMES))),
    });
    layer.add_mesh(UsdMeshPrim {
        name: "body",
        face_vertex_counts: vec![3; mesh.triangles().len()],
        face_vertex_indices: mesh
            .triangles()
            .iter()
            .flatten()
            .map(|&i| i as i32)
            .collect(),
        points: Samples::Times(
            frames
                .iter()
                .enumerate()
                .map(|(i, p)| ((i + 1) as f64, flat(p)))
                .collect(),
        ),
        uv: None,
        colors: None,
    });
    let usdc = dir.path().join("body.usdc");
    layer.write(&usdc).unwrap();
    let t = Instant::now();
    let usd = UsdMeshSource::open(
        &usdc,
        &UsdMeshOptions {
            prim: "/body".into(),
            units: None,
        },
    )
    .unwrap();
    let open_ms = t.elapsed().as_secs_f64() * 1e3;
    let t = Instant::now();
    for f in 1..=FRAMES {
        assert_eq!(usd.positions_at(f64::from(f)).unwrap().len(), n);
    }
    let usd_ms = ms_per_frame(t, FRAMES);

    // The same frames as an OBJ sequence.
    for (i, p) in frames.iter().enumerate() {
        let mut s = String::new();
        for v in p {
            writeln!(s, "v {:?} {:?} {:?}", v.x, v.y, v.z).unwrap();
        }
        for t in mesh.triangles() {
            writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1).unwrap();
        }
        std::fs::write(dir.path().join(format!("body.{:04}.obj", i + 1)), s).unwrap();
    }
    let seq = ObjSequence::new(&dir.path().join("body.####.obj"), ObjOptions::default()).unwrap();
    let rest = seq.mesh_at(1).unwrap();
    let t = Instant::now();
    for f in 1..=FRAMES {
        assert_eq!(seq.positions_at(f, &rest, 1).unwrap().len(), n);
    }
    let obj_ms = ms_per_frame(t, FRAMES);

    // The collider update: set the frame's vertices and step one frame (one reshape), with one
    // strand far away so that detection stays out of the figure.
    let mut strands = StrandSet::new();
    let anchor = Anchor::Body(RootFrame::at(Vector3::new(5.0, 0.0, 0.0)));
    let rest_shape = (0..=4).map(|i| Vector3::z() * (0.01 * i as f32)).collect();
    strands
        .push(StrandInput::uniform(
            anchor, rest_shape, 1e-3, 1e-3, 0.0, 0.0,
        ))
        .unwrap();
    let scalp = Scalp::fixed();
    strands.reset_to_rest(&scalp);
    let mut solver = MassSpringSolver::new(
        SolverSettings::default(),
        HairParams::default(),
        &strands,
        &scalp,
        1,
    )
    .unwrap();
    let mut colliders = Colliders::new();
    let id = colliders
        .insert(Collider::mesh(mesh.clone()), Isometry3::identity())
        .unwrap();
    let t = Instant::now();
    for f in 2..=FRAMES {
        let p = usd.positions_at(f64::from(f)).unwrap();
        colliders.set_vertices(id, &p).unwrap();
        solver
            .step_frame_with_colliders(&mut strands, &scalp, &mut colliders)
            .unwrap();
    }
    let update_ms = ms_per_frame(t, FRAMES - 1);
    println!(
        "deforming mesh of {n} vertices, {} triangles, {FRAMES} frames: open .usdc {open_ms:.1} ms; \
         read per frame: .usdc {usd_ms:.2} ms, OBJ sequence {obj_ms:.2} ms; .usdc read + \
         set_vertices + one solver frame (collider reshape) {update_ms:.2} ms",
        mesh.triangles().len()
    );
}
