//! Reading a finished cache: [`CacheReader`] reads the summary section, the metadata record, the
//! layout attachment and the message indexes when it opens a file, then reads any frame by
//! decompressing only the chunk that holds it.

use std::collections::BTreeSet;
use std::fmt;
use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use mcap::records::{op, Record};

use crate::error::CacheError;
use crate::input;
use crate::layout::{self, CacheHeader, CacheLayout, Frame, LeReader, MetadataError};
use crate::records::{self, RecordError, Records};
use crate::rig::{self, CacheRig, RigFrame};
use crate::summary::{CacheSummary, SummaryInput};
use crate::summary_section::{self, SummaryError, SummarySection};
use crate::writer::Precision;

/// The summary of the finished cache at `path` (what `hairsys cache info` prints).
pub fn summarize(path: impl AsRef<Path>) -> Result<CacheSummary, CacheError> {
    Ok(CacheReader::open(path)?.summary())
}

/// A message of a chunk: its `log_time` (ns) and payload.
pub(crate) type ChunkMessage = (u64, Vec<u8>);

/// An open cache file: its header, layout and frame list, and random access to its frames.
pub struct CacheReader {
    path: PathBuf,
    file: File,
    file_len: u64,
    summary: SummarySection,
    header: CacheHeader,
    layout: CacheLayout,
    /// Frame numbers stored, increasing.
    frames: Vec<u32>,
    /// For each entry of `frames`: the index in `summary.chunk_indexes` of the chunk holding it.
    frame_chunks: Vec<usize>,
    /// The last chunk decompressed: its index in `summary.chunk_indexes` and its frame messages
    /// (`log_time`, payload), so reading neighbouring frames decompresses it once.
    cached_chunk: Option<(usize, Vec<ChunkMessage>)>,
    /// Id of the frame channel (0 without frames).
    frame_channel: u16,
    /// The cache's rig, if it has one ([`crate::rig`]).
    rig: Option<CacheRig>,
    /// Id of the rig channel (0 without one), the frames it holds and their chunks.
    rig_channel: u16,
    rig_frames: Vec<u32>,
    rig_chunks: Vec<usize>,
    /// The last chunk read for a rig frame: its index and its rig messages.
    cached_rig_chunk: Option<(usize, Vec<ChunkMessage>)>,
    /// How the frames are stored, from the frame channel's message encoding.
    precision: Precision,
    compression: String,
    buf: Vec<u8>,
}

impl CacheReader {
    /// Opens the finished cache at `path` and reads its summary, metadata, layout and message
    /// indexes (not its frames). Refuses `.partial` files, files that are not MCAP, truncated
    /// files and MCAP files without the hairsys metadata, with an error naming the file.
    pub fn open(path: impl AsRef<Path>) -> Result<Self, CacheError> {
        let path = path.as_ref().to_path_buf();
        if let Some(finished) = path
            .file_name()
            .and_then(|n| n.to_str())
            .and_then(|n| n.strip_suffix(".partial"))
        {
            return Err(CacheError::Unfinished {
                finished: path.with_file_name(finished),
                path,
            });
        }
        let (mut file, file_len) = input::open_regular(&path)?;
        let mut magic = [0u8; 8];
        let n = read_up_to(&mut file, &mut magic).map_err(|source| CacheError::Io {
            path: path.clone(),
            action: "read",
            source,
        })?;
        if n < magic.len() || magic != mcap::MAGIC {
            return Err(CacheError::NotMcap {
                path,
                detail: if file_len < 8 {
                    format!("it has only {file_len} bytes")
                } else {
                    "it does not start with the MCAP magic bytes".into()
                },
            });
        }
        let summary = read_summary(&path, &mut file, file_len)?;
        let mut reader = Self {
            path,
            file,
            file_len,
            summary,
            header: CacheHeader::default(),
            layout: CacheLayout::default(),
            frames: Vec::new(),
            frame_chunks: Vec::new(),
            cached_chunk: None,
            frame_channel: 0,
            rig: None,
            rig_channel: 0,
            rig_frames: Vec::new(),
            rig_chunks: Vec::new(),
            cached_rig_chunk: None,
            precision: Precision::F32,
            compression: String::new(),
            buf: Vec::new(),
        };
        reader.read_header_and_layout()?;
        reader.read_frame_list()?;
        reader.read_rig()?;
        let names: BTreeSet<&str> = reader
            .summary
            .chunk_indexes
            .iter()
            .map(|c| match c.compression.as_str() {
                "" => "none",
                name => name,
            })
            .collect();
        reader.compression = if names.is_empty() {
            "none".into()
        } else {
            names.into_iter().collect::<Vec<_>>().join("+")
        };
        Ok(reader)
    }

