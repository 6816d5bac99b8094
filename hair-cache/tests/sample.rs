//! Sub-frame sampling and motion-blur sample sets; reading frames by time.

mod common;

use std::path::Path;

use common::{bits, frame_data, header, layout};
use hair_cache::{
    interpolate, CacheError, CacheReader, CacheWriter, Compression, Frame, Interpolation,
    Precision, Shutter, WriterOptions,
};
use nalgebra::Vector3;

/// Polynomial trajectory of point `i`: coefficients of `1, t, t², t³` per axis.
fn coefficients(i: usize, cubic: bool) -> [[f64; 4]; 3] {
    let k = i as f64;
    let c = |a: f64, b: f64, c2: f64, d: f64| {
        if cubic {
            [a, b, c2, d]
        } else {
            [a, b, 0.0, 0.0]
        }
    };
    [
        c(0.5 - 0.01 * k, 1.0 + 0.1 * k, 3.0 - 0.2 * k, 10.0 - k),
        c(-0.25 + 0.02 * k, -0.75, 2.0 + 0.1 * k, -6.0 + 0.5 * k),
        c(0.125 * k, 0.3 - 0.05 * k, -4.0, 7.5),
    ]
}

fn eval(coeffs: &[[f64; 4]; 3], t: f64) -> (Vector3<f64>, Vector3<f64>) {
    let p = |c: &[f64; 4]| c[0] + c[1] * t + c[2] * t * t + c[3] * t * t * t;
    let v = |c: &[f64; 4]| c[1] + 2.0 * c[2] * t + 3.0 * c[3] * t * t;
    (
        Vector3::new(p(&coeffs[0]), p(&coeffs[1]), p(&coeffs[2])),
        Vector3::new(v(&coeffs[0]), v(&coeffs[1]), v(&coeffs[2])),
    )
}

/// Writes frames 1..=5 at 24 fps sampling polynomial trajectories, velocities exact.
fn polynomial_cache(path: &Path, cubic: bool, compression: Compression) {
    let layout = layout();
    let options = WriterOptions {
        compression,
        chunk_size: 1000, // several chunks, so sampling crosses chunk boundaries
        foxglove: None,
        precision: Precision::F32,
    };
    let mut writer = CacheWriter::create(path, &header(), &layout, options).unwrap();
    for f in 1..=5u32 {
        let t = f64::from(f) / 24.0;
        let (x, v): (Vec<_>, Vec<_>) = (0..layout.point_count())
            .map(|i| {
                let (p, v) = eval(&coefficients(i, cubic), t);
                (p.cast::<f32>(), v.cast::<f32>())
            })
            .unzip();
        writer.write_frame(f, &x, &v).unwrap();
    }
    writer.finish().unwrap();
}

fn assert_close(got: &[Vector3<f32>], expected: impl Fn(usize) -> Vector3<f64>, tol: f64) {
    for (i, g) in got.iter().enumerate() {
        let e = expected(i);
        let err = (g.cast::<f64>() - e).amax();
        assert!(
            err <= tol * e.amax().max(1.0),
            "point {i}: {g:?} vs {e:?} (error {err:e})"
        );
    }
}

#[test]
fn hermite_reproduces_a_cubic_trajectory() {
    let dir = tempfile::tempdir().unwrap();
    for compression in [Compression::None, Compression::Zstd] {
        let path = dir.path().join(format!("cubic-{compression}.mcap"));
        polynomial_cache(&path, true, compression);
        let mut reader = CacheReader::open(&path).unwrap();
        for step in 0..=40 {
            let t = (1.0 + f64::from(step) * 0.1) / 24.0;
            let sample = reader.sample(t, Interpolation::Hermite).unwrap();
            assert_eq!(sample.time, t);
            // Stored values are f32: a few f32 ulps of error.
            assert_close(
                &sample.positions,
                |i| eval(&coefficients(i, true), t).0,
                4e-7,
            );
            assert_close(
                &sample.velocities,
                |i| eval(&coefficients(i, true), t).1,
                4e-6,
            );
        }
        // Linear interpolation does not reproduce a cubic (the test above is not vacuous).
        let t = 2.5 / 24.0;
        let linear = reader.sample(t, Interpolation::Linear).unwrap();
        let err = (linear.positions[0].cast::<f64>() - eval(&coefficients(0, true), t).0).amax();
        assert!(err > 1e-4, "{err}");
    }
}

#[test]
fn linear_mode_reproduces_linear_motion() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("linear.mcap");
    polynomial_cache(&path, false, Compression::Lz4);
    let mut reader = CacheReader::open(&path).unwrap();
    for step in 0..=20 {
        let t = (1.0 + f64::from(step) * 0.2) / 24.0;
        for mode in [Interpolation::Linear, Interpolation::Hermite] {
            let sample = reader.sample(t, mode).unwrap();
            assert_close(
                &sample.positions,
                |i| eval(&coefficients(i, false), t).0,
                4e-7,
            );
            assert_close(
                &sample.velocities,
                |i| eval(&coefficients(i, false), t).1,
                4e-6,
            );
        }
    }
}

