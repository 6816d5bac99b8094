//! Scene keys of animated guides (seed 001, "Hair Levels"): keyed guide poses
//! (`[[guides.pose]]`), the sim weight curve that hands the shot between simulation and the
//! animated guides (`[guides.sim_weight]`), pinned points (`[[guides.pin]]`) and hold-out
//! hair that follows the guides exactly (`[guides.hold_out]`). Hair is selected by guide (the
//! sim hairs whose nearest guide is listed), by sim-hair index, by a cone of root normals on
//! the scalp at rest, or by a painted map's value at the root (`map = { name, min, max }`,
//! see [`crate::scene::maps`]); a `[maps.sim_weight]` paints each sim hair's factor of the
//! sim weight curve.
//!
//! This module parses and checks the keys and turns them into an
//! [`crate::rig::animated_guides::GuideAnimation`]; applying it each frame is the runtime's.

use std::path::{Path, PathBuf};

use hair_core::{RootFrame, StrandInput, TriMesh};
use hair_groom::{GuideBlend, SimHair};
use nalgebra::{UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::rig::animated_guides::{GuideAnimation, PoseKey, PoseLift, WeightCurve};
use crate::scene::guides::ReadGuidesError;
use crate::scene::maps::{MapSelection, MapsError, ScalpMaps};
use crate::scene::motion::Interpolation;
use crate::scene::RegionSection;

/// `[[guides.pose]]`: the guides' shape at one frame. Give `file` (a groom with the same guides,
/// in the same order and point counts, in the scene's space), or `sweep` (the groom bent
/// towards a direction), or neither (the groom itself: a key that hands the pose back).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoseSection {
    /// Frame of the key (fractional allowed).
    pub frame: f32,
    /// Groom file of the posed guides (.hair, .tfx, .obj polylines, .usd*), relative to the scene
    /// file, read with `[guides]`'s `prim`, `scale` and `up_axis`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<PathBuf>,
    /// USD files: the time code whose samples are read (absent: the earliest sample or default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<f64>,
    /// The groom swept towards a direction, most at the tips.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sweep: Option<SweepSection>,
}

/// A procedural pose: every segment of every guide turned towards `direction` by an angle that
/// grows linearly from 0 at the root to `angle_deg` at the tip (lengths kept: a gust's bend).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSection {
    /// World direction the hair is swept towards (any non-zero length).
    pub direction: [f32; 3],
    /// Turn at the tip, degrees, in [0, 180].
    pub angle_deg: f32,
}

/// Which sim hairs a setting applies to: the union of the hairs whose nearest guide is in
/// `guides`, the sim hairs numbered in `strands` (0 = the first sim hair), the hairs rooted
/// where the scalp's normal at rest lies within `region`, and those where a painted map's value
/// at the root lies within `map`'s bounds.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HairSelection {
    /// Guide indices.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub guides: Option<Vec<usize>>,
    /// Sim-hair indices.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub strands: Option<Vec<usize>>,
    /// A cone of root normals.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub region: Option<RegionSection>,
    /// A painted map's range.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub map: Option<MapSelection>,
}

impl HairSelection {
    /// True when the selection gives no criterion at all.
    pub fn is_empty(&self) -> bool {
        self.guides.is_none()
            && self.strands.is_none()
            && self.region.is_none()
            && self.map.is_none()
    }
}

/// One key of the sim weight curve.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WeightKey {
    /// Frame of the key.
    pub frame: f32,
    /// Sim weight in [0, 1].
    pub value: f32,
}

/// `[guides.sim_weight]`: how far the selected sim hairs are moved onto the animated guides
/// after each frame's simulation: 0 = pure simulation, 1 = exactly the animated guides (positions
/// and velocities), in between a blend. Keys over frames; absent selection: every sim hair.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimWeightSection {
    /// Interpolation between keys (`"ease"` or `"linear"`).
    #[serde(default)]
    pub interpolation: Interpolation,
    /// Keys in increasing frame order; the curve holds before the first and after the last.
    pub keys: Vec<WeightKey>,
    /// The hair the curve acts on (absent: every sim hair).
    #[serde(default, flatten)]
    pub select: HairSelection,
}

