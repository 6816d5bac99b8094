//! USD `BasisCurves` in the `.usda` text format, for any USD-reading renderer.
//!
//! One prim, `/<prim>` (default `/children`), on a stage with `upAxis = "Z"` and
//! `metersPerUnit = 1` (children are meters, Z up), `timeCodesPerSecond` and
//! `framesPerSecond` set to the scene's rate. The curves are `type = "linear"`: the library
//! already subdivided the parents (Catmull–Rom) and shaped the children, so the renderer draws the
//! points as they are, and what it draws is exactly what the viewport shows.
//!
//! Attributes: `curveVertexCounts`, `points` (the frame's positions as the default value),
//! `extent` (bounds padded by half the widths, over every motion sample), `widths` with
//! `interpolation = "vertex"` (one diameter per point), `primvars:st` (`texCoord2f`, uniform: the
//! root UV of each curve) when the scalp has UVs, `primvars:displayColor` (uniform) when it has
//! vertex colors, and the per-curve `primvars:random` (float) and `primvars:parent` (int).
//!
//! Motion blur ([`Motion`]): either `points.timeSamples` at several time codes over the shutter
//! (children regenerated from parents sampled at each time, same topology), with the stage's
//! `startTimeCode`/`endTimeCode` spanning them; or `velocities` (m/s per point) on the one frame.
//! Every float is written as the shortest decimal that reads back to the same `f32` (`zmij`),
//! into a block buffer: no `format!` per value.

use std::io::Write;
use std::path::Path;

use super::write_atomically;
use crate::buffers::{extent_of, ChildBuffers, Extent};
use crate::error::{parameter, RenderError, Result};

/// One motion sample: the children at one time code.
#[derive(Debug, Clone, Copy)]
pub struct MotionSample<'a> {
    /// USD time code (frames at `frames_per_second`), e.g. 11.75 for frame 12 − ¼.
    pub time_code: f64,
    /// The children at that time; must have the topology of the exported children.
    pub children: &'a ChildBuffers,
}

/// How motion blur is carried.
#[derive(Debug, Clone, Copy, Default)]
pub enum Motion<'a> {
    /// No motion blur: the points of one frame.
    #[default]
    None,
    /// `points.timeSamples` at each sample's time code (in increasing order, at least 1).
    TimeSamples(&'a [MotionSample<'a>]),
    /// `velocities` per point, m/s, x y z interleaved (see [`velocities`]).
    Velocities(&'a [f32]),
}

/// Stage and prim settings of a `.usda` export.
#[derive(Debug, Clone, PartialEq)]
pub struct UsdOptions {
    /// Name of the `BasisCurves` prim (a USD identifier), also the stage's `defaultPrim`.
    pub prim: String,
    /// Frames per second: the stage's `timeCodesPerSecond` and `framesPerSecond` (> 0).
    pub frames_per_second: f64,
    /// Time code of the exported frame (the default `points`), in frames.
    pub time_code: f64,
}

impl Default for UsdOptions {
    /// Prim `children`, 24 fps, time code 1.
    fn default() -> Self {
        Self {
            prim: "children".into(),
            frames_per_second: 24.0,
            time_code: 1.0,
        }
    }
}

/// Velocities (m/s per point, x y z interleaved) of children that move from `before` to `after`
/// in `seconds` (> 0): the central difference a renderer extrapolates over its shutter.
pub fn velocities(before: &ChildBuffers, after: &ChildBuffers, seconds: f32) -> Result<Vec<f32>> {
    before.check_same_topology(after)?;
    if !(seconds.is_finite() && seconds > 0.0) {
        return Err(parameter(
            "seconds",
            seconds,
            "the time between the two samples must be a finite number > 0 s",
        ));
    }
    let inv = 1.0 / seconds;
    Ok(before
        .points
        .iter()
        .zip(&after.points)
        .map(|(a, b)| (b - a) * inv)
        .collect())
}

