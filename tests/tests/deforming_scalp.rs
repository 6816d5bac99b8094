//! Scalps and colliders that deform frame by frame from files (`[scalp.mesh] kind = "usd"` or
//! `"obj-sequence"`, `[[colliders]] shape.kind` the same; `hairsys::scene::deforming`).
//!
//! The built-in head is written to disk frame by frame, moved by deformation only (no
//! `[scalp.motion]`): a 10 rad/s turn (23.9° per frame at 24 fps) and a fast shrug (the lower
//! head rising 3 cm in two frames, 0.36 m/s, and falling back). Checked against independent
//! references: every root equals its mesh sample evaluated on the mesh read back from the
//! frame's own file, bit for bit, and no free hair point is inside that mesh (parry's point
//! projection on the closed mesh, the collision tests' reference). The same shrug written as an
//! OBJ sequence and as USD time samples gives the same simulation bit for bit, and a run
//! resumed at a middle frame (fresh session, fresh colliders, as `simulate --resume` builds
//! them) continues bit-identically with a deforming scalp and a deforming mesh collider.

mod common;

use std::fmt::Write as _;
use std::path::Path;

use common::collide::{ParryHead, SPRING_PHYSICS};
use hair_core::{Anchor, TriMesh};
use hairsys::scene::SceneFile;
use hairsys::Session;
use nalgebra::{Isometry3, Vector3};

const FPS: f32 = 24.0;

/// The built-in head at `frame` of a rigid turn about the vertical at `omega` rad/s from
/// frame 1.
fn turned(head: &TriMesh, omega: f32, frame: u32) -> Vec<Vector3<f32>> {
    let angle = omega * (frame - 1) as f32 / FPS;
    let rot = Isometry3::rotation(Vector3::z() * angle);
    head.positions().iter().map(|p| rot * p).collect()
}

/// Height of the shrug at `frame`, m: still to frame 3, up 3 cm by frame 5, held to frame 8,
/// down by frame 10.
fn shrug_height(frame: u32) -> f32 {
    let up = |a: u32, b: u32| ((frame as f32 - a as f32) / (b - a) as f32).clamp(0.0, 1.0);
    0.03 * (up(3, 5) - up(8, 10))
}

/// The built-in head at `frame` of the shrug: vertices below 5 cm rise by the full height,
/// above 15 cm not at all, smoothly between.
fn shrugged(head: &TriMesh, frame: u32) -> Vec<Vector3<f32>> {
    let h = shrug_height(frame);
    head.positions()
        .iter()
        .map(|p| {
            let t = ((p.z - 0.05) / 0.1).clamp(0.0, 1.0);
            let w = 1.0 - t * t * (3.0 - 2.0 * t);
            p + Vector3::z() * (h * w)
        })
        .collect()
}

/// Writes `positions` with `triangles` as an OBJ file (shortest round-trip decimals).
fn write_obj(path: &Path, positions: &[Vector3<f32>], triangles: &[[u32; 3]]) {
    let mut s = String::new();
    for p in positions {
        writeln!(s, "v {:?} {:?} {:?}", p.x, p.y, p.z).unwrap();
    }
    for t in triangles {
        writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1).unwrap();
    }
    std::fs::write(path, s).unwrap();
}

/// Writes frames `1..=frames.len()` as the OBJ sequence `dir/name.####.obj`.
fn write_sequence(dir: &Path, name: &str, frames: &[Vec<Vector3<f32>>], triangles: &[[u32; 3]]) {
    for (i, p) in frames.iter().enumerate() {
        write_obj(&dir.join(format!("{name}.{:04}.obj", i + 1)), p, triangles);
    }
}

