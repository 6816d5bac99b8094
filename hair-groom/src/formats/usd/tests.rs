use super::*;
use crate::formats::test_support::{assert_round_trip, tricky_groom};

fn round_trip(ext: &str) -> impl Fn(&Groom, &ImportOptions) -> Groom + '_ {
    move |g, o| {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(format!("g.{ext}"));
        write_usda(&path, g, o).unwrap();
        read_usda(&path, o).unwrap()
    }
}

#[test]
fn write_then_read_is_bit_exact_in_text_and_binary() {
    assert_round_trip(&tricky_groom(), round_trip("usda"));
    assert_round_trip(&tricky_groom(), round_trip("usdc"));
}

#[test]
fn written_stage_units_are_read_back_without_options() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("g.usdc");
    let groom = tricky_groom();
    let cm_y = ImportOptions {
        scale: 0.01,
        up_axis: UpAxis::Y,
    };
    write_usda(
        &path,
        &Groom::new(vec![groom.curves()[1].clone()]).unwrap(),
        &cm_y,
    )
    .unwrap();
    let read = read_usd(&path, &UsdReadOptions::default()).unwrap();
    assert_eq!(
        (read.meters_per_unit, read.up_axis),
        (0.01f32 as f64, UpAxis::Y)
    );
    for (a, b) in read.groom.curves()[0].iter().zip(&groom.curves()[1]) {
        assert!((a - b).norm() < 1e-6, "{a:?} vs {b:?}");
    }
}

/// Every truncation of a valid `.usdc`: an error that names the file, never a panic that
/// escapes (the reader's `catch_unwind` guard) nor an abort on a huge allocation (the vendored
/// openusd's `read_vec` reads before it allocates). Byte corruption (huge counts, flipped
/// bytes) is `tests/usdc_corrupt.rs`.
#[test]
fn truncated_usdc_is_an_error_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("g.usdc");
    write_usda(&good, &tricky_groom(), &ImportOptions::default()).unwrap();
    let bytes = std::fs::read(&good).unwrap();
    let bad_path = dir.path().join("bad.usdc");
    for cut in 0..bytes.len() {
        std::fs::write(&bad_path, &bytes[..cut]).unwrap();
        let e = read_usd(&bad_path, &UsdReadOptions::default()).unwrap_err();
        assert!(e.to_string().contains("bad.usdc"), "{e}");
    }
}

#[test]
fn periodic_curves_and_bad_counts_are_refused_by_prim() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("g.usda");
    std::fs::write(
        &path,
        "#usda 1.0\ndef BasisCurves \"c\" {\n uniform token wrap = \"periodic\"\n int[] curveVertexCounts = [2]\n point3f[] points = [(0,0,0),(0,0,1)]\n}\n",
    )
    .unwrap();
    let err = read_usd(&path, &UsdReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("g.usda") && err.contains("/c") && err.contains("periodic"),
        "{err}"
    );
    std::fs::write(
        &path,
        "#usda 1.0\ndef BasisCurves \"c\" {\n int[] curveVertexCounts = [3]\n point3f[] points = [(0,0,0),(0,0,1)]\n}\n",
    )
    .unwrap();
    let err = read_usd(&path, &UsdReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(err.contains("/c") && err.contains("disagree"), "{err}");
}

#[test]
fn bezier_curves_keep_their_on_curve_points() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("g.usda");
    std::fs::write(
        &path,
        "#usda 1.0\n(\n upAxis = \"Z\"\n metersPerUnit = 1\n)\ndef BasisCurves \"c\" {\n uniform token type = \"cubic\"\n uniform token basis = \"bezier\"\n int[] curveVertexCounts = [4]\n point3f[] points = [(0,0,0),(0,0,1),(0,0,2),(0,0,3)]\n float[] widths = [0.5] (interpolation = \"constant\")\n}\n",
    )
    .unwrap();
    let read = read_usd(&path, &UsdReadOptions::default()).unwrap();
    assert_eq!(
        read.groom.curves()[0],
        [Vector3::zeros(), Vector3::new(0.0, 0.0, 3.0)]
    );
    assert_eq!(read.radii.unwrap(), [0.25, 0.25]);
}
