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
//!
//! **No copies of the big arrays.** [`UsdLayer::add_curves`] and [`UsdLayer::add_mesh`] take their
//! prim by value and move its arrays into the layer: a flat `Vec<f32>` of x, y, z becomes the
//! layer's `Vec<Vec3f>` by reinterpreting the same allocation (`bytemuck::try_cast_vec`; both are
//! 4-byte aligned `f32`s), and the writers read the layer's values in place. A million children ×
//! 17 points (204 MB of points) are therefore written from the buffer the children were generated
//! into, with no copy on the way out but the one into the file.

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

    /// Adds a `BasisCurves` prim (linear, non-periodic); its arrays move into the layer.
    pub fn add_curves(&mut self, c: UsdCurvesPrim<'_>) {
        // Bounds first: the points move into the layer below.
        let extent = c
            .extent
            .then(|| extent_samples(&c.points, c.widths.as_ref()));
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
            Value::IntVec(c.vertex_counts),
            false,
            None,
        );
        attr("points", "point3f[]", vec3_samples(c.points), false, None);
        if let Some(v) = c.velocities {
            attr("velocities", "vector3f[]", vec3_samples(v), false, None);
        }
        if let Some(w) = c.widths {
            attr("widths", "float[]", float_samples(w), false, Some("vertex"));
        }
        if let Some(uv) = c.root_uv {
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
        if let Some(rgb) = c.colors {
            attr(
                "primvars:displayColor",
                "color3f[]",
                Value::Vec3fVec(vec3(rgb)),
                false,
                Some("uniform"),
            );
        }
        for (name, v) in c.uniform_floats {
            let name = format!("primvars:{name}");
            attr(&name, "float[]", Value::FloatVec(v), false, Some("uniform"));
        }
        for (name, v) in c.uniform_ints {
            let name = format!("primvars:{name}");
            attr(&name, "int[]", Value::IntVec(v), false, Some("uniform"));
        }
        if let Some(extent) = extent {
            attr("extent", "float3[]", extent, false, None);
        }
        self.set_properties(&prim, props);
    }

    /// Adds a `Mesh` prim; its arrays move into the layer.
    pub fn add_mesh(&mut self, m: UsdMeshPrim<'_>) {
        let extent = extent_samples(&m.points, None);
        let prim = self.add_prim(m.name, "Mesh");
        let mut props = Vec::new();
        let mut attr = |name: &str, ty: &str, value: Value, uniform: bool, interp: Option<&str>| {
            self.attribute(&prim, name, ty, value, uniform, interp);
            props.push(name.to_string());
        };
        attr(
            "faceVertexCounts",
            "int[]",
            Value::IntVec(m.face_vertex_counts),
            false,
            None,
        );
        attr(
            "faceVertexIndices",
            "int[]",
            Value::IntVec(m.face_vertex_indices),
            false,
            None,
        );
        attr("points", "point3f[]", vec3_samples(m.points), false, None);
        attr(
            "subdivisionScheme",
            "token",
            Value::token("none"),
            true,
            None,
        );
        if let Some(uv) = m.uv {
            attr(
                "primvars:st",
                "texCoord2f[]",
                Value::Vec2fVec(vec2(uv)),
                false,
                Some("vertex"),
            );
        }
        if let Some(rgb) = m.colors {
            attr(
                "primvars:displayColor",
                "color3f[]",
                Value::Vec3fVec(vec3(rgb)),
                false,
                Some("vertex"),
            );
        }
        attr("extent", "float3[]", extent, false, None);
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

/// Flat x, y, z as `Vec3f`s: the same allocation reinterpreted (no copy) when its length and
/// capacity are whole `Vec3f`s, else copied; a trailing partial triple is dropped.
fn vec3(flat: Vec<f32>) -> Vec<gf::Vec3f> {
    regroup(flat, |c: &[f32; 3]| gf::Vec3f {
        x: c[0],
        y: c[1],
        z: c[2],
    })
}

/// Flat u, v as `Vec2f`s, like [`vec3`].
fn vec2(flat: Vec<f32>) -> Vec<gf::Vec2f> {
    regroup(flat, |c: &[f32; 2]| gf::Vec2f { x: c[0], y: c[1] })
}

/// `flat` grouped into `T`s of `N` `f32`s each: reinterpreted in place when the allocation holds
/// whole `T`s (the common case: buffers sized `N × count`), else copied through `make`.
fn regroup<T: bytemuck::Pod, const N: usize>(
    mut flat: Vec<f32>,
    make: impl Fn(&[f32; N]) -> T,
) -> Vec<T> {
    debug_assert_eq!(std::mem::size_of::<T>(), N * std::mem::size_of::<f32>());
    flat.truncate(flat.len() - flat.len() % N);
    if !flat.capacity().is_multiple_of(N) {
        // Shrinking a large allocation is an in-place `realloc` (no copy) in the usual allocators.
        flat.shrink_to_fit();
    }
    match bytemuck::allocation::try_cast_vec::<f32, T>(flat) {
        Ok(v) => v,
        Err((_, flat)) => flat
            .chunks_exact(N)
            .map(|c| make(c.try_into().expect("chunks of N")))
            .collect(),
    }
}

/// An attribute's value: each array of `s` through `one`, as a default, time samples, or both
/// (a `Value::ValueVec` of the default and the time samples, split again by the layer).
fn sampled(s: Samples, one: impl Fn(Vec<f32>) -> Value) -> Value {
    let times = |t: Vec<(f64, Vec<f32>)>| {
        Value::TimeSamples(t.into_iter().map(|(time, v)| (time, one(v))).collect())
    };
    match s {
        Samples::Default(v) => one(v),
        Samples::Times(t) => times(t),
        Samples::DefaultAndTimes(v, t) => Value::ValueVec(vec![one(v), times(t)]),
    }
}

/// A `float3[]` attribute value.
fn vec3_samples(s: Samples) -> Value {
    sampled(s, |v| Value::Vec3fVec(vec3(v)))
}

/// A `float[]` attribute value.
fn float_samples(s: Samples) -> Value {
    sampled(s, Value::FloatVec)
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
    let value = |b: Option<Bounds>| {
        let (lo, hi) = b.unwrap_or(([0.0; 3], [0.0; 3]));
        let corner = |c: [f32; 3], d: f32| gf::Vec3f {
            x: c[0] + d,
            y: c[1] + d,
            z: c[2] + d,
        };
        Value::Vec3fVec(vec![corner(lo, -pad), corner(hi, pad)])
    };
    let times = |t: &[(f64, Vec<f32>)]| {
        Value::TimeSamples(
            t.iter()
                .map(|(time, v)| (*time, value(bounds(v))))
                .collect(),
        )
    };
    match points {
        Samples::Default(v) => value(bounds(v)),
        Samples::Times(t) => times(t),
        // The default extent bounds every sample (a reader without a time sees them all).
        Samples::DefaultAndTimes(_, t) => {
            let all = points
                .arrays()
                .into_iter()
                .filter_map(bounds)
                .reduce(|(lo, hi), (l, h)| {
                    (
                        std::array::from_fn(|k| lo[k].min(l[k])),
                        std::array::from_fn(|k| hi[k].max(h[k])),
                    )
                });
            Value::ValueVec(vec![value(all), times(t)])
        }
    }
}

/// Lowest and highest x, y, z.
type Bounds = ([f32; 3], [f32; 3]);

/// The bounds of flat x, y, z points; `None` for no points.
fn bounds(v: &[f32]) -> Option<Bounds> {
    if v.len() < 3 {
        return None;
    }
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for p in v.chunks_exact(3) {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    Some((lo, hi))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::usd::{read_usd, UsdReadOptions};

    #[test]
    fn flat_points_become_vec3s_in_their_own_allocation_without_a_copy() {
        let mut flat = Vec::with_capacity(3 * 1000);
        flat.extend((0..3000).map(|i| i as f32));
        let at = flat.as_ptr() as usize;
        let v = vec3(flat);
        assert_eq!(v.as_ptr() as usize, at, "the points were copied");
        assert_eq!((v.len(), v[999].x, v[999].z), (1000, 2997.0, 2999.0));
    }

    #[test]
    fn flat_points_in_an_odd_sized_allocation_keep_their_values() {
        // A capacity that is no whole number of triples (and a trailing partial triple).
        let mut flat = Vec::with_capacity(3 * 5 + 2);
        flat.extend((0..3 * 5 + 1).map(|i| i as f32 * 0.5));
        let v = vec3(flat);
        assert_eq!(v.len(), 5);
        for (i, p) in v.iter().enumerate() {
            let x = (3 * i) as f32 * 0.5;
            assert_eq!((p.x, p.y, p.z), (x, x + 0.5, x + 1.0));
        }
        let uv = vec2(vec![0.25, 0.75, 1.0]);
        assert_eq!(uv, vec![gf::Vec2f { x: 0.25, y: 0.75 }]);
    }

    /// The text writer prints arrays in blocks (`vendor/openusd`, `stream_vec`): arrays many
    /// blocks long, in the default and in time samples, read back bit for bit; so do the binary
    /// writer's, written from the layer in place.
    #[test]
    fn arrays_longer_than_a_text_block_read_back_bit_exact_in_text_and_binary() {
        let curves = 4000;
        let n = 17;
        let points: Vec<f32> = (0..curves * n * 3)
            .map(|i| ((i as f32) * 0.618_034).sin() * 0.123_456_7 + i as f32 * 1e-6)
            .collect();
        let widths: Vec<f32> = (0..curves * n).map(|i| 1e-4 / (1 + i % n) as f32).collect();
        let dir = tempfile::tempdir().unwrap();
        for ext in ["usda", "usdc"] {
            let path = dir.path().join(format!("big.{ext}"));
            let mut layer = UsdLayer::new(&UsdStageInfo {
                up_axis: UpAxis::Z,
                meters_per_unit: 1.0,
                time_codes_per_second: Some(24.0),
                time_range: Some((1.0, 2.0)),
            });
            let shifted: Vec<f32> = points.iter().map(|p| p + 1.0).collect();
            layer.add_curves(UsdCurvesPrim {
                name: "hair",
                vertex_counts: vec![n as i32; curves],
                points: Samples::DefaultAndTimes(
                    points.clone(),
                    vec![(1.0, points.clone()), (2.0, shifted)],
                ),
                widths: Some(Samples::Default(widths.clone())),
                velocities: None,
                root_uv: None,
                colors: None,
                extent: true,
                uniform_floats: Vec::new(),
                uniform_ints: Vec::new(),
            });
            layer.write(&path).unwrap();
            let read = read_usd(&path, &UsdReadOptions::default()).unwrap();
            let back: Vec<f32> = read
                .groom
                .curves()
                .iter()
                .flatten()
                .flat_map(|p| [p.x, p.y, p.z])
                .collect();
            assert_eq!(back.len(), points.len(), "{ext}");
            let same = back
                .iter()
                .zip(&points)
                .all(|(a, b)| a.to_bits() == b.to_bits());
            assert!(same, "{ext}: points changed on the way through the file");
            let radii = read.radii.expect("widths were written");
            let same = radii
                .iter()
                .zip(&widths)
                .all(|(r, w)| r.to_bits() == (0.5 * w).to_bits());
            assert!(same, "{ext}: widths changed on the way through the file");
        }
    }
}
