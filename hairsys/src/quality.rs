//! The quality report of a cached run (issue 17): does it look like hair? Every cached frame is
//! measured with [`hair_core::quality::measure`] against the colliders at that frame's pose (the
//! scene stored in the cache places them), the previous frame (velocity–position mismatch) and
//! the groom posed on the scalp at that frame; the frames merge into one report for the run.
//!
//! Drift from the groom is reported twice: over the run (large while the head moves hair around,
//! by design) and at the **first** and **last** frames — the first says whether hair held its
//! groom when the simulation started (sag-free initialisation), the last whether it came back
//! after the motion (the shipped scenes end in their starting pose). Frame 1 of a cache is the
//! state before any step, so the first frame reported here is the first *stepped* frame.
//!
//! Cost: one pass over the cache's frames, linear in points: a few operations per point, and an
//! exact parry projection only for points that may have reached a collider since the previous
//! frame ([`PenetrationMemory`]); see BENCHMARKS.md.

use std::path::Path;

use hair_core::quality::{measure_remembered, rest_positions, Frame, PenetrationMemory, Previous};
use hair_core::{QualityInput, QualityOptions, QualityReport};
use serde::Serialize;

use crate::children::open_cache;

/// What [`cache_quality`] measured.
#[derive(Debug, Clone, Serialize)]
pub struct RunQuality {
    /// Every frame after the first, merged (drift over the run included).
    pub run: QualityReport,
    /// The first stepped frame alone: did hair hold its groom when the simulation started?
    pub first_step: QualityReport,
    /// The last cached frame alone: drift from the groom after the motion.
    pub last: QualityReport,
}

/// Measures every frame of the cache at `cache` (the scene stored in it, or the scene file
/// `scene`, places the scalp and colliders). Errors name the cache or scene at fault.
pub fn cache_quality(cache: &Path, scene: Option<&Path>) -> Result<RunQuality, String> {
    let (scene, mut reader) = open_cache(cache, scene)?;
    let sim = scene.build().map_err(|e| e.to_string())?;
    let numbers = reader.frame_numbers().to_vec();
    if numbers.len() < 2 {
        return Err(format!(
            "{}: the cache holds {} frame(s); a quality report needs at least two (the first \
             and a stepped one)",
            cache.display(),
            numbers.len()
        ));
    }
    let fps = reader.header().fps;
    let cached_points = reader.layout().point_count();
    if cached_points != sim.strands.point_count() {
        return Err(format!(
            "{}: the cache holds {} points but its scene builds {}; give the scene that made \
             it with --scene",
            cache.display(),
            cached_points,
            sim.strands.point_count()
        ));
    }
    let options = QualityOptions::default();
    let mut run = QualityReport::default();
    let mut first_step = None;
    let mut last = QualityReport::default();
    let mut previous = reader.read_frame(numbers[0]).map_err(|e| e.to_string())?;
    let mut memory = PenetrationMemory::new();
    // Built once (a mesh collider's search tree is the costly part) and posed per frame.
    let mut colliders = sim
        .colliders_at(numbers[0] as f32)
        .map_err(|e| sim.collider_message(&e))?;
    for (k, &n) in numbers.iter().enumerate().skip(1) {
        let frame = reader.read_frame(n).map_err(|e| e.to_string())?;
        let f = n as f32;
        let scalp = sim.scalp_at(f);
        sim.pose_colliders(&mut colliders, f)
            .and_then(|()| colliders.place_scalp(&scalp))
            .map_err(|e| sim.collider_message(&e))?;
        let reference = rest_positions(&sim.strands, &scalp);
        let input = QualityInput {
            frame: Frame {
                offsets: sim.strands.offsets(),
                positions: &frame.positions,
                velocities: &frame.velocities,
                rest_lengths: sim.strands.rest_lengths(),
                radii: sim.strands.radii(),
                inverse_masses: Some(sim.strands.inverse_masses()),
            },
            previous: Some(Previous {
                positions: &previous.positions,
                velocities: &previous.velocities,
                dt: ((n - previous.frame) as f64 / fps) as f32,
            }),
            colliders: (!colliders.is_empty()).then_some(&colliders),
            reference: Some(&reference),
        };
        let report = measure_remembered(&input, &options, &mut memory)
            .map_err(|e| format!("frame {n}: {e}"))?;
        run.merge(&report);
        if first_step.is_none() {
            first_step = Some(report.clone());
        }
        if k + 1 == numbers.len() {
            last = report;
        }
        previous = frame;
    }
    Ok(RunQuality {
        run,
        first_step: first_step.unwrap_or_default(),
        last,
    })
}
