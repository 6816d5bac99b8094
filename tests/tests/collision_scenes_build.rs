//! The scene files with colliders (`scenes/collision_demo.toml`, `scenes/head_collide.toml`,
//! `scenes/parity_collide.toml`, `scenes/parity_sphere_collider.toml`) load and build, with the
//! colliders they declare, and the default scene's commented collision keys stay valid when
//! uncommented.

use std::path::PathBuf;

use hair_core::MeshKind;
use hairsys::scene::{SceneFile, DEFAULT_SCENE};

fn scene(name: &str) -> SceneFile {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(name);
    SceneFile::load(&path).unwrap()
}

#[test]
fn collision_scenes_build_with_their_colliders() {
    for (name, expected) in [
        ("collision_demo.toml", 3),
        ("head_collide.toml", 1),
        ("parity_collide.toml", 1),
    ] {
        let sim = scene(name).build().unwrap();
        let colliders = sim.colliders_at(sim.first_frame as f32).unwrap();
        println!("{name}: {} colliders", colliders.len());
        assert_eq!(colliders.len(), expected, "{name}");
        // The scalp collider is inserted last; the built-in head and the UV sphere are solids.
        let scalp = hair_core::ColliderId(expected as u32 - 1);
        assert!(
            matches!(colliders.mesh_kind(scalp), Some(MeshKind::Solid { .. })),
            "{name}: {:?}",
            colliders.mesh_kind(scalp)
        );
    }
}

#[test]
fn parity_with_an_analytic_sphere_head_builds() {
    let sim = scene("parity_sphere_collider.toml").build().unwrap();
    let colliders = sim.colliders_at(sim.first_frame as f32).unwrap();
    assert_eq!(colliders.len(), 1);
    assert!(colliders.mesh_kind(hair_core::ColliderId(0)).is_none());
    assert!(sim.scalp_collider.is_none());
}

#[test]
fn default_scene_collider_keys_parse_when_uncommented() {
    // The default scene collides with its head; more colliders are shown commented.
    let start = DEFAULT_SCENE
        .find("# [[colliders]]")
        .expect("the default scene documents [[colliders]]");
    // The collision block runs to the next blank line (other commented sections follow it).
    let uncommented: String = DEFAULT_SCENE[start..]
        .lines()
        .take_while(|l| !l.trim().is_empty())
        .map(|l| l.trim_start_matches("# "))
        .map(|l| format!("{l}\n"))
        .collect();
    let text = format!("{}{uncommented}", &DEFAULT_SCENE[..start]);
    let sim = SceneFile::parse(&text, "default+collision.toml", ".".into())
        .unwrap()
        .build()
        .unwrap();
    assert!(sim.has_colliders());
    assert_eq!(sim.colliders.len(), 1);
    assert!(sim.scalp_collider.is_some());
    assert!(SceneFile::parse(DEFAULT_SCENE, "default.toml", ".".into())
        .unwrap()
        .build()
        .unwrap()
        .scalp_collider
        .is_some());
}
