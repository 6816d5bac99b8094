//! Every shipped scene looks like hair: each runs as shipped, measured frame by frame
//! during the run (`SimulateOptions::quality`), and the report is held to bounds a hair artist
//! would sign:
//!
//! - **nothing inside a collider**: no point deeper than the 0.1 mm contact tolerance in any
//!   frame (the solver's frame-end check puts back what the substeps' contact model left deeper
//!   than 25 µm, `hair_core::contacts`);
//! - **no stretch**: p99 stretch within the scene's strain limit (hair is nearly inextensible;
//!   the limit is what the scene promises), the worst segment within twice it;
//! - **no hairpins**: no point turns by more than 90° in any frame;
//! - **the groom holds at the start**: after the first stepped frame, points moved less than
//!   5 mm RMS from the groom posed on the scalp (a head easing into a turn moves hair by a few mm
//!   in 1/24 s; a sagging or collapsing groom moves it by centimetres). Not checked where the
//!   head turns at full speed from the first frame (strips), since lag and sag look alike there.
//! - **velocities that moved the points**: the velocity–position mismatch between frames
//!   (`hair_core::quality`: the mean velocity the positions imply against the trapezoid of the
//!   stored ones) has p99 ≤ 0.25 m/s. Hermite sampling between frames then leaves the path by at
//!   most 0.096·Δt·0.25 m/s = 1 mm at 24 fps for 99 % of points. A stale velocity — a position
//!   correction not handed on to the velocity — reads directly: a strain limit that leaves
//!   velocities stale makes Sintel's p99 0.67 m/s and a hanging strand's 2.1 m/s.
//!
use std::path::Path;

use hair_cache::WriterOptions;
use hairsys::output::quality::{cache_quality, RunQuality};
use hairsys::run::{simulate, SimulateOptions};
use hairsys::scene::{SceneFile, DEFAULT_SCENE};

fn run(name: &str) -> RunQuality {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(name);
    run_checked(SceneFile::load(&path).unwrap(), false)
}

/// Simulates `scene` measuring its quality as it runs; the same report is then measured from
/// the cache alone (its rig places the scalp and colliders) and must agree to the bit when
/// `cross_check`.
fn run_checked(scene: SceneFile, cross_check: bool) -> RunQuality {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("run.mcap");
    let q = simulate(
        &SimulateOptions {
            scene,
            cache: cache.clone(),
            frames: None,
            threads: None,
            writer: WriterOptions::default(),
            resume: false,
            kernel: Default::default(),
            quality: true,
        },
        |_| {},
    )
    .unwrap()
    .quality
    .expect("asked for");
    if cross_check {
        let from_cache = cache_quality(&cache).unwrap();
        assert_eq!(from_cache.run, q.run);
        assert_eq!(from_cache.last, q.last);
    }
    q
}

struct Bounds {
    /// Whether the scene has colliders to measure against.
    colliders: bool,
    inside_fraction: f64,
    deepest: f32,
    max_strain: f32,
    /// RMS drift from the groom after the first step, m; `None` where the head already turns
    /// fast in the first frame (linear keys), so lag and sag cannot be told apart.
    start_rms: Option<f32>,
    /// Point-frames turning by more than 90° allowed.
    hairpins: u64,
    /// p99 of the velocity–position mismatch between frames, m/s.
    mismatch_p99: f32,
}

const CLEAN: Bounds = Bounds {
    colliders: true,
    inside_fraction: 0.0,
    deepest: 1e-4,
    max_strain: 0.01,
    start_rms: Some(5e-3),
    hairpins: 0,
    mismatch_p99: 0.25,
};

fn check(name: &str, q: &RunQuality, b: Bounds) {
    let r = &q.run;
    if b.colliders {
        let p = r.penetration.as_ref().expect("the scene has colliders");
        assert!(p.inside_fraction <= b.inside_fraction, "{name}: {p:?}");
        assert!(p.deepest <= b.deepest, "{name}: {p:?}");
    }
    // The strain limit holds to f32 round-off.
    let slack = 1e-4;
    assert!(
        r.strain.stretch.p99() <= b.max_strain + slack,
        "{name}: {:?}",
        r.strain
    );
    assert!(
        r.strain.stretch.max() <= 2.0 * b.max_strain,
        "{name}: {:?}",
        r.strain
    );
    assert!(r.hairpins.count <= b.hairpins, "{name}: {:?}", r.hairpins);
    let mismatch = r.velocity_mismatch.as_ref().expect("two frames or more");
    assert!(
        mismatch.p99() <= b.mismatch_p99,
        "{name}: velocity mismatch {mismatch:?}"
    );
    if let Some(bound) = b.start_rms {
        let start = q.first_step.drift.as_ref().unwrap();
        assert!(start.rms < bound, "{name}: first step {start:?}");
    }
}