/// `[[guides.pin]]`: points of the selected sim hairs held on the animated guides (kinematic).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PinSection {
    /// Point indices from the root (absent: every point).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub points: Option<Vec<usize>>,
    /// The hair pinned.
    #[serde(flatten)]
    pub select: HairSelection,
}

/// The animation keys of `[guides]`, as read from the scene.
#[derive(Debug, Clone, Copy)]
pub struct AnimationKeys<'a> {
    /// `[[guides.pose]]`.
    pub poses: &'a [PoseSection],
    /// `[guides] pose_interpolation`.
    pub interpolation: Interpolation,
    /// `[guides] pose_clearance`, m.
    pub clearance: Option<f32>,
    /// `[guides.sim_weight]`.
    pub sim_weight: Option<&'a SimWeightSection>,
    /// `[[guides.pin]]`.
    pub pins: &'a [PinSection],
    /// `[guides.hold_out]`.
    pub hold_out: Option<&'a HairSelection>,
}

impl<'a> AnimationKeys<'a> {
    /// The names of the maps the selections use.
    pub fn map_names(&self) -> Vec<&'a str> {
        let selections = self
            .sim_weight
            .map(|w| &w.select)
            .into_iter()
            .chain(self.pins.iter().map(|p| &p.select))
            .chain(self.hold_out);
        selections
            .filter_map(|s| s.map.as_ref().map(|m| m.name.as_str()))
            .collect()
    }

    /// True when any key is given (otherwise guides stay a static groom, at no cost).
    pub fn any(&self) -> bool {
        !self.poses.is_empty()
            || self.sim_weight.is_some()
            || !self.pins.is_empty()
            || self.hold_out.is_some()
    }
}

/// Reads a pose file into root-local guide shapes. `read` reads the file as `[guides] file` is.
pub type PoseReader<'a> =
    dyn Fn(&Path, Option<f64>) -> Result<Vec<Vec<Vector3<f32>>>, ReadGuidesError> + 'a;

