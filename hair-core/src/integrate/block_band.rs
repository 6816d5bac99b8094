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
//! chain of three divisions as in the band), the two blocks `B` below it become `W = B L⁻ᵀ` (the
//! band's partly eliminated column entries) and `W D⁻¹` (their `L`), and three blocks of the
//! trailing matrix lose `W D⁻¹ Wᵀ` (the band's `a a / d`): about 160 multiply–adds for 45 block
//! entries loaded and 45 stored. The blocks are not multiplied by the pivot block's explicit
//! inverse: on stiff chains (implicit Euler on the bench's curly hair with physical springs,
//! 700× past the explicit bound) its round-off makes the next pivots garbage and the run
//! non-finite; the form above does the band's operations. The forward substitution runs in
//! the same sweep (the right-hand side's blocks below a finished pivot lose their share at once),
//! so a second sweep does the back substitution alone. On the default scene the strand phase
//! costs a sixth less than with the band (`docs/design/implicit-integrators.md`).
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
/// blocks are overwritten by the factor (`diag` by each pivot block's packed scalar `L D Lᵀ`,
/// see `factor_pivot`; `next` and `skip` by `L`'s blocks); entries of `next` and `skip` reaching past the last point are ignored.
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
        let pivot = factor_pivot(&diag[k], &floors[0]);
        diag[k] = pivot;
        // z(k) = L(k, k)⁻¹ b(k) is final: the rows below lose L(·, k) z(k).
        let z = lower_solve(&pivot, &rhs[k]);
        if k + 1 < n {
            // A(k + 1, k) L(k, k)⁻ᵀ: the band's partly eliminated column entries, and
            // L(k + 1, k) = that times D(k)⁻¹, so the update is W D⁻¹ Wᵀ as the band's a a/d.
            let w1 = eliminated(&pivot, &next[k]);
            let l1 = scaled_columns(&pivot, &w1);
            next[k] = l1;
            rhs[k + 1] -= l1.mul(&z);
            diag[k + 1].sub(&l1.times_transposed_sym(&w1));
            if k + 2 < n {
                floors = [floors[1], pivot_floor(&diag[k + 2])];
                let w2 = eliminated(&pivot, &skip[k]);
                let l2 = scaled_columns(&pivot, &w2);
                skip[k] = l2;
                rhs[k + 2] -= l2.mul(&z);
                next[k + 1].sub(&l2.times_transposed(&w1));
                diag[k + 2].sub(&l2.times_transposed_sym(&w2));
            } else {
                floors = [floors[1], floors[1]];
            }
        }
        rhs[k] = inverse_pivots(&pivot, &z);
    }
    // Back: y(k) = L(k, k)⁻ᵀ (w(k) − L(k + 1, k)ᵀ y(k + 1) − L(k + 2, k)ᵀ y(k + 2)).
    for k in (0..n).rev() {
        let mut u = rhs[k];
        if k + 1 < n {
            u -= next[k].mul_transposed(&rhs[k + 1]);
        }
        if k + 2 < n {
            u -= skip[k].mul_transposed(&rhs[k + 2]);
        }
        rhs[k] = upper_solve(&diag[k], &u);
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

/// The scalar `L D Lᵀ` of the pivot block `d`, each pivot floored at `floor`'s component for
/// its row (module docs), packed in a [`Sym3`]: `xx, yy, zz` the inverse pivots `1/D`, `xy, xz,
/// yz` the unit lower factor's `L(1, 0), L(2, 0), L(2, 1)`.
#[inline(always)]
fn factor_pivot<L: Lane>(d: &Sym3<L>, floor: &V3<L>) -> Sym3<L> {
    let one = splat::<L>(1.0);
    let i0 = one / d.xx.max(floor.x);
    let (l10, l20) = (d.xy * i0, d.xz * i0);
    let i1 = one / (d.yy - l10 * d.xy).max(floor.y);
    // A(2, 1) after the first column: a21 − l20 a10.
    let a21 = d.yz - l20 * d.xy;
    let l21 = a21 * i1;
    let i2 = one / (d.zz - l20 * d.xz - l21 * a21).max(floor.z);
    Sym3 {
        xx: i0,
        yy: i1,
        zz: i2,
        xy: l10,
        xz: l20,
        yz: l21,
    }
}

/// `L⁻¹ v` for the pivot's unit lower factor (packed by [`factor_pivot`]).
#[inline(always)]
fn lower_solve<L: Lane>(p: &Sym3<L>, v: &V3<L>) -> V3<L> {
    let y = v.y - p.xy * v.x;
    V3 {
        x: v.x,
        y,
        z: v.z - p.xz * v.x - p.yz * y,
    }
}

/// `L⁻ᵀ v` for the pivot's unit lower factor (packed by [`factor_pivot`]).
#[inline(always)]
fn upper_solve<L: Lane>(p: &Sym3<L>, v: &V3<L>) -> V3<L> {
    let y = v.y - p.yz * v.z;
    V3 {
        x: v.x - p.xy * y - p.xz * v.z,
        y,
        z: v.z,
    }
}

/// `D⁻¹ v` for the pivot's scalar pivots (packed by [`factor_pivot`]).
#[inline(always)]
fn inverse_pivots<L: Lane>(p: &Sym3<L>, v: &V3<L>) -> V3<L> {
    V3 {
        x: v.x * p.xx,
        y: v.y * p.yy,
        z: v.z * p.zz,
    }
}

/// `B L⁻ᵀ` for a block `B` below the pivot: row `r` is `L⁻¹ b_r`.
#[inline(always)]
fn eliminated<L: Lane>(p: &Sym3<L>, b: &Mat3<L>) -> Mat3<L> {
    Mat3 {
        rows: [
            lower_solve(p, &b.rows[0]),
            lower_solve(p, &b.rows[1]),
            lower_solve(p, &b.rows[2]),
        ],
    }
}

/// `W D⁻¹`: row `r` is `D⁻¹ w_r`.
#[inline(always)]
fn scaled_columns<L: Lane>(p: &Sym3<L>, w: &Mat3<L>) -> Mat3<L> {
    Mat3 {
        rows: [
            inverse_pivots(p, &w.rows[0]),
            inverse_pivots(p, &w.rows[1]),
            inverse_pivots(p, &w.rows[2]),
        ],
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

    /// `A y − b` per point (lane 0) for the blocks of `A` as [`solve_in_place`] takes them.
    fn residuals(
        diag: &[Sym3<Baseline>],
        next: &[Mat3<Baseline>],
        skip: &[Mat3<Baseline>],
        y: &[V3<Baseline>],
        b: &[V3<Baseline>],
    ) -> Vec<nalgebra::Vector3<f32>> {
        let n = diag.len();
        (0..n)
            .map(|i| {
                let mut ay = diag[i].mul(&y[i]);
                if i + 1 < n {
                    ay += next[i].mul_transposed(&y[i + 1]);
                }
                if i + 2 < n {
                    ay += skip[i].mul_transposed(&y[i + 2]);
                }
                if i >= 1 {
                    ay += next[i - 1].mul(&y[i - 1]);
                }
                if i >= 2 {
                    ay += skip[i - 2].mul(&y[i - 2]);
                }
                (ay - b[i]).lane(0)
            })
            .collect()
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
        for (i, r) in residuals(&a_diag, &a_next, &a_skip, &rhs, &b)
            .iter()
            .enumerate()
        {
            assert!(r.norm() < 1e-5, "{n} points: residual {r:?} at block {i}");
        }
    }

    #[test]
    fn solves_random_block_pentadiagonal_systems() {
        for n in [1, 2, 3, 7, 17] {
            solves_random_system(n);
        }
    }

    /// A stiff chain's matrix (springs 10⁶ times the masses, as an implicit substep far past
    /// the explicit bound makes them) is solved with finite values and a backward error within
    /// what f32 allows (a few ε · ‖A‖ · ‖y‖).
    #[test]
    fn stiff_chain_is_solved() {
        let n = 17;
        let k = splat::<Baseline>(1e6);
        let t = V3::splat(&nalgebra::Vector3::new(0.6, 0.0, 0.8));
        let spring = Sym3::iso_outer(splat(0.0), k, &t);
        let mut diag: Vec<Sym3<Baseline>> = (0..n)
            .map(|i| {
                let mut d = Sym3::iso_outer(splat(1.0), splat(0.0), &t);
                d.add(&spring);
                if i + 1 < n {
                    d.add(&spring);
                }
                d
            })
            .collect();
        let mut next: Vec<Mat3<Baseline>> = (0..n)
            .map(|_| Mat3::from_sym(&spring.scaled(splat(-1.0))))
            .collect();
        let mut skip = vec![Mat3::default(); n];
        let seed = &mut 99u32;
        let mut rhs: Vec<V3<Baseline>> = (0..n).map(|_| random_v3(seed)).collect();
        let (a_diag, a_next, b) = (diag.clone(), next.clone(), rhs.clone());
        solve_in_place(&mut diag, &mut next, &mut skip, &mut rhs);
        let y_max = rhs.iter().map(|y| y.lane(0).amax()).fold(0.0f32, f32::max);
        assert!(y_max.is_finite());
        // ‖A‖∞ ≤ 1 + 4 · 10⁶ per row.
        let tolerance = 8.0 * f32::EPSILON * 4e6 * y_max;
        let a_skip = vec![Mat3::default(); n];
        for (i, r) in residuals(&a_diag, &a_next, &a_skip, &rhs, &b)
            .iter()
            .enumerate()
        {
            assert!(r.amax() < tolerance, "residual {r:?} at block {i}");
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
