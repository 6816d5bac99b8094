//! USD `BasisCurves` read from a composed stage (`.usd`, `.usda`, `.usdc`, `.usdz`) through the
//! `openusd` crate, and grooms written as `.usda`/`.usdc` through [`super::usd_write`].
//!
//! # Reading
//! [`read_usd`] opens the file as a stage (sublayers, references, payloads and variants
//! composed by `openusd`), then takes the `BasisCurves` prims to read: the prim named by
//! [`UsdReadOptions::prim`] (itself if it is a `BasisCurves`, else every `BasisCurves` below
//! it), or every `BasisCurves` of the stage. Inactive, abstract and unloaded prims are skipped
//! (`openusd`'s default predicate). For each prim, at the time asked for:
//! - `points` are taken to the world by the prim's local-to-world transform: the product of
//!   the `xformOpOrder` stacks of the prim and its ancestors, up to the first
//!   `!resetXformStack!` (USD's `ComputeLocalToWorldTransform`, row vectors: `p · M`);
//! - then to meters by the stage's `metersPerUnit` and to Z up by its `upAxis` (Y up maps
//!   (x, y, z) to (x, −z, y), as Blender's importer does), unless [`UsdReadOptions::units`]
//!   overrides both. Unauthored, they take USD's fallbacks: 0.01 m per unit, Y up;
//! - `widths` (or `primvars:widths`) become per-point radii (half the width, times the
//!   transform's uniform scale and the unit scale), from `constant`, `uniform` (per curve) or
//!   `vertex`/`varying` (per point, when the count matches) interpolation;
//! - `primvars:surface_uv_coordinate` (Blender) or `primvars:st` become one root UV per curve
//!   (per-curve values, or the root point's value of per-point ones).
//!
//! Curve bases: linear curves and cubic curves with the `catmullRom` or `bspline` basis are read
//! as their points (Blender exports its hair as "pinned" Catmull-Rom, whose points lie on the
//! curve); cubic `bezier` curves keep their on-curve points (every third). Periodic curves are
//! refused: a hair has a root and a tip.
//!
//! Time: [`UsdReadOptions::time`] is a USD time code; without one, attributes give their
//! earliest time sample (or their default). A time outside the stage's authored
//! `startTimeCode`–`endTimeCode` is refused.
//!
//! Errors name the file and, past opening, the prim (and the time). `openusd` may panic on a
//! malformed binary file (it indexes its tables with values read from the file); the reader
//! turns such a panic into an error naming the file (`std::panic::catch_unwind`, the last line
//! of defence: `tests::corrupted_usdc_is_an_error_not_a_panic` pins it).
//!
//! # Writing
//! [`write_usda`] writes one linear `BasisCurves` prim `/hair` with the stage's `upAxis` and
//! `metersPerUnit` from the options, as `.usda` or `.usdc` by the extension; write → read is
//! bit-exact (f32 values are stored as they are, or printed as the shortest decimal that reads
//! back to them).

use std::path::Path;

use nalgebra::{Matrix4, Vector3};
use openusd::schemas::geom::{Imageable, Xformable};
use openusd::usd::{Prim, PrimPredicate, SchemaBase, SchemaKind, Stage, TimeCode};
use openusd::{gf, sdf};
use thiserror::Error;

use super::usd_write::{UsdCurvesPrim, UsdLayer, UsdStageInfo};
use super::{bad, check_options, to_file, to_world, ImportOptions};
use crate::error::{FileLocation, GroomError};
use crate::formats::obj::UpAxis;
use crate::groom::Groom;

/// What to read from a stage, and how to place it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct UsdReadOptions {
    /// The prim to read (`"/Sintel/hair"`): a `BasisCurves`, or a prim whose descendant
    /// `BasisCurves` are read. `None`: every `BasisCurves` of the stage.
    pub prim: Option<String>,
    /// USD time code (frame) at which points, widths and transforms are read. `None`: each
    /// attribute's earliest time sample, or its default value.
    pub time: Option<f64>,
    /// Meters per unit and up axis that replace the stage's `metersPerUnit` and `upAxis`.
    /// `None`: the stage's.
    pub units: Option<ImportOptions>,
}

