//! Rod model: a released strand swinging under gravity with no drag never gains mechanical
//! energy, and results do not depend on the thread count.
//!
//! Reference for the energy: the rod's mechanical energy (kinetic + gravity + bending,
//! [`RodSolver::energy`]) at its release. A straight strand swings in a plane, where the
//! bending forces are the exact gradient of the bending energy; symplectic Euler keeps the
//! elastic part to first order and the projection onto inextensibility only removes kinetic
//! energy (it discards the velocity along the constraint gradients), so the energy may fall but
//! must never rise by more than the integrator's bounded oscillation (0.1 % of the energy scale
//! `m g L` here). A helical strand swings out of its plane, bending and twisting: its elastic
//! force is the gradient of bending plus twist energy at the quasistatic twist, so the same
//! bound holds over 2 s, round and elliptical.
//!
//! Determinism: strands are independent, so the same run in a one-thread and a two-thread rayon
//! pool must give bit-identical positions.

use hair_core::{
    Anchor, HairParams, RodParams, RodSolver, RootFrame, Scalp, SolverSettings, StrandInput,
    StrandSet,
};
use nalgebra::{UnitQuaternion, Vector3};

/// `count` horizontal strands of 24 cm, straight (`curl` = 0) or curled (m).
fn horizontal_strands(count: usize, curl: f32) -> StrandSet {
    let mut set = StrandSet::new();
    for k in 0..count {
        let rest = (0..=16)
            .map(|i| {
                let s = 0.015 * i as f32;
                Vector3::new(curl * (10.0 * s + k as f32).sin(), 0.0, s)
            })
            .collect();
        let anchor = Anchor::Body(RootFrame {
            origin: Vector3::new(0.0, 0.05 * k as f32, 1.0),
            rotation: UnitQuaternion::rotation_between(&Vector3::z(), &Vector3::x()).unwrap(),
        });
        set.push(StrandInput::uniform(anchor, rest, 1e-3, 1e-3, 0.0, 0.0))
            .unwrap();
    }
    set.reset_to_rest(&Scalp::fixed());
    set
}

fn undamped() -> HairParams {
    HairParams {
        air_drag: 0.0,
        ..HairParams::default()
    }
}

#[test]
fn released_strand_never_gains_energy() {
    let scalp = Scalp::fixed();
    let mut set = horizontal_strands(1, 0.0);
    let rod = RodParams {
        semi_major_axis: 3e-4,
        ..RodParams::default()
    };
    let mut solver =
        RodSolver::new(SolverSettings::default(), undamped(), rod, &set, &scalp, 1).unwrap();
    let e0 = solver.energy(&set).total();
    let scale = 1e-3 * 0.24 * 9.81 * 0.24; // m g L
    let (mut highest, mut lowest) = (f64::NEG_INFINITY, f64::INFINITY);
    for _ in 0..24 {
        solver.step_frame(&mut set, &scalp).unwrap();
        let e = solver.energy(&set).total();
        highest = highest.max(e - e0);
        lowest = lowest.min(e - e0);
    }
    let kinetic = solver.energy(&set).kinetic;
    println!(
        "released rod, no drag, 1 s: energy change from {:.3} % to {:.3} % of m g L; kinetic \
         energy at the end {:.2} % of m g L",
        100.0 * lowest / scale,
        100.0 * highest / scale,
        100.0 * kinetic / scale
    );
    assert!(kinetic > 0.01 * scale, "the strand must swing");
    assert!(highest < 1e-3 * scale, "energy rose by {highest} J");
}

/// One horizontal strand of 24 cm coiled as a helix of radius 1.5 cm about its rest direction
/// (about 1.6 turns).
fn helical_strand() -> StrandSet {
    let mut set = StrandSet::new();
    let rest = (0..=24)
        .map(|i| {
            let s = 0.01 * i as f32;
            let a = s / 0.025;
            Vector3::new(0.015 * (1.0 - a.cos()), 0.015 * a.sin(), 0.4 * s)
        })
        .collect();
    let anchor = Anchor::Body(RootFrame {
        origin: Vector3::new(0.0, 0.0, 1.0),
        rotation: UnitQuaternion::rotation_between(&Vector3::z(), &Vector3::x()).unwrap(),
    });
    set.push(StrandInput::uniform(anchor, rest, 1e-3, 1e-3, 0.0, 0.0))
        .unwrap();
    set.reset_to_rest(&Scalp::fixed());
    set
}

#[test]
fn released_helix_never_gains_energy_out_of_its_plane() {
    for axis_ratio in [1.0, 0.8] {
        let scalp = Scalp::fixed();
        let mut set = helical_strand();
        let rod = RodParams {
            semi_major_axis: 1.5e-4,
            axis_ratio,
            ..RodParams::default()
        };
        let mut solver =
            RodSolver::new(SolverSettings::default(), undamped(), rod, &set, &scalp, 1).unwrap();
        let e0 = solver.energy(&set).total();
        let length: f64 = set
            .positions
            .windows(2)
            .map(|w| (w[1] - w[0]).norm() as f64)
            .sum();
        let scale = 1e-3 * 9.81 * length; // m g L
        let (mut highest, mut lowest) = (f64::NEG_INFINITY, f64::INFINITY);
        let (mut twist, mut kinetic) = (0.0f64, 0.0f64);
        for _ in 0..48 {
            solver.step_frame(&mut set, &scalp).unwrap();
            let e = solver.energy(&set);
            highest = highest.max(e.total() - e0);
            lowest = lowest.min(e.total() - e0);
            twist = twist.max(e.twist);
            kinetic = kinetic.max(e.kinetic);
        }
        println!(
            "released helix, b/a = {axis_ratio}, no drag, 2 s, {} substeps/frame: energy change \
             from {:.3} % to {:.4} % of m g L; twist energy up to {:.3} % and kinetic energy up \
             to {:.2} % of m g L",
            solver.substeps(),
            100.0 * lowest / scale,
            100.0 * highest / scale,
            100.0 * twist / scale,
            100.0 * kinetic / scale
        );
        assert!(kinetic > 0.01 * scale, "the strand must swing");
        assert!(twist > 1e-4 * scale, "the swing must load the twist");
        assert!(highest < 1e-3 * scale, "energy rose by {highest} J");
    }
}

#[test]
fn thread_count_does_not_change_the_result() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let scalp = Scalp::fixed();
            let mut set = horizontal_strands(16, 0.01);
            let mut solver = RodSolver::new(
                SolverSettings::default(),
                undamped(),
                RodParams::default(),
                &set,
                &scalp,
                1,
            )
            .unwrap();
            for _ in 0..6 {
                solver.step_frame(&mut set, &scalp).unwrap();
            }
            set.positions
        })
    };
    let (one, two) = (run(1), run(2));
    assert!(one.iter().zip(&two).all(|(a, b)| a == b));
}
