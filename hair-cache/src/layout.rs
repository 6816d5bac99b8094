//! The byte format of a hairsys cache, format version 1.
//!
//! This page is the specification: a tool that knows MCAP (<https://mcap.dev/spec>) can read a
//! cache from it without this crate. Every integer and float is **little-endian**; floats are
//! IEEE-754. Units are SI: meters, seconds, meters per second.
//!
//! # The file
//!
//! One MCAP file per simulation run, written by [`crate::CacheWriter`]. While the run is going the
//! file is named `<path>.partial` ([`crate::partial_path`]); it is renamed to `<path>` only after
//! its summary has been written and synced to disk, so a file without the `.partial` suffix is a
//! complete cache. A `.partial` file has no summary section: its frames can be recovered by
//! scanning its chunks.
//!
//! Records, in file order:
//!
//! 1. **Header**: profile [`PROFILE`] (`"hairsys"`), library `"hair-cache/<crate version>"`.
//! 2. **Metadata** named [`METADATA_NAME`] (`"hairsys"`), a `map<string, string>`:
//!
//!    | key | value |
//!    |---|---|
//!    | [`KEY_FORMAT_VERSION`] `format_version` | `"1"` ([`FORMAT_VERSION`]); a reader refuses other versions |
//!    | [`KEY_FPS`] `fps` | frames per second, decimal, the shortest text that parses back to the same `f64` (`"24"`, `"29.97"`) |
//!    | [`KEY_FIRST_FRAME`] `first_frame` | the run's first frame number, decimal `u32` |
//!    | [`KEY_STRAND_COUNT`] `strand_count` | number of strands, decimal `u32` (equal to the layout's) |
//!    | [`KEY_POINT_COUNT`] `point_count` | number of points, decimal `u32` (equal to the layout's) |
//!    | [`KEY_SCENE_TOML`] `scene_toml` | the scene file's text (TOML) |
//!    | [`KEY_SCENE_HASH`] `scene_hash` | hash of the scene as hex digits, as given by the writer's caller |
//!    | [`EXTRA_PREFIX`]`<key>` (`extra.substeps`, …) | free key/values of the caller (solver components, substeps, …) |
//!
//! 3. **Attachment** named [`LAYOUT_ATTACHMENT_NAME`] (`"hairsys/layout.bin"`), media type
//!    [`LAYOUT_MEDIA_TYPE`] (`application/octet-stream`), log and create time 0: the strand
//!    layout, see [Layout attachment](#layout-attachment).
//! 4. Optionally, **attachment** named [`crate::rig::RIG_ATTACHMENT_NAME`]
//!    (`"hairsys/rig.bin"`), same media type and times: the [rig](#rig-attachment) the hair
//!    hangs on. A cache with it also has the rig channel below.
//! 5. **Chunks** (compression `""`, `"lz4"` or `"zstd"`, see [`crate::Compression`]), each
//!    followed by its Message Index record. The first chunk holds the Schema and the Channel
//!    records before the first frame; every chunk holds one or more consecutive frames.
//!    - Schema: name [`FRAME_SCHEMA_NAME`] (`"hairsys.Frame"`), encoding
//!      [`FRAME_SCHEMA_ENCODING`] (`"text/plain"`), data [`FRAME_SCHEMA_TEXT`]: a UTF-8
//!      description of the payload for humans and generic MCAP tools.
//!    - Channel: topic [`FRAME_TOPIC`] (`"/hairsys/frames"`), message encoding
//!      [`FRAME_MESSAGE_ENCODING`] (`"hairsys.frame.v1"`), no channel metadata.
//!    - One Message per frame, in increasing frame order: `sequence` = frame number,
//!      `log_time` = `publish_time` = frame time in nanoseconds ([`frame_time_ns`]), data: the
//!      [frame payload](#frame-payload).
//!    - With a rig: Schema [`crate::rig::RIG_SCHEMA_NAME`] (`"hairsys.RigFrame"`, encoding
//!      `"text/plain"`, data [`crate::rig::RIG_SCHEMA_TEXT`]) and Channel
//!      [`crate::rig::RIG_TOPIC`] (`"/hairsys/rig"`, message encoding `"hairsys.rig.v1"`), and
//!      beside every frame message, in the same chunk and at the same `log_time`, one message
//!      with the [rig frame payload](#rig-frame-payload).
//! 6. Data End, then the summary section (Schema, Channel, Statistics, Chunk Indexes,
//!    Attachment Index, Metadata Index), Summary Offsets and the Footer. Readers seek frames by
//!    `log_time` through the chunk indexes and message indexes.
//!
//! A run that writes no frame has no chunk, schema or channel.
//!
//! No wall-clock time or other varying value is written: the same inputs give a byte-identical
//! file (zstd is run single-threaded for that reason).
//!
//! # Frame time
//!
//! Frame `f` of a run at `fps` frames per second is at `t = f / fps` seconds (an `f64` division)
//! and is logged at `round(t × 10⁹)` nanoseconds (`f64` product, rounded half away from zero).
//! Frame numbers are `u32`, hence never negative, and frame times are limited to
//! [`MAX_TIME_NS`] (2⁵³ ns, about 104 days) so that the nanosecond time maps back to exactly
//! one frame number: `f = round(log_time × fps / 10⁹)`.
//!
//! # Layout attachment
//!
//! `S` strands, `P` points; strand `s` owns points `offsets[s] .. offsets[s+1]` and segments
//! `offsets[s] − s .. offsets[s+1] − s − 1` (segment `j` of a strand joins its points `j`, `j+1`).
//!
//! | offset (bytes) | type | count | content |
//! |---|---|---|---|
//! | 0 | `u32` | 1 | strand count `S` |
//! | 4 | `u32` | 1 | point count `P` |
//! | 8 | `u32` | `S + 1` | point offsets: `offsets[0] = 0`, strictly increasing, `offsets[S] = P` |
//! | 8 + 4(S+1) | `f32` | `P − S` | segment rest lengths, m |
//! | 8 + 4(S+1) + 4(P−S) | `f32` | `P` | point radii, m |
//!
//! Total `8 + 4(S + 1) + 4(P − S) + 4P` bytes.
//!
//! # Frame payload
//!
//! Message data on [`FRAME_TOPIC`], `P` points:
//!
//! | offset (bytes) | type | count | content |
//! |---|---|---|---|
//! | 0 | `u32` | 1 | format version, `1` |
//! | 4 | `u32` | 1 | frame number |
//! | 8 | `f64` | 1 | frame time, s (`frame / fps`) |
//! | 16 | `u32` | 1 | point count `P` |
//! | 20 | `f32` | `3P` | positions, m, world space, `x y z` interleaved per point |
//! | 20 + 12P | `f32` | `3P` | velocities, m/s, world space, `x y z` interleaved per point |
//!
//! Total `20 + 24P` bytes ([`frame_payload_len`]). Every value is finite: the writer refuses a
//! frame with a NaN or infinite coordinate.
//!
//! # Quantized frame payload
//!
//! A cache written with [`Precision::Quantized16`] (opt-in, **lossy**) stores its frames
//! differently; everything else in the file is as above. Its Schema is named [`FRAME_Q16_SCHEMA_NAME`] (`"hairsys.FrameQ16"`, encoding `"text/plain"`,
//! data [`FRAME_Q16_SCHEMA_TEXT`]) and its Channel (same topic [`FRAME_TOPIC`]) has message
//! encoding [`FRAME_Q16_MESSAGE_ENCODING`] (`"hairsys.frame.q16.v1"`). A file holds one frame
//! channel, so all its frames have the same encoding. Message data, `P` points:
//!
//! | offset (bytes) | type | count | content |
//! |---|---|---|---|
//! | 0 | `u32` | 1 | format version, `1` |
//! | 4 | `u32` | 1 | frame number |
//! | 8 | `f64` | 1 | frame time, s (`frame / fps`) |
//! | 16 | `u32` | 1 | point count `P` |
//! | 20 | `f32` | 3 | `pos_min`: smallest position `x y z` of the frame, m |
//! | 32 | `f32` | 3 | `pos_max`: largest position `x y z` of the frame, m |
//! | 44 | `f32` | 3 | `vel_min`: smallest velocity `x y z` of the frame, m/s |
//! | 56 | `f32` | 3 | `vel_max`: largest velocity `x y z` of the frame, m/s |
//! | 68 | `u16` | `3P` | quantized positions, `x y z` interleaved per point |
//! | 68 + 6P | `u16` | `3P` | quantized velocities, `x y z` interleaved per point |
//!
//! Total `68 + 12P` bytes ([`frame_q16_payload_len`]), half of the `f32` payload. The bounds are
//! finite with `min ≤ max` per axis (all zero when `P = 0`). A quantized value `q` of an axis with
//! bounds `min`, `max` decodes ([`dequantize`]) to
//!
//! ```text
//! value = min + q × (max − min) / 65535
//! ```
//!
//! evaluated in **`f64`** (`min`, `max` widened from `f32`; multiplication, then division, then
//! addition, each rounded to `f64`), then rounded to the nearest `f32`. An axis with
//! `max == min` decodes to `min`. The writer stores `q = round((v − min) / (max − min) × 65535)`
//! ([`quantize`], also in `f64`), the grid value nearest to `v`.
//!
//! **Error.** A decoded value differs from the written one by at most half a quantization step of
//! its axis, `(max − min) / 131070`, plus the final rounding to `f32` (half an `f32` ulp of the
//! value: 0.06 µm at 1 m). On a 2.97 m extent that is 22.7 µm; per-frame bounds make the step
//! follow the groom's extent in that frame, and velocities get the same relative precision over
//! their own range (one fast point coarsens every velocity of its frame). Sampling between frames
//! ([`crate::sample`]) interpolates the decoded values, so the interpolated result carries this
//! error too (Hermite sampling also interpolates the quantized velocities as tangents).