/// Curves read from a stage, in meters, Z up, with what the file said about them.
#[derive(Debug, Clone, PartialEq)]
pub struct UsdCurves {
    /// The curves in world space, meters, Z up, root first.
    pub groom: Groom,
    /// Radius of every point (curve by curve, as [`Groom::curves`] flattened), m; `None` when
    /// no prim authored `widths`.
    pub radii: Option<Vec<f32>>,
    /// One root UV per curve from `primvars:surface_uv_coordinate` or `primvars:st`; `None`
    /// when no prim authored either.
    pub root_uv: Option<Vec<[f32; 2]>>,
    /// Paths of the prims read, in stage order.
    pub prims: Vec<String>,
    /// Meters per stage unit that were applied.
    pub meters_per_unit: f64,
    /// The up axis that was converted from.
    pub up_axis: UpAxis,
}

/// Reads the `BasisCurves` of the USD stage at `path` chosen by `opts` (see the module docs).
pub fn read_usd(path: &Path, opts: &UsdReadOptions) -> Result<UsdCurves, GroomError> {
    if let Some(units) = &opts.units {
        check_options(units)?;
    }
    let name = openable_name(path)?;
    guarded(path, || read_stage(path, name, opts))
}

/// The name `openusd` opens `path` by, after the checks every USD read makes: a regular file
/// of at most [`MAX_GROOM_FILE_BYTES`](crate::input_file::MAX_GROOM_FILE_BYTES), with a UTF-8
/// path.
pub(super) fn openable_name(path: &Path) -> Result<&str, GroomError> {
    let limit = crate::input_file::MAX_GROOM_FILE_BYTES;
    let bytes = crate::input_file::check_regular_file(path)?;
    if bytes > limit {
        return Err(crate::input_file::InputFileError::TooLarge {
            path: path.to_path_buf(),
            bytes,
            limit,
        }
        .into());
    }
    path.to_str().ok_or_else(|| {
        bad(
            path,
            FileLocation::File,
            "has a path that is not UTF-8, which the USD reader cannot open; rename the file",
        )
    })
}

/// Runs a read of the USD file at `path` and turns a panic of `openusd` into an error naming
/// the file: `openusd` indexes tables with values from the file and may panic on a corrupt
/// one, and a panic must not take the host down (see the module docs). The panic hook still
/// prints its message.
pub(super) fn guarded<T>(
    path: &Path,
    read: impl FnOnce() -> Result<T, GroomError>,
) -> Result<T, GroomError> {
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(read));
    match result {
        Ok(r) => r,
        Err(payload) => {
            let why = payload
                .downcast_ref::<String>()
                .map(String::as_str)
                .or_else(|| payload.downcast_ref::<&str>().copied())
                .unwrap_or("unknown fault");
            Err(bad(
                path,
                FileLocation::File,
                format!(
                    "is not a readable USD file (the USD reader failed: {why}); check that it \
                     opens in usdview or `usdcat`, and re-export it"
                ),
            ))
        }
    }
}

/// Reads the groom file at `path` as USD with `opts` as the file's units and up axis (they
/// replace the stage's): every `BasisCurves` of the stage, at its earliest time.
pub fn read_usda(path: &Path, opts: &ImportOptions) -> Result<Groom, GroomError> {
    read_usd(
        path,
        &UsdReadOptions {
            units: Some(*opts),
            ..UsdReadOptions::default()
        },
    )
    .map(|c| c.groom)
}

/// Writes `groom` to `path` as one linear `BasisCurves` prim `/hair`, in file units and up
/// axis per `opts` (also written as the stage's `metersPerUnit` and `upAxis`); `.usdc` by that
/// extension, else `.usda` text.
pub fn write_usda(path: &Path, groom: &Groom, opts: &ImportOptions) -> Result<(), GroomError> {
    check_options(opts)?;
    let mut counts = Vec::with_capacity(groom.len());
    let mut points = Vec::with_capacity(groom.point_count() * 3);
    for curve in groom.curves() {
        counts.push(curve.len() as i32);
        for p in curve {
            points.extend_from_slice(&to_file(p, opts));
        }
    }
    let mut layer = UsdLayer::new(&UsdStageInfo {
        up_axis: opts.up_axis,
        meters_per_unit: f64::from(opts.scale),
        time_codes_per_second: None,
        time_range: None,
    });
    layer.add_curves(UsdCurvesPrim {
        name: "hair",
        vertex_counts: counts,
        points: super::usd_write::Samples::Default(points),
        widths: None,
        velocities: None,
        root_uv: None,
        colors: None,
        extent: true,
        uniform_floats: Vec::new(),
        uniform_ints: Vec::new(),
    });
    layer.set_default_prim("hair");
    layer.write(path).map_err(|e| match e {
        super::usd_write::UsdWriteError::Io(source) => GroomError::Write {
            path: path.to_path_buf(),
            source,
        },
        other => bad(path, FileLocation::File, other.to_string()),
    })
}

