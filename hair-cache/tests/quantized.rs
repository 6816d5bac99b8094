//! Quantized (`Precision::Quantized16`) caches: every decoded coordinate within half a
//! quantization step of the written one, 12 bytes per point-frame, readable by the reader, by
//! `recover` (also from a `.partial` file) and by the sampler.

mod common;

use std::path::Path;

use common::{frame_data, header, layout};
use hair_cache::layout::{axis_bounds, quantization_error};
use hair_cache::{
    recover, CacheLayout, CacheReader, CacheWriter, Compression, Frame, Interpolation, Precision,
    WriterOptions,
};
use nalgebra::Vector3;

fn quantized(compression: Compression, chunk_size: u64) -> WriterOptions {
    WriterOptions {
        compression,
        chunk_size,
        precision: Precision::Quantized16,
        ..WriterOptions::default()
    }
}

/// A groom of `strands` strands of 20 points hanging from a 2.97 m wide (x) line, swinging in y
/// and z with the frame number; velocities up to about 2 m/s.
fn groom(strands: usize) -> CacheLayout {
    CacheLayout {
        offsets: (0..=strands).map(|s| (20 * s) as u32).collect(),
        rest_lengths: vec![0.015; 19 * strands],
        radii: vec![4e-5; 20 * strands],
    }
}

fn groom_frame(frame: u32, layout: &CacheLayout) -> (Vec<Vector3<f32>>, Vec<Vector3<f32>>) {
    let strands = layout.strand_count();
    let mut x = Vec::with_capacity(layout.point_count());
    let mut v = Vec::with_capacity(layout.point_count());
    for s in 0..strands {
        let root = -1.485 + 2.97 * s as f32 / (strands - 1).max(1) as f32;
        for i in 0..20 {
            let phase = frame as f32 * 0.21 + s as f32 * 0.013;
            let swing = 0.004 * i as f32 * phase.sin();
            x.push(Vector3::new(
                root,
                1.6 - 0.015 * i as f32 + swing,
                0.3 * (s as f32 * 0.7).sin() + swing * 0.5,
            ));
            v.push(Vector3::new(
                0.0,
                0.1 * i as f32 * phase.cos() - 0.05 * i as f32,
                0.05 * i as f32 * phase.cos(),
            ));
        }
    }
    (x, v)
}

/// Largest |decoded − written| over `values` in units of the documented bound per axis, after
/// asserting the bound: half a step `(max − min) / 131070` plus the rounding to `f32` (half an
/// ulp of the value). Returns (largest error, largest error / half step).
fn check_bound(what: &str, written: &[Vector3<f32>], decoded: &[Vector3<f32>]) -> (f64, f64) {
    assert_eq!(written.len(), decoded.len());
    let (min, max) = axis_bounds(written);
    let (mut worst, mut worst_ratio) = (0f64, 0f64);
    for (i, (a, b)) in written.iter().zip(decoded).enumerate() {
        for axis in 0..3 {
            let half_step = quantization_error(min[axis], max[axis]);
            let rounding = f64::from(a[axis].abs().max(b[axis].abs())) * f64::from(f32::EPSILON)
                / 2.0
                + f64::from(f32::from_bits(1));
            let err = (f64::from(a[axis]) - f64::from(b[axis])).abs();
            assert!(
                err <= half_step + rounding,
                "{what} point {i} axis {axis}: wrote {} read {}, error {err} > half step {half_step} \
                 + f32 rounding {rounding}",
                a[axis],
                b[axis]
            );
            assert!((min[axis]..=max[axis]).contains(&b[axis]), "{what} {i}");
            worst = worst.max(err);
            if half_step > 0.0 {
                worst_ratio = worst_ratio.max(err / half_step);
            }
        }
    }
    (worst, worst_ratio)
}

