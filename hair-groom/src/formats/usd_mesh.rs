//! USD `Mesh` prims read as triangle meshes, at any time code: the scalp and colliders of an
//! animated character (time-sampled `points`, time-sampled transforms, or both).
//!
//! [`UsdMeshSource::open`] opens the stage once (composed by `openusd`, as for curves: see
//! [`super::usd`]), finds the `Mesh` prim by path and reads its topology at the earliest time:
//! `faceVertexCounts` and `faceVertexIndices` triangulated as fans (the OBJ reader's
//! triangulation; `orientation = "leftHanded"` and a mirroring world transform flip the winding
//! so that solids keep their outside), and UVs from `primvars:st` (or `primvars:UVMap`) where
//! present — per point (`vertex`/`varying`), per face corner (`faceVarying`) or indexed
//! (`primvars:st:indices`); a point with several UVs (a seam) becomes one vertex per UV, as
//! the OBJ reader splits vertices. [`UsdMeshSource::positions_at`] then reads the vertices at
//! any time code: `points` at that time, taken to the world by the prim's local-to-world
//! transform at that time (the ancestors' `xformOpOrder` stacks), then to meters and Z up by
//! the stage's `metersPerUnit` and `upAxis` (or the caller's override), the same conventions as
//! [`super::usd::read_usd`] for curves.
//!
//! A mesh whose topology changes over time (another point count, other face counts or
//! indices at some time) is refused, naming the file, the prim and the time: hair is rooted on
//! triangles, so the triangles must stay the same. So are a time outside the stage's authored
//! `startTimeCode`–`endTimeCode` (or, without one, outside the prim's samples when it is
//! animated), a prim path the stage does not have (the error lists its mesh prims) and a
//! `.usdz` with no USD layer in it.
//!
//! Cost: reading a frame is one composed value lookup for `points` and one per xformOp of the
//! prim and its ancestors, then one pass over the points; measured in the workspace's
//! BENCHMARKS.md (a 50k-vertex mesh).

use std::path::{Path, PathBuf};

use hair_core::TriMesh;
use nalgebra::{Matrix4, Vector2, Vector3, Vector4};
use openusd::usd::{Prim, PrimPredicate, Stage, TimeCode};
use openusd::{schemas::geom::Xformable, sdf};

use super::usd::{
    check_time, guarded, interpolation, openable_name, stage_units, token, value_at,
    world_transform, wrong_type, AnyXformable, PrimError,
};
use super::{bad, check_options, to_world, ImportOptions};
use crate::error::{FileLocation, GroomError};

/// Which mesh to read from a stage, and how to place it.
#[derive(Debug, Clone, PartialEq)]
pub struct UsdMeshOptions {
    /// Path of the `Mesh` prim (`"/Char/body"`).
    pub prim: String,
    /// Meters per unit and up axis replacing the stage's `metersPerUnit` and `upAxis`. `None`:
    /// the stage's (USD's fallbacks 0.01 m and Y up when unauthored).
    pub units: Option<ImportOptions>,
}

/// An open stage and one `Mesh` prim on it, read frame by frame (see the module docs).
pub struct UsdMeshSource {
    path: PathBuf,
    stage: Stage,
    prim: String,
    /// Meters per unit and up axis applied.
    place: ImportOptions,
    /// `faceVertexCounts` and `faceVertexIndices` at the earliest time.
    face_counts: Vec<i32>,
    face_indices: Vec<i32>,
    /// Whether counts or indices have time samples (then every read compares them).
    topology_sampled: bool,
    /// Number of USD points.
    point_count: usize,
    /// Triangles over the mesh's vertices.
    triangles: Vec<[u32; 3]>,
    /// Per mesh vertex, the USD point it takes its position from.
    point_of_vertex: Vec<u32>,
    /// Per mesh vertex, its UV, when the prim has UVs.
    uvs: Option<Vec<Vector2<f32>>>,
    /// Whether the fans' winding is flipped (left-handed or mirrored), for [`Self::primvar`].
    flip: bool,
    /// Times the mesh may be read at: the stage's authored range, or the samples' range.
    range: Option<(f64, f64)>,
    /// Whether `points` or a transform of the prim or an ancestor has more than one sample.
    animated: bool,
}

