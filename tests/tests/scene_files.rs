//! Validation cases given as plain scene files (`scenes/validation/*.toml`), loaded and built by the
//! same code as `hairsys simulate`: the pendulum's period against 2π√(L/g), and the settled chain
//! against the catenary of its span and length.

mod common;

use std::path::PathBuf;

use common::*;
use hairsys::build::Simulation;
use hairsys::scene::SceneFile;

fn load(name: &str) -> Simulation {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes/validation")
        .join(name);
    SceneFile::load(&path).unwrap().build().unwrap()
}

#[test]
fn pendulum_scene_swings_with_two_pi_sqrt_l_over_g() {
    let mut sim = load("pendulum.toml");
    let mut solver = solver_at_first_frame(&sim);
    let scalp = sim.scalp_at(0.0);
    let fps = sim.settings.fps as f64;
    let mut samples = vec![(0.0, sim.strands.positions[1].x as f64)];
    for frame in sim.first_frame + 1..=sim.last_frame {
        solver.step_frame(&mut sim.strands, &scalp).unwrap();
        samples.push((frame as f64 / fps, sim.strands.positions[1].x as f64));
    }
    let length = 0.5f64;
    let t_ref = 2.0 * std::f64::consts::PI * (length / G).sqrt();
    let period = period_from_crossings(&zero_crossings(&samples));
    let err = (period - t_ref).abs() / t_ref;
    println!("pendulum.toml: T = {period:.5} s, 2π√(L/g) = {t_ref:.5} s, error {err:.2e}");
    assert!(err < 0.01, "period off by {:.2} %", 100.0 * err);
}

#[test]
fn catenary_scene_settles_to_the_catenary() {
    let mut sim = load("catenary.toml");
    let mut solver = solver_at_first_frame(&sim);
    let scalp = sim.scalp_at(0.0);
    for _ in sim.first_frame..sim.last_frame {
        solver.step_frame(&mut sim.strands, &scalp).unwrap();
    }
    let (span, length) = (1.6f64, 2.0f64);
    let a = catenary_parameter(span, length);
    let worst = sim
        .strands
        .positions
        .iter()
        .map(|p| (p.z as f64 - catenary_height(a, span, p.x as f64)).abs())
        .fold(0.0f64, f64::max);
    let speed = sim
        .strands
        .velocities
        .iter()
        .map(|v| v.norm())
        .fold(0.0f32, f32::max);
    println!(
        "catenary.toml: max deviation {worst:.2e} m = {:.3} % of span (sag {:.4} m), max speed {speed:.1e} m/s",
        100.0 * worst / span,
        -catenary_height(a, span, span / 2.0)
    );
    assert!(speed < 1e-2, "the chain has not settled ({speed} m/s)");
    assert!(
        worst < 0.01 * span,
        "deviation {worst} m is over 1 % of span"
    );
}
