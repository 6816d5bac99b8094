//! The implicit substep's direct solve: block `L D Lᵀ` of a symmetric positive definite
//! block-pentadiagonal matrix with 3×3 blocks (a strand's points coupled up to two apart), eight
//! strands per SIMD lane like the rest of the kernel.
//!
//! # Why blocks, not the scalar band
//!
//! The same matrix is a scalar band of half-width 8 over the `3n` velocity components, which a
//! column-by-column band `L D Lᵀ` ([`super::band`], XPBD's solver) factors too. There each
//! column's update rewrites up to 36 entries of the trailing window in memory: per point about
//! 130 loads and as many stores for as many multiply–adds, after the matrix has been copied from
//! its blocks into band rows. Eliminating a point's three columns at once keeps the work in the
//! blocks the assembly wrote: the pivot block is factored in registers (three scalar pivots, a
//! chain of three divisions as in the band), the two blocks below it are multiplied by its
//! inverse, and three blocks of the trailing matrix are updated by 3×3 products: about 160
//! multiply–adds for 45 block entries loaded and 45 stored. The forward substitution runs in
//! the same sweep (the right-hand side's blocks below a finished pivot lose their share at once),
//! so a second sweep does the back substitution alone. On the default scene this made the strand
//! phase a sixth cheaper than the band did (`BENCHMARKS.md`, session 22).
//!
//! # The pivots
//!
//! In exact arithmetic the block factor's three scalar pivots per point are the band's (block
//! elimination is column elimination grouped by three). The implicit matrix is the masses plus
//! positive semi-definite stiffness and damping (kinematic rows the identity), so no pivot falls
//! below the smallest mass; the band's safeguard is kept as a guard against round-off all the
//! same: a pivot below `10⁻⁶` of its row's diagonal as assembled takes that floor, and the solve
//! stays finite.

use super::blocks::{Mat3, Sym3};
use super::lanes::{splat, Lane, V3};

/// Fraction of a row's assembled diagonal below which a pivot is floored (module docs).
const PIVOT_FLOOR: f32 = 1e-6;

/// Solves `A y = b` for the symmetric block-pentadiagonal `A` given by its lower blocks —
/// `diag[i]` the block `(i, i)`, `next[i]` the block `(i + 1, i)`, `skip[i]` the block
/// `(i + 2, i)` (their transposes are the upper blocks) — with `b` in `rhs` and `y` out. The
/// blocks are overwritten by the factor (`diag` by the inverse pivot blocks, `next` and `skip`
/// by `L`'s blocks); entries of `next` and `skip` reaching past the last point are ignored.
#[inline(always)]
pub(super) fn solve_in_place<L: Lane>(
    diag: &mut [Sym3<L>],
    next: &mut [Mat3<L>],
    skip: &mut [Mat3<L>],
    rhs: &mut [V3<L>],
) {
    let n = diag.len();
    debug_assert!(next.len() >= n && skip.len() >= n && rhs.len() >= n);
    // The floors of points k, k + 1 (k + 2 is taken before its first update, at step k).
    let mut floors = [
        pivot_floor(&diag[0]),
        if n > 1 {
            pivot_floor(&diag[1])
        } else {
            V3::default()
        },
    ];
    for k in 0..n {
        let inv = invert_pivot(&diag[k], &floors[0]);
        diag[k] = inv;
        // z(k) is final: the rows below lose L(·, k) z(k).
        let z = rhs[k];
        if k + 1 < n {
            let b1 = next[k];
            let l1 = b1.times_sym(&inv);
            next[k] = l1;
            rhs[k + 1] -= l1.mul(&z);
            diag[k + 1].sub(&l1.times_transposed_sym(&b1));
            if k + 2 < n {
                floors = [floors[1], pivot_floor(&diag[k + 2])];
                let b2 = skip[k];
                let l2 = b2.times_sym(&inv);
                skip[k] = l2;
                rhs[k + 2] -= l2.mul(&z);
                next[k + 1].sub(&l2.times_transposed(&b1));
                diag[k + 2].sub(&l2.times_transposed_sym(&b2));
            } else {
                floors = [floors[1], floors[1]];
            }
        }
        rhs[k] = inv.mul(&z);
    }
    // Back: y(k) = w(k) − L(k + 1, k)ᵀ y(k + 1) − L(k + 2, k)ᵀ y(k + 2).
    for k in (0..n).rev() {
        let mut y = rhs[k];
        if k + 1 < n {
            y -= next[k].mul_transposed(&rhs[k + 1]);
        }
        if k + 2 < n {
            y -= skip[k].mul_transposed(&rhs[k + 2]);
        }
        rhs[k] = y;
    }
}

/// The floors of the three pivots of a point whose assembled diagonal block is `d` (module
/// docs). (A function, not a closure: closures are not compiled for the kernel's AVX2.)
#[inline(always)]
fn pivot_floor<L: Lane>(d: &Sym3<L>) -> V3<L> {
    let f = splat::<L>(PIVOT_FLOOR);
    V3 {
        x: d.xx * f,
        y: d.yy * f,
        z: d.zz * f,
    }
}

