//! Post-step passes over edge strands: Provot's strain limit and the root angle limiter.
//!
//! Both move positions only towards the constraint and then remove the velocity component that
//! points further into violation (inelastic), so they never add energy.

use std::f32::consts::PI;

use nalgebra::{Unit, UnitQuaternion, Vector3};

use crate::error::{HairError, Result};
use crate::mesh::{any_perpendicular, RootFrame};
use crate::strands::StrandSet;

/// The largest angle, radians, the first segment of a strand may make with its rest direction in
/// the root frame (the follicle's direction), in (0, π).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RootAngleLimit(f32);

impl RootAngleLimit {
    /// A limit of `radians`, refused unless it lies strictly between 0 and π.
    pub fn new(radians: f32) -> Result<Self> {
        if radians.is_finite() && radians > 0.0 && radians < PI {
            Ok(Self(radians))
        } else {
            Err(HairError::Parameter {
                name: "strips.root_angle_deg".into(),
                value: format!("{}°", radians.to_degrees()),
                fix: "the root angle limit must lie strictly between 0° and 180°".into(),
            })
        }
    }

    /// The limit, radians.
    pub fn radians(&self) -> f32 {
        self.0
    }
}

/// Removes from `v` the part along unit `n` that is negative (moving against `n`).
fn remove_against(v: &mut Vector3<f32>, n: &Vector3<f32>) {
    let along = v.dot(n);
    if along < 0.0 {
        *v -= n * along;
    }
}

/// Rotates every strand's first segment that is bent more than `limit` from its rest direction
/// (expressed in `roots[s]`, the strands' root frames at this instant) back onto the limit cone
/// about the root, keeping its length, and translates the rest of the strand with its second
/// point (no segment changes length). Velocity of the second point out of the cone is removed.
/// Returns how many strands were corrected.
pub fn limit_root_angles(
    strands: &mut StrandSet,
    roots: &[RootFrame],
    limit: RootAngleLimit,
) -> usize {
    let mut corrected = 0;
    for (s, root) in roots.iter().enumerate().take(strands.len()) {
        let p = strands.points(s).start;
        let rest = strands.rest_local()[p + 1] - strands.rest_local()[p];
        let Some(rest_dir) = (root.rotation * rest).try_normalize(1e-12) else {
            continue;
        };
        let d = strands.positions[p + 1] - strands.positions[p];
        let len = d.norm();
        let Some(dir) = d.try_normalize(1e-12) else {
            continue;
        };
        let angle = rest_dir.dot(&dir).clamp(-1.0, 1.0).acos();
        if angle <= limit.0 {
            continue;
        }
        let axis = rest_dir
            .cross(&dir)
            .try_normalize(1e-9)
            .unwrap_or_else(|| any_perpendicular(&rest_dir));
        let limited =
            UnitQuaternion::from_axis_angle(&Unit::new_unchecked(axis), limit.0) * rest_dir;
        let target = strands.positions[p] + limited * len;
        // The cone wall's inward normal at the corrected point: towards the rest direction.
        let inward = (rest_dir - limited * limited.dot(&rest_dir))
            .try_normalize(1e-9)
            .unwrap_or(rest_dir);
        // The rest of the strand is carried along (translated), so the correction stretches no
        // segment: moving point 1 alone would load segment 1's spring, which flings the strand
        // back at the next frame.
        let shift = target - strands.positions[p + 1];
        let end = strands.points(s).end;
        for x in &mut strands.positions[p + 1..end] {
            *x += shift;
        }
        remove_against(&mut strands.velocities[p + 1], &inward);
        corrected += 1;
    }
    corrected
}

/// Provot's correction: root to tip, every free point whose segment to its predecessor is longer
/// than `(1 + max_strain) ×` the rest length is pulled back along the segment to that length
/// (the root and pinned points stay), and its velocity away from the predecessor is removed.
/// Because each point is moved after its predecessor, one pass leaves every segment within the
/// limit. Returns the largest strain found before correction.
pub fn limit_strain(strands: &mut StrandSet, max_strain: f32) -> f32 {
    let mut worst = 0.0f32;
    for s in 0..strands.len() {
        let points = strands.points(s);
        let segments = strands.segments(s);
        for (j, seg) in segments.enumerate() {
            let i = points.start + j + 1;
            let rest = strands.rest_lengths()[seg];
            let d = strands.positions[i] - strands.positions[i - 1];
            let len = d.norm();
            worst = worst.max(len / rest - 1.0);
            let max_len = (1.0 + max_strain) * rest;
            if len <= max_len || strands.inverse_masses()[i] == 0.0 {
                continue;
            }
            let dir = d / len;
            strands.positions[i] = strands.positions[i - 1] + dir * max_len;
            remove_against(&mut strands.velocities[i], &-dir);
        }
    }
    worst
}
