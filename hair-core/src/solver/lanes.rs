//! Eight strands side by side: the lane types of the solver kernel.
//!
//! The kernel advances [`LANES`] strands with the same number of points at once, one strand per
//! SIMD lane (`wide::f32x8`), so every pass — including the sequential frame transport down a
//! strand — runs on eight strands per instruction. [`V3`] is a 3-vector of lanes.

use std::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

use nalgebra::Vector3;
use wide::f32x8;

/// Strands advanced together.
pub(crate) const LANES: usize = 8;

/// One f32 per strand of a group.
pub(crate) type F = f32x8;

/// `f` in every lane.
#[inline(always)]
pub(crate) fn splat(f: f32) -> F {
    F::splat(f)
}

/// `a / b` where `b > eps`, else `0` (masked lanes never see a division by zero's result).
#[inline(always)]
pub(crate) fn div_or_zero(a: F, b: F, eps: f32) -> F {
    b.simd_gt(splat(eps)).select(a / b, splat(0.0))
}

/// A 3-vector with one component per lane.
#[derive(Clone, Copy, Default, Debug, PartialEq)]
pub(crate) struct V3 {
    pub x: F,
    pub y: F,
    pub z: F,
}

impl V3 {
    /// The same vector in every lane.
    #[inline(always)]
    pub fn splat(v: &Vector3<f32>) -> Self {
        Self {
            x: splat(v.x),
            y: splat(v.y),
            z: splat(v.z),
        }
    }

    #[inline(always)]
    pub fn dot(&self, o: &Self) -> F {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    #[inline(always)]
    pub fn cross(&self, o: &Self) -> Self {
        Self {
            x: self.y * o.z - self.z * o.y,
            y: self.z * o.x - self.x * o.z,
            z: self.x * o.y - self.y * o.x,
        }
    }

    /// Lane `l` as a nalgebra vector.
    #[cfg(test)]
    pub fn lane(&self, l: usize) -> Vector3<f32> {
        Vector3::new(
            self.x.to_array()[l],
            self.y.to_array()[l],
            self.z.to_array()[l],
        )
    }

    /// Builds lanes from eight vectors.
    #[inline(always)]
    pub fn from_lanes(v: &[Vector3<f32>; LANES]) -> Self {
        Self {
            x: F::new(v.map(|p| p.x)),
            y: F::new(v.map(|p| p.y)),
            z: F::new(v.map(|p| p.z)),
        }
    }

    /// Each lane's vector as an array.
    #[inline(always)]
    pub fn to_lanes(self) -> [Vector3<f32>; LANES] {
        let (x, y, z) = (self.x.to_array(), self.y.to_array(), self.z.to_array());
        std::array::from_fn(|l| Vector3::new(x[l], y[l], z[l]))
    }

    /// Lanes where `mask` is set take `a`, the others `b`.
    #[inline(always)]
    pub fn select(mask: F, a: &Self, b: &Self) -> Self {
        Self {
            x: mask.select(a.x, b.x),
            y: mask.select(a.y, b.y),
            z: mask.select(a.z, b.z),
        }
    }
}

impl Add for V3 {
    type Output = V3;
    #[inline(always)]
    fn add(self, o: V3) -> V3 {
        V3 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
}

impl Sub for V3 {
    type Output = V3;
    #[inline(always)]
    fn sub(self, o: V3) -> V3 {
        V3 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
}

impl Neg for V3 {
    type Output = V3;
    #[inline(always)]
    fn neg(self) -> V3 {
        V3 {
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
}

impl Mul<F> for V3 {
    type Output = V3;
    #[inline(always)]
    fn mul(self, s: F) -> V3 {
        V3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
}

impl AddAssign for V3 {
    #[inline(always)]
    fn add_assign(&mut self, o: V3) {
        *self = *self + o;
    }
}

impl SubAssign for V3 {
    #[inline(always)]
    fn sub_assign(&mut self, o: V3) {
        *self = *self - o;
    }
}

/// A rotation matrix per lane (columns).
#[derive(Clone, Copy, Default)]
pub(crate) struct M3 {
    pub cols: [V3; 3],
}

impl M3 {
    /// `R v`.
    #[inline(always)]
    pub fn mul(&self, v: &V3) -> V3 {
        self.cols[0] * v.x + self.cols[1] * v.y + self.cols[2] * v.z
    }
}

/// A unit quaternion per lane `(w, i, j, k)`.
#[derive(Clone, Copy, Default)]
pub(crate) struct Q4 {
    pub w: F,
    pub i: F,
    pub j: F,
    pub k: F,
}

impl Q4 {
    /// Normalised linear interpolation `nlerp(a, b, s)` (what `RootFrame::interpolate` does).
    #[inline(always)]
    pub fn nlerp(a: &Q4, b: &Q4, s: f32) -> Q4 {
        let (s, r) = (splat(s), splat(1.0 - s));
        let q = Q4 {
            w: a.w * r + b.w * s,
            i: a.i * r + b.i * s,
            j: a.j * r + b.j * s,
            k: a.k * r + b.k * s,
        };
        let inv = splat(1.0) / (q.w * q.w + q.i * q.i + q.j * q.j + q.k * q.k).sqrt();
        Q4 {
            w: q.w * inv,
            i: q.i * inv,
            j: q.j * inv,
            k: q.k * inv,
        }
    }

    /// The rotation matrix of this unit quaternion.
    #[inline(always)]
    pub fn matrix(&self) -> M3 {
        let (w, x, y, z) = (self.w, self.i, self.j, self.k);
        let two = splat(2.0);
        let one = splat(1.0);
        M3 {
            cols: [
                V3 {
                    x: one - two * (y * y + z * z),
                    y: two * (x * y + w * z),
                    z: two * (x * z - w * y),
                },
                V3 {
                    x: two * (x * y - w * z),
                    y: one - two * (x * x + z * z),
                    z: two * (y * z + w * x),
                },
                V3 {
                    x: two * (x * z + w * y),
                    y: two * (y * z - w * x),
                    z: one - two * (x * x + y * y),
                },
            ],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::UnitQuaternion;

    #[test]
    fn quaternion_matrix_matches_nalgebra() {
        let qs: [UnitQuaternion<f32>; LANES] = std::array::from_fn(|l| {
            UnitQuaternion::from_euler_angles(0.3 * l as f32, -0.2, 0.1 * l as f32)
        });
        let q = Q4 {
            w: F::new(qs.map(|q| q.w)),
            i: F::new(qs.map(|q| q.i)),
            j: F::new(qs.map(|q| q.j)),
            k: F::new(qs.map(|q| q.k)),
        };
        let v = V3::splat(&Vector3::new(0.3, -1.0, 2.0));
        let got = q.matrix().mul(&v).to_lanes();
        for l in 0..LANES {
            assert!((got[l] - qs[l] * Vector3::new(0.3, -1.0, 2.0)).norm() < 1e-5);
        }
    }

    #[test]
    fn division_is_masked() {
        let r = div_or_zero(
            splat(1.0),
            F::new([0.0, 2.0, 0.0, 4.0, 1.0, 1.0, 1.0, 1.0]),
            1e-6,
        );
        assert_eq!(r.to_array()[..4], [0.0, 0.5, 0.0, 0.25]);
    }
}