impl std::fmt::Debug for UsdMeshSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("UsdMeshSource")
            .field("path", &self.path)
            .field("prim", &self.prim)
            .field("points", &self.point_count)
            .field("triangles", &self.triangles.len())
            .field("animated", &self.animated)
            .finish_non_exhaustive()
    }
}

impl UsdMeshSource {
    /// Opens the stage at `path` and the `Mesh` prim `opts.prim` on it, reading its topology
    /// and UVs at the earliest time. Errors name the file and the prim (see the module docs).
    pub fn open(path: &Path, opts: &UsdMeshOptions) -> Result<Self, GroomError> {
        if let Some(units) = &opts.units {
            check_options(units)?;
        }
        let name = openable_name(path)?;
        guarded(path, || Self::open_stage(path, name, opts))
    }

    fn open_stage(path: &Path, name: &str, opts: &UsdMeshOptions) -> Result<Self, GroomError> {
        check_package(path)?;
        let stage = Stage::open(name).map_err(|e| {
            bad(
                path,
                FileLocation::File,
                format!(
                    "cannot be opened as a USD stage: {e:#}; check that it is .usd, .usda, .usdc \
                     or a .usdz holding one"
                ),
            )
        })?;
        let (mpu, up_axis) = match &opts.units {
            Some(u) => (f64::from(u.scale), u.up_axis),
            None => stage_units(&stage, path)?,
        };
        let prim_path = find_mesh(&stage, path, &opts.prim)?;
        let prim = stage.prim(prim_path.as_str());
        let fail = |msg: String| bad(path, FileLocation::File, format!("prim {prim_path}: {msg}"));
        let fail_on = |e: PrimError| fail(e.to_string());
        let (face_counts, face_indices) = topology(&prim, TimeCode::EARLIEST).map_err(fail_on)?;
        let points = points_at(&prim, TimeCode::EARLIEST).map_err(fail_on)?;
        let point_count = points.len();
        let corners = check_faces(&face_counts, &face_indices, point_count).map_err(fail_on)?;
        let sampled = |name: &str| -> Result<Vec<f64>, GroomError> {
            prim.attribute(name)
                .time_sample_times()
                .map_err(|e| fail(format!("attribute {name}: {e:#}")))
        };
        let topology_sampled =
            sampled("faceVertexCounts")?.len() > 1 || sampled("faceVertexIndices")?.len() > 1;
        let mut times = sampled("points")?;
        let mut animated = times.len() > 1;
        for op_times in xform_sample_times(&stage, &prim_path).map_err(fail_on)? {
            animated |= op_times.len() > 1;
            times.extend(op_times);
        }
        let range = if stage.has_authored_time_code_range() {
            Some((stage.start_time_code(), stage.end_time_code()))
        } else if animated {
            let lo = times.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = times.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            Some((lo, hi))
        } else {
            None
        };
        let uv_corners = corner_uvs(&prim, &face_indices, point_count).map_err(fail_on)?;
        let world = world_transform(&stage, &prim_path, TimeCode::EARLIEST)
            .map_err(|e| fail(format!("its transform: {e}")))?;
        let left_handed =
            token(value_at(&prim, "orientation", TimeCode::EARLIEST).map_err(fail_on)?).as_deref()
                == Some("leftHanded");
        let mirrored = world.fixed_view::<3, 3>(0, 0).determinant() < 0.0;
        let flip = left_handed != mirrored;
        let (triangles, point_of_vertex, uvs) = triangulate(
            &face_counts,
            &corners,
            point_count,
            uv_corners.as_deref(),
            flip,
        );
        Ok(Self {
            path: path.to_path_buf(),
            stage,
            prim: prim_path,
            place: ImportOptions {
                scale: mpu as f32,
                up_axis,
            },
            face_counts,
            face_indices,
            topology_sampled,
            point_count,
            triangles,
            point_of_vertex,
            uvs,
            flip,
            range,
            animated,
        })
    }

