//! Recovering the frames of a cache whose writer was killed (or dropped) before finishing.
//!
//! Such a file (normally `<path>.partial`) has no summary section, so [`recover`] walks its
//! records from the start: the header, the `hairsys` metadata, the layout attachment, then the
//! chunks, one record at a time. Every chunk whose record is complete and whose CRC checks is a
//! self-contained set of frames (see [`crate::writer`]): its frames are returned. The walk stops at the first record
//! that runs past the end of the file (the chunk the writer had open, or a cut file); a complete
//! chunk that fails its checks is skipped. What was lost is described by [`Recovery::warning`].
//! A finished cache is recovered too (its summary is not needed).

use std::fmt;
use std::io::{BufReader, Read};
use std::path::{Path, PathBuf};

use mcap::records::{op, Record};
use thiserror::Error;

use crate::error::CacheError;
use crate::input;
use crate::layout::{self, CacheHeader, CacheLayout, FormatError, Frame, MetadataError};
use crate::reader::{attachment_data, damaged};
use crate::records::{self, RecordError, Records};
use crate::rig::{self, CacheRig, RigError, RigFrame};
use crate::summary::CacheSummary;
use crate::writer::{CacheWriter, Precision, WriterOptions};

/// The frames recovered from a cache file, and what was lost.
#[derive(Debug, Clone)]
pub struct Recovery {
    /// The file read.
    pub path: PathBuf,
    /// The run's settings, from the metadata record.
    pub header: CacheHeader,
    /// The strand layout, from the layout attachment.
    pub layout: CacheLayout,
    /// Every frame of every complete chunk, in file order (increasing frame numbers), decoded
    /// to `f32` whatever their precision.
    pub frames: Vec<Frame>,
    /// The cache's rig ([`crate::rig`]), if it has one.
    pub rig: Option<CacheRig>,
    /// With a rig: the rig's state at each of `frames`, in the same order (empty without).
    pub rig_frames: Vec<RigFrame>,
    /// How the frames were stored (from the frame channel's message encoding);
    /// [`Precision::F32`] when no chunk declared the frame channel. Pass it in the
    /// [`WriterOptions`] of [`Recovery::write`] or of a resumed run to keep the file's precision.
    pub precision: Precision,
    /// What was lost; `None` when every chunk of the file was complete (only the summary was
    /// missing, or the file was finished).
    pub warning: Option<RecoveryWarning>,
}

/// What [`recover`] could not read.
#[derive(Debug, Clone, PartialEq)]
pub struct RecoveryWarning {
    /// Frames recovered, in words (`"frames 1–37"`, `"no frame"`).
    pub recovered: String,
    /// The last frame recovered, if any.
    pub last_frame: Option<u32>,
    /// Each loss, in words, in file order.
    pub losses: Vec<String>,
    /// Bytes of the file that held no recovered record (incomplete or damaged records).
    pub lost_bytes: u64,
}

impl fmt::Display for RecoveryWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} recovered; {}",
            self.recovered,
            self.losses.join("; ")
        )
    }
}

impl Recovery {
    /// Frame numbers recovered, increasing.
    pub fn frame_numbers(&self) -> Vec<u32> {
        self.frames.iter().map(|f| f.frame).collect()
    }

    /// Writes the recovered frames into a new, finished cache at `path` (through
    /// `<path>.partial`, like any run) and returns its summary.
    pub fn write(
        &self,
        path: impl AsRef<Path>,
        options: WriterOptions,
    ) -> Result<CacheSummary, CacheError> {
        let mut writer = CacheWriter::create(path, &self.header, &self.layout, options)?;
        self.write_into(&mut writer)?;
        writer.finish()
    }

    /// Writes the recovered rig and frames into `writer` (a new cache, no frame written yet).
    fn write_into(&self, writer: &mut CacheWriter) -> Result<(), CacheError> {
        match &self.rig {
            Some(rig) => {
                writer.attach_rig(rig)?;
                for (frame, state) in self.frames.iter().zip(&self.rig_frames) {
                    writer.write_frame_with_rig(
                        frame.frame,
                        &frame.positions,
                        &frame.velocities,
                        state,
                    )?;
                }
            }
            None => {
                for frame in &self.frames {
                    writer.write_frame(frame.frame, &frame.positions, &frame.velocities)?;
                }
            }
        }
        Ok(())
    }
}

