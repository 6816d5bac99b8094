//! C and C++ programs compiled with the system's `cc` and `c++` against `libhairsys_capi.so`:
//! they drive a session through a rigid and a deforming scalp with a moving collider, and what
//! they compute must be the Rust `Session`'s bits on the same input; every function refuses bad
//! input with the documented status. Skipped, with a message, on a machine without compilers.
//!
//! `valgrind_finds_no_leak_or_invalid_access` runs `tests/c/cycles.c` under `valgrind
//! --error-exitcode=1 --leak-check=full`, with `tests/c/valgrind.supp` for the memory of the
//! shared rayon pool's workers, which live until the process exits (said why there).

mod common;

use std::path::Path;

use common::{compile, compile_linked, crate_dir, have, run, Link};
use hair_core::{Collider, ColliderId, ColliderShape};
use hairsys::build::groom::{GroomArrays, GroomOptions};
use hairsys::scene::SceneFile;
use hairsys::Session;
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};

/// A rigid transform as the C API takes it: translation, then quaternion `(x, y, z, w)`.
type Pose = [f32; 7];

/// One frame of the scenario.
struct Frame {
    scalp: Pose,
    collider: Pose,
    /// Deformed scalp vertices (body space), or `None` for a rigid frame.
    vertices: Option<Vec<[f32; 3]>>,
}

/// A groom on a 5 × 5 grid scalp (0.1 m square), a sphere collider coming down onto it, six
/// rigid frames (the scalp turns about Z and slides) and six deforming ones (a travelling
/// wave over the scalp).
struct Scenario {
    vertices: Vec<[f32; 3]>,
    triangles: Vec<[u32; 3]>,
    counts: Vec<u32>,
    points: Vec<[f32; 3]>,
    radius: f32,
    collider: Pose,
    frames: Vec<Frame>,
}

fn pose(translation: [f32; 3], angle: f32) -> Pose {
    let (s, c) = (0.5 * angle).sin_cos();
    [
        translation[0],
        translation[1],
        translation[2],
        0.0,
        0.0,
        s,
        c,
    ]
}

fn isometry(p: &Pose) -> Isometry3<f32> {
    Isometry3::from_parts(
        Translation3::new(p[0], p[1], p[2]),
        UnitQuaternion::new_unchecked(Quaternion::new(p[6], p[3], p[4], p[5])),
    )
}

impl Scenario {
    fn new() -> Self {
        let n = 5;
        let vertices: Vec<[f32; 3]> = (0..n * n)
            .map(|k| [0.025 * (k % n) as f32, 0.025 * (k / n) as f32, 0.0])
            .collect();
        let mut triangles = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let a = (j * n + i) as u32;
                triangles.push([a, a + 1, a + n as u32 + 1]);
                triangles.push([a, a + n as u32 + 1, a + n as u32]);
            }
        }
        let mut points = Vec::new();
        let mut counts = Vec::new();
        for c in 0..6 {
            let (x, y) = (0.02 + 0.012 * c as f32, 0.03 + 0.008 * c as f32);
            counts.push(8);
            for k in 0..8 {
                let k = k as f32;
                points.push([x + 0.004 * k, y, 0.0005 + 0.011 * k]);
            }
        }
        let mut frames = Vec::new();
        for i in 1..=12 {
            let t = i as f32;
            // Down through the hair, which has fallen towards +x by the deforming frames.
            let collider = pose([0.08, 0.05, 0.12 - 0.008 * t], 0.0);
            if i <= 6 {
                frames.push(Frame {
                    scalp: pose([0.002 * t, 0.0, 0.0], 0.04 * t),
                    collider,
                    vertices: None,
                });
            } else {
                let wave = vertices
                    .iter()
                    .map(|v| [v[0], v[1], 0.004 * (40.0 * v[0] + t).sin()])
                    .collect();
                frames.push(Frame {
                    scalp: pose([0.012, 0.0, 0.0], 0.24),
                    collider,
                    vertices: Some(wave),
                });
            }
        }
        Self {
            vertices,
            triangles,
            counts,
            points,
            radius: 0.03,
            collider: pose([0.08, 0.05, 0.13], 0.0),
            frames,
        }
    }

    /// The scenario in the binary layout `tests/c/scenario.h` reads.
    fn write(&self, path: &Path) {
        let mut b: Vec<u8> = Vec::new();
        let u = |b: &mut Vec<u8>, v: u32| b.extend(v.to_le_bytes());
        let f = |b: &mut Vec<u8>, v: &[f32]| v.iter().for_each(|x| b.extend(x.to_le_bytes()));
        u(&mut b, self.vertices.len() as u32);
        f(&mut b, self.vertices.as_flattened());
        u(&mut b, self.triangles.len() as u32);
        self.triangles
            .as_flattened()
            .iter()
            .for_each(|&t| u(&mut b, t));
        u(&mut b, self.counts.len() as u32);
        self.counts.iter().for_each(|&c| u(&mut b, c));
        u(&mut b, self.points.len() as u32);
        f(&mut b, self.points.as_flattened());
        f(&mut b, &[self.radius]);
        f(&mut b, &self.collider);
        u(&mut b, self.frames.len() as u32);
        for fr in &self.frames {
            u(&mut b, u32::from(fr.vertices.is_some()));
            f(&mut b, &fr.scalp);
            f(&mut b, &fr.collider);
            if let Some(v) = &fr.vertices {
                f(&mut b, v.as_flattened());
            }
        }
        std::fs::write(path, b).expect("the scenario is written");
    }

    /// What the Rust `Session` computes: every frame's positions, then the last velocities,
    /// as the C drivers write them. Checks that the scenario tests what it says: the collider's
    /// motion changes the hair.
    fn rust_bytes(&self) -> Vec<u8> {
        let still = self.rust_run(false);
        let moving = self.rust_run(true);
        assert_ne!(
            still, moving,
            "the collider's motion does not change the hair: the scenario tests less"
        );
        moving
    }

    /// [`Scenario::rust_bytes`] of one run; `move_collider`: pose the collider every frame.
    fn rust_run(&self, move_collider: bool) -> Vec<u8> {
        let arrays = GroomArrays {
            scalp_vertices: &self.vertices,
            scalp_triangles: &self.triangles,
            scalp_uvs: None,
            curve_points: &self.points,
            curve_counts: &self.counts,
            goal_weights: None,
            pinned: None,
            strand_scales: None,
        };
        let mut options = GroomOptions::default();
        options.colliders.push((
            Collider {
                shape: ColliderShape::Sphere {
                    radius: self.radius,
                },
                thickness: 0.0,
                friction: 0.0,
            },
            isometry(&self.collider),
        ));
        options.expected_motion.collider_speed = Some(1.0);
        let mut s = Session::from_groom(&arrays, &options).expect("the groom session");
        let mut out = Vec::new();
        for fr in &self.frames {
            match &fr.vertices {
                None => s.set_scalp_transform(isometry(&fr.scalp)).unwrap(),
                Some(v) => s.set_scalp_vertices(v, isometry(&fr.scalp)).unwrap(),
            }
            if move_collider {
                s.set_collider_pose(ColliderId(0), isometry(&fr.collider))
                    .unwrap();
            }
            s.step().expect("a step");
            out.extend(bytemuck::cast_slice::<_, u8>(s.positions()));
        }
        out.extend(bytemuck::cast_slice::<_, u8>(s.velocities()));
        out
    }
}

