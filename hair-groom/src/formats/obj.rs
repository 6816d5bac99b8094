//! Wavefront OBJ meshes (scalps, heads, colliders) read with `tobj`: faces triangulated as fans,
//! one index per vertex, every object and group of the file merged into one [`TriMesh`],
//! converted to Z up and scaled to meters.
//!
//! Vertices are split where the file gives one position different texture coordinates or
//! normals (UV seams, sharp edges): that is what one index per vertex means. Normals in the file
//! are otherwise ignored; [`TriMesh`] computes its own. Points and lines are ignored, materials
//! are not read.

use std::path::Path;

use hair_core::{MeshError, TriMesh};
use nalgebra::Vector2;
use thiserror::Error;

use super::{check_options, to_world};
use crate::error::GroomError;

/// Which axis points up in the file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum UpAxis {
    /// Y up (Maya, most OBJ exporters' default, Blender's OBJ exporter default): converted to Z
    /// up by (x, y, z) -> (x, -z, y), so the file's front (+Z) faces -Y as in Blender.
    Y,
    /// Z up (Blender's own convention): coordinates are kept.
    #[default]
    Z,
}

/// How to read an OBJ file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ObjOptions {
    /// Meters per file unit (e.g. 0.01 for a file in centimeters); finite and > 0.
    pub scale: f32,
    /// Up axis of the file; the mesh returned is always Z up.
    pub up_axis: UpAxis,
}

impl Default for ObjOptions {
    /// A file in meters, Z up: coordinates are kept as they are.
    fn default() -> Self {
        Self {
            scale: 1.0,
            up_axis: UpAxis::Z,
        }
    }
}

/// Loads the OBJ file at `path` as one triangle mesh in meters, Z up.
///
/// Every object and group of the file is merged; polygons are triangulated as fans. The mesh
/// keeps per-vertex UVs when every face of the file has texture coordinates. Errors name the
/// file: missing or unreadable, not parseable, no triangles, a non-finite coordinate or a
/// degenerate triangle (its index counts the file's triangles from 0 after triangulation), and a
/// `scale` that is not finite and > 0.
pub fn load_obj(path: &Path, opts: &ObjOptions) -> Result<TriMesh, GroomError> {
    check_options(opts)?;
    let models = parse(path)?;
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    let mut uvs = Vec::new();
    let mut all_have_uvs = true;
    for model in &models {
        let mesh = &model.mesh;
        let base = positions.len() as u32;
        let count = mesh.positions.len() / 3;
        positions.extend(
            mesh.positions
                .chunks_exact(3)
                .map(|p| to_world([p[0], p[1], p[2]], opts)),
        );
        triangles.extend(
            mesh.indices
                .chunks_exact(3)
                .map(|t| [t[0] + base, t[1] + base, t[2] + base]),
        );
        all_have_uvs &= mesh.texcoords.len() == 2 * count;
        uvs.extend(
            mesh.texcoords
                .chunks_exact(2)
                .map(|t| Vector2::new(t[0], t[1])),
        );
    }
    if triangles.is_empty() {
        return Err(GroomError::ObjNoTriangles {
            path: path.to_path_buf(),
        });
    }
    let with_file = |source| GroomError::ObjMesh {
        path: path.to_path_buf(),
        source,
    };
    let mesh = TriMesh::new(positions, triangles).map_err(with_file)?;
    if !all_have_uvs {
        return Ok(mesh);
    }
    if let Some(vertex) = uvs.iter().position(|uv| !uv.iter().all(|c| c.is_finite())) {
        return Err(with_file(
            MeshError::NonFiniteUv {
                vertex,
                uv: uvs[vertex].into(),
            }
            .into(),
        ));
    }
    mesh.with_uvs(uvs).map_err(with_file)
}

