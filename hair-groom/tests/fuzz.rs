//! Mutation fuzzing of every file reader of the guide level: `.hair`, `.tfx`, OBJ polylines,
//! `.usda` `BasisCurves` and OBJ meshes, on mutants of real files (the Sintel groom and bust, and
//! small files the writers make). Each reader must answer with a groom (or mesh) or an error
//! naming the file: no panic, no abort, and no more memory than a budget proportional to the file
//! (harness: `fuzz/harness.rs` at the workspace root).
//!
//! The suite runs about 10 000 mutants in all (2 000 per reader, about 20 s in the dev profile on
//! a 2-core machine); the longer run (6 times as many, other seeds):
//!
//! ```sh
//! cargo test -p hair-groom --test fuzz -- --ignored --nocapture
//! ```

#[path = "../../fuzz/harness.rs"]
mod harness;

use std::path::{Path, PathBuf};

use hair_groom::{load_obj, read_groom, write_groom, Groom, ImportOptions, ObjOptions, UpAxis};
use nalgebra::Vector3;

#[global_allocator]
static ALLOC: harness::Counting = harness::Counting;

/// Memory a mutant of `n` bytes may use while it is read: a groom is about the size of its
/// binary file; text formats hold one token or index per few bytes; tobj keeps its own arrays.
fn budget(n: usize) -> usize {
    64 * n + (4 << 20)
}

/// A file of the Sintel groom and bust the repository ships in `data/sintel/`.
fn sintel_file(file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../data/sintel")
        .join(file)
}

/// Sintel's groom as the `.hair` file in `data/sintel/`: centimeters, Y up.
fn sintel_opts() -> ImportOptions {
    ImportOptions {
        scale: 0.01,
        up_axis: UpAxis::Y,
    }
}

/// A small groom: two curves of 4 points (TressFX needs equal counts), one bent.
fn small_groom() -> Groom {
    Groom::new(vec![
        (0..4)
            .map(|i| Vector3::new(0.0, 0.01 * (i * i) as f32, 0.03 * i as f32))
            .collect(),
        (0..4)
            .map(|i| Vector3::new(0.1, 0.0, -0.0 + 0.03 * i as f32))
            .collect(),
    ])
    .unwrap()
}

/// Seeds of the groom format with extension `ext`: the Sintel groom (a slice of it for text
/// formats, which are larger) and the small groom, written by this crate's writers.
fn groom_seeds(ext: &str, dir: &Path) -> Vec<(String, Vec<u8>)> {
    let sintel = read_groom(&sintel_file("sintel_hair.hair"), &sintel_opts()).unwrap();
    let mut seeds = Vec::new();
    match ext {
        "hair" => seeds.push((
            "sintel.hair".into(),
            std::fs::read(sintel_file("sintel_hair.hair")).unwrap(),
        )),
        "tfx" => seeds.push((
            "sintel.tfx".into(),
            std::fs::read(
                Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/sintel/sintel_hair.tfx"),
            )
            .unwrap(),
        )),
        _ => {
            // Sintel's first 40 strands: a real groom's numbers, in a few kilobytes of text.
            let part = Groom::new(sintel.curves()[..40].to_vec()).unwrap();
            let path = dir.join(format!("sintel-part.{ext}"));
            write_groom(&path, &part, &sintel_opts()).unwrap();
            seeds.push((format!("sintel-part.{ext}"), std::fs::read(&path).unwrap()));
        }
    }
    let path = dir.join(format!("small.{ext}"));
    write_groom(&path, &small_groom(), &ImportOptions::default()).unwrap();
    seeds.push((format!("small.{ext}"), std::fs::read(&path).unwrap()));
    seeds
}

