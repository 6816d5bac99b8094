//! Sub-frame sampling: positions between two cached frames, and motion-blur sample sets.
//!
//! Between frames `a` (time `t0`, positions `p0`, velocities `v0`) and `b` (`t1`, `p1`, `v1`),
//! with `h = t1 − t0` and `s = (t − t0) / h` in `[0, 1]`, [`Interpolation::Hermite`] evaluates
//! the cubic Hermite curve
//!
//! ```text
//! p(s) = (2s³ − 3s² + 1) p0 + (s³ − 2s² + s) h v0 + (−2s³ + 3s²) p1 + (s³ − s²) h v1
//! ```
//!
//! which passes through both frames with their stored velocities (it reproduces any cubic
//! trajectory whose velocities were stored exactly), and its derivative as the velocity.
//! [`Interpolation::Linear`] blends positions and velocities linearly. Arithmetic is done in
//! `f64` and rounded to `f32` once.
//!
//! At a frame time (to the nearest nanosecond, as frames are logged) the sample *is* the cached
//! frame, bit for bit. Times before the first or after the last cached frame are a
//! [`CacheError::TimeOutOfRange`] naming the cached range.
//!
//! # Quantized caches
//!
//! Frames of a [`Precision::Quantized16`](crate::Precision::Quantized16) cache are decoded
//! before sampling, so samples carry their quantization error
//! ([`crate::layout#quantized-frame-payload`]): per axis, at a frame time the frame's own
//! (at most half a step, `(max − min) / 131070`, plus the `f32` rounding); between frames, with
//! `εp` the larger position half step of the two frames and `εv0`, `εv1` their velocity half
//! steps, at most `εp` for [`Interpolation::Linear`] (a convex blend) and
//! `εp + (4/27) h (εv0 + εv1)` for [`Interpolation::Hermite`] (its tangent weights are at most
//! 4/27), plus the rounding to `f32`.
//!
//! A motion-blur [`Shutter`] spreads `n` samples over an interval around a frame given in frames,
//! e.g. `(−0.5, 0.5)` (a 180° shutter centred on the frame) or `(−0.25, 0.25)`.

use std::fmt;

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::error::CacheError;
use crate::layout::Frame;
use crate::reader::CacheReader;

/// How positions between two cached frames are computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Interpolation {
    /// Cubic Hermite with the stored velocities (the default): smooth, exact for cubic motion.
    #[default]
    Hermite,
    /// Linear blend of the two frames' positions (and velocities): exact for linear motion.
    Linear,
}

impl fmt::Display for Interpolation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Interpolation::Hermite => "hermite",
            Interpolation::Linear => "linear",
        })
    }
}

/// Positions and velocities of the strand points at one time.
#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    /// Time of the sample, s.
    pub time: f64,
    /// Point positions, m, in layout order.
    pub positions: Vec<Vector3<f32>>,
    /// Point velocities, m/s, in layout order: the Hermite curve's derivative, or the linear
    /// blend of the stored velocities.
    pub velocities: Vec<Vector3<f32>>,
}

impl From<Frame> for Sample {
    fn from(frame: Frame) -> Self {
        Self {
            time: frame.time,
            positions: frame.positions,
            velocities: frame.velocities,
        }
    }
}

/// Interpolates between frames `a` and `b` (`a.time < b.time`, same point count) at `time`
/// (s), which is clamped to `[a.time, b.time]`. Returns `a`'s or `b`'s own values, bit for bit,
/// when `time` equals its time.
pub fn interpolate(a: &Frame, b: &Frame, time: f64, interpolation: Interpolation) -> Sample {
    if time <= a.time {
        return Sample::from(a.clone());
    }
    if time >= b.time {
        return Sample::from(b.clone());
    }
    let h = b.time - a.time;
    let s = (time - a.time) / h;
    let to64 = |v: &Vector3<f32>| v.cast::<f64>();
    let to32 = |v: Vector3<f64>| v.cast::<f32>();
    let points = a.positions.len().min(b.positions.len());
    let mut positions = Vec::with_capacity(points);
    let mut velocities = Vec::with_capacity(points);
    match interpolation {
        Interpolation::Hermite => {
            let (s2, s3) = (s * s, s * s * s);
            let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
            let h10 = (s3 - 2.0 * s2 + s) * h;
            let h01 = -2.0 * s3 + 3.0 * s2;
            let h11 = (s3 - s2) * h;
            // Derivatives with respect to time.
            let d00 = (6.0 * s2 - 6.0 * s) / h;
            let d10 = 3.0 * s2 - 4.0 * s + 1.0;
            let d01 = (-6.0 * s2 + 6.0 * s) / h;
            let d11 = 3.0 * s2 - 2.0 * s;
            for i in 0..points {
                let (p0, v0) = (to64(&a.positions[i]), to64(&a.velocities[i]));
                let (p1, v1) = (to64(&b.positions[i]), to64(&b.velocities[i]));
                positions.push(to32(p0 * h00 + v0 * h10 + p1 * h01 + v1 * h11));
                velocities.push(to32(p0 * d00 + v0 * d10 + p1 * d01 + v1 * d11));
            }
        }
        Interpolation::Linear => {
            for i in 0..points {
                let (p0, v0) = (to64(&a.positions[i]), to64(&a.velocities[i]));
                let (p1, v1) = (to64(&b.positions[i]), to64(&b.velocities[i]));
                positions.push(to32(p0 + (p1 - p0) * s));
                velocities.push(to32(v0 + (v1 - v0) * s));
            }
        }
    }
    Sample {
        time,
        positions,
        velocities,
    }
}

