use super::*;

/// A stage in cm, Y up: a square (one quad) under an Xform that moves +10 cm along x
/// between time 1 and 3, whose points rise by 1 cm per time code; range 1–3.
const ANIMATED: &str = r#"#usda 1.0
(
    metersPerUnit = 0.01
    upAxis = "Y"
    startTimeCode = 1
    endTimeCode = 3
)
def Xform "Char" {
    double3 xformOp:translate.timeSamples = { 1: (0, 0, 0), 3: (10, 0, 0) }
    uniform token[] xformOpOrder = ["xformOp:translate"]
    def Mesh "body" {
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points.timeSamples = {
            1: [(0, 0, 0), (1, 0, 0), (1, 0, -1), (0, 0, -1)],
            2: [(0, 1, 0), (1, 1, 0), (1, 1, -1), (0, 1, -1)],
            3: [(0, 2, 0), (1, 2, 0), (1, 2, -1), (0, 2, -1)],
        }
        texCoord2f[] primvars:st = [(0, 0), (1, 0), (1, 1), (0, 1)] (interpolation = "faceVarying")
    }
    def Sphere "ball" {}
}
"#;

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn opts(prim: &str) -> UsdMeshOptions {
    UsdMeshOptions {
        prim: prim.into(),
        units: None,
    }
}

#[test]
fn points_and_transforms_are_read_at_each_time_in_meters_z_up() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "c.usda", ANIMATED);
    let src = UsdMeshSource::open(&path, &opts("/Char/body")).unwrap();
    assert!(src.is_animated());
    assert_eq!(src.time_range(), Some((1.0, 3.0)));
    assert_eq!(src.triangles(), [[0, 1, 2], [0, 2, 3]]);
    for (t, dx, up) in [(1.0, 0.0, 0.0), (2.0, 5.0, 1.0), (3.0, 10.0, 2.0)] {
        let p = src.positions_at(t).unwrap();
        // File (x, y, z) in cm, Y up → (x, −z, y) m; the Xform adds dx cm along x.
        let want = [
            Vector3::new(dx, 0.0, up),
            Vector3::new(1.0 + dx, 0.0, up),
            Vector3::new(1.0 + dx, 1.0, up),
            Vector3::new(dx, 1.0, up),
        ];
        for (a, b) in p.iter().zip(want) {
            assert!(
                (a - b * 0.01).norm() < 1e-7,
                "time {t}: {a:?} vs {:?}",
                b * 0.01
            );
        }
    }
    let mesh = src.mesh_at(2.0).unwrap();
    assert_eq!(mesh.uvs().unwrap()[2], Vector2::new(1.0, 1.0));
    // The quad's normal points up (+Z) after the Y-up turn: the winding is kept.
    assert!(
        mesh.vertex_normals()[0].z > 0.99,
        "{:?}",
        mesh.vertex_normals()[0]
    );
}

#[test]
fn a_missing_prim_lists_the_mesh_prims() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "c.usda", ANIMATED);
    let e = UsdMeshSource::open(&path, &opts("/Char/head"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("c.usda") && e.contains("/Char/head") && e.contains("/Char/body"),
        "{e}"
    );
    let e = UsdMeshSource::open(&path, &opts("/Char/ball"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("Sphere, not a Mesh") && e.contains("/Char/body"),
        "{e}"
    );
}

#[test]
fn a_time_outside_the_stage_range_names_file_prim_and_time() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "c.usda", ANIMATED);
    let src = UsdMeshSource::open(&path, &opts("/Char/body")).unwrap();
    let e = src.positions_at(4.0).unwrap_err().to_string();
    assert!(
        e.contains("c.usda") && e.contains("time 4") && e.contains("1 to 3"),
        "{e}"
    );
    // Without an authored range, the prim's samples bound the times.
    let unranged = ANIMATED.replace("    startTimeCode = 1\n    endTimeCode = 3\n", "");
    let path = write(dir.path(), "u.usda", &unranged);
    let src = UsdMeshSource::open(&path, &opts("/Char/body")).unwrap();
    let e = src.positions_at(0.0).unwrap_err().to_string();
    assert!(
        e.contains("/Char/body at time 0") && e.contains("1 to 3"),
        "{e}"
    );
}

#[test]
fn a_topology_change_over_time_names_the_time() {
    let dir = tempfile::tempdir().unwrap();
    let grown = ANIMATED.replace(
        "3: [(0, 2, 0), (1, 2, 0), (1, 2, -1), (0, 2, -1)],",
        "3: [(0, 2, 0), (1, 2, 0), (1, 2, -1), (0, 2, -1), (5, 5, 5)],",
    );
    let path = write(dir.path(), "g.usda", &grown);
    let src = UsdMeshSource::open(&path, &opts("/Char/body")).unwrap();
    assert!(src.positions_at(2.0).is_ok());
    let e = src.positions_at(3.0).unwrap_err().to_string();
    assert!(
        e.contains("g.usda") && e.contains("/Char/body at time 3") && e.contains("topology"),
        "{e}"
    );
    let refaced = ANIMATED.replace(
        "int[] faceVertexIndices = [0, 1, 2, 3]",
        "int[] faceVertexIndices.timeSamples = { 1: [0, 1, 2, 3], 3: [1, 2, 3, 0] }",
    );
    let path = write(dir.path(), "f.usda", &refaced);
    let src = UsdMeshSource::open(&path, &opts("/Char/body")).unwrap();
    let e = src.positions_at(3.0).unwrap_err().to_string();
    assert!(
        e.contains("at time 3") && e.contains("faceVertexIndices"),
        "{e}"
    );
}

#[test]
fn a_usdz_without_a_usd_layer_is_named() {
    use std::io::Write;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("tex.usdz");
    let mut zip = zip::ZipWriter::new(std::fs::File::create(&path).unwrap());
    zip.start_file("albedo.png", zip::write::SimpleFileOptions::default())
        .unwrap();
    zip.write_all(b"not a layer").unwrap();
    zip.finish().unwrap();
    let e = UsdMeshSource::open(&path, &opts("/Char/body"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("tex.usdz") && e.contains("no USD layer") && e.contains("albedo.png"),
        "{e}"
    );
}

#[test]
fn left_handed_and_mirrored_meshes_keep_the_outside() {
    // A left-handed quad and a mirroring scale both flip the winding; together they cancel.
    let dir = tempfile::tempdir().unwrap();
    let base = ANIMATED.replace(
        "        int[] faceVertexCounts = [4]",
        "        uniform token orientation = \"leftHanded\"\n        int[] faceVertexCounts = [4]",
    );
    let path = write(dir.path(), "l.usda", &base);
    let left = UsdMeshSource::open(&path, &opts("/Char/body")).unwrap();
    assert_eq!(left.triangles(), [[0, 2, 1], [0, 3, 2]]);
    let mirrored = base.replace(
        "uniform token[] xformOpOrder = [\"xformOp:translate\"]",
        "float3 xformOp:scale = (-1, 1, 1)\n    uniform token[] xformOpOrder = [\"xformOp:translate\", \"xformOp:scale\"]",
    );
    let path = write(dir.path(), "m.usda", &mirrored);
    let both = UsdMeshSource::open(&path, &opts("/Char/body")).unwrap();
    assert_eq!(both.triangles(), [[0, 1, 2], [0, 2, 3]]);
}
