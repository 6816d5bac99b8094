//! [`Motion`]: where a rigid body (the scalp, a collider) is at a frame.

use nalgebra::Isometry3;

use crate::scene::motion::RigidMotion;

/// The rigid motion of the scalp or a collider over the shot.
#[derive(Debug, Clone, PartialEq)]
pub enum Motion {
    /// Keyframed in a scene file (`[scalp.motion]`, `[colliders.motion]`).
    Keyed(RigidMotion),
    /// Fixed at one pose (m, world space): a host's body at the first frame, which the host
    /// then poses itself frame by frame.
    Fixed(Isometry3<f32>),
}

impl Motion {
    /// The body's pose at (possibly fractional) `frame`.
    pub fn at(&self, frame: f32) -> Isometry3<f32> {
        match self {
            Motion::Keyed(keys) => keys.at(frame),
            Motion::Fixed(pose) => *pose,
        }
    }
}
