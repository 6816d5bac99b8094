//! The optional Foxglove view: every `/hairsys/scene` message validates against the official
//! `foxglove.SceneUpdate` JSON schema (Python `jsonschema`) and shows the cached frame's strands,
//! while the frame channel reads back unchanged. Needs `pip install mcap jsonschema`; fails (never
//! skips) without them.

mod common;

use std::process::Command;

use common::{bits, frame_data, header, layout};
use hair_cache::foxglove::FoxgloveOptions;
use hair_cache::{CacheReader, CacheWriter, Compression, WriterOptions};

const SCRIPT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tests/python/validate_foxglove.py"
);

#[test]
fn scene_updates_validate_against_the_official_schema() {
    let dir = tempfile::tempdir().unwrap();
    let layout = layout();
    let max_strands = 2;
    let path = dir.path().join("view.mcap");
    let options = WriterOptions {
        compression: Compression::Zstd,
        foxglove: Some(FoxgloveOptions { max_strands }),
        ..WriterOptions::default()
    };
    let mut writer = CacheWriter::create(&path, &header(), &layout, options).unwrap();
    let frames = 1..=6;
    for frame in frames.clone() {
        let (x, v) = frame_data(frame, layout.point_count());
        writer.write_frame(frame, &x, &v).unwrap();
    }
    writer.finish().unwrap();

    // The frame channel is untouched by the view.
    let mut reader = CacheReader::open(&path).unwrap();
    assert_eq!(reader.frame_numbers(), frames.clone().collect::<Vec<_>>());
    for frame in frames {
        let (x, v) = frame_data(frame, layout.point_count());
        let got = reader.read_frame(frame).unwrap();
        assert_eq!(bits(&got.positions), bits(&x));
        assert_eq!(bits(&got.velocities), bits(&v));
    }

    // Recovery reads the frames past the view's messages.
    let recovered = hair_cache::recover(&path).unwrap();
    assert_eq!(recovered.frame_numbers(), reader.frame_numbers());

    let out = Command::new("python3")
        .arg(SCRIPT)
        .arg(&path)
        .arg(max_strands.to_string())
        .output()
        .expect("python3 runs (install Python 3 and `pip install mcap jsonschema`)");
    assert!(
        out.status.success(),
        "the Foxglove view does not validate (exit {:?}; `pip install mcap jsonschema` if a package is missing):\n{}{}",
        out.status.code(),
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    println!("{}", String::from_utf8_lossy(&out.stdout).trim());
}