    /// The prim read.
    pub fn prim(&self) -> &str {
        &self.prim
    }

    /// The file read.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The time codes the mesh may be read at (inclusive): the stage's authored
    /// `startTimeCode`–`endTimeCode`, else the range of the prim's samples when it is
    /// animated; `None`: any time (a still mesh on a stage without a range).
    pub fn time_range(&self) -> Option<(f64, f64)> {
        self.range
    }

    /// True when `points` or a transform of the prim or an ancestor has more than one time
    /// sample: the mesh moves or deforms over time.
    pub fn is_animated(&self) -> bool {
        self.animated
    }

    /// Number of mesh vertices (USD points, plus one per extra UV at seams).
    pub fn vertex_count(&self) -> usize {
        self.point_of_vertex.len()
    }

    /// The triangles over the mesh's vertices (fans of the USD faces).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The mesh at time code `time`: [`Self::positions_at`] with the triangles and UVs.
    pub fn mesh_at(&self, time: f64) -> Result<TriMesh, GroomError> {
        let positions = self.positions_at(time)?;
        let at = |e: hair_core::HairError| {
            bad(
                &self.path,
                FileLocation::File,
                format!("prim {} at time {time}: {e}", self.prim),
            )
        };
        let mesh = TriMesh::new(positions, self.triangles.clone()).map_err(at)?;
        match &self.uvs {
            Some(uvs) => mesh.with_uvs(uvs.clone()).map_err(at),
            None => Ok(mesh),
        }
    }

    /// Vertex positions at time code `time`, m, Z up, world space, in the order of
    /// [`Self::triangles`]. Refuses a time outside [`Self::time_range`] and a topology that
    /// differs from the one read at opening, naming the file, the prim and the time.
    pub fn positions_at(&self, time: f64) -> Result<Vec<Vector3<f32>>, GroomError> {
        guarded(&self.path, || self.read_positions(time))
    }

    fn read_positions(&self, time: f64) -> Result<Vec<Vector3<f32>>, GroomError> {
        let fail = |msg: String| {
            bad(
                &self.path,
                FileLocation::File,
                format!("prim {} at time {time}: {msg}", self.prim),
            )
        };
        check_time(&self.stage, &self.path, time)?;
        if let Some((lo, hi)) = self.range {
            if time < lo || time > hi {
                return Err(fail(format!(
                    "time {time} is outside the time range of the prim's samples, {lo} to {hi} \
                     (the stage authors no startTimeCode/endTimeCode); ask for a time in that \
                     range"
                )));
            }
        }
        let at = TimeCode::new(time);
        let prim = self.stage.prim(self.prim.as_str());
        let points = points_at(&prim, at).map_err(|e| fail(e.to_string()))?;
        if points.len() != self.point_count {
            return Err(fail(format!(
                "the topology changes over time: {} points here, {} at the earliest time; hair \
                 needs a mesh whose points and faces stay the same (bake the deformation, not a \
                 remesh)",
                points.len(),
                self.point_count
            )));
        }
        if self.topology_sampled {
            let (counts, indices) = topology(&prim, at).map_err(|e| fail(e.to_string()))?;
            if counts != self.face_counts || indices != self.face_indices {
                return Err(fail(
                    "the topology changes over time: faceVertexCounts or faceVertexIndices \
                     differ from the earliest time's; hair needs a mesh whose faces stay the \
                     same"
                        .into(),
                ));
            }
        }
        let world = world_transform(&self.stage, &self.prim, at)
            .map_err(|e| fail(format!("its transform: {e}")))?;
        let identity = world == Matrix4::identity();
        let placed: Vec<Vector3<f32>> = points
            .iter()
            .map(|p| {
                let local = if identity {
                    *p
                } else {
                    let h = world * Vector4::new(p[0], p[1], p[2], 1.0);
                    [h.x, h.y, h.z]
                };
                to_world(local, &self.place)
            })
            .collect();
        if let Some(i) = placed.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
            return Err(fail(format!("point {i} is not finite ({:?})", points[i])));
        }
        Ok(self
            .point_of_vertex
            .iter()
            .map(|&p| placed[p as usize])
            .collect())
    }
}

