//! `.hair` export read back by hair-groom's reader (Cem Yuksel's format).

mod common;

use common::{bent, flatten};
use hair_render::export::hair::export_hair;
use hair_render::{generate, ChildCount, ChildSettings, Lod, Parents};
use nalgebra::Vector3;

#[test]
fn hair_export_reads_back_bit_exact() {
    let (positions, offsets) =
        flatten(&[bent(Vector3::zeros(), 7, 0.1), bent(Vector3::x(), 4, 0.2)]);
    let parents = Parents::new(&positions, &offsets).unwrap();
    let settings = ChildSettings {
        count: ChildCount::PerParent(9),
        ..Default::default()
    };
    let c = generate(&parents, &settings, Lod::Render).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("children.hair");
    export_hair(&path, &c).unwrap();
    let groom = hair_groom::read_hair(&path, &Default::default()).unwrap();
    assert_eq!(groom.len(), c.curve_count());
    let back: Vec<f32> = groom
        .curves()
        .iter()
        .flatten()
        .flat_map(|p| [p.x, p.y, p.z])
        .collect();
    assert_eq!(back, c.points);
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(
        bytes.len(),
        128 + 2 * c.curve_count() + 16 * c.point_count(),
        "segments, points, thickness"
    );
}