    /// Path of the file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The run's settings (fps, first frame, scene text and hash, extra key/values).
    pub fn header(&self) -> &CacheHeader {
        &self.header
    }

    /// The strand layout (offsets, segment rest lengths in m, point radii in m).
    pub fn layout(&self) -> &CacheLayout {
        &self.layout
    }

    /// How the frames are stored: [`Precision::F32`] (exact) or [`Precision::Quantized16`]
    /// (lossy, see [`crate::layout#quantized-frame-payload`]). Frames are decoded to `f32`
    /// either way. [`Precision::F32`] for a cache without frames.
    pub fn precision(&self) -> Precision {
        self.precision
    }

    /// Number of frames stored.
    pub fn frame_count(&self) -> usize {
        self.frames.len()
    }

    /// Frame numbers stored, increasing (frame `f` is at `f / fps` seconds).
    pub fn frame_numbers(&self) -> &[u32] {
        &self.frames
    }

    /// The summary of this cache (frames, time range in s, size in bytes, compression).
    pub fn summary(&self) -> CacheSummary {
        CacheSummary::new(SummaryInput {
            path: self.path.display().to_string(),
            frames: &self.frames,
            fps: self.header.fps,
            strands: self.layout.strand_count(),
            points: self.layout.point_count(),
            bytes: self.file_len,
            compression: self.compression.clone(),
        })
    }

    /// Reads frame number `frame` (positions in m, velocities in m/s) through the index,
    /// decompressing only the chunk that holds it.
    pub fn read_frame(&mut self, frame: u32) -> Result<Frame, CacheError> {
        let Ok(index) = self.frames.binary_search(&frame) else {
            return Err(CacheError::NoSuchFrame {
                path: self.path.clone(),
                frame,
                available: match (self.frames.first(), self.frames.last()) {
                    (Some(a), Some(b)) if self.frames.len() as u64 == u64::from(b - a) + 1 => {
                        format!("frames {a}–{b}")
                    }
                    (Some(a), Some(b)) => {
                        format!("{} frames between {a} and {b}", self.frames.len())
                    }
                    _ => "no frame".into(),
                },
            });
        };
        // Every listed frame passed `frame_at_time_ns`, so its time exists.
        let time_ns = layout::frame_time_ns(frame, self.header.fps).unwrap_or(0);
        let chunk = self.frame_chunks[index];
        if self.cached_chunk.as_ref().map(|c| c.0) != Some(chunk) {
            self.cached_chunk = None;
            let messages = self.read_chunk(chunk, frame)?;
            self.cached_chunk = Some((chunk, messages));
        }
        let messages = self.cached_chunk.as_ref().map_or(&[][..], |c| &c.1[..]);
        let Some(payload) = messages
            .binary_search_by_key(&time_ns, |m| m.0)
            .ok()
            .map(|i| &messages[i].1)
        else {
            return Err(self.damaged(format!(
                "the index lists frame {frame} but its chunk does not hold it"
            )));
        };
        let decoded = layout::decode_frame_as(self.precision, payload, self.layout.point_count())
            .map_err(|e| damaged(&self.path, e))?;
        if decoded.frame != frame {
            return Err(self.damaged(format!(
                "the message logged at frame {frame}'s time holds frame {}",
                decoded.frame
            )));
        }
        Ok(decoded)
    }