/// Reads every frame of the complete chunks of the cache file at `path` (a `.partial` file
/// left by a killed or dropped writer, or any cache). Fails, naming the file, if it is not a
/// regular file, cannot be read, is not MCAP, or ends before its metadata and layout attachment
/// are complete (then no frame can be interpreted).
///
/// The file is read one record at a time: memory holds the largest record (a record longer than
/// the rest of the file is the incomplete end, never allocated) plus the frames recovered.
pub fn recover(path: impl AsRef<Path>) -> Result<Recovery, CacheError> {
    let path = path.as_ref().to_path_buf();
    let (file, file_len) = input::open_regular(&path)?;
    let mut file = BufReader::new(file);
    let io = |source| CacheError::Io {
        path: path.clone(),
        action: "read",
        source,
    };
    let mut magic = [0u8; 8];
    if file_len < magic.len() as u64
        || file.read_exact(&mut magic).is_err()
        || magic != *mcap::MAGIC
    {
        return Err(CacheError::NotMcap {
            path,
            detail: if file_len < magic.len() as u64 {
                format!("it has only {file_len} bytes")
            } else {
                "it does not start with the MCAP magic bytes".into()
            },
        });
    }
    let mut header: Option<CacheHeader> = None;
    let mut counts = None;
    let mut cache_layout: Option<CacheLayout> = None;
    let mut frame_channel: Option<(u16, Precision)> = None;
    let mut frames: Vec<Frame> = Vec::new();
    let mut rig: Option<CacheRig> = None;
    let mut rig_channel: Option<u16> = None;
    let mut rig_frames: Vec<RigFrame> = Vec::new();
    let mut losses = Vec::new();
    let mut lost_bytes = 0u64;
    let mut pos = magic.len() as u64;
    let mut body = Vec::new();
    let after = |frames: &[Frame]| match frames.last() {
        Some(f) => format!("after frame {}", f.frame),
        None => "before the first frame".to_string(),
    };
    let incomplete_start = |detail: String| CacheError::Incomplete {
        path: path.clone(),
        detail: format!("{detail}, so none of its frames can be read"),
    };
    while pos < file_len {
        let rest = file_len - pos;
        // Opcode and length; `rest >= 1`.
        let mut head = [0u8; 9];
        let head_len = rest.min(9) as usize;
        file.read_exact(&mut head[..head_len]).map_err(io)?;
        let len = u64::from_le_bytes(head[1..9].try_into().unwrap_or([0; 8]));
        // A length beyond the rest of the file is the incomplete end, never allocated.
        let complete = (rest >= 9 && len <= rest - 9).then_some(len);
        let Some(len) = complete else {
            if cache_layout.is_none() {
                return Err(incomplete_start(format!(
                    "it ends inside its header, metadata or layout attachment (at byte \
                     {file_len})"
                )));
            }
            let what = if head[0] == op::CHUNK {
                "chunk"
            } else {
                "record"
            };
            losses.push(format!(
                "the {what} {} was incomplete ({rest} bytes) and is lost",
                after(&frames),
            ));
            lost_bytes += rest;
            break;
        };
        let opcode = head[0];
        // `len` fits in the file, hence in memory's address space.
        body.resize(len as usize, 0);
        file.read_exact(&mut body).map_err(io)?;
        pos += 9 + len;
        match opcode {
            op::METADATA => {
                if let Ok(Record::Metadata(m)) = records::parse(op::METADATA, &body) {
                    if m.name == layout::METADATA_NAME {
                        let (h, c) =
                            layout::header_from_metadata(&m.metadata).map_err(|e| match e {
                                MetadataError::Version(found) => CacheError::Version {
                                    path: path.clone(),
                                    found,
                                    supported: layout::FORMAT_VERSION,
                                },
                                other => damaged(&path, other),
                            })?;
                        header = Some(h);
                        counts = Some(c);
                    }
                }
            }
            op::ATTACHMENT => {
                let Ok(Record::Attachment { header: a, .. }) =
                    records::parse(op::ATTACHMENT, &body)
                else {
                    continue;
                };
                if a.name == layout::LAYOUT_ATTACHMENT_NAME {
                    let data = attachment_data(&body).map_err(|e| damaged(&path, e))?;
                    let l = CacheLayout::decode(data)
                        .map_err(|e| damaged(&path, format!("strand layout: {e}")))?;
                    cache_layout = Some(l);
                } else if a.name == rig::RIG_ATTACHMENT_NAME {
                    let Some(l) = &cache_layout else {
                        return Err(damaged(&path, "its rig comes before its strand layout"));
                    };
                    let data = attachment_data(&body).map_err(|e| damaged(&path, e))?;
                    let r = CacheRig::decode(data, l)
                        .map_err(|e| damaged(&path, format!("rig: {e}")))?;
                    rig = Some(r);
                }
            }
            op::CHUNK => {
                let (Some(h), Some(l)) = (&header, &cache_layout) else {
                    return Err(CacheError::NotHairsys {
                        path,
                        detail: "it has no `hairsys` metadata record and `hairsys/layout.bin` \
                                 attachment before its first chunk"
                            .into(),
                    });
                };
                let channels = Channels {
                    frames: &mut frame_channel,
                    rig: rig.as_ref().map(|r| (r, &mut rig_channel)),
                };
                match chunk_frames(&body, h.fps, l.point_count(), channels) {
                    Ok((chunk, states)) => {
                        if let (Some(last), Some(first)) = (frames.last(), chunk.first()) {
                            if first.frame <= last.frame {
                                losses.push(format!(
                                    "a chunk {} holds frame {} out of order and was skipped",
                                    after(&frames),
                                    first.frame
                                ));
                                lost_bytes += 9 + len;
                                continue;
                            }
                        }
                        frames.extend(chunk);
                        rig_frames.extend(states);
                    }
                    Err(e) => {
                        losses.push(format!(
                            "the chunk {} is damaged ({e}, {} bytes) and is lost",
                            after(&frames),
                            9 + len
                        ));
                        lost_bytes += 9 + len;
                    }
                }
            }
            // The summary follows; every chunk has been seen.
            op::DATA_END | op::FOOTER => break,
            _ => {}
        }
    }
    let (Some(header), Some(cache_layout)) = (header, cache_layout) else {
        return Err(if pos >= file_len {
            incomplete_start(format!(
                "it ends (at byte {file_len}) before its metadata and layout attachment"
            ))
        } else {
            CacheError::NotHairsys {
                path,
                detail: "it has no `hairsys` metadata record or `hairsys/layout.bin` attachment"
                    .into(),
            }
        });
    };
    if let Some(c) = counts {
        if (c.strands, c.points) != (cache_layout.strand_count(), cache_layout.point_count()) {
            return Err(damaged(
                &path,
                format!(
                    "the metadata declares {} strands and {} points, the layout {} and {}",
                    c.strands,
                    c.points,
                    cache_layout.strand_count(),
                    cache_layout.point_count()
                ),
            ));
        }
    }
    let warning = (!losses.is_empty()).then(|| RecoveryWarning {
        recovered: frames_text(&frames),
        last_frame: frames.last().map(|f| f.frame),
        losses,
        lost_bytes,
    });
    Ok(Recovery {
        path,
        header,
        layout: cache_layout,
        frames,
        rig,
        rig_frames,
        precision: frame_channel.map_or(Precision::F32, |c| c.1),
        warning,
    })
}