/// Writes frames `1..=frames.len()` as a `.usda` stage (meters, Z up, time codes 1…n) with
/// one Mesh `/Char/body` whose `points` are time-sampled.
fn write_usda(path: &Path, frames: &[Vec<Vector3<f32>>], triangles: &[[u32; 3]]) {
    let mut s = format!(
        "#usda 1.0\n(\n    metersPerUnit = 1\n    upAxis = \"Z\"\n    startTimeCode = 1\n    \
         endTimeCode = {}\n)\ndef Xform \"Char\" {{\n    def Mesh \"body\" {{\n",
        frames.len()
    );
    let counts = vec!["3"; triangles.len()].join(", ");
    let indices: Vec<String> = triangles.iter().flatten().map(u32::to_string).collect();
    writeln!(s, "        int[] faceVertexCounts = [{counts}]").unwrap();
    writeln!(
        s,
        "        int[] faceVertexIndices = [{}]",
        indices.join(", ")
    )
    .unwrap();
    s.push_str("        point3f[] points.timeSamples = {\n");
    for (i, p) in frames.iter().enumerate() {
        let pts: Vec<String> = p
            .iter()
            .map(|v| format!("({:?}, {:?}, {:?})", v.x, v.y, v.z))
            .collect();
        writeln!(s, "            {}: [{}],", i + 1, pts.join(", ")).unwrap();
    }
    s.push_str("        }\n    }\n}\n");
    std::fs::write(path, s).unwrap();
}