/// Compares two runs' bytes, reporting the first float that differs.
fn assert_same_bits(c: &[u8], rust: &[u8], what: &str) {
    assert_eq!(c.len(), rust.len(), "{what}: output sizes differ");
    if let Some(i) = c.chunks(4).zip(rust.chunks(4)).position(|(a, b)| a != b) {
        let f = |b: &[u8]| f32::from_le_bytes(b[4 * i..4 * i + 4].try_into().unwrap());
        panic!(
            "{what}: float {i} differs: {} (host) against {} (Rust)",
            f(c),
            f(rust)
        );
    }
}

#[test]
fn a_c_host_steps_the_rust_sessions_bits_through_rigid_and_deforming_frames() {
    if !have("cc") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("session");
    compile("cc", &[crate_dir().join("tests/c/session.c")], &program);
    let scenario = Scenario::new();
    let input = dir.path().join("scenario.bin");
    scenario.write(&input);
    let output = dir.path().join("c.bin");
    run(
        &program,
        &[
            "groom",
            input.to_str().unwrap(),
            output.to_str().unwrap(),
            "2",
        ],
    );
    let c = std::fs::read(&output).unwrap();
    assert_same_bits(&c, &scenario.rust_bytes(), "C groom session");
}

#[test]
fn a_cpp_host_steps_the_rust_sessions_bits_through_rigid_and_deforming_frames() {
    if !have("c++") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("session_cpp");
    compile("c++", &[crate_dir().join("tests/c/session.cpp")], &program);
    let scenario = Scenario::new();
    let input = dir.path().join("scenario.bin");
    scenario.write(&input);
    let output = dir.path().join("cpp.bin");
    run(
        &program,
        &[input.to_str().unwrap(), output.to_str().unwrap(), "1"],
    );
    let cpp = std::fs::read(&output).unwrap();
    assert_same_bits(&cpp, &scenario.rust_bytes(), "C++ groom session");
}

#[test]
fn a_c_host_steps_the_default_scene_to_the_rust_sessions_bits() {
    if !have("cc") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("session");
    compile("cc", &[crate_dir().join("tests/c/session.c")], &program);
    let output = dir.path().join("scene.bin");
    run(&program, &["scene", "3", output.to_str().unwrap()]);
    let c = std::fs::read(&output).unwrap();

    let scene = SceneFile::builtin_default();
    let mut s = Session::from_scene(&scene).unwrap();
    let mut rust = Vec::new();
    for _ in 0..3 {
        s.step().unwrap();
        rust.extend(bytemuck::cast_slice::<_, u8>(s.positions()));
    }
    rust.extend(bytemuck::cast_slice::<_, u8>(s.velocities()));
    assert_same_bits(&c, &rust, "C default scene");
}

#[test]
fn every_function_refuses_bad_input_with_its_status() {
    if !have("cc") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("bad_input");
    compile("cc", &[crate_dir().join("tests/c/bad_input.c")], &program);
    let o = run(&program, &[dir.path().to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains(" passed, 0 failed"), "{stdout}");
}

#[test]
fn the_static_library_links_with_the_documented_system_libraries() {
    if !have("cc") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("bad_input_static");
    compile_linked(
        "cc",
        &[crate_dir().join("tests/c/bad_input.c")],
        &program,
        Link::Static,
    );
    let o = run(&program, &[dir.path().to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&o.stdout).contains(" passed, 0 failed"));
}

#[test]
fn valgrind_finds_no_leak_or_invalid_access() {
    if !have("cc") || !have("valgrind") {
        eprintln!("skipped: no `cc` or no `valgrind` on PATH");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("cycles");
    compile("cc", &[crate_dir().join("tests/c/cycles.c")], &program);
    let o = std::process::Command::new("valgrind")
        .args(["--error-exitcode=1", "--leak-check=full"])
        .arg(format!(
            "--suppressions={}",
            crate_dir().join("tests/c/valgrind.supp").display()
        ))
        .arg(&program)
        .arg(dir.path())
        .output()
        .expect("valgrind runs");
    assert!(
        o.status.success(),
        "valgrind found errors:\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
}
