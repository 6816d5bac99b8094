//! The parents children grow from: polylines of the simulation level at one instant (a cached
//! frame, a sub-frame sample or the rest state), with where their roots sit.
//!
//! Positions are flat and strand-contiguous like [`hair_core::StrandSet`] and the cache's frames:
//! parent `p` owns `positions[offsets[p]..offsets[p + 1]]`, root first. A parent's root frame
//! (local x tangent, y bitangent, z surface normal) is, in order of preference: its scalp mesh
//! sample evaluated on the mesh ([`Parents::with_scalp`]), the frame given by
//! [`Parents::with_root_frames`], or a frame built from its first segment (z along the segment).
//! Root UVs and colors come from the scalp (mesh UVs, optional per-vertex colors) through the
//! parent's sample. Per parent, a host may give the spread radius of its children
//! ([`Parents::with_spread_radii`]) and factors of their clump and curl
//! ([`Parents::with_shape_factors`], e.g. painted maps sampled at the parents' roots).

use hair_core::mesh::any_perpendicular;
use hair_core::{MeshSample, RootFrame, TriMesh};
use nalgebra::{Vector2, Vector3};

use crate::error::{InputError, RenderError, Result};
use crate::shape::Shape;

/// The scalp the parents are rooted on, for root frames, UVs and colors.
#[derive(Debug, Clone, Copy)]
pub struct ScalpRoots<'a> {
    /// The scalp mesh at the same instant as the positions (meters).
    pub mesh: &'a TriMesh,
    /// Each parent's mesh sample, `None` for a parent not rooted on the mesh.
    pub samples: &'a [Option<MeshSample>],
    /// Optional per-vertex linear RGB colors (0–1) of the mesh, interpolated to the roots.
    pub colors: Option<&'a [[f32; 3]]>,
}

/// Parent strands at one instant, borrowed from the caller.
#[derive(Debug, Clone, Copy)]
pub struct Parents<'a> {
    positions: &'a [Vector3<f32>],
    offsets: &'a [u32],
    root_frames: Option<&'a [RootFrame]>,
    scalp: Option<ScalpRoots<'a>>,
    spread: Option<&'a [f32]>,
    shape_factors: ShapeFactors<'a>,
}

/// Per-parent factors of the children's shape (painted maps): parent `p`'s children
/// have clump factor `clump[p] × shape.clump.factor` and curl radius `curl[p] ×
/// shape.curl.radius`. `None`: factor 1 for every parent.
#[derive(Debug, Clone, Copy, Default)]
pub struct ShapeFactors<'a> {
    /// Factor of the clump factor per parent, in [0, 1].
    pub clump: Option<&'a [f32]>,
    /// Factor of the curl radius per parent, in [0, 1].
    pub curl: Option<&'a [f32]>,
}

/// What one parent contributes besides its polyline: resolved root frame and attributes.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ParentRoot {
    /// Root frame (x tangent, y bitangent, z normal), meters.
    pub frame: RootFrame,
    /// Root UV from the scalp, if known.
    pub uv: Option<Vector2<f32>>,
    /// Root color from the scalp's vertex colors, if known.
    pub color: Option<[f32; 3]>,
}

impl ScalpRoots<'_> {
    /// Frame, UV and color of the scalp at `sample` (a valid sample of the mesh).
    pub(crate) fn point(&self, sample: &MeshSample) -> ParentRoot {
        let color = self.colors.map(|c| {
            let tri = self.mesh.triangles()[sample.triangle as usize];
            let mut rgb = [0.0; 3];
            for (&v, w) in tri.iter().zip(sample.weights) {
                for k in 0..3 {
                    rgb[k] += c[v as usize][k] * w;
                }
            }
            rgb
        });
        ParentRoot {
            frame: self.mesh.evaluate(sample),
            uv: self.mesh.sample_uv(sample),
            color,
        }
    }
}

