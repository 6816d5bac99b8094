//! Painted maps: a map sampled at a root equals the map at the root's UV (texture)
//! or the barycentric blend of its vertex values; map selections pick exactly the hair whose
//! root value lies in range; a density map puts no root where it is 0, roots per area in
//! proportion to it elsewhere, and the roots of no map when it is one value everywhere; clump
//! and curl maps scale each parent's children's clump and curl displacement by the value at its
//! root; a map whose values or UVs do not fit the scalp, a density that grows nothing, or a
//! selection that names no hair, is refused with the section and the fix.

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

fn load(dir: &Path, text: &str) -> Result<hairsys::build::Simulation, String> {
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let scene = SceneFile::load(&path).map_err(|e| e.to_string())?;
    scene.build().map_err(|e| e.to_string())
}

/// Root UV and goal weights of each strand of a built scene.
fn roots_and_goals(
    sim: &hairsys::build::Simulation,
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

/// The root UV of every scalp-rooted strand of `sim`.
fn root_uvs(sim: &hairsys::build::Simulation) -> Vec<Vector2<f32>> {
    let mesh = sim.rest_mesh().unwrap();
    sim.strands
        .anchors()
        .iter()
        .filter_map(|a| match a {
            Anchor::Surface(s) => Some(mesh.sample_uv(s).unwrap()),
            Anchor::Body(_) => None,
        })
        .collect()
}

/// Generated hair and sim hairs from guides on the built-in head in one scene, with `extra`
/// and `sim_hairs` (the `[sim_hairs]` root keys).
fn grown_scene(sim_hairs: &str, extra: &str) -> String {
    guided_scene(extra)
        .replace(
            "count = 400\nseed = 3\n",
            &format!("{sim_hairs}\nseed = 3\n"),
        )
        .replace(
            "[guides]",
            "[hair]\ncount = 300\nlength = 0.1\nsegments = 4\nseed = 5\n\n[guides]",
        )
}

#[test]
fn a_density_map_of_one_value_grows_the_roots_of_no_map_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    write_png(&dir.path().join("flat.png"), 16, 16, |_, _| 0.6);
    for sim_hairs in ["count = 400", "min_distance = 0.012"] {
        let plain = load(dir.path(), &grown_scene(sim_hairs, "")).unwrap();
        let mapped = load(
            dir.path(),
            &grown_scene(sim_hairs, "[maps.density]\ntexture = \"flat.png\"\n"),
        )
        .unwrap();
        assert_eq!(plain.strands.len(), mapped.strands.len());
        assert_eq!(
            plain.strands.anchors(),
            mapped.strands.anchors(),
            "{sim_hairs}"
        );
        assert_eq!(
            plain.strands.positions, mapped.strands.positions,
            "{sim_hairs}"
        );
    }
}

#[test]
fn a_density_map_painted_zero_on_half_the_scalp_grows_no_root_there() {
    let dir = tempfile::tempdir().unwrap();
    let width = 64;
    write_png(&dir.path().join("half.png"), width, 8, |u, _| {
        if u < 0.5 {
            0.0
        } else {
            1.0
        }
    });
    // Bilinear sampling is 0 up to the centre of the last unpainted pixel column.
    let unpainted = (width as f32 / 2.0 - 0.5) / width as f32;
    for sim_hairs in ["count = 400", "min_distance = 0.012"] {
        let sim = load(
            dir.path(),
            &grown_scene(sim_hairs, "[maps.density]\ntexture = \"half.png\"\n"),
        )
        .unwrap();
        let uvs = root_uvs(&sim);
        // The count stays the count: 300 [hair] strands, 400 sim hairs.
        if sim_hairs.starts_with("count") {
            assert_eq!(uvs.len(), 700);
        }
        let inside = uvs.iter().filter(|uv| uv.x <= unpainted).count();
        assert_eq!(inside, 0, "{sim_hairs}: {inside} roots where the map is 0");
        assert!(uvs.len() > 300, "{sim_hairs}: {} roots", uvs.len());
    }
}

