//! One USD layer of hair and meshes, written as `.usdc` (binary crate file) or `.usda` (text)
//! through the `openusd` crate: the writer hairsys's USD exports go through (grooms here, render
//! children in `hair-render`, whole-run shots in `hairsys`; hair cards still write their own
//! `.usda`).
//!
//! A [`UsdLayer`] holds the stage metadata ([`UsdStageInfo`]: `upAxis`, `metersPerUnit`,
//! `timeCodesPerSecond`, the time range) and root prims: `BasisCurves` ([`UsdCurvesPrim`]:
//! linear curves with `points`, `velocities`, `widths`, root UV (`primvars:st` and
//! `primvars:surface_uv_coordinate`),
//! `primvars:displayColor`, `extent`) and `Mesh` ([`UsdMeshPrim`]). Any of `points`,
//! `velocities` and `widths` can be one value ([`Samples::Default`]) or time samples
//! ([`Samples::Times`]: one array per time code), which is how a whole run becomes one animated
//! file. [`UsdLayer::write`] picks the format by the file's extension (`.usda` text; `.usdc` or
//! `.usd` binary) and writes through a `.partial` sibling renamed into place, so a failed write
//! never leaves a truncated file under the final name.
//!
//! The `.usdc` writer is `openusd` 0.6's with one fix (children lists typed `TfTokenVector`,
//! `vendor/openusd/VENDORED.md`), without which Pixar's USD refuses the file.

use std::fmt;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use openusd::sdf::{self, ChildrenKey, FieldKey, SpecType, Specifier, Value};
use openusd::{gf, usda, usdc};

use crate::formats::obj::UpAxis;

/// Stage metadata of a layer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UsdStageInfo {
    /// The up axis written as `upAxis`.
    pub up_axis: UpAxis,
    /// Meters per unit, written as `metersPerUnit`.
    pub meters_per_unit: f64,
    /// Time codes per second (the frame rate, frames/s); `None` writes none.
    pub time_codes_per_second: Option<f64>,
    /// `startTimeCode` and `endTimeCode`; `None` writes none.
    pub time_range: Option<(f64, f64)>,
}

/// A flat `f32` array attribute: one value, or one value per time code.
#[derive(Debug, Clone, PartialEq)]
pub enum Samples {
    /// The attribute's default value (flat components).
    Default(Vec<f32>),
    /// `(time code, flat components)` in increasing time.
    Times(Vec<(f64, Vec<f32>)>),
    /// A default value (what a reader gets without a time) and time samples.
    DefaultAndTimes(Vec<f32>, Vec<(f64, Vec<f32>)>),
}

impl Samples {
    /// Every array of the attribute.
    fn arrays(&self) -> Vec<&[f32]> {
        match self {
            Samples::Default(v) => vec![v.as_slice()],
            Samples::Times(t) => t.iter().map(|(_, v)| v.as_slice()).collect(),
            Samples::DefaultAndTimes(v, t) => std::iter::once(v.as_slice())
                .chain(t.iter().map(|(_, v)| v.as_slice()))
                .collect(),
        }
    }
}

/// A linear `BasisCurves` prim at the root of the layer.
#[derive(Debug, Clone, PartialEq)]
pub struct UsdCurvesPrim<'a> {
    /// Prim name (a USD identifier), e.g. `"hair"`.
    pub name: &'a str,
    /// Points per curve (`curveVertexCounts`).
    pub vertex_counts: Vec<i32>,
    /// `points`: x, y, z per vertex, stage units.
    pub points: Samples,
    /// `widths` per vertex (`vertex` interpolation), stage units.
    pub widths: Option<Samples>,
    /// `velocities`: x, y, z per vertex, stage units per second.
    pub velocities: Option<Samples>,
    /// Root UV per curve, u, v (`uniform` interpolation): written as `primvars:st` (renderers)
    /// and `primvars:surface_uv_coordinate` (the attribute Blender's curves carry it in).
    pub root_uv: Option<Vec<f32>>,
    /// `primvars:displayColor`: r, g, b per curve (`uniform` interpolation).
    pub colors: Option<Vec<f32>>,
    /// Write `extent` (bounds of the points, per time sample when they are sampled).
    pub extent: bool,
    /// More per-curve `float` primvars (`uniform`): `(name without "primvars:", values)`.
    pub uniform_floats: Vec<(&'a str, Vec<f32>)>,
    /// More per-curve `int` primvars (`uniform`): `(name without "primvars:", values)`.
    pub uniform_ints: Vec<(&'a str, Vec<i32>)>,
}

/// A polygon `Mesh` prim at the root of the layer.
#[derive(Debug, Clone, PartialEq)]
pub struct UsdMeshPrim<'a> {
    /// Prim name, e.g. `"scalp"`.
    pub name: &'a str,
    /// Vertices per face (`faceVertexCounts`).
    pub face_vertex_counts: Vec<i32>,
    /// Vertex indices of the faces (`faceVertexIndices`).
    pub face_vertex_indices: Vec<i32>,
    /// `points`: x, y, z per vertex, stage units.
    pub points: Samples,
    /// `primvars:st`: u, v per vertex (`vertex` interpolation).
    pub uv: Option<Vec<f32>>,
    /// `primvars:displayColor`: r, g, b per vertex.
    pub colors: Option<Vec<f32>>,
}

