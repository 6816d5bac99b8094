//! Deforming meshes from files: a scalp or a mesh collider whose vertices come, frame by frame,
//! from a USD `Mesh` prim (time-sampled `points` and/or transforms; `kind = "usd"`) or a
//! numbered OBJ sequence (`kind = "obj-sequence"`, `path = "body.####.obj"`).
//!
//! ```toml
//! [scalp.mesh]
//! kind = "usd"
//! path = "character.usdc"   # .usd, .usda, .usdc or .usdz, relative to the scene file
//! prim = "/Character/body"  # a Mesh prim
//!
//! [[colliders]]
//! name = "body"
//! shape = { kind = "obj-sequence", path = "body.####.obj", scale = 0.01, up_axis = "y" }
//! ```
//!
//! # Frames and times
//! Scene frame `f` reads USD time code `time_offset + time_scale × f` (defaults 0 and 1: time
//! code `f`, as Blender writes one time code per frame) or the sequence's file numbered `f`. A
//! character animated on the shot's frames 1001–1048 runs in a scene of frames 1–48 with
//! `time_offset = 1000`; a stage with two time codes per frame takes `time_scale = 2` (USD's
//! layer-offset convention: stage time = offset + scale × scene time). The mesh at the scene's first frame (`[scene] frames[0]`) is
//! the **rest mesh**: hair is grown or snapped on it, and the collider is built from it. Every
//! frame of `[scene] frames` is read when the scene is built, so a missing frame, a topology
//! change or a time outside the stage's range is refused before any step, naming the file, the
//! prim and the frame; a run over other frames (`--frames`) must stay inside that range.
//! Between frames (sub-frame samples, previews at fractional frames) vertices are interpolated
//! linearly, the motion the contact model assumes within a frame (`hair_core::contacts`).
//!
//! # How the frames reach the solver
//! - Scalp: [`Simulation::scalp_at`](crate::build::Simulation::scalp_at) puts the frame's vertices on the rest mesh (then the
//!   scalp's rigid `[scalp.motion]`, if keyed, on top): roots are evaluated on their mesh samples
//!   of that mesh, and the scalp collider follows it (`Colliders::insert_scalp`'s deformation).
//! - Colliders: each frame's vertices are the collider's body-space vertices at the frame's end
//!   (`Colliders::set_vertices`), placed by its `[colliders.motion]`; the contact model takes
//!   the surface velocity from consecutive frames.
//! - Resuming: a set built at a later frame inserts the rest mesh and puts it at that frame's
//!   vertices (`Colliders::place_vertices`, `Colliders::place_scalp`), which gives the shape of
//!   the uninterrupted run to the bit (see `hair_core::contacts::deforming`).
//!
//! The scene hash (which guards `--resume`) covers the bytes of the USD file and of every
//! sequence file of the scene's frames. Layers a USD file references (sublayers, references)
//! are not hashed: edit the top file, or do not resume across such edits.

use std::path::{Path, PathBuf};

use hair_core::TriMesh;
use hair_groom::{ObjOptions, ObjSequence, UpAxis};
#[cfg(feature = "usd")]
use hair_groom::{UsdMeshOptions, UsdMeshSource};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::budget::{Budget, OverBudget};

/// `kind = "usd"`: a USD `Mesh` prim, read at every frame's time code.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UsdMeshSection {
    /// The stage (`.usd`, `.usda`, `.usdc`, `.usdz`), relative to the scene file.
    pub path: PathBuf,
    /// Path of the `Mesh` prim on the stage, e.g. `"/Character/body"`.
    pub prim: String,
    /// Meters per stage unit, replacing the stage's `metersPerUnit` (give `up_axis` too);
    /// absent = the stage's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<f32>,
    /// Up axis, `"y"` or `"z"`, replacing the stage's `upAxis` (give `scale` too); absent =
    /// the stage's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub up_axis: Option<UpAxis>,
    /// Time code read at scene frame 0, in time codes (finite): frame `f` reads time code
    /// `time_offset + time_scale × f`. Default 0.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub time_offset: f64,
    /// Time codes per scene frame (finite, > 0). Default 1.
    #[serde(default = "one_f64", skip_serializing_if = "is_one")]
    pub time_scale: f64,
}

impl UsdMeshSection {
    /// The prim and units to open the stage with.
    #[cfg(feature = "usd")]
    pub fn options(&self) -> UsdMeshOptions {
        let units = match (self.scale, self.up_axis) {
            (None, None) => None,
            (scale, up_axis) => Some(ObjOptions {
                scale: scale.unwrap_or(1.0),
                up_axis: up_axis.unwrap_or_default(),
            }),
        };
        UsdMeshOptions {
            prim: self.prim.clone(),
            units,
        }
    }