/// The channels a chunk's messages are read from, as far as earlier chunks declared them.
struct Channels<'a> {
    /// The frame channel's id and precision (from its message encoding).
    frames: &'a mut Option<(u16, Precision)>,
    /// With a rig: the rig and its channel's id.
    rig: Option<(&'a CacheRig, &'a mut Option<u16>)>,
}

/// The frames of one chunk record body, CRC-checked and decoded, and with a rig each frame's
/// rig state (a frame without one fails the chunk).
fn chunk_frames(
    body: &[u8],
    fps: f64,
    points: usize,
    channels: Channels,
) -> Result<(Vec<Frame>, Vec<RigFrame>), ChunkError> {
    let Channels {
        frames: channel,
        rig,
    } = channels;
    let (rig, rig_channel) = match rig {
        Some((r, c)) => (Some(r), Some(c)),
        None => (None, None),
    };
    let mut chunk_rig_channel = rig_channel.as_deref().copied().flatten();
    let mut states: Vec<(u32, RigFrame)> = Vec::new();
    let (chunk_header, data) = match records::parse(op::CHUNK, body)? {
        Record::Chunk { header, data } => (header, data),
        _ => return Err(ChunkError::NotAChunk),
    };
    // Every length inside the chunk is used only after its CRC has checked.
    let content = records::chunk_content(&chunk_header, &data)?;
    // Nothing is kept unless the whole chunk reads.
    let mut chunk_channel = *channel;
    let mut frames = Vec::new();
    for record in Records::new(&content) {
        let (opcode, body) = record?;
        if !matches!(opcode, op::CHANNEL | op::MESSAGE) {
            continue;
        }
        match records::parse(opcode, body)? {
            Record::Channel(c) if c.topic == layout::FRAME_TOPIC => {
                let precision =
                    Precision::from_message_encoding(&c.message_encoding).ok_or_else(|| {
                        ChunkError::Encoding {
                            encoding: c.message_encoding.clone(),
                        }
                    })?;
                chunk_channel = Some((c.id, precision));
            }
            Record::Channel(c) if c.topic == rig::RIG_TOPIC => {
                chunk_rig_channel = Some(c.id);
            }
            Record::Message { header, data } if chunk_rig_channel == Some(header.channel_id) => {
                if let Some(rig) = rig {
                    states.push(RigFrame::decode(&data, rig)?);
                }
            }
            Record::Message { header, data }
                if chunk_channel.is_some_and(|c| c.0 == header.channel_id) =>
            {
                let precision = chunk_channel.map_or(Precision::F32, |c| c.1);
                let frame = layout::decode_frame_as(precision, &data, points)?;
                if layout::frame_time_ns(frame.frame, fps) != Some(header.log_time) {
                    return Err(ChunkError::Time {
                        frame: frame.frame,
                        log_time: header.log_time,
                    });
                }
                if frames
                    .last()
                    .is_some_and(|f: &Frame| f.frame >= frame.frame)
                {
                    return Err(ChunkError::Order { frame: frame.frame });
                }
                frames.push(frame);
            }
            _ => {}
        }
    }
    *channel = chunk_channel;
    let states = match (rig, rig_channel) {
        (Some(_), Some(slot)) => {
            *slot = chunk_rig_channel;
            let mut out = Vec::with_capacity(frames.len());
            for f in &frames {
                match states.iter().position(|(n, _)| *n == f.frame) {
                    Some(i) => out.push(states.swap_remove(i).1),
                    None => return Err(ChunkError::NoRigState { frame: f.frame }),
                }
            }
            out
        }
        _ => Vec::new(),
    };
    Ok((frames, states))
}

