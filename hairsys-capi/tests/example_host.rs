//! The example C++ host (`examples/cpp-host/`) built with its Makefile and run on a tiny
//! generated shot: a deforming grid scalp (four OBJ frames) and four curves. Its cache must hold
//! every frame of every curve, and its USD file the strands as curves. Skipped, with a message,
//! on a machine without `make` or `c++`.

mod common;

use std::fmt::Write as _;
use std::process::Command;

use common::{crate_dir, have, library_dir, run};

/// A 4 × 4-vertex grid (0.09 m square) at frame `frame`: a ripple that grows with the frame.
fn scalp_obj(frame: u32) -> String {
    let mut s = String::new();
    for j in 0..4 {
        for i in 0..4 {
            let (x, y) = (0.03 * i as f32, 0.03 * j as f32);
            let z = 0.002 * (frame - 1) as f32 * (60.0 * x).sin();
            writeln!(s, "v {x} {y} {z}").unwrap();
        }
    }
    for j in 0..3 {
        for i in 0..3 {
            let a = 4 * j + i + 1;
            writeln!(s, "f {a} {} {} {}", a + 1, a + 5, a + 4).unwrap();
        }
    }
    s
}

/// Four 5-point curves standing on the grid, as OBJ polylines.
fn groom_obj() -> String {
    let mut s = String::new();
    for c in 0..4 {
        for k in 0..5 {
            let x = 0.015 + 0.02 * c as f32;
            writeln!(s, "v {x} 0.045 {}", 0.0005 + 0.01 * k as f32).unwrap();
        }
    }
    for c in 0..4 {
        let a = 5 * c + 1;
        writeln!(s, "l {a} {} {} {} {}", a + 1, a + 2, a + 3, a + 4).unwrap();
    }
    s
}

#[test]
fn the_example_host_builds_and_writes_a_cache_and_a_usd_file() {
    if !have("make") || !have("c++") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let example = crate_dir().join("examples/cpp-host");
    let o = Command::new("make")
        .arg("-C")
        .arg(&example)
        .arg(format!("ROOT={}", crate_dir().parent().unwrap().display()))
        .arg(format!("LIBDIR={}", library_dir().display()))
        .arg(format!("BUILD={}", dir.path().display()))
        .output()
        .expect("make runs");
    assert!(
        o.status.success(),
        "make failed:\n{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    for frame in 1..=4 {
        std::fs::write(
            dir.path().join(format!("head.{frame:04}.obj")),
            scalp_obj(frame),
        )
        .unwrap();
    }
    std::fs::write(dir.path().join("groom.obj"), groom_obj()).unwrap();
    let pattern = dir.path().join("head.%04d.obj");
    run(
        &dir.path().join("host"),
        &[
            pattern.to_str().unwrap(),
            "1",
            "4",
            dir.path().join("groom.obj").to_str().unwrap(),
            dir.path().to_str().unwrap(),
        ],
    );

    let reader = hair_cache::CacheReader::open(dir.path().join("hair.mcap")).unwrap();
    assert_eq!(reader.frame_numbers(), &[1, 2, 3, 4]);
    assert_eq!(reader.layout().offsets, vec![0, 5, 10, 15, 20]);
    let usd = std::fs::read_to_string(dir.path().join("hair.usda")).unwrap();
    assert!(
        usd.starts_with("#usda 1.0"),
        "{}",
        &usd[..usd.len().min(200)]
    );
    assert!(usd.contains("BasisCurves"), "no curves in the USD file");
}
