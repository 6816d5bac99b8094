//! Damaged files that claim absurd sizes: a chunk whose header claims terabytes uncompressed, a
//! record whose length runs past the file, a message inside a chunk claiming more than its chunk.
//! Every reader entry point (open, read, summarize, recover) must answer with an error naming the
//! file, or with exactly the frames written, or (recovery) with a prefix and a warning — never a
//! panic, never garbage, and never an allocation larger than the file (a 1 TB claim would abort).

mod common;

use std::path::Path;

use common::{frame_data, header, layout};
use hair_cache::{CacheReader, CacheWriter, Compression, WriterOptions};

const CHUNK: u8 = 0x06;
const MESSAGE: u8 = 0x05;

fn finished_cache(path: &Path, compression: Compression) {
    let layout = layout();
    let options = WriterOptions {
        compression,
        chunk_size: 0,
        ..WriterOptions::default()
    };
    let mut writer = CacheWriter::create(path, &header(), &layout, options).unwrap();
    for frame in 1..=4 {
        let (x, v) = frame_data(frame, layout.point_count());
        writer.write_frame(frame, &x, &v).unwrap();
    }
    writer.finish().unwrap();
}

/// Offset of the opcode byte of the first record with `opcode` in the data section.
fn first_record(bytes: &[u8], opcode: u8) -> usize {
    let mut at = 8; // magic
    loop {
        let len = u64::from_le_bytes(bytes[at + 1..at + 9].try_into().unwrap()) as usize;
        if bytes[at] == opcode {
            return at;
        }
        at += 9 + len;
    }
}

fn put_u64(bytes: &mut [u8], at: usize, value: u64) {
    bytes[at..at + 8].copy_from_slice(&value.to_le_bytes());
}

/// Every entry point answers the damaged file either with an error naming the file or with
/// exactly the frames that were written (the damage lay outside what it reads); recovery may
/// also return a prefix of them with a warning. Returns how many answers were errors or warnings.
fn every_reader_survives(path: &Path) -> usize {
    let name = path.file_name().unwrap().to_string_lossy().to_string();
    let points = layout().point_count();
    let written = |frame: u32| frame_data(frame, points);
    let mut flagged = 0;
    let mut note = |e: String| {
        assert!(e.contains(&name), "the error names the file: {e}");
        flagged += 1;
    };
    if let Err(e) = hair_cache::summarize(path) {
        note(e.to_string());
    }
    match CacheReader::open(path) {
        Ok(mut reader) => {
            for frame in reader.frame_numbers().to_vec() {
                match reader.read_frame(frame) {
                    Ok(f) => assert!(
                        (f.positions, f.velocities) == written(frame),
                        "frame {frame} read as garbage"
                    ),
                    Err(e) => note(e.to_string()),
                }
            }
        }
        Err(e) => note(e.to_string()),
    }
    match hair_cache::recover(path) {
        Ok(recovery) => {
            for f in &recovery.frames {
                assert!(
                    (f.positions.clone(), f.velocities.clone()) == written(f.frame),
                    "frame {} recovered as garbage",
                    f.frame
                );
            }
            if recovery.warning.is_some() || recovery.frames.len() < 4 {
                flagged += 1;
            }
        }
        Err(e) => note(e.to_string()),
    }
    flagged
}

#[test]
fn a_chunk_claiming_a_terabyte_uncompressed_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    for compression in [Compression::None, Compression::Lz4, Compression::Zstd] {
        let path = dir.path().join(format!("huge-{compression}.mcap"));
        finished_cache(&path, compression);
        let mut bytes = std::fs::read(&path).unwrap();
        let chunk = first_record(&bytes, CHUNK);
        // Body: start time, end time, then the uncompressed size.
        put_u64(&mut bytes, chunk + 9 + 16, 1 << 40);
        std::fs::write(&path, &bytes).unwrap();
        // Readers locate chunks through the summary's index and check the data's CRC, so a lying
        // size field either changes nothing they read or is refused; neither may panic.
        every_reader_survives(&path);
    }
}

#[test]
fn a_record_longer_than_the_file_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("long-record.mcap");
    finished_cache(&path, Compression::None);
    let mut bytes = std::fs::read(&path).unwrap();
    let chunk = first_record(&bytes, CHUNK);
    put_u64(&mut bytes, chunk + 1, 1 << 60);
    std::fs::write(&path, &bytes).unwrap();
    // Indexed reads do not use the record's own length; recovery walks records and must notice.
    assert!(
        every_reader_survives(&path) > 0,
        "recovery did not notice the record running past the end"
    );
}

#[test]
fn a_message_claiming_more_than_its_chunk_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("long-message.mcap");
    finished_cache(&path, Compression::None);
    let mut bytes = std::fs::read(&path).unwrap();
    let chunk = first_record(&bytes, CHUNK);
    // Uncompressed chunk: its records start after the header fields and the compression string.
    let compression_len =
        u32::from_le_bytes(bytes[chunk + 9 + 28..chunk + 9 + 32].try_into().unwrap()) as usize;
    let records = chunk + 9 + 32 + compression_len + 8;
    let message = (records..).find(|&i| bytes[i] == MESSAGE).unwrap();
    put_u64(&mut bytes, message + 1, u64::MAX / 2);
    std::fs::write(&path, &bytes).unwrap();
    assert!(every_reader_survives(&path) > 0);
}
