//! Hair cards: the ribbon's layout (rows, columns, UVs, root tangent along the follicle) and its
//! exports — `.usda` opened and validated by Pixar's USD (`usd-core`, module `pxr`; fails, never
//! skips, when it is missing) and OBJ read back by `tobj`.

use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

use hair_core::model::strips::{StripGrowth, StripSet};
use hair_core::{Scalp, TriMesh};
use hair_render::export::cards_obj::{export_cards_obj, ObjUpAxis};
use hair_render::export::cards_usd::{export_cards_usda, CardSample, CardUsdOptions};
use hair_render::{build_cards, CardMesh, CardSettings};
use nalgebra::Vector3;

/// Two strips on a flat 2-triangle scalp (z = 0, normal +z), edges bent sideways by `bend`.
fn strips(bend: f32) -> (StripSet, Scalp) {
    let mesh = TriMesh::new(
        vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(0.1, 0.0, 0.0),
            Vector3::new(0.1, 0.1, 0.0),
            Vector3::new(0.0, 0.1, 0.0),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    )
    .unwrap();
    let growth = StripGrowth {
        length: 0.1,
        segments: 4,
        hairs_per_strip: 40,
        ..StripGrowth::default()
    };
    let mut set = StripSet::from_triangles(&mesh, &[0, 1], &growth).unwrap();
    for s in 0..set.strands.len() {
        let range = set.strands.points(s);
        let root = set.strands.positions[range.start];
        for (j, i) in range.enumerate() {
            let h = 0.025 * j as f32;
            set.strands.positions[i] = root + Vector3::new(bend * h * h * 10.0, 0.0, h);
        }
    }
    let scalp = Scalp {
        mesh: Some(mesh),
        body: nalgebra::Isometry3::identity(),
    };
    (set, scalp)
}

fn flat(points: &[Vector3<f32>]) -> Vec<f32> {
    points.iter().flat_map(|p| [p.x, p.y, p.z]).collect()
}

fn list(values: impl IntoIterator<Item = impl std::fmt::Debug>) -> String {
    let items: Vec<String> = values.into_iter().map(|v| format!("{v:?}")).collect();
    format!("[{}]", items.join(","))
}

#[test]
fn ribbon_has_rows_columns_uvs_and_leaves_the_root_along_the_follicle() {
    let (set, scalp) = strips(1.0);
    let settings = CardSettings {
        rows_per_segment: 5,
        columns: 4,
        clearance: 0.0,
    };
    let cards = build_cards(&set, &scalp, &settings, None).unwrap();
    assert_eq!(cards.cards, 2);
    assert_eq!(cards.rows, 4 * 5 + 1);
    assert_eq!(cards.positions.len(), 2 * 21 * 4);
    assert_eq!(cards.quads.len(), 2 * 20 * 3);
    // Edges pass through the edge strands' points (every 5th row), u = 0 left, 1 right.
    for k in 0..2 {
        let (l, r) = set.edges(k);
        for (j, (a, b)) in l.iter().zip(r).enumerate() {
            let v = k * 84 + j * 5 * 4;
            assert!((cards.positions[v] - a).norm() < 1e-6);
            assert!((cards.positions[v + 3] - b).norm() < 1e-6);
            assert_eq!(cards.uvs[v], [0.0, j as f32 / 4.0]);
            assert_eq!(cards.uvs[v + 3], [1.0, j as f32 / 4.0]);
        }
    }
    // The first sample row above the root moves along the follicle (+z) to first order: the
    // root tangent is the growth direction, not the bent chord.
    let d = (cards.positions[4] - cards.positions[0]).normalize();
    let chord = (set.edges(0).0[1] - set.edges(0).0[0]).normalize();
    assert!(
        d.z > chord.z,
        "first row {d:?} leans as far as the chord {chord:?}"
    );
    for uv in &cards.uvs {
        assert!((0.0..=1.0).contains(&uv[0]) && (0.0..=1.0).contains(&uv[1]));
    }
}

#[test]
fn bad_card_settings_are_refused() {
    let (set, scalp) = strips(0.0);
    for (bad, field) in [
        (
            CardSettings {
                columns: 1,
                ..CardSettings::default()
            },
            "cards.columns",
        ),
        (
            CardSettings {
                rows_per_segment: 0,
                ..CardSettings::default()
            },
            "cards.rows_per_segment",
        ),
        (
            CardSettings {
                clearance: f32::NAN,
                ..CardSettings::default()
            },
            "cards.clearance",
        ),
    ] {
        let text = build_cards(&set, &scalp, &bad, None)
            .unwrap_err()
            .to_string();
        assert!(text.contains(field), "{text}");
    }
}