    /// Time of the first and the last stored frame, s (`None` without frames).
    pub fn time_range(&self) -> Option<(f64, f64)> {
        let fps = self.header.fps;
        match (self.frames.first(), self.frames.last()) {
            (Some(&a), Some(&b)) => {
                Some((layout::frame_time_s(a, fps), layout::frame_time_s(b, fps)))
            }
            _ => None,
        }
    }

    /// The stored frame at time `time` (s), to the nearest nanosecond, if there is one.
    pub fn frame_at_time(&self, time: f64) -> Option<u32> {
        let ns = time_to_ns(time)?;
        let frame = layout::frame_at_time_ns(ns, self.header.fps)?;
        self.frames.binary_search(&frame).is_ok().then_some(frame)
    }

    /// The stored frames around time `time` (s): `(a, b)` with `a ≤ time ≤ b`, consecutive in
    /// the file, `a == b` when a frame is logged at `time` (to the nearest nanosecond). A time
    /// before the first or after the last frame is a [`CacheError::TimeOutOfRange`] that names
    /// the cached range.
    pub fn frames_around(&self, time: f64) -> Result<(u32, u32), CacheError> {
        if let Some(frame) = self.frame_at_time(time) {
            return Ok((frame, frame));
        }
        let fps = self.header.fps;
        let out_of_range = || CacheError::TimeOutOfRange {
            path: self.path.clone(),
            time,
            frame: time * fps,
            range: self.range_text(),
        };
        let ns = time_to_ns(time).ok_or_else(out_of_range)?;
        // Frame times increase with frame numbers, so the first frame after `time` is found by
        // bisection over the frame list.
        let after = self
            .frames
            .partition_point(|&f| layout::frame_time_ns(f, fps).is_some_and(|f_ns| f_ns <= ns));
        if after == 0 || after == self.frames.len() {
            return Err(out_of_range());
        }
        Ok((self.frames[after - 1], self.frames[after]))
    }

    /// Reads the frame logged at time `time` (s, to the nearest nanosecond) through the index.
    /// Without a frame at that time: [`CacheError::TimeOutOfRange`] outside the cached range,
    /// else [`CacheError::NoSuchFrame`] naming the frames around it.
    pub fn read_frame_at_time(&mut self, time: f64) -> Result<Frame, CacheError> {
        if let Some(frame) = self.frame_at_time(time) {
            return self.read_frame(frame);
        }
        let (a, b) = self.frames_around(time)?;
        Err(CacheError::NoSuchFrame {
            path: self.path.clone(),
            frame: (time * self.header.fps)
                .round()
                .clamp(0.0, f64::from(u32::MAX)) as u32,
            available: format!(
                "no frame at {time} s, only frames {a} and {b} around it (sample between them)"
            ),
        })
    }

    /// The cached range in words, for errors.
    fn range_text(&self) -> String {
        match (self.frames.first(), self.frames.last(), self.time_range()) {
            (Some(a), Some(b), Some((t0, t1))) => {
                format!("frames {a}–{b} ({t0:.4} s – {t1:.4} s)")
            }
            _ => "no frame".into(),
        }
    }

    /// Decompresses chunk `chunk` (index in the summary's chunk indexes), checks its CRC and
    /// returns its frame messages (`log_time`, payload) sorted by time. `frame` is for errors.
    fn read_chunk(&mut self, chunk: usize, frame: u32) -> Result<Vec<ChunkMessage>, CacheError> {
        self.read_channel_chunk(chunk, self.frame_channel, &format!("frame {frame}"))
    }

