//! MCAP records read defensively: every length a record declares is checked against the bytes
//! that hold it before anything is allocated from it.
//!
//! `mcap::parse_record` (mcap 0.26) trusts the length prefixes inside a record body: through
//! `binrw` a string's length reserves that many bytes before they are read (an 11 KB file could
//! reserve 4 GiB), and the crate's chunk readers allocate a chunk's declared uncompressed size
//! before decompressing it (a 1 TiB claim aborts the process). So this crate never hands it bytes
//! it has not checked:
//!
//! - [`parse`] first walks a record body field by field, as the MCAP specification lays it out
//!   (<https://mcap.dev/spec>, "Records"), checking that every string, byte array, map and array
//!   lies inside the body, and that maps and arrays are tiled exactly by whole entries. Only then
//!   does `mcap::parse_record` see it, and its allocations are bounded by the body.
//! - [`Records`] splits a byte region (a decompressed chunk, a message index region, the summary
//!   section) into records, refusing one whose length runs past the region.
//! - [`chunk_content`] decompresses a chunk itself: the declared uncompressed size is first
//!   bounded by what the compressed bytes present can expand to (LZ4 at most 255:1, Zstandard
//!   at most 32768:1 — an RLE block of 4 bytes gives 128 KiB), then the output grows only as
//!   the decoder actually produces bytes, and decoding stops one byte past the declared size.
//!   The chunk's CRC is checked before any record length inside it is used.
//!
//! Memory is therefore bounded by the record being read, which is bounded by the file, and by
//! what its compressed bytes really decode to; never by a number a damaged header claims.

use std::borrow::Cow;
use std::io::{self, Read};
use std::num::TryFromIntError;

use mcap::records::{op, ChunkHeader, Record};
use thiserror::Error;

use crate::layout::{LeReader, Truncated};

/// Why a record, or a chunk of records, cannot be read.
#[derive(Debug, Error)]
pub(crate) enum RecordError {
    /// The bytes end inside a record's opcode or length.
    #[error(transparent)]
    Truncated(#[from] Truncated),
    /// A field of the record does not lie in its body.
    #[error("{} record: {source}", name(*.opcode))]
    Field { opcode: u8, source: FieldError },
    /// `mcap` refused the record after its fields were checked.
    #[error("{} record: {source}", name(*.opcode))]
    Mcap { opcode: u8, source: mcap::McapError },
    /// A record's length runs past the region that holds it.
    #[error("a {} record claims {len} bytes but only {remaining} follow it", name(*.opcode))]
    Overrun {
        opcode: u8,
        len: u64,
        remaining: usize,
    },
    /// An uncompressed chunk's size is not its data's.
    #[error("an uncompressed chunk declares {declared} bytes but holds {held}")]
    UncompressedSize { declared: u64, held: usize },
    /// The decoder of a compressed chunk could not start.
    #[error("{codec} chunk: {source}")]
    Decoder {
        codec: &'static str,
        source: io::Error,
    },
    /// A chunk is compressed with a codec a hairsys cache does not use.
    #[error("chunk compression {compression:?} is not one a hairsys cache uses (none, lz4, zstd)")]
    Compression { compression: String },
    /// A chunk's CRC does not match its content.
    #[error("chunk CRC mismatch: stored {stored:#010x}, computed {computed:#010x}")]
    Crc { stored: u32, computed: u32 },
    /// A chunk declares more bytes than its compressed data can expand to.
    #[error(
        "a {codec} chunk of {compressed} compressed bytes claims {declared} bytes uncompressed, \
         more than {codec} can expand it to ({most})"
    )]
    Expansion {
        codec: &'static str,
        compressed: usize,
        declared: u64,
        most: u64,
    },
    /// A chunk's compressed data does not decode.
    #[error("{codec} chunk data: {source}")]
    Data {
        codec: &'static str,
        source: io::Error,
    },
    /// A chunk's data decodes to another size than it declares (`None`: more).
    #[error(
        "a {codec} chunk declares {declared} bytes uncompressed but its data decodes to {}",
        .decoded.map_or_else(|| "more".to_string(), |n| n.to_string())
    )]
    DecodedSize {
        codec: &'static str,
        declared: u64,
        decoded: Option<usize>,
    },
    /// An index points to a record that is no chunk.
    #[error("the index points to no chunk")]
    NoChunk,
    /// A chunk record's length is not the one its index gives.
    #[error("the chunk record is {length} bytes long but its index gives it {indexed}")]
    ChunkLength { length: u64, indexed: usize },
    /// An attachment index points to a record that is no attachment.
    #[error("the attachment index points to another record")]
    NotAttachment,
    /// The attachment's data was copied instead of borrowed from the record.
    #[error("the layout attachment was copied")]
    AttachmentCopied,
    /// The attachment record is damaged.
    #[error("layout attachment: {0}")]
    Attachment(Box<RecordError>),
}

