//! `hairsys scene check` lists the painted maps (name, source, purpose, values at the roots) and
//! the regions (selection, strands, parameters), and what it lists is what a run of the scene
//! uses: the goal map's range is the range of the run's root goal weights, and each region holds
//! exactly the strands its cone or map selects among the run's roots.

mod common;

use common::{hairsys, tempdir};
use hair_core::{Anchor, TriMesh};
use hairsys::scene::SceneFile;
use hairsys::Session;
use nalgebra::Vector3;

/// Red: a goal factor linear in position (0.5 ± 0.35 on the sphere); green: 1 on the +y half.
fn colour(p: &Vector3<f32>) -> [f32; 3] {
    [
        0.5 + 2.0 * p.x - 1.5 * p.z,
        if p.y > 0.0 { 1.0 } else { 0.0 },
        0.0,
    ]
}

const SCENE: &str = r#"
[scene]
frames = [1, 3]

[scalp.mesh]
kind = "obj"
path = "scalp.obj"

[hair]
count = 200
length = 0.08
segments = 4
seed = 4
goal_root = 1.0
goal_tip = 1.0

[maps.goal]
vertex_colors = true

[maps.back]
vertex_colors = true
channel = "g"

[[regions]]
name = "top"
region = { direction = [0.0, 0.0, 1.0], max_angle_deg = 50.0 }
bend_stiffness = 4.0

[[regions]]
name = "back"
map = { name = "back", min = 0.5 }
mass_scale = 0.5
"#;

#[test]
fn scene_check_lists_the_maps_and_regions_a_run_uses() {
    let dir = tempdir("check-maps");
    let mesh = TriMesh::uv_sphere(0.1, 24, 12).unwrap();
    let mut obj = String::new();
    for p in mesh.positions() {
        let c = colour(p);
        obj += &format!("v {} {} {} {} {} {}\n", p.x, p.y, p.z, c[0], c[1], c[2]);
    }
    for t in mesh.triangles() {
        obj += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    std::fs::write(dir.join("scalp.obj"), obj).unwrap();
    std::fs::write(dir.join("s.toml"), SCENE).unwrap();

    let o = hairsys(&["scene", "check", "s.toml", "--json"], &dir);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let check: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();

    // The run: a session of the same scene.
    let session = Session::from_scene(&SceneFile::load(&dir.join("s.toml")).unwrap()).unwrap();
    let strands = session.strands();
    let scalp = session.scalp();
    let mesh = scalp.mesh.as_ref().unwrap();
    assert_eq!(check["strands"], strands.len());

    // Maps, by name.
    let maps = check["maps"].as_array().unwrap();
    let names: Vec<&str> = maps.iter().map(|m| m["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["back", "goal"]);
    let goal = &maps[1];
    assert_eq!(goal["roots"], strands.len());
    assert!(goal["source"]
        .as_str()
        .unwrap()
        .contains("vertex colours (channel r)"));
    assert_eq!(goal["purpose"], "scales goal weights");
    assert!(maps[0]["purpose"]
        .as_str()
        .unwrap()
        .contains("selects hair"));
    // The goal map's range is the range of the run's root goal weights (goal_root = 1).
    let root_goals: Vec<f32> = (0..strands.len())
        .map(|s| strands.goal_weights()[strands.points(s).start])
        .collect();
    let lo = root_goals.iter().copied().fold(f32::INFINITY, f32::min);
    let hi = root_goals.iter().copied().fold(f32::NEG_INFINITY, f32::max);
    let range = goal["range"].as_array().unwrap();
    assert!(
        (range[0].as_f64().unwrap() - f64::from(lo)).abs() < 1e-6,
        "{range:?} vs {lo}"
    );
    assert!(
        (range[1].as_f64().unwrap() - f64::from(hi)).abs() < 1e-6,
        "{range:?} vs {hi}"
    );
    assert!(hi - lo > 0.3, "the map varies over the roots: {lo}–{hi}");

    // Regions: the strands each selects among the run's roots.
    let (mut top, mut back) = (0, 0);
    for anchor in strands.anchors() {
        let Anchor::Surface(sample) = anchor else {
            panic!("[hair] grows on the scalp")
        };
        let frame = mesh.evaluate(sample);
        let normal = frame.rotation * Vector3::z();
        top += usize::from(normal.z >= 50f32.to_radians().cos());
        // Vertex colours blend with the root's barycentric weights.
        let tri = mesh.triangles()[sample.triangle as usize];
        let g: f32 = tri
            .iter()
            .zip(sample.weights)
            .map(|(&v, w)| colour(&mesh.positions()[v as usize])[1] * w)
            .sum();
        back += usize::from(g >= 0.5);
    }
    let regions = check["regions"].as_array().unwrap();
    assert_eq!(regions.len(), 2);
    assert_eq!(regions[0]["name"], "top");
    assert_eq!(regions[0]["strands"], top);
    assert_eq!(
        regions[0]["params"],
        serde_json::json!({ "bend_stiffness": 4.0 })
    );
    assert_eq!(
        regions[0]["selection"]["region"]["max_angle_deg"],
        serde_json::json!(50.0)
    );
    assert_eq!(regions[1]["name"], "back");
    assert_eq!(regions[1]["strands"], back);
    assert_eq!(
        regions[1]["params"],
        serde_json::json!({ "mass_scale": 0.5 })
    );
    assert_eq!(regions[1]["selection"]["map"]["name"], "back");
    assert!(top > 10 && back > 10 && top < strands.len() && back < strands.len());

    // The text names the same things.
    let o = hairsys(&["scene", "check", "s.toml"], &dir);
    let text = String::from_utf8_lossy(&o.stdout);
    for needle in [
        "map goal: the scalp's vertex colours (channel r); scales goal weights; values "
            .to_string(),
        format!("at {} roots", strands.len()),
        format!("region top: {top} strands selected by {{\"region\""),
        "sets {\"bend_stiffness\":4.0}".to_string(),
        format!("region back: {back} strands"),
    ] {
        assert!(text.contains(&needle), "`{needle}` not in:\n{text}");
    }
}
