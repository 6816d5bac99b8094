//! [`Shot`]: a cache opened for output. Every output (render children, the shot export, cards,
//! previews, quality reports) opens a cache through [`Shot::open`] and takes from it alone what
//! it needs beside the hair: how each strand is rooted, the rest scalp with its UVs and colours,
//! the scalp and the colliders at every frame (the cache's rig, [`hair_cache::rig`]), and the
//! scene's `[children]` and `[strips]` settings (the scene text stored in the cache, parsed, never
//! built). The scene's mesh files are not read again: a cache exports the same wherever it is
//! moved, and whatever became of the files that made it.
//!
//! Between frames (motion-blur samples) the scalp's body transform is interpolated linearly in
//! translation and spherically in rotation, and a deforming scalp's vertices linearly, between
//! the two frames around the sample; at a whole frame the scalp is exactly the one the frame was
//! simulated with.

use std::path::{Path, PathBuf};

use hair_cache::{CacheReader, CacheRig, ColliderState, RigFrame};
use hair_core::{Colliders, Scalp, StrandInput, StrandSet, TriMesh};
use nalgebra::{Isometry3, Vector3};

use crate::scene::SceneFile;

/// Why a cache cannot be used for output.
#[derive(Debug, thiserror::Error)]
pub enum ShotError {
    /// The cache cannot be read.
    #[error("{0}")]
    Cache(#[from] hair_cache::CacheError),
    /// The cache has no rig: it was written before caches carried one.
    #[error(
        "{path}: this cache has no rig (the scalp, roots and colliders outputs need), so it was \
         written by an older hairsys; simulate the scene again to export it"
    )]
    NoRig {
        /// The cache.
        path: PathBuf,
    },
    /// The scene stored in the cache (or given instead) cannot be parsed.
    #[error("{0}")]
    Scene(#[from] crate::scene::SceneError),
    /// The rig cannot be used as the library needs it: the solver refuses its scalp, a
    /// collider or a strand.
    #[error(
        "{path}: {}{source}",
        strand.map(|s| format!("strand {s}: ")).unwrap_or_default()
    )]
    Rig {
        /// The cache.
        path: PathBuf,
        /// The strand refused, if the error is about one.
        strand: Option<usize>,
        /// The solver's error.
        source: hair_core::HairError,
    },
}

/// A cache opened for output. See the module docs.
pub struct Shot {
    reader: CacheReader,
    rig: CacheRig,
    /// The scene settings outputs take (`[children]`, `[strips]`): the scene stored in the
    /// cache, or a scene file given instead; `None` for a cache a host wrote without one.
    scene: Option<SceneFile>,
    /// The strands as the rig roots them (rest shapes, masses, radii), at rest.
    strands: StrandSet,
    /// The last rig frame read: its number and state.
    last: Option<(u32, RigFrame)>,
}

impl Shot {
    /// Opens the cache at `path`; `scene`, when given, supplies the scene settings instead of
    /// the scene stored in the cache (paths in it are not read).
    pub fn open(path: &Path, scene: Option<&Path>) -> Result<Self, ShotError> {
        let reader = CacheReader::open(path)?;
        let Some(rig) = reader.rig().cloned() else {
            return Err(ShotError::NoRig {
                path: path.to_path_buf(),
            });
        };
        let scene = match scene {
            Some(file) => Some(SceneFile::load(file)?),
            None => {
                let text = &reader.header().scene_toml;
                if text.is_empty() {
                    None
                } else {
                    let origin = format!("{} (scene stored in the cache)", path.display());
                    Some(SceneFile::parse(text, &origin, PathBuf::new())?)
                }
            }
        };
        let strands = strands_of(&rig, &reader).map_err(|(strand, source)| ShotError::Rig {
            path: path.to_path_buf(),
            strand: Some(strand),
            source,
        })?;
        Ok(Self {
            reader,
            rig,
            scene,
            strands,
            last: None,
        })
    }

    /// The cache's reader (frames, samples, header, layout).
    pub fn reader(&mut self) -> &mut CacheReader {
        &mut self.reader
    }

    /// The cache's rig.
    pub fn rig(&self) -> &CacheRig {
        &self.rig
    }

    /// The scene whose settings outputs take, if there is one.
    pub fn scene(&self) -> Option<&SceneFile> {
        self.scene.as_ref()
    }

    /// The strands as the rig roots them, at rest (their positions are not the cache's).
    pub fn strands(&self) -> &StrandSet {
        &self.strands
    }

    /// The frames the cache holds, increasing.
    pub fn cached_frames(&self) -> &[u32] {
        self.reader.frame_numbers()
    }

