//! Damaged caches that crashed a reader, kept as files under `tests/regressions/`,
//! each test named after the failure it pins. Every reader entry point (`summarize`, `open` and
//! reading every frame, `sample`, `recover`) must answer with an error naming the file, without a
//! panic and without allocating more than a small multiple of the file.
//!
//! The files were made by [`write_regression_files`] (run it with `--ignored` to remake them)
//! from a two-frame cache of the test layout (15 points), one field changed per file:
//!
//! | file | change |
//! |---|---|
//! | `record_length_past_chunk_end.mcap` | the length of the first message record inside the first (uncompressed) chunk runs 1000 bytes past the chunk; the chunk's CRC recomputed, so the length check itself is tested |
//! | `lz4_size_field_1tib.mcap` | the first lz4 chunk's uncompressed size is 2⁴⁰ + 9 (the size in the abort) |
//! | `chunk_size_field_capacity_overflow.mcap` | the first lz4 chunk's uncompressed size is 2⁶⁴ − 1 |
//! | `metadata_string_length_4gib.mcap` | the metadata record's name length is 2³² − 1: the reader of 8a3b50a reserved 4 GiB for it (the "11 KB cache reserves 4 GiB") |
//!
//! The readers of 8a3b50a answered the first three with errors (no crash: the panics
//! and aborts came from lengths inside decompressed chunks, pinned by the fuzzer's files below);
//! these files pin the new checks and messages.
//!
//! Mutants the fuzzer (`tests/fuzz.rs`) found crashing the readers of `main` at 8a3b50a (before
//! this hardening), kept as they were found:
//!
//! | file | what the old reader did |
//! |---|---|
//! | `lz4_record_length_trusted_before_crc.mcap` (lz4, compressed bytes of the first chunk mutated) | `cache sample` and `cache recover` aborted: "memory allocation of 93731172831461718 bytes failed": a record length inside the decompressed chunk was trusted before the chunk's CRC was checked |
//! | `zstd_record_length_abort.mcap` (zstd) | aborted: "memory allocation of 4412750543122661385 bytes failed" |
//! | `foxglove_lz4_allocation_abort.mcap` (lz4 with the Foxglove view) | aborted: "memory allocation of 3940658264014857 bytes failed" |
//! | `zstd_capacity_overflow.mcap` (zstd) | panicked: "capacity overflow" |
//! | `string_length_reserves_4gib.mcap` (uncompressed, 3 838 bytes) | allocated 4 294 967 042 bytes at once |
//! | `partial_record_length_reserves_4gib.mcap` (a killed writer's file, 2 959 bytes) | allocated 4 278 190 090 bytes at once |
//!
//! Of 3 081 mutants (`tests/fuzz.rs` with 280 mutants per seed and the generator seeded with
//! 0x6361_6368_6531), the readers of 8a3b50a aborted on 17, panicked on 3 and allocated more than
//! 16 × the file + 4 MiB on 214 (up to 4.3 GB for a 4 KB file); these readers fail none.

#[path = "../../fuzz/harness.rs"]
mod harness;

mod common;

use std::path::{Path, PathBuf};

use common::{frame_data, header, layout};
use hair_cache::{CacheReader, CacheWriter, Compression, Interpolation, WriterOptions};

#[global_allocator]
static ALLOC: harness::Counting = harness::Counting;

const CHUNK: u8 = 0x06;
const METADATA: u8 = 0x0c;
const MESSAGE: u8 = 0x05;

fn regression(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/regressions")
        .join(name)
}

/// Runs every reader on `path` and returns their errors, asserting that each names the file, that
/// none panics and that reading allocates at most 16 times the file plus 4 MiB.
fn every_reader_refuses(path: &Path) -> Vec<String> {
    let name = path.file_name().unwrap().to_string_lossy().to_string();
    let budget = 16 * std::fs::metadata(path).unwrap().len() as usize + (4 << 20);
    let (errors, peak, largest) = harness::measure(|| {
        let mut errors = Vec::new();
        if let Err(e) = hair_cache::summarize(path) {
            errors.push(e.to_string());
        }
        match CacheReader::open(path) {
            Ok(mut reader) => {
                for frame in reader.frame_numbers().to_vec() {
                    if let Err(e) = reader.read_frame(frame) {
                        errors.push(e.to_string());
                    }
                }
                if let Err(e) = reader.sample(1.5 / 24.0, Interpolation::Hermite) {
                    errors.push(e.to_string());
                }
            }
            Err(e) => errors.push(e.to_string()),
        }
        match hair_cache::recover(path) {
            Ok(recovery) => {
                if let Some(w) = recovery.warning {
                    errors.push(format!("{name}: {w}"));
                }
            }
            Err(e) => errors.push(e.to_string()),
        }
        errors
    });
    assert!(
        peak.max(largest) <= budget,
        "{name}: reading allocated {largest} bytes at once and {peak} at peak (budget {budget})"
    );
    for e in &errors {
        assert!(e.contains(&name), "the error does not name the file: {e}");
    }
    errors
}