//!
//! # Rig attachment
//!
//! What outputs need beside the hair ([`crate::rig`]), `S` strands. Counts are `u32`, flags
//! `u32` 0 or 1; a *mesh* is `u32 V`, `u32 T`, `f32 positions[3V]` (m, body space), `u32
//! triangles[3T]` (vertex indices); a *pose* is `f32[7]`: translation `x y z` (m) and rotation
//! quaternion `i j k w` (unit).
//!
//! | field | type | content |
//! |---|---|---|
//! | version | `u32` | `1` |
//! | `P` | `u32` | points (equal to the layout's) |
//! | rest positions | `f32[3P]` | each point's rest position in its root frame, m |
//! | inverse masses | `f32[P]` | 1/kg; 0 for points held kinematically (roots, pins) |
//! | `S` | `u32` | strands (equal to the layout's) |
//! | anchors | `S` × 36 bytes | `u32` kind, then kind 0 (on the scalp): `u32` triangle, `f32` barycentric weights `[3]`, 12 zero bytes; kind 1 (in the scalp's body space): `f32` origin `[3]` (m), `f32` rotation `i j k w` |
//! | scalp | flag, then a mesh, flag + `f32 uv[2V]`, flag + `f32 rgb[3V]` (0–1) | the scalp at rest in its body space |
//! | scalp collider | flag + `f32` thickness m + `f32` friction | when the scalp collides with its own hair |
//! | `C` | `u32` | colliders |
//! | colliders | `C` × (`u32` kind, `f32` thickness m, `f32` friction, shape) | kind 0 sphere: `f32` radius; 1 capsule along body z: `f32` half height, `f32` radius; 2: a mesh |
//! | clump | flag + `f32[S]` | each strand's factor of its children's clump, 0–1 |
//! | curl | flag + `f32[S]` | each strand's factor of its children's curl radius, 0–1 |
//!
//! # Rig frame payload
//!
//! Message data on [`crate::rig::RIG_TOPIC`], for the frame of the same `log_time`:
//!
//! | field | type | content |
//! |---|---|---|
//! | version | `u32` | `1` |
//! | frame | `u32` | frame number |
//! | scalp body | pose | the scalp's body to world transform |
//! | scalp vertices | flag + `f32[3V]` | the deformed scalp (m, body space; `V` of the rig's scalp) when it deforms |
//! | `C` | `u32` | colliders (equal to the rig's) |
//! | colliders | `C` × (pose, flag + `f32[3V]`) | each collider's pose and, for a deforming mesh, its vertices (m, body space) |
//!
//! Every value is finite; a reader refuses counts that disagree with the rig.

use std::collections::BTreeMap;

use hair_core::StrandSet;
use thiserror::Error;

use crate::writer::Precision;
use nalgebra::Vector3;

