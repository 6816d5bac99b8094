//! What `hairsys cache info` shows: a [`CacheSummary`] of a finished cache.

use std::fmt;

use serde::Serialize;

/// Figures of a finished cache. `Display` prints it for people, `Serialize` for `--json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CacheSummary {
    /// Path of the cache file.
    pub path: String,
    /// Number of frames stored.
    pub frames: usize,
    /// Frame number of the first stored frame (`None` without frames).
    pub first_frame: Option<u32>,
    /// Frame number of the last stored frame (`None` without frames).
    pub last_frame: Option<u32>,
    /// Time of the first stored frame, s (`None` without frames).
    pub start_time: Option<f64>,
    /// Time of the last stored frame, s (`None` without frames).
    pub end_time: Option<f64>,
    /// Frames per second of the run.
    pub fps: f64,
    /// Number of strands.
    pub strands: usize,
    /// Number of points (all strands).
    pub points: usize,
    /// Size of the file on disk, bytes.
    pub bytes: u64,
    /// File size divided by points × frames, bytes (`None` without frames or points); raw
    /// positions and velocities take 24.
    pub bytes_per_point_frame: Option<f64>,
    /// Chunk compression: `none`, `lz4`, `zstd` (several joined with `+`).
    pub compression: String,
}

/// Inputs of [`CacheSummary::new`] that come from the file's contents.
pub(crate) struct SummaryInput<'a> {
    pub path: String,
    pub frames: &'a [u32],
    pub fps: f64,
    pub strands: usize,
    pub points: usize,
    pub bytes: u64,
    pub compression: String,
}

impl CacheSummary {
    /// Summary of a cache holding frames `input.frames` (increasing).
    pub(crate) fn new(input: SummaryInput<'_>) -> Self {
        let first_frame = input.frames.first().copied();
        let last_frame = input.frames.last().copied();
        let point_frames = input.points as f64 * input.frames.len() as f64;
        Self {
            path: input.path,
            frames: input.frames.len(),
            first_frame,
            last_frame,
            start_time: first_frame.map(|f| crate::layout::frame_time_s(f, input.fps)),
            end_time: last_frame.map(|f| crate::layout::frame_time_s(f, input.fps)),
            fps: input.fps,
            strands: input.strands,
            points: input.points,
            bytes: input.bytes,
            bytes_per_point_frame: (point_frames > 0.0).then(|| input.bytes as f64 / point_frames),
            compression: input.compression,
        }
    }
}

impl fmt::Display for CacheSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "cache        {}", self.path)?;
        match (
            self.first_frame,
            self.last_frame,
            self.start_time,
            self.end_time,
        ) {
            (Some(first), Some(last), Some(t0), Some(t1)) => writeln!(
                f,
                "frames       {} (frames {first}–{last}, {t0:.4} s – {t1:.4} s at {} fps)",
                self.frames, self.fps
            )?,
            _ => writeln!(f, "frames       0 (at {} fps)", self.fps)?,
        }
        writeln!(f, "strands      {} ({} points)", self.strands, self.points)?;
        write!(f, "size         {} on disk", human_bytes(self.bytes))?;
        if let Some(b) = self.bytes_per_point_frame {
            write!(f, ", {b:.2} bytes per point-frame (raw: 24)")?;
        }
        write!(f, "\ncompression  {}", self.compression)
    }
}

/// `bytes` with a binary unit (B, KiB, MiB, GiB, TiB).
fn human_bytes(bytes: u64) -> String {
    const UNITS: [&str; 5] = ["B", "KiB", "MiB", "GiB", "TiB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{bytes} B")
    } else {
        format!("{value:.1} {} ({bytes} bytes)", UNITS[unit])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_names_frames_size_and_compression() {
        let s = CacheSummary::new(SummaryInput {
            path: "run.mcap".into(),
            frames: &[1, 2, 3],
            fps: 24.0,
            strands: 2,
            points: 10,
            bytes: 3 * 1024,
            compression: "lz4".into(),
        });
        let text = s.to_string();
        assert!(text.contains("frames       3 (frames 1–3"), "{text}");
        assert!(text.contains("3.0 KiB"), "{text}");
        assert!(text.contains("102.40 bytes per point-frame"), "{text}");
        assert!(text.contains("lz4"), "{text}");
        let json = serde_json::to_value(&s).unwrap();
        assert_eq!(json["frames"], 3);
        assert_eq!(json["compression"], "lz4");
    }
}