#[test]
fn record_length_past_chunk_end() {
    let errors = every_reader_refuses(&regression("record_length_past_chunk_end.mcap"));
    assert!(
        errors
            .iter()
            .any(|e| e.contains("but only") && e.contains("follow it")),
        "{errors:#?}"
    );
    // The frame channel is declared in the damaged first chunk, so the second chunk's frame
    // cannot be interpreted either: recovery names the damage and returns no frame.
    let recovery = hair_cache::recover(regression("record_length_past_chunk_end.mcap")).unwrap();
    assert_eq!(recovery.frame_numbers(), [] as [u32; 0]);
    let warning = recovery.warning.unwrap().to_string();
    assert!(warning.contains("is damaged"), "{warning}");
}

#[test]
fn lz4_size_field_1tib() {
    let errors = every_reader_refuses(&regression("lz4_size_field_1tib.mcap"));
    assert!(
        errors
            .iter()
            .any(|e| e.contains("claims 1099511627785 bytes uncompressed")),
        "{errors:#?}"
    );
}

#[test]
fn chunk_size_field_capacity_overflow() {
    let errors = every_reader_refuses(&regression("chunk_size_field_capacity_overflow.mcap"));
    assert!(
        errors.iter().any(|e| e.contains("18446744073709551615")),
        "{errors:#?}"
    );
}

#[test]
fn metadata_string_length_4gib() {
    let errors = every_reader_refuses(&regression("metadata_string_length_4gib.mcap"));
    // Every entry point needs the metadata, so every one refuses the file.
    assert_eq!(errors.len(), 3, "{errors:#?}");
    assert!(
        errors.iter().all(|e| e.contains("metadata record")),
        "{errors:#?}"
    );
}

#[test]
fn lz4_record_length_trusted_before_crc() {
    let errors = every_reader_refuses(&regression("lz4_record_length_trusted_before_crc.mcap"));
    assert!(
        errors
            .iter()
            .any(|e| e.contains("lz4") || e.contains("CRC")),
        "{errors:#?}"
    );
}

/// Found by the fuzzer on the readers of 8a3b50a; see the table above.
#[test]
fn zstd_record_length_abort() {
    assert!(!every_reader_refuses(&regression("zstd_record_length_abort.mcap")).is_empty());
}

#[test]
fn foxglove_lz4_allocation_abort() {
    assert!(!every_reader_refuses(&regression("foxglove_lz4_allocation_abort.mcap")).is_empty());
}

#[test]
fn zstd_capacity_overflow() {
    assert!(!every_reader_refuses(&regression("zstd_capacity_overflow.mcap")).is_empty());
}

#[test]
fn string_length_reserves_4gib() {
    assert!(!every_reader_refuses(&regression("string_length_reserves_4gib.mcap")).is_empty());
}

#[test]
fn partial_record_length_reserves_4gib() {
    let path = regression("partial_record_length_reserves_4gib.mcap");
    assert!(!every_reader_refuses(&path).is_empty());
}

