//! Writing a cache: [`CacheWriter`] streams one frame at a time into `<path>.partial` and renames
//! it to `<path>` when [`CacheWriter::finish`] has written the summary and synced the file.
//!
//! # Crash safety
//!
//! The MCAP writer streams the open chunk into the file behind a placeholder chunk header and
//! completes that header when the chunk is closed; it never closes a chunk by itself here
//! (its own `chunk_size` is off). After each frame this writer checks how many bytes the open
//! chunk holds and, once that reaches [`WriterOptions::chunk_size`], closes it with
//! `mcap::Writer::flush` (which ends the chunk, writes its message index and flushes the
//! `BufWriter` to the operating system). A killed process therefore leaves every closed chunk,
//! and every frame in it, in the `.partial` file; only the frames of the open chunk (less than
//! `chunk_size` bytes, by default one frame of 64 KiB or more) are lost. Dropping the writer
//! without `finish` also closes the open chunk, but never writes a summary: a `.partial` file,
//! even renamed, is never taken for a complete cache.

use std::borrow::Cow;
use std::fmt;
use std::fs::{self, File};
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::error::CacheError;
use crate::foxglove::{self, FoxgloveOptions};
use crate::layout::{self, CacheHeader, CacheLayout};
use crate::rig::{self, CacheRig, RigFrame};
use crate::summary::{CacheSummary, SummaryInput};

/// Chunk compression of a cache.
///
/// Simulated hair is a poor fit for general-purpose compressors: f32 mantissas of moving points
/// look random, so on a swinging 100,000-point groom LZ4 saves about 1 % and Zstandard about 9 %,
/// while writing drops from 888 MiB/s (none) to 331 (LZ4) and 236 MiB/s (Zstandard)
/// (`cargo bench -p hair-cache --bench throughput`, BENCHMARKS.md). Hence the default is none;
/// LZ4 pays for still or slowly moving hair (it halves a cache of hair at rest).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Compression {
    /// Frames stored as they are (24 bytes per point-frame); the default.
    #[default]
    None,
    /// LZ4 frames: fast, but little gain on moving hair.
    Lz4,
    /// Zstandard at its default level, single-threaded (so files are byte-identical on every
    /// machine): smaller than LZ4, slower to write.
    Zstd,
}

impl Compression {
    /// The MCAP chunk compression string: `""`, `"lz4"` or `"zstd"`.
    pub fn mcap_name(self) -> &'static str {
        match self {
            Compression::None => "",
            Compression::Lz4 => "lz4",
            Compression::Zstd => "zstd",
        }
    }

    fn to_mcap(self) -> Option<mcap::Compression> {
        match self {
            Compression::None => None,
            Compression::Lz4 => Some(mcap::Compression::Lz4),
            Compression::Zstd => Some(mcap::Compression::Zstd),
        }
    }
}

impl fmt::Display for Compression {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Compression::None => "none",
            Compression::Lz4 => "lz4",
            Compression::Zstd => "zstd",
        })
    }
}

/// How frame positions and velocities are stored.
///
/// [`Precision::Quantized16`] is an opt-in, **lossy** mode: every coordinate is stored as a
/// `u16` over its frame's per-axis bounds ([quantized payload](crate::layout#quantized-frame-payload)),
/// 12 bytes per point-frame instead of 24, which no chunk compression reaches on moving hair
/// (Zstandard gives about 21.6). A decoded value is within half a quantization step of its axis,
/// `(max − min) / 131070` (plus the rounding to `f32`): 22.7 µm on a 2.97 m extent. Readers
/// decode both encodings into the same `f32` [`crate::Frame`]; samples between quantized frames
/// carry the error too. Do not resume a simulation from quantized frames if it must be
/// reproducible bit for bit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Precision {
    /// `f32` positions and velocities, exact (24 bytes per point-frame); the default.
    #[default]
    F32,
    /// `u16` positions and velocities over each frame's per-axis bounds (12 bytes per
    /// point-frame); lossy.
    Quantized16,
}

