//! Random frame access: the cost of reading one frame must not grow with the file's length.
//!
//! Caches of 10 and 1,000 frames of 500 points (50 strands of 10 points, default 64 KiB lz4
//! chunks, i.e. 6 frames per chunk) are opened once; each iteration reads one frame chosen
//! pseudo-randomly, always in another chunk than the previous read (so the reader's one-chunk
//! cache never serves it): the time is an index lookup, one chunk read, decompressed and
//! CRC-checked, and one frame decoded. A sub-frame sample between two frames is timed too. The
//! last chunk of the 10-frame file holds only 4 frames, so its reads do a little less work; the
//! one-frame-per-chunk variant (`chunk_size` 0) does identical work at every file length.
//! Run: `cargo bench -p hair-cache --bench random_read`.

use std::hint::black_box;
use std::path::Path;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use hair_cache::{
    CacheHeader, CacheLayout, CacheReader, CacheWriter, Compression, Interpolation, Precision,
    WriterOptions,
};
use nalgebra::Vector3;

const STRANDS: u32 = 50;
const POINTS_PER_STRAND: u32 = 10;

fn layout() -> CacheLayout {
    let points = STRANDS * POINTS_PER_STRAND;
    CacheLayout {
        offsets: (0..=STRANDS).map(|s| s * POINTS_PER_STRAND).collect(),
        rest_lengths: vec![0.01; (points - STRANDS) as usize],
        radii: vec![1e-4; points as usize],
    }
}

fn write_cache(path: &Path, frames: u32, compression: Compression, chunk_size: u64) {
    let layout = layout();
    let header = CacheHeader {
        fps: 24.0,
        first_frame: 1,
        scene_hash: "00".into(),
        ..Default::default()
    };
    let options = WriterOptions {
        compression,
        chunk_size,
        foxglove: None,
        precision: Precision::F32,
    };
    let mut writer = CacheWriter::create(path, &header, &layout, options).unwrap();
    let n = layout.point_count();
    for f in 1..=frames {
        let t = f as f32 / 24.0;
        let x: Vec<_> = (0..n)
            .map(|i| Vector3::new((t + i as f32).sin(), 0.001 * i as f32, -0.01 * t))
            .collect();
        let v: Vec<_> = (0..n)
            .map(|i| Vector3::new((t + i as f32).cos(), 0.0, -0.01))
            .collect();
        writer.write_frame(f, &x, &v).unwrap();
    }
    writer.finish().unwrap();
}

/// A pseudo-random sequence of frames in `1..=frames` that alternates between the first and
/// the last third of the file (different chunks).
fn frame_sequence(frames: u32) -> Vec<u32> {
    let third = (frames / 3).max(1);
    let mut state = 0x2545_f491_u32;
    (0..1024)
        .map(|i| {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let k = (state >> 8) % third;
            if i % 2 == 0 {
                1 + k
            } else {
                frames - k
            }
        })
        .collect()
}

fn random_read(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap();
    let mut group = c.benchmark_group("random_read");
    group.warm_up_time(std::time::Duration::from_secs(1));
    group.measurement_time(std::time::Duration::from_secs(3));
    let default_chunks = WriterOptions::DEFAULT_CHUNK_SIZE;
    for (compression, chunk_size) in [
        (Compression::Lz4, default_chunks),
        (Compression::None, default_chunks),
        (Compression::Lz4, 0),
    ] {
        let name = match chunk_size {
            0 => format!("{compression}_chunk_per_frame"),
            _ => compression.to_string(),
        };
        for frames in [10u32, 1_000] {
            let path = dir.path().join(format!("{name}-{frames}.mcap"));
            write_cache(&path, frames, compression, chunk_size);
            let mut reader = CacheReader::open(&path).unwrap();
            let sequence = frame_sequence(frames);
            let mut i = 0;
            group.bench_function(
                BenchmarkId::new(format!("frame_500pts_{name}"), frames),
                |b| {
                    b.iter(|| {
                        i = (i + 1) % sequence.len();
                        black_box(reader.read_frame(sequence[i]).unwrap())
                    })
                },
            );
            group.bench_function(
                BenchmarkId::new(format!("sample_500pts_{name}"), frames),
                |b| {
                    b.iter(|| {
                        i = (i + 1) % sequence.len();
                        let f = sequence[i].min(frames - 1);
                        let t = (f as f64 + 0.37) / 24.0;
                        black_box(reader.sample(t, Interpolation::Hermite).unwrap())
                    })
                },
            );
        }
    }
    group.finish();
}

criterion_group!(benches, random_read);
criterion_main!(benches);