/// Why a layer could not be written.
#[derive(Debug)]
pub enum UsdWriteError {
    /// The operating system refused the file.
    Io(std::io::Error),
    /// The USD encoder refused the data.
    Encode(String),
}

impl fmt::Display for UsdWriteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UsdWriteError::Io(e) => write!(f, "{e}"),
            UsdWriteError::Encode(e) => write!(f, "the USD encoder refused the data: {e}"),
        }
    }
}

impl std::error::Error for UsdWriteError {}

/// The USD file formats [`UsdLayer::write`] writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UsdEncoding {
    /// `.usda` text.
    Text,
    /// `.usdc` (or `.usd`) binary crate file.
    Binary,
}

impl UsdEncoding {
    /// The encoding a file name's extension asks for (`usda`; `usdc`, `usd`), else `None`.
    pub fn of(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "usda" => Some(Self::Text),
            "usdc" | "usd" => Some(Self::Binary),
            _ => None,
        }
    }
}

/// One USD layer being built (see the module docs).
pub struct UsdLayer {
    data: sdf::Data,
    root_children: Vec<String>,
}

impl UsdLayer {
    /// An empty layer with `info` as its stage metadata.
    pub fn new(info: &UsdStageInfo) -> Self {
        let mut data = sdf::Data::new();
        let root = data.create_spec(sdf::Path::abs_root(), SpecType::PseudoRoot);
        let up = match info.up_axis {
            UpAxis::Y => "Y",
            UpAxis::Z => "Z",
        };
        root.add("upAxis", Value::token(up));
        root.add("metersPerUnit", Value::Double(info.meters_per_unit));
        if let Some(fps) = info.time_codes_per_second {
            root.add(FieldKey::TimeCodesPerSecond, Value::Double(fps));
            root.add(FieldKey::FramesPerSecond, Value::Double(fps));
        }
        if let Some((lo, hi)) = info.time_range {
            root.add(FieldKey::StartTimeCode, Value::Double(lo));
            root.add(FieldKey::EndTimeCode, Value::Double(hi));
        }
        Self {
            data,
            root_children: Vec::new(),
        }
    }

    /// Makes the root prim `name` the stage's default prim.
    pub fn set_default_prim(&mut self, name: &str) {
        if let Some(root) = self.data.spec_mut(&sdf::Path::abs_root()) {
            root.add(FieldKey::DefaultPrim, Value::token(name));
        }
    }

    /// Adds a `BasisCurves` prim (linear, non-periodic).
    pub fn add_curves(&mut self, c: &UsdCurvesPrim<'_>) {
        let prim = self.add_prim(c.name, "BasisCurves");
        let mut props = Vec::new();
        let mut attr = |name: &str, ty: &str, value: Value, uniform: bool, interp: Option<&str>| {
            self.attribute(&prim, name, ty, value, uniform, interp);
            props.push(name.to_string());
        };
        attr("type", "token", Value::token("linear"), true, None);
        attr("wrap", "token", Value::token("nonperiodic"), true, None);
        attr(
            "curveVertexCounts",
            "int[]",
            Value::IntVec(c.vertex_counts.clone()),
            false,
            None,
        );
        attr("points", "point3f[]", vec3_samples(&c.points), false, None);
        if let Some(v) = &c.velocities {
            attr("velocities", "vector3f[]", vec3_samples(v), false, None);
        }
        if let Some(w) = &c.widths {
            attr("widths", "float[]", float_samples(w), false, Some("vertex"));
        }
        if let Some(uv) = &c.root_uv {
            // `st` for renderers; `surface_uv_coordinate` is the name Blender's curves use.
            let uv = vec2(uv);
            attr(
                "primvars:st",
                "texCoord2f[]",
                Value::Vec2fVec(uv.clone()),
                false,
                Some("uniform"),
            );
            attr(
                "primvars:surface_uv_coordinate",
                "float2[]",
                Value::Vec2fVec(uv),
                false,
                Some("uniform"),
            );
        }
        if let Some(rgb) = &c.colors {
            attr(
                "primvars:displayColor",
                "color3f[]",
                Value::Vec3fVec(vec3(rgb)),
                false,
                Some("uniform"),
            );
        }
        for (name, v) in &c.uniform_floats {
            let name = format!("primvars:{name}");
            attr(
                &name,
                "float[]",
                Value::FloatVec(v.clone()),
                false,
                Some("uniform"),
            );
        }
        for (name, v) in &c.uniform_ints {
            let name = format!("primvars:{name}");
            attr(
                &name,
                "int[]",
                Value::IntVec(v.clone()),
                false,
                Some("uniform"),
            );
        }
        if c.extent {
            attr(
                "extent",
                "float3[]",
                extent_samples(&c.points, c.widths.as_ref()),
                false,
                None,
            );
        }
        self.set_properties(&prim, props);
    }

