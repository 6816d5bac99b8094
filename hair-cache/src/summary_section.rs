//! The summary section of a finished cache (MCAP "Summary Section" and "Footer",
//! <https://mcap.dev/spec>): channels, statistics and the chunk, attachment and metadata indexes
//! that let [`crate::CacheReader`] seek frames.
//!
//! It is read here rather than by `mcap`'s summary reader so that no length in it is trusted
//! before it is checked (see [`crate::records`]): the footer's offsets must lie inside the file,
//! the footer's summary CRC (over the summary and summary offset sections and the footer's
//! offsets) is checked when it is not 0, and every record is bounds-checked before it is parsed.
//! The section is read whole, so memory is bounded by the file.

use std::fs::File;
use std::io::{self, Read, Seek, SeekFrom};

use mcap::records::{op, AttachmentIndex, Channel, ChunkIndex, MetadataIndex, Record, Statistics};
use thiserror::Error;

use crate::records::{self, RecordError, Records};

/// Footer record length: opcode, `u64` length, then `summary_start`, `summary_offset_start`
/// (`u64` each) and `summary_crc` (`u32`).
const FOOTER_LEN: u64 = 9 + 20;
/// The magic bytes at both ends of an MCAP file.
const MAGIC_LEN: u64 = 8;

/// The index records of a finished cache.
#[derive(Debug, Default)]
pub(crate) struct SummarySection {
    /// Channel records, in file order.
    pub channels: Vec<Channel>,
    /// One per chunk, in file order.
    pub chunk_indexes: Vec<ChunkIndex>,
    /// One per attachment.
    pub attachment_indexes: Vec<AttachmentIndex>,
    /// One per metadata record.
    pub metadata_indexes: Vec<MetadataIndex>,
    /// The statistics record, if written.
    pub stats: Option<Statistics>,
}

/// Why a summary section could not be read.
#[derive(Debug)]
pub(crate) enum SummaryError {
    /// The file has no footer or no summary section: truncated, or its writer was killed.
    Incomplete(&'static str),
    /// The footer or a summary record is inconsistent.
    Damaged(SummaryDamage),
    /// Reading failed.
    Io(io::Error),
}

/// How the footer or the summary section is inconsistent.
#[derive(Debug, Error)]
pub(crate) enum SummaryDamage {
    /// The footer places the summary or its offsets outside the file's data.
    #[error(
        "its footer places the summary at byte {summary_start} and the summary offsets at byte \
         {offsets_start}, outside bytes {MAGIC_LEN}..{footer_at}"
    )]
    Footer {
        summary_start: u64,
        offsets_start: u64,
        footer_at: u64,
    },
    /// The summary's CRC does not match its bytes.
    #[error("summary CRC mismatch: stored {stored:#010x}, computed {computed:#010x}")]
    Crc { stored: u32, computed: u32 },
    /// A summary record is damaged.
    #[error(transparent)]
    Record(#[from] RecordError),
}

/// Reads the summary section of `file` (`file_len` bytes, starting with the MCAP magic).
pub(crate) fn read(file: &mut File, file_len: u64) -> Result<SummarySection, SummaryError> {
    let no_footer = SummaryError::Incomplete("it does not end with an MCAP footer");
    let Some(footer_at) = file_len.checked_sub(FOOTER_LEN + MAGIC_LEN) else {
        return Err(no_footer);
    };
    if footer_at < MAGIC_LEN {
        return Err(no_footer);
    }
    let mut tail = [0u8; (FOOTER_LEN + MAGIC_LEN) as usize];
    read_at(file, footer_at, &mut tail)?;
    let u64_at = |at: usize| u64::from_le_bytes(tail[at..at + 8].try_into().unwrap_or([0; 8]));
    if tail[0] != op::FOOTER || u64_at(1) != FOOTER_LEN - 9 || tail[29..] != *mcap::MAGIC {
        return Err(no_footer);
    }
    let (summary_start, offsets_start) = (u64_at(9), u64_at(17));
    let summary_crc = u32::from_le_bytes([tail[25], tail[26], tail[27], tail[28]]);
    if summary_start == 0 {
        return Err(SummaryError::Incomplete("it has no summary section"));
    }
    let data = MAGIC_LEN..=footer_at;
    if !data.contains(&summary_start)
        || !(offsets_start == 0 || (summary_start..=footer_at).contains(&offsets_start))
    {
        return Err(SummaryError::Damaged(SummaryDamage::Footer {
            summary_start,
            offsets_start,
            footer_at,
        }));
    }
    // The CRC covers the summary and summary offset sections and the footer up to its CRC.
    let mut section = vec![0u8; (footer_at + 9 + 16 - summary_start) as usize];
    read_at(file, summary_start, &mut section)?;
    if summary_crc != 0 {
        let computed = crc32fast::hash(&section);
        if computed != summary_crc {
            return Err(SummaryError::Damaged(SummaryDamage::Crc {
                stored: summary_crc,
                computed,
            }));
        }
    }
    let end = if offsets_start == 0 {
        footer_at
    } else {
        offsets_start
    };
    let mut summary = SummarySection::default();
    for record in Records::new(&section[..(end - summary_start) as usize]) {
        let damaged = |e| SummaryError::Damaged(SummaryDamage::Record(e));
        let (opcode, body) = record.map_err(damaged)?;
        match records::parse(opcode, body).map_err(damaged)? {
            Record::Channel(c) => summary.channels.push(c),
            Record::ChunkIndex(c) => summary.chunk_indexes.push(c),
            Record::AttachmentIndex(a) => summary.attachment_indexes.push(a),
            Record::MetadataIndex(m) => summary.metadata_indexes.push(m),
            Record::Statistics(s) => summary.stats = Some(s),
            _ => {}
        }
    }
    Ok(summary)
}

/// Fills `buf` from byte `offset` of `file`.
fn read_at(file: &mut File, offset: u64, buf: &mut [u8]) -> Result<(), SummaryError> {
    file.seek(SeekFrom::Start(offset))
        .and_then(|_| file.read_exact(buf))
        .map_err(SummaryError::Io)
}