impl<'a> Parents<'a> {
    /// Parents from flat world positions (meters) and strand offsets (`offsets[0] = 0`, one more
    /// entry than parents, the last equal to `positions.len()`). Every parent needs ≥ 2 points,
    /// finite coordinates and a first segment of non-zero length; checked here, naming the parent.
    pub fn new(positions: &'a [Vector3<f32>], offsets: &'a [u32]) -> Result<Self> {
        if offsets.len() < 2 {
            return Err(InputError::NoParents.into());
        }
        if offsets[0] != 0 || *offsets.last().unwrap_or(&0) as usize != positions.len() {
            return Err(InputError::Offsets {
                first: offsets[0],
                last: offsets[offsets.len() - 1],
                positions: positions.len(),
            }
            .into());
        }
        for p in 0..offsets.len() - 1 {
            let (a, b) = (offsets[p] as usize, offsets[p + 1] as usize);
            if b < a + 2 {
                return Err(RenderError::Parent {
                    parent: p,
                    message: format!(
                        "has {} point(s); a parent needs at least 2",
                        b.saturating_sub(a)
                    ),
                });
            }
            let pts = &positions[a..b];
            if let Some(i) = pts.iter().position(|v| !v.iter().all(|c| c.is_finite())) {
                return Err(RenderError::Parent {
                    parent: p,
                    message: format!(
                        "point {i} has a non-finite coordinate; the simulation blew up or the \
                         cache is damaged"
                    ),
                });
            }
            if (pts[1] - pts[0]).norm_squared() <= 0.0 {
                return Err(RenderError::Parent {
                    parent: p,
                    message: "its first segment has zero length, so it has no direction; \
                              remove the duplicate root point"
                        .into(),
                });
            }
        }
        Ok(Self {
            positions,
            offsets,
            root_frames: None,
            scalp: None,
            spread: None,
            shape_factors: ShapeFactors::default(),
        })
    }

    /// Uses these root frames (one per parent, e.g. `StrandSet::root_frames(&scalp)`) for parents
    /// without a scalp sample.
    pub fn with_root_frames(mut self, frames: &'a [RootFrame]) -> Result<Self> {
        self.check_len("root frames", frames.len())?;
        if let Some(p) = frames
            .iter()
            .position(|f| !f.origin.iter().all(|c| c.is_finite()))
        {
            return Err(RenderError::Parent {
                parent: p,
                message: "its root frame has a non-finite origin".into(),
            });
        }
        self.root_frames = Some(frames);
        Ok(self)
    }

    /// Roots parents on `scalp`: a parent with a sample takes its root frame, UV (if the mesh has
    /// UVs) and color (if colors are given, one per mesh vertex) from the mesh.
    pub fn with_scalp(mut self, scalp: ScalpRoots<'a>) -> Result<Self> {
        self.check_len("scalp samples", scalp.samples.len())?;
        for (p, s) in scalp.samples.iter().enumerate() {
            if let Some(s) = s {
                s.validate(scalp.mesh).map_err(|e| RenderError::Parent {
                    parent: p,
                    message: e.to_string(),
                })?;
            }
        }
        if let Some(colors) = scalp.colors {
            let n = scalp.mesh.positions().len();
            if colors.len() != n {
                return Err(InputError::ScalpColors {
                    colors: colors.len(),
                    vertices: n,
                }
                .into());
            }
        }
        self.scalp = Some(scalp);
        Ok(self)
    }

    /// Per-parent spread radii (meters, finite, ≥ 0): the radius of the disc a parent's simple
    /// children are rooted in, overriding the setting's single radius.
    pub fn with_spread_radii(mut self, radii: &'a [f32]) -> Result<Self> {
        self.check_len("spread radii", radii.len())?;
        if let Some(p) = radii.iter().position(|r| !(r.is_finite() && *r >= 0.0)) {
            return Err(RenderError::Parent {
                parent: p,
                message: format!("spread radius {} m; give a finite value ≥ 0", radii[p]),
            });
        }
        self.spread = Some(radii);
        Ok(self)
    }

    /// Per-parent factors of the children's clump factor and curl radius (each in [0, 1]; see
    /// [`ShapeFactors`]). A factor of 1 leaves the children as without it, bit for bit; 0
    /// removes that parent's clumping or curl.
    pub fn with_shape_factors(mut self, factors: ShapeFactors<'a>) -> Result<Self> {
        for (what, per_parent, list) in [
            ("clump", "clump factors", factors.clump),
            ("curl", "curl factors", factors.curl),
        ] {
            let Some(list) = list else { continue };
            self.check_len(per_parent, list.len())?;
            if let Some(p) = list.iter().position(|f| !(0.0..=1.0).contains(f)) {
                return Err(RenderError::Parent {
                    parent: p,
                    message: format!("{what} factor {}; give a factor in [0, 1]", list[p]),
                });
            }
        }
        self.shape_factors = factors;
        Ok(self)
    }

    /// The shape of parent `p`'s children: `shape` with its clump factor and curl radius
    /// scaled by `p`'s factors.
    pub(crate) fn shape(&self, p: usize, shape: &Shape) -> Shape {
        let mut out = *shape;
        if let Some(f) = self.shape_factors.clump {
            out.clump.factor *= f[p];
        }
        if let Some(f) = self.shape_factors.curl {
            out.curl.radius *= f[p];
        }
        out
    }