/// Refuses a `.usdz` package with no USD layer in it before `openusd` opens it (its own
/// error would not say so).
fn check_package(path: &Path) -> Result<(), GroomError> {
    let is_usdz = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("usdz"));
    if !is_usdz {
        return Ok(());
    }
    let file = std::fs::File::open(path)
        .map_err(|e| bad(path, FileLocation::File, format!("cannot be opened: {e}")))?;
    let names: Vec<String> = zip::ZipArchive::new(file)
        .map_err(|e| {
            bad(
                path,
                FileLocation::File,
                format!("is not a .usdz package (a zip archive): {e}; re-export it"),
            )
        })?
        .file_names()
        .map(str::to_string)
        .collect();
    let is_layer = |n: &str| {
        let n = n.to_ascii_lowercase();
        [".usd", ".usda", ".usdc"].iter().any(|e| n.ends_with(e))
    };
    if names.iter().any(|n| is_layer(n)) {
        return Ok(());
    }
    let shown: Vec<&str> = names.iter().map(String::as_str).take(10).collect();
    Err(bad(
        path,
        FileLocation::File,
        format!(
            "is a .usdz package with no USD layer (.usd, .usda or .usdc) in it (it holds: {}); \
             package the stage's layer with it (usdzip)",
            if shown.is_empty() {
                "nothing".to_string()
            } else {
                shown.join(", ")
            }
        ),
    ))
}

/// The path of the `Mesh` prim `wanted`, or an error listing the stage's mesh prims.
fn find_mesh(stage: &Stage, path: &Path, wanted: &str) -> Result<String, GroomError> {
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
    let meshes: Vec<&String> = all.iter().filter(|p| type_of(p) == "Mesh").collect();
    let listing = || {
        if meshes.is_empty() {
            "the stage has no Mesh prim".to_string()
        } else {
            let shown: Vec<&str> = meshes.iter().take(40).map(|s| s.as_str()).collect();
            format!("its Mesh prims: {}", shown.join(", "))
        }
    };
    let w = wanted.trim_end_matches('/');
    if !all.iter().any(|p| p == w) {
        return Err(bad(
            path,
            FileLocation::File,
            format!("has no prim {w} (or it is inactive); {}", listing()),
        ));
    }
    let t = type_of(w);
    if t != "Mesh" {
        return Err(bad(
            path,
            FileLocation::File,
            format!(
                "prim {w} is a {}, not a Mesh; {}",
                if t.is_empty() { "typeless prim" } else { &t },
                listing()
            ),
        ));
    }
    Ok(w.to_string())
}

/// `faceVertexCounts` and `faceVertexIndices` at `time`.
fn topology(prim: &Prim, time: TimeCode) -> Result<(Vec<i32>, Vec<i32>), PrimError> {
    let ints = |name: &'static str| -> Result<Vec<i32>, PrimError> {
        match value_at(prim, name, time)? {
            Some(sdf::Value::IntVec(v)) => Ok(v),
            Some(other) => Err(wrong_type(name, &other, "int[]")),
            None => Err(PrimError::NoTopology { name }),
        }
    };
    Ok((ints("faceVertexCounts")?, ints("faceVertexIndices")?))
}

/// `points` at `time`, file units, the prim's space.
fn points_at(prim: &Prim, time: TimeCode) -> Result<Vec<[f32; 3]>, PrimError> {
    match value_at(prim, "points", time)? {
        Some(sdf::Value::Vec3fVec(v)) => Ok(v.iter().map(|p| [p.x, p.y, p.z]).collect()),
        Some(sdf::Value::Vec3dVec(v)) => Ok(v
            .iter()
            .map(|p| [p.x as f32, p.y as f32, p.z as f32])
            .collect()),
        Some(other) => Err(wrong_type("points", &other, "point3f[]")),
        None => Err(PrimError::NoPoints),
    }
}