/// The per-vertex colours of the OBJ file at `path` (`v x y z r g b`, each channel as written,
/// usually 0–1), in the vertex order of the mesh [`load_obj`] returns; `None` when some vertex
/// has no colour. Refused, naming the file and the vertex, if a colour is not finite; the file is
/// read as [`load_obj`] reads it.
pub fn load_obj_vertex_colors(path: &Path) -> Result<Option<Vec<[f32; 3]>>, GroomError> {
    let mut colors = Vec::new();
    for model in parse(path)? {
        let mesh = &model.mesh;
        if mesh.vertex_color.len() != mesh.positions.len() {
            return Ok(None);
        }
        colors.extend(
            mesh.vertex_color
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]]),
        );
    }
    if let Some(vertex) = colors.iter().position(|c| !c.iter().all(|x| x.is_finite())) {
        return Err(GroomError::ObjMesh {
            path: path.to_path_buf(),
            source: MeshError::NonFiniteColor {
                vertex,
                color: colors[vertex],
            }
            .into(),
        });
    }
    Ok(Some(colors))
}

/// The models of the OBJ file at `path`, as tobj reads them with one index per vertex and
/// faces triangulated. The file is read whole first (a regular file within
/// [`MAX_GROOM_FILE_BYTES`](crate::input_file::MAX_GROOM_FILE_BYTES), so tobj never reads a
/// device or a FIFO), must be UTF-8, and its face indices are checked before tobj resolves them.
fn parse(path: &Path) -> Result<Vec<tobj::Model>, GroomError> {
    let bytes = super::read_bytes(path)?;
    let unparsable = |reason: ObjParseError| GroomError::ObjParse {
        path: path.to_path_buf(),
        reason,
    };
    let text = std::str::from_utf8(&bytes).map_err(|e| {
        unparsable(ObjParseError::NotUtf8 {
            byte: e.valid_up_to(),
        })
    })?;
    check_face_indices(text).map_err(unparsable)?;
    let load = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    // Materials are not needed: refuse to open any material library the file names.
    let (models, _materials) = tobj::load_obj_buf(&mut text.as_bytes(), &load, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| unparsable(ObjParseError::Tobj(e)))?;
    Ok(models)
}