impl Precision {
    /// The frame channel's message encoding: [`layout::FRAME_MESSAGE_ENCODING`] or
    /// [`layout::FRAME_Q16_MESSAGE_ENCODING`].
    pub fn message_encoding(self) -> &'static str {
        match self {
            Precision::F32 => layout::FRAME_MESSAGE_ENCODING,
            Precision::Quantized16 => layout::FRAME_Q16_MESSAGE_ENCODING,
        }
    }

    /// The precision whose frame channel has message encoding `encoding`, if any.
    pub fn from_message_encoding(encoding: &str) -> Option<Self> {
        [Precision::F32, Precision::Quantized16]
            .into_iter()
            .find(|p| p.message_encoding() == encoding)
    }
}

impl fmt::Display for Precision {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Precision::F32 => "f32",
            Precision::Quantized16 => "quantized16",
        })
    }
}

/// How a [`CacheWriter`] lays frames out in chunks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct WriterOptions {
    /// Chunk compression. Default [`Compression::None`].
    pub compression: Compression,
    /// Target uncompressed chunk size, bytes. Frames go into the open chunk until it holds at
    /// least this many bytes; then the chunk is closed, indexed and flushed to the operating
    /// system. `0` puts every frame in its own chunk. Default 64 KiB ([`Self::DEFAULT_CHUNK_SIZE`]):
    /// frames of 2731 points or more get a chunk each; smaller ones are grouped so chunk
    /// overhead (about 170 bytes) stays under 0.3 %. Larger chunks lose more frames when a run is
    /// killed and make reading one frame decompress its neighbours.
    pub chunk_size: u64,
    /// Also write the Foxglove view channel ([`crate::foxglove`]), if given.
    pub foxglove: Option<FoxgloveOptions>,
    /// How positions and velocities are stored. Default [`Precision::F32`] (exact);
    /// [`Precision::Quantized16`] halves the frames, lossily.
    pub precision: Precision,
}

impl WriterOptions {
    /// Default [`WriterOptions::chunk_size`], bytes.
    pub const DEFAULT_CHUNK_SIZE: u64 = 64 * 1024;
}

impl Default for WriterOptions {
    fn default() -> Self {
        Self {
            compression: Compression::default(),
            chunk_size: Self::DEFAULT_CHUNK_SIZE,
            foxglove: None,
            precision: Precision::F32,
        }
    }
}

/// The file a cache at `path` is written to until it is finished: `<path>.partial`, in the same
/// directory. Fails if `path` has no file name.
pub fn partial_path(path: &Path) -> Result<PathBuf, CacheError> {
    let Some(name) = path.file_name() else {
        return Err(CacheError::InvalidInput {
            path: path.to_path_buf(),
            detail: "the path has no file name; give a file path such as `out/run.mcap`".into(),
        });
    };
    let mut partial = name.to_os_string();
    partial.push(".partial");
    Ok(path.with_file_name(partial))
}