/// Everything animated guides need, built: pins and hold-outs are set on `inputs` (the sim
/// hairs, before they join the strand set, already trimmed to `fractions`, their painted
/// lengths, if any); the returned animation drives the rest, re-blending each hair trimmed to
/// its fraction.
#[allow(clippy::too_many_arguments)]
pub fn build(
    keys: &AnimationKeys,
    mesh: &TriMesh,
    guides: &[hair_groom::Guide],
    hairs: &[SimHair],
    inputs: &mut [StrandInput],
    points: usize,
    fractions: Option<Vec<f32>>,
    max_snap_distance: f32,
    maps: &ScalpMaps,
    read: &PoseReader,
) -> Result<GuideAnimation, GuideAnimError> {
    let mut blend = GuideBlend::new(mesh, guides, hairs, points).map_err(GuideAnimError::Blend)?;
    if let Some(fractions) = fractions {
        blend = blend
            .with_length_fractions(fractions)
            .map_err(GuideAnimError::LengthFractions)?;
    }
    let frames: Vec<RootFrame> = guides.iter().map(|g| mesh.evaluate(&g.root)).collect();
    let groom: Vec<Vec<Vector3<f32>>> = guides.iter().map(|g| g.rest.clone()).collect();
    let mut poses = Vec::with_capacity(keys.poses.len());
    for (i, key) in keys.poses.iter().enumerate() {
        let pose = PoseName {
            index: i,
            frame: key.frame,
        };
        if !key.frame.is_finite() {
            return Err(GuideAnimError::PoseFrame { pose });
        }
        if i > 0 && key.frame <= keys.poses[i - 1].frame {
            return Err(GuideAnimError::PoseOrder {
                pose,
                previous: keys.poses[i - 1].frame,
            });
        }
        if key.time.is_some() && key.file.is_none() {
            return Err(GuideAnimError::TimeWithoutFile { pose });
        }
        let shapes = match (&key.file, &key.sweep) {
            (Some(_), Some(_)) => {
                return Err(GuideAnimError::FileAndSweep { pose });
            }
            (Some(file), None) => {
                let world = read(file, key.time).map_err(|source| GuideAnimError::PoseFile {
                    pose,
                    file: file.clone(),
                    source: Box::new(source),
                })?;
                to_root_local(&world, &frames, max_snap_distance, pose, file)?
            }
            (None, Some(sweep)) => swept(&groom, &frames, sweep, pose)?,
            (None, None) => groom.clone(),
        };
        blend.check_pose(&shapes, &pose.to_string())?;
        poses.push(PoseKey {
            frame: key.frame,
            shapes,
        });
    }
    let lift = match keys.clearance {
        None => None,
        Some(c) if c.is_finite() && c >= 0.0 => {
            Some(PoseLift::new(mesh, c).map_err(GuideAnimError::PoseLift)?)
        }
        Some(c) => return Err(GuideAnimError::PoseClearance { value: c }),
    };
    let hair_count = hairs.len();
    let select = |s: &HairSelection, what: &str| -> Result<Vec<bool>, SelectionError> {
        selection(s, what, mesh, guides.len(), hairs, maps)
    };
    // Each hair's factor of the sim weight: every hair by default (the curve is then 0, but a
    // host's `set_sim_weight` reaches all hair), only the selected ones under a selection.
    let mut sim_factor = vec![1.0f32; hair_count];
    let curve = match keys.sim_weight {
        None if maps.get("sim_weight").is_some() => {
            return Err(MapsError::SimWeightWithoutCurve.into())
        }
        None => WeightCurve::default(),
        Some(w) => {
            let what = "[guides.sim_weight]";
            if w.keys.is_empty() {
                return Err(GuideAnimError::SimWeightNoKeys);
            }
            for (i, k) in w.keys.iter().enumerate() {
                if !(k.frame.is_finite() && k.value.is_finite() && (0.0..=1.0).contains(&k.value)) {
                    return Err(GuideAnimError::SimWeightValue {
                        key: i,
                        value: k.value,
                        frame: k.frame,
                    });
                }
                if i > 0 && k.frame <= w.keys[i - 1].frame {
                    return Err(GuideAnimError::SimWeightOrder {
                        key: i,
                        frame: k.frame,
                        previous: w.keys[i - 1].frame,
                    });
                }
            }
            let chosen = if w.select.is_empty() {
                vec![true; hair_count]
            } else {
                select(&w.select, what)?
            };
            for (f, c) in sim_factor.iter_mut().zip(chosen) {
                *f = if c { 1.0 } else { 0.0 };
            }
            if let Some(map) = maps.get("sim_weight") {
                for (i, (f, h)) in sim_factor.iter_mut().zip(hairs).enumerate() {
                    let v = map
                        .at(mesh, &h.root, &format!("sim hair {i}"))
                        .map_err(MapsError::Map)?;
                    if !(0.0..=1.0).contains(&v) {
                        return Err(MapsError::SimWeightFactor { value: v, hair: i }.into());
                    }
                    *f *= v;
                }
            }
            WeightCurve::new(
                w.interpolation,
                w.keys.iter().map(|k| (k.frame, k.value)).collect(),
            )
        }
    };
    for (i, pin) in keys.pins.iter().enumerate() {
        let what = format!("[[guides.pin]] #{i}");
        if pin.select.is_empty() {
            return Err(SelectionError::Nothing { selection: what }.into());
        }
        let chosen = select(&pin.select, &what)?;
        if let Some(p) = pin
            .points
            .as_ref()
            .and_then(|p| p.iter().find(|&&p| p >= points))
        {
            return Err(GuideAnimError::PinPoint {
                pin: i,
                point: *p,
                points,
            });
        }
        for (input, _) in inputs.iter_mut().zip(&chosen).filter(|(_, &c)| c) {
            match &pin.points {
                None => input.pinned.iter_mut().for_each(|p| *p = true),
                Some(list) => list.iter().for_each(|&p| input.pinned[p] = true),
            }
        }
    }
    let mut hold_out = vec![false; hair_count];
    if let Some(h) = keys.hold_out {
        let what = "[guides.hold_out]";
        if h.is_empty() {
            return Err(SelectionError::Nothing {
                selection: what.to_string(),
            }
            .into());
        }
        hold_out = select(h, what)?;
        for (input, _) in inputs.iter_mut().zip(&hold_out).filter(|(_, &c)| c) {
            input.pinned.iter_mut().for_each(|p| *p = true);
        }
    }
    Ok(GuideAnimation::new(
        blend,
        frames,
        groom,
        poses,
        keys.interpolation,
        curve,
        sim_factor,
        hold_out,
        lift,
    ))
}