#[test]
fn roots_per_area_follow_the_painted_density() {
    let dir = tempfile::tempdir().unwrap();
    // A quarter as dense on the u < 0.5 half (8-bit 64/255 is not 0.25: use the map's values).
    write_png(&dir.path().join("d.png"), 64, 8, |u, _| {
        if u < 0.5 {
            0.25
        } else {
            1.0
        }
    });
    let texture = hairsys::rig::maps::Texture::read_png(
        &dir.path().join("d.png"),
        hairsys::rig::maps::Channel::R,
    )
    .unwrap();
    let hair = |count: usize, seed: u64, map: &str| {
        hair_scene(map)
            .replace("count = 300", &format!("count = {count}"))
            .replace("seed = 5", &format!("seed = {seed}"))
    };
    // The expected share of the u ≥ 0.5 half: area-weighted roots (no map, another seed)
    // weighted by the map, ∫_A m dA / ∫ m dA.
    let plain = root_uvs(&load(dir.path(), &hair(40_000, 9, "")).unwrap());
    let m = |uv: &Vector2<f32>| f64::from(texture.sample(*uv).unwrap());
    let total: f64 = plain.iter().map(m).sum();
    let right: f64 = plain.iter().filter(|uv| uv.x >= 0.5).map(m).sum();
    let expected = right / total;
    let n = 4000;
    let dense = root_uvs(
        &load(
            dir.path(),
            &hair(n, 5, "[maps.density]\ntexture = \"d.png\"\n"),
        )
        .unwrap(),
    );
    assert_eq!(dense.len(), n);
    let share = dense.iter().filter(|uv| uv.x >= 0.5).count() as f64 / n as f64;
    // Binomial sd of the share ≈ 0.007 at n = 4000 (the expectation's own error is ~3× less).
    assert!(
        (share - expected).abs() < 0.03,
        "share {share} of roots where the map is 1, expected {expected}"
    );
    // Without the map the same half holds a clearly smaller share.
    let plain_share = plain.iter().filter(|uv| uv.x >= 0.5).count() as f64 / plain.len() as f64;
    assert!(expected > plain_share + 0.15, "{expected} vs {plain_share}");
}

#[test]
fn a_density_that_grows_nothing_or_is_negative_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    write_png(&dir.path().join("zero.png"), 4, 4, |_, _| 0.0);
    let e = refused(
        dir.path(),
        &hair_scene("[maps.density]\ntexture = \"zero.png\"\n"),
    );
    assert!(
        e.contains("[maps.density] is 0 everywhere") && e.contains("no hair would grow"),
        "{e}"
    );
    // Painted only where the [hair] region does not reach: nothing can grow in the region.
    write_png(&dir.path().join("half.png"), 64, 8, |u, _| {
        if u < 0.5 {
            0.0
        } else {
            1.0
        }
    });
    let mesh = TriMesh::uv_sphere(0.1, 24, 12).unwrap();
    write_obj(
        &dir.path().join("scalp.obj"),
        &mesh,
        |p| [if p.z > 0.0 { -0.5 } else { 1.0 }, 0.0, 0.0],
        true,
    );
    let e = refused(
        dir.path(),
        &obj_scene("[maps.density]\nvertex_colors = true\n"),
    );
    assert!(
        e.contains("[maps.density] is -0.5 at vertex") && e.contains("≥ 0"),
        "{e}"
    );
    let strands_only = "[scene]\nframes = [1, 4]\n\n[scalp.mesh]\nkind = \"builtin-head\"\n\n\
        [[strands]]\npoints = [[0.0, 0.0, 0.0], [0.0, 0.0, -0.1]]\n\n\
        [maps.density]\ntexture = \"half.png\"\n";
    let e = refused(dir.path(), strands_only);
    assert!(
        e.contains("[maps.density]") && e.contains("has neither"),
        "{e}"
    );
}

/// The children of parent `p` in `c`: each child's points, flat.
fn children_of(c: &hair_render::ChildBuffers, p: u32) -> Vec<Vec<f32>> {
    let mut at = 0;
    let mut out = Vec::new();
    for (k, &n) in c.vertex_counts.iter().enumerate() {
        let len = 3 * n as usize;
        if c.parent[k] == p {
            out.push(c.points[at..at + len].to_vec());
        }
        at += len;
    }
    out
}