/// A scene of hair on a deforming scalp `scalp_mesh` (the body of `[scalp.mesh]`), frames 1 to
/// `last`, the scalp colliding with its hair; `extra` is appended.
fn scene(dir: &Path, scalp_mesh: &str, last: u32, count: u32, extra: &str) -> SceneFile {
    let text = format!(
        r#"
[scene]
name = "deforming scalp"
fps = {FPS}
frames = [1, {last}]

[physics]
{SPRING_PHYSICS}

[scalp.mesh]
{scalp_mesh}

[scalp.collider]
thickness = 0.0
friction = 0.3

[hair]
count = {count}
length = 0.2
segments = 12
seed = 3
radius = 0.002
mass_per_length = 0.001
length_variation = 0.2
region = {{ direction = [0.0, 0.3, 1.0], max_angle_deg = 95.0 }}
{extra}
"#
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    SceneFile::load(&path).unwrap()
}

/// Steps `scene` to its last frame, checking at every frame that each root equals its sample
/// on `mesh_of(frame)` (the mesh read back from the frame's file) bit for bit and that no free
/// point is inside that mesh. Returns the smallest signed gap seen, m.
fn assert_roots_on_samples_and_hair_outside(
    scene: &SceneFile,
    mesh_of: impl Fn(u32) -> TriMesh,
) -> f32 {
    let mut session = Session::from_scene(scene).unwrap();
    let last = scene.scene.scene.frames[1];
    let mut smallest = f32::INFINITY;
    while session.frame() < last {
        session.step().unwrap();
        let frame = session.frame();
        let mesh = mesh_of(frame);
        let strands = session.strands();
        for (s, anchor) in strands.anchors().iter().enumerate() {
            let Anchor::Surface(sample) = anchor else {
                panic!("strand {s} is not rooted on the scalp");
            };
            let want = mesh.evaluate(sample).origin;
            let root = strands.positions[strands.offsets()[s] as usize];
            assert_eq!(
                root.map(f32::to_bits),
                want.map(f32::to_bits),
                "frame {frame}, strand {s}: root {root:?} is off its sample {want:?}"
            );
        }
        let gap = ParryHead::new(&mesh).free_point_gap(&Isometry3::identity(), strands);
        assert_eq!(
            gap.inside, 0,
            "frame {frame}: {} hair points inside the scalp (deepest {:.2e} m)",
            gap.inside, -gap.smallest
        );
        smallest = smallest.min(gap.smallest);
    }
    smallest
}

#[test]
fn head_turning_at_10_rad_s_by_deformation_keeps_roots_on_samples_and_hair_outside() {
    let dir = tempfile::tempdir().unwrap();
    let head = hair_groom::builtin_head();
    let frames: Vec<_> = (1..=13).map(|f| turned(&head, 10.0, f)).collect();
    write_sequence(dir.path(), "head", &frames, head.triangles());
    let scene = scene(
        dir.path(),
        "kind = \"obj-sequence\"\npath = \"head.####.obj\"",
        13,
        200,
        "",
    );
    let seq = hair_groom::ObjSequence::new(
        &dir.path().join("head.####.obj"),
        hair_groom::ObjOptions::default(),
    )
    .unwrap();
    let gap = assert_roots_on_samples_and_hair_outside(&scene, |f| seq.mesh_at(f).unwrap());
    assert!(gap > 0.0, "smallest gap {gap}");
}

/// 200 hairs on the built-in head shrugging (frames 1–12), written to `dir` as USD time
/// samples of `/Char/body` (`shrug.usda`) and read by the scene.
fn shrug_scene(dir: &Path) -> SceneFile {
    let head = hair_groom::builtin_head();
    let frames: Vec<_> = (1..=12).map(|f| shrugged(&head, f)).collect();
    write_usda(&dir.join("shrug.usda"), &frames, head.triangles());
    scene(
        dir,
        "kind = \"usd\"\npath = \"shrug.usda\"\nprim = \"/Char/body\"",
        12,
        200,
        "",
    )
}

#[test]
fn fast_shrug_by_deformation_keeps_roots_on_samples_and_hair_outside() {
    let dir = tempfile::tempdir().unwrap();
    let scene = shrug_scene(dir.path());
    let usd = hair_groom::UsdMeshSource::open(
        &dir.path().join("shrug.usda"),
        &hair_groom::UsdMeshOptions {
            prim: "/Char/body".into(),
            units: None,
        },
    )
    .unwrap();
    let gap =
        assert_roots_on_samples_and_hair_outside(&scene, |f| usd.mesh_at(f64::from(f)).unwrap());
    assert!(gap > 0.0, "smallest gap {gap}");
}

/// Positions and velocities of one frame, as bits.
type FrameBits = (Vec<[u32; 3]>, Vec<[u32; 3]>);

fn bits(v: &[[f32; 3]]) -> Vec<[u32; 3]> {
    v.iter().map(|p| p.map(f32::to_bits)).collect()
}

/// Every frame's positions and velocities of `scene` stepped from its first frame.
fn run(scene: &SceneFile) -> Vec<FrameBits> {
    let mut session = Session::from_scene(scene).unwrap();
    let mut out = Vec::new();
    while session.frame() < scene.scene.scene.frames[1] {
        session.step().unwrap();
        out.push((bits(session.positions()), bits(session.velocities())));
    }
    out
}

#[test]
fn obj_sequence_and_usd_time_samples_of_one_shrug_give_the_same_simulation() {
    let dir = tempfile::tempdir().unwrap();
    let head = hair_groom::builtin_head();
    let frames: Vec<_> = (1..=8).map(|f| shrugged(&head, f)).collect();
    write_sequence(dir.path(), "body", &frames, head.triangles());
    write_usda(&dir.path().join("body.usda"), &frames, head.triangles());
    let obj = run(&scene(
        dir.path(),
        "kind = \"obj-sequence\"\npath = \"body.####.obj\"",
        8,
        100,
        "",
    ));
    let usd = run(&scene(
        dir.path(),
        "kind = \"usd\"\npath = \"body.usda\"\nprim = \"/Char/body\"",
        8,
        100,
        "",
    ));
    assert_eq!(obj.len(), 7);
    for (k, (a, b)) in obj.iter().zip(&usd).enumerate() {
        assert!(a == b, "frame {}: the OBJ and USD runs differ", k + 2);
    }
}

/// A ball (UV sphere, radius 4 cm) sweeping behind the head from x = 0.3 to −0.3 m over frames
/// 1–12, moved by its vertices, as the OBJ sequence `dir/ball.####.obj`.
fn write_ball(dir: &Path) {
    let ball = TriMesh::uv_sphere(0.04, 16, 8).unwrap();
    let frames: Vec<Vec<Vector3<f32>>> = (1..=12)
        .map(|f| {
            let at = Vector3::new(0.3 - 0.6 * (f - 1) as f32 / 11.0, 0.14, 0.08);
            ball.positions().iter().map(|p| p + at).collect()
        })
        .collect();
    write_sequence(dir, "ball", &frames, ball.triangles());
}

#[test]
fn resumed_run_with_deforming_scalp_and_collider_is_bit_identical() {
    let dir = tempfile::tempdir().unwrap();
    let head = hair_groom::builtin_head();
    let frames: Vec<_> = (1..=12).map(|f| shrugged(&head, f)).collect();
    write_sequence(dir.path(), "head", &frames, head.triangles());
    write_ball(dir.path());
    let scene = scene(
        dir.path(),
        "kind = \"obj-sequence\"\npath = \"head.####.obj\"",
        12,
        150,
        "[[colliders]]\nname = \"ball\"\nshape = { kind = \"obj-sequence\", path = \"ball.####.obj\" }\nfriction = 0.3\n",
    );
    let whole = run(&scene);
    let cut = 6;
    let mut before = Session::from_scene(&scene).unwrap();
    while before.frame() < cut {
        before.step().unwrap();
    }
    // What `simulate --resume` does: the scene built afresh, put in the stored frame's state.
    let mut sim = scene.build().unwrap();
    let x: Vec<Vector3<f32>> = before
        .positions()
        .iter()
        .map(|p| Vector3::from(*p))
        .collect();
    let v: Vec<Vector3<f32>> = before
        .velocities()
        .iter()
        .map(|p| Vector3::from(*p))
        .collect();
    sim.strands.positions.copy_from_slice(&x);
    sim.strands.velocities.copy_from_slice(&v);
    sim.first_frame = cut;
    let hash = scene.hash().unwrap();
    let mut resumed = Session::from_simulation(sim, &scene, hash).unwrap();
    for frame in cut + 1..=12 {
        resumed.step().unwrap();
        let (x, v) = &whole[(frame - 2) as usize];
        assert!(
            &bits(resumed.positions()) == x && &bits(resumed.velocities()) == v,
            "frame {frame}: the resumed run differs from the uninterrupted one"
        );
    }
}

fn build_error(scene_text: &str, dir: &Path) -> String {
    let path = dir.join("bad.toml");
    std::fs::write(&path, scene_text).unwrap();
    match SceneFile::load(&path).and_then(|s| s.build()) {
        Ok(_) => panic!("the scene built"),
        Err(e) => e.to_string(),
    }
}

fn minimal(mesh: &str, last: u32) -> String {
    format!(
        "[scene]\nframes = [1, {last}]\n[scalp.mesh]\n{mesh}\n[hair]\ncount = 5\nlength = 0.1\nsegments = 4\n"
    )
}

#[test]
fn missing_frames_topology_changes_and_times_out_of_range_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let head = hair_groom::builtin_head();
    let mut frames: Vec<_> = (1..=6).map(|f| turned(&head, 1.0, f)).collect();
    write_sequence(dir.path(), "head", &frames, head.triangles());
    std::fs::remove_file(dir.path().join("head.0004.obj")).unwrap();
    let e = build_error(
        &minimal("kind = \"obj-sequence\"\npath = \"head.####.obj\"", 6),
        dir.path(),
    );
    assert!(
        e.contains("bad.toml")
            && e.contains("[scalp.mesh]")
            && e.contains("head.0004.obj")
            && e.contains("frame 4")
            && e.contains("1–3, 5–6"),
        "{e}"
    );

    // A frame with one triangle dropped: a topology change, named by file and frame.
    let tri = head.triangles();
    write_obj(
        &dir.path().join("head.0004.obj"),
        &frames[3],
        &tri[..tri.len() - 1],
    );
    let e = build_error(
        &minimal("kind = \"obj-sequence\"\npath = \"head.####.obj\"", 6),
        dir.path(),
    );
    assert!(
        e.contains("head.0004.obj") && e.contains("topology changes"),
        "{e}"
    );

    // USD: frames past the stage's range, and a prim the stage does not have.
    frames.truncate(4);
    write_usda(&dir.path().join("head.usda"), &frames, tri);
    let e = build_error(
        &minimal(
            "kind = \"usd\"\npath = \"head.usda\"\nprim = \"/Char/body\"",
            6,
        ),
        dir.path(),
    );
    assert!(
        e.contains("head.usda") && e.contains("time 5") && e.contains("1 to 4"),
        "{e}"
    );
    let e = build_error(
        &minimal(
            "kind = \"usd\"\npath = \"head.usda\"\nprim = \"/Char/head\"",
            4,
        ),
        dir.path(),
    );
    assert!(
        e.contains("[scalp.mesh]") && e.contains("/Char/head") && e.contains("/Char/body"),
        "{e}"
    );
    let collider = format!(
        "{}\n[[colliders]]\nname = \"body\"\nshape = {{ kind = \"usd\", path = \"head.usda\", prim = \"/Char\" }}\n",
        minimal("kind = \"builtin-head\"", 4)
    );
    let e = build_error(&collider, dir.path());
    assert!(
        e.contains("[[colliders]] #0 (body)") && e.contains("not a Mesh"),
        "{e}"
    );
}