    /// The stage time code read at scene frame `frame`.
    pub fn time_code(&self, frame: f64) -> f64 {
        self.time_offset + self.time_scale * frame
    }

    /// Refuses a time offset or scale that maps frames to no usable time code.
    fn check_time_mapping(&self) -> Result<(), DeformingError> {
        if !self.time_offset.is_finite() {
            return Err(DeformingError::TimeOffset {
                path: self.path.clone(),
                time_offset: self.time_offset,
            });
        }
        if !(self.time_scale.is_finite() && self.time_scale > 0.0) {
            return Err(DeformingError::TimeScale {
                path: self.path.clone(),
                time_scale: self.time_scale,
            });
        }
        Ok(())
    }
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

fn is_one(x: &f64) -> bool {
    *x == 1.0
}

fn one_f64() -> f64 {
    1.0
}

/// `kind = "obj-sequence"`: one OBJ file per frame, `path = "body.####.obj"`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjSequenceSection {
    /// The pattern, relative to the scene file: one run of `#` stands for the zero-padded
    /// frame number.
    pub path: PathBuf,
    /// Multiplier from file units to meters.
    #[serde(default = "one")]
    pub scale: f32,
    /// The files' up axis: `"z"` (default) or `"y"` (converted to Z up).
    #[serde(default)]
    pub up_axis: UpAxis,
}

fn one() -> f32 {
    1.0
}