#[test]
fn clump_and_curl_maps_scale_each_parents_children_by_the_value_at_its_root() {
    let dir = tempfile::tempdir().unwrap();
    // Thirds of the UV square: 0, 0.4 (102/255 in 8 bits… 16 bits here), 1.
    let band = |u: f32| {
        if u < 1.0 / 3.0 {
            0.0
        } else if u < 2.0 / 3.0 {
            0.4
        } else {
            1.0
        }
    };
    write_png(&dir.path().join("c.png"), 96, 8, move |u, _| band(u));
    let texture = hairsys::rig::maps::Texture::read_png(
        &dir.path().join("c.png"),
        hairsys::rig::maps::Channel::R,
    )
    .unwrap();
    let maps = "[maps.clump]\ntexture = \"c.png\"\n\n[maps.curl]\ntexture = \"c.png\"\n";
    let painted = hairsys::Session::from_scene(&{
        let path = dir.path().join("painted.toml");
        std::fs::write(&path, hair_scene(maps)).unwrap();
        SceneFile::load(&path).unwrap()
    })
    .unwrap();
    let plain = hairsys::Session::from_scene(&{
        let path = dir.path().join("plain.toml");
        std::fs::write(&path, hair_scene("")).unwrap();
        SceneFile::load(&path).unwrap()
    })
    .unwrap();
    let mut settings = hair_render::ChildSettings {
        count: hair_render::ChildCount::PerParent(4),
        ..Default::default()
    };
    settings.shape.clump.factor = 0.8;
    settings.shape.curl.radius = 0.004;
    settings.shape.curl.frequency = 30.0;
    let lod = hair_render::Lod::Render;
    let mapped = painted.children(&settings, lod, None).unwrap();
    let today = plain.children(&settings, lod, None).unwrap();
    let mut bare = settings;
    bare.shape.clump.factor = 0.0;
    bare.shape.curl.radius = 0.0;
    let none = plain.children(&bare, lod, None).unwrap();
    let mesh = painted.scalp().mesh.clone().unwrap();
    let mut seen = [0; 3];
    for (p, anchor) in painted.strands().anchors().iter().enumerate() {
        let Anchor::Surface(sample) = anchor else {
            unreachable!()
        };
        let uv = mesh.sample_uv(sample).unwrap();
        let m = texture.sample(uv).unwrap();
        let p = p as u32;
        let (got, one, zero) = (
            children_of(&mapped, p),
            children_of(&today, p),
            children_of(&none, p),
        );
        if m == 0.0 {
            // No clump and no curl displacement: the children of clump 0 and curl radius 0.
            assert_eq!(got, zero, "parent {p} painted 0 at {uv:?}");
            seen[0] += 1;
        } else if m == 1.0 {
            assert_eq!(got, one, "parent {p} painted 1 at {uv:?}");
            seen[2] += 1;
        } else if (m - 0.4).abs() < 1e-4 {
            // Clump and curl displacement (from the unclumped, uncurled child) scale by m.
            let mut largest = 0.0f32;
            for ((g, o), z) in got.iter().zip(&one).zip(&zero) {
                for i in 0..g.len() {
                    let want = z[i] + m * (o[i] - z[i]);
                    assert!(
                        (g[i] - want).abs() < 2e-6,
                        "parent {p} (m = {m}) coordinate {i}: {} vs {want}",
                        g[i]
                    );
                    largest = largest.max((o[i] - z[i]).abs());
                }
            }
            assert!(
                largest > 1e-3,
                "the settings displace children ({largest} m)"
            );
            seen[1] += 1;
        }
    }
    assert!(seen.iter().all(|&n| n > 20), "parents per band {seen:?}");
}

#[test]
fn clump_and_curl_factors_outside_zero_to_one_are_refused_naming_the_strand() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = TriMesh::uv_sphere(0.1, 24, 12).unwrap();
    write_obj(
        &dir.path().join("scalp.obj"),
        &mesh,
        |_| [0.5, 1.5, 0.0],
        false,
    );
    let e = refused(
        dir.path(),
        &obj_scene("[maps.curl]\nvertex_colors = true\nchannel = \"g\"\n"),
    );
    assert!(
        e.contains("[maps.curl] is 1.5 at strand 0") && e.contains("[0, 1]"),
        "{e}"
    );
}