/// Why a field of a record body does not lie in the body.
#[derive(Debug, Error)]
pub(crate) enum FieldError {
    /// The body ends inside the field.
    #[error(transparent)]
    Truncated(#[from] Truncated),
    /// A length does not fit in memory.
    #[error(transparent)]
    Length(#[from] TryFromIntError),
    /// A map or array is not tiled by whole entries.
    #[error("a map or array of {len} bytes does not hold whole {entry}-byte entries")]
    PartialEntries { len: usize, entry: usize },
}

/// One field of a record body, in the MCAP specification's types.
#[derive(Clone, Copy)]
enum Field {
    U8,
    U16,
    U32,
    U64,
    /// `u32` byte length, UTF-8 bytes.
    Str,
    /// `u32` byte length, bytes.
    Bytes32,
    /// `u64` byte length, bytes.
    Bytes64,
    /// `u32` byte length, then `(string, string)` entries filling it exactly.
    StrMap,
    /// `u32` byte length, then entries of this many bytes filling it exactly (integer maps and
    /// arrays of fixed-size tuples).
    Fixed(usize),
    /// The rest of the body (a message's data).
    Rest,
}

/// The fields of a record with opcode `opcode`, in order; none for an opcode this crate does
/// not parse (its body is kept as opaque bytes).
fn fields(opcode: u8) -> &'static [Field] {
    use Field::*;
    match opcode {
        op::HEADER => &[Str, Str],
        op::FOOTER => &[U64, U64, U32],
        op::SCHEMA => &[U16, Str, Str, Bytes32],
        op::CHANNEL => &[U16, U16, Str, Str, StrMap],
        op::MESSAGE => &[U16, U32, U64, U64, Rest],
        op::CHUNK => &[U64, U64, U64, U32, Str, Bytes64],
        // Records: (u64 log_time, u64 offset).
        op::MESSAGE_INDEX => &[U16, Fixed(16)],
        // message_index_offsets: u16 channel → u64 offset.
        op::CHUNK_INDEX => &[U64, U64, U64, U64, Fixed(10), U64, Str, U64, U64],
        op::ATTACHMENT => &[U64, U64, Str, Str, Bytes64, U32],
        op::ATTACHMENT_INDEX => &[U64, U64, U64, U64, U64, Str, Str],
        // channel_message_counts: u16 channel → u64 count.
        op::STATISTICS => &[U64, U16, U32, U32, U32, U32, U64, U64, Fixed(10)],
        op::METADATA => &[Str, StrMap],
        op::METADATA_INDEX => &[U64, U64, Str],
        op::SUMMARY_OFFSET => &[U8, U64, U64],
        op::DATA_END => &[U32],
        _ => &[],
    }
}

/// The name of a record kind, for errors.
pub(crate) fn name(opcode: u8) -> String {
    match opcode {
        op::HEADER => "header".into(),
        op::FOOTER => "footer".into(),
        op::SCHEMA => "schema".into(),
        op::CHANNEL => "channel".into(),
        op::MESSAGE => "message".into(),
        op::CHUNK => "chunk".into(),
        op::MESSAGE_INDEX => "message index".into(),
        op::CHUNK_INDEX => "chunk index".into(),
        op::ATTACHMENT => "attachment".into(),
        op::ATTACHMENT_INDEX => "attachment index".into(),
        op::STATISTICS => "statistics".into(),
        op::METADATA => "metadata".into(),
        op::METADATA_INDEX => "metadata index".into(),
        op::SUMMARY_OFFSET => "summary offset".into(),
        op::DATA_END => "data end".into(),
        other => format!("{other:#04x}"),
    }
}

/// Checks that `body` holds every field of a record with opcode `opcode`: each length prefix
/// fits in the bytes after it. Bytes after the last field are allowed (the specification lets
/// records grow new fields at their end).
pub(crate) fn check(opcode: u8, body: &[u8]) -> Result<(), RecordError> {
    let mut r = LeReader::new(body);
    let length = |r: &mut LeReader, n: u64| -> Result<(), FieldError> {
        r.take(usize::try_from(n)?)?;
        Ok(())
    };
    let walk = |r: &mut LeReader| -> Result<(), FieldError> {
        for field in fields(opcode) {
            match *field {
                Field::U8 => length(r, 1)?,
                Field::U16 => length(r, 2)?,
                Field::U32 => length(r, 4)?,
                Field::U64 => length(r, 8)?,
                Field::Str | Field::Bytes32 => {
                    let n = r.u32()?;
                    length(r, n.into())?;
                }
                Field::Bytes64 => {
                    let n = r.u64()?;
                    length(r, n)?;
                }
                Field::StrMap => {
                    let n = r.u32()?;
                    let mut map = LeReader::new(r.take(n as usize)?);
                    while map.remaining() > 0 {
                        for _ in 0..2 {
                            let n = map.u32()?;
                            length(&mut map, n.into())?;
                        }
                    }
                }
                Field::Fixed(entry) => {
                    let n = r.u32()? as usize;
                    if !n.is_multiple_of(entry) {
                        return Err(FieldError::PartialEntries { len: n, entry });
                    }
                    r.take(n)?;
                }
                Field::Rest => {}
            }
        }
        Ok(())
    };
    walk(&mut r).map_err(|source| RecordError::Field { opcode, source })
}

/// Parses a record body with `mcap` after [`check`]ing it; the record borrows from `body`.
pub(crate) fn parse(opcode: u8, body: &[u8]) -> Result<Record<'_>, RecordError> {
    check(opcode, body)?;
    mcap::parse_record(opcode, body).map_err(|source| RecordError::Mcap { opcode, source })
}