/// Checks that every index of every `f` line refers to a vertex, texture coordinate or normal
/// defined above it (1-based, or negative: relative to the last one). tobj 4.0.5 resolves
/// indices without that check and multiplies them unchecked (`vt * 2`), which overflows on an
/// index such as `-2147483648`.
fn check_face_indices(text: &str) -> Result<(), ObjParseError> {
    // Vertices, texture coordinates and normals defined so far.
    let mut counts = [0i64; 3];
    const KINDS: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    for (n, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => counts[0] += 1,
            Some("vt") => counts[1] += 1,
            Some("vn") => counts[2] += 1,
            Some("f") => {
                for word in words {
                    for (k, index) in word.split('/').enumerate().take(3) {
                        // Empty (`v//vn`) or unparsable indices are left to tobj's own errors.
                        let Ok(i) = index.parse::<i64>() else {
                            continue;
                        };
                        if i == 0 || i.unsigned_abs() > counts[k] as u64 {
                            return Err(ObjParseError::FaceIndex {
                                line: n + 1,
                                index: i,
                                kind: KINDS[k],
                                defined: counts[k],
                            });
                        }
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// Why an OBJ file cannot be parsed.
#[derive(Debug, Error)]
pub enum ObjParseError {
    /// The file is not UTF-8 text.
    #[error("byte {byte} is not UTF-8 text (an OBJ file is text; this looks like a binary file)")]
    NotUtf8 {
        /// Offset of the first byte that is not UTF-8.
        byte: usize,
    },
    /// A face index refers to no vertex, texture coordinate or normal defined above it.
    #[error(
        "line {line}: face index `{index}` refers to no {kind} (the file defines {defined} above \
         this line; indices start at 1, negative ones count back from the last)"
    )]
    FaceIndex {
        /// The 1-based line of the face.
        line: usize,
        /// The index as written.
        index: i64,
        /// `"vertex"`, `"texture coordinate"` or `"normal"`.
        kind: &'static str,
        /// How many of them the file defines above the line.
        defined: i64,
    },
    /// The OBJ parser (tobj) refused the file.
    #[error(transparent)]
    Tobj(tobj::LoadError),
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use nalgebra::Vector3;

    use super::*;

    /// The Sintel bust (Blender Foundation), shipped in `data/sintel/`: Y up, centimeters.
    const SINTEL: &str = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../data/sintel/sintel_bust.obj"
    );

    fn write(dir: &tempfile::TempDir, name: &str, text: &[u8]) -> PathBuf {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    fn bounds(mesh: &TriMesh) -> (Vector3<f32>, Vector3<f32>) {
        mesh.positions().iter().fold(
            (Vector3::repeat(f32::MAX), Vector3::repeat(f32::MIN)),
            |(lo, hi), p| (lo.inf(p), hi.sup(p)),
        )
    }

    #[test]
    fn sintel_loads_z_up_in_meters() {
        let opts = ObjOptions {
            scale: 0.01,
            up_axis: UpAxis::Y,
        };
        let mesh = load_obj(Path::new(SINTEL), &opts).unwrap();
        assert_eq!(mesh.positions().len(), 3046);
        assert_eq!(mesh.triangles().len(), 5952);
        assert!(mesh.uvs().is_none(), "the file has no texture coordinates");
        let (lo, hi) = bounds(&mesh);
        let size = hi - lo;
        assert!((size.z - 0.43).abs() < 0.01, "height {}", size.z);
        // Symmetric about x = 0, shoulders wider than deep, face towards -Y (nose at y ≈ -0.119).
        assert!((lo.x + hi.x).abs() < 1e-5);
        assert!(size.x > size.y);
        assert!(-lo.y > hi.y);
    }

    #[test]
    fn y_up_conversion_and_uvs() {
        let dir = tempfile::tempdir().unwrap();
        let text = b"o a\nv 0 0 0\nv 1 0 0\nv 0 2 3\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n\
                     o b\nv 0 0 0\nv 0 0 1\nv 1 0 0\nv 1 0 1\nvt 0 0\nvt 0 1\nvt 1 0\nvt 1 1\n\
                     f 4/4 6/6 7/7 5/5\n";
        let path = write(&dir, "two.obj", text);
        let opts = ObjOptions {
            scale: 2.0,
            up_axis: UpAxis::Y,
        };
        let mesh = load_obj(&path, &opts).unwrap();
        // A triangle and a quad (two triangles) merged; the quad's vertices follow the triangle's.
        assert_eq!(mesh.triangles().len(), 3);
        assert_eq!(mesh.positions().len(), 7);
        assert_eq!(mesh.positions()[2], Vector3::new(0.0, -6.0, 4.0));
        assert!(mesh.triangles()[1..].iter().flatten().all(|&i| i >= 3));
        let uvs = mesh.uvs().unwrap();
        assert_eq!(uvs[2], Vector2::new(0.0, 1.0));
    }

    #[test]
    fn uvs_dropped_when_some_faces_lack_them() {
        let dir = tempfile::tempdir().unwrap();
        let text = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n\
                     f 1/1 2/2 3/3\nf 2 4 3\n";
        let mesh = load_obj(&write(&dir, "mixed.obj", text), &ObjOptions::default()).unwrap();
        assert_eq!(mesh.triangles().len(), 2);
        assert!(mesh.uvs().is_none());
    }

    #[test]
    fn missing_file_is_named() {
        let err = load_obj(Path::new("/no/such/head.obj"), &ObjOptions::default()).unwrap_err();
        let msg = err.to_string();
        assert!(matches!(err, GroomError::Input(_)), "{msg}");
        assert!(
            msg.contains("/no/such/head.obj") && msg.contains("check"),
            "{msg}"
        );
    }

    #[test]
    fn garbage_is_refused_with_the_reason() {
        let dir = tempfile::tempdir().unwrap();
        let binary = write(
            &dir,
            "binary.obj",
            &[0xff, 0xfe, 0x00, 0x9c, 0x80, b'\n', 0xc3],
        );
        let err = load_obj(&binary, &ObjOptions::default()).unwrap_err();
        assert!(matches!(err, GroomError::ObjParse { .. }), "{err}");
        assert!(err.to_string().contains("binary.obj"), "{err}");

        let bad_vertex = write(&dir, "bad.obj", b"v 1 2 banana\nf 1 1 1\n");
        let err = load_obj(&bad_vertex, &ObjOptions::default()).unwrap_err();
        assert!(err.to_string().contains("position parse error"), "{err}");

        let prose = write(&dir, "prose.obj", b"this is not a mesh\nat all\n");
        let err = load_obj(&prose, &ObjOptions::default()).unwrap_err();
        assert!(matches!(err, GroomError::ObjNoTriangles { .. }), "{err}");
        assert!(err.to_string().contains("prose.obj"), "{err}");
    }

    #[test]
    fn face_index_out_of_range_is_refused_with_its_line() {
        let dir = tempfile::tempdir().unwrap();
        for (face, kind) in [
            ("f 1 2 4", "no vertex"),
            ("f 1/1 2/1 3/-2", "no texture coordinate"),
            ("f 1//1 2//1 3//-2147483648", "no normal"),
            ("f 0 1 2", "no vertex"),
        ] {
            let text = format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n{face}\n");
            let path = write(&dir, "index.obj", text.as_bytes());
            let err = load_obj(&path, &ObjOptions::default())
                .unwrap_err()
                .to_string();
            assert!(
                err.contains("index.obj: line 6") && err.contains(kind),
                "{err}"
            );
        }
    }

    #[test]
    fn vertex_colors_follow_the_mesh_vertices() {
        let dir = tempfile::tempdir().unwrap();
        let text = b"v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf 3 2 1\n";
        let path = write(&dir, "rgb.obj", text);
        let colors = load_obj_vertex_colors(&path).unwrap().unwrap();
        // Vertices come in the order faces first use them, as in `load_obj`.
        assert_eq!(colors, [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]]);
        let mesh = load_obj(&path, &ObjOptions::default()).unwrap();
        assert_eq!(mesh.positions()[0], nalgebra::Vector3::new(0.0, 1.0, 0.0));
        let plain = write(&dir, "plain.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        assert_eq!(load_obj_vertex_colors(&plain).unwrap(), None);
    }

    #[test]
    fn points_and_lines_are_not_triangles() {
        let dir = tempfile::tempdir().unwrap();
        let path = write(&dir, "wire.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nf 3\n");
        let err = load_obj(&path, &ObjOptions::default()).unwrap_err();
        assert!(matches!(err, GroomError::ObjNoTriangles { .. }), "{err}");
    }

    #[test]
    fn degenerate_face_is_named_with_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let text = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n";
        let path = write(&dir, "flat.obj", text);
        let err = load_obj(&path, &ObjOptions::default()).unwrap_err();
        let msg = err.to_string();
        assert!(matches!(err, GroomError::ObjMesh { .. }), "{msg}");
        assert!(
            msg.contains("flat.obj") && msg.contains("triangle 1") && msg.contains("degenerate"),
            "{msg}"
        );
    }

    #[test]
    fn non_finite_values_are_named_with_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let position = write(&dir, "nanv.obj", b"v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
        let err = load_obj(&position, &ObjOptions::default()).unwrap_err();
        assert!(err.to_string().contains("nanv.obj"), "{err}");
        assert!(err.to_string().contains("non-finite coordinate"), "{err}");
        let uv = write(
            &dir,
            "nanvt.obj",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt inf 0\nvt 0 1\nf 1/1 2/2 3/3\n",
        );
        let err = load_obj(&uv, &ObjOptions::default()).unwrap_err();
        assert!(err.to_string().contains("nanvt.obj"), "{err}");
        assert!(err.to_string().contains("texture coordinate"), "{err}");
    }

    #[test]
    fn bad_scale_is_refused() {
        for scale in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            let opts = ObjOptions {
                scale,
                up_axis: UpAxis::Z,
            };
            let err = load_obj(Path::new(SINTEL), &opts).unwrap_err();
            assert!(err.to_string().contains("`scale`"), "{err}");
        }
    }
}