/// The sim hairs `s` selects; errors name `what`, the bad index and the fix, or say that the
/// selection names no hair.
fn selection(
    s: &HairSelection,
    what: &str,
    mesh: &TriMesh,
    guide_count: usize,
    hairs: &[SimHair],
    maps: &ScalpMaps,
) -> Result<Vec<bool>, SelectionError> {
    let mut chosen = vec![false; hairs.len()];
    let selection = || what.to_string();
    if let Some(list) = &s.guides {
        let mut wanted = vec![false; guide_count];
        for &g in list {
            *wanted.get_mut(g).ok_or_else(|| SelectionError::Guide {
                selection: selection(),
                guide: g,
                count: guide_count,
            })? = true;
        }
        for (c, h) in chosen.iter_mut().zip(hairs) {
            *c |= h.sources.first().is_some_and(|s| wanted[s.guide]);
        }
    }
    if let Some(list) = &s.strands {
        for &i in list {
            *chosen.get_mut(i).ok_or_else(|| SelectionError::SimHair {
                selection: selection(),
                hair: i,
                count: hairs.len(),
            })? = true;
        }
    }
    if let Some(r) = &s.region {
        let (axis, cos) = r.cone(what)?;
        for (c, h) in chosen.iter_mut().zip(hairs) {
            let normal = mesh.evaluate(&h.root).rotation * Vector3::z();
            *c |= normal.dot(&axis) >= cos;
        }
    }
    if let Some(m) = &s.map {
        let map = maps.selected(m, what)?;
        for (i, (c, h)) in chosen.iter_mut().zip(hairs).enumerate() {
            *c |= m.contains(
                map.at(mesh, &h.root, &format!("sim hair {i}"))
                    .map_err(MapsError::Map)?,
            );
        }
    }
    if !chosen.iter().any(|&c| c) {
        return Err(SelectionError::NoHair {
            selection: selection(),
            hairs: "sim hair",
        });
    }
    Ok(chosen)
}

/// World (scene-space) posed guides to root-local shapes in the groom's guide frames. Each pose
/// keeps its root within `tolerance` m of the guide's root (the pose is translated onto it).
fn to_root_local(
    world: &[Vec<Vector3<f32>>],
    frames: &[RootFrame],
    tolerance: f32,
    pose: PoseName,
    file: &Path,
) -> Result<Vec<Vec<Vector3<f32>>>, GuideAnimError> {
    if world.len() != frames.len() {
        return Err(GuideAnimError::PoseGuides {
            pose,
            file: file.to_path_buf(),
            given: world.len(),
            guides: frames.len(),
        });
    }
    world
        .iter()
        .zip(frames)
        .enumerate()
        .map(|(g, (curve, frame))| {
            let root = curve[0];
            let off = (root - frame.origin).norm();
            if off > tolerance {
                return Err(GuideAnimError::PoseRoot {
                    pose,
                    file: file.to_path_buf(),
                    guide: g,
                    distance: off,
                    tolerance,
                });
            }
            let inv = frame.rotation.inverse();
            Ok(curve.iter().map(|p| inv * (p - root)).collect())
        })
        .collect()
}