/// The records `(opcode, body)` of a byte region, one after another. A record whose length runs
/// past the region yields an error and ends the iteration.
pub(crate) struct Records<'a> {
    bytes: &'a [u8],
}

impl<'a> Records<'a> {
    /// The records of `bytes`, which hold whole records back to back.
    pub(crate) fn new(bytes: &'a [u8]) -> Self {
        Self { bytes }
    }
}

impl<'a> Iterator for Records<'a> {
    type Item = Result<(u8, &'a [u8]), RecordError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.bytes.is_empty() {
            return None;
        }
        let mut r = LeReader::new(self.bytes);
        let mut record = || -> Result<_, RecordError> {
            let opcode = r.take(1)?[0];
            let len = r.u64()?;
            let body = usize::try_from(len)
                .ok()
                .filter(|&len| len <= r.remaining())
                .ok_or(RecordError::Overrun {
                    opcode,
                    len,
                    remaining: r.remaining(),
                })?;
            Ok((opcode, r.take(body)?))
        };
        let record = record();
        match record {
            Ok((opcode, body)) => {
                self.bytes = &self.bytes[9 + body.len()..];
                Some(Ok((opcode, body)))
            }
            Err(e) => {
                self.bytes = &[];
                Some(Err(e))
            }
        }
    }
}

/// Most uncompressed bytes one compressed byte of LZ4 can give (a match length grows by 255 per
/// byte), with room for frame headers.
const LZ4_MAX_RATIO: u64 = 256;
/// Most uncompressed bytes one compressed byte of Zstandard can give: a 4-byte RLE block
/// (3-byte header, 1 byte) expands to a 128 KiB block.
const ZSTD_MAX_RATIO: u64 = 32 * 1024;
/// Largest Zstandard window accepted, log2 bytes (zstd's own default limit, 128 MiB).
const ZSTD_MAX_WINDOW_LOG: u32 = 27;
/// Smallest Zstandard window limit, log2 bytes: enough for any level's default window on
/// small chunks (level 19 uses 2²³).
const ZSTD_MIN_WINDOW_LOG: u32 = 23;