    /// The messages of channel `channel` in chunk `chunk`, sorted by time; `what` names the
    /// message read in errors.
    fn read_channel_chunk(
        &mut self,
        chunk: usize,
        channel: u16,
        what: &str,
    ) -> Result<Vec<ChunkMessage>, CacheError> {
        let index = &self.summary.chunk_indexes[chunk];
        read_range(
            &self.path,
            &mut self.file,
            self.file_len,
            index.chunk_start_offset,
            index.chunk_length,
            &mut self.buf,
        )?;
        let mut messages = chunk_messages(&self.buf, Some(channel))
            .map_err(|e| damaged(&self.path, format!("chunk of {what}: {e}")))?;
        messages.sort_by_key(|m| m.0);
        Ok(messages)
    }

    fn damaged(&self, detail: impl fmt::Display) -> CacheError {
        damaged(&self.path, detail)
    }

    /// Reads the `hairsys` metadata record and the layout attachment and checks they agree.
    fn read_header_and_layout(&mut self) -> Result<(), CacheError> {
        let not_hairsys = |path: &Path, detail: &str| CacheError::NotHairsys {
            path: path.to_path_buf(),
            detail: detail.into(),
        };
        let Some(meta) = self
            .summary
            .metadata_indexes
            .iter()
            .find(|m| m.name == layout::METADATA_NAME)
            .cloned()
        else {
            return Err(not_hairsys(
                &self.path,
                "it has no `hairsys` metadata record",
            ));
        };
        self.read_record(meta.offset, meta.length, op::METADATA)?;
        let map = match records::parse(op::METADATA, &self.buf[9..]) {
            Ok(Record::Metadata(m)) => m.metadata,
            Ok(_) => return Err(self.damaged("the metadata index points to another record")),
            Err(e) => return Err(self.damaged(e)),
        };
        let (header, counts) = match layout::header_from_metadata(&map) {
            Ok(parsed) => parsed,
            Err(MetadataError::Version(found)) => {
                return Err(CacheError::Version {
                    path: self.path.clone(),
                    found,
                    supported: layout::FORMAT_VERSION,
                })
            }
            Err(e) => return Err(self.damaged(e)),
        };
        let Some(attachment) = self
            .summary
            .attachment_indexes
            .iter()
            .find(|a| a.name == layout::LAYOUT_ATTACHMENT_NAME)
            .cloned()
        else {
            return Err(not_hairsys(
                &self.path,
                "it has no `hairsys/layout.bin` attachment",
            ));
        };
        self.read_record(attachment.offset, attachment.length, op::ATTACHMENT)?;
        let data = attachment_data(&self.buf[9..]).map_err(|e| damaged(&self.path, e))?;
        let layout = CacheLayout::decode(data)
            .map_err(|e| damaged(&self.path, format!("strand layout: {e}")))?;
        if (layout.strand_count(), layout.point_count()) != (counts.strands, counts.points) {
            return Err(self.damaged(format!(
                "the metadata declares {} strands and {} points, the layout {} and {}",
                counts.strands,
                counts.points,
                layout.strand_count(),
                layout.point_count()
            )));
        }
        self.header = header;
        self.layout = layout;
        Ok(())
    }

    /// Lists the stored frames from the message indexes of the frame channel.
    fn read_frame_list(&mut self) -> Result<(), CacheError> {
        let Some(channel) = self
            .summary
            .channels
            .iter()
            .find(|c| c.topic == layout::FRAME_TOPIC)
            .cloned()
        else {
            // A run that wrote no frame has no channel.
            return self.check_message_count(0);
        };
        let Some(precision) = Precision::from_message_encoding(&channel.message_encoding) else {
            return Err(self.damaged(format!(
                "the frame channel has message encoding {:?}, expected {:?} or {:?}",
                channel.message_encoding,
                layout::FRAME_MESSAGE_ENCODING,
                layout::FRAME_Q16_MESSAGE_ENCODING
            )));
        };
        self.precision = precision;
        self.frame_channel = channel.id;
        let (frames, chunks) = self.list_messages(channel.id, "frame")?;
        self.frames = frames;
        self.frame_chunks = chunks;
        self.check_message_count(self.frames.len())
    }

