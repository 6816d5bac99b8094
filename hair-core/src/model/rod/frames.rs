//! Reference and material frames of the discrete rod, and the curvature binormal at its nodes.
//!
//! Every segment (edge) `j` has a unit tangent `t_j` and a twist-free **reference frame**
//! `(t_j, u_j, v_j = t_j × u_j)`: `u_j` is carried from the root by parallel transport along the
//! current centreline (the minimal rotation taking `t_{j−1}` to `t_j`), starting from the
//! **ghost edge** `−1`, a segment fixed in the root frame along the rest direction of the first
//! segment. The **material frame** of segment `j` is its reference frame turned about `t_j` by
//! the scalar twist angle `θ_j`:
//!
//! ```text
//! m1_j =  cos θ_j u_j + sin θ_j v_j    (major axis of the cross-section)
//! m2_j = −sin θ_j u_j + cos θ_j v_j    (minor axis)
//! ```
//!
//! Bending lives at the nodes: node `i` joins segments `i − 1` and `i` (node 0 joins the ghost
//! and segment 0) and carries the curvature binormal of Bergou et al. 2008,
//! `κb_i = 2 t_{i−1} × t_i / (1 + t_{i−1}·t_i)`, of length `2 tan(φ/2)` for a turn by `φ`; its
//! direction is the axis the strand bends about.

use nalgebra::Vector3;

/// A vector of the rod model (m, N or dimensionless), f64.
pub type V3 = Vector3<f64>;

/// Smallest `1 + t_a·t_b` used in the curvature binormal: a segment folded straight back onto
/// its neighbour (a turn of 180°) has no finite curvature; it is capped at this (about 177°).
pub const FOLD_CAP: f64 = 1e-3;

/// Parallel-transports `u` (⟂ `t_prev`) from unit tangent `t_prev` to unit tangent `t_next`: the
/// minimal rotation between them applied to `u`. A fold straight back keeps `u`.
#[inline]
pub fn transport(u: &V3, t_prev: &V3, t_next: &V3) -> V3 {
    let c = 1.0 + t_prev.dot(t_next);
    if c > 1e-12 {
        u - (t_prev + t_next) * (u.dot(t_next) / c)
    } else {
        *u
    }
}

/// A unit vector perpendicular to the unit vector `t`.
pub fn perpendicular(t: &V3) -> V3 {
    let axis = if t.x.abs() < 0.6 { V3::x() } else { V3::y() };
    (axis - t * axis.dot(t)).normalize()
}

/// Curvature binormal `2 t_a × t_b / (1 + t_a·t_b)` of two unit tangents (dimensionless).
#[inline]
pub fn curvature_binormal(t_a: &V3, t_b: &V3) -> V3 {
    t_a.cross(t_b) * (2.0 / (1.0 + t_a.dot(t_b)).max(FOLD_CAP))
}

/// Material axes `(m1, m2)` of a reference frame `(u, v)` turned by `theta` (rad).
#[inline]
pub fn material(u: &V3, v: &V3, theta: f64) -> (V3, V3) {
    let (s, c) = theta.sin_cos();
    (u * c + v * s, v * c - u * s)
}

/// The ghost edge: the segment before segment 0, fixed in the root frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ghost {
    /// Unit tangent, world.
    pub t: V3,
    /// Reference normal (⟂ `t`), world; the material frame of the ghost has twist 0.
    pub u: V3,
    /// Length, m (the rest length of segment 0).
    pub length: f64,
}

impl Ghost {
    /// `t × u`.
    pub fn v(&self) -> V3 {
        self.t.cross(&self.u)
    }
}

/// The per-segment frames of one strand's current shape.
#[derive(Debug, Clone, Default)]
pub struct EdgeFrames {
    /// Unit tangents `t_j`.
    pub t: Vec<V3>,
    /// Transported reference normals `u_j`.
    pub u: Vec<V3>,
    /// `v_j = t_j × u_j`.
    pub v: Vec<V3>,
    /// Current segment lengths, m.
    pub length: Vec<f64>,
    /// Curvature binormal of node `i` (`0..segments`; node 0 against the ghost).
    pub kb: Vec<V3>,
}

impl EdgeFrames {
    /// Recomputes every frame and binormal of the polyline `x` from `ghost`. Segments must have
    /// non-zero length (the solver checks rest shapes and keeps lengths by projection).
    pub fn update(&mut self, x: &[V3], ghost: &Ghost) {
        let n = x.len() - 1;
        self.t.clear();
        self.u.clear();
        self.v.clear();
        self.length.clear();
        self.kb.clear();
        let (mut t_prev, mut u_prev) = (ghost.t, ghost.u);
        for j in 0..n {
            let e = x[j + 1] - x[j];
            let len = e.norm();
            let t = if len > 0.0 { e / len } else { t_prev };
            // Transport keeps u unit and normal (to rounding: frames are rebuilt from the ghost
            // every substep, so nothing accumulates over time). Only a fold straight back, which
            // keeps u as it is, needs it made normal again.
            let mut u = transport(&u_prev, &t_prev, &t);
            if 1.0 + t_prev.dot(&t) <= 1e-12 {
                u -= t * u.dot(&t);
                let norm = u.norm();
                u = if norm > 1e-12 {
                    u / norm
                } else {
                    perpendicular(&t)
                };
            }
            self.kb.push(curvature_binormal(&t_prev, &t));
            self.v.push(t.cross(&u));
            self.t.push(t);
            self.u.push(u);
            self.length.push(len);
            t_prev = t;
            u_prev = u;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn binormal_has_length_two_tan_half_angle() {
        let a = V3::x();
        let phi = 0.7f64;
        let b = V3::new(phi.cos(), phi.sin(), 0.0);
        let kb = curvature_binormal(&a, &b);
        assert!((kb.norm() - 2.0 * (phi / 2.0).tan()).abs() < 1e-12);
        assert!((kb.normalize() - V3::z()).norm() < 1e-12);
    }

    #[test]
    fn frames_stay_orthonormal_along_a_helix() {
        let x: Vec<V3> = (0..30)
            .map(|i| {
                let a = 0.4 * i as f64;
                V3::new(a.cos(), a.sin(), 0.2 * i as f64)
            })
            .collect();
        let t0 = (x[1] - x[0]).normalize();
        let ghost = Ghost {
            t: t0,
            u: perpendicular(&t0),
            length: 1.0,
        };
        let mut f = EdgeFrames::default();
        f.update(&x, &ghost);
        for j in 0..f.t.len() {
            assert!((f.u[j].norm() - 1.0).abs() < 1e-12);
            assert!(f.u[j].dot(&f.t[j]).abs() < 1e-12);
            assert!((f.v[j] - f.t[j].cross(&f.u[j])).norm() < 1e-12);
        }
        assert!(f.kb[0].norm() < 1e-12, "segment 0 lies along the ghost");
    }
}
