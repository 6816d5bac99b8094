//! `[maps.length]` on `[sim_hairs]`: each sim hair is trimmed to the painted
//! fraction of its length (same point count, cut along its built curve, same mass per length),
//! and animated guides re-pose the trimmed hair, not the full one: at sim weight 1 the hair sits
//! exactly on its trimmed animated rest shape, which is the full hair's pose cut at the same
//! fraction; resuming is bit-identical, children grow on the trimmed parents, and a fraction
//! outside (0, 1] is refused naming the sim hair.

use std::path::Path;

use hair_core::{Anchor, RootFrame, StrandSet, TriMesh};
use hairsys::rig::maps::{Channel, Texture};
use hairsys::scene::SceneFile;
use hairsys::Session;
use nalgebra::Vector3;

/// Writes a `width × height` 16-bit grey PNG whose pixel centre at (u, v) is `f(u, v)`.
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

/// A guided head turning over frames 1–12 (like `animated_guides.rs`), 30 guides and 150 sim
/// hairs of 9 points, with `extra` appended (maps, keys under `[guides]` go in `keys`).
fn scene_text(keys: &str, extra: &str) -> String {
    format!(
        r#"
[scene]
fps = 24.0
frames = [1, 12]

[solver]
substeps = "auto"
damping_iterations = 10
max_strain = 0.01

[physics]
gravity = [0.0, 0.0, -9.81]
stretch_stiffness = 40.0
bend_stiffness = 5.0
goal_stiffness = 2.0
stretch_damping = 1000.0
air_drag = 2.0

[scalp.mesh]
kind = "builtin-head"

[scalp.collider]
thickness = 0.001

[scalp.motion]
keys = [
    {{ frame = 1, rotation_deg = [0.0, 0.0, 0.0] }},
    {{ frame = 12, rotation_deg = [0.0, 0.0, 60.0] }},
]

[guides]
count = 30
length = 0.2
segments = 8
seed = 2
region = {{ direction = [0.0, 0.4, 1.0], max_angle_deg = 80.0 }}
comb_direction = [0.0, 1.0, -0.6]
comb_angle_deg = 50.0
{keys}

[sim_hairs]
count = 150
seed = 3
k = 4
distance = "euclidean"
clearance = 0.003
goal_root = 0.2
goal_tip = 0.1

{extra}
"#
    )
}

const GUST: &str = r#"
[[guides.pose]]
frame = 1
[[guides.pose]]
frame = 7
sweep = { direction = [1.0, 0.0, 0.0], angle_deg = 70.0 }
"#;

const LENGTH_MAP: &str = "[maps.length]\ntexture = \"length.png\"\n";

/// A length ramp across the scalp's UVs: 0.3 at u = 0 to 1 at u = 1.
fn ramp(u: f32, _v: f32) -> f32 {
    0.3 + 0.7 * u
}

/// A directory holding the ramp map, and the map as hairsys reads it.
fn map_dir() -> (tempfile::TempDir, Texture) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("length.png");
    write_png(&path, 64, 16, ramp);
    let texture = Texture::read_png(&path, Channel::R).unwrap();
    (dir, texture)
}

fn load(dir: &Path, name: &str, text: &str) -> Result<SceneFile, String> {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    SceneFile::load(&path).map_err(|e| e.to_string())
}

fn polyline_length(p: &[Vector3<f32>]) -> f32 {
    p.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
}

/// The painted fraction at each sim hair's root (`texture` sampled at its UV), in sim-hair order.
fn fractions(
    strands: &StrandSet,
    mesh: &TriMesh,
    range: std::ops::Range<usize>,
    t: &Texture,
) -> Vec<f32> {
    range
        .map(|s| {
            let Anchor::Surface(sample) = strands.anchors()[s] else {
                unreachable!("sim hairs grow on the scalp")
            };
            t.sample(mesh.sample_uv(&sample).unwrap()).unwrap()
        })
        .collect()
}