/// The records of the chunk whose header and compressed data are given, decompressed and
/// CRC-checked (a CRC of 0 means "not computed" in MCAP and is not checked).
pub(crate) fn chunk_content<'a>(
    header: &ChunkHeader,
    data: &'a [u8],
) -> Result<Cow<'a, [u8]>, RecordError> {
    let declared = header.uncompressed_size;
    let content = match header.compression.as_str() {
        "" => {
            if declared != data.len() as u64 {
                return Err(RecordError::UncompressedSize {
                    declared,
                    held: data.len(),
                });
            }
            Cow::Borrowed(data)
        }
        "lz4" => {
            let decoder = lz4::Decoder::new(data).map_err(|source| RecordError::Decoder {
                codec: "lz4",
                source,
            })?;
            Cow::Owned(decompress(
                "lz4",
                decoder,
                declared,
                data.len(),
                LZ4_MAX_RATIO,
            )?)
        }
        "zstd" => {
            let zstd_error = |source| RecordError::Decoder {
                codec: "zstd",
                source,
            };
            let mut decoder = zstd::stream::read::Decoder::with_buffer(data).map_err(zstd_error)?;
            let window_log = (u64::BITS - declared.leading_zeros())
                .clamp(ZSTD_MIN_WINDOW_LOG, ZSTD_MAX_WINDOW_LOG);
            decoder.window_log_max(window_log).map_err(zstd_error)?;
            Cow::Owned(decompress(
                "zstd",
                decoder,
                declared,
                data.len(),
                ZSTD_MAX_RATIO,
            )?)
        }
        other => {
            return Err(RecordError::Compression {
                compression: other.to_string(),
            })
        }
    };
    if header.uncompressed_crc != 0 {
        let computed = crc32fast::hash(&content);
        if computed != header.uncompressed_crc {
            return Err(RecordError::Crc {
                stored: header.uncompressed_crc,
                computed,
            });
        }
    }
    Ok(content)
}

