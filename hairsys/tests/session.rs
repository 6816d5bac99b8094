//! The `Session` a host drives: deforming scalps keep roots on their samples, a host that
//! replays the scene's keyframes gets the batch run's bits, snapshots scrub exactly, thread
//! counts change nothing, and bad host input is refused by name.

use std::sync::Arc;

use hair_cache::{CacheReader, WriterOptions};
use hair_core::{Anchor, ColliderId};
use hairsys::run::{simulate, SimulateOptions};
use hairsys::scene::{SceneFile, DEFAULT_SCENE};
use hairsys::{Error, Session};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

/// The default scene, smaller and shorter (same head, motion and physics).
fn small_scene() -> SceneFile {
    let text = DEFAULT_SCENE
        .replace("count = 4000", "count = 200")
        .replace("frames = [1, 48]", "frames = [1, 12]");
    SceneFile::parse(&text, "small default", ".".into()).unwrap()
}

/// A smooth, large deformation of `rest` (body space) at frame `f`: the upper half of the head
/// sheared sideways and the top pulled up, as a bend and a shrug would.
fn deformed(rest: &[Vector3<f32>], f: u32) -> Vec<[f32; 3]> {
    let t = f as f32 / 12.0;
    rest.iter()
        .map(|v| {
            let up = v.z.max(0.0);
            [
                v.x + 0.25 * t * up * up / 0.22,
                v.y,
                v.z + 0.05 * t * up / 0.22,
            ]
        })
        .collect()
}

#[test]
fn roots_stay_exactly_on_a_deforming_scalp() {
    let mut session = Session::from_scene(&small_scene()).unwrap();
    let rest = session.rest_scalp().unwrap().positions().to_vec();
    let body = Isometry3::from_parts(
        Translation3::new(0.1, -0.2, 0.3),
        UnitQuaternion::from_euler_angles(0.2, 0.0, 0.5),
    );
    for f in 2..=12 {
        session
            .set_scalp_vertices(&deformed(&rest, f), body)
            .unwrap();
        session.step().unwrap();
        let mesh = session.scalp().mesh.as_ref().unwrap();
        let positions = session.positions();
        for (s, anchor) in session.strands().anchors().iter().enumerate() {
            let Anchor::Surface(sample) = anchor else {
                panic!("generated hair is rooted on the surface")
            };
            let root = positions[session.strand_offsets()[s] as usize];
            let on_surface = mesh.evaluate(sample).origin;
            let gap = (Vector3::from(root) - on_surface).norm();
            assert!(
                gap <= 1e-6,
                "frame {f}, strand {s}: root {gap:.3e} m off its mesh sample"
            );
        }
    }
}

#[test]
fn a_host_replaying_the_scene_keyframes_gets_the_batch_runs_bits() {
    let scene = small_scene();
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("run.mcap");
    simulate(
        &SimulateOptions {
            scene: scene.clone(),
            cache: cache.clone(),
            frames: None,
            threads: Some(2),
            writer: WriterOptions::default(),
            resume: false,
            kernel: Default::default(),
            quality: false,
        },
        |_| {},
    )
    .unwrap();
    let mut reader = CacheReader::open(&cache).unwrap();

    // The host sets the scalp itself every frame, from the scene's own motion.
    let sim = scene.build().unwrap();
    let mut session = Session::from_scene(&scene).unwrap();
    for f in 2..=12 {
        session
            .set_scalp_transform(sim.scalp_at(f as f32).body)
            .unwrap();
        session.step().unwrap();
        let cached = reader.read_frame(f).unwrap();
        let same = cached
            .positions
            .iter()
            .zip(session.positions())
            .all(|(a, b)| {
                a.x.to_bits() == b[0].to_bits()
                    && a.y.to_bits() == b[1].to_bits()
                    && a.z.to_bits() == b[2].to_bits()
            });
        assert!(same, "frame {f}: the session differs from the batch run");
    }
}

#[test]
fn restoring_a_snapshot_replays_the_same_bits() {
    let mut session = Session::from_scene(&small_scene()).unwrap();
    for _ in 0..4 {
        session.step().unwrap();
    }
    let snap = session.snapshot();
    let mut first = Vec::new();
    for _ in 0..4 {
        session.step().unwrap();
        first.push(session.positions().to_vec());
    }
    session.restore(&snap).unwrap();
    assert_eq!(session.frame(), snap.frame());
    for (i, expected) in first.iter().enumerate() {
        session.step().unwrap();
        assert_eq!(
            session.positions(),
            expected.as_slice(),
            "step {i} after restore"
        );
    }
}

