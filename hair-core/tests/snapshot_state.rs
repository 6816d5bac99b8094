//! A solver's state (`StrandSolver::snapshot_state`) is all the next frame needs from it: put
//! back with `restore_state`, with the strands' positions and velocities and the colliders, it
//! steps on to the same bits as the run it was taken from — into the solver it was taken from
//! after that solver stepped on (its workspace holding later frames' contacts and grid) and into
//! a solver built afresh (an empty workspace). Each model runs hair over a turning, nodding
//! head that is a mesh collider; the mass-spring model with hair–hair interaction and a host
//! that changes parameters after the snapshot, which the restore undoes.

mod common;

use common::bits;
use hair_core::model::strips::{HeadShape, StripSettings};
use hair_core::{
    Anchor, Collider, ColliderId, Colliders, HairError, HairHairSettings, HairParams,
    MassSpringSolver, RodParams, RodSolver, RootFrame, Scalp, SolverSettings, StrandInput,
    StrandModel, StrandSet, StrandSolver, StripSolver, TriMesh,
};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

/// Radius of the head, m.
const HEAD: f32 = 0.1;
/// Frames stepped before the snapshot.
const WARM_UP: u32 = 6;
/// Frames compared after it.
const COMPARED: u32 = 6;

/// The head's pose at frame `f`: a turn about z and a nod about x, with a sway along y.
fn head(f: u32) -> Scalp {
    let t = f as f32 / 24.0;
    let turn = 0.8 * (std::f32::consts::TAU * 0.7 * t).sin();
    let nod = 0.3 * (std::f32::consts::TAU * 1.1 * t).sin();
    let sway = 0.02 * (std::f32::consts::TAU * 1.3 * t).sin();
    Scalp {
        mesh: None,
        body: Isometry3::from_parts(
            Translation3::new(0.0, sway, 0.0),
            UnitQuaternion::from_euler_angles(nod, 0.0, turn),
        ),
    }
}

/// 24 strands (12 pairs of neighbours, for the strip model) of 12 segments and 0.2 m, rooted
/// just above the head's upper half and combed down over it, so they lie on it.
fn hair() -> StrandSet {
    hair_of(24)
}

/// The first `count` strands of [`hair`].
fn hair_of(count: usize) -> StrandSet {
    let mut set = StrandSet::new();
    for k in 0..count {
        let phi = std::f32::consts::TAU * (k / 2) as f32 / 12.0 + 0.05 * (k % 2) as f32;
        let out = Vector3::new(phi.cos(), phi.sin(), 0.0);
        let up = Vector3::z();
        let normal = (out * 0.6 + up).normalize();
        let origin = normal * (HEAD + 0.004);
        let dir = (out - up * 0.3).normalize();
        let rotation = UnitQuaternion::rotation_between(&Vector3::z(), &dir)
            .unwrap_or_else(UnitQuaternion::identity);
        let rest = (0..=12)
            .map(|i| Vector3::z() * (0.2 * i as f32 / 12.0))
            .collect();
        let anchor = Anchor::Body(RootFrame { origin, rotation });
        set.push(StrandInput::uniform(anchor, rest, 1e-3, 1.5e-3, 0.0, 0.0))
            .unwrap();
    }
    set.reset_to_rest(&head(0));
    set
}

fn params() -> HairParams {
    HairParams {
        gravity: [0.0, 0.0, -9.81],
        stretch_stiffness: 40.0,
        bend_stiffness: 0.05,
        goal_stiffness: 0.0,
        stretch_damping: 200.0,
        air_drag: 1.0,
    }
}

fn head_mesh() -> TriMesh {
    TriMesh::uv_sphere(HEAD, 32, 16).unwrap()
}

/// One run: the strands, the solver and the colliders (the head).
struct Run {
    strands: StrandSet,
    solver: StrandSolver,
    colliders: Colliders,
    head: ColliderId,
}

/// A run of `model` at frame 0.
fn build(model: StrandModel) -> Run {
    let strands = hair();
    let scalp = head(0);
    let settings = SolverSettings::default();
    let solver: StrandSolver = match model {
        StrandModel::MassSpring => MassSpringSolver::new(settings, params(), &strands, &scalp, 0)
            .unwrap()
            .with_hair_hair(
                HairHairSettings {
                    cell_size: 0.01,
                    friction: 0.3,
                    repulsion: 0.1,
                    target_density: 0.2,
                },
                &strands,
            )
            .unwrap()
            .into(),
        StrandModel::Rod => RodSolver::new(
            settings,
            params(),
            RodParams::default(),
            &strands,
            &scalp,
            0,
        )
        .unwrap()
        .into(),
        StrandModel::Strips => StripSolver::new(
            settings,
            params(),
            &strands,
            &scalp,
            0,
            StripSettings::default(),
            Some(HeadShape::new(&head_mesh()).unwrap()),
        )
        .unwrap()
        .into(),
    };
    let mut colliders = Colliders::new();
    let head = colliders
        .insert(Collider::mesh(head_mesh()), scalp.body)
        .unwrap();
    Run {
        strands,
        solver,
        colliders,
        head,
    }
}

