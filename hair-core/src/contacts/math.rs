//! Conversions between the project's math types (nalgebra, f32) and rapier/parry's (glam through
//! `glamx`, f32). Every crossing between the two worlds goes through this module, so a change of
//! either library's math types is fixed here and only here.

use nalgebra::{Isometry3, Vector3};
use parry3d::math::{Pose, Rotation, Vector};

/// A nalgebra vector (m or m/s) as a glam vector.
#[inline(always)]
pub(crate) fn to_glam(v: &Vector3<f32>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

/// A glam vector as a nalgebra vector.
#[inline(always)]
pub(crate) fn from_glam(v: Vector) -> Vector3<f32> {
    Vector3::new(v.x, v.y, v.z)
}

/// A rigid transform (m, unit quaternion) as a parry pose.
pub(crate) fn to_pose(iso: &Isometry3<f32>) -> Pose {
    let q = iso.rotation.quaternion();
    Pose::from_parts(
        to_glam(&iso.translation.vector),
        Rotation::from_xyzw(q.i, q.j, q.k, q.w),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pose_transforms_points_like_the_isometry() {
        let iso = Isometry3::new(Vector3::new(0.3, -1.0, 2.0), Vector3::new(0.4, -0.7, 1.2));
        let pose = to_pose(&iso);
        let p = Vector3::new(0.5, 0.25, -2.0);
        let by_na = iso * nalgebra::Point3::from(p);
        let by_glam = from_glam(pose.transform_point(to_glam(&p)));
        assert_eq!(from_glam(to_glam(&p)), p);
        assert!((by_na.coords - by_glam).norm() < 1e-5);
    }
}