/// Writes one simulation run into an MCAP cache, frame by frame. See the [module](self) for
/// what a killed or dropped writer leaves behind.
pub struct CacheWriter {
    /// Present until `finish` or `drop` takes it.
    mcap: Option<mcap::Writer<BufWriter<File>>>,
    path: PathBuf,
    partial: PathBuf,
    channel: Arc<mcap::Channel<'static>>,
    /// The Foxglove view channel, when enabled.
    view: Option<Arc<mcap::Channel<'static>>>,
    /// The rig channel and the rig it carries frames of, once [`CacheWriter::attach_rig`] wrote it.
    rig: Option<(Arc<mcap::Channel<'static>>, CacheRig)>,
    options: WriterOptions,
    layout: CacheLayout,
    fps: f64,
    first_frame: u32,
    frames: Vec<u32>,
    open_chunk_bytes: u64,
    payload: Vec<u8>,
}

impl CacheWriter {
    /// Creates `<path>.partial` (replacing an old one) and writes the header, the metadata
    /// record and the layout attachment to it. Fails at once, naming the file, if the header or
    /// layout is invalid or the file cannot be created (missing or unwritable directory).
    pub fn create(
        path: impl AsRef<Path>,
        header: &CacheHeader,
        layout: &CacheLayout,
        options: WriterOptions,
    ) -> Result<Self, CacheError> {
        let path = path.as_ref().to_path_buf();
        let invalid = |detail: String| CacheError::InvalidInput {
            path: path.clone(),
            detail,
        };
        header
            .validate()
            .map_err(|source| CacheError::InvalidHeader {
                path: path.clone(),
                source,
            })?;
        layout
            .validate()
            .map_err(|source| CacheError::InvalidLayout {
                path: path.clone(),
                source,
            })?;
        if path.is_dir() {
            return Err(invalid(
                "it is a directory; give a file path such as `out/run.mcap`".into(),
            ));
        }
        let partial = partial_path(&path)?;
        let file = lock_partial(&partial, &path)?;
        let write_err = |source| CacheError::Write {
            path: partial.clone(),
            source,
        };
        let mut mcap = mcap::WriteOptions::new()
            .profile(layout::PROFILE)
            .library(layout::LIBRARY)
            .compression(options.compression.to_mcap())
            // Chunks are closed by `write_frame`, never by the MCAP writer, so that every closed
            // chunk is also flushed to the operating system.
            .chunk_size(None)
            // zstd's multi-threaded output depends on its worker count: one thread keeps files
            // byte-identical across machines.
            .compression_threads(0)
            .create(BufWriter::new(file))
            .map_err(write_err)?;
        mcap.write_metadata(&mcap::records::Metadata {
            name: layout::METADATA_NAME.into(),
            metadata: header.to_metadata(layout),
        })
        .map_err(write_err)?;
        mcap.attach(&mcap::Attachment {
            log_time: 0,
            create_time: 0,
            name: layout::LAYOUT_ATTACHMENT_NAME.into(),
            media_type: layout::LAYOUT_MEDIA_TYPE.into(),
            data: Cow::Owned(layout.encode()),
        })
        .map_err(write_err)?;
        mcap.flush().map_err(write_err)?;
        let (schema_name, schema_text) = match options.precision {
            Precision::F32 => (layout::FRAME_SCHEMA_NAME, layout::FRAME_SCHEMA_TEXT),
            Precision::Quantized16 => {
                (layout::FRAME_Q16_SCHEMA_NAME, layout::FRAME_Q16_SCHEMA_TEXT)
            }
        };
        let schema = mcap::Schema {
            id: 1,
            name: schema_name.into(),
            encoding: layout::FRAME_SCHEMA_ENCODING.into(),
            data: Cow::Borrowed(schema_text.as_bytes()),
        };
        let channel = mcap::Channel {
            id: 1,
            topic: layout::FRAME_TOPIC.into(),
            schema: Some(Arc::new(schema)),
            message_encoding: options.precision.message_encoding().into(),
            metadata: Default::default(),
        };
        let view = options.foxglove.map(|_| {
            Arc::new(mcap::Channel {
                id: 2,
                topic: foxglove::SCENE_TOPIC.into(),
                schema: Some(Arc::new(mcap::Schema {
                    id: 2,
                    name: foxglove::SCENE_UPDATE_SCHEMA_NAME.into(),
                    encoding: "jsonschema".into(),
                    data: Cow::Borrowed(foxglove::SCENE_UPDATE_SCHEMA.as_bytes()),
                })),
                message_encoding: "json".into(),
                metadata: Default::default(),
            })
        });
        Ok(Self {
            mcap: Some(mcap),
            path,
            partial,
            channel: Arc::new(channel),
            view,
            rig: None,
            options,
            layout: layout.clone(),
            fps: header.fps,
            first_frame: header.first_frame,
            frames: Vec::new(),
            open_chunk_bytes: 0,
            payload: Vec::new(),
        })
    }

    /// The cache's final path (where [`CacheWriter::finish`] puts it).
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The file being written, `<path>.partial`.
    pub fn partial_path(&self) -> &Path {
        &self.partial
    }

