//! Recovering the complete frames of a `.partial` cache whose writer never finished.

mod common;

use std::fs;
use std::path::Path;

use common::{bits, frame_data, header, layout};
use hair_cache::{
    recover, CacheError, CacheReader, CacheWriter, Compression, Precision, WriterOptions,
};

/// Writes frames 1..=20 and drops the writer without `finish`; returns the `.partial` bytes.
fn dropped_run(path: &Path, options: WriterOptions) -> Vec<u8> {
    let layout = layout();
    let mut writer = CacheWriter::create(path, &header(), &layout, options).unwrap();
    for f in 1..=20 {
        let (x, v) = frame_data(f, layout.point_count());
        writer.write_frame(f, &x, &v).unwrap();
    }
    let partial = writer.partial_path().to_path_buf();
    drop(writer);
    assert!(!path.exists());
    fs::read(partial).unwrap()
}

/// (start, end) byte offsets of each chunk record and the frames it holds, from the summary of
/// the same run finished (its data section is the `.partial` file's bytes).
fn chunks(finished: &[u8]) -> Vec<(u64, u64, Vec<u32>)> {
    let summary = mcap::read::Summary::read(finished).unwrap().unwrap();
    summary
        .chunk_indexes
        .iter()
        .map(|c| {
            // 24 fps: frame f is logged at round(f / 24 s) in ns.
            let frames = (1..=20u32)
                .filter(|&f| {
                    let ns = (f64::from(f) / 24.0 * 1e9).round() as u64;
                    (c.message_start_time..=c.message_end_time).contains(&ns)
                })
                .collect();
            (
                c.chunk_start_offset,
                c.chunk_start_offset + c.chunk_length,
                frames,
            )
        })
        .collect()
}

fn check_frames(recovered: &hair_cache::Recovery, expected: &[u32]) {
    assert_eq!(recovered.frame_numbers(), expected);
    for frame in &recovered.frames {
        let (x, v) = frame_data(frame.frame, layout().point_count());
        assert_eq!(bits(&frame.positions), bits(&x), "frame {}", frame.frame);
        assert_eq!(bits(&frame.velocities), bits(&v), "frame {}", frame.frame);
        assert_eq!(frame.time, f64::from(frame.frame) / 24.0);
    }
}

#[test]
fn truncated_partial_files_give_back_exactly_their_complete_chunks() {
    let dir = tempfile::tempdir().unwrap();
    for compression in [Compression::None, Compression::Lz4, Compression::Zstd] {
        let options = WriterOptions {
            compression,
            chunk_size: 1500, // about four frames per chunk
            foxglove: None,
            precision: Precision::F32,
        };
        let run = dir.path().join(format!("run-{compression}.mcap"));
        let partial = dropped_run(&run, options);
        // The same run, finished, tells where its chunks are.
        let done = dir.path().join(format!("done-{compression}.mcap"));
        let layout = layout();
        let mut writer = CacheWriter::create(&done, &header(), &layout, options).unwrap();
        for f in 1..=20 {
            let (x, v) = frame_data(f, layout.point_count());
            writer.write_frame(f, &x, &v).unwrap();
        }
        writer.finish().unwrap();
        let finished = fs::read(&done).unwrap();
        assert_eq!(
            &finished[..partial.len()],
            &partial[..],
            "data sections differ"
        );
        let chunks = chunks(&finished);
        assert!(chunks.len() >= 4, "{} chunks", chunks.len());

        // The whole `.partial` file: every frame, nothing lost (only the summary is missing).
        let partial_path = dir.path().join(format!("run-{compression}.mcap.partial"));
        let whole = recover(&partial_path).unwrap();
        check_frames(&whole, &(1..=20).collect::<Vec<_>>());
        assert_eq!(whole.warning, None);
        assert_eq!(whole.header, header());
        assert_eq!(whole.layout, layout);
        // The recovered frames make a finished cache again.
        let fixed = dir.path().join(format!("fixed-{compression}.mcap"));
        whole.write(&fixed, options).unwrap();
        assert_eq!(fs::read(&fixed).unwrap(), finished);

        // Cuts: at a chunk end (nothing lost but later chunks), inside chunks, one byte short.
        let mut cuts = Vec::new();
        for (start, end, _) in &chunks {
            cuts.extend([*start + 1, *start + 9, (*start + *end) / 2, *end - 1, *end]);
        }
        for cut in cuts {
            let cut = usize::try_from(cut).unwrap().min(partial.len());
            let path = dir
                .path()
                .join(format!("cut-{compression}-{cut}.mcap.partial"));
            fs::write(&path, &partial[..cut]).unwrap();
            let recovered = recover(&path).unwrap();
            let complete: Vec<u32> = chunks
                .iter()
                .filter(|c| c.1 as usize <= cut)
                .flat_map(|c| c.2.clone())
                .collect();
            check_frames(&recovered, &complete);
            // A cut inside a chunk (or its message index) loses it, and the warning says so.
            let in_chunk = chunks
                .iter()
                .find(|c| (c.0 as usize) < cut && cut < c.1 as usize);
            match in_chunk {
                Some((start, _, _)) => {
                    let warning = recovered.warning.as_ref().expect("a warning");
                    let text = warning.to_string();
                    let lost = cut - *start as usize;
                    let expected = match complete.last() {
                        Some(last) => format!(
                            "frames 1–{last} recovered; the chunk after frame {last} was \
                             incomplete ({lost} bytes) and is lost"
                        ),
                        None => format!(
                            "no frame recovered; the chunk before the first frame was \
                             incomplete ({lost} bytes) and is lost"
                        ),
                    };
                    assert_eq!(text, expected, "cut at {cut}");
                    assert_eq!(warning.lost_bytes, lost as u64);
                    assert_eq!(warning.last_frame, complete.last().copied());
                }
                None => {
                    // Cut at a chunk end or inside the message index after it: the index record
                    // is incomplete, no frame is lost.
                    if let Some(w) = &recovered.warning {
                        assert!(w.to_string().contains("incomplete record"), "{w}");
                    }
                }
            }
        }
    }
}

