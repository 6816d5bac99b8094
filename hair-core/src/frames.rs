//! Segment frames by parallel transport, the reference in which bending springs hold their rest
//! direction.
//!
//! Each segment `j` has a frame `(t_j, u_j, w_j)`: `t_j` its unit direction, `u_j` a normal carried
//! down the strand by parallel transport (the minimal rotation taking `t_{j-1}` to `t_j`), and
//! `w_j = t_j × u_j`. The frame before the first segment is the root frame (t = surface normal,
//! u = tangent, w = bitangent), so the whole chain of frames turns with the head. The
//! [`RestDirection`] of segment `j`, `(a, b, c)`, is its rest direction in its predecessor's frame,
//! `a t_{j-1} + b u_{j-1} + c w_{j-1}` (for the first segment: in the root frame); the solver
//! bends the strand towards the rest curvature that turn describes
//! ([`crate::integrate::curvature`]). Since the frame turns with the segments before it, the solver
//! applies the full gradient of the bending energy, forces on the earlier points included (see the
//! kernel).
//!
//! Transport of a normal `u ⟂ t_prev` to `t_next` uses the closed form
//! `u − (u·t_next)/(1 + t_prev·t_next) (t_prev + t_next)`, which is exactly the minimal rotation
//! applied to `u` (no trigonometry, one division). A segment folded straight back (`t_next = −t_prev`)
//! has no minimal rotation; `u` is then kept as it is.

use nalgebra::Vector3;

/// Rest direction of a segment in its predecessor's frame: unit vector components along the
/// predecessor's tangent `t`, transported normal `u` and binormal `w`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RestDirection {
    /// Component along the predecessor's tangent.
    pub t: f32,
    /// Component along the predecessor's transported normal.
    pub u: f32,
    /// Component along the predecessor's binormal.
    pub w: f32,
}

impl RestDirection {
    /// The unit direction this describes, in the frame `(t, u, w)`.
    #[inline(always)]
    pub fn in_frame(&self, t: &Vector3<f32>, u: &Vector3<f32>, w: &Vector3<f32>) -> Vector3<f32> {
        t * self.t + u * self.u + w * self.w
    }
}

/// Parallel-transports the normal `u` (⟂ `t_prev`) from unit tangent `t_prev` to unit tangent
/// `t_next`.
#[inline(always)]
pub fn transport(u: &Vector3<f32>, t_prev: &Vector3<f32>, t_next: &Vector3<f32>) -> Vector3<f32> {
    let c = 1.0 + t_prev.dot(t_next);
    if c > 1e-6 {
        u - (t_prev + t_next) * (u.dot(t_next) / c)
    } else {
        *u
    }
}

/// Rest directions of every segment of a rest shape given in root-local coordinates (the root
/// frame's axes: x tangent, y bitangent, z normal).
pub fn rest_directions(rest: &[Vector3<f32>]) -> Vec<RestDirection> {
    let mut t = Vector3::z();
    let mut u = Vector3::x();
    let mut out = Vec::with_capacity(rest.len().saturating_sub(1));
    for pair in rest.windows(2) {
        let d = (pair[1] - pair[0]).normalize();
        let w = t.cross(&u);
        out.push(RestDirection {
            t: d.dot(&t),
            u: d.dot(&u),
            w: d.dot(&w),
        });
        u = transport(&u, &t, &d);
        t = d;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transport_keeps_u_unit_and_normal() {
        let t0 = Vector3::new(0.0, 0.0, 1.0f32);
        let u0 = Vector3::new(1.0, 0.0, 0.0);
        let t1 = Vector3::new(0.3, 0.5, 0.8).normalize();
        let u1 = transport(&u0, &t0, &t1);
        assert!((u1.norm() - 1.0).abs() < 1e-6);
        assert!(u1.dot(&t1).abs() < 1e-6);
    }

    #[test]
    fn rest_directions_rebuild_a_curve() {
        // A helix: rebuilding it from its rest directions and the identity root frame gives it back.
        let rest: Vec<Vector3<f32>> = (0..20)
            .map(|i| {
                let a = i as f32 * 0.5;
                Vector3::new(0.1 * a.cos() - 0.1, 0.1 * a.sin(), 0.03 * i as f32)
            })
            .collect();
        let dirs = rest_directions(&rest);
        let (mut t, mut u) = (Vector3::z(), Vector3::x());
        let mut x = rest[0];
        for (j, d) in dirs.iter().enumerate() {
            let w = t.cross(&u);
            let dir = d.in_frame(&t, &u, &w);
            x += dir * (rest[j + 1] - rest[j]).norm();
            assert!((x - rest[j + 1]).norm() < 1e-4, "point {}", j + 1);
            u = transport(&u, &t, &dir);
            t = dir;
        }
    }
}
