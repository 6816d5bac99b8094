//! The quality report of a cached run: does it look like hair? Every cached frame is
//! measured with [`hair_core::quality::measure`] against the colliders at that frame's pose (the
//! cache's rig places them, [`Shot`]), the previous frame (velocity–position mismatch) and
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

use super::OutputError;
use std::path::Path;

use hair_core::quality::{measure_remembered, Frame, PenetrationMemory, Previous, Reference};
use hair_core::{Colliders, QualityInput, QualityOptions, QualityReport, RootFrame, StrandSet};
use nalgebra::Vector3;
use serde::Serialize;

use crate::output::shot::Shot;

/// What [`cache_quality`] (or a run, [`QualityTracker`]) measured.
#[derive(Debug, Clone, Default, Serialize)]
pub struct RunQuality {
    /// Every frame after the first, merged (drift over the run included).
    pub run: QualityReport,
    /// The first stepped frame alone: did hair hold its groom when the simulation started?
    pub first_step: QualityReport,
    /// The last frame alone: drift from the groom after the motion.
    pub last: QualityReport,
}

/// One frame handed to a [`QualityTracker`]: the strands' layout from `strands`, the frame's
/// positions and velocities (m, m/s), the colliders at the frame's pose and the root frames then.
pub struct FrameToMeasure<'a> {
    /// Frame number.
    pub frame: u32,
    /// Positions, m (the layout of `strands`).
    pub positions: &'a [Vector3<f32>],
    /// Velocities, m/s.
    pub velocities: &'a [Vector3<f32>],
    /// Colliders at the frame's pose (none measured when empty).
    pub colliders: &'a Colliders,
    /// The root frames of the strands at the frame (one per strand, e.g.
    /// `StrandSet::root_frames` of the scalp then), which place the groom for the drift.
    pub roots: &'a [RootFrame],
}

/// The last frame a [`QualityTracker`] saw: its number, positions (m) and velocities (m/s).
struct Seen {
    frame: u32,
    positions: Vec<Vector3<f32>>,
    velocities: Vec<Vector3<f32>>,
}

/// Measures a run frame by frame: hand it the first frame, then every stepped frame in order.
/// It keeps a copy of the previous frame (velocity–position mismatch) and the penetration
/// memory that lets points far from colliders skip the exact projection.
pub struct QualityTracker {
    options: QualityOptions,
    memory: PenetrationMemory,
    fps: f64,
    previous: Option<Seen>,
    result: RunQuality,
    stepped: u32,
}

impl QualityTracker {
    /// A tracker for frames at `fps` frames per second.
    pub fn new(fps: f64) -> Self {
        Self {
            options: QualityOptions::default(),
            memory: PenetrationMemory::new(),
            fps,
            previous: None,
            result: RunQuality::default(),
            stepped: 0,
        }
    }

    /// Measures `f` (the first frame is only remembered: it is the groom before any step).
    pub fn add(&mut self, strands: &StrandSet, f: &FrameToMeasure) -> Result<(), OutputError> {
        if let Some(seen) = &self.previous {
            let input = QualityInput {
                frame: Frame {
                    offsets: strands.offsets(),
                    positions: f.positions,
                    velocities: f.velocities,
                    rest_lengths: strands.rest_lengths(),
                    radii: strands.radii(),
                    inverse_masses: Some(strands.inverse_masses()),
                },
                previous: Some(Previous {
                    positions: &seen.positions,
                    velocities: &seen.velocities,
                    dt: (f.frame.saturating_sub(seen.frame).max(1) as f64 / self.fps) as f32,
                }),
                colliders: (!f.colliders.is_empty()).then_some(f.colliders),
                reference: Some(Reference::Posed {
                    roots: f.roots,
                    rest_local: strands.rest_local(),
                }),
            };
            let report =
                measure_remembered(&input, &self.options, &mut self.memory).map_err(|source| {
                    OutputError::Quality {
                        frame: f.frame,
                        source,
                    }
                })?;
            self.result.run.merge(&report);
            if self.stepped == 0 {
                self.result.first_step = report.clone();
            }
            self.result.last = report;
            self.stepped += 1;
        }
        match &mut self.previous {
            Some(seen) => {
                seen.frame = f.frame;
                seen.positions.copy_from_slice(f.positions);
                seen.velocities.copy_from_slice(f.velocities);
            }
            None => {
                self.previous = Some(Seen {
                    frame: f.frame,
                    positions: f.positions.to_vec(),
                    velocities: f.velocities.to_vec(),
                })
            }
        }
        Ok(())
    }

    /// The report so far.
    pub fn finish(self) -> RunQuality {
        self.result
    }
}

/// Measures every frame of the cache at `cache`, its scalp and colliders placed by the cache's
/// rig. Errors name the cache at fault.
pub fn cache_quality(cache: &Path) -> Result<RunQuality, OutputError> {
    let mut shot = Shot::open(cache, None)?;
    let numbers = shot.cached_frames().to_vec();
    if numbers.len() < 2 {
        return Err(OutputError::Request(format!(
            "{}: the cache holds {} frame(s); a quality report needs at least two (the first \
             and a stepped one)",
            cache.display(),
            numbers.len()
        )));
    }
    let mut tracker = QualityTracker::new(shot.fps());
    // Built once (a mesh collider's search tree is the costly part) and placed per frame.
    let mut colliders = shot.colliders_at(f64::from(numbers[0]), shot.scalp_collider())?;
    for &n in &numbers {
        let frame = shot.reader().read_frame(n)?;
        let scalp = shot.scalp_at(f64::from(n))?;
        shot.place_colliders(&mut colliders, f64::from(n))?;
        let roots = shot.strands().root_frames(&scalp);
        tracker.add(
            shot.strands(),
            &FrameToMeasure {
                frame: n,
                positions: &frame.positions,
                velocities: &frame.velocities,
                colliders: &colliders,
                roots: &roots,
            },
        )?;
    }
    Ok(tracker.finish())
}