    /// Number of frames written so far.
    pub fn frame_count(&self) -> usize {
        self.frames.len()
    }

    /// Whether a rig is attached ([`CacheWriter::attach_rig`]): every frame then takes its
    /// rig state.
    pub fn has_rig(&self) -> bool {
        self.rig.is_some()
    }

    /// Writes the [`rig`] of the cache (the attachment [`rig::RIG_ATTACHMENT_NAME`])
    /// and opens its channel; from then on every frame is written with its [`RigFrame`]
    /// ([`CacheWriter::write_frame_with_rig`]). Only before the first frame, once, and for a
    /// rig that matches the layout (one anchor per strand).
    pub fn attach_rig(&mut self, rig: &CacheRig) -> Result<(), CacheError> {
        let invalid = |detail: String| CacheError::InvalidInput {
            path: self.partial.clone(),
            detail,
        };
        if !self.frames.is_empty() || self.rig.is_some() {
            return Err(invalid(
                "the rig is attached once, before the first frame".into(),
            ));
        }
        rig.validate(&self.layout)
            .map_err(|source| CacheError::InvalidRig {
                path: self.partial.clone(),
                source,
            })?;
        let mcap = self
            .mcap
            .as_mut()
            .expect("the MCAP writer is present until finish or drop");
        mcap.attach(&mcap::Attachment {
            log_time: 0,
            create_time: 0,
            name: rig::RIG_ATTACHMENT_NAME.into(),
            media_type: layout::LAYOUT_MEDIA_TYPE.into(),
            data: Cow::Owned(rig.encode()),
        })
        .map_err(|source| CacheError::Write {
            path: self.partial.clone(),
            source,
        })?;
        let channel = mcap::Channel {
            id: 3,
            topic: rig::RIG_TOPIC.into(),
            schema: Some(Arc::new(mcap::Schema {
                id: 3,
                name: rig::RIG_SCHEMA_NAME.into(),
                encoding: layout::FRAME_SCHEMA_ENCODING.into(),
                data: Cow::Borrowed(rig::RIG_SCHEMA_TEXT.as_bytes()),
            })),
            message_encoding: rig::RIG_MESSAGE_ENCODING.into(),
            metadata: Default::default(),
        };
        self.rig = Some((Arc::new(channel), rig.clone()));
        Ok(())
    }

    /// Appends frame `frame` (at `frame / fps` seconds): `positions` in m and `velocities` in
    /// m/s, world space, one per layout point. Frame numbers must increase strictly, starting at
    /// or after the header's `first_frame`. A frame with a wrong point count, a NaN or infinite
    /// value, or out of order is refused and nothing is written; the writer stays usable. A
    /// cache with a rig takes its frames through [`CacheWriter::write_frame_with_rig`].
    pub fn write_frame(
        &mut self,
        frame: u32,
        positions: &[Vector3<f32>],
        velocities: &[Vector3<f32>],
    ) -> Result<(), CacheError> {
        self.write(frame, positions, velocities, None)
    }

    /// Appends frame `frame` as [`CacheWriter::write_frame`] does, with the rig's state at the
    /// frame (checked against the attached rig; nothing is written if it does not match).
    pub fn write_frame_with_rig(
        &mut self,
        frame: u32,
        positions: &[Vector3<f32>],
        velocities: &[Vector3<f32>],
        rig_frame: &RigFrame,
    ) -> Result<(), CacheError> {
        self.write(frame, positions, velocities, Some(rig_frame))
    }

