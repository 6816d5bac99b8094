//! [`Snapshot`]: a copy of a session's state at one frame, for scrubbing. Stepping on from a
//! restored snapshot gives the same bits as stepping on from where it was taken.

use hair_core::frames::RestDirection;
use hair_core::{Colliders, Scalp, StrandSolverState};
use nalgebra::Vector3;

use crate::error::{Error, Result};

use super::{Deformed, Pending, Session};

/// A copy of a session's state at one frame, for scrubbing ([`Session::snapshot`]).
#[derive(Debug, Clone)]
pub struct Snapshot {
    frame: u32,
    positions: Vec<Vector3<f32>>,
    velocities: Vec<Vector3<f32>>,
    solver: StrandSolverState,
    colliders: Colliders,
    scalp: Scalp,
    /// Animated rest shapes and rest directions, with animated guides.
    rest: Option<(Vec<Vector3<f32>>, Vec<RestDirection>)>,
    /// The deformed scalp's and colliders' vertices that caches record.
    rig: Deformed,
}

impl Snapshot {
    /// The frame the snapshot holds.
    pub fn frame(&self) -> u32 {
        self.frame
    }
}

impl Session {
    /// A copy of the state at the current frame (see the module docs).
    pub fn snapshot(&self) -> Snapshot {
        Snapshot {
            frame: self.frame(),
            positions: self.strands.positions.clone(),
            velocities: self.strands.velocities.clone(),
            solver: self.solver.snapshot_state(),
            colliders: self.colliders.clone(),
            scalp: self.scalp.clone(),
            rest: self.guides.as_ref().map(|_| {
                (
                    self.strands.rest_local().to_vec(),
                    self.strands.bend_rest().to_vec(),
                )
            }),
            rig: self.rig.deformed.clone(),
        }
    }

    /// Puts the session back in the state of `snapshot` (taken from this session) and clears
    /// a failure. Refused while a cache is being recorded (its frames must increase) and for a
    /// snapshot of other strands.
    pub fn restore(&mut self, snapshot: &Snapshot) -> Result<()> {
        if self.recorder.is_some() {
            return Err(Error::argument(
                "snapshot",
                "cannot go back in time while recording a cache: finish the cache first",
            ));
        }
        if snapshot.positions.len() != self.strands.point_count()
            || snapshot.solver.roots().len() != self.strands.len()
        {
            return Err(Error::argument(
                "snapshot",
                format!(
                    "holds {} points of {} strands, this session {} of {}: restore a snapshot of \
                     this session",
                    snapshot.positions.len(),
                    snapshot.solver.roots().len(),
                    self.strands.point_count(),
                    self.strands.len()
                ),
            ));
        }
        self.solver
            .restore_state(&snapshot.solver)
            .map_err(|e| Error::argument("snapshot", e.to_string()))?;
        self.strands.positions.clone_from(&snapshot.positions);
        self.strands.velocities.clone_from(&snapshot.velocities);
        self.colliders = snapshot.colliders.clone();
        self.scalp = snapshot.scalp.clone();
        self.rig.deformed.clone_from(&snapshot.rig);
        if let Some((rest, bend)) = &snapshot.rest {
            self.strands.rest_local_mut().copy_from_slice(rest);
            self.strands.bend_rest_mut().copy_from_slice(bend);
        }
        self.pending = Pending::default();
        self.failed = None;
        Ok(())
    }
}