/// Decodes `decoder` into exactly `declared` bytes, refusing a declared size beyond what
/// `compressed` bytes of `codec` can expand to (`max_ratio`) and growing the output only as bytes
/// come out of the decoder.
fn decompress(
    codec: &'static str,
    decoder: impl Read,
    declared: u64,
    compressed: usize,
    max_ratio: u64,
) -> Result<Vec<u8>, RecordError> {
    let most = (compressed as u64).saturating_mul(max_ratio);
    if declared > most {
        return Err(RecordError::Expansion {
            codec,
            compressed,
            declared,
            most,
        });
    }
    // Frames of moving hair barely compress: the compressed size is a good first guess.
    let guess = (compressed as u64).saturating_mul(2).saturating_add(4096);
    let mut out = Vec::with_capacity(usize::try_from(declared.min(guess)).unwrap_or(0));
    decoder
        .take(declared.saturating_add(1))
        .read_to_end(&mut out)
        .map_err(|source| RecordError::Data { codec, source })?;
    let decoded = match (out.len() as u64).cmp(&declared) {
        std::cmp::Ordering::Equal => return Ok(out),
        std::cmp::Ordering::Greater => None,
        std::cmp::Ordering::Less => Some(out.len()),
    };
    Err(RecordError::DecodedSize {
        codec,
        declared,
        decoded,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(opcode: u8, body: &[u8]) -> Vec<u8> {
        let mut out = vec![opcode];
        out.extend_from_slice(&(body.len() as u64).to_le_bytes());
        out.extend_from_slice(body);
        out
    }

    fn string(s: &str) -> Vec<u8> {
        let mut out = (s.len() as u32).to_le_bytes().to_vec();
        out.extend_from_slice(s.as_bytes());
        out
    }

    fn metadata(name: &str, pairs: &[(&str, &str)]) -> Vec<u8> {
        let mut map = Vec::new();
        for (k, v) in pairs {
            map.extend(string(k));
            map.extend(string(v));
        }
        let mut body = string(name);
        body.extend((map.len() as u32).to_le_bytes());
        body.extend(map);
        body
    }

    #[test]
    fn a_well_formed_record_parses() {
        let body = metadata("hairsys", &[("fps", "24"), ("a", "")]);
        match parse(op::METADATA, &body).unwrap() {
            Record::Metadata(m) => {
                assert_eq!(m.name, "hairsys");
                assert_eq!(m.metadata["fps"], "24");
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_string_length_past_the_body_is_refused_before_parsing() {
        let mut body = metadata("hairsys", &[("fps", "24")]);
        // The name's length: 4 GiB − 1.
        body[..4].copy_from_slice(&u32::MAX.to_le_bytes());
        let err = parse(op::METADATA, &body).unwrap_err().to_string();
        assert!(
            err.starts_with("metadata record") && err.contains("more needed"),
            "{err}"
        );
        // A map entry whose value runs past the map's own length.
        let mut body = metadata("hairsys", &[("fps", "24")]);
        let value_len = 4 + 7 + 4 + 4 + 3;
        body[value_len..value_len + 4].copy_from_slice(&100u32.to_le_bytes());
        assert!(parse(op::METADATA, &body).is_err());
    }

    #[test]
    fn arrays_must_hold_whole_entries() {
        // Message index: channel 1, 17 bytes of (u64, u64) entries.
        let mut body = 1u16.to_le_bytes().to_vec();
        body.extend(17u32.to_le_bytes());
        body.extend([0u8; 17]);
        let err = parse(op::MESSAGE_INDEX, &body).unwrap_err().to_string();
        assert!(err.contains("whole 16-byte entries"), "{err}");
    }

    #[test]
    fn records_stop_at_one_running_past_the_region() {
        let mut bytes = record(op::DATA_END, &[0; 4]);
        let mut long = record(op::DATA_END, &[0; 4]);
        long[1..9].copy_from_slice(&(1u64 << 40).to_le_bytes());
        bytes.extend(long);
        let records: Vec<_> = Records::new(&bytes).collect();
        assert_eq!(records.len(), 2);
        assert_eq!(records[0].as_ref().unwrap(), &(op::DATA_END, &[0u8; 4][..]));
        let err = records[1].as_ref().unwrap_err().to_string();
        assert!(
            err.contains("claims 1099511627776 bytes but only 4"),
            "{err}"
        );
    }

    fn chunk_header(compression: &str, uncompressed: &[u8]) -> ChunkHeader {
        ChunkHeader {
            message_start_time: 0,
            message_end_time: 0,
            uncompressed_size: uncompressed.len() as u64,
            uncompressed_crc: crc32fast::hash(uncompressed),
            compression: compression.into(),
            compressed_size: 0,
        }
    }

    #[test]
    fn compressed_chunks_decode_and_lying_sizes_are_refused() {
        let content: Vec<u8> = (0..10_000u32).flat_map(|i| (i % 7).to_le_bytes()).collect();
        let lz4_data = {
            let mut e = lz4::EncoderBuilder::new().build(Vec::new()).unwrap();
            std::io::Write::write_all(&mut e, &content).unwrap();
            e.finish().0
        };
        let zstd_data = zstd::encode_all(&content[..], 3).unwrap();
        for (codec, data) in [("lz4", &lz4_data), ("zstd", &zstd_data)] {
            let header = chunk_header(codec, &content);
            assert_eq!(chunk_content(&header, data).unwrap().as_ref(), &content[..]);
            // A size field of 1 TiB: refused from the compressed length, nothing allocated.
            let mut huge = header.clone();
            huge.uncompressed_size = 1 << 40;
            let err = chunk_content(&huge, data).unwrap_err().to_string();
            assert!(err.contains("more than"), "{codec}: {err}");
            // A size field a little too large or too small: the data decides.
            for size in [content.len() as u64 + 1, content.len() as u64 - 1] {
                let mut off = header.clone();
                off.uncompressed_size = size;
                let err = chunk_content(&off, data).unwrap_err().to_string();
                assert!(err.contains("decodes to"), "{codec}: {err}");
            }
            let mut crc = header.clone();
            crc.uncompressed_crc ^= 1;
            assert!(chunk_content(&crc, data)
                .unwrap_err()
                .to_string()
                .contains("CRC"));
        }
        let header = chunk_header("", &content);
        assert!(chunk_content(&header, &content).is_ok());
        assert!(chunk_content(&header, &content[1..]).is_err());
        let err = chunk_content(&chunk_header("brotli", &content), &content)
            .unwrap_err()
            .to_string();
        assert!(err.contains("\"brotli\""), "{err}");
    }
}
