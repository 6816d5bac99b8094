//! Recording a session into a point cache: the header, the rig beside the hair, one frame a
//! step.

use std::path::Path;

use hair_cache::{
    CacheHeader, CacheLayout, CacheRig, CacheSummary, CacheWriter, ColliderState, RigFrame,
    WriterOptions,
};
use hair_core::{ColliderId, StrandSet};
use nalgebra::Isometry3;
use sha2::{Digest, Sha256};

use crate::error::{Error, Result};

use super::Session;

impl Session {
    /// Writes the current frame to the cache being recorded, if any.
    pub(super) fn write_frame(&mut self) -> Result<()> {
        let frame = self.frame();
        if self.recorder.is_none() {
            return Ok(());
        }
        let t = std::time::Instant::now();
        let state = self.rig_frame();
        if let Some(w) = &mut self.recorder {
            record_frame(w, frame, &self.strands, &state)?;
        }
        self.cache_time += t.elapsed();
        Ok(())
    }

    /// The scalp and the colliders at the current frame, as caches record them.
    pub(super) fn rig_frame(&self) -> RigFrame {
        RigFrame {
            scalp_body: self.scalp.body,
            scalp_vertices: self.rig.deformed.scalp.clone(),
            colliders: self
                .rig
                .deformed
                .colliders
                .iter()
                .enumerate()
                .map(|(i, vertices)| ColliderState {
                    pose: self
                        .colliders
                        .pose(ColliderId(i as u32))
                        .unwrap_or_else(Isometry3::identity),
                    vertices: vertices.clone(),
                })
                .collect(),
        }
    }

    /// Starts recording to the MCAP cache at `path` (written as `path.partial`, renamed by
    /// [`Session::finish_recording`]): the current frame now, then every step.
    ///
    /// A cache names the scene that made it by a hash (`--resume` compares it). A session a host
    /// assembled without a scene file ([`Session::from_groom`]) is named by
    /// what it starts from instead: SHA-256 of the strand layout (offsets, rest lengths, radii),
    /// the current positions and velocities, the fps and the frame number.
    pub fn record(&mut self, path: &Path, options: WriterOptions) -> Result<()> {
        let mut header = self.cache_header();
        let layout = CacheLayout::of(&self.strands);
        if header.scene_hash.is_empty() {
            header.scene_hash = self.state_hash(&layout);
        }
        let writer = CacheWriter::create(path, &header, &layout, options)?;
        self.record_into(writer)
    }

    /// SHA-256 (hex) of the layout and the current state (see [`Session::record`]).
    fn state_hash(&self, layout: &CacheLayout) -> String {
        let mut h = Sha256::new();
        for o in &layout.offsets {
            h.update(o.to_le_bytes());
        }
        for x in layout.rest_lengths.iter().chain(&layout.radii) {
            h.update(x.to_le_bytes());
        }
        for p in self.positions().iter().chain(self.velocities()) {
            for c in p {
                h.update(c.to_le_bytes());
            }
        }
        h.update(self.fps.to_le_bytes());
        h.update(self.frame().to_le_bytes());
        h.finalize().iter().map(|b| format!("{b:02x}")).collect()
    }

    /// Records into `writer` (already holding any earlier frames, e.g. those a resumed run
    /// takes over): the current frame now, then every step. A new cache gets the session's
    /// rig ([`hair_cache::rig`]), so outputs need nothing but the cache; a writer that already
    /// holds frames keeps whether it has one.
    pub fn record_into(&mut self, mut writer: CacheWriter) -> Result<()> {
        if self.recorder.is_some() {
            return Err(Error::argument(
                "cache",
                "this session is already recording a cache: finish it first",
            ));
        }
        if writer.frame_count() == 0 && !writer.has_rig() {
            writer.attach_rig(&self.rig.rig)?;
        }
        self.recorder = Some(writer);
        let written = self.write_frame();
        if written.is_err() {
            self.recorder = None;
        }
        written
    }

    /// The rig the caches of this session carry ([`hair_cache::rig`]).
    pub fn cache_rig(&self) -> &CacheRig {
        &self.rig.rig
    }

    /// Finishes the cache being recorded (index, summary, rename to its final name).
    pub fn finish_recording(&mut self) -> Result<CacheSummary> {
        match self.recorder.take() {
            Some(w) => Ok(w.finish()?),
            None => Err(Error::argument(
                "cache",
                "this session is not recording a cache",
            )),
        }
    }

    /// The header of a cache of this session: the fps and current frame, the scene (text and
    /// hash; empty for a session a host assembled) and the model's description.
    pub fn cache_header(&self) -> CacheHeader {
        let mut components = self.solver.components(&self.strands);
        if !self.colliders.is_empty() {
            components.insert(hair_core::Component::Contacts);
        }
        let mut extra = std::collections::BTreeMap::new();
        extra.insert("components".to_string(), components.names().join(","));
        extra.insert("substeps".to_string(), self.solver.substeps().to_string());
        extra.insert("model".to_string(), self.solver.model().name().to_string());
        if let Some(s) = self.solver.mass_spring() {
            extra.insert(
                "integrator".to_string(),
                format!("{:?}", s.settings().integrator),
            );
        }
        let (scene_toml, scene_hash) = match &self.animation {
            Some(a) => (a.source.text.clone(), a.source.hash.clone()),
            None => (String::new(), String::new()),
        };
        CacheHeader {
            fps: self.fps as f64,
            first_frame: self.frame(),
            scene_toml,
            scene_hash,
            extra,
        }
    }

    /// Wall-clock time spent writing the recorded frames so far (part of [`Session::step`]'s).
    pub fn cache_write_time(&self) -> std::time::Duration {
        self.cache_time
    }
}

/// Writes frame `frame` of `strands` into `writer`, with the rig's `state` when the cache has
/// a rig.
pub(super) fn record_frame(
    writer: &mut CacheWriter,
    frame: u32,
    strands: &StrandSet,
    state: &RigFrame,
) -> std::result::Result<(), hair_cache::CacheError> {
    let (x, v) = (&strands.positions, &strands.velocities);
    if writer.has_rig() {
        writer.write_frame_with_rig(frame, x, v, state)
    } else {
        writer.write_frame(frame, x, v)
    }
}
