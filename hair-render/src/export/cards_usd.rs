//! Hair cards ([`CardMesh`]) as a USD `Mesh` in the `.usda` text format.
//!
//! One prim, `/<prim>` (default `/cards`), on a stage with `upAxis = "Z"`, `metersPerUnit = 1`
//! and `timeCodesPerSecond`/`framesPerSecond` at the scene's rate. The mesh is quads
//! (`faceVertexCounts` all 4), `subdivisionScheme = "none"` (the surface is already sampled
//! densely) and `doubleSided = 1` (cards are seen from both sides); `primvars:st`
//! (`texCoord2f`, `interpolation = "vertex"`) carries u across the card and v root → tip.
//!
//! Motion blur: `points.timeSamples` at the given time codes, each a [`CardMesh`] of the same
//! topology (the strips sampled from the cache at that time), with `startTimeCode`/`endTimeCode`
//! spanning them; `extent` covers every sample.

use std::io::Write;
use std::path::Path;

use super::write_atomically;
use crate::cards::CardMesh;
use crate::error::{parameter, InputError, Result};

/// One motion sample of the cards: the mesh at one time code.
#[derive(Debug, Clone, Copy)]
pub struct CardSample<'a> {
    /// USD time code (frames), e.g. 11.75 for frame 12 − ¼.
    pub time_code: f64,
    /// The cards at that time; same topology as the exported mesh.
    pub mesh: &'a CardMesh,
}

/// Stage and prim settings of a cards `.usda` export.
#[derive(Debug, Clone, PartialEq)]
pub struct CardUsdOptions {
    /// Name of the `Mesh` prim (a USD identifier), also the stage's `defaultPrim`.
    pub prim: String,
    /// Frames per second (> 0): `timeCodesPerSecond` and `framesPerSecond`.
    pub frames_per_second: f64,
    /// Time code of the exported frame (the default `points`), in frames.
    pub time_code: f64,
}

impl Default for CardUsdOptions {
    /// Prim `cards`, 24 fps, time code 1.
    fn default() -> Self {
        Self {
            prim: "cards".into(),
            frames_per_second: 24.0,
            time_code: 1.0,
        }
    }
}

fn write_points<W: Write>(out: &mut W, mesh: &CardMesh) -> Result<()> {
    out.write_all(b"[")?;
    for (i, p) in mesh.positions.iter().enumerate() {
        if i > 0 {
            out.write_all(b", ")?;
        }
        write!(out, "({:?}, {:?}, {:?})", p.x, p.y, p.z)?;
    }
    out.write_all(b"]")?;
    Ok(())
}

/// Writes `mesh` (and its motion `samples`, in increasing time order, possibly none) as a
/// `.usda` stage to `out`. Refuses a bad prim name or rate, samples of another topology and
/// samples out of order.
pub fn write_cards_usda<W: Write>(
    out: &mut W,
    mesh: &CardMesh,
    samples: &[CardSample<'_>],
    opts: &CardUsdOptions,
) -> Result<()> {
    let ident = !opts.prim.is_empty()
        && !opts.prim.starts_with(|c: char| c.is_ascii_digit())
        && opts
            .prim
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_');
    if !ident {
        return Err(parameter(
            "prim",
            &opts.prim,
            "use a USD identifier: letters, digits and _, not starting with a digit",
        ));
    }
    if !(opts.frames_per_second.is_finite() && opts.frames_per_second > 0.0) {
        return Err(parameter(
            "frames_per_second",
            opts.frames_per_second,
            "must be a finite number > 0",
        ));
    }
    for (i, s) in samples.iter().enumerate() {
        mesh.check_same_topology(s.mesh)?;
        if i > 0 && s.time_code <= samples[i - 1].time_code {
            return Err(InputError::MotionOrder {
                sample: i,
                time_code: s.time_code,
                previous: samples[i - 1].time_code,
            }
            .into());
        }
    }
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for p in std::iter::once(mesh)
        .chain(samples.iter().map(|s| s.mesh))
        .flat_map(|m| &m.positions)
    {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    if mesh.positions.is_empty() {
        (lo, hi) = ([0.0; 3], [0.0; 3]);
    }
    let (start, end) = match (samples.first(), samples.last()) {
        (Some(a), Some(b)) => (
            a.time_code.min(opts.time_code),
            b.time_code.max(opts.time_code),
        ),
        _ => (opts.time_code, opts.time_code),
    };
    let fps = opts.frames_per_second;
    write_stage_header(out, &opts.prim, "hairsys hair cards", [start, end], fps)?;
    writeln!(out, "def Mesh \"{}\"\n{{", opts.prim)?;
    writeln!(out, "    uniform bool doubleSided = 1")?;
    writeln!(out, "    uniform token subdivisionScheme = \"none\"")?;
    writeln!(
        out,
        "    float3[] extent = [({:?}, {:?}, {:?}), ({:?}, {:?}, {:?})]",
        lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]
    )?;
    write!(out, "    int[] faceVertexCounts = [")?;
    for i in 0..mesh.quads.len() {
        out.write_all(if i > 0 { b", 4" } else { b"4" })?;
    }
    write!(out, "]\n    int[] faceVertexIndices = [")?;
    for (i, q) in mesh.quads.iter().enumerate() {
        if i > 0 {
            out.write_all(b", ")?;
        }
        write!(out, "{}, {}, {}, {}", q[0], q[1], q[2], q[3])?;
    }
    write!(out, "]\n    point3f[] points = ")?;
    write_points(out, mesh)?;
    if !samples.is_empty() {
        writeln!(out, "\n    point3f[] points.timeSamples = {{")?;
        for s in samples {
            write!(out, "        {:?}: ", s.time_code)?;
            write_points(out, s.mesh)?;
            writeln!(out, ",")?;
        }
        write!(out, "    }}")?;
    }
    write!(out, "\n    texCoord2f[] primvars:st = [")?;
    for (i, uv) in mesh.uvs.iter().enumerate() {
        if i > 0 {
            out.write_all(b", ")?;
        }
        write!(out, "({:?}, {:?})", uv[0], uv[1])?;
    }
    writeln!(out, "] (\n        interpolation = \"vertex\"\n    )\n}}")?;
    Ok(())
}

/// Writes the cards to `path` atomically (see [`super`]); errors name the file.
pub fn export_cards_usda(
    path: &Path,
    mesh: &CardMesh,
    samples: &[CardSample<'_>],
    opts: &CardUsdOptions,
) -> Result<()> {
    write_atomically(path, |out| write_cards_usda(out, mesh, samples, opts))
}

/// Writes the `.usda` layer header of a cards stage: the default prim `prim`, `doc`, the time
/// code range `[start, end]` at `fps` frames (and time codes) per second, meters, Z up.
fn write_stage_header<W: Write>(
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
