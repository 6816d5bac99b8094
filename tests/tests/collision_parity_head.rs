//! The parity scene with its head as collider (`scenes/parity_collide.toml`: 20,000 strands of
//! 1.5 m, 340,000 points, on a UV-sphere head of radius 1 m that moves 1 m and turns 30°, one
//! collision step per frame): no hair point is inside the head at any frame.
//!
//! Reference: an independent parry check — the head mesh as an oriented parry `TriMesh` posed
//! at each frame, every free point's signed distance by point projection. The solver keeps point
//! centres one hair radius (5 mm) off the surface; the test prints the smallest gap and requires
//! it to be ≥ 0. Also run on `scenes/parity_sphere_collider.toml` (the head as an analytic
//! sphere), checked against the same mesh: the sphere encloses the mesh, so its hair must be
//! outside the mesh too. Whipping tips slide 20–35 cm over the head within one step; before the
//! contact sphere took the smooth (vertex-interpolated) normal instead of the facet's, that let
//! them end frames up to 2.8 mm inside the mesh at one step per frame (measured 3.0 mm clear
//! since). The mesh case is `#[ignore]`d for time (about 20 s): `cargo test -p hairsys-tests
//! --test collision_parity_head -- --ignored`.
//!
//! The sphere scene runs a second time on BDF2 at one substep per frame (a backward Euler third
//! of the frame, then one BDF2 solve), whose extrapolated start carries whipping tips on into the
//! head by up to 9 cm after detection. While the push-out of that depth was held to
//! `max_push_speed` (1 m/s), tips ended frames up to 6.4 cm inside the mesh; the response now
//! removes within the substep all depth gained after detection (`hair_core::contacts`).

use std::path::PathBuf;

mod common;

use common::collide::{run_with_colliders, Gap, ParryHead};
use hairsys::scene::{SceneFile, SubstepsValue};

/// The shipped scene `name`.
fn shipped(name: &str) -> SceneFile {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(name);
    SceneFile::load(&path).unwrap()
}

/// Runs `scene` and returns the smallest signed distance (m) of a free point to the head mesh
/// over all frames, and the largest number of collision steps of a frame.
fn worst_gap(scene: &SceneFile) -> (f32, u32) {
    let mut sim = scene.build().unwrap();
    let head = ParryHead::new(&hair_groom::uv_sphere(1.0, 64, 32).unwrap());
    let (mut gap, mut steps) = (Gap::NONE, 0);
    let last = sim.last_frame;
    run_with_colliders(&mut sim, last, |_, sim, scalp, report| {
        steps = steps.max(report.steps);
        gap = gap.merge(head.free_point_gap(&scalp.body, &sim.strands));
    });
    (gap.smallest, steps)
}

fn check(name: &str, scene: &SceneFile) {
    let (worst, steps) = worst_gap(scene);
    println!(
        "{name}: smallest gap between a point centre and the head mesh over 23 frames: {:.3} mm \
         (hair radius 5 mm); up to {steps} collision step(s) per frame",
        worst * 1e3
    );
    assert!(
        worst >= 0.0,
        "{name}: a point is {} m inside the head",
        -worst
    );
}

#[test]
fn parity_scene_with_a_sphere_head_keeps_every_point_outside_it() {
    check(
        "parity_sphere_collider.toml",
        &shipped("parity_sphere_collider.toml"),
    );
}

#[test]
fn parity_scene_on_bdf2_at_one_substep_per_frame_keeps_every_point_outside_the_head() {
    let mut scene = shipped("parity_sphere_collider.toml");
    scene.scene.solver.integrator = "bdf2".parse().unwrap();
    scene.scene.solver.substeps = SubstepsValue::Count(1);
    check("parity_sphere_collider.toml on BDF2 at 1 substep", &scene);
}

/// About 20 s in the (optimised) test profile on a loaded machine: run it with `--ignored`.
#[test]
#[ignore]
fn parity_scene_with_its_head_mesh_keeps_every_point_outside_it() {
    check("parity_collide.toml", &shipped("parity_collide.toml"));
}
