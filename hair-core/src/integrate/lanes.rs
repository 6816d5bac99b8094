//! Eight strands side by side: the lane types of the solver kernel.
//!
//! The kernel advances [`LANES`] strands with the same number of points at once, one strand per
//! SIMD lane, so every pass — including the sequential frame transport down a strand — runs on
//! eight strands per instruction. It is written once over the [`Lane`] trait and compiled for two
//! lane types:
//!
//! - [`Baseline`] (`wide::f32x8`): explicit SIMD chosen when the crate is compiled — two 128-bit
//!   halves (SSE2 on x86-64, NEON on aarch64) unless `-C target-cpu` allows more;
//! - [`F8`] (see [`super::f32_lanes`]): a plain array the compiler widens to whole 256-bit
//!   registers in the copy of the kernel compiled for AVX2, chosen at run time on CPUs that have
//!   it ([`super::kernel::wide_registers`]).
//!
//! Both do the same IEEE-754 operation per lane, so they give the same bits. [`V3`] is a 3-vector
//! of lanes.

use std::fmt::Debug;
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub, SubAssign};

use nalgebra::Vector3;

pub(crate) use super::f32_lanes::F8;

/// Strands advanced together.
pub(crate) const LANES: usize = 8;

/// The lane type of CPUs without a wider kernel copy.
pub(crate) type Baseline = wide::f32x8;

/// One f32 per strand of a group, with the operations the kernel needs. Every operation is the
/// IEEE-754 operation of its scalar form, lane by lane.
pub(crate) trait Lane:
    Copy
    + Default
    + Debug
    + Send
    + Sync
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
{
    /// The result of a lane-wise comparison.
    type Mask: Copy;
    /// `f` in every lane.
    fn splat(f: f32) -> Self;
    /// The given lane values.
    fn new(lanes: [f32; LANES]) -> Self;
    /// The lane values.
    fn to_array(self) -> [f32; LANES];
    /// Square root (correctly rounded).
    fn sqrt(self) -> Self;
    /// Absolute value.
    fn abs(self) -> Self;
    /// Larger value; a NaN lane takes the other operand, and of `−0` and `+0` the second is
    /// returned (`wide`'s x86 semantics).
    fn max(self, o: Self) -> Self;
    /// Smaller value; a NaN lane takes the other operand, and of `−0` and `+0` the second is
    /// returned (`wide`'s x86 semantics).
    fn min(self, o: Self) -> Self;
    /// Lanes where `self > o`.
    fn simd_gt(self, o: Self) -> Self::Mask;
    /// Lanes where `self < o`.
    fn simd_lt(self, o: Self) -> Self::Mask;
    /// `a` where `mask` is set, `b` elsewhere.
    fn select(mask: Self::Mask, a: Self, b: Self) -> Self;
    /// Is any lane of `mask` set?
    fn any(mask: Self::Mask) -> bool;
}

impl Lane for wide::f32x8 {
    type Mask = wide::f32x8;
    #[inline(always)]
    fn splat(f: f32) -> Self {
        wide::f32x8::splat(f)
    }
    #[inline(always)]
    fn new(lanes: [f32; LANES]) -> Self {
        wide::f32x8::new(lanes)
    }
    #[inline(always)]
    fn to_array(self) -> [f32; LANES] {
        wide::f32x8::to_array(self)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        wide::f32x8::sqrt(self)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        wide::f32x8::abs(self)
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        wide::f32x8::max(self, o)
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        wide::f32x8::min(self, o)
    }
    #[inline(always)]
    fn simd_gt(self, o: Self) -> Self {
        wide::f32x8::simd_gt(self, o)
    }
    #[inline(always)]
    fn simd_lt(self, o: Self) -> Self {
        wide::f32x8::simd_lt(self, o)
    }
    #[inline(always)]
    fn select(mask: Self, a: Self, b: Self) -> Self {
        mask.select(a, b)
    }
    #[inline(always)]
    fn any(mask: Self) -> bool {
        wide::f32x8::any(mask)
    }
}

