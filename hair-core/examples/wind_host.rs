//! A host driving force fields and hair–hair interaction frame by frame, as a DCC plugin would:
//! a wind whose speed the host sets every frame (e.g. from an animated slider), turbulence with a
//! keyed strength, and voxel friction and repulsion on a small bundle. Prints the bundle's tip
//! and each frame's cost of the grid and the fields.
//!
//! Run: `cargo run -p hair-core --example wind_host`.

use hair_core::{
    Anchor, FieldKind, ForceField, HairHairSettings, HairParams, MassSpringSolver, RootFrame,
    Scalp, SolverSettings, StrandInput, StrandSet, Strength,
};
use nalgebra::Vector3;

fn main() -> Result<(), hair_core::HairError> {
    // 64 strands of 12 segments hanging from a 2 cm patch.
    let mut strands = StrandSet::new();
    for s in 0..64 {
        let root = Vector3::new((s % 8) as f32, (s / 8) as f32, 0.0) * 0.003;
        let rest = (0..=12)
            .map(|i| Vector3::new(0.0, 0.0, -0.2 * i as f32 / 12.0))
            .collect();
        let anchor = Anchor::Body(RootFrame::at(root));
        strands.push(StrandInput::uniform(anchor, rest, 1e-3, 1e-3, 0.0, 0.0))?;
    }
    let scalp = Scalp::fixed();
    strands.reset_to_rest(&scalp);

    let mut wind = ForceField::new(
        FieldKind::Wind {
            noise: 0.2,
            seed: 1,
        },
        0.0,
    );
    wind.direction = Vector3::x();
    let mut turbulence = ForceField::new(
        FieldKind::Turbulence {
            size: 0.05,
            flow: 1.0,
            seed: 2,
        },
        0.0,
    );
    // Keyed in the scene's frames: off until frame 12, 1 m/s air speed from frame 24.
    turbulence.strength = Strength::Keys(vec![(12.0, 0.0), (24.0, 1.0)]);
    let hair_hair = HairHairSettings {
        cell_size: 0.01,
        friction: 0.3,
        repulsion: 0.3,
        target_density: 0.2,
    };
    let params = HairParams {
        air_drag: 2.0,
        ..HairParams::default()
    };
    let mut solver = MassSpringSolver::new(SolverSettings::default(), params, &strands, &scalp, 1)?
        .with_hair_hair(hair_hair, &strands)?
        .with_fields(vec![wind, turbulence])?;

    for frame in 2..=48 {
        // The host's own animation of the wind speed (m/s): a gust peaking at frame 24.
        let gust = 3.0 * (std::f32::consts::PI * (frame - 2) as f32 / 46.0).sin();
        solver.fields_mut()[0].strength = Strength::Constant(gust);
        let report = solver.step_frame(&mut strands, &scalp)?;
        let tip = strands.positions[strands.points(0).end - 1];
        println!(
            "frame {frame:2}: wind {gust:4.2} m/s, tip of strand 0 at ({:+.3}, {:+.3}, {:+.3}) m; \
             grid {:.3} ms, fields {:.3} ms",
            tip.x,
            tip.y,
            tip.z,
            report.times.volume.as_secs_f64() * 1e3,
            report.times.fields.as_secs_f64() * 1e3
        );
    }
    Ok(())
}