/// A view of any prim as `Xformable`, to compose its `xformOpOrder` whatever its type.
pub(super) struct AnyXformable(pub(super) Prim);

impl SchemaBase for AnyXformable {
    const KIND: SchemaKind = SchemaKind::ConcreteTyped;
    fn prim(&self) -> &Prim {
        &self.0
    }
}
impl Imageable for AnyXformable {}
impl Xformable for AnyXformable {}

/// The read itself, inside the panic guard of [`read_usd`].
fn read_stage(path: &Path, name: &str, opts: &UsdReadOptions) -> Result<UsdCurves, GroomError> {
    let stage = Stage::open(name).map_err(|e| {
        bad(
            path,
            FileLocation::File,
            format!("cannot be opened as a USD stage: {e:#}; check that it is .usd, .usda, .usdc or a .usdz holding one"),
        )
    })?;
    let time = match opts.time {
        Some(t) => {
            check_time(&stage, path, t)?;
            TimeCode::new(t)
        }
        None => TimeCode::EARLIEST,
    };
    let (meters_per_unit, up_axis) = match &opts.units {
        Some(u) => (f64::from(u.scale), u.up_axis),
        None => stage_units(&stage, path)?,
    };
    let prims = select_prims(&stage, path, opts.prim.as_deref())?;
    let at = |prim: &str| match opts.time {
        Some(t) => format!("prim {prim} at time {t}"),
        None => format!("prim {prim}"),
    };
    let mut curves = Vec::new();
    let mut radii: Vec<(usize, Option<Vec<f32>>)> = Vec::new();
    let mut uvs: Vec<(usize, Option<Vec<[f32; 2]>>)> = Vec::new();
    for prim_path in &prims {
        let prim = stage.prim(prim_path.as_str());
        let fail = |msg: String| {
            bad(
                path,
                FileLocation::File,
                format!("{}: {msg}", at(prim_path)),
            )
        };
        let world = world_transform(&stage, prim_path, time)
            .map_err(|e| fail(format!("its transform: {e}")))?;
        let place = ImportOptions {
            scale: meters_per_unit as f32,
            up_axis,
        };
        let read = read_curves(&prim, time).map_err(|e| fail(e.to_string()))?;
        // Widths scale with the transform: its cube-root volume scale is the uniform part.
        let width_scale = world.fixed_view::<3, 3>(0, 0).determinant().abs().cbrt() * place.scale;
        let identity = world == Matrix4::identity();
        for c in &read.curves {
            let points: Vec<Vector3<f32>> = c
                .iter()
                .map(|p| {
                    // The axis turn and unit scale are exact (−0.0 stays −0.0), and an
                    // identity placement is skipped, so file values survive bit for bit.
                    let local = if identity {
                        *p
                    } else {
                        let h = world * nalgebra::Vector4::new(p[0], p[1], p[2], 1.0);
                        [h.x, h.y, h.z]
                    };
                    to_world(local, &place)
                })
                .collect();
            curves.push(points);
        }
        let point_count = read.curves.iter().map(Vec::len).sum();
        radii.push((
            point_count,
            read.radii
                .map(|r| r.iter().map(|w| 0.5 * w * width_scale).collect()),
        ));
        uvs.push((read.curves.len(), read.root_uv));
    }
    let groom = Groom::new(curves).map_err(|e| bad(path, FileLocation::File, e.to_string()))?;
    let radii = merge(radii, 0.0);
    let root_uv = merge(uvs, [0.0, 0.0]);
    Ok(UsdCurves {
        groom,
        radii,
        root_uv,
        prims,
        meters_per_unit,
        up_axis,
    })
}

/// Concatenates per-prim values when at least one prim has them: `(count, values)` per prim,
/// where a prim without values takes `count` copies of `fill`.
fn merge<T: Copy>(parts: Vec<(usize, Option<Vec<T>>)>, fill: T) -> Option<Vec<T>> {
    if parts.iter().all(|(_, v)| v.is_none()) {
        return None;
    }
    let mut out = Vec::new();
    for (count, values) in parts {
        match values {
            Some(v) => out.extend(v),
            None => out.extend(std::iter::repeat_n(fill, count)),
        }
    }
    Some(out)
}

