//! [`Session::children`]: render children of a session's current frame, in memory.
//!
//! The same generation as `hairsys render-children export` ([`crate::output::children`]), fed from the
//! session instead of a cache: the parents are the session's strands at their current
//! positions, rooted (mesh samples, root frames, the scalp's UVs) on the session's current
//! scalp, so a host (the Python module, a DCC's viewport) gets children without writing a cache.
//! The result is [`hair_render`]'s flat buffers, ready for a host's curves or an exporter.

use hair_render::{ChildBuffers, ChildSettings, Lod};

use crate::error::{Error, Result};
use crate::output::children::children_of;
use crate::scene::maps::ChildMapFactors;
use crate::Session;

impl Session {
    /// Render children of the current frame with `settings` at level of detail `lod`; `colors`
    /// (one RGB per scalp vertex, 0–1) colour the children's roots. A session of a scene with
    /// `[maps.clump]` or `[maps.curl]` scales each parent's clump and curl by them. Errors name the argument
    /// (`children`, `colors`) and what is expected.
    pub fn children(
        &self,
        settings: &ChildSettings,
        lod: Lod,
        colors: Option<&[[f32; 3]]>,
    ) -> Result<ChildBuffers> {
        if let (Some(c), Some(mesh)) = (colors, &self.scalp().mesh) {
            let n = mesh.positions().len();
            if c.len() != n {
                return Err(Error::argument(
                    "colors",
                    format!(
                        "{} colors for {n} scalp vertices: give shape ({n}, 3)",
                        c.len()
                    ),
                ));
            }
        }
        if colors.is_some() && self.scalp().mesh.is_none() {
            return Err(Error::argument(
                "colors",
                "this session's scalp has no mesh to take root colors from",
            ));
        }
        let strands = self.strands();
        let none = ChildMapFactors::default();
        let maps = self.scene_child_maps().unwrap_or(&none);
        children_of(
            strands,
            &strands.positions,
            self.scalp(),
            colors,
            maps,
            settings,
            lod,
        )
        .map_err(|e| Error::argument("children", e.to_string()))
    }
}