    /// The frames (increasing) logged on channel `channel` and the index of the chunk holding
    /// each, from the chunks' message indexes; `what` names the messages in errors.
    fn list_messages(
        &mut self,
        channel: u16,
        what: &str,
    ) -> Result<(Vec<u32>, Vec<usize>), CacheError> {
        // (log_time, chunk) of every message, from the chunks' message indexes.
        let mut times = Vec::new();
        for (chunk_number, chunk) in self.summary.chunk_indexes.iter().enumerate() {
            if !chunk.message_index_offsets.contains_key(&channel) {
                continue;
            }
            let start = chunk
                .chunk_start_offset
                .checked_add(chunk.chunk_length)
                .ok_or_else(|| damaged(&self.path, "a chunk index overflows"))?;
            read_range(
                &self.path,
                &mut self.file,
                self.file_len,
                start,
                chunk.message_index_length,
                &mut self.buf,
            )?;
            for record in Records::new(&self.buf) {
                let parsed = record.and_then(|(opcode, body)| records::parse(opcode, body));
                match parsed.map_err(|e| damaged(&self.path, e))? {
                    Record::MessageIndex(index) if index.channel_id == channel => {
                        times.extend(index.records.iter().map(|r| (r.log_time, chunk_number)));
                    }
                    Record::MessageIndex(_) => {}
                    _ => {
                        return Err(damaged(
                            &self.path,
                            "a chunk's message index region holds another record",
                        ))
                    }
                }
            }
        }
        let fps = self.header.fps;
        let mut frames = times
            .into_iter()
            .map(|(ns, chunk)| {
                let frame = layout::frame_at_time_ns(ns, fps).ok_or_else(|| {
                    damaged(
                        &self.path,
                        format!(
                            "a {what} is logged at {ns} ns, which is no frame time at {fps} fps"
                        ),
                    )
                })?;
                Ok((frame, chunk))
            })
            .collect::<Result<Vec<(u32, usize)>, CacheError>>()?;
        frames.sort_unstable();
        if let Some(w) = frames.windows(2).find(|w| w[0].0 == w[1].0) {
            return Err(self.damaged(format!("{what} {} is stored twice", w[0].0)));
        }
        Ok(frames.into_iter().unzip())
    }

    /// Reads the rig attachment and lists the rig channel's frames, if the cache has a rig.
    fn read_rig(&mut self) -> Result<(), CacheError> {
        let Some(attachment) = self
            .summary
            .attachment_indexes
            .iter()
            .find(|a| a.name == rig::RIG_ATTACHMENT_NAME)
            .cloned()
        else {
            return Ok(());
        };
        self.read_record(attachment.offset, attachment.length, op::ATTACHMENT)?;
        let data = attachment_data(&self.buf[9..]).map_err(|e| damaged(&self.path, e))?;
        let rig = CacheRig::decode(data, &self.layout)
            .map_err(|e| damaged(&self.path, format!("rig: {e}")))?;
        self.rig = Some(rig);
        if let Some(channel) = self
            .summary
            .channels
            .iter()
            .find(|c| c.topic == rig::RIG_TOPIC)
            .cloned()
        {
            if channel.message_encoding != rig::RIG_MESSAGE_ENCODING {
                return Err(self.damaged(format!(
                    "the rig channel has message encoding {:?}, expected {:?}",
                    channel.message_encoding,
                    rig::RIG_MESSAGE_ENCODING
                )));
            }
            self.rig_channel = channel.id;
            let (frames, chunks) = self.list_messages(channel.id, "rig frame")?;
            self.rig_frames = frames;
            self.rig_chunks = chunks;
        }
        Ok(())
    }

    /// The cache's rig (how strands are rooted, the rest scalp, the colliders), if it has one.
    pub fn rig(&self) -> Option<&CacheRig> {
        self.rig.as_ref()
    }

