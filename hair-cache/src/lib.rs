//! # hair-cache
//!
//! The MCAP point cache of hairsys: one file per simulation run, holding the run's settings, the
//! strand layout and one message per frame (positions in m, velocities in m/s). The byte format
//! is specified in [`layout`]; [`CacheWriter`] writes a run crash-safely (into `<path>.partial`,
//! renamed when finished) and [`CacheReader`] reads any frame through the file's index, by frame
//! number or time, and samples between frames ([`sample`]: cubic Hermite or linear, motion-blur
//! [`Shutter`] sets). [`recover()`] reads the complete frames of a file whose writer was killed.
//!
//! Readers take only regular files (a directory, FIFO or device is refused by name before it is
//! opened) and trust no length in the file: every record is bounds-checked before it is parsed,
//! chunks are decompressed with output bounded by what their bytes decode to and CRC-checked
//! before the records inside them are used, so memory follows the file, never a damaged header
//! (see `src/records.rs`; fuzzed by `tests/fuzz.rs`, crashes kept in `tests/regressions/`).
//!
//! ```
//! use hair_cache::{CacheHeader, CacheLayout, CacheReader, CacheWriter, WriterOptions};
//! use nalgebra::Vector3;
//!
//! # let dir = std::env::temp_dir().join(format!("hair-cache-doc-{}", std::process::id()));
//! # std::fs::create_dir_all(&dir).unwrap();
//! let path = dir.join("run.mcap");
//! // One strand of three points.
//! let layout = CacheLayout { offsets: vec![0, 3], rest_lengths: vec![0.1, 0.1], radii: vec![1e-3; 3] };
//! let header = CacheHeader { fps: 24.0, scene_hash: "0a1b".into(), ..Default::default() };
//! let mut writer = CacheWriter::create(&path, &header, &layout, WriterOptions::default()).unwrap();
//! let x = vec![Vector3::new(0.0, 0.0, 0.0), Vector3::new(0.0, 0.0, -0.1), Vector3::new(0.0, 0.0, -0.2)];
//! let v = vec![Vector3::zeros(); 3];
//! writer.write_frame(0, &x, &v).unwrap();
//! writer.write_frame(1, &x, &v).unwrap();
//! let summary = writer.finish().unwrap();
//! assert_eq!(summary.frames, 2);
//!
//! let mut reader = CacheReader::open(&path).unwrap();
//! assert_eq!(reader.frame_numbers(), &[0, 1]);
//! let frame = reader.read_frame(1).unwrap();
//! assert_eq!((frame.time, frame.positions), (1.0 / 24.0, x));
//! # std::fs::remove_dir_all(&dir).unwrap();
//! ```

#![warn(missing_docs)]

pub mod error;
pub mod foxglove;
mod input;
pub mod layout;
pub mod reader;
mod records;
pub mod recover;
pub mod rig;
pub mod sample;
pub mod summary;
mod summary_section;
pub mod writer;

pub use error::CacheError;
pub use layout::{CacheHeader, CacheLayout, Frame};
pub use reader::{summarize, CacheReader};
pub use recover::{recover, Recovery, RecoveryWarning};
pub use rig::{CacheRig, ColliderState, RigFrame, RigScalp};
pub use sample::{interpolate, Interpolation, Sample, Shutter};
pub use summary::CacheSummary;
pub use writer::{partial_path, CacheWriter, Compression, Precision, WriterOptions};
