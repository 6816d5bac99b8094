//! Painted maps (issue 20): a map sampled at a root equals the map at the root's UV (texture)
//! or the barycentric blend of its vertex values; map selections pick exactly the hair whose
//! root value lies in range; a map whose values or UVs do not fit the scalp, or a selection
//! that names no hair, is refused with the section and the fix.

use std::path::Path;

use hair_core::{Anchor, TriMesh};
use hairsys::scene::SceneFile;
use nalgebra::{Vector2, Vector3};

/// Writes a `width × height` 16-bit grey PNG whose pixel at column `i`, row `j` (row 0 at the
/// top, v = 1) is `f(u, v)` at the pixel's centre.
fn write_png(path: &Path, width: u32, height: u32, f: impl Fn(f32, f32) -> f32) {
    let mut data = Vec::new();
    for j in 0..height {
        for i in 0..width {
            let u = (i as f32 + 0.5) / width as f32;
            let v = 1.0 - (j as f32 + 0.5) / height as f32;
            let value = (f(u, v).clamp(0.0, 1.0) * 65535.0).round() as u16;
            data.extend_from_slice(&value.to_be_bytes());
        }
    }
    let file = std::fs::File::create(path).unwrap();
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    enc.set_color(png::ColorType::Grayscale);
    enc.set_depth(png::BitDepth::Sixteen);
    enc.write_header().unwrap().write_image_data(&data).unwrap();
}

/// A scene on the built-in head (which has UVs) with generated `[hair]` whose goal weight is 1
/// at every point, and `extra` appended.
fn hair_scene(extra: &str) -> String {
    format!(
        r#"
[scene]
frames = [1, 4]

[scalp.mesh]
kind = "builtin-head"

[hair]
count = 300
length = 0.1
segments = 4
seed = 5
goal_root = 1.0
goal_tip = 1.0

{extra}
"#
    )
}

fn load(dir: &Path, text: &str) -> Result<hairsys::scene::Simulation, String> {
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let scene = SceneFile::load(&path).map_err(|e| e.to_string())?;
    scene.build().map_err(|e| e.to_string())
}

/// Root UV and goal weights of each strand of a built scene.
fn roots_and_goals(
    sim: &hairsys::scene::Simulation,
) -> Vec<(Vector2<f32>, Vector3<f32>, Vec<f32>)> {
    let scalp = sim.scalp_at(sim.first_frame as f32);
    let mesh = scalp.mesh.as_ref().unwrap();
    let strands = &sim.strands;
    (0..strands.len())
        .map(|s| {
            let Anchor::Surface(sample) = strands.anchors()[s] else {
                panic!("generated hair grows on the scalp")
            };
            let uv = mesh.sample_uv(&sample).unwrap();
            let root = mesh.evaluate(&sample).origin;
            let goals = strands.goal_weights()[strands.points(s)].to_vec();
            (uv, root, goals)
        })
        .collect()
}

#[test]
fn a_texture_map_at_a_root_is_the_map_at_its_uv() {
    let dir = tempfile::tempdir().unwrap();
    // A linear ramp: bilinear sampling reproduces it exactly between the outer pixel centres.
    let ramp = |u: f32, v: f32| 0.2 + 0.5 * u + 0.25 * v;
    let (w, h) = (64, 32);
    write_png(&dir.path().join("goal.png"), w, h, ramp);
    let sim = load(
        dir.path(),
        &hair_scene("[maps.goal]\ntexture = \"goal.png\"\n"),
    )
    .unwrap();
    let mut checked = 0;
    for (uv, _, goals) in roots_and_goals(&sim) {
        let inside = (0.5 / w as f32..=1.0 - 0.5 / w as f32).contains(&uv.x)
            && (0.5 / h as f32..=1.0 - 0.5 / h as f32).contains(&uv.y);
        if !inside {
            continue;
        }
        // 16-bit quantisation of the painted values: 1/65535.
        let want = ramp(uv.x, uv.y);
        for g in goals.iter().skip(1) {
            assert!((g - want).abs() < 2e-5, "goal {g} at UV {uv:?}, map {want}");
        }
        checked += 1;
    }
    assert!(checked > 200, "only {checked} roots inside the ramp");
}

/// Writes `mesh` as an OBJ whose vertex colours are `color(position)`, with or without its UVs.
fn write_obj(path: &Path, mesh: &TriMesh, color: impl Fn(&Vector3<f32>) -> [f32; 3], uvs: bool) {
    let mut text = String::new();
    for p in mesh.positions() {
        let c = color(p);
        text += &format!("v {} {} {} {} {} {}\n", p.x, p.y, p.z, c[0], c[1], c[2]);
    }
    if uvs {
        for t in mesh.uvs().unwrap() {
            text += &format!("vt {} {}\n", t.x, t.y);
        }
    }
    for t in mesh.triangles() {
        let [a, b, c] = t.map(|i| i + 1);
        text += &if uvs {
            format!("f {a}/{a} {b}/{b} {c}/{c}\n")
        } else {
            format!("f {a} {b} {c}\n")
        };
    }
    std::fs::write(path, text).unwrap();
}