#[test]
fn default_scene() {
    check("default", &run("default.toml"), CLEAN);
}

/// No sag at the start (sag-free initialisation, the head carrying the hair lying on it): the
/// shipped default on a still head (its motion keys removed), half a second after the start,
/// has moved less than 3 mm RMS and no point more than 15 mm (the hair is 25 cm long; the upper
/// layer settles onto the lower by at most the 4 mm layer depth, which a hanging tip amplifies).
/// Also: the report measured during the run is the one measured from its cache afterwards.
#[test]
fn default_groom_does_not_sag_when_the_simulation_starts() {
    let start = DEFAULT_SCENE.find("keys = [").unwrap();
    let end = start + DEFAULT_SCENE[start..].find("]\n\n").unwrap() + 2;
    let still = format!("{}{}", &DEFAULT_SCENE[..start], &DEFAULT_SCENE[end..])
        .replace("frames = [1, 48]", "frames = [1, 13]");
    let scene = SceneFile::parse(&still, "default, still head", ".".into()).unwrap();
    let q = run_checked(scene, true);
    check("default, still head", &q, CLEAN);
    let drift = q.last.drift.as_ref().unwrap();
    assert!(drift.rms < 3e-3, "{drift:?}");
    assert!(drift.max < 15e-3, "{drift:?}");
}

/// The character: a deforming mesh (Blender's skinned head turn and shrug, read from USD) is
/// scalp and collider. Also: the report measured from its cache, where the mesh is placed at
/// each cached frame, is the run's own.
///
/// Its mesh is given at whole frames and moves linearly between them (as the contacts assume),
/// so every root's velocity jumps at every frame and its mismatch is exactly half the jump
/// (measured from the cache: equal to the root's `|v₁ − v₀|/2` in every frame, p99
/// 0.16 m/s at the roots), and the hair it drags inherits the kinks (p99 0.59 m/s over all
/// points; the same with the collider or the strain limit taken out, so no correction causes
/// it). Its mismatch is allowed 0.75 m/s: what a piecewise-linear drive gives, not a stale
/// velocity.
#[test]
fn character() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/character.toml");
    let q = run_checked(SceneFile::load(&path).unwrap(), true);
    check(
        "character",
        &q,
        Bounds {
            mismatch_p99: 0.75,
            ..CLEAN
        },
    );
}

#[test]
fn wind_demo() {
    check("wind_demo", &run("wind_demo.toml"), CLEAN);
}

/// The keyed gust sweeps the guides back into the head and the sim hairs follow them exactly for
/// a while: the hardest contact of the shipped scenes for the implicit path.
#[test]
fn gust() {
    check("gust", &run("gust.toml"), CLEAN);
}

#[test]
fn collision_demo() {
    check("collision_demo", &run("collision_demo.toml"), CLEAN);
}

#[test]
fn strips_head() {
    // Provot's 5 % limit is the strip model's; the head turns linearly from frame 1.
    check(
        "strips_head",
        &run("strips_head.toml"),
        Bounds {
            max_strain: 0.05,
            start_rms: None,
            ..CLEAN
        },
    );
}

#[test]
fn parity() {
    // No collider (a comparison scene against Blender); its strain limit is 1.5 %; the head
    // moves 1 m in the first frames (linear), so lag and sag look alike there. Its head, like
    // every scalp, moves linearly between the frame's key poses (as the contacts assume): the
    // roots' velocities jump at every frame by up to 1.2 m/s (1 m eased over 11 frames), their
    // mismatch is half the jump (p99 0.72 m/s at the roots, measured from the cache),
    // and 1.5 m strands amplify it to the tips (p99 4.6 m/s there, 1.02 m/s over all points).
    // Allowed 1.5 m/s: what the drive gives, not a stale velocity (see `character`).
    check(
        "parity",
        &run("parity.toml"),
        Bounds {
            colliders: false,
            max_strain: 0.015,
            start_rms: None,
            mismatch_p99: 1.5,
            ..CLEAN
        },
    );
}

/// Sintel: the groom leaves out the sim hairs that started inside the gap between her right ear
/// and head (with them: 0.0067 % of point-frames inside, up to 1.40 mm, and a first segment held
/// 40 % compressed) and the one rooted on that ear's rim that stood out behind it. `"auto"` runs
/// her on BDF2 at 32 substeps per frame (sharp rest joints, `hairsys::scene::integrator`): 0
/// hairpins (largest turn 83°), stretch p99 0.32 %, max 1.011 % against her 1 % limit.
#[test]
fn sintel() {
    check("sintel", &run("sintel.toml"), CLEAN);
}