/// Refuses a time outside the stage's authored time range.
pub(super) fn check_time(stage: &Stage, path: &Path, t: f64) -> Result<(), GroomError> {
    if !t.is_finite() {
        return Err(bad(
            path,
            FileLocation::File,
            format!("time {t} is not a finite time code"),
        ));
    }
    if stage.has_authored_time_code_range() {
        let (lo, hi) = (stage.start_time_code(), stage.end_time_code());
        if t < lo || t > hi {
            return Err(bad(
                path,
                FileLocation::File,
                format!(
                    "time {t} is outside the stage's time range {lo} to {hi} \
                     (startTimeCode–endTimeCode); ask for a time in that range"
                ),
            ));
        }
    }
    Ok(())
}

/// The stage's `metersPerUnit` and `upAxis`, with USD's fallbacks (0.01, Y).
pub(super) fn stage_units(stage: &Stage, path: &Path) -> Result<(f64, UpAxis), GroomError> {
    let meta = |key: &str| {
        stage.stage_metadata(key).map_err(|e| {
            bad(
                path,
                FileLocation::File,
                format!("stage metadata `{key}`: {e:#}"),
            )
        })
    };
    let mpu = match meta("metersPerUnit")? {
        None => 0.01,
        Some(sdf::Value::Double(v)) => v,
        Some(sdf::Value::Float(v)) => f64::from(v),
        Some(sdf::Value::Int(v)) => f64::from(v),
        Some(other) => {
            return Err(bad(
                path,
                FileLocation::File,
                format!("stage metadata metersPerUnit is {other:?}, not a number; write e.g. `metersPerUnit = 0.01`"),
            ))
        }
    };
    if !(mpu.is_finite() && mpu > 0.0) {
        return Err(bad(
            path,
            FileLocation::File,
            format!("stage metadata metersPerUnit = {mpu}: must be a finite number > 0"),
        ));
    }
    let up = match meta("upAxis")? {
        None => UpAxis::Y,
        Some(sdf::Value::Token(t)) if t.as_str() == "Y" => UpAxis::Y,
        Some(sdf::Value::Token(t)) if t.as_str() == "Z" => UpAxis::Z,
        Some(other) => {
            return Err(bad(
                path,
                FileLocation::File,
                format!("stage metadata upAxis is {other:?}; USD allows \"Y\" or \"Z\""),
            ))
        }
    };
    Ok((mpu, up))
}

/// Local-to-world of the prim at `prim_path` at `time` as a column-vector matrix: the
/// ancestors' `xformOpOrder` stacks, up to the first `!resetXformStack!`.
pub(super) fn world_transform(
    stage: &Stage,
    prim_path: &str,
    time: TimeCode,
) -> Result<Matrix4<f32>, PrimError> {
    let mut m = gf::Matrix4d::IDENTITY;
    let mut p = sdf::path(prim_path).map_err(|error| PrimError::Path { error })?;
    loop {
        if p == sdf::Path::abs_root() {
            break;
        }
        let x = AnyXformable(stage.prim(p.clone()));
        // Row vectors: world = local · parent · grandparent …
        let at = |error| PrimError::XformOps {
            prim: p.as_str().to_string(),
            error,
        };
        m = m * x.local_to_parent_transform(time).map_err(at)?;
        if x.resets_xform_stack().map_err(at)? {
            break;
        }
        match p.parent() {
            Some(parent) => p = parent,
            None => break,
        }
    }
    // gf is row-major with row vectors; nalgebra's from_row_slice of the transpose.
    let t = m.0;
    let mut out = Matrix4::<f32>::zeros();
    for r in 0..4 {
        for c in 0..4 {
            out[(c, r)] = t[r * 4 + c] as f32;
        }
    }
    Ok(out)
}

