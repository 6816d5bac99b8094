//! Cache throughput at production size: writing frames of 100,000 points (2.4 MB each) with each
//! compression, reading a random frame, and a cubic Hermite sub-frame sample of all 100,000
//! points. Frames are swinging-hair-like (smooth, different every frame) so compression sees
//! realistic data. Files go to the system temp directory (the disk a run would use).
//! Run: `cargo bench -p hair-cache --bench throughput`.

use std::hint::black_box;
use std::path::{Path, PathBuf};

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use hair_cache::{
    CacheHeader, CacheLayout, CacheReader, CacheWriter, Compression, Interpolation, WriterOptions,
};
use nalgebra::Vector3;

const STRANDS: u32 = 5_000;
const POINTS_PER_STRAND: u32 = 20;
const FRAMES: u32 = 24;

fn layout() -> CacheLayout {
    let points = STRANDS * POINTS_PER_STRAND;
    CacheLayout {
        offsets: (0..=STRANDS).map(|s| s * POINTS_PER_STRAND).collect(),
        rest_lengths: vec![0.01; (points - STRANDS) as usize],
        radii: vec![1e-4; points as usize],
    }
}

/// Positions (m) and velocities (m/s) of one frame.
type FrameData = (Vec<Vector3<f32>>, Vec<Vector3<f32>>);

/// Positions and velocities of frame `f`: strands hanging and swinging.
fn frame(f: u32) -> FrameData {
    let t = f as f32 / 24.0;
    let mut x = Vec::with_capacity((STRANDS * POINTS_PER_STRAND) as usize);
    let mut v = Vec::with_capacity(x.capacity());
    for s in 0..STRANDS {
        let (root_x, root_y) = ((s % 100) as f32 * 0.003, (s / 100) as f32 * 0.003);
        for i in 0..POINTS_PER_STRAND {
            let d = i as f32 * 0.01;
            let swing = 0.3 * d * (3.0 * t + 0.01 * s as f32).sin();
            x.push(Vector3::new(root_x + swing, root_y, -d));
            v.push(Vector3::new(
                0.9 * d * (3.0 * t + 0.01 * s as f32).cos(),
                0.0,
                0.0,
            ));
        }
    }
    (x, v)
}

fn header() -> CacheHeader {
    CacheHeader {
        fps: 24.0,
        first_frame: 1,
        scene_hash: "00".into(),
        ..Default::default()
    }
}

fn write(path: &Path, compression: Compression, frames: &[FrameData]) {
    let options = WriterOptions {
        compression,
        ..WriterOptions::default()
    };
    let mut writer = CacheWriter::create(path, &header(), &layout(), options).unwrap();
    for (f, (x, v)) in frames.iter().enumerate() {
        writer.write_frame(f as u32 + 1, x, v).unwrap();
    }
    writer.finish().unwrap();
}

fn temp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("hairsys-bench-{name}-{}.mcap", std::process::id()))
}

fn bench(c: &mut Criterion) {
    let frames: Vec<_> = (1..=FRAMES).map(frame).collect();
    let frame_bytes = 24 * (STRANDS * POINTS_PER_STRAND) as u64;

    let mut group = c.benchmark_group("write 24 frames of 100k points");
    group.sample_size(10);
    group.throughput(Throughput::Bytes(frame_bytes * FRAMES as u64));
    for compression in [Compression::None, Compression::Lz4, Compression::Zstd] {
        let path = temp(&format!("write-{compression}"));
        group.bench_function(BenchmarkId::from_parameter(compression), |b| {
            b.iter(|| write(&path, compression, &frames))
        });
        let _ = std::fs::remove_file(&path);
    }
    group.finish();

    let mut group = c.benchmark_group("read 100k points");
    group.sample_size(20);
    for compression in [Compression::None, Compression::Lz4] {
        let path = temp(&format!("read-{compression}"));
        write(&path, compression, &frames);
        let mut reader = CacheReader::open(&path).unwrap();
        let mut k = 0u32;
        group.bench_function(BenchmarkId::new("random frame", compression), |b| {
            b.iter(|| {
                k = (k * 7 + 5) % FRAMES;
                black_box(reader.read_frame(k + 1).unwrap());
            })
        });
        let mut k = 0u32;
        group.bench_function(BenchmarkId::new("Hermite sample", compression), |b| {
            b.iter(|| {
                k = (k * 7 + 5) % (FRAMES - 1);
                black_box(
                    reader
                        .sample((k as f64 + 1.37) / 24.0, Interpolation::Hermite)
                        .unwrap(),
                );
            })
        });
        let _ = std::fs::remove_file(&path);
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
