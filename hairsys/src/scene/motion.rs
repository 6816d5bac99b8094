//! Keyframed rigid motion (translation and rotation over frames), as animators key it.
//!
//! Rotations are keyed as XYZ Euler angles in degrees and interpolated channel by channel (so a
//! key of 720° turns twice, as in Blender); the resulting rotation is applied as
//! `Rz · Ry · Rx`. Between keys the interpolation is linear or eased (smoothstep: zero velocity at
//! every key, like Blender's auto-clamped Bézier handles at extremes). Before the first key and
//! after the last the motion holds.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

/// How values change between two keys.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Interpolation {
    /// Straight lines between keys (constant velocity, velocity jumps at keys).
    Linear,
    /// Smoothstep between keys: zero velocity at each key, smooth in between.
    #[default]
    Ease,
}

/// One key of a rigid motion.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionKey {
    /// Frame number of the key.
    pub frame: f32,
    /// Translation, m.
    #[serde(default)]
    pub translation: [f32; 3],
    /// Rotation as XYZ Euler angles, degrees (applied as Rz·Ry·Rx).
    #[serde(default)]
    pub rotation_deg: [f32; 3],
}

/// A keyframed rigid motion. No keys means the identity at every frame.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigidMotion {
    /// Interpolation between keys.
    #[serde(default)]
    pub interpolation: Interpolation,
    /// Keys in increasing frame order.
    #[serde(default)]
    pub keys: Vec<MotionKey>,
}

impl RigidMotion {
    /// Checks keys are finite and strictly increasing in frame; returns a message naming the key.
    pub fn validate(&self) -> Result<(), MotionError> {
        for (i, k) in self.keys.iter().enumerate() {
            let finite = k.frame.is_finite()
                && k.translation.iter().all(|v| v.is_finite())
                && k.rotation_deg.iter().all(|v| v.is_finite());
            if !finite {
                return Err(MotionError::NotFinite { key: i });
            }
            if i > 0 && k.frame <= self.keys[i - 1].frame {
                return Err(MotionError::Unordered {
                    key: i,
                    frame: k.frame,
                    previous: self.keys[i - 1].frame,
                });
            }
        }
        Ok(())
    }

    /// The transform at (possibly fractional) `frame`.
    pub fn at(&self, frame: f32) -> Isometry3<f32> {
        let (translation, euler) = self.channels(frame);
        let r = euler.map(f32::to_radians);
        let rotation = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), r.z)
            * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), r.y)
            * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), r.x);
        Isometry3::from_parts(Translation3::from(translation), rotation)
    }

    fn channels(&self, frame: f32) -> (Vector3<f32>, Vector3<f32>) {
        let key = |k: &MotionKey| (Vector3::from(k.translation), Vector3::from(k.rotation_deg));
        let (Some(first), Some(last)) = (self.keys.first(), self.keys.last()) else {
            return (Vector3::zeros(), Vector3::zeros());
        };
        if frame <= first.frame {
            return key(first);
        }
        if frame >= last.frame {
            return key(last);
        }
        let i = self.keys.partition_point(|k| k.frame <= frame) - 1;
        let (a, b) = (&self.keys[i], &self.keys[i + 1]);
        let mut s = (frame - a.frame) / (b.frame - a.frame);
        if self.interpolation == Interpolation::Ease {
            s = s * s * (3.0 - 2.0 * s);
        }
        let (ta, ra) = key(a);
        let (tb, rb) = key(b);
        (ta.lerp(&tb, s), ra.lerp(&rb, s))
    }
}

/// Why keyframed rigid motion is refused; the caller names the section (`[scalp.motion]`,
/// `[[colliders]] #i motion`).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MotionError {
    /// A key has a non-finite frame, translation or rotation.
    #[error("key {key} has a non-finite value; use finite numbers")]
    NotFinite {
        /// The key's index.
        key: usize,
    },
    /// A key is not after the one before it.
    #[error(
        "key {key} is at frame {frame} but key {} is at frame {previous}; keys must be in \
         increasing frame order",
        .key - 1
    )]
    Unordered {
        /// The key's index.
        key: usize,
        /// Its frame.
        frame: f32,
        /// The frame of the key before it.
        previous: f32,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    fn motion(interpolation: Interpolation) -> RigidMotion {
        RigidMotion {
            interpolation,
            keys: vec![
                MotionKey {
                    frame: 1.0,
                    translation: [0.0; 3],
                    rotation_deg: [0.0; 3],
                },
                MotionKey {
                    frame: 11.0,
                    translation: [1.0, 0.0, 0.0],
                    rotation_deg: [0.0, 0.0, 90.0],
                },
            ],
        }
    }

    #[test]
    fn holds_outside_and_interpolates_inside() {
        let m = motion(Interpolation::Linear);
        assert_eq!(m.at(0.0), Isometry3::identity());
        let mid = m.at(6.0);
        assert!((mid.translation.vector.x - 0.5).abs() < 1e-6);
        assert!((mid.rotation.angle() - 45f32.to_radians()).abs() < 1e-5);
        let end = m.at(20.0);
        assert!((end.rotation * Vector3::x() - Vector3::y()).norm() < 1e-6);
    }

    #[test]
    fn ease_has_zero_velocity_at_keys() {
        let m = motion(Interpolation::Ease);
        let d = m.at(1.01).translation.vector.x - m.at(1.0).translation.vector.x;
        assert!(d < 1e-4, "{d}");
        assert!((m.at(6.0).translation.vector.x - 0.5).abs() < 1e-6);
    }

    #[test]
    fn unordered_keys_are_named() {
        let mut m = motion(Interpolation::Linear);
        m.keys[1].frame = 1.0;
        assert!(m.validate().unwrap_err().to_string().contains("key 1"));
    }
}