/// Paths of the `BasisCurves` prims to read: `wanted` itself, its descendants, or the whole
/// stage. Refuses a missing prim (listing the curve and mesh prims) or a selection without
/// curves.
fn select_prims(
    stage: &Stage,
    path: &Path,
    wanted: Option<&str>,
) -> Result<Vec<String>, GroomError> {
    let mut all = Vec::new();
    stage
        .traverse(PrimPredicate::DEFAULT, |p| all.push(p.as_str().to_string()))
        .map_err(|e| {
            bad(
                path,
                FileLocation::File,
                format!("cannot list its prims: {e:#}"),
            )
        })?;
    let type_of = |p: &str| {
        stage
            .prim(p)
            .type_name()
            .ok()
            .flatten()
            .map(|t| t.as_str().to_string())
            .unwrap_or_default()
    };
    let curves: Vec<String> = all
        .iter()
        .filter(|p| type_of(p) == "BasisCurves")
        .cloned()
        .collect();
    let listing = || {
        let shown: Vec<String> = all
            .iter()
            .filter_map(|p| {
                let t = type_of(p);
                matches!(
                    t.as_str(),
                    "BasisCurves" | "Mesh" | "NurbsCurves" | "HermiteCurves"
                )
                .then(|| format!("{p} ({t})"))
            })
            .take(40)
            .collect();
        if shown.is_empty() {
            "it has no curve or mesh prim".to_string()
        } else {
            format!("its curve and mesh prims: {}", shown.join(", "))
        }
    };
    let chosen: Vec<String> = match wanted {
        None => curves,
        Some(w) => {
            let w = w.trim_end_matches('/');
            if !all.iter().any(|p| p == w) {
                return Err(bad(
                    path,
                    FileLocation::File,
                    format!("has no prim {w} (or it is inactive); {}", listing()),
                ));
            }
            let below = format!("{w}/");
            curves
                .into_iter()
                .filter(|p| p == w || p.starts_with(&below))
                .collect()
        }
    };
    if chosen.is_empty() {
        let scope = wanted.map_or("the stage".to_string(), |w| format!("prim {w}"));
        return Err(bad(
            path,
            FileLocation::File,
            format!(
                "{scope} holds no BasisCurves prim to read as hair; {}",
                listing()
            ),
        ));
    }
    Ok(chosen)
}

/// One prim's curves in its local space, file units.
struct PrimCurves {
    curves: Vec<Vec<[f32; 3]>>,
    /// Per point of `curves`, file units (widths, not radii).
    radii: Option<Vec<f32>>,
    root_uv: Option<Vec<[f32; 2]>>,
}

/// A token-valued attribute or metadata as a string (`None` when unauthored).
pub(super) fn token(v: Option<sdf::Value>) -> Option<String> {
    match v {
        Some(sdf::Value::Token(t)) => Some(t.as_str().to_string()),
        Some(sdf::Value::String(s)) => Some(s),
        _ => None,
    }
}

/// The value of `name` on `prim` at `time` (`None` when unauthored).
pub(super) fn value_at(
    prim: &Prim,
    name: &str,
    time: TimeCode,
) -> Result<Option<sdf::Value>, PrimError> {
    prim.attribute(name)
        .get_at::<sdf::Value>(time)
        .map_err(|error| PrimError::Attribute {
            name: name.to_string(),
            error,
        })
}

/// A [`PrimError::Type`]: `name` holds `found` where `expected` (a USD type) is read.
pub(super) fn wrong_type(name: &str, found: &sdf::Value, expected: &'static str) -> PrimError {
    PrimError::Type {
        name: name.to_string(),
        found: kind(found),
        expected,
    }
}

/// Reads one `BasisCurves` prim: counts, points (on-curve points per basis), widths, root UV.
fn read_curves(prim: &Prim, time: TimeCode) -> Result<PrimCurves, PrimError> {
    let counts: Vec<i64> = match value_at(prim, "curveVertexCounts", time)? {
        Some(sdf::Value::IntVec(v)) => v.into_iter().map(i64::from).collect(),
        Some(other) => return Err(wrong_type("curveVertexCounts", &other, "int[]")),
        None => return Err(PrimError::NoCurveVertexCounts),
    };
    let points: Vec<[f32; 3]> = match value_at(prim, "points", time)? {
        Some(sdf::Value::Vec3fVec(v)) => v.iter().map(|p| [p.x, p.y, p.z]).collect(),
        Some(sdf::Value::Vec3dVec(v)) => v
            .iter()
            .map(|p| [p.x as f32, p.y as f32, p.z as f32])
            .collect(),
        Some(other) => return Err(wrong_type("points", &other, "point3f[]")),
        None => return Err(PrimError::NoPoints),
    };
    let total: i64 = counts.iter().sum();
    if counts.iter().any(|&c| c < 2) || total != points.len() as i64 {
        return Err(PrimError::CurveCounts {
            curves: counts.len(),
            total,
            smallest: counts.iter().min().copied().unwrap_or(0),
            points: points.len(),
        });
    }
    if let Some((point, _)) = points
        .iter()
        .enumerate()
        .find(|(_, p)| p.iter().any(|c| !c.is_finite()))
    {
        return Err(PrimError::NonFinitePoint { point });
    }
    let ty = token(value_at(prim, "type", time)?).unwrap_or_else(|| "cubic".into());
    let basis = token(value_at(prim, "basis", time)?).unwrap_or_else(|| "bezier".into());
    let wrap = token(value_at(prim, "wrap", time)?).unwrap_or_else(|| "nonperiodic".into());
    if wrap == "periodic" {
        return Err(PrimError::Periodic);
    }
    // Which vertices of a curve of n are points of the hair.
    let bezier = ty == "cubic" && basis == "bezier";
    let keep = |n: usize| -> Vec<usize> {
        if bezier && n >= 4 && (n - 1).is_multiple_of(3) {
            (0..n).step_by(3).collect()
        } else {
            (0..n).collect()
        }
    };
    let widths = widths(prim, time, &counts)?;
    let uv = root_uv(prim, time, &counts)?;
    let mut curves = Vec::with_capacity(counts.len());
    let mut radii = widths.as_ref().map(|_| Vec::new());
    let mut start = 0usize;
    for &c in &counts {
        let n = c as usize;
        let idx = keep(n);
        curves.push(idx.iter().map(|&i| points[start + i]).collect());
        if let (Some(out), Some(w)) = (radii.as_mut(), widths.as_ref()) {
            out.extend(idx.iter().map(|&i| w[start + i]));
        }
        start += n;
    }
    Ok(PrimCurves {
        curves,
        radii,
        root_uv: uv,
    })
}