/// Version of this byte format, stored in the metadata and in every frame payload.
pub const FORMAT_VERSION: u32 = 1;
/// MCAP header profile of a hairsys cache.
pub const PROFILE: &str = "hairsys";
/// MCAP header library string.
pub const LIBRARY: &str = concat!("hair-cache/", env!("CARGO_PKG_VERSION"));
/// Name of the metadata record holding the run's settings.
pub const METADATA_NAME: &str = "hairsys";
/// Metadata key: format version (decimal).
pub const KEY_FORMAT_VERSION: &str = "format_version";
/// Metadata key: frames per second (decimal `f64`).
pub const KEY_FPS: &str = "fps";
/// Metadata key: the run's first frame number (decimal `u32`).
pub const KEY_FIRST_FRAME: &str = "first_frame";
/// Metadata key: number of strands (decimal `u32`).
pub const KEY_STRAND_COUNT: &str = "strand_count";
/// Metadata key: number of points (decimal `u32`).
pub const KEY_POINT_COUNT: &str = "point_count";
/// Metadata key: text of the scene file (TOML).
pub const KEY_SCENE_TOML: &str = "scene_toml";
/// Metadata key: hash of the scene, hex digits.
pub const KEY_SCENE_HASH: &str = "scene_hash";
/// Prefix of the caller's free metadata keys: `extra` key `k` is stored as `extra.k`.
pub const EXTRA_PREFIX: &str = "extra.";
/// Name of the attachment holding the strand layout.
pub const LAYOUT_ATTACHMENT_NAME: &str = "hairsys/layout.bin";
/// Media type of the layout attachment.
pub const LAYOUT_MEDIA_TYPE: &str = "application/octet-stream";
/// Topic of the frame channel.
pub const FRAME_TOPIC: &str = "/hairsys/frames";
/// Message encoding of the frame channel.
pub const FRAME_MESSAGE_ENCODING: &str = "hairsys.frame.v1";
/// Name of the frame channel's schema.
pub const FRAME_SCHEMA_NAME: &str = "hairsys.Frame";
/// Encoding of the frame channel's schema: its data is plain UTF-8 text.
pub const FRAME_SCHEMA_ENCODING: &str = "text/plain";
/// Data of the frame channel's schema: a description of the payload.
pub const FRAME_SCHEMA_TEXT: &str = "hairsys frame, format version 1, little-endian:\n\
u32 format_version (1)\n\
u32 frame\n\
f64 time_s (frame / fps)\n\
u32 point_count P\n\
f32 positions[3P] (m, world, x y z per point)\n\
f32 velocities[3P] (m/s, world, x y z per point)\n\
Strand layout (offsets, rest lengths, radii): attachment hairsys/layout.bin.\n";
/// Message encoding of the frame channel of a [quantized](self#quantized-frame-payload) cache.
pub const FRAME_Q16_MESSAGE_ENCODING: &str = "hairsys.frame.q16.v1";
/// Name of the frame channel's schema in a [quantized](self#quantized-frame-payload) cache.
pub const FRAME_Q16_SCHEMA_NAME: &str = "hairsys.FrameQ16";
/// Data of the quantized frame channel's schema: a description of the payload.
pub const FRAME_Q16_SCHEMA_TEXT: &str =
    "hairsys quantized frame, format version 1, little-endian:\n\
u32 format_version (1)\n\
u32 frame\n\
f64 time_s (frame / fps)\n\
u32 point_count P\n\
f32 pos_min[3], f32 pos_max[3] (m, per axis over the frame's points)\n\
f32 vel_min[3], f32 vel_max[3] (m/s, per axis over the frame's points)\n\
u16 positions[3P] (x y z per point)\n\
u16 velocities[3P] (x y z per point)\n\
value = min + q * (max - min) / 65535, in f64, then rounded to f32; max == min decodes to min.\n\
Error: at most (max - min) / 131070 per axis, plus the f32 rounding.\n\
Strand layout (offsets, rest lengths, radii): attachment hairsys/layout.bin.\n";
/// Bytes of the quantized frame payload before the quantized positions.
pub const FRAME_Q16_HEADER_LEN: usize = 68;
/// Bytes per point in a quantized frame payload: 3 `u16` positions and 3 `u16` velocities.
pub const FRAME_Q16_BYTES_PER_POINT: usize = 12;
/// Bytes of the frame payload before the positions.
pub const FRAME_HEADER_LEN: usize = 20;
/// Bytes per point in a frame payload: 3 `f32` positions and 3 `f32` velocities.
pub const FRAME_BYTES_PER_POINT: usize = 24;
/// Largest frame time, ns (2⁵³): below it `f64` holds every nanosecond exactly.
pub const MAX_TIME_NS: u64 = 1 << 53;

/// Strand layout of a cache: which points belong to which strand, segment rest lengths and point
/// radii. Stored once per file, in the [layout attachment](self#layout-attachment).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CacheLayout {
    /// Point offsets: strand `s` owns points `offsets[s]..offsets[s + 1]`; `offsets[0] = 0`,
    /// strictly increasing; the last entry is the point count.
    pub offsets: Vec<u32>,
    /// Segment rest lengths, m: `point count − strand count` values, strand after strand.
    pub rest_lengths: Vec<f32>,
    /// Point radii (collision and render width), m: one per point.
    pub radii: Vec<f32>,
}

impl CacheLayout {
    /// The layout of `strands`: its offsets, segment rest lengths (m) and point radii (m).
    pub fn of(strands: &StrandSet) -> Self {
        let offsets = if strands.offsets().is_empty() {
            vec![0]
        } else {
            strands.offsets().to_vec()
        };
        Self {
            offsets,
            rest_lengths: strands.rest_lengths().to_vec(),
            radii: strands.radii().to_vec(),
        }
    }