#[test]
fn the_thread_count_changes_no_bit() {
    let run = |threads: usize| {
        let mut session = Session::from_scene(&small_scene()).unwrap();
        let pool = hair_par::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        session.set_thread_pool(Arc::new(pool));
        for _ in 0..6 {
            session.step().unwrap();
        }
        session.positions().to_vec()
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn bad_host_input_is_refused_by_name() {
    let mut session = Session::from_scene(&small_scene()).unwrap();
    let n = session.rest_scalp().unwrap().positions().len();
    let e = session
        .set_scalp_vertices(&vec![[0.0; 3]; n - 1], Isometry3::identity())
        .unwrap_err();
    assert!(
        matches!(&e, Error::Argument { argument, .. } if argument == "scalp_vertices"),
        "{e}"
    );
    assert!(e.to_string().contains(&format!("({n}, 3)")), "{e}");
    let mut nan = vec![[0.0f32; 3]; n];
    nan[7][1] = f32::NAN;
    let e = session
        .set_scalp_vertices(&nan, Isometry3::identity())
        .unwrap_err();
    assert!(e.to_string().contains("vertex 7"), "{e}");
    let e = session
        .set_collider_pose(ColliderId(3), Isometry3::identity())
        .unwrap_err();
    assert!(e.to_string().contains("collider 3"), "{e}");
    let mut bad = Isometry3::identity();
    bad.translation.vector.x = f32::INFINITY;
    assert!(session.set_scalp_transform(bad).is_err());
    // Nothing refused reached the state: the session still steps.
    session.step().unwrap();
}

#[test]
fn a_failed_session_refuses_to_step_until_restored() {
    // Without the strain limit (which keeps even absurd loads bounded), gravity of 1e12 m/s²
    // blows any strand up within a frame.
    let text = DEFAULT_SCENE
        .replace("count = 4000", "count = 200")
        .replace("\nmax_strain = 0.01 ", "\n# max_strain = 0.01 ");
    assert!(!text.contains("\nmax_strain"));
    let scene = SceneFile::parse(&text, "no strain limit", ".".into()).unwrap();
    let mut session = Session::from_scene(&scene).unwrap();
    let snap = session.snapshot();
    session.params_mut().unwrap().gravity = [0.0, 0.0, -1e12];
    let e = session.step().unwrap_err();
    assert!(matches!(e, Error::Solver { .. }), "{e}");
    let again = session.step().unwrap_err();
    assert!(matches!(again, Error::Failed { frame: 2, .. }), "{again}");
    session.restore(&snap).unwrap();
    session.step().unwrap();
}

/// Deepest free point (its centre) inside `mesh` (world space, a closed solid), m.
fn deepest_inside(mesh: &hair_core::TriMesh, positions: &[[f32; 3]], inv_mass: &[f32]) -> f32 {
    use parry3d::math::Vector as GlamVector;
    use parry3d::query::PointQuery;
    use parry3d::shape::{TriMesh as ParryMesh, TriMeshFlags};
    let vertices = mesh
        .positions()
        .iter()
        .map(|p| GlamVector::new(p.x, p.y, p.z))
        .collect();
    let solid =
        ParryMesh::with_flags(vertices, mesh.triangles().to_vec(), TriMeshFlags::ORIENTED).unwrap();
    positions
        .iter()
        .zip(inv_mass)
        .filter(|(_, &w)| w > 0.0)
        .map(|(p, _)| {
            let x = GlamVector::new(p[0], p[1], p[2]);
            let hit = solid.project_local_point(x, false);
            if hit.is_inside {
                (hit.point - x).length()
            } else {
                0.0
            }
        })
        .fold(0.0, f32::max)
}

#[test]
fn hair_stays_outside_a_deforming_scalp_collider() {
    let text = DEFAULT_SCENE
        .replace("count = 4000", "count = 200")
        .replace("frames = [1, 48]", "frames = [1, 12]");
    assert!(
        text.contains("[scalp.collider]"),
        "the default head collides"
    );
    let scene = SceneFile::parse(&text, "deforming head", ".".into()).unwrap();
    let mut session = Session::from_scene(&scene).unwrap();
    let rest = session.rest_scalp().unwrap().positions().to_vec();
    for f in 2..=12 {
        session
            .set_scalp_vertices(&deformed(&rest, f), Isometry3::identity())
            .unwrap();
        session.step().unwrap();
        let mesh = session.scalp().mesh.as_ref().unwrap();
        let depth = deepest_inside(
            mesh,
            session.positions(),
            session.strands().inverse_masses(),
        );
        assert!(
            depth == 0.0,
            "frame {f}: a hair point is {depth:.2e} m inside the scalp"
        );
    }
}

#[test]
fn a_deformed_mesh_collider_is_refused_by_name_when_its_vertex_count_is_wrong() {
    let text = DEFAULT_SCENE
        .replace("count = 4000", "count = 50")
        .replace("frames = [1, 48]", "frames = [1, 4]")
        .replace(
            "[hair]",
            "[[colliders]]\nname = \"ball\"\nshape = { kind = \"sphere\", radius = 0.05 }\n\n[hair]",
        );
    let scene = SceneFile::parse(&text, "ball", ".".into()).unwrap();
    let mut session = Session::from_scene(&scene).unwrap();
    // A sphere is analytic: it cannot deform.
    let e = session
        .set_collider_vertices(ColliderId(0), &[[0.0; 3]; 3])
        .unwrap_err();
    assert!(e.to_string().contains("collider 0 vertices"), "{e}");
    let e = session
        .set_collider_vertices(ColliderId(0), &[[f32::NAN; 3]; 3])
        .unwrap_err();
    assert!(e.to_string().contains("vertex 0 is not finite"), "{e}");
    session.step().unwrap();
}
