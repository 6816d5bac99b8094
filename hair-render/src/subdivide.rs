//! Smooth subdivision of parent polylines for render curves: uniform Catmull–Rom through the
//! parent's points.
//!
//! Each parent segment `P_i → P_{i+1}` is split into `steps` pieces by the uniform Catmull–Rom
//! spline through `P_{i−1}, P_i, P_{i+1}, P_{i+2}`; the ends use mirrored phantom points
//! (`2P_0 − P_1`, `2P_{n−1} − P_{n−2}`), so the curve passes through every parent point, keeps
//! the end tangents and a straight, evenly spaced parent stays exactly so. `steps = 1` returns the
//! parent unchanged.

use nalgebra::Vector3;

/// Number of points of a `points`-point polyline subdivided with `steps` pieces per segment.
pub fn subdivided_len(points: usize, steps: u32) -> usize {
    (points.saturating_sub(1)) * steps as usize + 1
}

/// Appends `points` (≥ 2, meters) subdivided with `steps ≥ 1` pieces per segment to `out`:
/// [`subdivided_len`] points, passing through every input point.
pub fn catmull_rom(points: &[Vector3<f32>], steps: u32, out: &mut Vec<Vector3<f32>>) {
    let n = points.len();
    out.reserve(subdivided_len(n, steps));
    let at = |i: isize| -> Vector3<f32> {
        if i < 0 {
            points[0] * 2.0 - points[1]
        } else if i as usize >= n {
            points[n - 1] * 2.0 - points[n - 2]
        } else {
            points[i as usize]
        }
    };
    for i in 0..n as isize - 1 {
        let (p0, p1, p2, p3) = (at(i - 1), at(i), at(i + 1), at(i + 2));
        out.push(p1);
        let a = p2 - p0;
        let b = p0 * 2.0 - p1 * 5.0 + p2 * 4.0 - p3;
        let c = (p1 - p2) * 3.0 + p3 - p0;
        for k in 1..steps {
            let t = k as f32 / steps as f32;
            out.push(p1 + (a + (b + c * t) * t) * (0.5 * t));
        }
    }
    out.push(points[n - 1]);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_through_the_parent_and_keeps_lines_straight() {
        let line: Vec<_> = (0..5)
            .map(|i| Vector3::new(0.0, 0.0, 0.1 * i as f32))
            .collect();
        let mut out = Vec::new();
        catmull_rom(&line, 4, &mut out);
        assert_eq!(out.len(), subdivided_len(5, 4));
        for (k, p) in out.iter().enumerate() {
            assert!(
                (p - Vector3::new(0.0, 0.0, 0.025 * k as f32)).norm() < 1e-6,
                "{k}"
            );
        }
        let bent = vec![Vector3::zeros(), Vector3::x(), Vector3::new(1.0, 1.0, 0.0)];
        out.clear();
        catmull_rom(&bent, 3, &mut out);
        assert_eq!(out[0], bent[0]);
        assert_eq!(out[3], bent[1]);
        assert_eq!(out[6], bent[2]);
        out.clear();
        catmull_rom(&bent, 1, &mut out);
        assert_eq!(out, bent);
    }
}