    /// The rig's state at stored frame `frame`: the scalp and the colliders as they were when
    /// the frame was simulated. `None` for a cache without a rig; an error if the cache has a
    /// rig but not this frame's state.
    pub fn read_rig_frame(&mut self, frame: u32) -> Result<Option<RigFrame>, CacheError> {
        if self.rig.is_none() {
            return Ok(None);
        }
        let Ok(index) = self.rig_frames.binary_search(&frame) else {
            return Err(CacheError::NoSuchFrame {
                path: self.path.clone(),
                frame,
                available: format!(
                    "the rig's state of {} frames (frames without it cannot be exported)",
                    self.rig_frames.len()
                ),
            });
        };
        let time_ns = layout::frame_time_ns(frame, self.header.fps).unwrap_or(0);
        let chunk = self.rig_chunks[index];
        if self.cached_rig_chunk.as_ref().map(|c| c.0) != Some(chunk) {
            self.cached_rig_chunk = None;
            let messages =
                self.read_channel_chunk(chunk, self.rig_channel, &format!("rig frame {frame}"))?;
            self.cached_rig_chunk = Some((chunk, messages));
        }
        let messages = self.cached_rig_chunk.as_ref().map_or(&[][..], |c| &c.1[..]);
        let Some(rig) = &self.rig else {
            return Ok(None);
        };
        let Some(payload) = messages
            .binary_search_by_key(&time_ns, |m| m.0)
            .ok()
            .map(|i| &messages[i].1)
        else {
            return Err(self.damaged(format!(
                "the index lists rig frame {frame} but its chunk does not hold it"
            )));
        };
        let (held, state) = RigFrame::decode(payload, rig)
            .map_err(|e| damaged(&self.path, format!("rig frame {frame}: {e}")))?;
        if held != frame {
            return Err(self.damaged(format!(
                "the rig message logged at frame {frame}'s time holds frame {held}"
            )));
        }
        Ok(Some(state))
    }

    /// Checks the statistics record's message count on the frame channel (all messages when
    /// there is no frame channel) against the frames listed.
    fn check_message_count(&self, frames: usize) -> Result<(), CacheError> {
        let Some(stats) = &self.summary.stats else {
            return Ok(());
        };
        let counted = if self.frame_channel == 0 {
            stats.message_count
        } else {
            stats
                .channel_message_counts
                .get(&self.frame_channel)
                .copied()
                .unwrap_or(0)
        };
        if counted == frames as u64 {
            Ok(())
        } else {
            Err(self.damaged(format!(
                "its statistics count {counted} frame messages but the indexes list {frames} frames"
            )))
        }
    }

    /// Reads the record at `offset` (`length` bytes including opcode and length fields) into
    /// `self.buf` and checks its opcode and length; its body is `self.buf[9..]`.
    fn read_record(&mut self, offset: u64, length: u64, opcode: u8) -> Result<(), CacheError> {
        read_range(
            &self.path,
            &mut self.file,
            self.file_len,
            offset,
            length,
            &mut self.buf,
        )?;
        let mut r = LeReader::new(&self.buf);
        let header = r
            .take(1)
            .and_then(|op| Ok((op[0], r.u64()?)))
            .map_err(|e| damaged(&self.path, e))?;
        if header != (opcode, length.saturating_sub(9)) {
            return Err(damaged(
                &self.path,
                format!(
                    "the index points to record {:#04x} of {} bytes, expected {opcode:#04x} of {}",
                    header.0,
                    header.1,
                    length.saturating_sub(9)
                ),
            ));
        }
        Ok(())
    }
}

/// Reads the summary section, naming the file in errors.
fn read_summary(path: &Path, file: &mut File, file_len: u64) -> Result<SummarySection, CacheError> {
    summary_section::read(file, file_len).map_err(|e| match e {
        SummaryError::Incomplete(detail) => CacheError::Incomplete {
            path: path.to_path_buf(),
            detail: detail.into(),
        },
        SummaryError::Damaged(damage) => damaged(path, damage),
        SummaryError::Io(source) => CacheError::Io {
            path: path.to_path_buf(),
            action: "read",
            source,
        },
    })
}