/// Writes `children` as a `.usda` stage to `out`, with `motion` blur. Refuses no children, a bad
/// prim name or rate, and motion samples whose curves differ from `children`.
pub fn write_usda<W: Write>(
    mut out: W,
    children: &ChildBuffers,
    motion: &Motion,
    opts: &UsdOptions,
) -> Result<()> {
    let extent = check(children, motion, opts)?;
    let fps = opts.frames_per_second;
    let (start, end) = match motion {
        Motion::TimeSamples(s) => (s[0].time_code, s[s.len() - 1].time_code),
        _ => (opts.time_code, opts.time_code),
    };
    write_stage_header(
        &mut out,
        &opts.prim,
        "hairsys render children",
        [start, end],
        fps,
    )?;
    writeln!(out, "def BasisCurves \"{}\"\n{{", opts.prim)?;
    writeln!(out, "    uniform token type = \"linear\"")?;
    writeln!(out, "    uniform token wrap = \"nonperiodic\"")?;
    write!(out, "    int[] curveVertexCounts = ")?;
    write_ints(&mut out, &children.vertex_counts)?;
    write!(out, "\n    point3f[] points = ")?;
    write_vec3s(&mut out, &children.points)?;
    match motion {
        Motion::None => {}
        Motion::TimeSamples(samples) => {
            writeln!(out, "\n    point3f[] points.timeSamples = {{")?;
            for s in samples.iter() {
                write!(out, "        {:?}: ", s.time_code)?;
                write_vec3s(&mut out, &s.children.points)?;
                writeln!(out, ",")?;
            }
            write!(out, "    }}")?;
        }
        Motion::Velocities(v) => {
            write!(out, "\n    vector3f[] velocities = ")?;
            write_vec3s(&mut out, v)?;
        }
    }
    let [a, b, c] = extent.min;
    let [d, e, f] = extent.max;
    write!(
        out,
        "\n    float3[] extent = [({a:?}, {b:?}, {c:?}), ({d:?}, {e:?}, {f:?})]"
    )?;
    write!(out, "\n    float[] widths = ")?;
    write_floats(&mut out, &children.widths, 1)?;
    write!(out, " (\n        interpolation = \"vertex\"\n    )")?;
    if let Some(st) = &children.root_uv {
        write!(out, "\n    texCoord2f[] primvars:st = ")?;
        write_floats(&mut out, st, 2)?;
        write!(out, " (\n        interpolation = \"uniform\"\n    )")?;
    }
    if let Some(rgb) = &children.color {
        write!(out, "\n    color3f[] primvars:displayColor = ")?;
        write_vec3s(&mut out, rgb)?;
        write!(out, " (\n        interpolation = \"uniform\"\n    )")?;
    }
    write!(out, "\n    float[] primvars:random = ")?;
    write_floats(&mut out, &children.random, 1)?;
    write!(out, " (\n        interpolation = \"uniform\"\n    )")?;
    write!(out, "\n    int[] primvars:parent = ")?;
    write_ints(&mut out, &children.parent)?;
    writeln!(out, " (\n        interpolation = \"uniform\"\n    )\n}}")?;
    Ok(())
}

/// Writes `children` to the file at `path` atomically (see [`crate::export`]): `.usdc` or
/// `.usd` binary through [`super::usd_crate::export_usdc`], any other name as `.usda` text.
pub fn export_usda(
    path: &Path,
    children: &ChildBuffers,
    motion: &Motion,
    opts: &UsdOptions,
) -> Result<()> {
    if hair_groom::formats::usd_write::UsdEncoding::of(path)
        == Some(hair_groom::formats::usd_write::UsdEncoding::Binary)
    {
        return super::usd_crate::export_usdc(path, children, motion, opts);
    }
    write_atomically(path, |out| write_usda(out, children, motion, opts))
}

/// Validates an export (prim name, rate, time code, motion samples' topology) as
/// [`write_usda`] does; shared with [`super::usd_crate`].
pub(crate) fn check_export(
    children: &ChildBuffers,
    motion: &Motion,
    opts: &UsdOptions,
) -> Result<()> {
    check(children, motion, opts).map(drop)
}

/// Validates the export and returns the extent over every sample.
fn check(children: &ChildBuffers, motion: &Motion, opts: &UsdOptions) -> Result<Extent> {
    let name_ok = opts
        .prim
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && opts
            .prim
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_');
    if !name_ok {
        return Err(parameter(
            "prim",
            format!("{:?}", opts.prim),
            "use a USD identifier: letters, digits and _, not starting with a digit",
        ));
    }
    if !(opts.frames_per_second.is_finite() && opts.frames_per_second > 0.0) {
        return Err(parameter(
            "frames_per_second",
            opts.frames_per_second,
            "use a finite rate > 0, e.g. 24",
        ));
    }
    if !opts.time_code.is_finite() {
        return Err(parameter(
            "time_code",
            opts.time_code,
            "use a finite frame number",
        ));
    }
    let mut extent = children
        .extent()
        .ok_or_else(|| RenderError::Input("no children to export: raise the child count".into()))?;
    match motion {
        Motion::None => {}
        Motion::TimeSamples(samples) => {
            if samples.is_empty() {
                return Err(RenderError::Input(
                    "motion blur by time samples needs at least 1 sample".into(),
                ));
            }
            let mut prev = f64::NEG_INFINITY;
            for s in samples.iter() {
                children.check_same_topology(s.children)?;
                if !(s.time_code.is_finite() && s.time_code > prev) {
                    return Err(parameter(
                        "motion sample time code",
                        s.time_code,
                        "give finite time codes in increasing order",
                    ));
                }
                prev = s.time_code;
                if let Some(e) = extent_of(&s.children.points, &children.widths) {
                    for k in 0..3 {
                        extent.min[k] = extent.min[k].min(e.min[k]);
                        extent.max[k] = extent.max[k].max(e.max[k]);
                    }
                }
            }
        }
        Motion::Velocities(v) => {
            if v.len() != children.points.len() {
                return Err(RenderError::Input(format!(
                    "{} velocity components for {} points: give x y z per point",
                    v.len(),
                    children.point_count()
                )));
            }
        }
    }
    Ok(extent)
}