/// The groom (root-local shapes in `frames`) swept by `sweep`.
fn swept(
    groom: &[Vec<Vector3<f32>>],
    frames: &[RootFrame],
    sweep: &SweepSection,
    pose: PoseName,
) -> Result<Vec<Vec<Vector3<f32>>>, GuideAnimError> {
    let dir = Vector3::from(sweep.direction);
    if !(dir.iter().all(|c| c.is_finite()) && dir.norm() > 0.0) {
        return Err(GuideAnimError::SweepDirection {
            pose,
            direction: sweep.direction,
        });
    }
    if !(sweep.angle_deg.is_finite() && (0.0..=180.0).contains(&sweep.angle_deg)) {
        return Err(GuideAnimError::SweepAngle {
            pose,
            angle_deg: sweep.angle_deg,
        });
    }
    let dir = dir.normalize();
    Ok(groom
        .iter()
        .zip(frames)
        .map(|(shape, frame)| {
            let world: Vec<Vector3<f32>> = shape.iter().map(|p| frame.rotation * p).collect();
            let span = world[world.len() - 1] - world[0];
            // Turn about the axis taking the guide's chord towards the direction.
            let axis = span.cross(&dir);
            let Some(axis) = nalgebra::Unit::try_new(axis, 1e-9) else {
                return shape.clone();
            };
            let segments = world.len() - 1;
            let mut out = Vec::with_capacity(world.len());
            let mut p = world[0];
            out.push(p);
            for j in 0..segments {
                let s = (j as f32 + 0.5) / segments as f32;
                let turn = UnitQuaternion::from_axis_angle(&axis, s * sweep.angle_deg.to_radians());
                p += turn * (world[j + 1] - world[j]);
                out.push(p);
            }
            let inv = frame.rotation.inverse();
            out.iter().map(|p| inv * p).collect()
        })
        .collect())
}
/// A `[[guides.pose]]` key as messages name it: `[[guides.pose]] #i (frame f)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseName {
    /// The key's index in `[[guides.pose]]`.
    pub index: usize,
    /// Its frame.
    pub frame: f32,
}

impl std::fmt::Display for PoseName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "[[guides.pose]] #{} (frame {})", self.index, self.frame)
    }
}