/// Steps `run` to frame `f`; returns the contacts found.
fn step(run: &mut Run, f: u32) -> u64 {
    let scalp = head(f);
    run.colliders.set_pose(run.head, scalp.body).unwrap();
    run.solver
        .step_frame(&mut run.strands, &scalp, Some(&mut run.colliders))
        .unwrap()
        .contact_points
}

/// What a host saves to step on from a frame.
struct Saved {
    state: hair_core::StrandSolverState,
    positions: Vec<Vector3<f32>>,
    velocities: Vec<Vector3<f32>>,
    colliders: Colliders,
}

fn save(run: &Run) -> Saved {
    Saved {
        state: run.solver.snapshot_state(),
        positions: run.strands.positions.clone(),
        velocities: run.strands.velocities.clone(),
        colliders: run.colliders.clone(),
    }
}

fn restore(run: &mut Run, saved: &Saved) -> Result<(), HairError> {
    run.solver.restore_state(&saved.state)?;
    run.strands.positions.clone_from(&saved.positions);
    run.strands.velocities.clone_from(&saved.velocities);
    run.colliders = saved.colliders.clone();
    Ok(())
}

/// Steps `run` over the compared frames and checks every frame's bits against `reference`.
fn check(run: &mut Run, reference: &[Vec<u32>], what: &str) {
    for (k, f) in (WARM_UP + 1..=WARM_UP + COMPARED).enumerate() {
        step(run, f);
        let got = bits(&run.strands);
        let differ = got
            .iter()
            .zip(&reference[k])
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(
            differ, 0,
            "{what}: {differ} coordinates differ at frame {f}"
        );
    }
}

fn steps_on_bit_identically(model: StrandModel) {
    let mut run = build(model);
    let mut contacts = 0;
    for f in 1..=WARM_UP {
        contacts += step(&mut run, f);
    }
    let saved = save(&run);
    assert_eq!(saved.state.frame(), WARM_UP);
    assert_eq!(saved.state.model(), model);
    let mut reference = Vec::new();
    for f in WARM_UP + 1..=WARM_UP + COMPARED {
        contacts += step(&mut run, f);
        reference.push(bits(&run.strands));
    }
    assert!(contacts > 0, "{model:?}: the hair never touched the head");

    // The host changes what it may change between frames, and steps on with other frames.
    if let Some(s) = run.solver.mass_spring_mut() {
        s.params_mut().air_drag = 4.0;
        s.params_mut().gravity = [0.0, 1.0, -9.81];
        if let Some(h) = s.hair_hair_mut() {
            h.friction = 0.9;
        }
    }
    for f in WARM_UP + COMPARED + 1..=WARM_UP + COMPARED + 4 {
        step(&mut run, f);
    }
    restore(&mut run, &saved).unwrap();
    assert_eq!(run.solver.frame(), WARM_UP);
    check(
        &mut run,
        &reference,
        &format!("{model:?}, restored into its own solver"),
    );

    let mut fresh = build(model);
    restore(&mut fresh, &saved).unwrap();
    check(
        &mut fresh,
        &reference,
        &format!("{model:?}, restored into a new solver"),
    );
}

#[test]
fn mass_spring_with_contacts_and_hair_hair_steps_on_bit_identically() {
    steps_on_bit_identically(StrandModel::MassSpring);
}

#[test]
fn rod_with_contacts_steps_on_bit_identically() {
    steps_on_bit_identically(StrandModel::Rod);
}

#[test]
fn strips_with_contacts_step_on_bit_identically() {
    steps_on_bit_identically(StrandModel::Strips);
}

#[test]
fn a_state_of_another_model_or_other_strands_is_refused() {
    let mass_spring = build(StrandModel::MassSpring);
    let mut rod = build(StrandModel::Rod);
    let e = rod
        .solver
        .restore_state(&mass_spring.solver.snapshot_state())
        .unwrap_err();
    assert!(
        matches!(&e, HairError::Parameter { name, .. } if name == "state"),
        "{e}"
    );
    let fewer = hair_of(2);
    let mut small: StrandSolver =
        MassSpringSolver::new(SolverSettings::default(), params(), &fewer, &head(0), 0)
            .unwrap()
            .into();
    assert!(small
        .restore_state(&mass_spring.solver.snapshot_state())
        .is_err());
}
