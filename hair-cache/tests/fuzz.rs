//! Mutation fuzzing of every cache reader: `summarize`, `CacheReader` (open, every frame, a sample
//! between frames) and `recover`, on mutants of real caches (uncompressed, LZ4, Zstandard,
//! quantized, with the Foxglove view, and a killed writer's `.partial`). Each must answer with
//! frames or an error naming the file: no panic, no abort, and no more memory than a budget
//! proportional to the file (harness: `fuzz/harness.rs` at the workspace root).
//!
//! The suite runs about 5 000 mutants (12–25 s in the dev profile on the busy 2-core machine); the
//! longer run (60 000 mutants, other seeds):
//!
//! ```sh
//! cargo test -p hair-cache --test fuzz -- --ignored --nocapture
//! ```

#[path = "../../fuzz/harness.rs"]
mod harness;

mod common;

use std::path::Path;

use common::{frame_data, header, layout};
use hair_cache::foxglove::FoxgloveOptions;
use hair_cache::{CacheReader, CacheWriter, Compression, Interpolation, Precision, WriterOptions};

#[global_allocator]
static ALLOC: harness::Counting = harness::Counting;

/// Memory a mutant of `n` bytes may use while it is read: decoded frames and a decompressed chunk
/// are about the file's size each, plus the readers' and decoders' fixed buffers.
fn budget(n: usize) -> usize {
    16 * n + (4 << 20)
}

/// Caches to mutate: every way the writer lays out frames, finished, and one killed writer.
fn seeds(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let layout = layout();
    let variants = [
        ("plain", Compression::None, Precision::F32, 1500, false),
        (
            "plain-one-frame-chunks",
            Compression::None,
            Precision::F32,
            0,
            false,
        ),
        ("lz4", Compression::Lz4, Precision::F32, 1500, false),
        ("zstd", Compression::Zstd, Precision::F32, 1500, false),
        (
            "quantized",
            Compression::None,
            Precision::Quantized16,
            0,
            false,
        ),
        ("foxglove-lz4", Compression::Lz4, Precision::F32, 0, true),
    ];
    let mut seeds = Vec::new();
    for (name, compression, precision, chunk_size, foxglove) in variants {
        let path = dir.join(format!("{name}.mcap"));
        let options = WriterOptions {
            compression,
            chunk_size,
            foxglove: foxglove.then(FoxgloveOptions::default),
            precision,
        };
        let mut writer = CacheWriter::create(&path, &header(), &layout, options).unwrap();
        for frame in 1..=6 {
            let (x, v) = frame_data(frame, layout.point_count());
            writer.write_frame(frame, &x, &v).unwrap();
        }
        writer.finish().unwrap();
        seeds.push((name.to_string(), std::fs::read(&path).unwrap()));
    }
    // A killed writer: dropped without `finish`, so no summary.
    let path = dir.join("killed.mcap");
    let options = WriterOptions {
        chunk_size: 0,
        ..WriterOptions::default()
    };
    let mut writer = CacheWriter::create(&path, &header(), &layout, options).unwrap();
    for frame in 1..=4 {
        let (x, v) = frame_data(frame, layout.point_count());
        writer.write_frame(frame, &x, &v).unwrap();
    }
    drop(writer);
    let partial = dir.join("killed.mcap.partial");
    seeds.push(("killed-partial".into(), std::fs::read(partial).unwrap()));
    // Without checksums, damage reaches the lengths and frames behind them: readers must hold
    // without relying on a CRC.
    for i in [0, 2, 3, 6] {
        let (name, bytes) = &seeds[i];
        seeds.push((format!("{name}-no-crc"), without_crcs(bytes)));
    }
    seeds
}

/// `bytes` (a cache) with every CRC set to 0, which MCAP defines as "not computed": chunks,
/// attachments, data end and the footer's summary CRC.
fn without_crcs(bytes: &[u8]) -> Vec<u8> {
    let mut out = bytes.to_vec();
    let mut at = 8;
    while at + 9 <= out.len() {
        let len = u64::from_le_bytes(out[at + 1..at + 9].try_into().unwrap()) as usize;
        let body = at + 9;
        if body + len > out.len() {
            break;
        }
        let crc = match out[at] {
            0x06 => Some(body + 24), // chunk: after start, end and uncompressed size
            0x09 => Some(body + len - 4), // attachment: its last field
            0x0f => Some(body),      // data end
            0x02 => Some(body + 16), // footer: after the two offsets
            _ => None,
        };
        if let Some(crc) = crc {
            out[crc..crc + 4].fill(0);
        }
        at = body + len;
    }
    out
}

/// Runs every reader on the file `path`; `Err` with the first error (which must name the file).
fn read_every_way(path: &Path) -> Result<(), String> {
    let name = path.file_name().unwrap().to_string_lossy().to_string();
    let mut first_error = None;
    let mut note = |e: hair_cache::CacheError| {
        let e = e.to_string();
        assert!(e.contains(&name), "the error does not name the file: {e}");
        first_error.get_or_insert(e);
    };
    if let Err(e) = hair_cache::summarize(path) {
        note(e);
    }
    match CacheReader::open(path) {
        Ok(mut reader) => {
            for frame in reader.frame_numbers().to_vec() {
                if let Err(e) = reader.read_frame(frame) {
                    note(e);
                }
            }
            if let Some((t0, t1)) = reader.time_range() {
                let mid = 0.5 * (t0 + t1) + 1e-4;
                for interpolation in [Interpolation::Hermite, Interpolation::Linear] {
                    if let Err(e) = reader.sample(mid, interpolation) {
                        note(e);
                    }
                }
            }
        }
        Err(e) => note(e),
    }
    match hair_cache::recover(path) {
        Ok(recovery) => assert!(recovery.frames.len() <= 6, "frames appeared from nowhere"),
        Err(e) => note(e),
    }
    first_error.map_or(Ok(()), Err)
}

fn fuzz(mutants_per_seed: usize, seed: u64) {
    let dir = tempfile::tempdir().unwrap();
    let seeds = seeds(dir.path());
    let mutant = dir.path().join("mutant.mcap");
    let report = harness::run(
        "cache",
        &seeds,
        mutants_per_seed,
        seed,
        false,
        budget,
        |bytes| {
            std::fs::write(&mutant, bytes).unwrap();
            read_every_way(&mutant)
        },
    );
    harness::assert_clean("cache readers", &report);
}

#[test]
fn cache_readers_survive_mutated_caches() {
    // 11 seeds × 450 ≈ 5 000 mutants.
    fuzz(450, 3001);
}

#[test]
#[ignore = "long run, about a minute: cargo test -p hair-cache --test fuzz -- --ignored"]
fn cache_readers_survive_many_mutated_caches() {
    fuzz(5500, 4001);
}