    /// Frames per second of the cache.
    pub fn fps(&self) -> f64 {
        self.reader.header().fps
    }

    /// The rest scalp (body space), if the strands are rooted on one.
    pub fn rest_scalp(&self) -> Option<&TriMesh> {
        self.rig.scalp.as_ref().map(|s| &s.mesh)
    }

    /// The rig's state at stored frame `frame`.
    fn state(&mut self, frame: u32) -> Result<RigFrame, ShotError> {
        if let Some((f, state)) = &self.last {
            if *f == frame {
                return Ok(state.clone());
            }
        }
        let state = self
            .reader
            .read_rig_frame(frame)?
            .expect("a shot's cache has a rig");
        self.last = Some((frame, state.clone()));
        Ok(state)
    }

    /// The stored frames around (possibly fractional) `frame`, and how far between them it is.
    fn around(&self, frame: f64) -> (u32, u32, f32) {
        let frames = self.reader.frame_numbers();
        let (first, last) = (frames[0], frames[frames.len() - 1]);
        let f = frame.clamp(f64::from(first), f64::from(last));
        let a = frames[frames.partition_point(|&n| f64::from(n) <= f).max(1) - 1];
        let b = frames
            .get(frames.partition_point(|&n| f64::from(n) < f))
            .copied()
            .unwrap_or(a);
        let s = if b > a {
            ((f - f64::from(a)) / f64::from(b - a)) as f32
        } else {
            0.0
        };
        (a, b, s)
    }

    /// The rig's state at (possibly fractional) `frame`: a stored frame's exactly; between two,
    /// body transforms interpolated linearly in translation and spherically in rotation and
    /// deformed vertices linearly (see the module docs).
    fn state_at(&mut self, frame: f64) -> Result<RigFrame, ShotError> {
        let (a, b, s) = self.around(frame);
        let start = self.state(a)?;
        if s == 0.0 {
            return Ok(start);
        }
        let end = self.state(b)?;
        let blend = |p: Option<Vec<Vector3<f32>>>,
                     q: Option<Vec<Vector3<f32>>>,
                     rest: Option<&[Vector3<f32>]>| match (p, q, rest) {
            (None, None, _) | (_, _, None) => None,
            (p, q, Some(rest)) => {
                let p = p.as_deref().unwrap_or(rest);
                let q = q.as_deref().unwrap_or(rest);
                Some(p.iter().zip(q).map(|(x, y)| x.lerp(y, s)).collect())
            }
        };
        let scalp_vertices = blend(
            start.scalp_vertices,
            end.scalp_vertices,
            self.rest_scalp().map(|m| m.positions()),
        );
        let colliders = start
            .colliders
            .into_iter()
            .zip(end.colliders)
            .zip(&self.rig.colliders)
            .map(|((p, q), c)| {
                let rest = match &c.shape {
                    hair_core::ColliderShape::Mesh(m) => Some(m.positions()),
                    _ => None,
                };
                ColliderState {
                    pose: p.pose.lerp_slerp(&q.pose, s),
                    vertices: blend(p.vertices, q.vertices, rest),
                }
            })
            .collect();
        Ok(RigFrame {
            scalp_body: start.scalp_body.lerp_slerp(&end.scalp_body, s),
            scalp_vertices,
            colliders,
        })
    }

    /// The scalp at (possibly fractional) `frame`, as it was simulated (see the module docs).
    pub fn scalp_at(&mut self, frame: f64) -> Result<Scalp, ShotError> {
        if self.reader.frame_numbers().is_empty() {
            return Ok(Scalp {
                mesh: self.rest_scalp().cloned(),
                body: Isometry3::identity(),
            });
        }
        let state = self.state_at(frame)?;
        self.scalp_of(&state)
    }

    /// The scalp of the rig's `state`.
    fn scalp_of(&self, state: &RigFrame) -> Result<Scalp, ShotError> {
        let body = state.scalp_body;
        let mesh = match (self.rest_scalp(), &state.scalp_vertices) {
            (None, _) => None,
            (Some(rest), None) => Some(rest.transformed(&body)),
            (Some(rest), Some(v)) => {
                let mut m = rest.clone();
                m.set_positions(v).map_err(|e| self.rig_error(e))?;
                Some(m.transformed(&body))
            }
        };
        Ok(Scalp { mesh, body })
    }