#[test]
fn a_painted_length_map_trims_each_sim_hair_to_the_map_at_its_root() {
    let (dir, texture) = map_dir();
    let plain = load(dir.path(), "plain.toml", &scene_text("", ""))
        .unwrap()
        .build()
        .unwrap();
    let painted = load(dir.path(), "painted.toml", &scene_text("", LENGTH_MAP))
        .unwrap()
        .build()
        .unwrap();
    let range = painted.guide_animation.as_ref().unwrap().strands();
    assert_eq!(range, plain.guide_animation.as_ref().unwrap().strands());
    let scalp = painted.scalp_at(1.0);
    let f = fractions(
        &painted.strands,
        scalp.mesh.as_ref().unwrap(),
        range.clone(),
        &texture,
    );
    let (a, b) = (&plain.strands, &painted.strands);
    let mut shortest = 1.0f32;
    for (h, s) in range.enumerate() {
        // Same roots, same point count.
        assert_eq!(a.anchors()[s], b.anchors()[s]);
        assert_eq!(a.points(s).len(), b.points(s).len());
        let full = &a.rest_local()[a.points(s)];
        let cut = &b.rest_local()[b.points(s)];
        // The trimmed hair is the built one cut at the painted fraction of its arc length and
        // resampled (the same function on the same built curve: bit for bit).
        let mut want = vec![Vector3::zeros(); full.len()];
        hair_groom::trim_polyline(full, f[h], &mut want);
        assert_eq!(cut, &want[..], "sim hair {h} painted {}", f[h]);
        // Its length is the painted fraction of the full one's, short of it only by the chords
        // of the resampled curve (gently combed hair: well under 1 %).
        let ratio = polyline_length(cut) / polyline_length(full);
        assert!(
            (f[h] * 0.99..=f[h] * (1.0 + 1e-5)).contains(&ratio),
            "sim hair {h}: length ratio {ratio}, painted {}",
            f[h]
        );
        // Same mass per length.
        let mass = |set: &StrandSet| -> f32 {
            set.inverse_masses()[set.points(s)]
                .iter()
                .skip(1) // the root is pinned (no inverse mass)
                .map(|w| 1.0 / w)
                .sum()
        };
        let per_length = |set: &StrandSet, p: &[Vector3<f32>]| mass(set) / polyline_length(p);
        let (ma, mb) = (per_length(a, full), per_length(b, cut));
        assert!(
            (ma / mb - 1.0).abs() < 0.02,
            "sim hair {h}: {ma} vs {mb} kg/m"
        );
        shortest = shortest.min(f[h]);
    }
    assert!(
        shortest < 0.6,
        "the ramp should reach short hair: least {shortest}"
    );
}

/// Where the session's animated guides put each sim hair point now (its root frame placing its
/// current rest shape), hair by hair.
fn animated(session: &Session) -> Vec<Vec<Vector3<f32>>> {
    let strands = session.strands();
    let roots: &[RootFrame] = session.solver().roots();
    session
        .guide_animation()
        .unwrap()
        .strands()
        .map(|s| {
            strands
                .points(s)
                .map(|i| roots[s].to_world(&strands.rest_local()[i]))
                .collect()
        })
        .collect()
}

