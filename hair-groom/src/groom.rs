//! A groom as files hold it: guide curves as world-space point lists, meters, Z up, before they
//! are attached to a scalp ([`crate::snap`]). Every format of [`crate::formats`] reads into and
//! writes from a [`Groom`]; [`groom_info`] summarises one.

use std::fmt;

use nalgebra::Vector3;

use crate::error::GroomError;

/// Guide curves in world space, meters, Z up. Every curve has at least 2 points, all finite
/// ([`Groom::new`] checks it).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Groom {
    curves: Vec<Vec<Vector3<f32>>>,
}

impl Groom {
    /// A groom of `curves` (points in meters, root first). Refuses a curve with fewer than 2
    /// points or a non-finite coordinate, naming the curve and point.
    pub fn new(curves: Vec<Vec<Vector3<f32>>>) -> Result<Self, GroomError> {
        for (c, curve) in curves.iter().enumerate() {
            check_curve(c, curve)?;
        }
        Ok(Self { curves })
    }

    /// The curves, root first, meters.
    pub fn curves(&self) -> &[Vec<Vector3<f32>>] {
        &self.curves
    }

    /// Takes the curves out.
    pub fn into_curves(self) -> Vec<Vec<Vector3<f32>>> {
        self.curves
    }

    /// Number of curves.
    pub fn len(&self) -> usize {
        self.curves.len()
    }

    /// Whether the groom has no curve.
    pub fn is_empty(&self) -> bool {
        self.curves.is_empty()
    }

    /// Total number of points over all curves.
    pub fn point_count(&self) -> usize {
        self.curves.iter().map(Vec::len).sum()
    }
}

/// Checks one curve: at least 2 points, every coordinate finite.
pub(crate) fn check_curve(c: usize, curve: &[Vector3<f32>]) -> Result<(), GroomError> {
    if curve.len() < 2 {
        return Err(GroomError::Curve {
            curve: c,
            message: format!(
                "has {} point(s); a curve needs at least 2 (a root and a tip)",
                curve.len()
            ),
        });
    }
    if let Some(i) = curve.iter().position(|p| !p.iter().all(|x| x.is_finite())) {
        return Err(GroomError::Curve {
            curve: c,
            message: format!(
                "point {i} has a non-finite coordinate {:?}; fix or remove the curve",
                curve[i].as_slice()
            ),
        });
    }
    Ok(())
}

/// Length of a polyline, m (sum of its segment lengths, accumulated in f64).
pub(crate) fn polyline_length(points: &[Vector3<f32>]) -> f64 {
    points
        .windows(2)
        .map(|w| f64::from((w[1] - w[0]).norm()))
        .sum()
}

/// A summary of a groom, for `hairsys groom info`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroomInfo {
    /// Number of curves.
    pub strands: usize,
    /// Number of points over all curves.
    pub points: usize,
    /// Fewest points in a curve (0 for an empty groom).
    pub points_min: usize,
    /// Most points in a curve (0 for an empty groom).
    pub points_max: usize,
    /// Shortest curve length, m (0 for an empty groom).
    pub length_min: f64,
    /// Mean curve length, m (0 for an empty groom).
    pub length_mean: f64,
    /// Longest curve length, m (0 for an empty groom).
    pub length_max: f64,
    /// Axis-aligned bounds of all points, m: (lowest corner, highest corner); zeros if empty.
    pub bounds: (Vector3<f32>, Vector3<f32>),
}

/// Summarises `groom`: counts, curve lengths (m) and bounds (m).
pub fn groom_info(groom: &Groom) -> GroomInfo {
    let lengths: Vec<f64> = groom.curves.iter().map(|c| polyline_length(c)).collect();
    let n = lengths.len();
    let (mut lo, mut hi) = (
        Vector3::repeat(f32::INFINITY),
        Vector3::repeat(f32::NEG_INFINITY),
    );
    for p in groom.curves.iter().flatten() {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    if n == 0 {
        (lo, hi) = (Vector3::zeros(), Vector3::zeros());
    }
    let counts = groom.curves.iter().map(Vec::len);
    GroomInfo {
        strands: n,
        points: groom.point_count(),
        points_min: counts.clone().min().unwrap_or(0),
        points_max: counts.max().unwrap_or(0),
        length_min: lengths.iter().copied().reduce(f64::min).unwrap_or(0.0),
        length_mean: if n == 0 {
            0.0
        } else {
            lengths.iter().sum::<f64>() / n as f64
        },
        length_max: lengths.iter().copied().reduce(f64::max).unwrap_or(0.0),
        bounds: (lo, hi),
    }
}

impl fmt::Display for GroomInfo {
    /// Several lines: strands, points, lengths in mm, bounds in m.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (lo, hi) = self.bounds;
        writeln!(f, "strands  {}", self.strands)?;
        writeln!(
            f,
            "points   {} ({}–{} per strand)",
            self.points, self.points_min, self.points_max
        )?;
        writeln!(
            f,
            "length   min {:.1} mm, mean {:.1} mm, max {:.1} mm",
            self.length_min * 1e3,
            self.length_mean * 1e3,
            self.length_max * 1e3
        )?;
        write!(
            f,
            "bounds   ({:.4}, {:.4}, {:.4}) .. ({:.4}, {:.4}, {:.4}) m",
            lo.x, lo.y, lo.z, hi.x, hi.y, hi.z
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn info_counts_and_measures() {
        let g = Groom::new(vec![
            vec![Vector3::zeros(), Vector3::new(0.0, 0.0, 0.1)],
            vec![
                Vector3::new(1.0, 0.0, 0.0),
                Vector3::new(1.0, 0.0, 0.2),
                Vector3::new(1.0, 0.1, 0.2),
            ],
        ])
        .unwrap();
        let info = groom_info(&g);
        assert_eq!((info.strands, info.points), (2, 5));
        assert_eq!((info.points_min, info.points_max), (2, 3));
        assert!((info.length_min - 0.1).abs() < 1e-7);
        assert!((info.length_max - 0.3).abs() < 1e-7);
        assert!((info.length_mean - 0.2).abs() < 1e-7);
        assert_eq!(info.bounds.1, Vector3::new(1.0, 0.1, 0.2));
        assert!(info.to_string().contains("strands  2"));
        assert_eq!(groom_info(&Groom::default()).bounds.0, Vector3::zeros());
    }

    #[test]
    fn short_and_non_finite_curves_are_named() {
        let err = Groom::new(vec![vec![Vector3::zeros()]]).unwrap_err();
        assert!(err.to_string().contains("curve 0") && err.to_string().contains("1 point"));
        let err = Groom::new(vec![
            vec![Vector3::zeros(), Vector3::x()],
            vec![Vector3::zeros(), Vector3::new(f32::NAN, 0.0, 0.0)],
        ])
        .unwrap_err();
        assert!(err.to_string().contains("curve 1: point 1"), "{err}");
    }
}