#[test]
fn default_chunking_keeps_every_frame_of_a_dropped_writer() {
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("run.mcap");
    let partial = dropped_run(&run, WriterOptions::default());
    let path = dir.path().join("run.mcap.partial");
    let recovered = recover(&path).unwrap();
    check_frames(&recovered, &(1..=20).collect::<Vec<_>>());
    assert_eq!(recovered.warning, None);
    // The reader refuses the `.partial` file; recovery is the way to read it.
    assert!(matches!(
        CacheReader::open(&path),
        Err(CacheError::Unfinished { .. })
    ));
    // Cut inside the only chunk: no frame, and the warning says what was lost.
    let cut = dir.path().join("cut.mcap.partial");
    fs::write(&cut, &partial[..partial.len() - 1000]).unwrap();
    let recovered = recover(&cut).unwrap();
    assert!(recovered.frames.is_empty());
    let text = recovered.warning.unwrap().to_string();
    assert!(text.starts_with("no frame recovered; the chunk"), "{text}");
}

#[test]
fn a_file_cut_inside_its_header_or_metadata_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("run.mcap");
    let partial = dropped_run(
        &run,
        WriterOptions {
            compression: Compression::None,
            chunk_size: 1500,
            foxglove: None,
            precision: Precision::F32,
        },
    );
    let finished_len = 8 + 9; // magic and the header record's opcode and length
    for cut in [0, 4, 8, 12, finished_len + 3, 60, 200] {
        let path = dir.path().join(format!("head-{cut}.mcap.partial"));
        fs::write(&path, &partial[..cut]).unwrap();
        let err = recover(&path).unwrap_err();
        let text = err.to_string();
        assert!(text.contains(&path.display().to_string()), "{cut}: {text}");
        if cut < 8 {
            assert!(matches!(err, CacheError::NotMcap { .. }), "{cut}: {text}");
        } else {
            assert!(
                matches!(err, CacheError::Incomplete { .. }),
                "{cut}: {text}"
            );
            assert!(text.contains("none of its frames can be read"), "{text}");
        }
    }
    let missing = dir.path().join("missing.mcap.partial");
    let err = recover(&missing).unwrap_err();
    assert!(err.to_string().contains("missing.mcap.partial"), "{err}");
}

#[test]
fn a_damaged_chunk_is_skipped_and_named() {
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("run.mcap");
    let options = WriterOptions {
        compression: Compression::None,
        chunk_size: 1500,
        foxglove: None,
        precision: Precision::F32,
    };
    let mut partial = dropped_run(&run, options);
    let done = dir.path().join("done.mcap");
    let layout = layout();
    let mut writer = CacheWriter::create(&done, &header(), &layout, options).unwrap();
    for f in 1..=20 {
        let (x, v) = frame_data(f, layout.point_count());
        writer.write_frame(f, &x, &v).unwrap();
    }
    writer.finish().unwrap();
    let chunks = chunks(&fs::read(&done).unwrap());
    // Flip a byte in the middle of the second chunk's data.
    let (start, end, lost) = chunks[1].clone();
    partial[((start + end) / 2) as usize] ^= 0x40;
    let path = dir.path().join("flipped.mcap.partial");
    fs::write(&path, &partial).unwrap();
    let recovered = recover(&path).unwrap();
    let expected: Vec<u32> = (1..=20).filter(|f| !lost.contains(f)).collect();
    check_frames(&recovered, &expected);
    let text = recovered.warning.unwrap().to_string();
    let after = chunks[0].2.last().unwrap();
    assert!(
        text.contains(&format!("the chunk after frame {after} is damaged")),
        "{text}"
    );
}

#[test]
fn a_killed_writer_leaves_its_closed_chunks() {
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("run.mcap");
    let layout = layout();
    let options = WriterOptions {
        compression: Compression::Lz4,
        chunk_size: 1500,
        foxglove: None,
        precision: Precision::F32,
    };
    let mut writer = CacheWriter::create(&run, &header(), &layout, options).unwrap();
    for f in 1..=22 {
        let (x, v) = frame_data(f, layout.point_count());
        writer.write_frame(f, &x, &v).unwrap();
    }
    let partial = writer.partial_path().to_path_buf();
    // Like SIGKILL: no destructor runs, the open chunk keeps its placeholder header and the
    // buffered bytes never reach the file.
    std::mem::forget(writer);
    let recovered = recover(&partial).unwrap();
    let frames = recovered.frame_numbers();
    let last = *frames.last().unwrap();
    assert!((16..22).contains(&last), "{frames:?}");
    check_frames(&recovered, &(1..=last).collect::<Vec<_>>());
    let text = recovered.warning.unwrap().to_string();
    assert!(
        text.starts_with(&format!(
            "frames 1–{last} recovered; the chunk after frame {last} was incomplete ("
        )),
        "{text}"
    );
}
