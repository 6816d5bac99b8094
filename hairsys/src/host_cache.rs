//! [`Session::record_host`]: recording a cache of a session a host assembled without a scene
//! file ([`Session::new`], [`Session::from_groom`]).
//!
//! A cache names the scene that made it by a hash (hex digits; `--resume` compares it), and the
//! cache writer refuses an empty one. A host-assembled session has no scene text, so its cache is
//! named by what it starts from instead: SHA-256 of the strand layout (offsets, rest lengths,
//! radii), the first frame's positions and velocities, the fps and the first frame number. Two
//! caches of the same groom started from the same state get the same hash; anything else
//! differs. A session built from a scene records with the scene's own hash, as
//! [`Session::record`] does.

use std::path::Path;

use hair_cache::{CacheLayout, CacheWriter, WriterOptions};
use sha2::{Digest, Sha256};

use crate::error::Result;
use crate::Session;

impl Session {
    /// Starts recording to the MCAP cache at `path` like [`Session::record`], naming a session
    /// without a scene by the hash of its starting state (see the module docs).
    pub fn record_host(&mut self, path: &Path, options: WriterOptions) -> Result<()> {
        let mut header = self.cache_header();
        let layout = CacheLayout::of(self.strands());
        if header.scene_hash.is_empty() {
            header.scene_hash = self.state_hash(&layout);
        }
        let writer = CacheWriter::create(path, &header, &layout, options)?;
        self.record_into(writer)
    }

    /// SHA-256 (hex) of the layout and the current state.
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
        h.update(self.fps().to_le_bytes());
        h.update(self.frame().to_le_bytes());
        h.finalize().iter().map(|b| format!("{b:02x}")).collect()
    }
}