fn write(path: &Path, layout: &CacheLayout, options: WriterOptions, frames: &[u32]) {
    let mut writer = CacheWriter::create(path, &header(), layout, options).unwrap();
    for &f in frames {
        let (x, v) = frame_data(f, layout.point_count());
        writer.write_frame(f, &x, &v).unwrap();
    }
    writer.finish().unwrap();
}

#[test]
fn quantized_frames_are_within_half_a_step_of_the_written_ones() {
    let dir = tempfile::tempdir().unwrap();
    let layout = layout();
    let frames: Vec<u32> = (1..=12).collect();
    for compression in [Compression::None, Compression::Lz4, Compression::Zstd] {
        for chunk_size in [0, WriterOptions::DEFAULT_CHUNK_SIZE] {
            let path = dir
                .path()
                .join(format!("q-{compression}-{chunk_size}.mcap"));
            write(&path, &layout, quantized(compression, chunk_size), &frames);
            let mut reader = CacheReader::open(&path).unwrap();
            assert_eq!(reader.precision(), Precision::Quantized16);
            assert_eq!(reader.frame_numbers(), &frames[..]);
            let recovered = recover(&path).unwrap();
            assert_eq!(recovered.precision, Precision::Quantized16);
            assert_eq!(recovered.warning, None);
            for &f in frames.iter().rev() {
                let frame = reader.read_frame(f).unwrap();
                let (x, v) = frame_data(f, layout.point_count());
                assert_eq!((frame.frame, frame.time), (f, f64::from(f) / 24.0));
                check_bound("position", &x, &frame.positions);
                // Velocities include -0.0, a subnormal and f32::MAX: the bound still holds.
                check_bound("velocity", &v, &frame.velocities);
                // Every reader decodes the same frame.
                assert_eq!(recovered.frames[(f - 1) as usize], frame);
            }
        }
    }
}

#[test]
fn a_groom_over_three_meters_is_within_23_micrometers_at_12_bytes_per_point_frame() {
    let dir = tempfile::tempdir().unwrap();
    let layout = groom(1000);
    let frames: Vec<u32> = (1..=40).collect();
    let mut sizes = Vec::new();
    for precision in [Precision::F32, Precision::Quantized16] {
        let path = dir.path().join(format!("groom-{precision}.mcap"));
        let options = WriterOptions {
            precision,
            ..WriterOptions::default()
        };
        let mut writer = CacheWriter::create(&path, &header(), &layout, options).unwrap();
        for &f in &frames {
            let (x, v) = groom_frame(f, &layout);
            writer.write_frame(f, &x, &v).unwrap();
        }
        let summary = writer.finish().unwrap();
        let per_point_frame = summary.bytes_per_point_frame.unwrap();
        sizes.push(per_point_frame);

        let mut reader = CacheReader::open(&path).unwrap();
        assert_eq!(reader.precision(), precision);
        assert_eq!(reader.summary(), summary);
        let (mut worst, mut worst_ratio) = (0f64, 0f64);
        for &f in &frames {
            let frame = reader.read_frame(f).unwrap();
            let (x, v) = groom_frame(f, &layout);
            let (extent_min, extent_max) = axis_bounds(&x);
            let extent = extent_max[0] - extent_min[0];
            assert!((extent - 2.97).abs() < 1e-6, "{extent}");
            let (e, r) = check_bound("position", &x, &frame.positions);
            check_bound("velocity", &v, &frame.velocities);
            worst = worst.max(e);
            worst_ratio = worst_ratio.max(r);
            if precision == Precision::F32 {
                assert_eq!(frame.positions, x);
            }
        }
        // 2.97 m / 131070 = 22.66 µm, plus the f32 rounding.
        assert!(worst <= 2.98 / 131070.0, "{worst}");
        eprintln!(
            "{precision}: {per_point_frame:.3} bytes per point-frame, largest position error \
             {:.2} µm ({worst_ratio:.4} half steps)",
            worst * 1e6
        );
    }
    // 20 000 points: 24 bytes per point (+ 20 of frame header) in f32, 12 (+ 68) quantized,
    // plus the file's own bytes (the 160 kB layout attachment: 0.2 byte per point-frame).
    assert!((24.0..24.3).contains(&sizes[0]), "{sizes:?}");
    assert!((12.0..12.3).contains(&sizes[1]), "{sizes:?}");
    assert!((sizes[0] - sizes[1] - 12.0).abs() < 0.01, "{sizes:?}");
}

