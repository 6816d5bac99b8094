//! [`Session::children`]: render children of a session's current frame, in memory.
//!
//! The same generation as `hairsys render-children export` ([`crate::output::children`]), fed from the
//! session instead of a cache: the parents are the session's strands at their current
//! positions, rooted (mesh samples, root frames, the scalp's UVs) on the session's current
//! scalp, so a host (the Python module, a DCC's viewport) gets children without writing a cache.
//! The result is [`hair_render`]'s flat buffers, ready for a host's curves or an exporter.
//! [`Session::children_at`] makes children of positions the host hands over (a cached frame it
//! plays back) on the scalp deformed as at that frame, without stepping the session.

use bytemuck::cast_slice;
use hair_core::Scalp;
use hair_render::{ChildBuffers, ChildSettings, Lod};
use nalgebra::{Isometry3, Vector3};

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

    /// Render children of the strands at `positions` (m, world space, one per point of this
    /// session's strands in their order, e.g. a frame of its cache) rooted on the scalp at
    /// `scalp_vertices` (m, world space, one per vertex of the rest scalp in its order; `None`
    /// keeps the session's current scalp), with `settings` at level of detail `lod`. The
    /// session itself does not change: a host makes children of frames it plays back rather
    /// than steps. Errors name the argument (`positions`, `scalp_vertices`, `children`).
    pub fn children_at(
        &self,
        positions: &[[f32; 3]],
        scalp_vertices: Option<&[[f32; 3]]>,
        settings: &ChildSettings,
        lod: Lod,
    ) -> Result<ChildBuffers> {
        let strands = self.strands();
        let expected = strands.point_count();
        if positions.len() != expected {
            return Err(Error::argument(
                "positions",
                format!(
                    "{} points given, the session's strands have {expected}: give shape \
                     ({expected}, 3), the strands' points in order",
                    positions.len()
                ),
            ));
        }
        if let Some(i) = positions
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(Error::argument(
                "positions",
                format!("point {i} is not finite ({:?})", positions[i]),
            ));
        }
        let deformed;
        let scalp = match scalp_vertices {
            None => self.scalp(),
            Some(vertices) => {
                let Some(rest) = &self.rest_scalp else {
                    return Err(Error::argument(
                        "scalp_vertices",
                        "this session's scalp has no mesh to deform",
                    ));
                };
                let mut mesh = rest.clone();
                mesh.set_positions(cast_slice::<[f32; 3], Vector3<f32>>(vertices))
                    .map_err(|e| Error::argument("scalp_vertices", e.to_string()))?;
                deformed = Scalp {
                    mesh: Some(mesh),
                    body: Isometry3::identity(),
                };
                &deformed
            }
        };
        let none = ChildMapFactors::default();
        let maps = self.scene_child_maps().unwrap_or(&none);
        children_of(
            strands,
            cast_slice(positions),
            scalp,
            None,
            maps,
            settings,
            lod,
        )
        .map_err(|e| Error::argument("children", e.to_string()))
    }
}
