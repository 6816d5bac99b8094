//! `hairsys simulate --resume`: continue an interrupted run from its last complete frame.
//!
//! A run writes `CACHE.partial` until it finishes. After a crash or a kill, the frames of every
//! complete chunk are recovered from it ([`hair_cache::recover()`]); the run's state at the last
//! recovered frame is its positions and velocities (stored exactly, as f32) plus the scalp at that
//! frame, which the scene gives again. The solver restarts there, so the resumed cache's frames
//! are bit-identical to those of an uninterrupted run — except with the rod model
//! (`model = "rod"`), whose twist angles are solver state the cache does not carry: they restart
//! from the rest twist, and the resumed frames match to round-off (see `hair_core::model::rod`). A
//! `.partial` written from a different scene (scene hash) or another frame range is refused.

use std::path::Path;

use hair_cache::{CacheRig, Frame, Precision, RecoveryWarning, RigFrame};

use crate::build::Simulation;
use crate::error::Error;

/// What was taken over from the interrupted run.
pub struct Resumed {
    /// Every recovered frame, in order; the last is the state the run continues from.
    pub frames: Vec<Frame>,
    /// What the interrupted run lost (frames after the last complete chunk).
    pub warning: Option<RecoveryWarning>,
    /// How the interrupted run stored its frames; the resumed run keeps it.
    pub precision: Precision,
    /// The interrupted run's rig, if its cache had one, and the rig's state at each of
    /// `frames`.
    pub rig: Option<(CacheRig, Vec<RigFrame>)>,
}

impl Resumed {
    /// The frame the run continues from.
    pub fn last_frame(&self) -> u32 {
        self.frames.last().map_or(0, |f| f.frame)
    }
}

/// Recovers `CACHE.partial`, checks it belongs to this scene (`scene_hash`) and frame range, and
/// puts `sim` in the state of its last complete frame (`sim.first_frame` becomes that frame).
pub fn resume(cache: &Path, scene_hash: &str, sim: &mut Simulation) -> Result<Resumed, Error> {
    let partial = hair_cache::partial_path(cache)?;
    if !partial.exists() {
        let done = if cache.exists() {
            format!("; {} is already complete", cache.display())
        } else {
            String::new()
        };
        return Err(Error::Usage(format!(
            "--resume: there is no interrupted run to resume ({} does not exist{done}); run without --resume",
            partial.display()
        )));
    }
    let recovery = hair_cache::recover(&partial)?;
    if recovery.header.scene_hash != scene_hash {
        return Err(Error::Usage(format!(
            "--resume: {} was written from a different scene (scene hash {} ≠ {}); resume with the scene \
             that started it, or run without --resume to start over",
            partial.display(),
            short(&recovery.header.scene_hash),
            short(scene_hash)
        )));
    }
    if recovery.header.first_frame != sim.first_frame
        || recovery.layout.point_count() != sim.strands.point_count()
    {
        return Err(Error::Usage(format!(
            "--resume: {} starts at frame {} with {} points, this run at frame {} with {}; use the same --frames",
            partial.display(),
            recovery.header.first_frame,
            recovery.layout.point_count(),
            sim.first_frame,
            sim.strands.point_count()
        )));
    }
    let Some(last) = recovery.frames.last() else {
        return Err(Error::Usage(format!(
            "--resume: {} holds no complete frame; run without --resume to start over",
            partial.display()
        )));
    };
    if last.frame >= sim.last_frame {
        return Err(Error::Usage(format!(
            "--resume: {} already reaches frame {} (the run ends at {}); finish it with `hairsys cache recover`",
            partial.display(),
            last.frame,
            sim.last_frame
        )));
    }
    // A frame with a non-finite position or velocity cannot be continued from (and the solver
    // would then report a "divergence" the run never had): refuse it by frame and point.
    for f in &recovery.frames {
        let bad = f
            .positions
            .iter()
            .chain(&f.velocities)
            .position(|v| !v.iter().all(|x| x.is_finite()));
        if let Some(i) = bad {
            let point = i % f.positions.len().max(1);
            return Err(Error::Usage(format!(
                "--resume: {} holds a non-finite position or velocity at frame {}, point {point} \
                 (a damaged or hand-edited file): it cannot be continued; recover the frames \
                 before it with `hairsys cache recover`, or run without --resume (--force) to \
                 start over",
                partial.display(),
                f.frame
            )));
        }
    }
    sim.strands.positions.copy_from_slice(&last.positions);
    sim.strands.velocities.copy_from_slice(&last.velocities);
    sim.first_frame = last.frame;
    Ok(Resumed {
        rig: recovery.rig.map(|rig| (rig, recovery.rig_frames)),
        frames: recovery.frames,
        warning: recovery.warning,
        precision: recovery.precision,
    })
}

fn short(hash: &str) -> &str {
    &hash[..hash.len().min(12)]
}