/// A value's USD type name for messages.
pub(super) fn kind(v: &sdf::Value) -> String {
    format!("{v:?}")
        .split('(')
        .next()
        .unwrap_or("a value")
        .to_string()
}

/// The `interpolation` metadata of the attribute `name`.
pub(super) fn interpolation(prim: &Prim, name: &str) -> Option<String> {
    token(
        prim.attribute(name)
            .get_metadata::<sdf::Value>("interpolation")
            .ok()
            .flatten(),
    )
}

/// Per-vertex widths of the prim (file units), expanded from constant/uniform/vertex values.
fn widths(prim: &Prim, time: TimeCode, counts: &[i64]) -> Result<Option<Vec<f32>>, PrimError> {
    let mut found = None;
    for name in ["primvars:widths", "widths"] {
        if let Some(v) = value_at(prim, name, time)? {
            found = Some((name, v));
            break;
        }
    }
    let Some((name, v)) = found else {
        return Ok(None);
    };
    let values: Vec<f32> = match v {
        sdf::Value::FloatVec(v) => v,
        sdf::Value::DoubleVec(v) => v.into_iter().map(|x| x as f32).collect(),
        sdf::Value::Float(x) => vec![x],
        other => return Err(wrong_type(name, &other, "float[]")),
    };
    if values.iter().any(|w| !(w.is_finite() && *w >= 0.0)) {
        return Err(PrimError::Width { name });
    }
    let expanded =
        expand(&values, counts, interpolation(prim, name).as_deref()).ok_or_else(|| {
            PrimError::WidthCount {
                name,
                values: values.len(),
                curves: counts.len(),
                vertices: counts.iter().sum(),
            }
        })?;
    Ok(Some(expanded))
}

/// `values` expanded to one per vertex, by count (and the `interpolation` metadata when the
/// counts are ambiguous): constant, per curve, per vertex.
fn expand<T: Copy>(values: &[T], counts: &[i64], interp: Option<&str>) -> Option<Vec<T>> {
    let total: i64 = counts.iter().sum();
    let n = values.len() as i64;
    let per_curve =
        n == counts.len() as i64 && interp != Some("vertex") && interp != Some("varying");
    if n == total && !per_curve {
        Some(values.to_vec())
    } else if per_curve {
        Some(
            counts
                .iter()
                .zip(values)
                .flat_map(|(&c, &v)| std::iter::repeat_n(v, c as usize))
                .collect(),
        )
    } else if n == 1 {
        Some(vec![values[0]; total as usize])
    } else {
        None
    }
}