/// Why a selection of hair (`guides`, `strands`, `region`, `map` in `[guides.sim_weight]`,
/// `[[guides.pin]]`, `[guides.hold_out]` or `[[regions]]`) is refused. `selection` names the
/// selecting section as messages show it.
#[derive(Debug, thiserror::Error)]
pub enum SelectionError {
    /// The selection gives none of `guides`, `strands`, `region` and `map`.
    #[error("{selection} selects no hair: give `guides`, `strands`, `region` or `map`")]
    Nothing {
        /// The selecting section.
        selection: String,
    },
    /// `guides` in a scene without guides.
    #[error(
        "{selection} guides: the scene has no [guides]; select by `strands`, `region` or `map`"
    )]
    NoGuides {
        /// The selecting section.
        selection: String,
    },
    /// `guides` names a guide that does not exist.
    #[error(
        "{selection} guides names guide {guide}, but there are {count} guides (0–{})",
        .count.saturating_sub(1)
    )]
    Guide {
        /// The selecting section.
        selection: String,
        /// The guide named.
        guide: usize,
        /// The guides there are.
        count: usize,
    },
    /// `strands` names a strand the run does not have.
    #[error(
        "{selection} strands names strand {strand}, but the run has {count} strands (0–{})",
        .count.saturating_sub(1)
    )]
    Strand {
        /// The selecting section.
        selection: String,
        /// The strand named.
        strand: usize,
        /// The run's strands.
        count: usize,
    },
    /// `strands` names a sim hair that does not exist.
    #[error(
        "{selection} strands names sim hair {hair}, but there are {count} sim hairs (0–{})",
        .count.saturating_sub(1)
    )]
    SimHair {
        /// The selecting section.
        selection: String,
        /// The sim hair named.
        hair: usize,
        /// The sim hairs there are.
        count: usize,
    },
    /// The `region` cone has no direction or its angle is out of range.
    #[error("{selection} region: give a non-zero direction and max_angle_deg in [0, 180]")]
    Cone {
        /// The selecting section.
        selection: String,
        /// The direction given.
        direction: [f32; 3],
        /// The half-angle given, degrees.
        max_angle_deg: f32,
    },
    /// `region` on hair without a scalp mesh.
    #[error("{selection} region: a cone of root normals needs a scalp mesh; select by `strands`")]
    RegionWithoutScalp {
        /// The selecting section.
        selection: String,
    },
    /// `map` on hair without a scalp mesh.
    #[error("{selection} map: a painted map needs a scalp mesh")]
    MapWithoutScalp {
        /// The selecting section.
        selection: String,
    },
    /// The map cannot be selected by or sampled.
    #[error("{0}")]
    Map(Box<MapsError>),
    /// Nothing matches the selection.
    #[error(
        "{selection} names no hair: no {hairs} matches its guides, strands, region or map; \
         widen the selection"
    )]
    NoHair {
        /// The selecting section.
        selection: String,
        /// What was searched: `"strand"` or `"sim hair"`.
        hairs: &'static str,
    },
}

