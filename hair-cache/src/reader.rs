//! Reading a finished cache: [`CacheReader`] reads the summary section, the metadata record, the
//! layout attachment and the message indexes when it opens a file, then reads any frame by
//! decompressing only the chunk that holds it.

use std::collections::BTreeSet;
use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use mcap::records::{op, Record};
use mcap::sans_io::{SummaryReadEvent, SummaryReader, SummaryReaderOptions};
use mcap::McapError;

use crate::error::CacheError;
use crate::layout::{self, CacheHeader, CacheLayout, Frame, LeReader, MetadataError};
use crate::summary::{CacheSummary, SummaryInput};

/// The summary of the finished cache at `path` (what `hairsys cache info` prints).
pub fn summarize(path: impl AsRef<Path>) -> Result<CacheSummary, CacheError> {
    Ok(CacheReader::open(path)?.summary())
}

/// An open cache file: its header, layout and frame list, and random access to its frames.
pub struct CacheReader {
    path: PathBuf,
    file: File,
    file_len: u64,
    summary: mcap::Summary,
    header: CacheHeader,
    layout: CacheLayout,
    /// Frame numbers stored, increasing.
    frames: Vec<u32>,
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
        let mut file = File::open(&path).map_err(|source| CacheError::Io {
            path: path.clone(),
            action: "open",
            source,
        })?;
        let file_len = file
            .metadata()
            .map_err(|source| CacheError::Io {
                path: path.clone(),
                action: "read the size of",
                source,
            })?
            .len();
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
            compression: String::new(),
            buf: Vec::new(),
        };
        reader.read_header_and_layout()?;
        reader.read_frame_list()?;
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
        if self.frames.binary_search(&frame).is_err() {
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
        }
        // Every listed frame passed `frame_at_time_ns`, so its time exists.
        let time_ns = layout::frame_time_ns(frame, self.header.fps).unwrap_or(0);
        let Some(chunk) = self
            .summary
            .chunk_indexes
            .iter()
            .find(|c| (c.message_start_time..=c.message_end_time).contains(&time_ns))
        else {
            return Err(self.damaged(format!("no chunk index covers frame {frame}")));
        };
        read_range(
            &self.path,
            &mut self.file,
            self.file_len,
            chunk.chunk_start_offset,
            chunk.chunk_length,
            &mut self.buf,
        )?;
        let body = (self.buf.first() == Some(&op::CHUNK))
            .then(|| self.buf.get(9..))
            .flatten();
        let (chunk_header, data) = match body.map(|b| mcap::parse_record(op::CHUNK, b)) {
            Some(Ok(Record::Chunk { header, data })) => (header, data),
            Some(Err(e)) => return Err(self.damaged(format!("chunk of frame {frame}: {e}"))),
            _ => return Err(self.damaged(format!("the index of frame {frame} points to no chunk"))),
        };
        // `ChunkReader` checks the chunk's CRC once it reaches the chunk's end, so the chunk is
        // read to its end even after the frame was found.
        let records = mcap::read::ChunkReader::new(chunk_header, &data)
            .map_err(|e| damaged(&self.path, format!("chunk of frame {frame}: {e}")))?;
        let mut payload = None;
        for record in records {
            match record {
                Ok(Record::Message { header, data }) if header.log_time == time_ns => {
                    payload = Some(data);
                }
                Ok(_) => {}
                Err(e) => return Err(self.damaged(format!("chunk of frame {frame}: {e}"))),
            }
        }
        let Some(payload) = payload else {
            return Err(self.damaged(format!(
                "the index lists frame {frame} but its chunk does not hold it"
            )));
        };
        let decoded = layout::decode_frame(&payload, self.layout.point_count())
            .map_err(|e| damaged(&self.path, e))?;
        if decoded.frame != frame {
            return Err(self.damaged(format!(
                "the message logged at frame {frame}'s time holds frame {}",
                decoded.frame
            )));
        }
        Ok(decoded)
    }

    fn damaged(&self, detail: String) -> CacheError {
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
        let map = match mcap::parse_record(op::METADATA, &self.buf[9..]) {
            Ok(Record::Metadata(m)) => m.metadata,
            Ok(_) => return Err(self.damaged("the metadata index points to another record".into())),
            Err(e) => return Err(self.damaged(e.to_string())),
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
            Err(MetadataError::Key(detail)) => return Err(self.damaged(detail)),
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
            .values()
            .find(|c| c.topic == layout::FRAME_TOPIC)
            .cloned()
        else {
            // A run that wrote no frame has no channel.
            return self.check_message_count(0);
        };
        if channel.message_encoding != layout::FRAME_MESSAGE_ENCODING {
            return Err(self.damaged(format!(
                "the frame channel has message encoding {:?}, expected {:?}",
                channel.message_encoding,
                layout::FRAME_MESSAGE_ENCODING
            )));
        }
        let mut times = Vec::new();
        for chunk in &self.summary.chunk_indexes {
            if !chunk.message_index_offsets.contains_key(&channel.id) {
                continue;
            }
            let start = chunk
                .chunk_start_offset
                .checked_add(chunk.chunk_length)
                .ok_or_else(|| damaged(&self.path, "a chunk index overflows".into()))?;
            read_range(
                &self.path,
                &mut self.file,
                self.file_len,
                start,
                chunk.message_index_length,
                &mut self.buf,
            )?;
            for record in mcap::read::LinearReader::sans_magic(&self.buf) {
                match record.map_err(|e| damaged(&self.path, e.to_string()))? {
                    Record::MessageIndex(index) if index.channel_id == channel.id => {
                        times.extend(index.records.iter().map(|r| r.log_time));
                    }
                    Record::MessageIndex(_) => {}
                    _ => {
                        return Err(damaged(
                            &self.path,
                            "a chunk's message index region holds another record".into(),
                        ))
                    }
                }
            }
        }
        let fps = self.header.fps;
        let mut frames = times
            .into_iter()
            .map(|ns| {
                layout::frame_at_time_ns(ns, fps).ok_or_else(|| {
                    damaged(
                        &self.path,
                        format!(
                            "a frame is logged at {ns} ns, which is no frame time at {fps} fps"
                        ),
                    )
                })
            })
            .collect::<Result<Vec<u32>, _>>()?;
        frames.sort_unstable();
        if let Some(w) = frames.windows(2).find(|w| w[0] == w[1]) {
            return Err(self.damaged(format!("frame {} is stored twice", w[0])));
        }
        self.frames = frames;
        self.check_message_count(self.frames.len())
    }

    /// Checks the statistics record's message count against the frames listed.
    fn check_message_count(&self, frames: usize) -> Result<(), CacheError> {
        match &self.summary.stats {
            Some(stats) if stats.message_count != frames as u64 => Err(self.damaged(format!(
                "its statistics count {} messages but the indexes list {frames} frames",
                stats.message_count
            ))),
            _ => Ok(()),
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

/// Reads the summary section; maps a missing or unreadable footer to [`CacheError::Incomplete`].
fn read_summary(path: &Path, file: &mut File, file_len: u64) -> Result<mcap::Summary, CacheError> {
    let io = |source| CacheError::Io {
        path: path.to_path_buf(),
        action: "read",
        source,
    };
    let incomplete = |detail: &str| CacheError::Incomplete {
        path: path.to_path_buf(),
        detail: detail.into(),
    };
    let mut reader =
        SummaryReader::new_with_options(SummaryReaderOptions::default().with_file_size(file_len));
    while let Some(event) = reader.next_event() {
        match event {
            Ok(SummaryReadEvent::ReadRequest(n)) => {
                let read = read_up_to(file, reader.insert(n)).map_err(io)?;
                reader.notify_read(read);
            }
            Ok(SummaryReadEvent::SeekRequest(to)) => {
                let pos = file.seek(to).map_err(io)?;
                reader.notify_seeked(pos);
            }
            Err(McapError::BadMagic | McapError::UnexpectedEof | McapError::BadFooter) => {
                return Err(incomplete("it does not end with an MCAP footer"))
            }
            Err(e) => return Err(damaged(path, e.to_string())),
        }
    }
    reader
        .finish()
        .ok_or_else(|| incomplete("it has no summary section"))
}

/// The data of an attachment record body (header, `u64` length, data, `u32` CRC), CRC checked.
fn attachment_data(body: &[u8]) -> Result<&[u8], String> {
    // Check the structure first: `mcap::parse_record` slices the body without bounds checks.
    let mut r = LeReader::new(body);
    r.u64()?; // log time
    r.u64()?; // create time
    r.string()?; // name
    r.string()?; // media type
    let len = usize::try_from(r.u64()?).map_err(|e| e.to_string())?;
    r.take(len)?;
    r.u32()?; // CRC
    match mcap::parse_record(op::ATTACHMENT, body) {
        Ok(Record::Attachment { data, .. }) => match data {
            std::borrow::Cow::Borrowed(data) => Ok(data),
            std::borrow::Cow::Owned(_) => Err("the layout attachment was copied".into()),
        },
        Ok(_) => Err("the attachment index points to another record".into()),
        Err(e) => Err(format!("layout attachment: {e}")),
    }
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

fn damaged(path: &Path, detail: String) -> CacheError {
    CacheError::Damaged {
        path: path.to_path_buf(),
        detail,
    }
}
