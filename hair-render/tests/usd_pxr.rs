//! Every exported `.usda` and `.usdc` (one layer writer) is opened by Pixar's USD (`usd-core`, module `pxr`) and checked:
//! curve counts, points, time samples, widths and their interpolation, st, extent, metadata.
//! Fails (never skips) when python3 or pxr is missing: CI installs `pip install usd-core`.

mod common;

use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

use common::{bent, flatten};
use hair_core::{MeshSample, TriMesh};
use hair_render::export::usd::{export_usd, velocities, Motion, MotionSample, UsdOptions};
use hair_render::{
    generate, ChildBuffers, ChildCount, ChildMode, ChildSettings, Clump, Curl, Lod, Parents,
    ScalpRoots, Shape,
};
use nalgebra::{Vector2, Vector3};

fn list(values: &[f32]) -> String {
    let items: Vec<String> = values.iter().map(|v| format!("{v:?}")).collect();
    format!("[{}]", items.join(","))
}

/// The expectations file the Python checker compares the stage with.
fn expected(c: &ChildBuffers, samples: &[(f64, &ChildBuffers)], vel: Option<&[f32]>) -> String {
    let counts: Vec<String> = c.vertex_counts.iter().map(u32::to_string).collect();
    let mut s = format!(
        "{{\"prim\":\"/children\",\"fps\":24.0,\"counts\":[{}],\"points\":{},\"widths\":{},\"st\":{}",
        counts.join(","),
        list(&c.points),
        list(&c.widths),
        c.root_uv.as_deref().map_or("null".into(), list)
    );
    let ts: Vec<String> = samples
        .iter()
        .map(|(t, b)| format!("\"{t:?}\":{}", list(&b.points)))
        .collect();
    let _ = write!(s, ",\"time_samples\":{{{}}}", ts.join(","));
    let _ = write!(s, ",\"velocities\":{}}}", vel.map_or("null".into(), list));
    s
}

fn run_checker(usda: &Path, expected: &str) {
    let json = usda.with_extension("json");
    std::fs::write(&json, expected).unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/python/check_usda.py");
    let out = Command::new("python3")
        .arg(&script)
        .arg(usda)
        .arg(&json)
        .output();
    let out = match out {
        Ok(o) => o,
        Err(e) => panic!(
            "cannot run python3 ({e}): install Python 3 and Pixar's USD with `pip install usd-core`"
        ),
    };
    let stderr = String::from_utf8_lossy(&out.stderr);
    match out.status.code() {
        Some(0) => println!("{}", String::from_utf8_lossy(&out.stdout).trim()),
        Some(3) => {
            panic!("Pixar's USD Python module `pxr` is missing: pip install usd-core ({stderr})")
        }
        _ => panic!("usd-core rejected {}: {stderr}", usda.display()),
    }
}

/// Parents on a scalp with UVs, moved by `dx` (a frame of simple motion).
fn children_at(dx: f32, settings: &ChildSettings, uvs: bool) -> ChildBuffers {
    let mut mesh = TriMesh::new(
        vec![
            Vector3::new(-1.0 + dx, -1.0, 0.0),
            Vector3::new(1.0 + dx, -1.0, 0.0),
            Vector3::new(dx, 1.0, 0.0),
        ],
        vec![[0, 1, 2]],
    )
    .unwrap();
    if uvs {
        mesh = mesh
            .with_uvs(vec![
                Vector2::new(0.0, 0.0),
                Vector2::new(1.0, 0.0),
                Vector2::new(0.5, 1.0),
            ])
            .unwrap();
    }
    let samples = [
        Some(MeshSample {
            triangle: 0,
            weights: [0.4, 0.3, 0.3],
        }),
        Some(MeshSample {
            triangle: 0,
            weights: [0.2, 0.5, 0.3],
        }),
    ];
    let roots: Vec<_> = samples
        .iter()
        .map(|s| mesh.evaluate(&s.unwrap()).origin)
        .collect();
    let (positions, offsets) = flatten(&[bent(roots[0], 8, 0.08), bent(roots[1], 6, 0.05)]);
    let parents = Parents::new(&positions, &offsets)
        .unwrap()
        .with_scalp(ScalpRoots {
            mesh: &mesh,
            samples: &samples,
            colors: None,
        })
        .unwrap();
    generate(&parents, settings, Lod::Render).unwrap()
}