/// Reads `mutants` mutants of each seed through `read` on a file `mutant.<ext>`.
fn fuzz(
    name: &str,
    ext: &str,
    seeds: &[(String, Vec<u8>)],
    mutants: usize,
    seed: u64,
    dir: &Path,
    read: impl Fn(&Path) -> Result<(), String>,
) {
    let text = ext != "hair" && ext != "tfx";
    let path = dir.join(format!("mutant.{ext}"));
    let file_name = path.file_name().unwrap().to_string_lossy().to_string();
    for (seed_name, bytes) in seeds {
        std::fs::write(&path, bytes).unwrap();
        assert_eq!(read(&path), Ok(()), "seed {seed_name} must read");
    }
    let report = harness::run(name, seeds, mutants, seed, text, budget, |bytes| {
        std::fs::write(&path, bytes).unwrap();
        read(&path).inspect_err(|e| {
            assert!(
                e.contains(&file_name),
                "the error does not name the file: {e}"
            );
        })
    });
    harness::assert_clean(name, &report);
}

fn fuzz_groom(ext: &str, mutants: usize, seed: u64) {
    let dir = tempfile::tempdir().unwrap();
    let seeds = groom_seeds(ext, dir.path());
    fuzz(
        &format!(".{ext} reader"),
        ext,
        &seeds,
        mutants,
        seed,
        dir.path(),
        |path| {
            read_groom(path, &sintel_opts())
                .map(|g| assert!(g.point_count() >= 2 * g.len()))
                .map_err(|e| e.to_string())
        },
    );
}

/// Small meshes with what OBJ files hold besides triangles: quads, UVs, normals, negative
/// indices, groups, a material library line, points and lines.
const SMALL_MESHES: [&str; 2] = [
    "# quad and triangle\nmtllib scalp.mtl\no scalp\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\n\
     vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\ng top\nf 1/1/1 2/2/1 3/3/1 4/4/1\n\
     f -5/1 -4/2 -1/3\nl 1 2\np 3\n",
    "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nv 1 1 0.5 1 1 1\nf 1 2 3\nf 2 4 3\n",
];

fn fuzz_obj_mesh(mutants: usize, seed: u64) {
    let dir = tempfile::tempdir().unwrap();
    let mut seeds: Vec<(String, Vec<u8>)> = SMALL_MESHES
        .iter()
        .enumerate()
        .map(|(i, m)| (format!("small-{i}.obj"), m.as_bytes().to_vec()))
        .collect();
    // Part of the Sintel bust: its first 150 vertices and the faces among them (normals,
    // whose indices differ, dropped).
    let bust = std::fs::read_to_string(sintel_file("sintel_bust.obj")).unwrap();
    let (mut part, mut vertices) = (String::new(), 0);
    for line in bust.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") if vertices < 150 => {
                vertices += 1;
                part.push('\n');
                part.push_str(line);
            }
            Some("f") => {
                let v: Vec<&str> = words.map(|w| w.split('/').next().unwrap()).collect();
                if v.iter().all(|i| i.parse::<usize>().unwrap() <= 150) {
                    part.push_str(&format!("\nf {}", v.join(" ")));
                }
            }
            _ => {}
        }
    }
    seeds.push(("sintel-bust-part.obj".into(), part.into_bytes()));
    let opts = ObjOptions {
        scale: 0.01,
        up_axis: UpAxis::Y,
    };
    fuzz(
        "OBJ mesh reader",
        "obj",
        &seeds,
        mutants,
        seed,
        dir.path(),
        |path| {
            load_obj(path, &opts)
                .map(|mesh| assert!(!mesh.triangles().is_empty()))
                .map_err(|e| e.to_string())
        },
    );
}

#[test]
fn hair_reader_survives_mutants() {
    fuzz_groom("hair", 1000, 1001);
}

#[test]
fn tfx_reader_survives_mutants() {
    fuzz_groom("tfx", 1000, 1002);
}

#[test]
fn obj_curves_reader_survives_mutants() {
    fuzz_groom("obj", 1000, 1003);
}

#[test]
fn usda_reader_survives_mutants() {
    fuzz_groom("usda", 1000, 1004);
}

#[test]
fn obj_mesh_reader_survives_mutants() {
    fuzz_obj_mesh(700, 1005);
}

#[test]
#[ignore = "long run: cargo test -p hair-groom --test fuzz -- --ignored"]
fn every_groom_reader_survives_many_mutants() {
    for (i, ext) in ["hair", "tfx", "obj", "usda"].into_iter().enumerate() {
        fuzz_groom(ext, 6000, 2001 + i as u64);
    }
    fuzz_obj_mesh(4000, 2010);
}
