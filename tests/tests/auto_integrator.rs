//! `[solver] integrator = "auto"` on the shipped scenes: BDF2 where the stability
//! bound's explicit substeps cost more and contact is gentle (the default and wind scenes; Sintel
//! at the finer step of sharply bent grooms), and semi-implicit Euler for each measured reason
//! elsewhere (`hairsys/src/scene/integrator.rs` gives the measurements behind each rule,
//! `docs/design/auto-integrator.md` their history). The built scene's solver
//! takes the chosen integrator and its substeps.

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
fn the_default_and_wind_scenes_run_bdf2_at_its_accuracy_limit() {
    for name in ["default.toml", "wind_demo.toml"] {
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

#[test]
fn hard_contact_and_cheap_explicit_steps_keep_semi_implicit_euler() {
    for (name, why) in [
        ("collision_demo.toml", "a collider moves"),
        ("gust.toml", ""),
        ("character.toml", "a collider deforms"),
        ("parity.toml", ""),
    ] {
        let sim = build(name);
        assert_eq!(
            sim.settings.integrator,
            Integrator::SemiImplicitEuler,
            "{name}: {}",
            sim.integrator.reason()
        );
        assert!(sim.integrator.reason().contains(why), "{name}");
    }
    // The gust names semi-implicit Euler itself; "auto" would keep it for its animated guides.
    let mut gust =
        SceneFile::load(&PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../scenes/gust.toml"))
            .unwrap();
    gust.scene.solver.integrator = "auto".parse().unwrap();
    let sim = gust.build().unwrap();
    assert_eq!(sim.settings.integrator, Integrator::SemiImplicitEuler);
    assert!(sim.integrator.reason().contains("animated guides"));
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