/// The readers refuse a path that is not a regular file before reading from it: a directory,
/// `/dev/zero` (which never ends) and a FIFO (whose open would block until a writer comes).
#[test]
fn dev_zero_fifo_and_directory_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe.mcap");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    assert!(made.is_ok_and(|s| s.success()), "mkfifo failed");
    let cases = [
        (dir.path().to_path_buf(), "is a directory"),
        (PathBuf::from("/dev/zero"), "is a device"),
        (fifo, "is a FIFO (named pipe)"),
    ];
    for (path, kind) in cases {
        // In a thread, so a reader that blocks fails the test instead of hanging it.
        let (send, receive) = std::sync::mpsc::channel();
        let p = path.clone();
        std::thread::spawn(move || {
            let errors = [
                hair_cache::summarize(&p).err(),
                CacheReader::open(&p).err(),
                hair_cache::recover(&p).err(),
            ];
            let _ = send.send(errors.map(|e| e.map(|e| e.to_string())));
        });
        let errors = receive
            .recv_timeout(std::time::Duration::from_secs(10))
            .unwrap_or_else(|_| panic!("a reader blocked on {}", path.display()));
        for e in errors {
            let e = e.unwrap_or_else(|| panic!("{} was read", path.display()));
            assert!(
                e.contains(&path.display().to_string()) && e.contains(kind),
                "{e}"
            );
        }
    }
}

/// A two-frame cache, one frame per chunk.
fn two_frames(path: &Path, compression: Compression) -> Vec<u8> {
    let layout = layout();
    let options = WriterOptions {
        compression,
        chunk_size: 0,
        ..WriterOptions::default()
    };
    let mut writer = CacheWriter::create(path, &header(), &layout, options).unwrap();
    for frame in 1..=2 {
        let (x, v) = frame_data(frame, layout.point_count());
        writer.write_frame(frame, &x, &v).unwrap();
    }
    writer.finish().unwrap();
    std::fs::read(path).unwrap()
}

/// Offset of the first record with `opcode` in the data section.
fn first_record(bytes: &[u8], opcode: u8) -> usize {
    let mut at = 8;
    while bytes[at] != opcode {
        at += 9 + u64::from_le_bytes(bytes[at + 1..at + 9].try_into().unwrap()) as usize;
    }
    at
}

fn put_u64(bytes: &mut [u8], at: usize, value: u64) {
    bytes[at..at + 8].copy_from_slice(&value.to_le_bytes());
}

/// Remakes the files under `tests/regressions/` as the table in this file's docs says.
#[test]
#[ignore = "remakes the committed regression files: cargo test -p hair-cache --test regressions -- --ignored"]
fn write_regression_files() {
    let dir = tempfile::tempdir().unwrap();
    let plain = two_frames(&dir.path().join("plain.mcap"), Compression::None);
    let lz4 = two_frames(&dir.path().join("lz4.mcap"), Compression::Lz4);

    // A message record inside the first chunk runs past the chunk; the chunk's CRC still checks.
    let mut bytes = plain.clone();
    let chunk = first_record(&bytes, CHUNK);
    let body = chunk + 9;
    let compression_len = u32::from_le_bytes(bytes[body + 28..body + 32].try_into().unwrap());
    let records = body + 32 + compression_len as usize + 8;
    let records_len = u64::from_le_bytes(bytes[records - 8..records].try_into().unwrap()) as usize;
    let message = (records..).find(|&i| bytes[i] == MESSAGE).unwrap();
    let past_end = (records + records_len - message - 9 + 1000) as u64;
    put_u64(&mut bytes, message + 1, past_end);
    let crc = crc32(&bytes[records..records + records_len]);
    bytes[body + 24..body + 28].copy_from_slice(&crc.to_le_bytes());
    std::fs::write(regression("record_length_past_chunk_end.mcap"), &bytes).unwrap();

    // The first lz4 chunk's uncompressed size field.
    for (name, size) in [
        ("lz4_size_field_1tib.mcap", (1u64 << 40) + 9),
        ("chunk_size_field_capacity_overflow.mcap", u64::MAX),
    ] {
        let mut bytes = lz4.clone();
        let chunk = first_record(&bytes, CHUNK);
        put_u64(&mut bytes, chunk + 9 + 16, size);
        std::fs::write(regression(name), &bytes).unwrap();
    }

    // The metadata record's name length.
    let mut bytes = plain;
    let metadata = first_record(&bytes, METADATA);
    bytes[metadata + 9..metadata + 13].copy_from_slice(&u32::MAX.to_le_bytes());
    std::fs::write(regression("metadata_string_length_4gib.mcap"), &bytes).unwrap();
}

/// CRC-32 (IEEE), as MCAP uses, bit by bit: only for making the files above.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = (crc >> 1) ^ (0xedb8_8320 & (crc & 1).wrapping_neg());
        }
    }
    !crc
}
