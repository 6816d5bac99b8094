//! Typed errors of the cache. Every message names the file and says what to do about it, because
//! the `hairsys` command and DCC hosts show them as they are.

use std::io;
use std::path::PathBuf;

use thiserror::Error;

use crate::layout::FormatError;
use crate::rig::RigError;

/// Everything reading or writing a cache can refuse or detect.
#[derive(Debug, Error)]
pub enum CacheError {
    /// The `.partial` file of a new cache could not be created.
    #[error(
        "cannot create cache file `{}` (renamed to `{}` when the run finishes): {source}; check \
         that the directory exists and is writable, or choose another output path",
        .partial.display(), .path.display()
    )]
    Create {
        /// The file that could not be created (`<path>.partial`).
        partial: PathBuf,
        /// The cache's final path.
        path: PathBuf,
        /// What the operating system said.
        source: io::Error,
    },
    /// Another writer holds the lock on the `.partial` file: two runs on one cache path.
    #[error(
        "`{}` is being written by {holder}: one run writes a cache at a time; wait for it, \
         stop it, or choose another --cache path",
        .partial.display()
    )]
    Locked {
        /// The locked `.partial` file.
        partial: PathBuf,
        /// Who holds it: "process 1234", or "another process" when its id is unknown.
        holder: String,
    },
    /// The writer's inputs (header, layout, output path) are invalid; nothing was written.
    #[error("cannot write cache `{}`: {detail}", .path.display())]
    InvalidInput {
        /// The cache's path.
        path: PathBuf,
        /// What is wrong and what to use instead.
        detail: String,
    },
    /// The writer's header is invalid; nothing was written.
    #[error("cannot write cache `{}`: {source}", .path.display())]
    InvalidHeader {
        /// The cache's path.
        path: PathBuf,
        /// What is wrong with the header.
        source: FormatError,
    },
    /// The writer's strand layout is invalid; nothing was written.
    #[error("cannot write cache `{}`: invalid strand layout: {source}", .path.display())]
    InvalidLayout {
        /// The cache's path.
        path: PathBuf,
        /// What is wrong with the layout.
        source: FormatError,
    },
    /// The rig given to the writer does not match its layout; it was not attached.
    #[error("cannot write cache `{}`: invalid rig: {source}", .path.display())]
    InvalidRig {
        /// The file being written (`<path>.partial`).
        path: PathBuf,
        /// What is wrong with the rig.
        source: RigError,
    },
    /// A frame's rig state does not match the cache's rig; the frame was not written.
    #[error("cannot write cache `{}`: frame {frame}'s rig: {source}", .path.display())]
    InvalidRigFrame {
        /// The file being written (`<path>.partial`).
        path: PathBuf,
        /// The frame refused.
        frame: u32,
        /// What is wrong with its rig state.
        source: RigError,
    },
    /// A file operation failed.
    #[error(
        "cannot {action} `{}`: {source}; check the path, its permissions and the free disk space",
        .path.display()
    )]
    Io {
        /// The file concerned.
        path: PathBuf,
        /// What was being done ("open", "read", "sync", …).
        action: &'static str,
        /// What the operating system said.
        source: io::Error,
    },
    /// The MCAP writer failed (usually an I/O error underneath).
    #[error(
        "cannot write cache `{}`: {source}; check the free disk space and permissions, then re-run",
        .path.display()
    )]
    Write {
        /// The file being written (`<path>.partial`).
        path: PathBuf,
        /// The MCAP writer's error.
        source: mcap::McapError,
    },
    /// A frame's slices do not have one entry per point of the cache's layout.
    #[error(
        "frame {frame} for `{}` has {positions} positions and {velocities} velocities, but the \
         cache layout has {expected} points; write the frames of the strand set the cache was \
         created with",
        .path.display()
    )]
    PointCount {
        /// The file being written.
        path: PathBuf,
        /// The frame refused.
        frame: u32,
        /// Number of positions given.
        positions: usize,
        /// Number of velocities given.
        velocities: usize,
        /// Number of points of the layout.
        expected: usize,
    },
    /// A frame holds a NaN or infinite value; it was not written.
    #[error(
        "frame {frame} for `{}` has a non-finite {quantity} at point {point} (strand {strand}) \
         and was not written: the simulation diverged. Use more substeps (or substeps = \"auto\") \
         or lower the stiffness and re-run; the frames before it are kept",
        .path.display()
    )]
    NonFinite {
        /// The file being written.
        path: PathBuf,
        /// The frame refused.
        frame: u32,
        /// `"position"` or `"velocity"`.
        quantity: &'static str,
        /// Index of the first bad point.
        point: usize,
        /// Strand of that point.
        strand: usize,
    },
    /// Frames were written out of order.
    #[error(
        "frame {frame} for `{}` is out of order: the next frame must be ≥ {min} (frames increase \
         strictly and start at the header's first_frame); write frames in increasing order",
        .path.display()
    )]
    FrameOrder {
        /// The file being written.
        path: PathBuf,
        /// The frame refused.
        frame: u32,
        /// The smallest frame number accepted next.
        min: u32,
    },
    /// A frame's time does not fit the cache's time range.
    #[error(
        "frame {frame} for `{}` at {fps} fps is beyond the cache's time range of 2^53 ns \
         (about 104 days); use smaller frame numbers or a higher fps",
        .path.display()
    )]
    FrameTime {
        /// The file being written.
        path: PathBuf,
        /// The frame refused.
        frame: u32,
        /// The cache's frame rate, frames per second.
        fps: f64,
    },
    /// The path is not a regular file (a directory, a FIFO, a device such as `/dev/zero`); it
    /// was refused before anything was read from it.
    #[error(
        "`{}` is a {kind}, not a regular file; pass the path of a cache file written by \
         `hairsys simulate`",
        .path.display()
    )]
    NotAFile {
        /// The path given.
        path: PathBuf,
        /// What it is: "directory", "FIFO (named pipe)", "device", "socket" or "special file".
        kind: &'static str,
    },
    /// The file is not an MCAP file at all.
    #[error(
        "`{}` is not an MCAP file ({detail}); pass a cache written by `hairsys simulate`",
        .path.display()
    )]
    NotMcap {
        /// The file read.
        path: PathBuf,
        /// What was found instead.
        detail: String,
    },
    /// The file is a `.partial` cache: its writer has not finished.
    #[error(
        "`{}` is an unfinished cache: its writer was killed or is still running, and only a \
         finished run is renamed to `{}`. If the run is still going, wait for it; if it was \
         killed, continue it with `hairsys simulate SCENE --cache {} --resume`, or keep its \
         complete frames with `hairsys cache recover {} FIXED.mcap`",
        .path.display(), .finished.display(), .finished.display(), .path.display()
    )]
    Unfinished {
        /// The `.partial` file.
        path: PathBuf,
        /// The name the cache gets when its writer finishes.
        finished: PathBuf,
    },
    /// The file starts like an MCAP file but has no complete summary: truncated, or written by a
    /// killed process.
    #[error(
        "`{}` is incomplete ({detail}): it was truncated or its writer was killed before \
         finishing; re-run the simulation to rewrite it",
        .path.display()
    )]
    Incomplete {
        /// The file read.
        path: PathBuf,
        /// What is missing.
        detail: String,
    },
    /// The file is an MCAP file but not a hairsys cache.
    #[error(
        "`{}` is an MCAP file but not a hairsys cache ({detail}); pass a cache written by \
         `hairsys simulate`",
        .path.display()
    )]
    NotHairsys {
        /// The file read.
        path: PathBuf,
        /// What is missing.
        detail: String,
    },
    /// The cache was written in another format version.
    #[error(
        "`{}` has cache format version {found}, this hairsys reads version {supported}; read it \
         with the hairsys that wrote it, or re-run the simulation",
        .path.display()
    )]
    Version {
        /// The file read.
        path: PathBuf,
        /// The version found (as stored).
        found: String,
        /// The version this crate reads.
        supported: u32,
    },
    /// The file's records contradict each other or fail their checksums.
    #[error("`{}` is damaged: {detail}; re-run the simulation to rewrite it", .path.display())]
    Damaged {
        /// The file read.
        path: PathBuf,
        /// What is inconsistent.
        detail: String,
    },
    /// The requested frame is not in the cache.
    #[error(
        "`{}` has no frame {frame}; it holds {available}: pick one of those frames",
        .path.display()
    )]
    NoSuchFrame {
        /// The file read.
        path: PathBuf,
        /// The frame asked for.
        frame: u32,
        /// The frames it holds, in words ("frames 1–120", "no frame").
        available: String,
    },
    /// A time outside the cached frames was asked for.
    #[error(
        "`{}` holds no frame at or around frame {} ({time:.4} s): it holds {range}; pick a \
         frame in that range",
        .path.display(), short(*.frame)
    )]
    TimeOutOfRange {
        /// The file read.
        path: PathBuf,
        /// The time asked for, s.
        time: f64,
        /// The time asked for in frames (time × fps), possibly fractional.
        frame: f64,
        /// The cached range in words ("frames 1–120 (0.0417 s – 5.0000 s)", "no frame").
        range: String,
    },
}

/// A frame number in short form: whole frames without decimals, sub-frames to 3 decimals.
fn short(frame: f64) -> String {
    if frame.fract() == 0.0 && frame.abs() < 1e15 {
        format!("{frame:.0}")
    } else {
        format!("{frame:.3}")
    }
}
