//! [`Session::children`]: render children of a session's current frame, in memory.
//!
//! The same generation as `hairsys render-children export` ([`crate::children`]), fed from the
//! session instead of a cache: the parents are the session's strands at their current
//! positions, rooted (mesh samples, root frames, the scalp's UVs) on the session's current
//! scalp, so a host (the Python module, a DCC's viewport) gets children without writing a cache.
//! The result is [`hair_render`]'s flat buffers, ready for a host's curves or an exporter.

use hair_core::{Anchor, MeshSample};
use hair_render::{generate, ChildBuffers, ChildSettings, Lod, Parents, ScalpRoots};

use crate::error::{Error, Result};
use crate::Session;

impl Session {
    /// Render children of the current frame with `settings` at level of detail `lod`; `colors`
    /// (one RGB per scalp vertex, 0–1) colour the children's roots. Errors name the argument
    /// (`children`, `colors`) and what is expected.
    pub fn children(
        &self,
        settings: &ChildSettings,
        lod: Lod,
        colors: Option<&[[f32; 3]]>,
    ) -> Result<ChildBuffers> {
        let err = |e: hair_render::RenderError| Error::argument("children", e.to_string());
        let strands = self.strands();
        let roots = strands.root_frames(self.scalp());
        let samples: Vec<Option<MeshSample>> = strands
            .anchors()
            .iter()
            .map(|a| match a {
                Anchor::Surface(s) => Some(*s),
                Anchor::Body(_) => None,
            })
            .collect();
        let mut parents = Parents::new(&strands.positions, strands.offsets())
            .map_err(err)?
            .with_root_frames(&roots)
            .map_err(err)?;
        match (&self.scalp().mesh, colors) {
            (Some(mesh), _) => {
                if let Some(c) = colors {
                    if c.len() != mesh.positions().len() {
                        return Err(Error::argument(
                            "colors",
                            format!(
                                "{} colors for {} scalp vertices: give shape ({}, 3)",
                                c.len(),
                                mesh.positions().len(),
                                mesh.positions().len()
                            ),
                        ));
                    }
                }
                parents = parents
                    .with_scalp(ScalpRoots {
                        mesh,
                        samples: &samples,
                        colors,
                    })
                    .map_err(err)?;
            }
            (None, Some(_)) => {
                return Err(Error::argument(
                    "colors",
                    "this session's scalp has no mesh to take root colors from",
                ))
            }
            (None, None) => {}
        }
        generate(&parents, settings, lod).map_err(err)
    }
}
