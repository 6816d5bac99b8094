//! `[solver] integrator = "auto"` on the shipped scenes: BDF2 where the stability
//! bound's explicit substeps cost more (the default, wind, collision, gust and character scenes;
//! Sintel at the finer step of sharply bent grooms), and semi-implicit Euler for each measured
//! reason elsewhere: cheap explicit steps, a collider too fast for BDF2's substeps
//! (`hairsys/src/scene/integrator.rs` gives the measurements behind each rule,
//! `docs/design/auto-integrator.md` their history). The built scene's solver takes the chosen
//! integrator and its substeps.

use std::path::PathBuf;

use hair_core::Integrator;
use hairsys::scene::SceneFile;

fn build(name: &str) -> hairsys::build::Simulation {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(name);
    SceneFile::load(&path).unwrap().build().unwrap()
}

#[test]
fn every_stiff_mass_spring_scene_runs_bdf2_at_its_accuracy_limit() {
    // A moving ball (collision_demo), animated guides swept into the head (gust) and a
    // deforming scalp collider (character) included.
    for name in [
        "default.toml",
        "wind_demo.toml",
        "collision_demo.toml",
        "gust.toml",
        "character.toml",
    ] {
        let sim = build(name);
        let chosen = &sim.integrator;
        assert!(chosen.auto, "{name}");
        assert_eq!(chosen.integrator, Integrator::Bdf2, "{name}");
        assert_eq!(sim.settings.integrator, Integrator::Bdf2, "{name}");
        assert!(chosen.explicit_substeps > 21, "{name}: {chosen:?}");
        let solver = sim.strand_solver().unwrap();
        assert_eq!(solver.substeps(), chosen.implicit_substeps, "{name}");
        assert_eq!(chosen.implicit_substeps, 7, "{name}");
    }
    // The built-in default is the shipped default file.
    let builtin = SceneFile::builtin_default().build().unwrap();
    assert_eq!(builtin.settings.integrator, Integrator::Bdf2);
}

/// The parity scene's long soft hair is stable at a few semi-implicit substeps per frame,
/// cheaper than 7 BDF2 ones at three times the cost each: `"auto"` (which the scene does not
/// ask for: it names semi-implicit Euler) would keep semi-implicit Euler.
#[test]
fn cheap_explicit_steps_keep_semi_implicit_euler() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../scenes/parity.toml");
    let mut scene = SceneFile::load(&path).unwrap();
    scene.scene.solver.integrator = "auto".parse().unwrap();
    let sim = scene.build().unwrap();
    assert_eq!(
        sim.settings.integrator,
        Integrator::SemiImplicitEuler,
        "{}",
        sim.integrator.reason()
    );
    assert!(sim
        .integrator
        .reason()
        .contains("are stable and cost no more"));
}

/// The collision scene's ball crossing in one frame instead of ten (28.8 m/s, 2.9 of its 0.06 m
/// radius in one of BDF2's 1/168 s substeps, beyond `MAX_BDF2_CROSSING`): `"auto"` keeps
/// semi-implicit Euler and says why.
#[test]
fn a_collider_crossing_much_of_its_size_in_a_substep_keeps_semi_implicit_euler() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../scenes/collision_demo.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let key = "{ frame = 30, translation = [0.6, 0.13, -0.15] }";
    assert!(text.contains(key));
    let fast = text.replace(key, "{ frame = 21, translation = [0.6, 0.13, -0.15] }");
    let scene = SceneFile::parse(&fast, "fast_ball.toml", path.parent().unwrap().into()).unwrap();
    let sim = scene.build().unwrap();
    assert_eq!(
        sim.settings.integrator,
        Integrator::SemiImplicitEuler,
        "{}",
        sim.integrator.reason()
    );
    assert!(
        sim.integrator
            .reason()
            .contains("of its size in one BDF2 substep"),
        "{}",
        sim.integrator.reason()
    );
}

/// Sintel's groom has rest joints turning 71–83° (sharper than `MAX_IMPLICIT_REST_TURN`) and
/// no keyed guide poses: `"auto"` gives BDF2 the finer step, 32 substeps per frame, which the
/// solver takes, and says why. (Her guides carry an animation object without keys, which must
/// not count as animated guides.)
#[test]
fn sintels_sharp_joints_run_bdf2_at_the_finer_step() {
    let sim = build("sintel.toml");
    let chosen = &sim.integrator;
    assert!(chosen.max_rest_turn.to_degrees() > 45.0, "{chosen:?}");
    assert_eq!(
        sim.settings.integrator,
        Integrator::Bdf2,
        "{}",
        chosen.reason()
    );
    assert_eq!(chosen.implicit_substeps, 32);
    assert_eq!(sim.strand_solver().unwrap().substeps(), 32);
    assert!(
        chosen.reason().contains("finer BDF2 step"),
        "{}",
        chosen.reason()
    );
}