    /// Adds a `Mesh` prim.
    pub fn add_mesh(&mut self, m: &UsdMeshPrim<'_>) {
        let prim = self.add_prim(m.name, "Mesh");
        let mut props = Vec::new();
        let mut attr = |name: &str, ty: &str, value: Value, uniform: bool, interp: Option<&str>| {
            self.attribute(&prim, name, ty, value, uniform, interp);
            props.push(name.to_string());
        };
        attr(
            "faceVertexCounts",
            "int[]",
            Value::IntVec(m.face_vertex_counts.clone()),
            false,
            None,
        );
        attr(
            "faceVertexIndices",
            "int[]",
            Value::IntVec(m.face_vertex_indices.clone()),
            false,
            None,
        );
        attr("points", "point3f[]", vec3_samples(&m.points), false, None);
        attr(
            "subdivisionScheme",
            "token",
            Value::token("none"),
            true,
            None,
        );
        if let Some(uv) = &m.uv {
            attr(
                "primvars:st",
                "texCoord2f[]",
                Value::Vec2fVec(vec2(uv)),
                false,
                Some("vertex"),
            );
        }
        if let Some(rgb) = &m.colors {
            attr(
                "primvars:displayColor",
                "color3f[]",
                Value::Vec3fVec(vec3(rgb)),
                false,
                Some("vertex"),
            );
        }
        attr(
            "extent",
            "float3[]",
            extent_samples(&m.points, None),
            false,
            None,
        );
        self.set_properties(&prim, props);
    }

    /// Writes the layer to `path`, as text or binary by its extension (see [`UsdEncoding`];
    /// any other extension is written as text).
    pub fn write(&self, path: &Path) -> Result<(), UsdWriteError> {
        let encoding = UsdEncoding::of(path).unwrap_or(UsdEncoding::Text);
        let partial = partial_path(path);
        let result = (|| {
            let file = std::fs::File::create(&partial).map_err(UsdWriteError::Io)?;
            let mut out = BufWriter::with_capacity(1 << 20, file);
            match encoding {
                UsdEncoding::Text => usda::TextWriter::write(&self.data, &mut out),
                UsdEncoding::Binary => usdc::CrateWriter::write(&self.data, &mut out),
            }
            .map_err(|e| match e.downcast::<std::io::Error>() {
                Ok(io) => UsdWriteError::Io(io),
                Err(e) => UsdWriteError::Encode(format!("{e:#}")),
            })?;
            let file = out
                .into_inner()
                .map_err(|e| UsdWriteError::Io(e.into_error()))?;
            file.sync_all().map_err(UsdWriteError::Io)?;
            std::fs::rename(&partial, path).map_err(UsdWriteError::Io)
        })();
        if result.is_err() {
            let _ = std::fs::remove_file(&partial);
        }
        result
    }

    /// Writes the layer as text to `out` (e.g. a `Vec<u8>`).
    pub fn write_text<W: Write>(&self, out: &mut W) -> Result<(), UsdWriteError> {
        usda::TextWriter::write(&self.data, out)
            .map_err(|e| UsdWriteError::Encode(format!("{e:#}")))
    }

    /// Creates the prim spec `/name` of `type_name`, listed among the root's children.
    fn add_prim(&mut self, name: &str, type_name: &str) -> sdf::Path {
        let path = sdf::Path::abs_root()
            .append_path(name)
            .unwrap_or_else(|_| sdf::Path::abs_root());
        let spec = self.data.create_spec(path.clone(), SpecType::Prim);
        spec.add(FieldKey::Specifier, Value::Specifier(Specifier::Def));
        spec.add(FieldKey::TypeName, Value::token(type_name));
        self.root_children.push(name.to_string());
        let children = Value::token_vec(self.root_children.clone());
        if let Some(root) = self.data.spec_mut(&sdf::Path::abs_root()) {
            root.add(ChildrenKey::PrimChildren, children);
        }
        path
    }