/// A shutter that is not a valid sample set.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum InvalidShutter {
    /// A bound is not finite.
    #[error(
        "invalid shutter: the interval ({open}, {close}) is not finite; give finite frame offsets \
         such as (-0.5, 0.5)"
    )]
    NotFinite {
        /// Shutter open, frames relative to the frame.
        open: f64,
        /// Shutter close, frames relative to the frame.
        close: f64,
    },
    /// The shutter opens after it closes.
    #[error(
        "invalid shutter: the shutter opens at {open} after it closes at {close}; give open ≤ \
         close"
    )]
    Reversed {
        /// Shutter open, frames relative to the frame.
        open: f64,
        /// Shutter close, frames relative to the frame.
        close: f64,
    },
    /// No sample is asked for.
    #[error("invalid shutter: 0 samples; ask for at least one sample")]
    NoSamples,
}

/// Motion-blur sample set: `samples` times over the shutter interval `[open, close]`, in frames
/// relative to a frame (e.g. `(−0.5, 0.5)`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Shutter {
    /// Shutter open, frames relative to the frame (e.g. −0.5).
    pub open: f64,
    /// Shutter close, frames relative to the frame (e.g. 0.5); ≥ `open`.
    pub close: f64,
    /// Number of samples, ≥ 1.
    pub samples: usize,
}

impl Shutter {
    /// A shutter over `[open, close]` frames with `samples` samples. Refuses non-finite bounds,
    /// `open > close` and `samples == 0`.
    pub fn new(open: f64, close: f64, samples: usize) -> Result<Self, InvalidShutter> {
        if !(open.is_finite() && close.is_finite()) {
            return Err(InvalidShutter::NotFinite { open, close });
        }
        if open > close {
            return Err(InvalidShutter::Reversed { open, close });
        }
        if samples == 0 {
            return Err(InvalidShutter::NoSamples);
        }
        Ok(Self {
            open,
            close,
            samples,
        })
    }

    /// Sample offsets in frames: evenly spaced from `open` to `close` (both included) for two or
    /// more samples, the centre `(open + close) / 2` for one.
    pub fn offsets(&self) -> Vec<f64> {
        match self.samples {
            0 => Vec::new(),
            1 => vec![0.5 * (self.open + self.close)],
            n => (0..n)
                .map(|i| {
                    if i + 1 == n {
                        self.close
                    } else {
                        self.open + (self.close - self.open) * i as f64 / (n - 1) as f64
                    }
                })
                .collect(),
        }
    }

    /// Sample times around frame `frame` at `fps` frames per second, s: `(frame + offset) / fps`
    /// (an offset of 0 gives exactly the frame's time).
    pub fn times(&self, frame: u32, fps: f64) -> Vec<f64> {
        self.offsets()
            .into_iter()
            .map(|o| (f64::from(frame) + o) / fps)
            .collect()
    }
}

impl CacheReader {
    /// Positions and velocities at `time` (s) between the cached frames around it (see the
    /// [module](self)). At a frame time the sample is that frame, bit for bit; outside the
    /// cached range it is a [`CacheError::TimeOutOfRange`].
    pub fn sample(
        &mut self,
        time: f64,
        interpolation: Interpolation,
    ) -> Result<Sample, CacheError> {
        let (a, b) = self.frames_around(time)?;
        let first = self.read_frame(a)?;
        if a == b {
            return Ok(Sample::from(first));
        }
        let second = self.read_frame(b)?;
        Ok(interpolate(&first, &second, time, interpolation))
    }

    /// The motion-blur samples of frame `frame` ([`Shutter::times`]), in increasing time. Fails
    /// with [`CacheError::TimeOutOfRange`] if a sample time lies outside the cached range.
    pub fn sample_shutter(
        &mut self,
        frame: u32,
        shutter: &Shutter,
        interpolation: Interpolation,
    ) -> Result<Vec<Sample>, CacheError> {
        let times = shutter.times(frame, self.header().fps);
        // Check every time first, so nothing is read for a set that cannot be completed.
        for &t in &times {
            self.frames_around(t)?;
        }
        times
            .into_iter()
            .map(|t| self.sample(t, interpolation))
            .collect()
    }
}
