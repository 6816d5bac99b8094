//! `[[regions]]` and `[maps.stiffness]` (per-region physics): a region's stiffness
//! changes only that region's motion (the other strands bit for bit as without it) and a stiffer
//! region keeps closer to its groomed shape under gravity; a scene without regions gives the
//! solver no factors; overlapping regions take each key from the last; a region that names no
//! hair, a duplicate name, a value the scene has switched off and the rod model are refused by
//! name. The session changes a region's parameters between frames.

use std::path::Path;

use hairsys::scene::regions::RegionParams;
use hairsys::scene::SceneFile;
use hairsys::Session;
use nalgebra::Vector3;

/// Generated hair on the built-in head (straight along the normals, so it sags under gravity),
/// a fixed substep (so that a region changes no other strand's discretisation), and `extra`.
fn scene(extra: &str) -> String {
    format!(
        r#"
[scene]
frames = [1, 13]

[solver]
substeps = 240

[physics]
stretch_stiffness = 40.0
bend_stiffness = 2.0
stretch_damping = 200.0
air_drag = 2.0

[scalp.mesh]
kind = "builtin-head"

[hair]
count = 120
length = 0.12
segments = 8
seed = 3

{extra}
"#
    )
}

/// The fringe: hair whose root normal is within 45° of the face's direction (−Y).
const FRINGE: &str = "region = { direction = [0.0, -1.0, 0.0], max_angle_deg = 45.0 }";

fn file(dir: &Path, text: &str) -> SceneFile {
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    SceneFile::load(&path).unwrap()
}