/// A deforming mesh source of a scene: what the file says, before it is read.
#[derive(Debug, Clone, Copy)]
pub enum DeformingSource<'a> {
    /// A USD `Mesh` prim.
    Usd(&'a UsdMeshSection),
    /// A numbered OBJ sequence.
    ObjSequence(&'a ObjSequenceSection),
}

/// The vertices of a deforming mesh at every frame of a scene, in the order of its rest mesh
/// (m, Z up; world space for USD, the files' space for OBJ).
#[derive(Debug, Clone)]
pub struct MeshAnimation {
    /// The source in words (`character.usdc prim /Character/body`), for messages.
    pub source: String,
    /// Frame of the first entry of `frames` (the rest frame).
    first: u32,
    /// Vertices per frame, `first`, `first + 1`, ….
    frames: Vec<Vec<Vector3<f32>>>,
}

impl MeshAnimation {
    /// First and last frame held.
    pub fn frames(&self) -> (u32, u32) {
        (self.first, self.first + self.frames.len() as u32 - 1)
    }

    /// The vertices at (possibly fractional) `frame`: the frame's own at a whole frame, a
    /// linear blend between the two nearest frames between them; held before the first and
    /// after the last.
    pub fn vertices_at(&self, frame: f32) -> Vec<Vector3<f32>> {
        let (first, last) = self.frames();
        let f = frame.clamp(first as f32, last as f32) - first as f32;
        let i = (f.floor() as usize).min(self.frames.len() - 1);
        let s = f - i as f32;
        let a = &self.frames[i];
        if s == 0.0 || i + 1 == self.frames.len() {
            return a.clone();
        }
        let b = &self.frames[i + 1];
        let blend: Vec<Vector3<f32>> = a.iter().zip(b).map(|(p, q)| p.lerp(q, s)).collect();
        // Finite inputs can overflow in the blend only near f32::MAX; hold the frame then.
        if blend.iter().all(|v| v.iter().all(|c| c.is_finite())) {
            blend
        } else {
            a.clone()
        }
    }

    /// The fastest any vertex moves between two consecutive frames, times `fps` (frames per
    /// second): the deformation's largest speed, m/s (0 for a single frame).
    pub fn fastest_vertex_speed(&self, fps: f64) -> f64 {
        let moved = self
            .frames
            .windows(2)
            .flat_map(|w| w[0].iter().zip(&w[1]).map(|(a, b)| (b - a).norm()))
            .fold(0.0f32, f32::max);
        f64::from(moved) * fps
    }

    /// Refuses a run over `first..=last` that leaves the frames read, naming the source.
    pub fn check_covers(&self, first: u32, last: u32) -> Result<(), FramesNotRead> {
        let (lo, hi) = self.frames();
        if first < lo || last > hi {
            return Err(FramesNotRead {
                mesh: self.source.clone(),
                read: (lo, hi),
                run: (first, last),
            });
        }
        Ok(())
    }
}

/// Reads a deforming source for frames `first..=last`: the rest mesh (at `first`) and the
/// vertices of every frame. Errors name the file, the prim and the frame; the memory held
/// (frames × vertices) is checked against `budget` after the rest frame is read.
pub fn load(
    source: DeformingSource<'_>,
    base_dir: &Path,
    (first, last): (u32, u32),
    budget: &Budget,
) -> Result<(TriMesh, MeshAnimation), DeformingError> {
    let frames = u64::from(last - first) + 1;
    let check = |vertices: usize, what: &str| {
        budget.check_points(
            &format!("{what}: {frames} frames × {vertices} vertices"),
            frames as f64 * vertices as f64,
        )
    };
    match source {
        #[cfg(not(feature = "usd"))]
        DeformingSource::Usd(s) => {
            s.check_time_mapping()?;
            Err(hair_groom::GroomError::usd_not_built(&base_dir.join(&s.path)).into())
        }
        #[cfg(feature = "usd")]
        DeformingSource::Usd(s) => {
            s.check_time_mapping()?;
            let path = base_dir.join(&s.path);
            let usd = UsdMeshSource::open(&path, &s.options())?;
            let what = format!("{} prim {}", s.path.display(), usd.prim());
            let at = |f: u32| s.time_code(f64::from(f));
            let rest = usd.mesh_at(at(first))?;
            check(rest.positions().len(), &what)?;
            let mut out = vec![rest.positions().to_vec()];
            for f in first + 1..=last {
                out.push(usd.positions_at(at(f))?);
            }
            Ok((rest, animation(what, first, out)))
        }
        DeformingSource::ObjSequence(s) => {
            let seq = ObjSequence::new(
                &base_dir.join(&s.path),
                ObjOptions {
                    scale: s.scale,
                    up_axis: s.up_axis,
                },
            )?;
            let what = format!("the sequence {}", s.path.display());
            let rest = seq.mesh_at(first)?;
            check(rest.positions().len(), &what)?;
            let mut out = vec![rest.positions().to_vec()];
            for f in first + 1..=last {
                out.push(seq.positions_at(f, &rest, first)?);
            }
            Ok((rest, animation(what, first, out)))
        }
    }
}

fn animation(source: String, first: u32, frames: Vec<Vec<Vector3<f32>>>) -> MeshAnimation {
    MeshAnimation {
        source,
        first,
        frames,
    }
}

/// The files whose bytes the scene hash covers for `source` over frames `first..=last`: the
/// USD file, or every sequence file of those frames.
pub fn hashed_files(
    source: DeformingSource<'_>,
    base_dir: &Path,
    (first, last): (u32, u32),
) -> Result<Vec<PathBuf>, DeformingError> {
    Ok(match source {
        DeformingSource::Usd(s) => vec![base_dir.join(&s.path)],
        DeformingSource::ObjSequence(s) => {
            let seq = ObjSequence::new(&base_dir.join(&s.path), ObjOptions::default())?;
            (first..=last).map(|f| seq.frame_path(f)).collect()
        }
    })
}

/// Why a deforming mesh cannot be read for a run; the caller names the section.
#[derive(Debug, thiserror::Error)]
pub enum DeformingError {
    /// `time_offset` is not finite.
    #[error(
        "{}: time_offset = {time_offset}: give a finite number of time codes, e.g. 1000 for a \
         character animated from frame 1001 in a scene starting at frame 1",
        path.display()
    )]
    TimeOffset {
        /// The USD file, as the scene names it.
        path: PathBuf,
        /// The value given.
        time_offset: f64,
    },
    /// `time_scale` is not a finite number > 0.
    #[error(
        "{}: time_scale = {time_scale}: give the time codes per scene frame, a finite number > 0 \
         (1 when the stage has one time code per frame)",
        path.display()
    )]
    TimeScale {
        /// The USD file, as the scene names it.
        path: PathBuf,
        /// The value given.
        time_scale: f64,
    },
    /// The file, the prim or a frame's points cannot be read.
    #[error("{0}")]
    Read(#[from] hair_groom::GroomError),
    /// Every frame's vertices together are over the memory budget.
    #[error("{0}")]
    Budget(#[from] OverBudget),
}

/// A run asks for frames a deforming mesh was not read for.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "{mesh} is read for the scene's frames {}–{} ([scene] frames), not {}–{}; widen [scene] \
     frames (the mesh must have every frame of the run)",
    .read.0, .read.1, .run.0, .run.1
)]
pub struct FramesNotRead {
    /// The mesh, in words (file and prim, or the sequence).
    pub mesh: String,
    /// The first and last frame it was read for.
    pub read: (u32, u32),
    /// The first and last frame of the run.
    pub run: (u32, u32),
}