    /// The colliders (the rig's, then the scalp as a collider when `with_scalp` is given with
    /// its thickness and friction) placed at (possibly fractional) `frame`, with no motion into
    /// it: for measuring a frame.
    pub fn colliders_at(
        &mut self,
        frame: f64,
        with_scalp: Option<(f32, f32)>,
    ) -> Result<Colliders, ShotError> {
        let state = self.state_at(frame)?;
        let mut set = Colliders::new();
        let err = |e: hair_core::HairError| self.rig_error(e);
        for (c, s) in self.rig.colliders.iter().zip(&state.colliders) {
            let id = set.insert(c.clone(), s.pose).map_err(err)?;
            if let Some(v) = &s.vertices {
                set.place_vertices(id, v).map_err(err)?;
            }
        }
        if let (Some((thickness, friction)), Some(rest)) = (with_scalp, self.rest_scalp()) {
            set.insert_scalp_rest(rest.clone(), state.scalp_body, thickness, friction)
                .map_err(err)?;
            if state.scalp_vertices.is_some() {
                let scalp = self.scalp_of(&state)?;
                set.place_scalp(&scalp).map_err(|e| self.rig_error(e))?;
            }
        }
        Ok(set)
    }

    /// Puts the colliders of `set` (made by [`Shot::colliders_at`]) at (possibly fractional)
    /// `frame`, with no motion into it: poses, deformed vertices and the scalp.
    pub fn place_colliders(&mut self, set: &mut Colliders, frame: f64) -> Result<(), ShotError> {
        let state = self.state_at(frame)?;
        for (i, s) in state.colliders.iter().enumerate() {
            let id = hair_core::ColliderId(i as u32);
            set.set_pose(id, s.pose).map_err(|e| self.rig_error(e))?;
            if let Some(v) = &s.vertices {
                set.place_vertices(id, v).map_err(|e| self.rig_error(e))?;
            }
        }
        let scalp = self.scalp_of(&state)?;
        set.place_scalp(&scalp).map_err(|e| self.rig_error(e))
    }

    /// Each rig collider's shape at (possibly fractional) `frame` (deformed where it deforms)
    /// and pose.
    pub fn collider_shapes_at(
        &mut self,
        frame: f64,
    ) -> Result<Vec<(hair_core::ColliderShape, Isometry3<f32>)>, ShotError> {
        let state = self.state_at(frame)?;
        let mut out = Vec::with_capacity(state.colliders.len());
        for (c, s) in self.rig.colliders.iter().zip(&state.colliders) {
            let shape = match (&c.shape, &s.vertices) {
                (hair_core::ColliderShape::Mesh(rest), Some(v)) => {
                    let mut m = rest.clone();
                    m.set_positions(v).map_err(|e| self.rig_error(e))?;
                    hair_core::ColliderShape::Mesh(m)
                }
                (shape, _) => shape.clone(),
            };
            out.push((shape, s.pose));
        }
        Ok(out)
    }

    /// The scalp collider's thickness (m) and friction, when the scalp collides with its hair.
    pub fn scalp_collider(&self) -> Option<(f32, f32)> {
        self.rig.scalp_collider
    }

    fn rig_error(&self, source: hair_core::HairError) -> ShotError {
        ShotError::Rig {
            path: self.reader.path().to_path_buf(),
            strand: None,
            source,
        }
    }
}

/// The strands the rig roots (rest shapes in their root frames, inverse masses, the layout's
/// radii and rest lengths), at rest on the rig's rest scalp. A strand the strand set refuses is
/// returned with its index.
fn strands_of(
    rig: &CacheRig,
    reader: &CacheReader,
) -> Result<StrandSet, (usize, hair_core::HairError)> {
    let layout = reader.layout();
    let mut strands = StrandSet::new();
    for (s, anchor) in rig.anchors.iter().enumerate() {
        let points = layout.offsets[s] as usize..layout.offsets[s + 1] as usize;
        let inverse = &rig.inverse_masses[points.clone()];
        let input = StrandInput {
            anchor: *anchor,
            rest: rig.rest_local[points.clone()].to_vec(),
            mass: inverse
                .iter()
                .map(|&w| if w > 0.0 { 1.0 / w } else { 1.0 })
                .collect(),
            radius: layout.radii[points.clone()].to_vec(),
            goal_weight: vec![0.0; points.len()],
            pinned: inverse.iter().map(|&w| w == 0.0).collect(),
        };
        strands.push(input).map_err(|e| (s, e))?;
    }
    // The run's rest lengths (sag-free initialisation sets them apart from the rest shape's).
    strands
        .rest_lengths_mut()
        .copy_from_slice(&layout.rest_lengths);
    let scalp = Scalp {
        mesh: rig.scalp.as_ref().map(|s| s.mesh.clone()),
        body: Isometry3::identity(),
    };
    strands.reset_to_rest(&scalp);
    Ok(strands)
}