/// The inverse of the symmetric pivot block `d` from its scalar `L D Lᵀ`, each pivot floored at
/// `floor`'s component for its row (module docs).
#[inline(always)]
fn invert_pivot<L: Lane>(d: &Sym3<L>, floor: &V3<L>) -> Sym3<L> {
    let one = splat::<L>(1.0);
    let d0 = d.xx.max(floor.x);
    let i0 = one / d0;
    let (l10, l20) = (d.xy * i0, d.xz * i0);
    let d1 = (d.yy - l10 * d.xy).max(floor.y);
    let i1 = one / d1;
    // A(2, 1) after the first column: a21 − l20 a10.
    let a21 = d.yz - l20 * d.xy;
    let l21 = a21 * i1;
    let d2 = (d.zz - l20 * d.xz - l21 * a21).max(floor.z);
    let i2 = one / d2;
    // L⁻¹ = [[1, 0, 0], [m10, 1, 0], [m20, m21, 1]]; D⁻¹ of the block = L⁻ᵀ diag(i) L⁻¹.
    let (m10, m21) = (L::default() - l10, L::default() - l21);
    let m20 = l10 * l21 - l20;
    let (i2m20, i2m21) = (i2 * m20, i2 * m21);
    Sym3 {
        xx: i0 + i1 * m10 * m10 + i2m20 * m20,
        yy: i1 + i2m21 * m21,
        zz: i2,
        xy: i1 * m10 + i2m20 * m21,
        xz: i2m20,
        yz: i2m21,
    }
}

#[cfg(test)]
mod tests {
    use super::super::lanes::Baseline;
    use super::*;

    /// A pseudo-random number in [−0.5, 0.5) in every lane, from a linear congruential `seed`.
    fn random(seed: &mut u32) -> Baseline {
        *seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
        splat((*seed >> 8) as f32 / (1u32 << 24) as f32 - 0.5)
    }

    /// A random vector.
    fn random_v3(seed: &mut u32) -> V3<Baseline> {
        V3 {
            x: random(seed),
            y: random(seed),
            z: random(seed),
        }
    }

    /// A random symmetric positive definite block-pentadiagonal system of `n` points
    /// (unsymmetric off-diagonal blocks, each appearing transposed above the diagonal), solved by
    /// [`solve_in_place`], satisfies `A y = b` (multiplied back with the blocks).
    fn solves_random_system(n: usize) {
        let seed = &mut 12345u32;
        let mut diag: Vec<Sym3<Baseline>> = (0..n)
            .map(|_| {
                let ([xx, yy, zz], [xy, xz, yz]) = (
                    [random(seed), random(seed), random(seed)],
                    [random(seed), random(seed), random(seed)],
                );
                Sym3 {
                    xx,
                    yy,
                    zz,
                    xy,
                    xz,
                    yz,
                }
            })
            .collect();
        let mut full = || Mat3 {
            rows: [random_v3(seed), random_v3(seed), random_v3(seed)],
        };
        let mut next: Vec<Mat3<Baseline>> = (0..n).map(|_| full()).collect();
        let mut skip: Vec<Mat3<Baseline>> = (0..n).map(|_| full()).collect();
        // Diagonally dominant, so positive definite.
        for d in &mut diag {
            d.add_diagonal(splat(6.0));
        }
        let mut rhs: Vec<V3<Baseline>> = (0..n).map(|_| random_v3(seed)).collect();
        let (a_diag, a_next, a_skip, b) = (diag.clone(), next.clone(), skip.clone(), rhs.clone());
        solve_in_place(&mut diag, &mut next, &mut skip, &mut rhs);
        let y = rhs;
        for i in 0..n {
            let mut ay = a_diag[i].mul(&y[i]);
            if i + 1 < n {
                ay += a_next[i].mul_transposed(&y[i + 1]);
            }
            if i >= 1 {
                ay += a_next[i - 1].mul(&y[i - 1]);
            }
            if i + 2 < n {
                ay += a_skip[i].mul_transposed(&y[i + 2]);
            }
            if i >= 2 {
                ay += a_skip[i - 2].mul(&y[i - 2]);
            }
            let r = (ay - b[i]).lane(0);
            assert!(r.norm() < 1e-5, "{n} points: residual {r:?} at block {i}");
        }
    }

    #[test]
    fn solves_random_block_pentadiagonal_systems() {
        for n in [1, 2, 3, 7, 17] {
            solves_random_system(n);
        }
    }

    /// The pivot block's inverse is the inverse: `S S⁻¹ = I` for a well-conditioned `S`.
    #[test]
    fn pivot_inverse_inverts() {
        let s = Sym3::<Baseline> {
            xx: splat(4.0),
            yy: splat(3.0),
            zz: splat(5.0),
            xy: splat(1.0),
            xz: splat(-0.5),
            yz: splat(0.75),
        };
        let inv = invert_pivot(&s, &V3::default());
        for axis in 0..3 {
            let e = V3::<Baseline>::splat(&nalgebra::Vector3::ith(axis, 1.0));
            let back = s.mul(&inv.mul(&e)).lane(0);
            let expected = nalgebra::Vector3::<f32>::ith(axis, 1.0);
            assert!((back - expected).norm() < 1e-6, "{back:?}");
        }
    }

    /// A matrix singular along one direction (rank-deficient in round-off) gives a finite
    /// solve: the floored pivot stands in for the zero one.
    #[test]
    fn singular_matrix_gives_a_finite_solution() {
        // One point, its block t tᵀ + e_z e_zᵀ for t = (1, 1, 0)/√2: the second pivot is 0.
        let h = splat::<Baseline>(0.5);
        let mut diag = [Sym3 {
            xx: h,
            yy: h,
            zz: splat(1.0),
            xy: h,
            xz: splat(0.0),
            yz: splat(0.0),
        }];
        let mut next = [Mat3::default()];
        let mut skip = [Mat3::default()];
        let mut rhs = [V3::splat(&nalgebra::Vector3::new(1.0, 1.0, 1.0))];
        solve_in_place(&mut diag, &mut next, &mut skip, &mut rhs);
        let y = rhs[0].lane(0);
        assert!(y.iter().all(|c| c.is_finite()), "{y:?}");
    }
}