/// The data of an attachment record body (header, `u64` length, data, `u32` CRC), CRC checked.
pub(crate) fn attachment_data(body: &[u8]) -> Result<&[u8], RecordError> {
    match records::parse(op::ATTACHMENT, body) {
        Ok(Record::Attachment { data, .. }) => match data {
            std::borrow::Cow::Borrowed(data) => Ok(data),
            std::borrow::Cow::Owned(_) => Err(RecordError::AttachmentCopied),
        },
        Ok(_) => Err(RecordError::NotAttachment),
        Err(e) => Err(RecordError::Attachment(Box::new(e))),
    }
}

/// Seconds to nanoseconds, rounded; `None` for negative, non-finite or too large times.
fn time_to_ns(time: f64) -> Option<u64> {
    let ns = (time * 1e9).round();
    (ns.is_finite() && ns >= 0.0 && ns <= layout::MAX_TIME_NS as f64).then_some(ns as u64)
}

/// The messages (`log_time`, payload) of a whole chunk record (`record`: opcode, length and
/// body, as the chunk index locates it), decompressed and CRC-checked; only those of channel
/// `channel` if it is given.
fn chunk_messages(record: &[u8], channel: Option<u16>) -> Result<Vec<ChunkMessage>, RecordError> {
    let mut r = LeReader::new(record);
    let (opcode, length) = r
        .take(1)
        .and_then(|op| Ok((op[0], r.u64()?)))
        .map_err(|_| RecordError::NoChunk)?;
    if opcode != op::CHUNK {
        return Err(RecordError::NoChunk);
    }
    if length != r.remaining() as u64 {
        return Err(RecordError::ChunkLength {
            length,
            indexed: r.remaining(),
        });
    }
    let (header, data) = match records::parse(op::CHUNK, &record[9..])? {
        Record::Chunk { header, data } => (header, data),
        _ => return Err(RecordError::NoChunk),
    };
    // Every length inside the chunk is used only after its CRC has checked.
    let content = records::chunk_content(&header, &data)?;
    let mut messages = Vec::new();
    for record in Records::new(&content) {
        let (opcode, body) = record?;
        if opcode != op::MESSAGE {
            continue;
        }
        if let Record::Message { header, data } = records::parse(opcode, body)? {
            if channel.is_none_or(|c| c == header.channel_id) {
                messages.push((header.log_time, data.into_owned()));
            }
        }
    }
    Ok(messages)
}

/// Reads `length` bytes at `offset` of `file` into `buf`, after checking they lie in the file.
fn read_range(
    path: &Path,
    file: &mut File,
    file_len: u64,
    offset: u64,
    length: u64,
    buf: &mut Vec<u8>,
) -> Result<(), CacheError> {
    let end = offset.checked_add(length).filter(|&end| end <= file_len);
    let (Some(_), Ok(len)) = (end, usize::try_from(length)) else {
        return Err(damaged(
            path,
            format!("an index points to bytes {offset}..{offset}+{length}, past the end of the file ({file_len} bytes)"),
        ));
    };
    buf.resize(len, 0);
    file.seek(SeekFrom::Start(offset))
        .and_then(|_| file.read_exact(buf))
        .map_err(|source| CacheError::Io {
            path: path.to_path_buf(),
            action: "read",
            source,
        })
}

/// Reads into `buf` until it is full or the file ends; returns the bytes read.
fn read_up_to(file: &mut File, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut filled = 0;
    while filled < buf.len() {
        match file.read(&mut buf[filled..]) {
            Ok(0) => break,
            Ok(n) => filled += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(filled)
}

/// A [`CacheError::Damaged`] of `path` for `detail` (a typed error of the format or a sentence).
pub(crate) fn damaged(path: &Path, detail: impl fmt::Display) -> CacheError {
    CacheError::Damaged {
        path: path.to_path_buf(),
        detail: detail.to_string(),
    }
}