#[test]
fn frames_option_outside_the_frames_read_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let head = hair_groom::builtin_head();
    let frames: Vec<_> = (1..=4).map(|f| turned(&head, 1.0, f)).collect();
    write_sequence(dir.path(), "head", &frames, head.triangles());
    let path = dir.path().join("s.toml");
    std::fs::write(
        &path,
        minimal("kind = \"obj-sequence\"\npath = \"head.####.obj\"", 4),
    )
    .unwrap();
    let opts = hairsys::run::SimulateOptions {
        scene: SceneFile::load(&path).unwrap(),
        cache: dir.path().join("c.mcap"),
        frames: Some((2, 8)),
        threads: Some(1),
        writer: Default::default(),
        resume: false,
        kernel: Default::default(),
        quality: false,
    };
    let e = hairsys::run::simulate(&opts, |_| {})
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("--frames 2-8") && e.contains("head.####.obj") && e.contains("1–4"),
        "{e}"
    );
}

/// The shipped character (`scenes/character.toml`, the Blender-made `data/character/`), cut to
/// 300 sim hairs and frames 1–13 (still, then the head turning 50° while the shoulders shrug):
/// roots on their samples of the mesh read back from the `.usdc` at each frame, no hair point
/// inside it.
#[test]
fn shipped_character_keeps_roots_on_samples_and_hair_outside() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let text = std::fs::read_to_string(root.join("scenes/character.toml"))
        .unwrap()
        .replace("count = 1500", "count = 300")
        .replace("frames = [1, 24]", "frames = [1, 13]");
    let scene = SceneFile::parse(&text, "character.toml", root.join("scenes")).unwrap();
    let usd = hair_groom::UsdMeshSource::open(
        &root.join("data/character/character.usdc"),
        &hair_groom::UsdMeshOptions {
            prim: "/root/rig/body/body".into(),
            units: None,
        },
    )
    .unwrap();
    assert!(usd.is_animated());
    let gap =
        assert_roots_on_samples_and_hair_outside(&scene, |f| usd.mesh_at(f64::from(f)).unwrap());
    assert!(gap > 0.0, "smallest gap {gap}");
}

