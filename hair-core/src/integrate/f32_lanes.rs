//! [`F8`]: eight `f32` lanes as a plain array, widened to the CPU's SIMD registers by the
//! compiler.
//!
//! `wide::f32x8` ([`super::lanes::Baseline`]) picks its instructions when the crate is compiled:
//! without `-C target-cpu` flags that is two 128-bit SSE halves, even on CPUs with 256-bit AVX.
//! Every operation here is a loop over the eight lanes of an array instead, marked
//! `inline(always)`, so inside the kernel copy compiled for AVX2 ([`super::kernel`]) each
//! operation becomes one 256-bit instruction. (Compiled for plain SSE2 the same loops vectorise
//! worse than `wide`'s explicit halves — about 1.4× slower — so the baseline keeps `wide`.)
//!
//! Each lane does exactly the IEEE-754 operation its scalar form does (no fused multiply–add, no
//! approximate reciprocals), so the two lane types give the same bits
//! (`lanes::tests::lane_types_agree_bit_for_bit`).

use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use super::lanes::{Lane, LANES};

/// One `f32` per strand of a group of eight.
#[derive(Clone, Copy, Default, Debug, PartialEq)]
#[repr(C, align(32))]
pub(crate) struct F8([f32; LANES]);

/// A lane mask from a comparison of two [`F8`]: all bits set where true, none where false.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub(crate) struct Mask([u32; LANES]);

impl F8 {
    #[inline(always)]
    fn map(self, f: impl Fn(f32) -> f32) -> Self {
        Self(std::array::from_fn(|l| f(self.0[l])))
    }

    #[inline(always)]
    fn zip(self, o: Self, f: impl Fn(f32, f32) -> f32) -> Self {
        Self(std::array::from_fn(|l| f(self.0[l], o.0[l])))
    }

    #[inline(always)]
    fn compare(self, o: Self, f: impl Fn(f32, f32) -> bool) -> Mask {
        Mask(std::array::from_fn(|l| {
            if f(self.0[l], o.0[l]) {
                u32::MAX
            } else {
                0
            }
        }))
    }
}

impl Lane for F8 {
    type Mask = Mask;
    #[inline(always)]
    fn splat(f: f32) -> Self {
        Self([f; LANES])
    }
    #[inline(always)]
    fn new(lanes: [f32; LANES]) -> Self {
        Self(lanes)
    }
    #[inline(always)]
    fn to_array(self) -> [f32; LANES] {
        self.0
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        self.map(f32::sqrt)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        self.map(f32::abs)
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        self.zip(o, |a, b| if b.is_nan() || a > b { a } else { b })
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        self.zip(o, |a, b| if b.is_nan() || a < b { a } else { b })
    }
    #[inline(always)]
    fn simd_gt(self, o: Self) -> Mask {
        self.compare(o, |a, b| a > b)
    }
    #[inline(always)]
    fn simd_lt(self, o: Self) -> Mask {
        self.compare(o, |a, b| a < b)
    }
    #[inline(always)]
    fn select(mask: Mask, a: Self, b: Self) -> Self {
        Self(std::array::from_fn(|l| {
            let m = mask.0[l];
            f32::from_bits((a.0[l].to_bits() & m) | (b.0[l].to_bits() & !m))
        }))
    }
    #[inline(always)]
    fn any(mask: Mask) -> bool {
        mask.0.iter().fold(0, |acc, &m| acc | m) != 0
    }
}

macro_rules! lanewise {
    ($op:ident, $method:ident, $assign:ident, $assign_method:ident) => {
        impl $op for F8 {
            type Output = F8;
            #[inline(always)]
            fn $method(self, o: F8) -> F8 {
                self.zip(o, |a, b| $op::$method(a, b))
            }
        }
        impl $assign for F8 {
            #[inline(always)]
            fn $assign_method(&mut self, o: F8) {
                *self = $op::$method(*self, o);
            }
        }
    };
}

lanewise!(Add, add, AddAssign, add_assign);
lanewise!(Sub, sub, SubAssign, sub_assign);
lanewise!(Mul, mul, MulAssign, mul_assign);
lanewise!(Div, div, DivAssign, div_assign);

impl Neg for F8 {
    type Output = F8;
    #[inline(always)]
    fn neg(self) -> F8 {
        self.map(|a| -a)
    }
}