/// A run over frames a deforming scalp or collider was not read for
/// ([`crate::build::Simulation::check_deforming_frames`]).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{field}: {source}")]
pub struct DeformingFrames {
    /// The section (`[scalp.mesh]`, `[[colliders]] #i (name)`).
    pub field: String,
    /// The frames asked for and read.
    pub source: FramesNotRead,
}

#[cfg(all(test, feature = "usd"))]
mod tests {
    use super::*;
    use hair_groom::formats::usd_write::{Samples, UsdLayer, UsdMeshPrim, UsdStageInfo};

    /// A one-triangle mesh whose vertices rise by 0.1 m per time code, written with time samples
    /// at `first..first + 3`.
    fn rising_triangle(path: &Path, first: f64) {
        let mut layer = UsdLayer::new(&UsdStageInfo {
            up_axis: UpAxis::Z,
            meters_per_unit: 1.0,
            time_codes_per_second: Some(24.0),
            time_range: Some((first, first + 3.0)),
        });
        let at = |k: f64| {
            let z = 0.1 * k as f32;
            vec![0.0, 0.0, z, 1.0, 0.0, z, 0.0, 1.0, z]
        };
        layer.add_mesh(UsdMeshPrim {
            name: "body",
            face_vertex_counts: vec![3],
            face_vertex_indices: vec![0, 1, 2],
            points: Samples::Times((0..4).map(|k| (first + k as f64, at(k as f64))).collect()),
            uv: None,
            colors: None,
        });
        layer.write(path).unwrap();
    }

    fn section(path: &str, time_offset: f64, time_scale: f64) -> UsdMeshSection {
        UsdMeshSection {
            path: path.into(),
            prim: "/body".into(),
            scale: None,
            up_axis: None,
            time_offset,
            time_scale,
        }
    }

    fn heights(s: &UsdMeshSection, dir: &Path, frames: (u32, u32)) -> Vec<f32> {
        let (_, anim) = load(DeformingSource::Usd(s), dir, frames, &Budget::default()).unwrap();
        (frames.0..=frames.1)
            .map(|f| anim.vertices_at(f as f32)[0].z)
            .collect()
    }

    #[test]
    fn a_shot_animated_from_frame_1001_runs_on_scene_frames_1_to_4_with_a_time_offset() {
        let dir = tempfile::tempdir().unwrap();
        rising_triangle(&dir.path().join("shot.usdc"), 1001.0);
        rising_triangle(&dir.path().join("plain.usda"), 1.0);
        let offset = heights(&section("shot.usdc", 1000.0, 1.0), dir.path(), (1, 4));
        let plain = heights(&section("plain.usda", 0.0, 1.0), dir.path(), (1, 4));
        assert_eq!(offset, plain);
        assert_eq!(offset, vec![0.0, 0.1, 0.2, 0.3]);
        // Two time codes per scene frame: frames 1001, 1002 read time codes 1001 and 1003.
        let halves = heights(
            &section("shot.usdc", -1001.0, 2.0),
            dir.path(),
            (1001, 1002),
        );
        assert_eq!(halves, vec![0.0, 0.2]);
        // Without the offset the shot's time codes are outside scene frames 1–4: refused.
        let e = load(
            DeformingSource::Usd(&section("shot.usdc", 0.0, 1.0)),
            dir.path(),
            (1, 4),
            &Budget::default(),
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("shot.usdc"), "{e}");
    }

    #[test]
    fn a_time_scale_that_maps_frames_to_no_time_code_is_refused_naming_the_key() {
        let dir = tempfile::tempdir().unwrap();
        rising_triangle(&dir.path().join("shot.usdc"), 1.0);
        for (offset, scale, key) in [
            (0.0, 0.0, "time_scale"),
            (0.0, f64::NAN, "time_scale"),
            (f64::INFINITY, 1.0, "time_offset"),
        ] {
            let s = section("shot.usdc", offset, scale);
            let e = load(
                DeformingSource::Usd(&s),
                dir.path(),
                (1, 2),
                &Budget::default(),
            )
            .unwrap_err()
            .to_string();
            assert!(e.contains("shot.usdc") && e.contains(key), "{e}");
        }
    }
}