fn obj_scene(extra: &str) -> String {
    hair_scene(extra).replace(
        "kind = \"builtin-head\"",
        "kind = \"obj\"\npath = \"scalp.obj\"",
    )
}

#[test]
fn a_vertex_colour_map_at_a_root_is_the_barycentric_blend_of_its_vertices() {
    let dir = tempfile::tempdir().unwrap();
    // Green linear in position: the barycentric blend of a linear field is the field at the
    // root, exactly (to f32).
    let field = |p: &Vector3<f32>| 0.5 + 2.0 * p.x - 1.5 * p.z;
    let mesh = TriMesh::uv_sphere(0.1, 24, 12).unwrap();
    write_obj(
        &dir.path().join("scalp.obj"),
        &mesh,
        |p| [0.0, field(p), 1.0],
        false,
    );
    let sim = load(
        dir.path(),
        &obj_scene("[maps.goal]\nvertex_colors = true\nchannel = \"g\"\n"),
    );
    // The UV sphere's root values stay in [0, 1]: 0.5 ± 0.35.
    let sim = sim.unwrap();
    let scalp = sim.scalp_at(1.0);
    let mesh = scalp.mesh.as_ref().unwrap();
    for s in 0..sim.strands.len() {
        let Anchor::Surface(sample) = sim.strands.anchors()[s] else {
            unreachable!()
        };
        let root = mesh.evaluate(&sample).origin;
        let want = field(&root);
        for g in &sim.strands.goal_weights()[sim.strands.points(s)] {
            assert!(
                (g - want).abs() < 1e-5,
                "goal {g}, field {want} at {root:?}"
            );
        }
    }
}

/// A guided scene with a half-painted map selecting the hold-out.
fn guided_scene(extra: &str) -> String {
    format!(
        r#"
[scene]
frames = [1, 4]

[scalp.mesh]
kind = "builtin-head"

[guides]
count = 40
length = 0.15
segments = 6
seed = 2
region = {{ direction = [0.0, 0.4, 1.0], max_angle_deg = 80.0 }}

[sim_hairs]
count = 400
seed = 3
k = 4
distance = "euclidean"

{extra}
"#
    )
}

#[test]
fn a_map_selection_holds_out_exactly_the_hair_painted_in_range() {
    let dir = tempfile::tempdir().unwrap();
    // Painted on the +u half of the scalp (the +X side of the head).
    let (w, h) = (32, 32);
    let paint = |u: f32, _v: f32| if u > 0.5 { 1.0 } else { 0.0 };
    write_png(&dir.path().join("side.png"), w, h, paint);
    let sim = load(
        dir.path(),
        &guided_scene(
            "[maps.side]\ntexture = \"side.png\"\n\n[guides.hold_out]\nmap = { name = \"side\", min = 0.5 }\n",
        ),
    )
    .unwrap();
    let anim = sim.guide_animation.as_ref().unwrap();
    let scalp = sim.scalp_at(1.0);
    let mesh = scalp.mesh.as_ref().unwrap();
    let mut held = 0;
    for (i, s) in anim.strands().enumerate() {
        let Anchor::Surface(sample) = sim.strands.anchors()[s] else {
            unreachable!()
        };
        let uv = mesh.sample_uv(&sample).unwrap();
        // Away from the painted edge, where bilinear sampling blends the two halves.
        if (uv.x - 0.5).abs() < 1.0 / w as f32 {
            continue;
        }
        assert_eq!(anim.hold_out()[i], uv.x > 0.5, "sim hair {i} at UV {uv:?}");
        held += usize::from(anim.hold_out()[i]);
    }
    assert!(held > 50, "{held} held out");
    // Hold-out hair is pinned at every point; the rest is free but for its root.
    for (i, s) in anim.strands().enumerate() {
        // A pinned point has no inverse mass.
        let inverse = &sim.strands.inverse_masses()[sim.strands.points(s)];
        assert_eq!(inverse.iter().all(|&m| m == 0.0), anim.hold_out()[i]);
    }
}