/// Why the animated guides' keys (`[[guides.pose]]`, `[guides.sim_weight]`, `[[guides.pin]]`,
/// `[guides.hold_out]`, `pose_clearance`) are refused.
#[derive(Debug, thiserror::Error)]
pub enum GuideAnimError {
    /// The sim hairs cannot be blended from the guides.
    #[error("[sim_hairs] {0}")]
    Blend(#[source] hair_groom::GroomError),
    /// The `length` map's fractions do not fit the sim hairs.
    #[error("[maps.length] {0}")]
    LengthFractions(#[source] hair_groom::GroomError),
    /// A pose's frame is not finite.
    #[error("{pose}: frame is not finite; use a frame number")]
    PoseFrame {
        /// The pose.
        pose: PoseName,
    },
    /// A pose is not after the one before it.
    #[error(
        "{pose}: keys must be in increasing frame order (key {} is at frame {previous})",
        .pose.index - 1
    )]
    PoseOrder {
        /// The pose.
        pose: PoseName,
        /// The frame of the key before it.
        previous: f32,
    },
    /// `time` without `file`.
    #[error("{pose}: `time` picks a USD time sample of `file`; give `file` or remove `time`")]
    TimeWithoutFile {
        /// The pose.
        pose: PoseName,
    },
    /// Both `file` and `sweep`.
    #[error("{pose}: give `file` or `sweep`, not both")]
    FileAndSweep {
        /// The pose.
        pose: PoseName,
    },
    /// The pose's file cannot be read.
    #[error("{pose} file {}: {source}", file.display())]
    PoseFile {
        /// The pose.
        pose: PoseName,
        /// The file, as the scene names it.
        file: PathBuf,
        /// Why.
        source: Box<ReadGuidesError>,
    },
    /// The pose's file has another number of guides than the groom.
    #[error(
        "{pose} file {} has {given} guides, but the groom has {guides}: a pose must give every \
         guide, in the groom's order",
        file.display()
    )]
    PoseGuides {
        /// The pose.
        pose: PoseName,
        /// The file, as the scene names it.
        file: PathBuf,
        /// Guides in the file.
        given: usize,
        /// Guides in the groom.
        guides: usize,
    },
    /// A posed guide's root is away from where the guide grows.
    #[error(
        "{pose} file {}: guide {guide}'s root is {:.1} mm from where the guide grows (the most \
         is [guides] max_snap_distance = {:.1} mm): a pose moves guides, not their roots; keep \
         the guides in the groom's order",
        file.display(),
        .distance * 1e3,
        .tolerance * 1e3
    )]
    PoseRoot {
        /// The pose.
        pose: PoseName,
        /// The file, as the scene names it.
        file: PathBuf,
        /// The guide.
        guide: usize,
        /// Its root's distance from the groom's root, m.
        distance: f32,
        /// The most allowed (`[guides] max_snap_distance`), m.
        tolerance: f32,
    },
    /// A sweep's direction is zero or not finite.
    #[error("{pose} sweep: direction must be a finite non-zero vector")]
    SweepDirection {
        /// The pose.
        pose: PoseName,
        /// The direction given.
        direction: [f32; 3],
    },
    /// A sweep's angle is outside [0, 180] degrees.
    #[error("{pose} sweep: angle_deg = {angle_deg}: use an angle in [0, 180] degrees")]
    SweepAngle {
        /// The pose.
        pose: PoseName,
        /// The angle given, degrees.
        angle_deg: f32,
    },
    /// A pose's shapes do not fit the guides (point counts, non-finite points).
    #[error("{0}")]
    Pose(#[from] hair_groom::PoseError),
    /// The pose lift cannot be built on the scalp.
    #[error("[guides] pose_clearance: {0}")]
    PoseLift(#[source] hair_groom::GroomError),
    /// `pose_clearance` is negative or not finite.
    #[error(
        "[guides] pose_clearance = {value}: give a height ≥ 0 m above the scalp (e.g. the sim \
         hairs' clearance) or remove the key"
    )]
    PoseClearance {
        /// The value given, m.
        value: f32,
    },
    /// `[guides.sim_weight]` without keys.
    #[error(
        "[guides.sim_weight] has no keys; give keys = [{{ frame = 1, value = 0.0 }}, …] or \
         remove the section"
    )]
    SimWeightNoKeys,
    /// A sim weight key outside [0, 1] or not finite.
    #[error(
        "[guides.sim_weight] keys[{key}] value = {value} at frame {frame}: a sim weight is in \
         [0, 1] (0 = simulation, 1 = the animated guides)"
    )]
    SimWeightValue {
        /// The key's index.
        key: usize,
        /// Its value.
        value: f32,
        /// Its frame.
        frame: f32,
    },
    /// A sim weight key is not after the one before it.
    #[error(
        "[guides.sim_weight] keys[{key}] is at frame {frame} but keys[{}] at {previous}: keys \
         must be in increasing frame order",
        .key - 1
    )]
    SimWeightOrder {
        /// The key's index.
        key: usize,
        /// Its frame.
        frame: f32,
        /// The frame of the key before it.
        previous: f32,
    },
    /// A pin names a point sim hairs do not have.
    #[error(
        "[[guides.pin]] #{pin} points names point {point}, but sim hairs have {points} points \
         (0–{})",
        .points - 1
    )]
    PinPoint {
        /// The pin's index in `[[guides.pin]]`.
        pin: usize,
        /// The point named.
        point: usize,
        /// Points per sim hair.
        points: usize,
    },
    /// A selection of hair is refused.
    #[error("{0}")]
    Selection(Box<SelectionError>),
    /// A map cannot be applied (`[maps.sim_weight]`).
    #[error("{0}")]
    Maps(Box<MapsError>),
}

boxed_from!(SelectionError, Map, MapsError);
boxed_from!(GuideAnimError, Selection, SelectionError);
boxed_from!(GuideAnimError, Maps, MapsError);