fn settings() -> ChildSettings {
    ChildSettings {
        count: ChildCount::PerParent(15),
        shape: Shape {
            clump: Clump {
                factor: 0.5,
                shape: 1.0,
            },
            curl: Curl {
                radius: 0.002,
                frequency: 30.0,
            },
            ..Default::default()
        },
        ..Default::default()
    }
}

#[test]
fn usda_with_time_samples_opens_in_pixar_usd() {
    let s = settings();
    let (before, frame, after) = (
        children_at(-0.01, &s, true),
        children_at(0.0, &s, true),
        children_at(0.01, &s, true),
    );
    let samples = [
        MotionSample {
            time_code: 11.75,
            children: &before,
        },
        MotionSample {
            time_code: 12.0,
            children: &frame,
        },
        MotionSample {
            time_code: 12.25,
            children: &after,
        },
    ];
    let dir = tempfile::tempdir().unwrap();
    // Text, and binary through the openusd layer writer.
    for ext in ["usda", "usdc"] {
        let path = dir.path().join(format!("children.{ext}"));
        let opts = UsdOptions {
            time_code: 12.0,
            ..Default::default()
        };
        export_usd(&path, frame.clone(), &Motion::TimeSamples(&samples), &opts).unwrap();
        assert!(!dir.path().join(format!("children.{ext}.partial")).exists());
        let exp = expected(
            &frame,
            &[(11.75, &before), (12.0, &frame), (12.25, &after)],
            None,
        );
        run_checker(&path, &exp);
    }
}

#[test]
fn usda_with_velocities_and_without_uvs_opens_in_pixar_usd() {
    let s = settings();
    let (before, frame, after) = (
        children_at(-0.01, &s, false),
        children_at(0.0, &s, false),
        children_at(0.01, &s, false),
    );
    let v = velocities(&before, &after, 0.5 / 24.0).unwrap();
    assert!(
        (v[0] - 0.96).abs() < 1e-3,
        "roots move 2 cm in 1/48 s: {}",
        v[0]
    );
    let dir = tempfile::tempdir().unwrap();
    for ext in ["usda", "usdc"] {
        let path = dir.path().join(format!("children.{ext}"));
        export_usd(
            &path,
            frame.clone(),
            &Motion::Velocities(&v),
            &UsdOptions {
                time_code: 12.0,
                ..Default::default()
            },
        )
        .unwrap();
        run_checker(&path, &expected(&frame, &[], Some(&v)));
    }
}

#[test]
fn usda_with_interpolated_children_opens_in_pixar_usd() {
    let s = ChildSettings {
        mode: ChildMode::Interpolated { neighbours: 2 },
        spread: 0.3,
        ..settings()
    };
    let frame = children_at(0.0, &s, true);
    // Interpolated roots are spread over the scalp: each child has its own UV.
    let st = frame.root_uv.as_ref().unwrap();
    assert_ne!(st[..2], st[2..4]);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("interpolated.usda");
    let opts = UsdOptions {
        time_code: 12.0,
        ..Default::default()
    };
    export_usd(&path, frame.clone(), &Motion::None, &opts).unwrap();
    run_checker(&path, &expected(&frame, &[], None));
}

#[test]
fn a_failed_export_leaves_nothing_behind() {
    let s = settings();
    let frame = children_at(0.0, &s, true);
    let other = ChildBuffers {
        vertex_counts: vec![2],
        points: vec![0.0; 6],
        widths: vec![0.0; 2],
        ..Default::default()
    };
    let samples = [MotionSample {
        time_code: 1.0,
        children: &other,
    }];
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.usda");
    let err = export_usd(
        &path,
        frame.clone(),
        &Motion::TimeSamples(&samples),
        &UsdOptions::default(),
    )
    .unwrap_err();
    assert!(err.to_string().contains("motion samples differ"), "{err}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    let err = export_usd(
        &dir.path().join("missing/c.usda"),
        frame.clone(),
        &Motion::None,
        &UsdOptions::default(),
    )
    .unwrap_err();
    assert!(err.to_string().contains("missing/c.usda"), "{err}");
}