    /// Number of strands.
    pub fn strand_count(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Number of points (the last offset).
    pub fn point_count(&self) -> usize {
        self.offsets.last().map_or(0, |&p| p as usize)
    }

    /// Index of the strand that owns point `point`, if the point exists.
    pub fn strand_of(&self, point: usize) -> Option<usize> {
        if point >= self.point_count() {
            return None;
        }
        Some(self.offsets.partition_point(|&o| o as usize <= point) - 1)
    }

    /// Checks the invariants of the [layout attachment](self#layout-attachment); the error says
    /// what is wrong.
    pub(crate) fn validate(&self) -> Result<(), FormatError> {
        let Some(&first) = self.offsets.first() else {
            return Err(FormatError::NoOffsets);
        };
        if first != 0 {
            return Err(FormatError::FirstOffset { first });
        }
        if let Some(strand) = self.offsets.windows(2).position(|w| w[1] <= w[0]) {
            return Err(FormatError::EmptyStrand {
                strand,
                start: self.offsets[strand],
                end: self.offsets[strand + 1],
            });
        }
        let (strands, points) = (self.strand_count(), self.point_count());
        if self.rest_lengths.len() != points - strands {
            return Err(FormatError::RestLengthCount {
                found: self.rest_lengths.len(),
                points,
                strands,
            });
        }
        if self.radii.len() != points {
            return Err(FormatError::RadiusCount {
                found: self.radii.len(),
                points,
            });
        }
        if let Some(segment) = self.rest_lengths.iter().position(|l| !l.is_finite()) {
            return Err(FormatError::RestLength {
                segment,
                value: self.rest_lengths[segment],
            });
        }
        if let Some(point) = self.radii.iter().position(|r| !r.is_finite()) {
            return Err(FormatError::Radius {
                point,
                value: self.radii[point],
            });
        }
        Ok(())
    }

    /// The attachment bytes. The layout must be valid ([`CacheLayout::validate`]).
    pub(crate) fn encode(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(
            8 + 4 * (self.offsets.len() + self.rest_lengths.len() + self.radii.len()),
        );
        out.extend_from_slice(&(self.strand_count() as u32).to_le_bytes());
        out.extend_from_slice(&(self.point_count() as u32).to_le_bytes());
        for o in &self.offsets {
            out.extend_from_slice(&o.to_le_bytes());
        }
        for v in self.rest_lengths.iter().chain(&self.radii) {
            out.extend_from_slice(&v.to_le_bytes());
        }
        out
    }

    /// Parses and validates attachment bytes.
    pub(crate) fn decode(bytes: &[u8]) -> Result<Self, FormatError> {
        let mut r = LeReader::new(bytes);
        let strands = r.u32()? as usize;
        let points = r.u32()? as usize;
        if points < strands {
            return Err(FormatError::FewerPoints { points, strands });
        }
        let expected = 8 + 4 * (strands + 1) + 4 * (points - strands) + 4 * points;
        if bytes.len() != expected {
            return Err(FormatError::LayoutLength {
                len: bytes.len(),
                strands,
                points,
                expected,
            });
        }
        let offsets = (0..=strands)
            .map(|_| r.u32())
            .collect::<Result<Vec<_>, _>>()?;
        let rest_lengths = (0..points - strands)
            .map(|_| r.f32())
            .collect::<Result<Vec<_>, _>>()?;
        let radii = (0..points)
            .map(|_| r.f32())
            .collect::<Result<Vec<_>, _>>()?;
        let layout = Self {
            offsets,
            rest_lengths,
            radii,
        };
        layout.validate()?;
        if layout.point_count() != points {
            return Err(FormatError::LastOffset {
                points,
                last: layout.point_count(),
            });
        }
        Ok(layout)
    }
}

/// Settings of a run stored in the cache's metadata record.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CacheHeader {
    /// Frames per second: frame `f` is at `f / fps` seconds. Finite, in (0, 10⁶].
    pub fps: f64,
    /// Frame number of the run's first frame (its initial state); written frames are ≥ it.
    pub first_frame: u32,
    /// Text of the scene file (TOML) that produced the run.
    pub scene_toml: String,
    /// Hash of the scene, hex digits (computed by the caller, e.g. SHA-256 of the scene text).
    pub scene_hash: String,
    /// Free key/values of the caller (solver components, substeps, …), stored under
    /// [`EXTRA_PREFIX`]. Keys are non-empty.
    pub extra: BTreeMap<String, String>,
}

impl CacheHeader {
    /// Checks the header; the error says what is wrong and what to use instead.
    pub(crate) fn validate(&self) -> Result<(), FormatError> {
        if !(self.fps.is_finite() && self.fps > 0.0 && self.fps <= 1e6) {
            return Err(FormatError::Fps { fps: self.fps });
        }
        if self.scene_hash.is_empty() || !self.scene_hash.chars().all(|c| c.is_ascii_hexdigit()) {
            return Err(FormatError::SceneHash {
                hash: self.scene_hash.clone(),
            });
        }
        if self.extra.contains_key("") {
            return Err(FormatError::EmptyExtraKey);
        }
        Ok(())
    }

    /// The metadata map of this header for a run with `layout`.
    pub(crate) fn to_metadata(&self, layout: &CacheLayout) -> BTreeMap<String, String> {
        let mut map: BTreeMap<String, String> = [
            (KEY_FORMAT_VERSION, FORMAT_VERSION.to_string()),
            (KEY_FPS, self.fps.to_string()),
            (KEY_FIRST_FRAME, self.first_frame.to_string()),
            (KEY_STRAND_COUNT, layout.strand_count().to_string()),
            (KEY_POINT_COUNT, layout.point_count().to_string()),
            (KEY_SCENE_TOML, self.scene_toml.clone()),
            (KEY_SCENE_HASH, self.scene_hash.clone()),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_string(), v))
        .collect();
        for (k, v) in &self.extra {
            map.insert(format!("{EXTRA_PREFIX}{k}"), v.clone());
        }
        map
    }
}

/// What a metadata map holds besides the [`CacheHeader`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct MetadataCounts {
    pub strands: usize,
    pub points: usize,
}

