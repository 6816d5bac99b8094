//! Bad collider input gives a clear error naming the collider, the field and the fix, or a
//! documented behaviour — never a panic: open and non-manifold meshes (two-sided shells),
//! zero-area triangles, NaN keyframes, a mesh without triangles, bad sizes, thickness, friction
//! and settings, a scalp collider without a scalp, non-finite poses from a host.

use std::path::{Path, PathBuf};

use hair_core::{
    Collider, ColliderId, Colliders, ContactSettings, HairError, HairParams, MassSpringSolver,
    MeshKind, Scalp, SolverSettings, StrandInput, StrandSet,
};
use hairsys::scene::SceneFile;
use nalgebra::{Isometry3, Vector3};

const HAIR: &str = r#"
[scene]
frames = [1, 3]

[[strands]]
points = [[0.0, 0.0, 1.0], [0.0, 0.0, 0.9], [0.0, 0.0, 0.8]]
"#;

/// A scratch directory holding `files`.
fn dir_with(name: &str, files: &[(&str, &str)]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "hairsys-collision-bad-input-{}-{name}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    for (file, text) in files {
        std::fs::write(dir.join(file), text).unwrap();
    }
    dir
}

/// Builds `HAIR` plus `extra` in `dir`.
fn build(extra: &str, dir: &Path) -> Result<hairsys::build::Simulation, String> {
    let text = format!("{HAIR}\n{extra}");
    SceneFile::parse(&text, "bad.toml", dir.to_path_buf())
        .and_then(|s| s.build())
        .map_err(|e| e.to_string())
}

fn obj_collider(path: &str) -> String {
    format!("[[colliders]]\nname = \"mesh\"\nshape = {{ kind = \"obj\", path = \"{path}\" }}\n")
}

fn expect_error(result: Result<hairsys::build::Simulation, String>, needles: &[&str]) {
    let err = match result {
        Ok(_) => panic!("expected an error containing {needles:?}"),
        Err(e) => e,
    };
    println!("{err}");
    for needle in needles {
        assert!(err.contains(needle), "`{err}` lacks `{needle}`");
    }
}

#[test]
fn open_and_non_manifold_meshes_become_two_sided_shells() {
    let open = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let fan = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n";
    let dir = dir_with("shells", &[("open.obj", open), ("fan.obj", fan)]);
    for (file, needle) in [("open.obj", "boundary edges"), ("fan.obj", "non-manifold")] {
        let sim = build(&obj_collider(file), &dir).unwrap();
        let colliders = sim.colliders_at(1.0).unwrap();
        match colliders.mesh_kind(ColliderId(0)) {
            Some(MeshKind::Shell { reason }) => {
                println!("{file}: shell ({reason})");
                assert!(reason.contains(needle), "{reason}");
            }
            other => panic!("{file}: expected a shell, got {other:?}"),
        }
    }
}

#[test]
fn zero_area_triangle_is_named() {
    let dir = dir_with(
        "degenerate",
        &[(
            "flat.obj",
            "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 4\nf 1 2 3\n",
        )],
    );
    expect_error(
        build(&obj_collider("flat.obj"), &dir),
        &["[[colliders]] #0 (mesh)", "triangle 1", "degenerate"],
    );
}

#[test]
fn mesh_without_triangles_is_refused() {
    let dir = dir_with("empty", &[("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n")]);
    expect_error(
        build(&obj_collider("points.obj"), &dir),
        &["[[colliders]] #0 (mesh)", "no triangles"],
    );
}

#[test]
fn missing_mesh_file_is_named() {
    let dir = dir_with("missing", &[]);
    expect_error(
        build(&obj_collider("nowhere.obj"), &dir),
        &["[[colliders]] #0", "nowhere.obj"],
    );
}

#[test]
fn nan_keyframe_is_refused() {
    let dir = dir_with("nan", &[]);
    let extra = "[[colliders]]\nshape = { kind = \"sphere\", radius = 0.1 }\n\
                 motion = { keys = [{ frame = 1, translation = [nan, 0.0, 0.0] }] }\n";
    expect_error(
        build(extra, &dir),
        &["[[colliders]] #0", "motion", "key 0", "non-finite"],
    );
}

#[test]
fn bad_sizes_thickness_friction_and_settings_are_named() {
    let dir = dir_with("sizes", &[]);
    let cases = [
        (
            "[[colliders]]\nshape = { kind = \"sphere\", radius = 0.0 }\n",
            "radius",
        ),
        (
            "[[colliders]]\nshape = { kind = \"capsule\", half_height = -1.0, radius = 0.1 }\n",
            "half_height",
        ),
        (
            "[[colliders]]\nshape = { kind = \"sphere\", radius = 0.1 }\nthickness = -0.001\n",
            "thickness",
        ),
        (
            "[[colliders]]\nshape = { kind = \"sphere\", radius = 0.1 }\nfriction = inf\n",
            "friction",
        ),
        (
            "[[colliders]]\nshape = { kind = \"sphere\", radius = 0.1 }\n[contacts]\ntolerance = 0.0\n",
            "tolerance",
        ),
        (
            "[[colliders]]\nshape = { kind = \"sphere\", radius = 0.1 }\n[contacts]\nmax_steps = 0\n",
            "max_steps",
        ),
        (
            "[[colliders]]\nshape = { kind = \"sphere\", radius = 0.1 }\ncolour = \"red\"\n",
            "colour",
        ),
        ("[scalp.collider]\nfriction = 0.3\n", "[scalp.collider]"),
    ];
    for (extra, needle) in cases {
        expect_error(build(extra, &dir), &[needle]);
    }
}

fn one_strand() -> StrandSet {
    let rest = (0..5)
        .map(|i| Vector3::new(0.0, 0.0, -0.05 * i as f32))
        .collect();
    let anchor = hair_core::Anchor::Body(hair_core::RootFrame::at(Vector3::new(0.0, 0.0, 1.0)));
    let mut set = StrandSet::new();
    set.push(StrandInput::uniform(anchor, rest, 1e-3, 1e-3, 0.0, 0.0))
        .unwrap();
    set.reset_to_rest(&Scalp::fixed());
    set
}

#[test]
fn host_errors_are_typed_not_panics() {
    let mut colliders = Colliders::new();
    let ball = colliders
        .insert(Collider::sphere(0.1), Isometry3::identity())
        .unwrap();
    // A non-finite pose from a host.
    let bad = Isometry3::translation(f32::NAN, 0.0, 0.0);
    assert!(matches!(
        colliders.set_pose(ball, bad),
        Err(HairError::Collider { collider: 0, .. })
    ));
    assert!(colliders.insert(Collider::sphere(0.1), bad).is_err());
    // An id that does not exist.
    assert!(colliders
        .set_pose(ColliderId(7), Isometry3::identity())
        .is_err());
    // The scalp as collider needs a scalp mesh.
    let err = colliders
        .insert_scalp(&Scalp::fixed(), 0.0, 0.0)
        .unwrap_err();
    assert!(err.to_string().contains("no mesh"), "{err}");
    // Bad settings stop the step with a parameter error.
    let mut strands = one_strand();
    let scalp = Scalp::fixed();
    let mut solver = MassSpringSolver::new(
        SolverSettings::default(),
        HairParams::default(),
        &strands,
        &scalp,
        0,
    )
    .unwrap();
    colliders.settings = ContactSettings {
        max_push_speed: -1.0,
        ..ContactSettings::default()
    };
    let err = solver
        .step_frame_with_colliders(&mut strands, &scalp, &mut colliders)
        .unwrap_err();
    assert!(err.to_string().contains("max_push_speed"), "{err}");
}