    fn write(
        &mut self,
        frame: u32,
        positions: &[Vector3<f32>],
        velocities: &[Vector3<f32>],
        rig_frame: Option<&RigFrame>,
    ) -> Result<(), CacheError> {
        let invalid = |detail: String| CacheError::InvalidInput {
            path: self.partial.clone(),
            detail,
        };
        match (&self.rig, rig_frame) {
            (Some((_, rig)), Some(state)) => {
                state
                    .validate(rig)
                    .map_err(|source| CacheError::InvalidRigFrame {
                        path: self.partial.clone(),
                        frame,
                        source,
                    })?
            }
            (Some(_), None) => {
                return Err(invalid(format!(
                    "frame {frame} has no rig state, but the cache has a rig: write it with \
                     write_frame_with_rig"
                )))
            }
            (None, Some(_)) => {
                return Err(invalid(format!(
                    "frame {frame} has a rig state, but no rig is attached: attach_rig first"
                )))
            }
            (None, None) => {}
        }
        let expected = self.layout.point_count();
        if positions.len() != expected || velocities.len() != expected {
            return Err(CacheError::PointCount {
                path: self.partial.clone(),
                frame,
                positions: positions.len(),
                velocities: velocities.len(),
                expected,
            });
        }
        for (quantity, values) in [("position", positions), ("velocity", velocities)] {
            if let Some(point) = values.iter().position(|v| !v.iter().all(|c| c.is_finite())) {
                return Err(CacheError::NonFinite {
                    path: self.partial.clone(),
                    frame,
                    quantity,
                    point,
                    strand: self.layout.strand_of(point).unwrap_or(0),
                });
            }
        }
        let min = match self.frames.last() {
            Some(&last) => last.saturating_add(1),
            None => self.first_frame,
        };
        if frame < min || self.frames.last() == Some(&u32::MAX) {
            return Err(CacheError::FrameOrder {
                path: self.partial.clone(),
                frame,
                min,
            });
        }
        let Some(time_ns) = layout::frame_time_ns(frame, self.fps) else {
            return Err(CacheError::FrameTime {
                path: self.partial.clone(),
                frame,
                fps: self.fps,
            });
        };
        let encode = match self.options.precision {
            Precision::F32 => layout::encode_frame,
            Precision::Quantized16 => layout::encode_frame_q16,
        };
        encode(
            &mut self.payload,
            frame,
            layout::frame_time_s(frame, self.fps),
            positions,
            velocities,
        );
        let mcap = self
            .mcap
            .as_mut()
            .expect("the MCAP writer is present until finish or drop");
        let write_err = |source| CacheError::Write {
            path: self.partial.clone(),
            source,
        };
        mcap.write(&mcap::Message {
            channel: self.channel.clone(),
            sequence: frame,
            log_time: time_ns,
            publish_time: time_ns,
            data: Cow::Borrowed(&self.payload),
        })
        .map_err(write_err)?;
        self.open_chunk_bytes += self.payload.len() as u64;
        if let (Some((channel, _)), Some(state)) = (&self.rig, rig_frame) {
            let data = state.encode(frame);
            mcap.write(&mcap::Message {
                channel: channel.clone(),
                sequence: frame,
                log_time: time_ns,
                publish_time: time_ns,
                data: Cow::Borrowed(&data),
            })
            .map_err(write_err)?;
            self.open_chunk_bytes += data.len() as u64;
        }
        if let (Some(view), Some(opts)) = (&self.view, &self.options.foxglove) {
            let json = foxglove::scene_update(&self.layout, positions, time_ns, opts);
            mcap.write(&mcap::Message {
                channel: view.clone(),
                sequence: frame,
                log_time: time_ns,
                publish_time: time_ns,
                data: Cow::Borrowed(&json),
            })
            .map_err(write_err)?;
            self.open_chunk_bytes += json.len() as u64;
        }
        self.frames.push(frame);
        if self.open_chunk_bytes >= self.options.chunk_size {
            mcap.flush().map_err(write_err)?;
            self.open_chunk_bytes = 0;
        }
        Ok(())
    }