fn refused(dir: &Path, text: &str) -> String {
    match file(dir, text).build() {
        Ok(_) => panic!("the scene was accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// Positions after the scene's 12 frames.
fn run(scene: &SceneFile) -> Vec<[f32; 3]> {
    let mut session = Session::from_scene(scene).unwrap();
    for _ in 0..12 {
        session.step().unwrap();
    }
    session.positions().to_vec()
}

/// Mean distance of the region's tips from their groomed rest positions, m.
fn mean_tip_offset(sim: &hairsys::build::Simulation, at: &[[f32; 3]], strands: &[usize]) -> f64 {
    let rest = &sim.strands.positions;
    let sum: f64 = strands
        .iter()
        .map(|&s| {
            let tip = sim.strands.points(s).end - 1;
            (Vector3::from(at[tip]) - rest[tip]).norm() as f64
        })
        .sum();
    sum / strands.len() as f64
}

#[test]
fn a_regions_stiffness_changes_only_that_regions_motion() {
    let dir = tempfile::tempdir().unwrap();
    let plain = file(dir.path(), &scene(""));
    let without = run(&plain);
    let stiff = file(
        dir.path(),
        &scene(&format!(
            "[[regions]]\nname = \"fringe\"\n{FRINGE}\nbend_stiffness = 20.0\n"
        )),
    );
    let sim = stiff.build().unwrap();
    let fringe = &sim.regions.regions[0].strands;
    assert!(
        !fringe.is_empty() && fringe.len() < sim.strands.len(),
        "the fringe holds {} of {} strands",
        fringe.len(),
        sim.strands.len()
    );
    let with = run(&stiff);
    for s in 0..sim.strands.len() {
        let points = sim.strands.points(s);
        let same = without[points.clone()] == with[points];
        assert_eq!(
            same,
            !fringe.contains(&s),
            "strand {s} (in the fringe: {})",
            fringe.contains(&s)
        );
    }
    // Ten times the bending stiffness: the fringe keeps much closer to its groomed shape.
    let soft = mean_tip_offset(&sim, &without, fringe);
    let hard = mean_tip_offset(&sim, &with, fringe);
    println!("fringe tips from rest: {soft:.4e} m soft, {hard:.4e} m at 10× bending");
    assert!(
        hard < 0.5 * soft,
        "stiff fringe tips {hard} m from rest against {soft} m"
    );
}

#[test]
fn a_scene_without_regions_gives_the_solver_no_factors() {
    // What keeps a scene without regions bit for bit as before they existed: the solver runs
    // without per-strand factors (and unit factors are the unscaled material, tested in
    // tests/tests/region_physics.rs).
    let sim = SceneFile::builtin_default().build().unwrap();
    assert!(sim.regions.is_empty());
    let solver = sim.strand_solver().unwrap();
    assert!(solver.mass_spring().unwrap().strand_scales().is_empty());
    // A region giving the scene's own values changes no bit.
    let dir = tempfile::tempdir().unwrap();
    let same = file(
        dir.path(),
        &scene(&format!(
            "[[regions]]\nname = \"fringe\"\n{FRINGE}\nbend_stiffness = 2.0\nair_drag = 2.0\n"
        )),
    );
    assert_eq!(run(&same), run(&file(dir.path(), &scene(""))));
}

#[test]
fn overlapping_regions_take_each_key_from_the_last() {
    let dir = tempfile::tempdir().unwrap();
    let text = scene(&format!(
        "[[regions]]\nname = \"front\"\n{FRINGE}\nbend_stiffness = 4.0\nstretch_stiffness = 80.0\n\
         mass_scale = 2.0\n\n\
         [[regions]]\nname = \"first\"\nstrands = [0, 1, 2]\nbend_stiffness = 6.0\n"
    ));
    let sim = file(dir.path(), &text).build().unwrap();
    let front = sim.regions.regions[0].strands.clone();
    let scales = sim.regions.scales(&sim.params, sim.strands.len()).unwrap();
    let both: Vec<usize> = front.iter().copied().filter(|s| *s < 3).collect();
    let only_front: Vec<usize> = front.iter().copied().filter(|s| *s >= 3).collect();
    assert!(
        !only_front.is_empty(),
        "the test needs fringe hair beyond strand 2"
    );
    for (s, scale) in scales.iter().enumerate().take(3) {
        // The later region's bending; the earlier one's stretch where it holds the strand.
        assert_eq!(scale.bend, 3.0, "strand {s}");
        let stretch = if both.contains(&s) { 2.0 } else { 1.0 };
        assert_eq!(scale.stretch, stretch, "strand {s}");
    }
    for &s in &only_front {
        assert_eq!(
            (scales[s].bend, scales[s].stretch),
            (2.0, 2.0),
            "strand {s}"
        );
    }
    // Mass: ×2 in the fringe only.
    let plain = file(dir.path(), &scene("")).build().unwrap();
    let outside = (0..sim.strands.len())
        .find(|s| !front.contains(s))
        .expect("hair outside the fringe");
    for (s, factor) in [(only_front[0], 2.0), (outside, 1.0)] {
        let i = sim.strands.points(s).start + 1;
        assert_eq!(sim.strands.masses()[i], plain.strands.masses()[i] * factor);
    }
}

#[test]
fn bad_regions_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let region = |body: &str| scene(&format!("[[regions]]\nname = \"fringe\"\n{body}\n"));
    // Hair grows only on top of the head; a cone under the chin names none of it.
    let top_only = scene("").replace(
        "seed = 3",
        "seed = 3\nregion = { direction = [0.0, 0.0, 1.0], max_angle_deg = 30.0 }",
    ) + "[[regions]]\nname = \"chin\"\nregion = { direction = [0.0, 0.0, -1.0], max_angle_deg = 30.0 }\nbend_stiffness = 4.0\n";
    let e = refused(dir.path(), &top_only);
    assert!(e.contains("\"chin\"") && e.contains("names no hair"), "{e}");
    let e = refused(dir.path(), &region("bend_stiffness = 4.0"));
    assert!(e.contains("\"fringe\" selects no hair"), "{e}");
    let e = refused(
        dir.path(),
        &region(&format!("{FRINGE}\nbend_stiffness = -1.0")),
    );
    assert!(e.contains("\"fringe\" bend_stiffness = -1"), "{e}");
    let e = refused(
        dir.path(),
        &region(&format!("{FRINGE}\ngoal_stiffness = 5.0")),
    );
    assert!(
        e.contains("goal_stiffness = 5") && e.contains("[physics] goal_stiffness = 0"),
        "{e}"
    );
    let e = refused(dir.path(), &region("strands = [9999]"));
    assert!(
        e.contains("strand 9999") && e.contains("120 strands"),
        "{e}"
    );
    let twice = region(&format!("{FRINGE}\nbend_stiffness = 3.0"))
        + "[[regions]]\nname = \"fringe\"\nstrands = [1]\nbend_stiffness = 3.0\n";
    let e = refused(dir.path(), &twice);
    assert!(e.contains("another region has this name"), "{e}");
    let rod = region(&format!("{FRINGE}\nbend_stiffness = 3.0"))
        .replace("[solver]\n", "[solver]\nmodel = \"rod\"\n");
    let e = refused(dir.path(), &rod);
    assert!(
        e.contains("[[regions]]") && e.contains("mass-spring"),
        "{e}"
    );
}

#[test]
fn a_session_changes_a_regions_parameters_between_frames() {
    let dir = tempfile::tempdir().unwrap();
    let text = scene(&format!(
        "[[regions]]\nname = \"fringe\"\n{FRINGE}\nbend_stiffness = 2.0\n"
    ));
    let scene_file = file(dir.path(), &text);
    let mut session = Session::from_scene(&scene_file).unwrap();
    assert_eq!(session.region_names(), ["fringe"]);
    let fringe = session.region_strands("fringe").unwrap();
    let mut params = session.region_params("fringe").unwrap();
    assert_eq!(params.bend_stiffness, Some(2.0));
    params.bend_stiffness = Some(20.0);
    session.set_region_params("fringe", params).unwrap();
    assert_eq!(
        session.region_params("fringe").unwrap().bend_stiffness,
        Some(20.0)
    );
    let scales = session.solver().mass_spring().unwrap().strand_scales();
    assert_eq!(scales[fringe[0]].bend, 10.0);
    // The same as a scene that gave 20 from the start.
    for _ in 0..12 {
        session.step().unwrap();
    }
    let stiff = file(
        dir.path(),
        &text.replace("bend_stiffness = 2.0\n\n", "bend_stiffness = 20.0\n\n"),
    );
    assert_eq!(session.positions(), run(&stiff).as_slice());

    let e = session
        .set_region_params("back", RegionParams::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("\"back\"") && e.contains("fringe"), "{e}");
    let bad = RegionParams {
        mass_scale: Some(3.0),
        ..RegionParams::default()
    };
    let e = session
        .set_region_params("fringe", bad)
        .unwrap_err()
        .to_string();
    assert!(e.contains("mass_scale"), "{e}");
}

/// Writes a `width × height` 8-bit grey PNG whose pixel at column `i`, row `j` (row 0 at the
/// top, v = 1) is `f(u, v)`.
fn write_png(path: &Path, width: u32, height: u32, f: impl Fn(f32, f32) -> f32) {
    let mut data = Vec::new();
    for j in 0..height {
        for i in 0..width {
            let u = (i as f32 + 0.5) / width as f32;
            let v = 1.0 - (j as f32 + 0.5) / height as f32;
            data.push((f(u, v).clamp(0.0, 1.0) * 255.0).round() as u8);
        }
    }
    let file = std::fs::File::create(path).unwrap();
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    enc.set_color(png::ColorType::Grayscale);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header().unwrap().write_image_data(&data).unwrap();
}

#[test]
fn a_stiffness_map_scales_each_hairs_bending_by_its_root_value() {
    let dir = tempfile::tempdir().unwrap();
    // Grey levels 0.2 and 0.8 (exact in 8 bits: 51/255, 204/255) either side of u = 0.5.
    write_png(&dir.path().join("stiff.png"), 64, 64, |u, _| {
        if u < 0.5 {
            0.2
        } else {
            0.8
        }
    });
    let text = scene(&format!(
        "[maps.stiffness]\ntexture = \"stiff.png\"\n\n[[regions]]\nname = \"fringe\"\n{FRINGE}\n\
         bend_stiffness = 4.0\n"
    ));
    let sim = file(dir.path(), &text).build().unwrap();
    let scales = sim.regions.scales(&sim.params, sim.strands.len()).unwrap();
    let fringe = &sim.regions.regions[0].strands;
    let mesh = sim.rest_mesh().unwrap();
    let map = hairsys::rig::maps::ScalpMap::new(
        "stiffness",
        hairsys::rig::maps::MapSource::Texture {
            path: dir.path().join("stiff.png"),
            texture: hairsys::rig::maps::Texture::read_png(
                &dir.path().join("stiff.png"),
                hairsys::rig::maps::Channel::R,
            )
            .unwrap(),
        },
        mesh,
    )
    .unwrap();
    for (s, scale) in scales.iter().enumerate() {
        let hair_core::Anchor::Surface(sample) = sim.strands.anchors()[s] else {
            panic!("generated hair grows on the scalp")
        };
        let painted = map.at(mesh, &sample, "root").unwrap();
        let region = if fringe.contains(&s) { 2.0 } else { 1.0 };
        assert_eq!(scale.bend, region * painted, "strand {s}");
        assert_eq!(scale.stretch, 1.0);
    }
}

#[test]
fn a_length_map_trims_each_hair_to_its_painted_fraction_along_its_groomed_curve() {
    let dir = tempfile::tempdir().unwrap();
    // Short (0.4) on the front of the UV disc (v < 0.5: the face side), full length behind.
    write_png(&dir.path().join("length.png"), 64, 64, |_, v| {
        if v < 0.5 {
            0.4
        } else {
            1.0
        }
    });
    let styled = |extra: &str| {
        scene(extra).replace(
            "seed = 3\n",
            "seed = 3\n[hair.style]\ncomb = [0.0, 1.0, 0.0]\nlift_deg = 20.0\nclearance = 0.003\n",
        )
    };
    let plain = file(dir.path(), &styled("")).build().unwrap();
    let trimmed = file(
        dir.path(),
        &styled("[maps.length]\ntexture = \"length.png\"\n"),
    )
    .build()
    .unwrap();
    let length = |sim: &hairsys::build::Simulation, s: usize| -> f32 {
        sim.strands.rest_lengths()[sim.strands.segments(s)]
            .iter()
            .sum()
    };
    let mass = |sim: &hairsys::build::Simulation, s: usize| -> f32 {
        // Free points only (the root's is not kept), compared as a ratio below.
        sim.strands.masses()[sim.strands.points(s)].iter().sum()
    };
    // The trimmed polyline's chords cut the groomed curve's corners: its length is the
    // fraction of the original's within 1 %. Roots on the map's edge (bilinear between 0.4 and 1)
    // get a length in between.
    let (mut short, mut full, mut edge) = (0, 0, 0);
    for s in 0..plain.strands.len() {
        let ratio = length(&trimmed, s) / length(&plain, s);
        if ratio > 0.4 * 1.01 && ratio < 0.999 {
            edge += 1;
        } else if ratio < 0.5 {
            assert!(ratio > 0.4 * 0.99, "strand {s}: length ratio {ratio}");
            short += 1;
            // Every trimmed point lies on the groomed curve: within the original's polyline.
            let original = &plain.strands.rest_local()[plain.strands.points(s)];
            for p in &trimmed.strands.rest_local()[trimmed.strands.points(s)] {
                let nearest = original
                    .windows(2)
                    .map(|w| {
                        let d = w[1] - w[0];
                        let a = ((p - w[0]).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
                        (w[0] + d * a - p).norm()
                    })
                    .fold(f32::INFINITY, f32::min);
                assert!(
                    nearest < 1e-6,
                    "strand {s}: a point {nearest} m off the curve"
                );
            }
            let m = mass(&trimmed, s) / mass(&plain, s);
            assert!((m - 0.4).abs() < 0.02, "strand {s}: mass ratio {m}");
        } else {
            assert!(
                (ratio - 1.0).abs() < 1e-6,
                "strand {s}: length ratio {ratio}"
            );
            full += 1;
        }
    }
    assert!(
        short > 10 && full > 10 && edge < short,
        "{short} trimmed, {full} full, {edge} on the edge"
    );
    write_png(&dir.path().join("zero.png"), 4, 4, |_, _| 0.0);
    let e = refused(
        dir.path(),
        &scene("[maps.length]\ntexture = \"zero.png\"\n"),
    );
    assert!(
        e.contains("[maps.length] is 0") && e.contains("(0, 1]"),
        "{e}"
    );
}
