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
use crate::scene::maps::{MapSelection, ScalpMaps};
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
pub type PoseReader<'a> = dyn Fn(&Path, Option<f64>) -> Result<Vec<Vec<Vector3<f32>>>, String> + 'a;

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
) -> Result<GuideAnimation, String> {
    let mut blend =
        GuideBlend::new(mesh, guides, hairs, points).map_err(|e| format!("[sim_hairs] {e}"))?;
    if let Some(fractions) = fractions {
        blend = blend
            .with_length_fractions(fractions)
            .map_err(|e| format!("[maps.length] {e}"))?;
    }
    let frames: Vec<RootFrame> = guides.iter().map(|g| mesh.evaluate(&g.root)).collect();
    let groom: Vec<Vec<Vector3<f32>>> = guides.iter().map(|g| g.rest.clone()).collect();
    let mut poses = Vec::with_capacity(keys.poses.len());
    for (i, key) in keys.poses.iter().enumerate() {
        let name = format!("[[guides.pose]] #{i} (frame {})", key.frame);
        if !key.frame.is_finite() {
            return Err(format!("{name}: frame is not finite; use a frame number"));
        }
        if i > 0 && key.frame <= keys.poses[i - 1].frame {
            return Err(format!(
                "{name}: keys must be in increasing frame order (key {} is at frame {})",
                i - 1,
                keys.poses[i - 1].frame
            ));
        }
        if key.time.is_some() && key.file.is_none() {
            return Err(format!(
                "{name}: `time` picks a USD time sample of `file`; give `file` or remove `time`"
            ));
        }
        let shapes = match (&key.file, &key.sweep) {
            (Some(_), Some(_)) => {
                return Err(format!("{name}: give `file` or `sweep`, not both"));
            }
            (Some(file), None) => {
                let world = read(file, key.time)
                    .map_err(|e| format!("{name} file {}: {e}", file.display()))?;
                let what = format!("{name} file {}", file.display());
                to_root_local(&world, &frames, max_snap_distance, &what)?
            }
            (None, Some(sweep)) => {
                swept(&groom, &frames, sweep).map_err(|e| format!("{name} sweep: {e}"))?
            }
            (None, None) => groom.clone(),
        };
        blend
            .check_pose(&shapes, &name)
            .map_err(|e| e.to_string())?;
        poses.push(PoseKey {
            frame: key.frame,
            shapes,
        });
    }
    let lift = match keys.clearance {
        None => None,
        Some(c) if c.is_finite() && c >= 0.0 => {
            Some(PoseLift::new(mesh, c).map_err(|e| format!("[guides] pose_clearance: {e}"))?)
        }
        Some(c) => {
            return Err(format!(
                "[guides] pose_clearance = {c}: give a height ≥ 0 m above the scalp \
                 (e.g. the sim hairs' clearance) or remove the key"
            ))
        }
    };
    let hair_count = hairs.len();
    let select = |s: &HairSelection, what: &str| -> Result<Vec<bool>, String> {
        selection(s, what, mesh, guides.len(), hairs, maps)
    };
    // Each hair's factor of the sim weight: every hair by default (the curve is then 0, but a
    // host's `set_sim_weight` reaches all hair), only the selected ones under a selection.
    let mut sim_factor = vec![1.0f32; hair_count];
    let curve = match keys.sim_weight {
        None if maps.get("sim_weight").is_some() => {
            return Err(
                "[maps.sim_weight] paints each sim hair's factor of the sim weight \
                        curve, but there is no [guides.sim_weight]: add its keys or remove the map"
                    .into(),
            )
        }
        None => WeightCurve::default(),
        Some(w) => {
            let what = "[guides.sim_weight]";
            if w.keys.is_empty() {
                return Err(format!("{what} has no keys; give keys = [{{ frame = 1, value = 0.0 }}, …] or remove the section"));
            }
            for (i, k) in w.keys.iter().enumerate() {
                if !(k.frame.is_finite() && k.value.is_finite() && (0.0..=1.0).contains(&k.value)) {
                    return Err(format!(
                        "{what} keys[{i}] value = {} at frame {}: a sim weight is in [0, 1] \
                         (0 = simulation, 1 = the animated guides)",
                        k.value, k.frame
                    ));
                }
                if i > 0 && k.frame <= w.keys[i - 1].frame {
                    return Err(format!("{what} keys[{i}] is at frame {} but keys[{}] at {}: keys must be in increasing frame order", k.frame, i - 1, w.keys[i - 1].frame));
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
                        .map_err(|e| e.to_string())?;
                    if !(0.0..=1.0).contains(&v) {
                        return Err(format!(
                            "[maps.sim_weight] is {v} at sim hair {i}: a sim weight factor is \
                             in [0, 1]; paint values in [0, 1]"
                        ));
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
            return Err(format!(
                "{what} selects no hair: give `guides`, `strands`, `region` or `map`"
            ));
        }
        let chosen = select(&pin.select, &what)?;
        if let Some(p) = pin
            .points
            .as_ref()
            .and_then(|p| p.iter().find(|&&p| p >= points))
        {
            return Err(format!(
                "{what} points names point {p}, but sim hairs have {points} points (0–{})",
                points - 1
            ));
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
            return Err(format!(
                "{what} selects no hair: give `guides`, `strands`, `region` or `map`"
            ));
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
) -> Result<Vec<bool>, String> {
    let mut chosen = vec![false; hairs.len()];
    if let Some(list) = &s.guides {
        let mut wanted = vec![false; guide_count];
        for &g in list {
            *wanted.get_mut(g).ok_or_else(|| {
                format!(
                    "{what} guides names guide {g}, but there are {guide_count} guides (0–{})",
                    guide_count.saturating_sub(1)
                )
            })? = true;
        }
        for (c, h) in chosen.iter_mut().zip(hairs) {
            *c |= h.sources.first().is_some_and(|s| wanted[s.guide]);
        }
    }
    if let Some(list) = &s.strands {
        for &i in list {
            *chosen.get_mut(i).ok_or_else(|| {
                format!(
                    "{what} strands names sim hair {i}, but there are {} sim hairs (0–{})",
                    hairs.len(),
                    hairs.len().saturating_sub(1)
                )
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
                    .map_err(|e| e.to_string())?,
            );
        }
    }
    if !chosen.iter().any(|&c| c) {
        return Err(format!("{what} names no hair: no sim hair matches its guides, strands, region or map; widen the selection"));
    }
    Ok(chosen)
}

/// World (scene-space) posed guides to root-local shapes in the groom's guide frames. Each pose
/// keeps its root within `tolerance` m of the guide's root (the pose is translated onto it).
fn to_root_local(
    world: &[Vec<Vector3<f32>>],
    frames: &[RootFrame],
    tolerance: f32,
    what: &str,
) -> Result<Vec<Vec<Vector3<f32>>>, String> {
    if world.len() != frames.len() {
        return Err(format!(
            "{what} has {} guides, but the groom has {}: a pose must give every guide, in the groom's order",
            world.len(),
            frames.len()
        ));
    }
    world
        .iter()
        .zip(frames)
        .enumerate()
        .map(|(g, (curve, frame))| {
            let root = curve[0];
            let off = (root - frame.origin).norm();
            if off > tolerance {
                return Err(format!(
                    "{what}: guide {g}'s root is {:.1} mm from where the guide grows (the most is \
                     [guides] max_snap_distance = {:.1} mm): a pose moves guides, not their roots; \
                     keep the guides in the groom's order",
                    off * 1e3,
                    tolerance * 1e3
                ));
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
) -> Result<Vec<Vec<Vector3<f32>>>, String> {
    let dir = Vector3::from(sweep.direction);
    if !(dir.iter().all(|c| c.is_finite()) && dir.norm() > 0.0) {
        return Err("direction must be a finite non-zero vector".into());
    }
    if !(sweep.angle_deg.is_finite() && (0.0..=180.0).contains(&sweep.angle_deg)) {
        return Err(format!(
            "angle_deg = {}: use an angle in [0, 180] degrees",
            sweep.angle_deg
        ));
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
