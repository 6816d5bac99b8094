//! A parent prepared for its children: its subdivided points, a parallel-transported frame at every
//! point and the arc length from the root.
//!
//! The frame at point 0 is the parent's root frame (u = tangent x, w = bitangent y, normal z);
//! the frame at point `i ≥ 1` is the frame of the segment ending there, carried from the root
//! frame's normal to each segment's direction by [`hair_core::frames::transport`] (the solver's
//! convention: "the frame before the first segment is the root frame"). An offset `(a, b)` given
//! in the root's tangent plane therefore sits on the scalp at the root and turns with the hair
//! along its length without twisting.

use hair_core::frames::transport;
use hair_core::RootFrame;
use nalgebra::Vector3;

/// One parent's subdivided points with frames and arc length, meters.
#[derive(Debug, Clone, Default)]
pub(crate) struct ParentPath {
    /// Points, root first.
    pub points: Vec<Vector3<f32>>,
    /// Transported normal at each point (unit, ⟂ the segment ending there).
    pub u: Vec<Vector3<f32>>,
    /// Binormal `t × u` at each point.
    pub w: Vec<Vector3<f32>>,
    /// Arc length from the root to each point.
    pub arc: Vec<f32>,
}

impl ParentPath {
    /// Rebuilds the frames and arc lengths of `self.points` from `root`.
    pub fn build_frames(&mut self, root: &RootFrame) {
        let n = self.points.len();
        self.u.clear();
        self.w.clear();
        self.arc.clear();
        let mut t = root.rotation * Vector3::z();
        let mut u = root.rotation * Vector3::x();
        self.u.push(u);
        self.w.push(t.cross(&u));
        self.arc.push(0.0);
        let mut length = 0.0;
        for i in 1..n {
            let d = self.points[i] - self.points[i - 1];
            let l = d.norm();
            if l > 1e-12 {
                let next = d / l;
                u = transport(&u, &t, &next);
                u = (u - next * u.dot(&next)).normalize();
                t = next;
            }
            length += l;
            self.u.push(u);
            self.w.push(t.cross(&u));
            self.arc.push(length);
        }
    }

    /// Point, normal, binormal and arc length at fractional point index `x` (linear between
    /// points; `x` clamped to the path).
    #[inline(always)]
    pub fn at(&self, x: f32) -> (Vector3<f32>, Vector3<f32>, Vector3<f32>, f32) {
        let last = self.points.len() - 1;
        let x = x.clamp(0.0, last as f32);
        let j = (x as usize).min(last.saturating_sub(1));
        let f = x - j as f32;
        if f == 0.0 {
            return (self.points[j], self.u[j], self.w[j], self.arc[j]);
        }
        let g = 1.0 - f;
        (
            self.points[j] * g + self.points[j + 1] * f,
            self.u[j] * g + self.u[j + 1] * f,
            self.w[j] * g + self.w[j + 1] * f,
            self.arc[j] * g + self.arc[j + 1] * f,
        )
    }
}

impl ParentPath {
    /// Point at fractional point index `x` (linear between points; `x` clamped to the path).
    #[inline(always)]
    pub fn point_at(&self, x: f32) -> Vector3<f32> {
        let last = self.points.len() - 1;
        let x = x.clamp(0.0, last as f32);
        let j = (x as usize).min(last.saturating_sub(1));
        let f = x - j as f32;
        if f == 0.0 {
            return self.points[j];
        }
        self.points[j] * (1.0 - f) + self.points[j + 1] * f
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_orthonormal_and_start_at_the_root_frame() {
        let mut path = ParentPath {
            points: (0..20)
                .map(|i| {
                    let a = i as f32 * 0.3;
                    Vector3::new(a.cos(), a.sin(), 0.2 * a)
                })
                .collect(),
            ..Default::default()
        };
        let root = RootFrame::from_normal_and_edge(path.points[0], Vector3::z(), Vector3::x());
        path.build_frames(&root);
        assert!((path.u[0] - Vector3::x()).norm() < 1e-6);
        for i in 1..20 {
            let t = (path.points[i] - path.points[i - 1]).normalize();
            assert!((path.u[i].norm() - 1.0).abs() < 1e-5);
            assert!(path.u[i].dot(&t).abs() < 1e-5);
            assert!((path.w[i] - t.cross(&path.u[i])).norm() < 1e-5);
        }
    }
}
