//! Refusals: each error names the file and says what to do.

mod common;

use std::fs;
use std::path::Path;

use common::{frame_data, header, layout};
use hair_cache::{
    summarize, CacheError, CacheReader, CacheWriter, Compression, Precision, WriterOptions,
};
use nalgebra::Vector3;

fn finished_cache(path: &Path, options: WriterOptions) {
    let layout = layout();
    let mut writer = CacheWriter::create(path, &header(), &layout, options).unwrap();
    for f in 1..=3 {
        let (x, v) = frame_data(f, layout.point_count());
        writer.write_frame(f, &x, &v).unwrap();
    }
    writer.finish().unwrap();
}

#[test]
fn creating_in_a_missing_directory_fails_at_once_naming_the_path() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("missing").join("run.mcap");
    let err = CacheWriter::create(&path, &header(), &layout(), WriterOptions::default())
        .err()
        .unwrap();
    assert!(matches!(err, CacheError::Create { .. }), "{err}");
    let text = err.to_string();
    assert!(text.contains(&path.display().to_string()), "{text}");
    assert!(text.contains("directory exists"), "{text}");
}

#[test]
fn truncated_file_is_reported_as_incomplete() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    finished_cache(&path, WriterOptions::default());
    let bytes = fs::read(&path).unwrap();
    for len in [bytes.len() - 1, bytes.len() / 2, 40] {
        let cut = dir.path().join(format!("cut-{len}.mcap"));
        fs::write(&cut, &bytes[..len]).unwrap();
        let err = summarize(&cut).unwrap_err();
        assert!(matches!(err, CacheError::Incomplete { .. }), "{len}: {err}");
        let text = err.to_string();
        assert!(text.contains(&cut.display().to_string()), "{text}");
        assert!(text.contains("re-run"), "{text}");
    }
}

#[test]
fn garbage_and_empty_files_are_not_mcap() {
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes) in [
        (
            "garbage.mcap",
            b"hello, this is not a cache at all".to_vec(),
        ),
        ("empty.mcap", vec![]),
    ] {
        let path = dir.path().join(name);
        fs::write(&path, bytes).unwrap();
        let err = summarize(&path).unwrap_err();
        assert!(matches!(err, CacheError::NotMcap { .. }), "{err}");
        assert!(err.to_string().contains(name), "{err}");
    }
}

#[test]
fn an_mcap_without_hairsys_metadata_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("other.mcap");
    let mut writer = mcap::Writer::new(fs::File::create(&path).unwrap()).unwrap();
    writer.finish().unwrap();
    drop(writer);
    let err = CacheReader::open(&path).err().unwrap();
    assert!(matches!(err, CacheError::NotHairsys { .. }), "{err}");
    assert!(err.to_string().contains("other.mcap"), "{err}");
}

#[test]
fn a_flipped_byte_in_a_frame_is_detected() {
    let dir = tempfile::tempdir().unwrap();
    for compression in [Compression::None, Compression::Lz4, Compression::Zstd] {
        let path = dir.path().join(format!("{compression}.mcap"));
        let options = WriterOptions {
            compression,
            chunk_size: 0,
            foxglove: None,
            precision: Precision::F32,
        };
        finished_cache(&path, options);
        let mut bytes = fs::read(&path).unwrap();
        let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
        // The middle of frame 2's chunk.
        let chunk = &summary.chunk_indexes[1];
        let at = (chunk.chunk_start_offset + chunk.chunk_length / 2) as usize;
        bytes[at] ^= 0x55;
        fs::write(&path, &bytes).unwrap();
        let mut reader = CacheReader::open(&path).unwrap();
        assert!(reader.read_frame(1).is_ok());
        let err = reader.read_frame(2).unwrap_err();
        assert!(
            matches!(err, CacheError::Damaged { .. }),
            "{compression}: {err}"
        );
        assert!(
            err.to_string().contains(&format!("{compression}.mcap")),
            "{err}"
        );
    }
}

#[test]
fn write_frame_refuses_wrong_counts_non_finite_values_and_disorder() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let layout = layout();
    let n = layout.point_count();
    let mut writer =
        CacheWriter::create(&path, &header(), &layout, WriterOptions::default()).unwrap();
    let (x, v) = frame_data(1, n);

    let err = writer.write_frame(1, &x[..n - 1], &v).unwrap_err();
    assert!(
        matches!(err, CacheError::PointCount { expected: 15, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("run.mcap.partial"), "{err}");

    let mut bad = x.clone();
    bad[6] = Vector3::new(0.0, f32::NAN, 0.0);
    let err = writer.write_frame(1, &bad, &v).unwrap_err();
    assert!(
        matches!(
            err,
            CacheError::NonFinite {
                quantity: "position",
                point: 6,
                strand: 1,
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("substeps"), "{err}");
    let mut bad = v.clone();
    bad[14].z = f32::INFINITY;
    let err = writer.write_frame(1, &x, &bad).unwrap_err();
    assert!(
        matches!(
            err,
            CacheError::NonFinite {
                quantity: "velocity",
                strand: 2,
                ..
            }
        ),
        "{err}"
    );

    // Before the header's first frame (1), then not increasing.
    let err = writer.write_frame(0, &x, &v).unwrap_err();
    assert!(
        matches!(err, CacheError::FrameOrder { min: 1, .. }),
        "{err}"
    );
    writer.write_frame(2, &x, &v).unwrap();
    let err = writer.write_frame(2, &x, &v).unwrap_err();
    assert!(
        matches!(err, CacheError::FrameOrder { min: 3, .. }),
        "{err}"
    );

    // Refused frames left nothing behind: the cache holds frame 2 only.
    writer.finish().unwrap();
    let mut reader = CacheReader::open(&path).unwrap();
    assert_eq!(reader.frame_numbers(), &[2]);
    assert!(reader.read_frame(2).is_ok());
}

#[test]
fn invalid_header_or_layout_is_refused_before_any_file_is_made() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let mut h = header();
    h.fps = 0.0;
    let err = CacheWriter::create(&path, &h, &layout(), WriterOptions::default())
        .err()
        .unwrap();
    assert!(err.to_string().contains("fps"), "{err}");
    let mut h = header();
    h.scene_hash = "not hex".into();
    assert!(CacheWriter::create(&path, &h, &layout(), WriterOptions::default()).is_err());
    let mut l = layout();
    l.radii.pop();
    let err = CacheWriter::create(&path, &header(), &l, WriterOptions::default())
        .err()
        .unwrap();
    assert!(err.to_string().contains("radii"), "{err}");
    assert!(fs::read_dir(dir.path()).unwrap().next().is_none());
}