    /// Closes the last chunk, writes the summary section, flushes and syncs the file, renames
    /// `<path>.partial` to `<path>` (replacing an old cache there) and syncs the directory.
    /// Returns the cache's [`CacheSummary`]. On error the `.partial` file stays.
    pub fn finish(mut self) -> Result<CacheSummary, CacheError> {
        let mut mcap = self
            .mcap
            .take()
            .expect("the MCAP writer is present until finish or drop");
        let partial = self.partial.clone();
        let io = |action, source| CacheError::Io {
            path: partial.clone(),
            action,
            source,
        };
        mcap.finish().map_err(|source| CacheError::Write {
            path: partial.clone(),
            source,
        })?;
        let file = mcap
            .into_inner()
            .into_inner()
            .map_err(|e| io("flush", e.into_error()))?;
        file.sync_all().map_err(|e| io("sync", e))?;
        // Renamed while still locked, so no second writer can take the `.partial` in between;
        // the lock goes with the file, released when it is closed just after.
        fs::rename(&self.partial, &self.path).map_err(|e| CacheError::Io {
            path: self.path.clone(),
            action: "rename the finished `.partial` file to",
            source: e,
        })?;
        drop(file);
        let _ = fs::remove_file(pid_path(&self.partial));
        sync_parent_dir(&self.path)?;
        let bytes = fs::metadata(&self.path)
            .map_err(|e| CacheError::Io {
                path: self.path.clone(),
                action: "read the size of",
                source: e,
            })?
            .len();
        let compression = if self.frames.is_empty() {
            "none".to_string()
        } else {
            self.options.compression.to_string()
        };
        Ok(CacheSummary::new(SummaryInput {
            path: self.path.display().to_string(),
            frames: &self.frames,
            fps: self.fps,
            strands: self.layout.strand_count(),
            points: self.layout.point_count(),
            bytes,
            compression,
        }))
    }
}

/// The sidecar `<partial>.pid` holding the process id of the writer that locks `<partial>`: for
/// the message a second writer gets, never for the locking itself.
pub fn pid_path(partial: &Path) -> PathBuf {
    let mut name = partial.as_os_str().to_os_string();
    name.push(".pid");
    PathBuf::from(name)
}

/// Opens `partial` without truncating it and takes an exclusive lock on it (the operating
/// system's file lock, released when the file is closed — also when the process is killed, so a
/// killed run never blocks the next), then empties it and records this process's id beside it.
/// A `.partial` locked by another writer is refused with that writer's process id.
fn lock_partial(partial: &Path, path: &Path) -> Result<File, CacheError> {
    let create = |source| CacheError::Create {
        partial: partial.to_path_buf(),
        path: path.to_path_buf(),
        source,
    };
    let file = fs::OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .open(partial)
        .map_err(create)?;
    match file.try_lock() {
        Ok(()) => {}
        Err(fs::TryLockError::WouldBlock) => {
            let holder = fs::read_to_string(pid_path(partial))
                .ok()
                .map(|p| p.trim().to_string())
                .filter(|p| !p.is_empty())
                .map_or("another process".to_string(), |p| format!("process {p}"));
            return Err(CacheError::Locked {
                partial: partial.to_path_buf(),
                holder,
            });
        }
        Err(fs::TryLockError::Error(e)) => return Err(create(e)),
    }
    file.set_len(0).map_err(create)?;
    // The id is only for the message above; failing to write it does not stop the run.
    let _ = fs::write(pid_path(partial), format!("{}\n", std::process::id()));
    Ok(file)
}

impl Drop for CacheWriter {
    /// Without `finish`: closes the open chunk so its frames reach the file, and leaves
    /// `<path>.partial` without a summary. Errors cannot be reported here and are ignored.
    fn drop(&mut self) {
        if let Some(mut mcap) = self.mcap.take() {
            let _ = mcap.flush();
            // `into_inner` does not write the summary, unlike dropping the MCAP writer.
            drop(mcap.into_inner());
            let _ = fs::remove_file(pid_path(&self.partial));
        }
    }
}

/// Makes the rename of a finished cache durable (on Unix, where directories can be synced).
fn sync_parent_dir(path: &Path) -> Result<(), CacheError> {
    #[cfg(unix)]
    {
        let dir = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        File::open(dir)
            .and_then(|d| d.sync_all())
            .map_err(|source| CacheError::Io {
                path: dir.to_path_buf(),
                action: "sync the directory",
                source,
            })?;
    }
    #[cfg(not(unix))]
    let _ = path;
    Ok(())
}
