//! [`Session::step`]: one frame — the host's (or the scene's) scalp and colliders, the guides'
//! pose, the strand solver's frame, the sim weight, the cache.

use hair_core::{ColliderId, FrameReport, HairError};
use nalgebra::Vector3;

use crate::error::{Error, Result};

use super::record::record_frame;
use super::{FrameView, Session};

impl Session {
    /// Advances one frame with what the host set (and the scene's keyframes for the rest);
    /// writes the frame to the cache being recorded, if any.
    pub fn step(&mut self) -> Result<FrameReport> {
        let report = self.advance()?;
        self.write_frame()?;
        Ok(report)
    }

    /// [`Session::step`], then `beside` on the new frame, run at the same time as the frame is
    /// written to the cache being recorded (encoding and writing keep one thread busy): a host
    /// that inspects every frame — the quality report of `hairsys simulate` — pays only for
    /// what outlasts the write. `beside` runs on the session's thread pool. Returns the frame's
    /// report, what `beside` returned and how much longer than the write it took (zero when it
    /// finished first): what it added to the frame's time.
    pub fn step_with<R: Send>(
        &mut self,
        beside: impl FnOnce(&FrameView) -> R + Send,
    ) -> Result<(FrameReport, R, std::time::Duration)> {
        let report = self.advance()?;
        let mut recorder = self.recorder.take();
        let state = recorder.as_ref().map(|_| self.rig_frame());
        let view = FrameView {
            frame: self.frame(),
            strands: &self.strands,
            colliders: &self.colliders,
            roots: self.solver.roots(),
        };
        let start = std::time::Instant::now();
        let both = || {
            hair_par::join(
                || {
                    let t = std::time::Instant::now();
                    let written = recorder
                        .as_mut()
                        .zip(state.as_ref())
                        .map(|(w, state)| record_frame(w, view.frame, view.strands, state));
                    (written, t.elapsed())
                },
                || beside(&view),
            )
        };
        let ((written, took), result) = match &self.pool {
            Some(pool) => pool.install(both),
            None => both(),
        };
        let added = start.elapsed().saturating_sub(took);
        self.recorder = recorder;
        if let Some(written) = written {
            self.cache_time += took;
            written?;
        }
        Ok((report, result, added))
    }

    /// Solves one frame (see [`Session::step`]) without writing it.
    fn advance(&mut self) -> Result<FrameReport> {
        if let Some((frame, cause)) = &self.failed {
            return Err(Error::Failed {
                frame: *frame,
                cause: cause.clone(),
            });
        }
        let frame = self.frame() + 1;
        let pending = std::mem::take(&mut self.pending);
        let scalp = match (pending.scalp, &self.animation) {
            (Some(s), _) => s,
            (None, Some(a)) => a.sim.scalp_at(frame as f32),
            (None, None) => self.scalp.clone(),
        };
        if let Some(a) = &self.animation {
            for (i, c) in a.sim.colliders.iter().enumerate() {
                let id = ColliderId(i as u32);
                if !pending.posed.get(i).copied().unwrap_or(false) {
                    self.colliders
                        .set_pose(id, c.motion.at(frame as f32))
                        .map_err(|e| Error::Scene(a.scene_error(e)))?;
                }
                // A deforming collider of the scene (USD, OBJ sequence) takes the frame's
                // vertices unless the host deformed it.
                if let (Some(anim), false) = (
                    &c.animation,
                    pending.deformed.get(i).copied().unwrap_or(false),
                ) {
                    self.colliders
                        .set_vertices(id, &anim.vertices_at(frame as f32))
                        .map_err(|e| Error::Scene(a.scene_error(e)))?;
                }
            }
        }
        let blend = self.pose_guides(frame, pending.guide_pose, pending.sim_weight);
        let (solver, strands, colliders) =
            (&mut self.solver, &mut self.strands, &mut self.colliders);
        let mut step = || solver.step_frame(strands, &scalp, Some(colliders));
        let result = match &self.pool {
            Some(pool) => pool.install(step),
            None => step(),
        };
        let report = match result {
            Ok(r) => r,
            Err(source) => {
                self.failed = Some((frame, source.to_string()));
                return Err(self.solver_error(source));
            }
        };
        self.scalp = scalp;
        self.track_rig(frame, pending.scalp_vertices, pending.collider_vertices);
        if let (Some((before, weights)), Some(g)) = (blend, &self.guides) {
            g.animation.blend_onto(
                &mut self.strands,
                self.solver.roots(),
                &before,
                &weights,
                self.fps,
            );
        }
        Ok(report)
    }

    /// After stepping to `frame`: the deformed scalp's and colliders' vertices caches record,
    /// from what the host set (`scalp`, `colliders`) or else the scene's keyframes; what
    /// neither sets stays as it was.
    fn track_rig(
        &mut self,
        frame: u32,
        scalp: Option<Option<Vec<Vector3<f32>>>>,
        colliders: Vec<Option<Vec<Vector3<f32>>>>,
    ) {
        let sim = self.animation.as_ref().map(|a| &a.sim);
        match (scalp, sim) {
            (Some(v), _) => self.rig.deformed.scalp = v,
            (None, Some(sim)) => self.rig.deformed.scalp = sim.scalp_vertices_at(frame as f32),
            (None, None) => {}
        }
        for (i, slot) in self.rig.deformed.colliders.iter_mut().enumerate() {
            let keyed = sim
                .and_then(|s| s.colliders.get(i))
                .and_then(|c| c.animation.as_ref());
            match (colliders.get(i).cloned().flatten(), keyed) {
                (Some(v), _) => *slot = Some(v),
                (None, Some(a)) => *slot = Some(a.vertices_at(frame as f32)),
                (None, None) => {}
            }
        }
    }

    /// Before stepping to `frame`: the animated positions of the frame before, when any hair
    /// will be blended onto the guides after the step, with each hair's weight; then the sim
    /// hairs' rest shapes set to the host's `pose` or the scene's keyed pose at `frame`.
    #[allow(clippy::type_complexity)]
    fn pose_guides(
        &mut self,
        frame: u32,
        pose: Option<Vec<Vec<Vector3<f32>>>>,
        weight: Option<f32>,
    ) -> Option<(Vec<Vector3<f32>>, Vec<f32>)> {
        let g = self.guides.as_mut()?;
        let weights = g.animation.weights(frame as f32, weight);
        let blend = weights.iter().any(|&w| w > 0.0).then(|| {
            let before = g
                .animation
                .animated_positions(&self.strands, self.solver.roots());
            (before, weights)
        });
        let t = std::time::Instant::now();
        g.work = 0;
        if let Some(pose) = pose.or_else(|| g.animation.pose_at(frame as f32)) {
            g.work = g
                .animation
                .apply_pose(&pose, &mut self.strands, &mut g.scratch);
        }
        g.time = t.elapsed();
        blend
    }

    fn solver_error(&self, source: HairError) -> Error {
        let scene = match &self.animation {
            Some(a) => a.origin.clone(),
            None => "session".into(),
        };
        Error::Solver { scene, source }
    }
}