    /// Creates the attribute `prim.name`.
    fn attribute(
        &mut self,
        prim: &sdf::Path,
        name: &str,
        type_name: &str,
        value: Value,
        uniform: bool,
        interpolation: Option<&str>,
    ) {
        let Ok(path) = prim.append_property(name) else {
            return;
        };
        let spec = self.data.create_spec(path, SpecType::Attribute);
        spec.add(FieldKey::TypeName, Value::token(type_name));
        if uniform {
            spec.add(
                FieldKey::Variability,
                Value::Variability(sdf::Variability::Uniform),
            );
        }
        if let Some(i) = interpolation {
            spec.add("interpolation", Value::token(i));
        }
        // `sampled` pairs a default with time samples as a two-element `ValueVec`.
        match value {
            Value::TimeSamples(t) => spec.add(FieldKey::TimeSamples, Value::TimeSamples(t)),
            Value::ValueVec(mut pair) if pair.len() == 2 => {
                let times = pair.pop().unwrap_or(Value::None);
                let default = pair.pop().unwrap_or(Value::None);
                spec.add(FieldKey::Default, default);
                spec.add(FieldKey::TimeSamples, times);
            }
            v => spec.add(FieldKey::Default, v),
        }
    }

    /// Lists a prim's properties.
    fn set_properties(&mut self, prim: &sdf::Path, props: Vec<String>) {
        if let Some(spec) = self.data.spec_mut(prim) {
            spec.add(ChildrenKey::PropertyChildren, Value::token_vec(props));
        }
    }
}

/// `path` with `.partial` appended to its name.
fn partial_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".partial");
    path.with_file_name(name)
}

/// Flat x, y, z as `Vec3f`s.
fn vec3(flat: &[f32]) -> Vec<gf::Vec3f> {
    flat.chunks_exact(3)
        .map(|c| gf::Vec3f {
            x: c[0],
            y: c[1],
            z: c[2],
        })
        .collect()
}

/// Flat u, v as `Vec2f`s.
fn vec2(flat: &[f32]) -> Vec<gf::Vec2f> {
    flat.chunks_exact(2)
        .map(|c| gf::Vec2f { x: c[0], y: c[1] })
        .collect()
}

/// An attribute's value: each array of `s` through `one`, as a default, time samples, or both
/// (a `Value::TimeSamples` wrapping the default first, split again by the layer).
fn sampled(s: &Samples, one: impl Fn(&[f32]) -> Value) -> Value {
    let times = |t: &[(f64, Vec<f32>)]| {
        Value::TimeSamples(t.iter().map(|(time, v)| (*time, one(v))).collect())
    };
    match s {
        Samples::Default(v) => one(v),
        Samples::Times(t) => times(t),
        Samples::DefaultAndTimes(v, t) => Value::ValueVec(vec![one(v), times(t)]),
    }
}

/// A `float3[]` attribute value.
fn vec3_samples(s: &Samples) -> Value {
    sampled(s, |v| Value::Vec3fVec(vec3(v)))
}

/// A `float[]` attribute value.
fn float_samples(s: &Samples) -> Value {
    sampled(s, |v| Value::FloatVec(v.to_vec()))
}

/// `extent` of points (grown by half the largest width when given), per time sample.
fn extent_samples(points: &Samples, widths: Option<&Samples>) -> Value {
    let pad = widths.map_or(0.0, |w| {
        0.5 * w
            .arrays()
            .iter()
            .flat_map(|a| a.iter())
            .fold(0.0f32, |m, &x| m.max(x))
    });
    let bounds = |v: &[f32]| {
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for p in v.chunks_exact(3) {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if v.is_empty() {
            lo = [0.0; 3];
            hi = [0.0; 3];
        }
        Value::Vec3fVec(vec![
            gf::Vec3f {
                x: lo[0] - pad,
                y: lo[1] - pad,
                z: lo[2] - pad,
            },
            gf::Vec3f {
                x: hi[0] + pad,
                y: hi[1] + pad,
                z: hi[2] + pad,
            },
        ])
    };
    match points {
        // The default extent bounds every sample (a reader without a time sees them all).
        Samples::DefaultAndTimes(_, t) => {
            let all: Vec<f32> = points.arrays().concat();
            Value::ValueVec(vec![
                bounds(&all),
                sampled(&Samples::Times(t.clone()), bounds),
            ])
        }
        _ => sampled(points, bounds),
    }
}
