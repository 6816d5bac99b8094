//! Grooms read from USD stages that Pixar's USD (`usd-core`) wrote: a Y-up, centimetre stage
//! whose curves sit under a transformed, animated Xform parent must land where usd-core's own
//! `ComputeLocalToWorldTransform` puts them (then × 0.01 m and Y up → Z up), in `.usda` and
//! `.usdc`, at the time asked for; prims are picked by path; bad prims and times are refused by
//! name. Fails (never skips) when python3 or pxr is missing: `scripts/test.sh` installs
//! usd-core into the venv it puts on PATH.

use std::collections::HashMap;
use std::path::Path;
use std::process::Command;

use hair_groom::{read_usd, ImportOptions, UpAxis, UsdReadOptions};

/// Runs `tests/python/<script>` with `args`, panicking with its stderr when it fails.
fn python(script: &str, args: &[&Path]) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("python")
        .join(script);
    let out = Command::new("python3")
        .arg(&path)
        .args(args)
        .output()
        .unwrap_or_else(|e| {
            panic!("cannot run python3 ({e}): run the tests through scripts/test.sh")
        });
    let stderr = String::from_utf8_lossy(&out.stderr);
    match out.status.code() {
        Some(0) => {}
        Some(3) => panic!("Pixar's USD module `pxr` is missing: pip install usd-core ({stderr})"),
        _ => panic!("{script} failed: {stderr}"),
    }
}

/// The fixture's `name values…` lines.
fn expectations(path: &Path) -> HashMap<String, Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| {
            let mut it = l.split_whitespace();
            let k = it.next().unwrap().to_string();
            (k, it.map(|v| v.parse().unwrap()).collect())
        })
        .collect()
}

/// usd-core's stage-unit, Y-up world point in meters, Z up.
fn z_up_meters(p: &[f64]) -> [f64; 3] {
    [p[0] * 0.01, -p[2] * 0.01, p[1] * 0.01]
}

#[test]
fn curves_under_a_transformed_parent_land_where_usd_core_puts_them() {
    let dir = tempfile::tempdir().unwrap();
    for ext in ["usda", "usdc"] {
        let file = dir.path().join(format!("groom.{ext}"));
        let exp_file = dir.path().join(format!("groom.{ext}.txt"));
        python("usd_groom_fixture.py", &[&file, &exp_file]);
        let exp = expectations(&exp_file);
        for time in [1, 6] {
            let read = read_usd(
                &file,
                &UsdReadOptions {
                    prim: Some("/Character/Body/hair".into()),
                    time: Some(f64::from(time)),
                    units: None,
                },
            )
            .unwrap();
            assert_eq!(read.prims, ["/Character/Body/hair"]);
            assert_eq!(read.meters_per_unit, 0.01);
            assert_eq!(read.up_axis, UpAxis::Y);
            let counts: Vec<usize> = read.groom.curves().iter().map(Vec::len).collect();
            assert_eq!(counts, [3, 4]);
            let want = &exp[&format!("points@{time}")];
            let got: Vec<_> = read.groom.curves().iter().flatten().collect();
            for (i, p) in got.iter().enumerate() {
                let w = z_up_meters(&want[3 * i..3 * i + 3]);
                for k in 0..3 {
                    // f32 world positions ~1.6 m: a few ulps.
                    assert!(
                        (f64::from(p[k]) - w[k]).abs() < 1e-6,
                        "{ext} t={time} point {i}: {p:?} vs {w:?}"
                    );
                }
            }
            let radii = read.radii.as_ref().expect("widths are read");
            for (r, w) in radii.iter().zip(&exp[&format!("widths@{time}")]) {
                // Radius = half the world width, in meters.
                assert!((f64::from(*r) - 0.5 * w * 0.01).abs() < 1e-7, "{r} vs {w}");
            }
            assert_eq!(
                read.root_uv.as_deref().unwrap(),
                [[0.25, 0.5], [0.75, 0.125]]
            );
        }
    }
}