/// Checks the faces against the point count; returns the face corners as point indices.
fn check_faces(counts: &[i32], indices: &[i32], points: usize) -> Result<Vec<u32>, PrimError> {
    if let Some(face) = counts.iter().position(|&c| c < 3) {
        return Err(PrimError::FaceCorners {
            face,
            corners: counts[face],
        });
    }
    let total: i64 = counts.iter().map(|&c| i64::from(c)).sum();
    if total != indices.len() as i64 {
        return Err(PrimError::CornerCount {
            total,
            indices: indices.len(),
        });
    }
    if counts.is_empty() {
        return Err(PrimError::NoFaces);
    }
    indices
        .iter()
        .enumerate()
        .map(|(corner, &p)| {
            if p >= 0 && (p as usize) < points {
                Ok(p as u32)
            } else {
                Err(PrimError::CornerPoint {
                    corner,
                    point: p,
                    points,
                })
            }
        })
        .collect()
}

/// One UV per face corner from `primvars:st` or `primvars:UVMap`, if authored (read at the
/// earliest time: UVs do not animate here).
fn corner_uvs(
    prim: &Prim,
    corners: &[i32],
    points: usize,
) -> Result<Option<Vec<Vector2<f32>>>, PrimError> {
    for name in ["primvars:st", "primvars:UVMap"] {
        let Some(v) = value_at(prim, name, TimeCode::EARLIEST)? else {
            continue;
        };
        let values: Vec<Vector2<f32>> = match v {
            sdf::Value::Vec2fVec(v) => v.iter().map(|p| Vector2::new(p.x, p.y)).collect(),
            sdf::Value::Vec2dVec(v) => v
                .iter()
                .map(|p| Vector2::new(p.x as f32, p.y as f32))
                .collect(),
            other => return Err(wrong_type(name, &other, "texCoord2f[]")),
        };
        if let Some(index) = values.iter().position(|v| !v.iter().all(|c| c.is_finite())) {
            return Err(PrimError::NonFiniteUv { name, index });
        }
        let indices_name = format!("{name}:indices");
        let indices = match value_at(prim, &indices_name, TimeCode::EARLIEST)? {
            Some(sdf::Value::IntVec(ix)) => Some(ix),
            Some(other) => return Err(wrong_type(&indices_name, &other, "int[]")),
            None => None,
        };
        let element = |element: usize| -> Result<Vector2<f32>, PrimError> {
            let j = match &indices {
                Some(ix) => {
                    let index = ix.get(element).copied().unwrap_or(-1);
                    usize::try_from(index).map_err(|_| PrimError::UvIndex {
                        name,
                        element,
                        index,
                    })?
                }
                None => element,
            };
            values.get(j).copied().ok_or(PrimError::UvElement {
                name,
                values: values.len(),
                element,
                index: j,
            })
        };
        let elements = indices.as_ref().map_or(values.len(), Vec::len);
        let interp = interpolation(prim, name);
        let per_corner = match interp.as_deref() {
            Some("faceVarying") => true,
            Some("vertex") | Some("varying") => false,
            _ => elements == corners.len() && elements != points,
        };
        let uvs = if per_corner {
            if elements != corners.len() {
                return Err(PrimError::UvCorners {
                    name,
                    elements,
                    corners: corners.len(),
                });
            }
            (0..corners.len()).map(element).collect::<Result<_, _>>()?
        } else {
            if elements != points {
                return Err(PrimError::UvCount {
                    name,
                    elements,
                    points,
                    corners: corners.len(),
                });
            }
            corners
                .iter()
                .map(|&p| element(p as usize))
                .collect::<Result<_, _>>()?
        };
        return Ok(Some(uvs));
    }
    Ok(None)
}

