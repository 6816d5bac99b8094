//! Render children as a USD `BasisCurves` stage, `.usdc` (binary crate file) or `.usda` (text),
//! through the one layer writer every hairsys USD export goes through
//! ([`hair_groom::formats::usd_write`], on the `openusd` crate).
//!
//! One prim, `/<prim>` (default `/children`), on a stage with `upAxis = "Z"` and
//! `metersPerUnit = 1` (children are meters, Z up), `timeCodesPerSecond` and
//! `framesPerSecond` set to the scene's rate. The curves are `type = "linear"`: the library
//! already subdivided the parents (Catmull–Rom) and shaped the children, so the renderer draws the
//! points as they are, and what it draws is exactly what the viewport shows.
//!
//! Attributes: `curveVertexCounts`, `points` (the frame's positions as the default value),
//! `extent` (bounds padded by half the largest width; per sample, and a default over every
//! sample), `widths` with `interpolation = "vertex"` (one diameter per point), the root UV of each
//! curve as `primvars:st` (`texCoord2f`, for renderers) and `primvars:surface_uv_coordinate`
//! (`float2`, Blender's name) when the scalp has UVs, `primvars:displayColor` when it has vertex
//! colors, and the per-curve `primvars:random` (float), `primvars:parent` and `primvars:id`
//! (int); every primvar is `uniform` (one value per curve).
//!
//! Motion blur ([`Motion`]): either `points.timeSamples` at several time codes over the shutter
//! (children regenerated from parents sampled at each time, same topology), with the stage's
//! `startTimeCode`/`endTimeCode` spanning them; or `velocities` (m/s per point) on the one frame.
//! A whole range of frames in one file is `hairsys::export_shot`, which builds its prim with
//! [`curves_prim`].
//!
//! The exported frame is taken by value: its points, widths and per-curve arrays move into the
//! layer and are written from there, not copied (a million children × 17 points are 204 MB of
//! points; `BENCHMARKS.md`). Motion samples are borrowed and copied once into their time samples.

use std::io::Write;
use std::path::Path;

use hair_groom::formats::obj::UpAxis;
use hair_groom::formats::usd_write::{
    Samples, UsdCurvesPrim, UsdLayer, UsdStageInfo, UsdWriteError,
};

use crate::buffers::ChildBuffers;
use crate::error::{parameter, InputError, RenderError, Result};

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

/// The layer of `children` with `motion` blur (see the module docs); the children's buffers
/// move into it. Refuses no children, a bad prim name or rate, and motion samples whose curves
/// differ from `children`.
pub fn children_layer(
    mut children: ChildBuffers,
    motion: &Motion,
    opts: &UsdOptions,
) -> Result<UsdLayer> {
    check(&children, motion, opts)?;
    let (start, end) = match motion {
        Motion::TimeSamples(s) => (s[0].time_code, s[s.len() - 1].time_code),
        _ => (opts.time_code, opts.time_code),
    };
    let mut layer = UsdLayer::new(&UsdStageInfo {
        up_axis: UpAxis::Z,
        meters_per_unit: 1.0,
        time_codes_per_second: Some(opts.frames_per_second),
        time_range: Some((start, end)),
    });
    let frame_points = std::mem::take(&mut children.points);
    let points = match motion {
        // The frame's points as the default too: a reader without a time sees the frame.
        Motion::TimeSamples(s) => Samples::DefaultAndTimes(
            frame_points,
            s.iter()
                .map(|m| (m.time_code, m.children.points.clone()))
                .collect(),
        ),
        _ => Samples::Default(frame_points),
    };
    let velocities = match motion {
        Motion::Velocities(v) => Some(Samples::Default(v.to_vec())),
        _ => None,
    };
    layer.add_curves(curves_prim(&opts.prim, children, points, velocities));
    layer.set_default_prim(&opts.prim);
    Ok(layer)
}

/// The `BasisCurves` prim of `children` with `points` (and `velocities`) as given (the
/// children's own `points` are not used): topology, widths, root UVs, colours, `random`,
/// `parent` and a per-curve `id` (the child's index). The children's buffers move into the prim.
pub fn curves_prim<'a>(
    name: &'a str,
    children: ChildBuffers,
    points: Samples,
    velocities: Option<Samples>,
) -> UsdCurvesPrim<'a> {
    let ids = (0..children.curve_count() as i32).collect();
    UsdCurvesPrim {
        name,
        vertex_counts: children.vertex_counts.iter().map(|&c| c as i32).collect(),
        points,
        widths: Some(Samples::Default(children.widths)),
        velocities,
        root_uv: children.root_uv,
        colors: children.color,
        extent: true,
        uniform_floats: vec![("random", children.random)],
        uniform_ints: vec![
            (
                "parent",
                children.parent.iter().map(|&p| p as i32).collect(),
            ),
            ("id", ids),
        ],
    }
}

/// Writes `children` as a `.usda` stage to `out`, with `motion` blur; refuses what
/// [`children_layer`] refuses.
pub fn write_usda<W: Write>(
    mut out: W,
    children: ChildBuffers,
    motion: &Motion,
    opts: &UsdOptions,
) -> Result<()> {
    children_layer(children, motion, opts)?
        .write_text(&mut out)
        .map_err(|e| InputError::Usd(e).into())
}

/// Writes `children` to the file at `path` through a `.partial` sibling renamed into place:
/// `.usdc` or `.usd` binary, any other name `.usda` text ([`UsdLayer::write`]). The children's
/// buffers are written without a copy ([`children_layer`]).
pub fn export_usd(
    path: &Path,
    children: ChildBuffers,
    motion: &Motion,
    opts: &UsdOptions,
) -> Result<()> {
    children_layer(children, motion, opts)?
        .write(path)
        .map_err(|e| RenderError::Write {
            path: path.to_path_buf(),
            source: match e {
                UsdWriteError::Io(source) => source,
                UsdWriteError::Encode(m) => std::io::Error::other(m),
            },
        })
}

/// Validates the export: prim name, rate, time code, some children, motion samples of the
/// same topology in increasing time, one velocity per point.
fn check(children: &ChildBuffers, motion: &Motion, opts: &UsdOptions) -> Result<()> {
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
    // What `children.extent()` is `None` for, without a pass over the points.
    if children.widths.is_empty() {
        return Err(InputError::NoChildren.into());
    }
    match motion {
        Motion::None => {}
        Motion::TimeSamples(samples) => {
            if samples.is_empty() {
                return Err(InputError::NoMotionSamples.into());
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
            }
        }
        Motion::Velocities(v) => {
            if v.len() != children.points.len() {
                return Err(InputError::Velocities {
                    components: v.len(),
                    points: children.point_count(),
                }
                .into());
            }
        }
    }
    Ok(())
}