#[test]
fn a_painted_sim_weight_is_each_hairs_factor_of_the_curve() {
    let dir = tempfile::tempdir().unwrap();
    let ramp = |u: f32, _v: f32| u;
    write_png(&dir.path().join("w.png"), 64, 8, ramp);
    let sim = load(
        dir.path(),
        &guided_scene(
            "[maps.sim_weight]\ntexture = \"w.png\"\n\n[guides.sim_weight]\nkeys = [{ frame = 1, value = 1.0 }]\n",
        ),
    )
    .unwrap();
    let anim = sim.guide_animation.as_ref().unwrap();
    let scalp = sim.scalp_at(1.0);
    let mesh = scalp.mesh.as_ref().unwrap();
    for (i, s) in anim.strands().enumerate() {
        let Anchor::Surface(sample) = sim.strands.anchors()[s] else {
            unreachable!()
        };
        let uv = mesh.sample_uv(&sample).unwrap();
        if !(1.0 / 128.0..=1.0 - 1.0 / 128.0).contains(&uv.x) {
            continue;
        }
        assert!((anim.factors()[i] - uv.x).abs() < 2e-5, "{i} {uv:?}");
    }
}

fn refused(dir: &Path, text: &str) -> String {
    match load(dir, text) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e,
    }
}

#[test]
fn a_texture_on_a_scalp_without_uvs_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = TriMesh::uv_sphere(0.1, 12, 6).unwrap();
    write_obj(&dir.path().join("scalp.obj"), &mesh, |_| [0.5; 3], false);
    write_png(&dir.path().join("goal.png"), 4, 4, |_, _| 0.5);
    let e = refused(
        dir.path(),
        &obj_scene("[maps.goal]\ntexture = \"goal.png\"\n"),
    );
    assert!(e.contains("[maps.goal]") && e.contains("no UVs"), "{e}");
}

#[test]
fn a_texture_whose_uvs_leave_the_unit_square_is_refused_naming_the_root() {
    let dir = tempfile::tempdir().unwrap();
    // The sphere's UVs moved to the next tile (UDIM 1002).
    let sphere = TriMesh::uv_sphere(0.1, 12, 6).unwrap();
    let uvs: Vec<Vector2<f32>> = sphere
        .uvs()
        .unwrap()
        .iter()
        .map(|t| t + Vector2::new(1.0, 0.0))
        .collect();
    let mesh = TriMesh::new(sphere.positions().to_vec(), sphere.triangles().to_vec())
        .unwrap()
        .with_uvs(uvs)
        .unwrap();
    write_obj(&dir.path().join("scalp.obj"), &mesh, |_| [0.5; 3], true);
    write_png(&dir.path().join("goal.png"), 4, 4, |_, _| 0.5);
    let e = refused(
        dir.path(),
        &obj_scene("[maps.goal]\ntexture = \"goal.png\"\n"),
    );
    assert!(
        e.contains("goal.png") && e.contains("[hair] strand 0") && e.contains("outside"),
        "{e}"
    );
}

#[test]
fn vertex_colours_on_a_scalp_without_them_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let e = refused(
        dir.path(),
        &hair_scene("[maps.goal]\nvertex_colors = true\n"),
    );
    assert!(
        e.contains("[maps.goal]") && e.contains("no vertex colours"),
        "{e}"
    );
}

#[test]
fn a_map_selection_that_names_no_hair_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    write_png(&dir.path().join("side.png"), 4, 4, |_, _| 0.2);
    let e = refused(
        dir.path(),
        &guided_scene(
            "[maps.side]\ntexture = \"side.png\"\n\n[guides.hold_out]\nmap = { name = \"side\", min = 0.5 }\n",
        ),
    );
    assert!(
        e.contains("[guides.hold_out]") && e.contains("names no hair"),
        "{e}"
    );
    let e = refused(
        dir.path(),
        &guided_scene("[[guides.pin]]\nmap = { name = \"fringe\" }\n"),
    );
    assert!(
        e.contains("\"fringe\"") && e.contains("[maps.fringe]"),
        "{e}"
    );
}

#[test]
fn unused_and_unsupported_maps_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    write_png(&dir.path().join("m.png"), 4, 4, |_, _| 0.5);
    let e = refused(
        dir.path(),
        &hair_scene("[maps.goal_weight]\ntexture = \"m.png\"\n"),
    );
    assert!(e.contains("[maps.goal_weight] is used by nothing"), "{e}");
    let e = refused(
        dir.path(),
        &hair_scene("[maps.density]\ntexture = \"m.png\"\n"),
    );
    assert!(e.contains("not supported yet"), "{e}");
    let e = refused(
        dir.path(),
        &hair_scene("[maps.sim_weight]\ntexture = \"m.png\"\n"),
    );
    assert!(
        e.contains("[maps.sim_weight]") && e.contains("no [guides]"),
        "{e}"
    );
    let e = refused(
        dir.path(),
        &hair_scene("[maps.goal]\ntexture = \"missing.png\"\n"),
    );
    assert!(
        e.contains("missing.png") && e.contains("cannot open"),
        "{e}"
    );
}
