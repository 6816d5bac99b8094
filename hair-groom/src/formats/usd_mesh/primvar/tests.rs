//! Primvars at triangle corners against USD's interpolation rules, on a hand-written stage: a
//! quad (points 0 1 2 3) and a triangle (points 1 4 2), fanned into the triangles
//! [0 1 2], [0 2 3] and [1 4 2] (face corners 0 1 2, 0 2 3 and 4 5 6).

use std::path::{Path, PathBuf};

use super::super::{UsdMeshOptions, UsdMeshSource};
use super::PrimvarInterpolation;

/// `lin` at a point: the linear field painted on `vertex`, `faceVarying` and `color` primvars.
fn lin(p: [f32; 3]) -> f32 {
    0.1 + 0.2 * p[0] + 0.3 * p[1]
}

const POINTS: [[f32; 3]; 5] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 1.0, 0.0],
    [2.0, 0.5, 0.0],
];
const FACE_INDICES: [usize; 7] = [0, 1, 2, 3, 1, 4, 2];

fn stage(orientation: &str) -> String {
    let fmt = |v: Vec<f32>| {
        v.iter()
            .map(|x| format!("{x}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let vertex = fmt(POINTS.iter().map(|&p| lin(p)).collect());
    let corners = fmt(FACE_INDICES.iter().map(|&i| lin(POINTS[i])).collect());
    let colors = POINTS
        .iter()
        .map(|&p| format!("(0.9, {}, 0.05)", lin(p)))
        .collect::<Vec<_>>()
        .join(", ");
    format!(
        r#"#usda 1.0
(
    metersPerUnit = 1
    upAxis = "Z"
)
def Mesh "scalp" {{
    uniform token orientation = "{orientation}"
    int[] faceVertexCounts = [4, 3]
    int[] faceVertexIndices = [0, 1, 2, 3, 1, 4, 2]
    point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (2, 0.5, 0)]
    float[] primvars:lin = [{vertex}] (interpolation = "vertex")
    double[] primvars:lin_varying = [{vertex}] (interpolation = "varying")
    float[] primvars:corner = [{corners}] (interpolation = "faceVarying")
    float[] primvars:per_face = [0.25, 0.75] (interpolation = "uniform")
    float primvars:one = 0.5 (interpolation = "constant")
    float[] primvars:one_array = [0.625] (interpolation = "constant")
    float[] primvars:indexed = [0.2, 0.8] (interpolation = "faceVarying")
    int[] primvars:indexed:indices = [0, 1, 1, 0, 1, 0, 0]
    color3f[] primvars:color = [{colors}] (interpolation = "vertex")
    float[] primvars:short = [1, 2, 3] (interpolation = "vertex")
    float[] primvars:unauthored = [1, 2, 3, 4, 5]
    float[] primvars:bad_index = [0.2, 0.8] (interpolation = "vertex")
    int[] primvars:bad_index:indices = [0, 1, 2, 0, 1]
    float2[] primvars:pair = [(0, 1), (0, 1), (0, 1), (0, 1), (0, 1)] (interpolation = "vertex")
}}
"#
    )
}

fn open(orientation: &str) -> (tempfile::TempDir, UsdMeshSource) {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), &stage(orientation));
    let src = UsdMeshSource::open(
        &path,
        &UsdMeshOptions {
            prim: "/scalp".into(),
            units: None,
        },
    )
    .unwrap();
    (dir, src)
}

fn write(dir: &Path, text: &str) -> PathBuf {
    let p = dir.join("scalp.usda");
    std::fs::write(&p, text).unwrap();
    p
}

fn close(a: [f32; 3], b: [f32; 3]) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-6)
}

#[test]
fn vertex_and_face_varying_primvars_give_each_corner_its_points_value() {
    for orientation in ["rightHanded", "leftHanded"] {
        let (_dir, src) = open(orientation);
        let tris = src.triangles().to_vec();
        // Without UVs mesh vertex i is USD point i.
        let want: Vec<[f32; 3]> = tris
            .iter()
            .map(|t| t.map(|v| lin(POINTS[v as usize])))
            .collect();
        for name in ["lin", "lin_varying", "primvars:corner"] {
            let got = src.primvar(name, None, 0.0).unwrap();
            assert_eq!(got.values.len(), 3, "{name}");
            for (g, w) in got.values.iter().zip(&want) {
                assert!(close(*g, *w), "{orientation} {name}: {g:?} vs {w:?}");
            }
        }
        let color = src.primvar("color", Some(1), 0.0).unwrap();
        for (g, w) in color.values.iter().zip(&want) {
            assert!(close(*g, *w), "{orientation} color g: {g:?} vs {w:?}");
        }
        let red = src.primvar("color", None, 0.0).unwrap();
        assert!(red.values.iter().all(|v| close(*v, [0.9; 3])));
    }
}

#[test]
fn uniform_constant_and_indexed_primvars_follow_faces_and_indices() {
    let (_dir, src) = open("rightHanded");
    let uni = src.primvar("per_face", None, 0.0).unwrap();
    assert_eq!(uni.interpolation, PrimvarInterpolation::Uniform);
    // The quad's two triangles take face 0's value, the triangle face 1's.
    assert_eq!(uni.values, vec![[0.25; 3], [0.25; 3], [0.75; 3]]);
    for (name, v) in [("one", 0.5), ("one_array", 0.625)] {
        let c = src.primvar(name, None, 0.0).unwrap();
        assert_eq!(c.interpolation, PrimvarInterpolation::Constant);
        assert_eq!(c.values, vec![[v; 3]; 3], "{name}");
    }
    // Face corners 0..7 take values [a b b a | b a a] (a = 0.2, b = 0.8); the fans are corners
    // (0 1 2), (0 2 3), (4 5 6).
    let ix = src.primvar("indexed", None, 0.0).unwrap();
    assert_eq!(
        ix.values,
        vec![[0.2, 0.8, 0.8], [0.2, 0.8, 0.2], [0.8, 0.2, 0.2]]
    );
}

#[test]
fn a_primvar_whose_count_does_not_fit_its_interpolation_is_refused_naming_it() {
    let (_dir, src) = open("rightHanded");
    let e = src.primvar("short", None, 0.0).unwrap_err().to_string();
    assert!(
        e.contains("scalp.usda")
            && e.contains("/scalp")
            && e.contains("primvars:short")
            && e.contains("3 values")
            && e.contains("5 points"),
        "{e}"
    );
    let e = src
        .primvar("unauthored", None, 0.0)
        .unwrap_err()
        .to_string();
    assert!(e.contains("fallback is constant"), "{e}");
    let e = src.primvar("bad_index", None, 0.0).unwrap_err().to_string();
    assert!(e.contains("primvars:bad_index:indices[2] = 2"), "{e}");
}

#[test]
fn a_missing_primvar_is_refused_listing_the_prims_primvars() {
    let (_dir, src) = open("rightHanded");
    let e = src.primvar("density", None, 0.0).unwrap_err().to_string();
    assert!(
        e.contains("primvars:density")
            && e.contains("is not on the prim")
            && e.contains("primvars:lin")
            && !e.contains("primvars:indexed:indices"),
        "{e}"
    );
}

#[test]
fn a_channel_of_a_float_primvar_or_a_two_component_primvar_is_refused() {
    let (_dir, src) = open("rightHanded");
    let e = src.primvar("lin", Some(1), 0.0).unwrap_err().to_string();
    assert!(e.contains("leave out the channel"), "{e}");
    let e = src.primvar("pair", None, 0.0).unwrap_err().to_string();
    assert!(e.contains("color3f/float3"), "{e}");
}