/// Fans of the faces over mesh vertices. Without UVs, vertex `i` is USD point `i`; with
/// UVs, one vertex per (point, UV) pair in the order the corners first use them. Returns the
/// triangles, each vertex's point and each vertex's UV.
#[allow(clippy::type_complexity)]
fn triangulate(
    counts: &[i32],
    corners: &[u32],
    points: usize,
    uvs: Option<&[Vector2<f32>]>,
    flip: bool,
) -> (Vec<[u32; 3]>, Vec<u32>, Option<Vec<Vector2<f32>>>) {
    let mut vertex_of = std::collections::HashMap::new();
    let mut point_of_vertex: Vec<u32> = match uvs {
        Some(_) => Vec::new(),
        None => (0..points as u32).collect(),
    };
    let mut vertex_uvs = uvs.map(|_| Vec::new());
    let mut vertex = |corner: usize| -> u32 {
        let p = corners[corner];
        let Some(uv) = uvs else {
            return p;
        };
        let key = (p, uv[corner].x.to_bits(), uv[corner].y.to_bits());
        *vertex_of.entry(key).or_insert_with(|| {
            point_of_vertex.push(p);
            if let Some(out) = vertex_uvs.as_mut() {
                out.push(uv[corner]);
            }
            (point_of_vertex.len() - 1) as u32
        })
    };
    let mut triangles = Vec::with_capacity(corners.len());
    for (_, [a, b, d]) in fans(counts) {
        triangles.push(wind([vertex(a), vertex(b), vertex(d)], flip));
    }
    (triangles, point_of_vertex, vertex_uvs)
}

/// The fan triangulation of faces of `counts` corners (each ≥ 3, checked by `check_faces`),
/// triangle after triangle: its face and its three face corners (indices into
/// `faceVertexIndices`) before [`wind`].
fn fans(counts: &[i32]) -> impl Iterator<Item = (usize, [usize; 3])> + '_ {
    let starts = counts.iter().scan(0usize, |start, &c| {
        let s = *start;
        *start += c as usize;
        Some((s, c as usize))
    });
    starts
        .enumerate()
        .flat_map(|(face, (s, c))| (1..c - 1).map(move |k| (face, [s, s + k, s + k + 1])))
}

/// A fan triangle's corners in the mesh's winding: `[a, b, c]`, or `[a, c, b]` when `flip`.
fn wind<T: Copy>([a, b, c]: [T; 3], flip: bool) -> [T; 3] {
    if flip {
        [a, c, b]
    } else {
        [a, b, c]
    }
}

/// Time sample times of every xformOp on the prim at `prim_path` and its ancestors (up to a
/// `!resetXformStack!`), one list per op.
fn xform_sample_times(stage: &Stage, prim_path: &str) -> Result<Vec<Vec<f64>>, PrimError> {
    let mut out = Vec::new();
    let mut p = sdf::path(prim_path).map_err(|error| PrimError::Path { error })?;
    while p != sdf::Path::abs_root() {
        let prim = stage.prim(p.clone());
        let x = AnyXformable(prim.clone());
        let at = |error| PrimError::XformOps {
            prim: p.as_str().to_string(),
            error,
        };
        let order = x.xform_op_order().map_err(at)?.unwrap_or_default();
        for op in order.iter() {
            let op = op.strip_prefix("!invert!").unwrap_or(op);
            if op.starts_with('!') {
                continue;
            }
            out.push(prim.attribute(op).time_sample_times().map_err(|error| {
                PrimError::XformOpTimes {
                    prim: p.as_str().to_string(),
                    op: op.to_string(),
                    error,
                }
            })?);
        }
        if x.resets_xform_stack().map_err(at)? {
            break;
        }
        match p.parent() {
            Some(parent) => p = parent,
            None => break,
        }
    }
    Ok(out)
}

mod primvar;
pub use primvar::{CornerValues, PrimvarInterpolation};
#[cfg(test)]
mod tests;