#[test]
fn sample_at_a_frame_time_is_the_frame_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let layout = layout();
    let mut writer =
        CacheWriter::create(&path, &header(), &layout, WriterOptions::default()).unwrap();
    for f in 1..=4 {
        let (x, v) = frame_data(f, layout.point_count());
        writer.write_frame(f, &x, &v).unwrap();
    }
    writer.finish().unwrap();
    let mut reader = CacheReader::open(&path).unwrap();
    for f in 1..=4 {
        let (x, v) = frame_data(f, layout.point_count());
        for mode in [Interpolation::Hermite, Interpolation::Linear] {
            let sample = reader.sample(f64::from(f) / 24.0, mode).unwrap();
            assert_eq!(bits(&sample.positions), bits(&x), "frame {f}");
            assert_eq!(bits(&sample.velocities), bits(&v), "frame {f}");
        }
        let by_time = reader.read_frame_at_time(f64::from(f) / 24.0).unwrap();
        assert_eq!(by_time, reader.read_frame(f).unwrap());
        assert_eq!(reader.frames_around(f64::from(f) / 24.0).unwrap(), (f, f));
    }
    assert_eq!(reader.frames_around(2.5 / 24.0).unwrap(), (2, 3));
    assert_eq!(reader.frame_at_time(2.5 / 24.0), None);
    let err = reader.read_frame_at_time(2.5 / 24.0).unwrap_err();
    assert!(matches!(err, CacheError::NoSuchFrame { .. }), "{err}");
    // The centre of a shutter set is the frame itself.
    let shutter = Shutter::new(-0.5, 0.5, 3).unwrap();
    let set = reader
        .sample_shutter(2, &shutter, Interpolation::Hermite)
        .unwrap();
    assert_eq!(set.len(), 3);
    assert_eq!(
        bits(&set[1].positions),
        bits(&frame_data(2, layout.point_count()).0)
    );
    // The pure function returns the frames' own values at their ends.
    let a = reader.read_frame(1).unwrap();
    let b = reader.read_frame(2).unwrap();
    let at_b = interpolate(&a, &b, b.time, Interpolation::Hermite);
    assert_eq!(bits(&at_b.positions), bits(&b.positions));
}

#[test]
fn shutter_sample_times_are_evenly_spaced_over_the_interval() {
    let s = Shutter::new(-0.5, 0.5, 5).unwrap();
    assert_eq!(s.offsets(), vec![-0.5, -0.25, 0.0, 0.25, 0.5]);
    assert_eq!(
        s.times(10, 24.0),
        vec![
            9.5 / 24.0,
            9.75 / 24.0,
            10.0 / 24.0,
            10.25 / 24.0,
            10.5 / 24.0
        ]
    );
    assert_eq!(
        Shutter::new(-0.25, 0.25, 2).unwrap().offsets(),
        vec![-0.25, 0.25]
    );
    assert_eq!(Shutter::new(-0.25, 0.25, 1).unwrap().offsets(), vec![0.0]);
    assert_eq!(Shutter::new(0.0, 0.5, 1).unwrap().offsets(), vec![0.25]);
    assert_eq!(
        Shutter::new(-0.5, 0.5, 3).unwrap().times(7, 30.0)[1],
        7.0 / 30.0
    );
    assert!(Shutter::new(0.5, -0.5, 3).is_err());
    assert!(Shutter::new(-0.5, 0.5, 0).is_err());
    assert!(Shutter::new(f64::NAN, 0.5, 2).is_err());
}

#[test]
fn times_outside_the_cached_range_are_errors_naming_the_range() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cubic.mcap");
    polynomial_cache(&path, true, Compression::Lz4);
    let mut reader = CacheReader::open(&path).unwrap();
    assert_eq!(reader.time_range(), Some((1.0 / 24.0, 5.0 / 24.0)));
    for t in [0.0, 0.5 / 24.0, 5.01 / 24.0, 100.0, -1.0, f64::NAN] {
        let err = reader.sample(t, Interpolation::Hermite).unwrap_err();
        assert!(
            matches!(err, CacheError::TimeOutOfRange { .. }),
            "{t}: {err}"
        );
        let text = err.to_string();
        assert!(text.contains("frames 1–5"), "{text}");
        assert!(text.contains(&path.display().to_string()), "{text}");
    }
    // A shutter reaching before the first frame is refused as a whole.
    let shutter = Shutter::new(-0.5, 0.5, 3).unwrap();
    let err = reader
        .sample_shutter(1, &shutter, Interpolation::Hermite)
        .unwrap_err();
    assert!(matches!(err, CacheError::TimeOutOfRange { .. }), "{err}");
    let set = reader
        .sample_shutter(3, &shutter, Interpolation::Linear)
        .unwrap();
    let times: Vec<f64> = set.iter().map(|s| s.time).collect();
    assert_eq!(times, vec![2.5 / 24.0, 3.0 / 24.0, 3.5 / 24.0]);
}

#[test]
fn random_reads_in_any_order_match_frame_by_frame() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("many.mcap");
    let layout = layout();
    let options = WriterOptions {
        compression: Compression::Lz4,
        chunk_size: 2000,
        foxglove: None,
        precision: Precision::F32,
    };
    let mut writer = CacheWriter::create(&path, &header(), &layout, options).unwrap();
    for f in 1..=60 {
        let (x, v) = frame_data(f, layout.point_count());
        writer.write_frame(f, &x, &v).unwrap();
    }
    writer.finish().unwrap();
    let mut reader = CacheReader::open(&path).unwrap();
    let mut f = 17u32;
    for _ in 0..200 {
        f = (f * 37 + 11) % 60 + 1;
        let frame: Frame = reader.read_frame(f).unwrap();
        assert_eq!(frame.frame, f);
        assert_eq!(
            bits(&frame.positions),
            bits(&frame_data(f, layout.point_count()).0)
        );
    }
}