/// Why a metadata map could not be read.
#[derive(Debug, Clone, PartialEq, Error)]
pub(crate) enum MetadataError {
    /// `format_version` is missing or not [`FORMAT_VERSION`]; holds the value found.
    #[error("format version {0:?}, expected {FORMAT_VERSION}")]
    Version(String),
    /// A key is missing.
    #[error("metadata key `{key}` is missing")]
    Missing { key: &'static str },
    /// A value does not parse.
    #[error("metadata `{key}` = {value:?} is not valid")]
    Invalid { key: &'static str, value: String },
    /// The values parse but are not a valid header.
    #[error(transparent)]
    Header(#[from] FormatError),
}

/// Parses a metadata map into a header and the counts it declares.
pub(crate) fn header_from_metadata(
    map: &BTreeMap<String, String>,
) -> Result<(CacheHeader, MetadataCounts), MetadataError> {
    let version = map
        .get(KEY_FORMAT_VERSION)
        .map_or("(missing)", String::as_str);
    if version != FORMAT_VERSION.to_string() {
        return Err(MetadataError::Version(version.to_string()));
    }
    let get = |key: &'static str| map.get(key).ok_or(MetadataError::Missing { key });
    fn parse<T: std::str::FromStr>(key: &'static str, value: &str) -> Result<T, MetadataError> {
        value.parse().map_err(|_| MetadataError::Invalid {
            key,
            value: value.to_string(),
        })
    }
    let header = CacheHeader {
        fps: parse(KEY_FPS, get(KEY_FPS)?)?,
        first_frame: parse(KEY_FIRST_FRAME, get(KEY_FIRST_FRAME)?)?,
        scene_toml: get(KEY_SCENE_TOML)?.clone(),
        scene_hash: get(KEY_SCENE_HASH)?.clone(),
        extra: map
            .iter()
            .filter_map(|(k, v)| Some((k.strip_prefix(EXTRA_PREFIX)?.to_string(), v.clone())))
            .collect(),
    };
    header.validate()?;
    let counts = MetadataCounts {
        strands: parse(KEY_STRAND_COUNT, get(KEY_STRAND_COUNT)?)?,
        points: parse(KEY_POINT_COUNT, get(KEY_POINT_COUNT)?)?,
    };
    Ok((header, counts))
}

/// One frame of a cache.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Frame number.
    pub frame: u32,
    /// Frame time, s (`frame / fps`).
    pub time: f64,
    /// Point positions, m, world space, in layout order.
    pub positions: Vec<Vector3<f32>>,
    /// Point velocities, m/s, world space, in layout order.
    pub velocities: Vec<Vector3<f32>>,
}

/// Time of frame `frame` at `fps` frames per second, s.
pub fn frame_time_s(frame: u32, fps: f64) -> f64 {
    f64::from(frame) / fps
}

/// `log_time` of frame `frame` at `fps` frames per second, ns; `None` above [`MAX_TIME_NS`].
pub fn frame_time_ns(frame: u32, fps: f64) -> Option<u64> {
    let ns = (frame_time_s(frame, fps) * 1e9).round();
    // The bound check comes first, so the cast below is exact.
    (ns.is_finite() && ns >= 0.0 && ns <= MAX_TIME_NS as f64).then_some(ns as u64)
}

/// The frame number whose `log_time` at `fps` is exactly `ns`, if there is one.
pub fn frame_at_time_ns(ns: u64, fps: f64) -> Option<u32> {
    let f = (ns as f64 * fps / 1e9).round();
    if !(f >= 0.0 && f <= f64::from(u32::MAX)) {
        return None;
    }
    let frame = f as u32;
    (frame_time_ns(frame, fps) == Some(ns)).then_some(frame)
}

/// Length of the payload of a frame of `points` points, bytes.
pub fn frame_payload_len(points: usize) -> usize {
    FRAME_HEADER_LEN + FRAME_BYTES_PER_POINT * points
}

/// Writes the payload of one frame into `out` (cleared first). Slices have equal lengths.
pub(crate) fn encode_frame(
    out: &mut Vec<u8>,
    frame: u32,
    time: f64,
    positions: &[Vector3<f32>],
    velocities: &[Vector3<f32>],
) {
    out.clear();
    out.reserve(frame_payload_len(positions.len()));
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&frame.to_le_bytes());
    out.extend_from_slice(&time.to_le_bytes());
    out.extend_from_slice(&(positions.len() as u32).to_le_bytes());
    for v in positions.iter().chain(velocities) {
        for c in v.iter() {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
}

/// Reads the header shared by both frame encodings (version, frame, time, point count) and
/// checks it and the payload length (`expected_len` bytes) against a layout of `points` points.
/// Returns the frame number and time (s); `encoding` names the encoding in errors.
fn decode_frame_header(
    r: &mut LeReader,
    encoding: &'static str,
    points: usize,
    expected_len: usize,
) -> Result<(u32, f64), FormatError> {
    let len = r.bytes.len();
    let version = r.u32()?;
    if version != FORMAT_VERSION {
        return Err(FormatError::FrameVersion { encoding, version });
    }
    let frame = r.u32()?;
    let time = r.f64()?;
    let count = r.u32()? as usize;
    if count != points {
        return Err(FormatError::FramePoints {
            frame,
            count,
            points,
        });
    }
    if len != expected_len {
        return Err(FormatError::FrameLength {
            encoding,
            frame,
            len,
            points,
            expected: expected_len,
        });
    }
    Ok((frame, time))
}

/// Parses a frame payload of a cache with `points` points.
pub(crate) fn decode_frame(bytes: &[u8], points: usize) -> Result<Frame, FormatError> {
    let mut r = LeReader::new(bytes);
    let (frame, time) = decode_frame_header(&mut r, "frame", points, frame_payload_len(points))?;
    let vectors = |data: &[u8]| -> Vec<Vector3<f32>> {
        data.chunks_exact(12)
            .map(|c| {
                let f = |i: usize| f32::from_le_bytes([c[i], c[i + 1], c[i + 2], c[i + 3]]);
                Vector3::new(f(0), f(4), f(8))
            })
            .collect()
    };
    let body = &bytes[FRAME_HEADER_LEN..];
    let (pos, vel) = body.split_at(12 * points);
    Ok(Frame {
        frame,
        time,
        positions: vectors(pos),
        velocities: vectors(vel),
    })
}

/// Length of the [quantized payload](self#quantized-frame-payload) of a frame of `points`
/// points, bytes.
pub fn frame_q16_payload_len(points: usize) -> usize {
    FRAME_Q16_HEADER_LEN + FRAME_Q16_BYTES_PER_POINT * points
}

/// The quantized value of `v` on an axis with bounds `min ≤ v ≤ max`:
/// `round((v − min) / (max − min) × 65535)` in `f64`; `0` when `max == min`.
pub fn quantize(v: f32, min: f32, max: f32) -> u16 {
    let range = f64::from(max) - f64::from(min);
    if range <= 0.0 {
        return 0;
    }
    let q = ((f64::from(v) - f64::from(min)) / range * 65535.0).round();
    // In range for `min ≤ v ≤ max`; the clamp makes the cast exact otherwise too.
    q.clamp(0.0, 65535.0) as u16
}

/// The value of quantized `q` on an axis with bounds `min`, `max`:
/// `min + q × (max − min) / 65535`, in `f64`, rounded to `f32` (`min` when `max == min`).
pub fn dequantize(q: u16, min: f32, max: f32) -> f32 {
    let (min, max) = (f64::from(min), f64::from(max));
    (min + f64::from(q) * (max - min) / 65535.0) as f32
}

/// Half a quantization step of an axis with bounds `min`, `max`: `(max − min) / 131070`, the
/// largest error of [`quantize`] then [`dequantize`] before the final rounding to `f32`.
pub fn quantization_error(min: f32, max: f32) -> f64 {
    (f64::from(max) - f64::from(min)) / 131070.0
}

/// Per-axis smallest and largest coordinates of `values`; zeros when it is empty.
pub fn axis_bounds(values: &[Vector3<f32>]) -> ([f32; 3], [f32; 3]) {
    let Some(first) = values.first() else {
        return ([0.0; 3], [0.0; 3]);
    };
    let (mut min, mut max) = ([first.x, first.y, first.z], [first.x, first.y, first.z]);
    for v in values {
        for axis in 0..3 {
            min[axis] = min[axis].min(v[axis]);
            max[axis] = max[axis].max(v[axis]);
        }
    }
    (min, max)
}

/// Writes the [quantized payload](self#quantized-frame-payload) of one frame into `out` (cleared
/// first). Slices have equal lengths and finite values.
pub(crate) fn encode_frame_q16(
    out: &mut Vec<u8>,
    frame: u32,
    time: f64,
    positions: &[Vector3<f32>],
    velocities: &[Vector3<f32>],
) {
    out.clear();
    out.reserve(frame_q16_payload_len(positions.len()));
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&frame.to_le_bytes());
    out.extend_from_slice(&time.to_le_bytes());
    out.extend_from_slice(&(positions.len() as u32).to_le_bytes());
    let bounds = [axis_bounds(positions), axis_bounds(velocities)];
    for (min, max) in &bounds {
        for c in min.iter().chain(max) {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
    for (values, (min, max)) in [positions, velocities].into_iter().zip(&bounds) {
        for v in values {
            for axis in 0..3 {
                out.extend_from_slice(&quantize(v[axis], min[axis], max[axis]).to_le_bytes());
            }
        }
    }
}

/// Parses a [quantized frame payload](self#quantized-frame-payload) of a cache with `points`
/// points.
pub(crate) fn decode_frame_q16(bytes: &[u8], points: usize) -> Result<Frame, FormatError> {
    let mut r = LeReader::new(bytes);
    let (frame, time) = decode_frame_header(
        &mut r,
        "quantized frame",
        points,
        frame_q16_payload_len(points),
    )?;
    let mut bounds = [[0f32; 3]; 4];
    for b in &mut bounds {
        for c in b.iter_mut() {
            *c = r.f32()?;
        }
    }
    for (quantity, min, max) in [
        ("position", bounds[0], bounds[1]),
        ("velocity", bounds[2], bounds[3]),
    ] {
        if (0..3).any(|a| !(min[a].is_finite() && max[a].is_finite() && min[a] <= max[a])) {
            return Err(FormatError::QuantizedBounds {
                frame,
                quantity,
                min,
                max,
            });
        }
    }
    let vectors = |data: &[u8], min: [f32; 3], max: [f32; 3]| -> Vec<Vector3<f32>> {
        data.chunks_exact(6)
            .map(|c| {
                let q = |a: usize| u16::from_le_bytes([c[2 * a], c[2 * a + 1]]);
                Vector3::new(
                    dequantize(q(0), min[0], max[0]),
                    dequantize(q(1), min[1], max[1]),
                    dequantize(q(2), min[2], max[2]),
                )
            })
            .collect()
    };
    let body = &bytes[FRAME_Q16_HEADER_LEN..];
    let (pos, vel) = body.split_at(6 * points);
    Ok(Frame {
        frame,
        time,
        positions: vectors(pos, bounds[0], bounds[1]),
        velocities: vectors(vel, bounds[2], bounds[3]),
    })
}

/// Parses a frame payload of `precision` (the channel's message encoding).
pub(crate) fn decode_frame_as(
    precision: Precision,
    bytes: &[u8],
    points: usize,
) -> Result<Frame, FormatError> {
    match precision {
        Precision::F32 => decode_frame(bytes, points),
        Precision::Quantized16 => decode_frame_q16(bytes, points),
    }
}

/// Reads little-endian values from a byte slice, failing (not panicking) at its end.
pub(crate) struct LeReader<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> LeReader<'a> {
    /// A reader at the start of `bytes`.
    pub(crate) fn new(bytes: &'a [u8]) -> Self {
        Self { bytes, pos: 0 }
    }

    /// The next `n` bytes.
    pub(crate) fn take(&mut self, n: usize) -> Result<&'a [u8], Truncated> {
        let end = self
            .pos
            .checked_add(n)
            .filter(|&end| end <= self.bytes.len())
            .ok_or(Truncated {
                len: self.bytes.len(),
                needed: n,
                at: self.pos,
            })?;
        let out = &self.bytes[self.pos..end];
        self.pos = end;
        Ok(out)
    }

    fn array<const N: usize>(&mut self) -> Result<[u8; N], Truncated> {
        let mut out = [0; N];
        out.copy_from_slice(self.take(N)?);
        Ok(out)
    }

    /// Bytes not read yet.
    pub(crate) fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    /// The next `u32`.
    pub(crate) fn u32(&mut self) -> Result<u32, Truncated> {
        self.array().map(u32::from_le_bytes)
    }

    /// The next `u64`.
    pub(crate) fn u64(&mut self) -> Result<u64, Truncated> {
        self.array().map(u64::from_le_bytes)
    }

    /// The next `f32`.
    pub(crate) fn f32(&mut self) -> Result<f32, Truncated> {
        self.array().map(f32::from_le_bytes)
    }

    /// The next `f64`.
    pub(crate) fn f64(&mut self) -> Result<f64, Truncated> {
        self.array().map(f64::from_le_bytes)
    }
}

/// Bytes that end before the value being read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
#[error("record ends after {len} bytes, {needed} more needed at byte {at}")]
pub struct Truncated {
    /// Length of the bytes, bytes.
    pub len: usize,
    /// Bytes the value needs.
    pub needed: usize,
    /// Offset of the value, bytes.
    pub at: usize,
}

/// Why a layout attachment, a header or a frame payload breaks the format this page specifies.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FormatError {
    /// The bytes end before a value.
    #[error(transparent)]
    Truncated(#[from] Truncated),
    /// The layout has no offsets at all.
    #[error("the layout has no offsets; build it with CacheLayout::of")]
    NoOffsets,
    /// The first offset is not 0.
    #[error("offsets[0] is {first}; it must be 0")]
    FirstOffset {
        /// The first offset found.
        first: u32,
    },
    /// Offsets do not strictly increase: a strand has no point.
    #[error(
        "strand {strand} has no point (offsets[{strand}] = {start}, offsets[{}] = {end}); \
         offsets must strictly increase",
        .strand + 1
    )]
    EmptyStrand {
        /// The strand.
        strand: usize,
        /// Its first point's offset.
        start: u32,
        /// The next strand's first point's offset.
        end: u32,
    },
    /// Not one rest length per segment.
    #[error(
        "{found} rest lengths for {points} points in {strands} strands; there must be one per \
         segment ({})",
        .points - .strands
    )]
    RestLengthCount {
        /// Number of rest lengths given.
        found: usize,
        /// Number of points of the layout.
        points: usize,
        /// Number of strands of the layout.
        strands: usize,
    },
    /// Not one radius per point.
    #[error("{found} radii for {points} points; there must be one per point")]
    RadiusCount {
        /// Number of radii given.
        found: usize,
        /// Number of points of the layout.
        points: usize,
    },
    /// A rest length is not finite.
    #[error("rest length of segment {segment} is {value}")]
    RestLength {
        /// The segment.
        segment: usize,
        /// Its rest length, m.
        value: f32,
    },
    /// A radius is not finite.
    #[error("radius of point {point} is {value}")]
    Radius {
        /// The point.
        point: usize,
        /// Its radius, m.
        value: f32,
    },
    /// The attachment declares fewer points than strands.
    #[error("{points} points for {strands} strands")]
    FewerPoints {
        /// Number of points declared.
        points: usize,
        /// Number of strands declared.
        strands: usize,
    },
    /// The attachment's length does not match the counts it declares.
    #[error(
        "layout attachment has {len} bytes; {strands} strands and {points} points need \
         {expected}"
    )]
    LayoutLength {
        /// Length of the attachment, bytes.
        len: usize,
        /// Number of strands declared.
        strands: usize,
        /// Number of points declared.
        points: usize,
        /// Length those counts need, bytes.
        expected: usize,
    },
    /// The declared point count is not the last offset.
    #[error("layout says {points} points but its last offset is {last}")]
    LastOffset {
        /// Number of points declared.
        points: usize,
        /// The last offset.
        last: usize,
    },
    /// The frame rate is not finite or not in (0, 10⁶].
    #[error("fps is {fps}; use a frame rate in (0, 1e6] frames per second")]
    Fps {
        /// The frame rate given, frames per second.
        fps: f64,
    },
    /// The scene hash is empty or not hex digits.
    #[error("scene hash {hash:?} is not a hex string; pass the hex digits of the scene's hash")]
    SceneHash {
        /// The hash given.
        hash: String,
    },
    /// An extra metadata key is empty.
    #[error("an extra metadata key is empty; give every extra value a name")]
    EmptyExtraKey,
    /// A frame payload has another format version.
    #[error("{encoding} payload has format version {version}, expected {FORMAT_VERSION}")]
    FrameVersion {
        /// `"frame"` or `"quantized frame"`.
        encoding: &'static str,
        /// The version found.
        version: u32,
    },
    /// A frame payload's point count is not the layout's.
    #[error("frame {frame} has {count} points, the layout {points}")]
    FramePoints {
        /// The frame.
        frame: u32,
        /// Number of points it declares.
        count: usize,
        /// Number of points of the layout.
        points: usize,
    },
    /// A frame payload's length does not match its point count.
    #[error("{encoding} {frame} payload has {len} bytes, {points} points need {expected}")]
    FrameLength {
        /// `"frame"` or `"quantized frame"`.
        encoding: &'static str,
        /// The frame.
        frame: u32,
        /// Length of the payload, bytes.
        len: usize,
        /// Number of points of the layout.
        points: usize,
        /// Length those points need, bytes.
        expected: usize,
    },
    /// A quantized frame's bounds are not finite or a minimum is above its maximum.
    #[error(
        "quantized frame {frame} has {quantity} bounds {min:?}..{max:?}; they must be finite \
         with min <= max"
    )]
    QuantizedBounds {
        /// The frame.
        frame: u32,
        /// `"position"` (m) or `"velocity"` (m/s).
        quantity: &'static str,
        /// The per-axis minima.
        min: [f32; 3],
        /// The per-axis maxima.
        max: [f32; 3],
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layout() -> CacheLayout {
        CacheLayout {
            offsets: vec![0, 3, 5],
            rest_lengths: vec![0.1, 0.2, 0.3],
            radii: vec![1e-3, 2e-3, 3e-3, 4e-3, 5e-3],
        }
    }

    #[test]
    fn layout_bytes_follow_the_documented_table() {
        let bytes = layout().encode();
        assert_eq!(bytes.len(), 8 + 4 * 3 + 4 * 3 + 4 * 5);
        assert_eq!(&bytes[0..8], &[2, 0, 0, 0, 5, 0, 0, 0]);
        assert_eq!(&bytes[8..20], &[0, 0, 0, 0, 3, 0, 0, 0, 5, 0, 0, 0]);
        assert_eq!(&bytes[20..24], &0.1f32.to_le_bytes());
        assert_eq!(CacheLayout::decode(&bytes), Ok(layout()));
        assert_eq!(layout().strand_of(4), Some(1));
        assert_eq!(layout().strand_of(2), Some(0));
        assert_eq!(layout().strand_of(5), None);
    }

    #[test]
    fn truncated_layout_is_refused() {
        let bytes = layout().encode();
        let err = CacheLayout::decode(&bytes[..bytes.len() - 1]).unwrap_err();
        assert!(err.to_string().contains("bytes"), "{err}");
    }

    #[test]
    fn empty_strand_is_refused() {
        let mut l = layout();
        l.offsets = vec![0, 3, 3, 5];
        assert!(l
            .validate()
            .unwrap_err()
            .to_string()
            .contains("strand 1 has no point"));
    }

    #[test]
    fn frame_payload_follows_the_documented_table() {
        let p = [Vector3::new(1.0f32, 2.0, 3.0)];
        let v = [Vector3::new(-1.0f32, 0.5, 0.25)];
        let mut out = Vec::new();
        encode_frame(&mut out, 7, 7.0 / 24.0, &p, &v);
        assert_eq!(out.len(), frame_payload_len(1));
        assert_eq!(&out[0..8], &[1, 0, 0, 0, 7, 0, 0, 0]);
        assert_eq!(&out[8..16], &(7.0f64 / 24.0).to_le_bytes());
        assert_eq!(&out[16..20], &[1, 0, 0, 0]);
        assert_eq!(&out[20..24], &1.0f32.to_le_bytes());
        assert_eq!(&out[32..36], &(-1.0f32).to_le_bytes());
        let frame = decode_frame(&out, 1).unwrap();
        assert_eq!(
            (frame.frame, frame.positions[0], frame.velocities[0]),
            (7, p[0], v[0])
        );
        assert!(decode_frame(&out, 2).is_err());
        assert!(decode_frame(&out[..out.len() - 1], 1).is_err());
    }

    #[test]
    fn quantized_frame_payload_follows_the_documented_table() {
        let p = [
            Vector3::new(1.0f32, 2.0, 3.0),
            Vector3::new(3.0f32, 2.0, -1.0),
        ];
        let v = [
            Vector3::new(-1.0f32, 0.5, 0.25),
            Vector3::new(1.0f32, 0.5, 0.0),
        ];
        let mut out = Vec::new();
        encode_frame_q16(&mut out, 7, 7.0 / 24.0, &p, &v);
        assert_eq!(out.len(), frame_q16_payload_len(2));
        assert_eq!(out.len(), 68 + 24);
        assert_eq!(&out[0..8], &[1, 0, 0, 0, 7, 0, 0, 0]);
        assert_eq!(&out[8..16], &(7.0f64 / 24.0).to_le_bytes());
        assert_eq!(&out[16..20], &[2, 0, 0, 0]);
        let f = |at: usize| f32::from_le_bytes(out[at..at + 4].try_into().unwrap());
        let bounds: Vec<f32> = (0..12).map(|i| f(20 + 4 * i)).collect();
        assert_eq!(
            bounds,
            [1.0, 2.0, -1.0, 3.0, 2.0, 3.0, -1.0, 0.5, 0.0, 1.0, 0.5, 0.25]
        );
        let q = |at: usize| u16::from_le_bytes([out[at], out[at + 1]]);
        // Positions: x of point 0 is the x minimum, of point 1 the maximum; y has max == min.
        assert_eq!([q(68), q(70), q(72)], [0, 0, 65535]);
        assert_eq!([q(74), q(76), q(78)], [65535, 0, 0]);
        // Velocities start at 68 + 6P.
        assert_eq!([q(80), q(82), q(84)], [0, 0, 65535]);
        assert_eq!([q(86), q(88), q(90)], [65535, 0, 0]);
        let frame = decode_frame_q16(&out, 2).unwrap();
        assert_eq!((frame.frame, frame.time), (7, 7.0 / 24.0));
        // Extremes and flat axes decode exactly.
        assert_eq!(frame.positions, p);
        assert_eq!(frame.velocities, v);
        assert_eq!(decode_frame_as(Precision::Quantized16, &out, 2), Ok(frame));
        assert!(decode_frame_q16(&out, 3).is_err());
        assert!(decode_frame_q16(&out[..out.len() - 1], 2).is_err());
        assert!(decode_frame(&out, 2).is_err());
        // A min above its max is refused.
        let mut bad = out.clone();
        bad[20..24].copy_from_slice(&5.0f32.to_le_bytes());
        assert!(decode_frame_q16(&bad, 2)
            .unwrap_err()
            .to_string()
            .contains("bounds"));
    }

    #[test]
    fn quantization_is_within_half_a_step() {
        assert_eq!(dequantize(0, -1.5, 1.47), -1.5);
        assert_eq!(dequantize(65535, -1.5, 1.47), 1.47);
        assert_eq!(dequantize(1234, 0.25, 0.25), 0.25);
        assert_eq!(quantize(0.25, 0.25, 0.25), 0);
        assert_eq!(quantization_error(-1.5, 1.47), 2.97f32 as f64 / 131070.0);
        let (min, max) = (-1.5f32, 1.47f32);
        for i in 0..10_000 {
            let v = min + (max - min) * (i as f32 / 9999.0).min(1.0);
            let v = v.clamp(min, max);
            let back = dequantize(quantize(v, min, max), min, max);
            let err = (f64::from(v) - f64::from(back)).abs();
            assert!(
                err <= quantization_error(min, max) + f64::from(f32::EPSILON),
                "{v} -> {back}"
            );
        }
    }

    #[test]
    fn frame_times_map_back_to_frame_numbers() {
        for fps in [24.0, 23.976, 29.97, 30.0, 60.0, 1000.0, 0.5] {
            for frame in [0, 1, 2, 17, 1001, 100_000] {
                let ns = frame_time_ns(frame, fps).unwrap();
                assert_eq!(frame_at_time_ns(ns, fps), Some(frame), "{fps} {frame}");
                assert_eq!(frame_at_time_ns(ns + 1, fps), None);
            }
        }
        assert_eq!(frame_time_ns(24, 24.0), Some(1_000_000_000));
        assert_eq!(frame_time_ns(u32::MAX, 1.0), None);
    }

    #[test]
    fn metadata_round_trips() {
        let header = CacheHeader {
            fps: 29.97,
            first_frame: 3,
            scene_toml: "[sim]\nfps = 29.97\n".into(),
            scene_hash: "00ff".into(),
            extra: [("substeps".to_string(), "12".to_string())].into(),
        };
        let map = header.to_metadata(&layout());
        assert_eq!(map["extra.substeps"], "12");
        assert_eq!(map["fps"], "29.97");
        let (back, counts) = header_from_metadata(&map).unwrap();
        assert_eq!(back, header);
        assert_eq!(
            counts,
            MetadataCounts {
                strands: 2,
                points: 5
            }
        );
        let mut newer = map.clone();
        newer.insert(KEY_FORMAT_VERSION.into(), "2".into());
        assert_eq!(
            header_from_metadata(&newer),
            Err(MetadataError::Version("2".into()))
        );
    }
}