/// Frames in words: "frames 1–37", "3 frames between 1 and 9", "no frame".
/// Why a chunk of a `.partial` file cannot be recovered.
#[derive(Debug, Error)]
enum ChunkError {
    /// A record of the chunk, or the chunk itself, is damaged.
    #[error(transparent)]
    Record(#[from] RecordError),
    /// A frame payload breaks the format.
    #[error(transparent)]
    Frame(#[from] FormatError),
    /// A rig frame payload is refused.
    #[error(transparent)]
    Rig(#[from] RigError),
    /// The record is no chunk.
    #[error("not a chunk")]
    NotAChunk,
    /// The chunk's frame channel has an unknown message encoding.
    #[error(
        "the frame channel has message encoding {encoding:?}, expected {:?} or {:?}",
        layout::FRAME_MESSAGE_ENCODING,
        layout::FRAME_Q16_MESSAGE_ENCODING
    )]
    Encoding { encoding: String },
    /// A frame is logged at another time than its own (`log_time`, ns).
    #[error("frame {frame} is logged at {log_time} ns, not at its time")]
    Time { frame: u32, log_time: u64 },
    /// A frame does not come after the one before it.
    #[error("frame {frame} is out of order")]
    Order { frame: u32 },
    /// The cache has a rig but the chunk holds no rig state for a frame.
    #[error("frame {frame} has no rig state")]
    NoRigState { frame: u32 },
}

fn frames_text(frames: &[Frame]) -> String {
    match (frames.first(), frames.last()) {
        (Some(a), Some(b)) if frames.len() as u64 == u64::from(b.frame - a.frame) + 1 => {
            if a.frame == b.frame {
                format!("frame {}", a.frame)
            } else {
                format!("frames {}–{}", a.frame, b.frame)
            }
        }
        (Some(a), Some(b)) => format!(
            "{} frames between {} and {}",
            frames.len(),
            a.frame,
            b.frame
        ),
        _ => "no frame".into(),
    }
}