    /// Number of parents.
    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Always false: [`Parents::new`] refuses an empty set.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Points of parent `p`, root first, meters.
    pub fn points(&self, p: usize) -> &'a [Vector3<f32>] {
        &self.positions[self.offsets[p] as usize..self.offsets[p + 1] as usize]
    }

    /// Spread radius of parent `p`: the per-parent radius if given, else `default` (meters).
    pub(crate) fn spread(&self, p: usize, default: f32) -> f32 {
        self.spread.map_or(default, |r| r[p])
    }

    /// True when root colors come from the scalp.
    pub(crate) fn has_colors(&self) -> bool {
        self.scalp.is_some_and(|s| s.colors.is_some())
    }

    /// True when root UVs come from the scalp.
    pub(crate) fn has_uvs(&self) -> bool {
        self.scalp.is_some_and(|s| s.mesh.uvs().is_some())
    }

    /// The scalp the parents are rooted on, if given.
    pub(crate) fn scalp(&self) -> Option<ScalpRoots<'a>> {
        self.scalp
    }

    /// Parent `p`'s mesh sample on the scalp, if it has one.
    pub(crate) fn sample(&self, p: usize) -> Option<MeshSample> {
        self.scalp.and_then(|s| s.samples[p])
    }

    /// Root frame and attributes of parent `p`.
    pub(crate) fn root(&self, p: usize) -> ParentRoot {
        if let (Some(scalp), Some(sample)) = (self.scalp, self.sample(p)) {
            return scalp.point(&sample);
        }
        let frame = match self.root_frames {
            Some(f) => f[p],
            None => {
                let pts = self.points(p);
                let t = (pts[1] - pts[0]).normalize();
                RootFrame::from_normal_and_edge(pts[0], t, any_perpendicular(&t))
            }
        };
        ParentRoot {
            frame,
            uv: None,
            color: None,
        }
    }

    fn check_len(&self, what: &'static str, n: usize) -> Result<()> {
        if n == self.len() {
            Ok(())
        } else {
            Err(InputError::PerParent {
                what,
                found: n,
                parents: self.len(),
            }
            .into())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_parents_are_named() {
        let pts = vec![
            Vector3::zeros(),
            Vector3::z(),
            Vector3::zeros(),
            Vector3::zeros(),
        ];
        let err = Parents::new(&pts, &[0, 2, 4]).unwrap_err().to_string();
        assert!(
            err.contains("parent 1") && err.contains("zero length"),
            "{err}"
        );
        let err = Parents::new(&pts, &[0, 1, 4]).unwrap_err().to_string();
        assert!(
            err.contains("parent 0") && err.contains("at least 2"),
            "{err}"
        );
        let err = Parents::new(&pts, &[0]).unwrap_err().to_string();
        assert!(err.contains("at least one parent"), "{err}");
        let nan = vec![Vector3::zeros(), Vector3::new(f32::NAN, 0.0, 1.0)];
        let err = Parents::new(&nan, &[0, 2]).unwrap_err().to_string();
        assert!(err.contains("non-finite"), "{err}");
    }

    #[test]
    fn shape_factors_outside_zero_to_one_or_of_the_wrong_count_are_named() {
        let pts = vec![
            Vector3::zeros(),
            Vector3::z(),
            Vector3::x(),
            Vector3::new(1.0, 0.0, 1.0),
        ];
        let parents = Parents::new(&pts, &[0, 2, 4]).unwrap();
        let err = parents
            .with_shape_factors(ShapeFactors {
                clump: Some(&[1.0, 1.5]),
                curl: None,
            })
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("parent 1") && err.contains("clump factor 1.5"),
            "{err}"
        );
        let err = parents
            .with_shape_factors(ShapeFactors {
                clump: None,
                curl: Some(&[0.5]),
            })
            .unwrap_err()
            .to_string();
        assert!(err.contains("1 curl factors for 2 parents"), "{err}");
        // Factors scale the setting's clump factor and curl radius per parent.
        let p = parents
            .with_shape_factors(ShapeFactors {
                clump: Some(&[0.0, 0.5]),
                curl: Some(&[1.0, 0.25]),
            })
            .unwrap();
        let mut shape = Shape::default();
        shape.clump.factor = 0.8;
        shape.curl.radius = 0.004;
        assert_eq!(p.shape(0, &shape).clump.factor, 0.0);
        assert_eq!(p.shape(0, &shape).curl.radius, 0.004);
        assert_eq!(p.shape(1, &shape).clump.factor, 0.4);
        assert_eq!(p.shape(1, &shape).curl.radius, 0.001);
    }

    #[test]
    fn root_frame_from_first_segment_has_z_along_it() {
        let pts = vec![Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0)];
        let parents = Parents::new(&pts, &[0, 2]).unwrap();
        let f = parents.root(0).frame;
        assert!((f.rotation * Vector3::z() - Vector3::x()).norm() < 1e-6);
    }
}
