//! The Sintel scene (soft 3 mm segments at a 1 % strain limit), where a strain limit that
//! corrects positions without velocities caches 0.25 m/s on hair that does not move: over its
//! first second the median velocity–position mismatch between consecutive frames stays well
//! below that (3,000 strands, on BDF2 at 32 substeps per frame as `"auto"` chooses: about a
//! second in release).
//! `cargo test -p hairsys-tests --test velocity_consistency_sintel -- --nocapture` prints the
//! figures.

use hair_core::quality::{measure, Frame, Previous, QualityInput, QualityOptions};
use hair_core::{MassSpringSolver, QualityReport};
use hairsys::scene::SceneFile;

#[test]
fn sintel_velocities_match_the_motion() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/sintel.toml");
    let mut sim = SceneFile::load(&path).unwrap().build().unwrap();
    let first = sim.first_frame;
    let mut solver = MassSpringSolver::new(
        sim.settings,
        sim.params,
        &sim.strands,
        &sim.scalp_at(first as f32),
        first,
    )
    .unwrap();
    let dt = 1.0 / sim.settings.fps;
    let mut run = QualityReport::default();
    for frame in first + 1..=first + 24 {
        let (x0, v0) = (
            sim.strands.positions.clone(),
            sim.strands.velocities.clone(),
        );
        let scalp = sim.scalp_at(frame as f32);
        solver.step_frame(&mut sim.strands, &scalp).unwrap();
        let input = QualityInput {
            frame: Frame::of(&sim.strands),
            previous: Some(Previous {
                positions: &x0,
                velocities: &v0,
                dt,
            }),
            colliders: None,
            reference: None,
        };
        run.merge(&measure(&input, &QualityOptions::default()).unwrap());
    }
    let m = run.velocity_mismatch.as_ref().unwrap();
    let speed = sim
        .strands
        .velocities
        .iter()
        .map(|v| v.norm())
        .fold(0.0f32, f32::max);
    println!(
        "Sintel, first second: velocity–position mismatch p50 {:.4} p99 {:.4} max {:.3} m/s; \
         stretch p99 {:.5} max {:.5}; fastest point at the end {speed:.3} m/s",
        m.p50(),
        m.p99(),
        m.max(),
        run.strain.stretch.p99(),
        run.strain.stretch.max()
    );
    // The failure was the bulk of the hair carrying a stale velocity (median 0.27 m/s over this
    // second before the fix). The tail is fast collapse motion 24 fps does not resolve (p99
    // 0.67 m/s, see the Limits of the strain limit in `hair_core::integrate`), so the median is
    // what this holds.
    assert!(m.p50() < 0.1, "mismatch p50 {} m/s", m.p50());
}