/// `f` in every lane.
#[inline(always)]
pub(crate) fn splat<L: Lane>(f: f32) -> L {
    L::splat(f)
}

/// Sets `buf` to `len` default (zero) values, keeping its allocation.
///
/// The stores are a plain loop inlined into the caller, so they run in the caller's (AVX2)
/// code; `Vec::resize` writes each value through an out-of-line clone, which costs a sixth of the
/// implicit substep on the default scene when its 288-byte blocks are zeroed that way.
#[inline(always)]
pub(crate) fn zeroed<T: Copy + Default>(buf: &mut Vec<T>, len: usize) {
    if buf.len() != len {
        buf.resize(len, T::default());
    }
    for b in buf.iter_mut() {
        *b = T::default();
    }
}

/// `a / b` where `b > eps`, else `0` (masked lanes never see a division by zero's result).
#[inline(always)]
pub(crate) fn div_or_zero<L: Lane>(a: L, b: L, eps: f32) -> L {
    L::select(b.simd_gt(L::splat(eps)), a / b, L::splat(0.0))
}

/// A 3-vector with one component per lane.
#[derive(Clone, Copy, Default, Debug, PartialEq)]
pub(crate) struct V3<L = Baseline> {
    pub x: L,
    pub y: L,
    pub z: L,
}