#[test]
fn recover_reads_a_quantized_partial_file() {
    let dir = tempfile::tempdir().unwrap();
    let layout = layout();
    let options = quantized(Compression::Zstd, 1500);
    let run = dir.path().join("run.mcap");
    let mut writer = CacheWriter::create(&run, &header(), &layout, options).unwrap();
    for f in 1..=20 {
        let (x, v) = frame_data(f, layout.point_count());
        writer.write_frame(f, &x, &v).unwrap();
    }
    let partial = writer.partial_path().to_path_buf();
    drop(writer);
    assert!(!run.exists());

    let recovered = recover(&partial).unwrap();
    assert_eq!(recovered.precision, Precision::Quantized16);
    assert_eq!(recovered.warning, None);
    assert_eq!(
        recovered.frame_numbers(),
        (1..=20).collect::<Vec<u32>>(),
        "every closed chunk"
    );
    for frame in &recovered.frames {
        let (x, v) = frame_data(frame.frame, layout.point_count());
        check_bound("position", &x, &frame.positions);
        check_bound("velocity", &v, &frame.velocities);
    }

    // Rewritten quantized: decoded values are on their grid, so they come back unchanged when
    // the bounds do (they do: the bounds are decoded exactly).
    let fixed = dir.path().join("fixed.mcap");
    recovered
        .write(
            &fixed,
            WriterOptions {
                precision: recovered.precision,
                ..options
            },
        )
        .unwrap();
    let mut reader = CacheReader::open(&fixed).unwrap();
    assert_eq!(reader.precision(), Precision::Quantized16);
    for frame in &recovered.frames {
        let again: Frame = reader.read_frame(frame.frame).unwrap();
        check_bound("position", &frame.positions, &again.positions);
    }
}

#[test]
fn sampling_between_quantized_frames_stays_near_the_exact_samples() {
    let dir = tempfile::tempdir().unwrap();
    let layout = groom(20);
    let mut readers = Vec::new();
    for precision in [Precision::F32, Precision::Quantized16] {
        let path = dir.path().join(format!("sample-{precision}.mcap"));
        let options = WriterOptions {
            precision,
            ..WriterOptions::default()
        };
        let mut writer = CacheWriter::create(&path, &header(), &layout, options).unwrap();
        for f in 1..=4 {
            let (x, v) = groom_frame(f, &layout);
            writer.write_frame(f, &x, &v).unwrap();
        }
        writer.finish().unwrap();
        readers.push(CacheReader::open(&path).unwrap());
    }
    let (x, _) = groom_frame(2, &layout);
    let (min, max) = axis_bounds(&x);
    for interpolation in [Interpolation::Hermite, Interpolation::Linear] {
        let t = 2.4 / 24.0;
        let exact = readers[0].sample(t, interpolation).unwrap();
        let lossy = readers[1].sample(t, interpolation).unwrap();
        for (a, b) in exact.positions.iter().zip(&lossy.positions) {
            for axis in 0..3 {
                // Position error of the frames, plus Hermite's tangents (velocities × frame
                // duration) carrying their own quantization error: a few half steps at most.
                let bound = 4.0 * quantization_error(min[axis], max[axis]) + 1e-6;
                let err = (f64::from(a[axis]) - f64::from(b[axis])).abs();
                assert!(
                    err <= bound,
                    "{interpolation:?} axis {axis}: {err} > {bound}"
                );
            }
        }
    }
}
