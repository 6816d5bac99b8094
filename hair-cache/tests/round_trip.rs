//! Caches written and read back: bit-exact frames, identical files, crash-safe `.partial` files.

mod common;

use std::fs;

use common::{bits, frame_data, header, layout};
use hair_cache::{
    partial_path, summarize, CacheError, CacheReader, CacheWriter, Compression, Precision,
    WriterOptions,
};

fn write(
    path: &std::path::Path,
    options: WriterOptions,
    frames: &[u32],
) -> hair_cache::CacheSummary {
    let layout = layout();
    let mut writer = CacheWriter::create(path, &header(), &layout, options).unwrap();
    for &f in frames {
        let (x, v) = frame_data(f, layout.point_count());
        writer.write_frame(f, &x, &v).unwrap();
    }
    writer.finish().unwrap()
}

#[test]
fn layout_and_three_frames_round_trip_bit_exactly() {
    let dir = tempfile::tempdir().unwrap();
    for compression in [Compression::None, Compression::Lz4, Compression::Zstd] {
        for chunk_size in [0, WriterOptions::DEFAULT_CHUNK_SIZE] {
            let path = dir.path().join(format!("{compression}-{chunk_size}.mcap"));
            let options = WriterOptions {
                compression,
                chunk_size,
                foxglove: None,
                precision: Precision::F32,
            };
            let summary = write(&path, options, &[1, 2, 4]);
            assert_eq!(summary.frames, 3);

            let mut reader = CacheReader::open(&path).unwrap();
            assert_eq!(reader.header(), &header());
            assert_eq!(reader.layout(), &layout());
            assert_eq!(reader.frame_count(), 3);
            assert_eq!(reader.frame_numbers(), &[1, 2, 4]);
            // Read out of order: random access through the index.
            for f in [4, 1, 2] {
                let frame = reader.read_frame(f).unwrap();
                let (x, v) = frame_data(f, layout().point_count());
                assert_eq!(frame.frame, f);
                assert_eq!(frame.time, f as f64 / 24.0);
                assert_eq!(bits(&frame.positions), bits(&x), "{compression} frame {f}");
                assert_eq!(bits(&frame.velocities), bits(&v), "{compression} frame {f}");
            }
            let err = reader.read_frame(3).unwrap_err();
            assert!(
                matches!(err, CacheError::NoSuchFrame { frame: 3, .. }),
                "{err}"
            );
            assert_eq!(reader.summary(), summary);
            assert_eq!(summarize(&path).unwrap(), summary);
            let expected = if compression == Compression::None {
                "none"
            } else {
                compression.mcap_name()
            };
            assert_eq!(summary.compression, expected);
        }
    }
}

#[test]
fn summary_reports_frames_times_and_sizes() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let summary = write(&path, WriterOptions::default(), &[1, 2, 3]);
    assert_eq!(
        (summary.first_frame, summary.last_frame),
        (Some(1), Some(3))
    );
    assert_eq!(
        (summary.start_time, summary.end_time),
        (Some(1.0 / 24.0), Some(3.0 / 24.0))
    );
    assert_eq!((summary.strands, summary.points), (3, 15));
    assert_eq!(summary.bytes, fs::metadata(&path).unwrap().len());
    let text = summary.to_string();
    assert!(
        text.contains("run.mcap") && text.contains("frames 1–3"),
        "{text}"
    );
    let json = serde_json::to_value(&summary).unwrap();
    assert_eq!(json["points"], 15);
}

#[test]
fn a_run_without_frames_is_a_valid_cache() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("empty.mcap");
    let summary = write(&path, WriterOptions::default(), &[]);
    assert_eq!((summary.frames, summary.first_frame), (0, None));
    let reader = CacheReader::open(&path).unwrap();
    assert_eq!(reader.frame_count(), 0);
    assert_eq!(reader.layout(), &layout());
}

#[test]
fn identical_runs_write_byte_identical_files() {
    let dir = tempfile::tempdir().unwrap();
    for compression in [Compression::None, Compression::Lz4, Compression::Zstd] {
        let options = WriterOptions {
            compression,
            ..Default::default()
        };
        let a = dir.path().join(format!("a-{compression}.mcap"));
        let b = dir.path().join(format!("b-{compression}.mcap"));
        write(&a, options, &[1, 2, 3, 4]);
        write(&b, options, &[1, 2, 3, 4]);
        assert_eq!(
            fs::read(&a).unwrap(),
            fs::read(&b).unwrap(),
            "{compression}"
        );
    }
}

#[test]
fn partial_file_exists_until_finish_renames_it() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let partial = partial_path(&path).unwrap();
    assert_eq!(partial, dir.path().join("run.mcap.partial"));
    let layout = layout();
    let mut writer =
        CacheWriter::create(&path, &header(), &layout, WriterOptions::default()).unwrap();
    assert!(partial.exists() && !path.exists());
    let (x, v) = frame_data(1, layout.point_count());
    writer.write_frame(1, &x, &v).unwrap();
    assert!(partial.exists() && !path.exists());
    writer.finish().unwrap();
    assert!(!partial.exists() && path.exists());
}

#[test]
fn every_closed_chunk_is_on_disk_while_the_writer_runs() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let layout = layout();
    let options = WriterOptions {
        chunk_size: 0,
        ..Default::default()
    };
    let mut writer = CacheWriter::create(&path, &header(), &layout, options).unwrap();
    for f in 1..=3 {
        let (x, v) = frame_data(f, layout.point_count());
        writer.write_frame(f, &x, &v).unwrap();
        // What a killed process would leave: read the file as it is on disk now.
        let bytes = fs::read(writer.partial_path()).unwrap();
        let options = mcap::read::Options::IgnoreEndMagic.into();
        let messages = mcap::MessageStream::new_with_options(&bytes, options)
            .unwrap()
            .take_while(Result::is_ok)
            .count();
        assert_eq!(messages, f as usize);
    }
    drop(writer);
}

#[test]
fn a_dropped_writer_leaves_a_partial_file_that_is_never_read_as_complete() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let layout = layout();
    let mut writer =
        CacheWriter::create(&path, &header(), &layout, WriterOptions::default()).unwrap();
    let (x, v) = frame_data(1, layout.point_count());
    writer.write_frame(1, &x, &v).unwrap();
    drop(writer);
    let partial = partial_path(&path).unwrap();
    assert!(partial.exists() && !path.exists());

    let err = CacheReader::open(&partial).err().unwrap();
    assert!(matches!(err, CacheError::Unfinished { .. }), "{err}");
    assert!(err.to_string().contains("run.mcap.partial"), "{err}");
    // Even renamed, it has no summary: it is reported as incomplete.
    fs::rename(&partial, &path).unwrap();
    let err = summarize(&path).unwrap_err();
    assert!(matches!(err, CacheError::Incomplete { .. }), "{err}");
    // The frame written before the drop is in the file.
    let bytes = fs::read(&path).unwrap();
    let options = mcap::read::Options::IgnoreEndMagic.into();
    let messages = mcap::MessageStream::new_with_options(&bytes, options)
        .unwrap()
        .take_while(Result::is_ok)
        .count();
    assert_eq!(messages, 1);
}