impl<L: Lane> V3<L> {
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
    pub fn dot(&self, o: &Self) -> L {
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
            x: L::new(v.map(|p| p.x)),
            y: L::new(v.map(|p| p.y)),
            z: L::new(v.map(|p| p.z)),
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
    pub fn select(mask: L::Mask, a: &Self, b: &Self) -> Self {
        Self {
            x: L::select(mask, a.x, b.x),
            y: L::select(mask, a.y, b.y),
            z: L::select(mask, a.z, b.z),
        }
    }
}

impl<L: Lane> Add for V3<L> {
    type Output = V3<L>;
    #[inline(always)]
    fn add(self, o: V3<L>) -> V3<L> {
        V3 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
}

impl<L: Lane> Sub for V3<L> {
    type Output = V3<L>;
    #[inline(always)]
    fn sub(self, o: V3<L>) -> V3<L> {
        V3 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
}

impl<L: Lane> Neg for V3<L> {
    type Output = V3<L>;
    #[inline(always)]
    fn neg(self) -> V3<L> {
        V3 {
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
}

impl<L: Lane> Mul<L> for V3<L> {
    type Output = V3<L>;
    #[inline(always)]
    fn mul(self, s: L) -> V3<L> {
        V3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
}

impl<L: Lane> AddAssign for V3<L> {
    #[inline(always)]
    fn add_assign(&mut self, o: V3<L>) {
        *self = *self + o;
    }
}

impl<L: Lane> SubAssign for V3<L> {
    #[inline(always)]
    fn sub_assign(&mut self, o: V3<L>) {
        *self = *self - o;
    }
}

/// A rotation matrix per lane (columns).
#[derive(Clone, Copy, Default)]
pub(crate) struct M3<L> {
    pub cols: [V3<L>; 3],
}

impl<L: Lane> M3<L> {
    /// `R v`.
    #[inline(always)]
    pub fn mul(&self, v: &V3<L>) -> V3<L> {
        self.cols[0] * v.x + self.cols[1] * v.y + self.cols[2] * v.z
    }
}

/// A unit quaternion per lane `(w, i, j, k)`.
#[derive(Clone, Copy, Default)]
pub(crate) struct Q4<L> {
    pub w: L,
    pub i: L,
    pub j: L,
    pub k: L,
}

impl<L: Lane> Q4<L> {
    /// Normalised linear interpolation `nlerp(a, b, s)` (what `RootFrame::interpolate` does).
    #[inline(always)]
    pub fn nlerp(a: &Self, b: &Self, s: f32) -> Self {
        let (s, r) = (splat::<L>(s), splat::<L>(1.0 - s));
        let q = Q4 {
            w: a.w * r + b.w * s,
            i: a.i * r + b.i * s,
            j: a.j * r + b.j * s,
            k: a.k * r + b.k * s,
        };
        let inv = splat::<L>(1.0) / (q.w * q.w + q.i * q.i + q.j * q.j + q.k * q.k).sqrt();
        Q4 {
            w: q.w * inv,
            i: q.i * inv,
            j: q.j * inv,
            k: q.k * inv,
        }
    }

    /// The rotation matrix of this unit quaternion.
    #[inline(always)]
    pub fn matrix(&self) -> M3<L> {
        let (w, x, y, z) = (self.w, self.i, self.j, self.k);
        let two = splat::<L>(2.0);
        let one = splat::<L>(1.0);
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

    fn quaternion_matrix<L: Lane>() {
        let qs: [UnitQuaternion<f32>; LANES] = std::array::from_fn(|l| {
            UnitQuaternion::from_euler_angles(0.3 * l as f32, -0.2, 0.1 * l as f32)
        });
        let q = Q4 {
            w: L::new(qs.map(|q| q.w)),
            i: L::new(qs.map(|q| q.i)),
            j: L::new(qs.map(|q| q.j)),
            k: L::new(qs.map(|q| q.k)),
        };
        let v = V3::<L>::splat(&Vector3::new(0.3, -1.0, 2.0));
        let got = q.matrix().mul(&v).to_lanes();
        for l in 0..LANES {
            assert!((got[l] - qs[l] * Vector3::new(0.3, -1.0, 2.0)).norm() < 1e-5);
        }
    }

    #[test]
    fn quaternion_matrix_matches_nalgebra() {
        quaternion_matrix::<Baseline>();
        quaternion_matrix::<F8>();
    }

    fn masked_division<L: Lane>() {
        let r = div_or_zero(
            splat::<L>(1.0),
            L::new([0.0, 2.0, 0.0, 4.0, 1.0, 1.0, 1.0, 1.0]),
            1e-6,
        );
        assert_eq!(r.to_array()[..4], [0.0, 0.5, 0.0, 0.25]);
    }

    #[test]
    fn division_is_masked() {
        masked_division::<Baseline>();
        masked_division::<F8>();
    }

    /// Both lane types give the same bits for every operation, NaN handling of max/min
    /// included.
    #[test]
    fn lane_types_agree_bit_for_bit() {
        let a = [1.0, -2.0, 3.5, 0.0, -0.0, 9.0, f32::NAN, 1e-30];
        let b = [2.0, 2.0, -7.25, f32::NAN, 0.0, 1e30, 3.0, 3.0];
        fn ops<L: Lane>(a: [f32; LANES], b: [f32; LANES]) -> Vec<[f32; LANES]> {
            let (a, b) = (L::new(a), L::new(b));
            vec![
                (a + b).to_array(),
                (a - b).to_array(),
                (a * b).to_array(),
                (a / b).to_array(),
                (-a).to_array(),
                a.abs().sqrt().to_array(),
                a.max(b).to_array(),
                a.min(b).to_array(),
                b.max(a).to_array(),
                L::select(a.simd_gt(b), a, b).to_array(),
                L::select(a.simd_lt(b), a, b).to_array(),
            ]
        }
        let bits = |v: Vec<[f32; LANES]>| -> Vec<u32> {
            v.iter().flatten().map(|f| f.to_bits()).collect()
        };
        assert_eq!(bits(ops::<Baseline>(a, b)), bits(ops::<F8>(a, b)));
        assert!(!Baseline::any(Lane::simd_lt(
            splat::<Baseline>(1.0),
            splat(0.0)
        )));
        assert!(F8::any(F8::new(a).simd_gt(splat(8.0))));
    }
}