#[test]
fn overridden_units_replace_the_stage_metadata() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("groom.usdc");
    python("usd_groom_fixture.py", &[&file, &dir.path().join("e.txt")]);
    let opts = |units| UsdReadOptions {
        prim: Some("/Character/Body/hair".into()),
        time: Some(1.0),
        units,
    };
    let stage = read_usd(&file, &opts(None)).unwrap();
    let raw = read_usd(
        &file,
        &opts(Some(ImportOptions {
            scale: 1.0,
            up_axis: UpAxis::Z,
        })),
    )
    .unwrap();
    // Same point: the override skips × 0.01 and the Y → Z turn.
    let (s, r) = (stage.groom.curves()[1][2], raw.groom.curves()[1][2]);
    assert!((s.x - r.x * 0.01).abs() < 1e-6 && (s.y + r.z * 0.01).abs() < 1e-6);
    assert!((s.z - r.y * 0.01).abs() < 1e-6);
}

#[test]
fn every_curve_prim_is_read_without_a_prim_and_a_parent_prim_selects_its_subtree() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("groom.usda");
    python("usd_groom_fixture.py", &[&file, &dir.path().join("e.txt")]);
    let all = read_usd(&file, &UsdReadOptions::default()).unwrap();
    assert_eq!(all.prims, ["/Character/Body/hair", "/Character/Props/rope"]);
    assert_eq!(all.groom.len(), 3);
    // Curves without widths among ones with: radius 0 for the rope's points.
    assert_eq!(all.radii.as_ref().unwrap().len(), 9);
    let body = read_usd(
        &file,
        &UsdReadOptions {
            prim: Some("/Character/Body".into()),
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(body.prims, ["/Character/Body/hair"]);
}

#[test]
fn a_missing_prim_is_refused_with_the_prims_the_stage_has() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("groom.usdc");
    python("usd_groom_fixture.py", &[&file, &dir.path().join("e.txt")]);
    let err = read_usd(
        &file,
        &UsdReadOptions {
            prim: Some("/Sintel/hair".into()),
            ..Default::default()
        },
    )
    .unwrap_err()
    .to_string();
    for want in [
        "groom.usdc",
        "/Sintel/hair",
        "/Character/Body/hair (BasisCurves)",
        "/Character/Body/skin (Mesh)",
    ] {
        assert!(err.contains(want), "{want} not in: {err}");
    }
    // A prim with no curves under it.
    let err = read_usd(
        &file,
        &UsdReadOptions {
            prim: Some("/Character/Body/skin".into()),
            ..Default::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("holds no BasisCurves"), "{err}");
}

#[test]
fn a_time_outside_the_stage_range_is_refused_naming_the_range() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("groom.usda");
    python("usd_groom_fixture.py", &[&file, &dir.path().join("e.txt")]);
    let err = read_usd(
        &file,
        &UsdReadOptions {
            time: Some(40.0),
            ..Default::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("time 40") && err.contains("1 to 11"), "{err}");
}

#[test]
fn a_blender_groom_with_an_object_transform_lands_where_blender_puts_it() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("blender.usdc");
    let exp_file = dir.path().join("blender.txt");
    python("blender_groom_fixture.py", &[&file, &exp_file]);
    let want: Vec<f64> = std::fs::read_to_string(&exp_file)
        .unwrap()
        .split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect();
    // Blender writes its hair object as /root/<object>/<data>; read that prim by path.
    let read = read_usd(
        &file,
        &UsdReadOptions {
            prim: Some("/root/hair".into()),
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(read.prims, ["/root/hair/groom"]);
    // Pinned Catmull-Rom curves read as their points.
    let counts: Vec<usize> = read.groom.curves().iter().map(Vec::len).collect();
    assert_eq!(counts, [4, 3]);
    for (i, p) in read.groom.curves().iter().flatten().enumerate() {
        for k in 0..3 {
            assert!(
                (f64::from(p[k]) - want[3 * i + k]).abs() < 1e-6,
                "point {i}: {p:?} vs {:?}",
                &want[3 * i..3 * i + 3]
            );
        }
    }
}