#[test]
fn animated_guides_re_pose_the_trimmed_hairs_and_sim_weight_one_follows_them_exactly() {
    let (dir, texture) = map_dir();
    let keys = format!("{GUST}\n[guides.sim_weight]\nkeys = [{{ frame = 1, value = 1.0 }}]\n");
    // Without the build's lift the built rest shapes are the blend of the groom (to f32
    // rounding), so a posed rest shape is the blend of the pose re-walked at the built lengths.
    let text = |maps: &str| scene_text(&keys, maps).replace("clearance = 0.003\n", "");
    let mut full = Session::from_scene(&load(dir.path(), "f.toml", &text("")).unwrap()).unwrap();
    let mut cut =
        Session::from_scene(&load(dir.path(), "c.toml", &text(LENGTH_MAP)).unwrap()).unwrap();
    let range = cut.guide_animation().unwrap().strands();
    let f = fractions(
        cut.strands(),
        cut.scalp().mesh.as_ref().unwrap(),
        range.clone(),
        &texture,
    );
    let n = cut.strands().points(range.start).len();
    let built: Vec<f32> = range
        .clone()
        .map(|s| polyline_length(&cut.strands().rest_local()[cut.strands().points(s)]))
        .collect();
    let groom: Vec<Vec<Vector3<f32>>> = range
        .clone()
        .map(|s| cut.strands().rest_local()[cut.strands().points(s)].to_vec())
        .collect();
    let (mut worst, mut swept) = (0.0f32, 0.0f32);
    for _ in 2..=12 {
        full.step().unwrap();
        cut.step().unwrap();
        // The trimmed animated guides: the full hairs' blend of this frame's pose, trimmed.
        let pose = cut
            .guide_animation()
            .unwrap()
            .pose_at(cut.frame() as f32)
            .unwrap();
        let mut blend_full = vec![Vector3::zeros(); range.len() * n];
        let mut blend_cut = blend_full.clone();
        full.guide_animation()
            .unwrap()
            .blend()
            .apply(&pose, &mut blend_full);
        cut.guide_animation()
            .unwrap()
            .blend()
            .apply(&pose, &mut blend_cut);
        let posed_cut = animated(&cut);
        for (h, s) in range.clone().enumerate() {
            let at = h * n..(h + 1) * n;
            let mut want = blend_full[at.clone()].to_vec();
            if f[h] < 1.0 {
                hair_groom::trim_polyline(&blend_full[at.clone()], f[h], &mut want);
            }
            assert_eq!(&blend_cut[at.clone()], &want[..], "sim hair {h}");
            // Sim weight 1: every point exactly on the trimmed animated guides.
            for (i, xa) in cut.strands().points(s).zip(&posed_cut[h]) {
                let x = Vector3::from(cut.positions()[i]);
                assert!(
                    (x - xa).norm() <= 1e-6 * (1.0 + xa.norm()),
                    "frame {}: sim hair {h} point {i} at {x:?}, its animated guide at {xa:?}",
                    cut.frame()
                );
            }
            // The posed rest shape keeps the trimmed hair's length…
            let rest = &cut.strands().rest_local()[cut.strands().points(s)];
            let length = polyline_length(rest);
            assert!(
                (length - built[h]).abs() < 1e-5,
                "frame {}: sim hair {h} posed to {length} m, built {} m",
                cut.frame(),
                built[h]
            );
            // …and lies on the trimmed blend of the pose, re-walked at the built lengths.
            let off = rest
                .iter()
                .zip(&blend_cut[at])
                .map(|(a, b)| (a - b).norm())
                .fold(0.0, f32::max);
            worst = worst.max(off);
            swept = swept.max(
                rest.iter()
                    .zip(&groom[h])
                    .map(|(a, b)| (a - b).norm())
                    .fold(0.0, f32::max),
            );
        }
    }
    // The 70° gust moved the trimmed rest shapes by centimetres, and they stayed on the trimmed
    // blend of the pose.
    assert!(
        swept > 0.02,
        "the gust moved trimmed rest shapes by only {swept} m"
    );
    assert!(
        worst < 1e-3,
        "the trimmed pose is {worst} m off the trimmed blend of the pose"
    );
}