/// Bytes of a long list, built in a buffer and written out in blocks of about 256 KiB.
struct Block<'w, W: Write> {
    out: &'w mut W,
    buf: Vec<u8>,
    num: zmij::Buffer,
}

impl<'w, W: Write> Block<'w, W> {
    const SIZE: usize = 256 << 10;

    fn new(out: &'w mut W) -> Self {
        Self {
            out,
            buf: Vec::with_capacity(Self::SIZE + 256),
            num: zmij::Buffer::new(),
        }
    }

    /// Appends the shortest decimal that reads back to the same `f32`.
    #[inline(always)]
    fn float(&mut self, v: f32) {
        self.buf.extend_from_slice(self.num.format(v).as_bytes());
    }

    /// Appends `v` in decimal.
    #[inline(always)]
    fn int(&mut self, mut v: u32) {
        let mut digits = [0u8; 10];
        let mut i = digits.len();
        loop {
            i -= 1;
            digits[i] = b'0' + (v % 10) as u8;
            v /= 10;
            if v == 0 {
                break;
            }
        }
        self.buf.extend_from_slice(&digits[i..]);
    }

    /// Writes the buffer out once it is full.
    #[inline(always)]
    fn spill(&mut self) -> std::io::Result<()> {
        if self.buf.len() >= Self::SIZE {
            self.out.write_all(&self.buf)?;
            self.buf.clear();
        }
        Ok(())
    }

    fn finish(self) -> std::io::Result<()> {
        self.out.write_all(&self.buf)
    }
}

/// Writes `[a, b, …]` of integers.
/// Writes the `.usda` layer header hairsys puts on every stage: the default prim `prim`, `doc`,
/// the time code range `[start, end]` at `fps` frames (and time codes) per second, meters, Z up.
pub(crate) fn write_stage_header<W: Write>(
    out: &mut W,
    prim: &str,
    doc: &str,
    [start, end]: [f64; 2],
    fps: f64,
) -> Result<()> {
    writeln!(out, "#usda 1.0\n(")?;
    writeln!(out, "    defaultPrim = \"{prim}\"")?;
    writeln!(out, "    doc = \"{doc}\"")?;
    writeln!(out, "    endTimeCode = {end:?}")?;
    writeln!(out, "    framesPerSecond = {fps:?}")?;
    writeln!(out, "    metersPerUnit = 1")?;
    writeln!(out, "    startTimeCode = {start:?}")?;
    writeln!(out, "    timeCodesPerSecond = {fps:?}")?;
    writeln!(out, "    upAxis = \"Z\"\n)\n")?;
    Ok(())
}

fn write_ints<W: Write>(out: &mut W, values: &[u32]) -> Result<()> {
    let mut b = Block::new(out);
    b.buf.push(b'[');
    for (k, &v) in values.iter().enumerate() {
        if k > 0 {
            b.buf.extend_from_slice(b", ");
        }
        b.int(v);
        b.spill()?;
    }
    b.buf.push(b']');
    b.finish()?;
    Ok(())
}

/// Writes floats taken `arity` at a time: `[a, b, …]` for 1, `[(a, b), …]` for 2 or 3.
fn write_floats<W: Write>(out: &mut W, values: &[f32], arity: usize) -> Result<()> {
    let mut b = Block::new(out);
    b.buf.push(b'[');
    for (k, v) in values.chunks_exact(arity).enumerate() {
        if k > 0 {
            b.buf.extend_from_slice(b", ");
        }
        if arity == 1 {
            b.float(v[0]);
        } else {
            b.buf.push(b'(');
            for (i, &x) in v.iter().enumerate() {
                if i > 0 {
                    b.buf.extend_from_slice(b", ");
                }
                b.float(x);
            }
            b.buf.push(b')');
        }
        b.spill()?;
    }
    b.buf.push(b']');
    b.finish()?;
    Ok(())
}

/// Writes interleaved x y z as `[(x, y, z), …]`.
fn write_vec3s<W: Write>(out: &mut W, xyz: &[f32]) -> Result<()> {
    write_floats(out, xyz, 3)
}