/// One root UV per curve from `primvars:surface_uv_coordinate` or `primvars:st`.
fn root_uv(
    prim: &Prim,
    time: TimeCode,
    counts: &[i64],
) -> Result<Option<Vec<[f32; 2]>>, PrimError> {
    for name in ["primvars:surface_uv_coordinate", "primvars:st"] {
        let Some(v) = value_at(prim, name, time)? else {
            continue;
        };
        let values: Vec<[f32; 2]> = match v {
            sdf::Value::Vec2fVec(v) => v.iter().map(|p| [p.x, p.y]).collect(),
            sdf::Value::Vec2dVec(v) => v.iter().map(|p| [p.x as f32, p.y as f32]).collect(),
            other => return Err(wrong_type(name, &other, "float2[]")),
        };
        let per_vertex =
            expand(&values, counts, interpolation(prim, name).as_deref()).ok_or_else(|| {
                PrimError::RootUvCount {
                    name,
                    values: values.len(),
                    curves: counts.len(),
                    vertices: counts.iter().sum(),
                }
            })?;
        let mut roots = Vec::with_capacity(counts.len());
        let mut start = 0usize;
        for &c in counts {
            roots.push(per_vertex[start]);
            start += c as usize;
        }
        return Ok(Some(roots));
    }
    Ok(None)
}