#[test]
fn resume_with_a_length_map_and_animated_guides_is_bit_identical() {
    let (dir, _) = map_dir();
    let keys = format!(
        "{GUST}\n[guides.sim_weight]\nkeys = [{{ frame = 3, value = 0.0 }}, {{ frame = 6, value = 1.0 }}, {{ frame = 9, value = 0.3 }}]\n"
    );
    let file = load(dir.path(), "r.toml", &scene_text(&keys, LENGTH_MAP)).unwrap();
    let run = |s: &mut Session, last: u32| {
        let mut out = Vec::new();
        while s.frame() < last {
            s.step().unwrap();
            out.push((s.positions().to_vec(), s.velocities().to_vec()));
        }
        out
    };
    let bits =
        |v: &[[f32; 3]]| -> Vec<[u32; 3]> { v.iter().map(|p| p.map(f32::to_bits)).collect() };
    let reference = run(&mut Session::from_scene(&file).unwrap(), 12);
    let cut = 7;
    let mut before = Session::from_scene(&file).unwrap();
    run(&mut before, cut);
    // What `simulate --resume` does: a fresh build put in the stored state at the cut.
    let mut sim = file.build().unwrap();
    for (x, p) in sim.strands.positions.iter_mut().zip(before.positions()) {
        *x = Vector3::from(*p);
    }
    for (v, p) in sim.strands.velocities.iter_mut().zip(before.velocities()) {
        *v = Vector3::from(*p);
    }
    sim.first_frame = cut;
    let mut resumed = Session::from_simulation(sim, &file, file.hash().unwrap()).unwrap();
    let continued = run(&mut resumed, 12);
    assert_eq!(continued.len(), (12 - cut) as usize);
    for (k, (a, b)) in continued
        .iter()
        .zip(&reference[(cut - 1) as usize..])
        .enumerate()
    {
        assert!(
            bits(&a.0) == bits(&b.0) && bits(&a.1) == bits(&b.1),
            "frame {}: the resumed run differs",
            cut + 1 + k as u32
        );
    }
    // Children grow on the trimmed parents: a child is about as long as its parent.
    let settings = hair_render::ChildSettings {
        count: hair_render::ChildCount::PerParent(3),
        ..Default::default()
    };
    let children = resumed
        .children(&settings, hair_render::Lod::Render, None)
        .unwrap();
    let strands = resumed.strands();
    let mut at = 0;
    let mut checked = 0;
    for (k, &n) in children.vertex_counts.iter().enumerate() {
        let points: Vec<Vector3<f32>> = children.points[at..at + 3 * n as usize]
            .chunks_exact(3)
            .map(|c| Vector3::new(c[0], c[1], c[2]))
            .collect();
        at += 3 * n as usize;
        let p = children.parent[k] as usize;
        let parent: Vec<Vector3<f32>> = strands.points(p).map(|i| strands.positions[i]).collect();
        let ratio = polyline_length(&points) / polyline_length(&parent);
        assert!(
            (0.7..1.5).contains(&ratio),
            "child {k} of {p}: {ratio} × its parent's length"
        );
        checked += 1;
    }
    assert!(checked >= 150 * 3, "{checked} children");
}

/// Writes `mesh` as an OBJ (with its UVs) whose every vertex colour is `value` in red.
fn write_obj(path: &Path, mesh: &TriMesh, value: f32) {
    let mut text = String::new();
    for p in mesh.positions() {
        text += &format!("v {} {} {} {value} 0 0\n", p.x, p.y, p.z);
    }
    for t in mesh.uvs().unwrap() {
        text += &format!("vt {} {}\n", t.x, t.y);
    }
    for t in mesh.triangles() {
        let [a, b, c] = t.map(|i| i + 1);
        text += &format!("f {a}/{a} {b}/{b} {c}/{c}\n");
    }
    std::fs::write(path, text).unwrap();
}

#[test]
fn length_fractions_outside_zero_to_one_are_refused_naming_the_sim_hair() {
    let dir = tempfile::tempdir().unwrap();
    // 0 on the left half of the UV square, where some sim hairs grow.
    write_png(&dir.path().join("length.png"), 64, 16, |u, _| {
        if u < 0.5 {
            0.0
        } else {
            1.0
        }
    });
    let e = load(dir.path(), "zero.toml", &scene_text("", LENGTH_MAP))
        .unwrap()
        .build()
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("[maps.length] is 0 at sim hair") && e.contains("(0, 1]"),
        "{e}"
    );
    // Vertex colours may exceed 1: a fraction of 1.5 would lengthen hair, which a trim cannot.
    write_obj(
        &dir.path().join("scalp.obj"),
        &hair_groom::builtin_head(),
        1.5,
    );
    let text = scene_text("", "[maps.length]\nvertex_colors = true\n").replace(
        "kind = \"builtin-head\"",
        "kind = \"obj\"\npath = \"scalp.obj\"",
    );
    let e = load(dir.path(), "long.toml", &text)
        .unwrap()
        .build()
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("[maps.length] is 1.5 at sim hair 0") && e.contains("at most 1"),
        "{e}"
    );
}