fn run_checker(usda: &Path, expected: &str) {
    let json = usda.with_extension("json");
    std::fs::write(&json, expected).unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/python/check_cards_usda.py");
    let out = Command::new("python3")
        .arg(&script)
        .arg(usda)
        .arg(&json)
        .output()
        .unwrap_or_else(|e| {
            panic!("cannot run python3 ({e}): install Python 3 and `pip install usd-core`")
        });
    let stderr = String::from_utf8_lossy(&out.stderr);
    match out.status.code() {
        Some(0) => println!("{}", String::from_utf8_lossy(&out.stdout).trim()),
        Some(3) => {
            panic!("Pixar's USD Python module `pxr` is missing: pip install usd-core ({stderr})")
        }
        _ => panic!("usd-core rejected {}: {stderr}", usda.display()),
    }
}

fn expected(cards: &CardMesh, samples: &[(f64, &CardMesh)]) -> String {
    let mut s = format!(
        "{{\"prim\":\"/cards\",\"fps\":24.0,\"counts\":{},\"indices\":{},\"points\":{},\"st\":{}",
        list(cards.quads.iter().map(|_| 4)),
        list(cards.quads.iter().flatten()),
        list(flat(&cards.positions)),
        list(cards.uvs.iter().flatten()),
    );
    let ts: Vec<String> = samples
        .iter()
        .map(|(t, m)| format!("\"{t:?}\":{}", list(flat(&m.positions))))
        .collect();
    let _ = write!(s, ",\"time_samples\":{{{}}}}}", ts.join(","));
    s
}

#[test]
fn exported_cards_pass_pixar_usd_checks_with_motion_samples() {
    let dir = tempfile::tempdir().unwrap();
    let settings = CardSettings::default();
    let (a, scalp) = strips(0.0);
    let (b, _) = strips(0.5);
    let (c, _) = strips(1.0);
    let at = |s: &StripSet| build_cards(s, &scalp, &settings, None).unwrap();
    let (ma, mb, mc) = (at(&a), at(&b), at(&c));
    let opts = CardUsdOptions {
        time_code: 12.0,
        ..CardUsdOptions::default()
    };

    let still = dir.path().join("still.usda");
    export_cards_usda(&still, &mb, &[], &opts).unwrap();
    run_checker(&still, &expected(&mb, &[]));

    let blurred = dir.path().join("blur.usda");
    let samples = [
        CardSample {
            time_code: 11.75,
            mesh: &ma,
        },
        CardSample {
            time_code: 12.0,
            mesh: &mb,
        },
        CardSample {
            time_code: 12.25,
            mesh: &mc,
        },
    ];
    export_cards_usda(&blurred, &mb, &samples, &opts).unwrap();
    run_checker(
        &blurred,
        &expected(&mb, &[(11.75, &ma), (12.0, &mb), (12.25, &mc)]),
    );

    // A motion sample of another topology is refused and nothing is left behind.
    let coarse = build_cards(
        &a,
        &scalp,
        &CardSettings {
            columns: 2,
            ..settings
        },
        None,
    )
    .unwrap();
    let bad = dir.path().join("bad.usda");
    let err = export_cards_usda(
        &bad,
        &mb,
        &[CardSample {
            time_code: 11.0,
            mesh: &coarse,
        }],
        &opts,
    )
    .unwrap_err();
    assert!(err.to_string().contains("same card settings"), "{err}");
    assert!(!bad.exists());
}

#[test]
fn cards_obj_round_trips_through_tobj_in_either_up_axis() {
    let dir = tempfile::tempdir().unwrap();
    let (set, scalp) = strips(1.0);
    let cards = build_cards(&set, &scalp, &CardSettings::default(), None).unwrap();
    for up in [ObjUpAxis::Y, ObjUpAxis::Z] {
        let path = dir.path().join(format!("cards-{}.obj", up.name()));
        export_cards_obj(&path, &cards, up).unwrap();
        let load = tobj::LoadOptions {
            single_index: true,
            triangulate: false,
            ignore_points: true,
            ignore_lines: true,
        };
        let (models, _) = tobj::load_obj(&path, &load).unwrap();
        assert_eq!(models.len(), 1);
        let m = &models[0].mesh;
        // tobj renumbers vertices by first use: compare every face corner's position and UV.
        assert_eq!(m.positions.len(), 3 * cards.positions.len());
        assert_eq!(m.texcoords.len(), 2 * cards.uvs.len());
        assert!(m.face_arities.iter().all(|&n| n == 4));
        assert_eq!(m.face_arities.len(), cards.quads.len());
        for (corner, &ours) in cards.quads.iter().flatten().enumerate() {
            let (read, ours) = (m.indices[corner] as usize, ours as usize);
            let p = &cards.positions[ours];
            let [x, y, z] = &m.positions[3 * read..3 * read + 3] else {
                unreachable!("three coordinates per vertex")
            };
            // Y up turns Z-up (x, y, z) into (x, z, -y); an importer's Y-up → Z-up turn
            // (x, y, z) → (x, -z, y) gives the simulated point back exactly.
            let back = match up {
                ObjUpAxis::Y => [*x, -*z, *y],
                ObjUpAxis::Z => [*x, *y, *z],
            };
            assert_eq!(back, [p.x, p.y, p.z], "{up:?}");
            assert_eq!(&m.texcoords[2 * read..2 * read + 2], &cards.uvs[ours]);
        }
    }
}