/// Regression: a deforming mesh placed between frames (`Colliders::place_vertices`,
/// `place_scalp`) kept the shape it was built with until the next step, so `preview --report`
/// measured a cached frame against the first frame's mesh and found hair "inside" where the mesh
/// had moved away (the character's ears). The report measured from the cache must be the one
/// measured during the run (where the mesh moved away, it found points "inside" that the run
/// did not). Also a regression: a cache read from another directory looked for the scene's
/// meshes beside itself.
///
/// The shrug's hair stays within the shipped scenes' depth bound (0.5 mm). Under `"auto"` it
/// runs BDF2, which applies contact after each substep's solve: 10 of 26,400 point-frames end
/// 0.1–0.22 mm inside; semi-implicit Euler, with contact at each of its many more substeps,
/// leaves none.
#[test]
fn the_report_of_a_cached_run_on_a_deforming_scalp_is_the_run_report() {
    let dir = tempfile::tempdir().unwrap();
    let scene = shrug_scene(dir.path());
    // The cache lives elsewhere than the scene: reading it back finds the scene's relative
    // mesh path from the scene directory stored in the cache.
    let elsewhere = tempfile::tempdir().unwrap();
    let cache = elsewhere.path().join("run.mcap");
    let run = hairsys::run::simulate(
        &hairsys::run::SimulateOptions {
            scene,
            cache: cache.clone(),
            frames: None,
            threads: None,
            writer: Default::default(),
            resume: false,
            kernel: Default::default(),
            quality: true,
        },
        |_| {},
    )
    .unwrap()
    .quality
    .expect("asked for");
    let from_cache = hairsys::output::quality::cache_quality(&cache).unwrap();
    assert_eq!(from_cache.run, run.run);
    assert_eq!(from_cache.last, run.last);
    let p = run.run.penetration.as_ref().expect("the scalp collides");
    // The frame-end check: no point deeper than 25 µm, so none beyond the 0.1 mm tolerance.
    assert_eq!(p.inside, 0, "{p:?}");
}