/// Why a prim's attributes cannot be read as curves, a mesh or a primvar. The reader adds the
/// file and the prim; the message says what is wrong and how to fix it.
#[derive(Debug, Error)]
pub(crate) enum PrimError {
    /// `openusd` could not read an attribute.
    #[error("attribute {name}: {error:#}")]
    Attribute { name: String, error: anyhow::Error },
    /// A prim path does not parse.
    #[error("{error:#}")]
    Path { error: anyhow::Error },
    /// `openusd` could not read the xformOps of a prim (the prim or an ancestor).
    #[error("{prim} xformOps: {error:#}")]
    XformOps { prim: String, error: anyhow::Error },
    /// `openusd` could not read the time samples of an xformOp.
    #[error("{prim} {op}: {error:#}")]
    XformOpTimes {
        prim: String,
        op: String,
        error: anyhow::Error,
    },
    /// `openusd` could not list the prim's properties.
    #[error("cannot list the prim's properties: {error:#}")]
    Properties { error: anyhow::Error },
    /// An attribute holds another type than the one read (`found`: USD's type name).
    #[error("{name} is {found}, not {expected}")]
    Type {
        name: String,
        found: String,
        expected: &'static str,
    },
    /// A `BasisCurves` prim has no `curveVertexCounts`.
    #[error("has no curveVertexCounts; export the curves with their vertex counts")]
    NoCurveVertexCounts,
    /// The prim has no points at the time read.
    #[error("has no points (at this time)")]
    NoPoints,
    /// The curve vertex counts do not tile the points, or a curve has fewer than 2.
    #[error(
        "curveVertexCounts ({curves} curves, {total} vertices, smallest {smallest}) disagree \
         with its {points} points; every curve needs ≥ 2 points and the counts must sum to the \
         points"
    )]
    CurveCounts {
        curves: usize,
        total: i64,
        smallest: i64,
        points: usize,
    },
    /// A point has a NaN or infinite coordinate.
    #[error("point {point} has a non-finite coordinate")]
    NonFinitePoint { point: usize },
    /// The curves are closed.
    #[error(
        "has periodic (closed) curves; hair needs open curves (wrap = \"nonperiodic\" or \
         \"pinned\")"
    )]
    Periodic,
    /// A width is negative or not finite.
    #[error("{name} has a negative or non-finite width")]
    Width { name: &'static str },
    /// The widths are neither one, one per curve nor one per vertex.
    #[error(
        "{name} has {values} values, which fits neither 1 (constant), {curves} (uniform, per \
         curve) nor {vertices} (vertex); fix its count or interpolation"
    )]
    WidthCount {
        name: &'static str,
        values: usize,
        curves: usize,
        vertices: i64,
    },
    /// The root UVs are neither one per curve nor one per vertex.
    #[error(
        "{name} has {values} values, which fits neither {curves} (per curve) nor {vertices} (per \
         vertex)"
    )]
    RootUvCount {
        name: &'static str,
        values: usize,
        curves: usize,
        vertices: i64,
    },
    /// A `Mesh` prim lacks `faceVertexCounts` or `faceVertexIndices`.
    #[error(
        "has no {name}; export the mesh with its faces (a Mesh prim needs faceVertexCounts and \
         faceVertexIndices)"
    )]
    NoTopology { name: &'static str },
    /// A face has fewer than 3 corners.
    #[error("face {face} has {corners} corners; every face needs at least 3")]
    FaceCorners { face: usize, corners: i32 },
    /// The face corner counts do not sum to the corner indices.
    #[error(
        "faceVertexCounts sum to {total} corners but faceVertexIndices has {indices}; fix the \
         export"
    )]
    CornerCount { total: i64, indices: usize },
    /// The mesh has no face.
    #[error("has no faces; a scalp or collider needs triangles")]
    NoFaces,
    /// A corner refers to no point.
    #[error("faceVertexIndices[{corner}] = {point} but the mesh has {points} points")]
    CornerPoint {
        corner: usize,
        point: i32,
        points: usize,
    },
    /// A UV is not finite.
    #[error("{name}[{index}] is not finite")]
    NonFiniteUv { name: &'static str, index: usize },
    /// A UV index is negative or missing.
    #[error("{name}:indices[{element}] = {index}")]
    UvIndex {
        name: &'static str,
        element: usize,
        index: i32,
    },
    /// A UV element asks for a value past the values.
    #[error("{name} has {values} values but element {element} asks for value {index}")]
    UvElement {
        name: &'static str,
        values: usize,
        element: usize,
        index: usize,
    },
    /// Face-varying UVs are not one per face corner.
    #[error("{name} is faceVarying with {elements} values for {corners} face corners")]
    UvCorners {
        name: &'static str,
        elements: usize,
        corners: usize,
    },
    /// The UVs are neither one per point nor one per face corner.
    #[error(
        "{name} has {elements} values, which fits neither {points} points (vertex) nor \
         {corners} face corners (faceVarying)"
    )]
    UvCount {
        name: &'static str,
        elements: usize,
        points: usize,
        corners: usize,
    },
    /// A primvar is not on the prim (`primvars`: the prim's primvars, sorted).
    #[error(
        "is not on the prim (its primvars: {}); check the name (Blender's USD export writes a \
         vertex group or a float attribute NAME as primvars:NAME)",
        list_or_none(.primvars)
    )]
    NoPrimvar { primvars: Vec<String> },
    /// A primvar value is not finite.
    #[error("value {index} is {value}; give finite values")]
    NonFiniteValue { index: usize, value: f32 },
    /// A primvar holds more than one value per element (`found`: the metadata, printed).
    #[error("has elementSize {found}; a map needs one value per element (elementSize 1)")]
    ElementSize { found: String },
    /// A primvar's indices are not `int[]`.
    #[error("its indices ({attr}:indices) are {found}, not int[]")]
    PrimvarIndices { attr: String, found: String },
    /// A primvar's interpolation is none of USD's.
    #[error(
        "has interpolation \"{found}\"; USD's are constant, uniform, vertex, varying and \
         faceVarying"
    )]
    Interpolation { found: String },
    /// A primvar's element count does not match its interpolation.
    #[error(
        "has {elements} {} but the mesh has {wanted} {per}{}; author the interpolation that \
         matches its values (constant 1, uniform {faces}, vertex {points}, faceVarying {corners})",
        if *.indexed { "indices" } else { "values" },
        if *.unauthored {
            " (no interpolation is authored, and USD's fallback is constant)"
        } else {
            ""
        }
    )]
    ElementCount {
        /// Indices (when `indexed`) or values held.
        elements: usize,
        indexed: bool,
        /// Elements the interpolation needs.
        wanted: usize,
        /// What they are per ("faces (uniform)").
        per: &'static str,
        /// Whether no interpolation is authored.
        unauthored: bool,
        faces: usize,
        points: usize,
        corners: usize,
    },
    /// A primvar index refers to no value.
    #[error("{attr}:indices[{element}] = {index}, but there are {values} values")]
    PrimvarIndex {
        attr: String,
        element: usize,
        index: i32,
        values: usize,
    },
    /// A channel of a scalar primvar is asked for.
    #[error(
        "holds one value per element, so it has no component {component} (channel \"{}\"); \
         leave out the channel",
        ["r", "g", "b"].get(*.component).copied().unwrap_or("?")
    )]
    NoComponent { component: usize },
    /// A component past the third of a 3-vector primvar is asked for.
    #[error("has 3 components; component {component} does not exist (use r, g or b)")]
    Component { component: usize },
    /// A primvar holds a type a map does not read.
    #[error(
        "is {found}; a map reads float, double, half or int values (one per element) or \
         color3f/float3 (one channel)"
    )]
    ValueType { found: String },
}

/// `names` joined by ", ", or "none".
fn list_or_none(names: &[String]) -> String {
    if names.is_empty() {
        "none".to_string()
    } else {
        names.join(", ")
    }
}

#[cfg(test)]
mod tests;
