//! A symmetric positive definite banded system `A y = b` solved directly by a band `L D Lᵀ`
//! factorisation, one strand per SIMD lane: the XPBD substep's solve.
//!
//! XPBD ([`super::xpbd`]) reduces a strand's step to a banded system in the constraint
//! multipliers (bending and stretch, 4×4 blocks, half-width 11), because a strand is a chain and
//! its constraints couple only points a few apart. Dense elimination would cost `O(n³)`; keeping
//! the factor inside the band costs `n · W²/2` multiply–adds for `W − 1` the half-width (Golub
//! and Van Loan, *Matrix Computations*, §4.3.5), linear in the strand's length, and each
//! operation advances the eight strands of a group at once like the rest of the kernel. (The
//! implicit integrators' block-pentadiagonal system is factored on its 3×3 blocks instead,
//! [`super::block_band`], which moves a third of the data this column-by-column form does.)
//!
//! # Why right-looking `L D Lᵀ`
//!
//! Each lane is one strand, so there is no parallelism across strands left for the CPU to find:
//! what limits the factorisation is the longest chain of dependent operations, not their count.
//! A row-by-row (left-looking) Cholesky computes each entry of a row from the one before it
//! through a dot product, and takes a square root and a division per row: about 200 cycles of
//! latency per row of a half-width-8 band, most of the implicit substep. Eliminating column by
//! column instead (right-looking), the `W(W − 1)/2` updates of the trailing window are
//! independent of one another, and the chain from one pivot to the next is one division, one
//! multiplication and one multiply–subtract; `L D Lᵀ` (unit `L`) needs no square root. The
//! substitutions are ordered the same way: each solved unknown is subtracted from the rows below
//! it at once (forward), and each row's dot product adds its newest term last (back).
//!
//! Storage: row `r` holds `W` entries, entry `d` is `A(r, r − d)` (the lower band, diagonal
//! first), overwritten by `L(r, r − d)` below the diagonal and `D(r)` on it, with `A = L D Lᵀ`.
//!
//! A pivot that falls below `10⁻⁶` of its row's diagonal (a matrix singular in f32 round-off, as
//! a straight joint's curvature constraint is along its own tangent when the joint is very stiff
//! for the step) takes that floor: the solve stays finite, and the solution is that of a matrix
//! changed by less than the round-off already in it.

use super::lanes::{splat, Lane};

/// The band `L D Lᵀ` factor of a symmetric positive definite matrix whose entries vanish more
/// than `W − 1` rows off the diagonal, per lane.
#[derive(Default)]
pub(crate) struct BandLdlt<L: Lane, const W: usize> {
    /// Row `r`: entry `d` is `A(r, r − d)`; after [`Self::factor`], `L(r, r − d)` for `d > 0`
    /// and `D(r)` for `d = 0`.
    rows: Vec<[L; W]>,
    /// The matrix's diagonal, then `1 / D(r)` per row after [`Self::factor`].
    inv_pivot: Vec<L>,
}

impl<L: Lane, const W: usize> BandLdlt<L, W> {
    /// Sets the matrix to zero with `rows` rows.
    #[inline(always)]
    pub fn reset(&mut self, rows: usize) {
        self.resize_for_overwrite(rows);
        // `factor` takes the pivots from the rows, so only the rows need clearing.
        for row in self.rows.iter_mut() {
            *row = [L::default(); W];
        }
    }

    /// Sizes the matrix to `rows` rows without clearing them, for a caller that writes every
    /// entry `d ≤ r` of every row `r` before [`Self::factor`] (entries reaching before row 0
    /// are never read, and `factor` takes the diagonal from the rows).
    #[inline(always)]
    pub fn resize_for_overwrite(&mut self, rows: usize) {
        if self.rows.len() != rows {
            self.rows.resize(rows, [L::default(); W]);
            self.inv_pivot.resize(rows, L::default());
        }
    }

    /// Row `r` of the lower band: entry `d` is `A(r, r − d)` (entries reaching before row 0 are
    /// ignored).
    #[inline(always)]
    pub fn row_mut(&mut self, r: usize) -> &mut [L; W] {
        &mut self.rows[r]
    }

    /// Factors the matrix in place, `A = L D Lᵀ` (module docs).
    #[inline(always)]
    pub fn factor(&mut self) {
        let rows = self.rows.len();
        for (diagonal, row) in self.inv_pivot.iter_mut().zip(&self.rows) {
            *diagonal = row[0];
        }
        // Columns with W − 1 rows below them: a window of constant size, so the updates unroll
        // into independent operations without bounds checks.
        let full = rows.saturating_sub(W - 1);
        for c in 0..full {
            let window: &mut [[L; W]; W] = (&mut self.rows[c..c + W])
                .try_into()
                .expect("the window holds W rows");
            self.inv_pivot[c] = eliminate(window, self.inv_pivot[c]);
        }
        for c in full..rows {
            let window = &mut self.rows[c..];
            self.inv_pivot[c] = eliminate(window, self.inv_pivot[c]);
        }
    }

    /// Solves `A y = b` with the factor: `b` in, `y` out (one entry per row).
    #[inline(always)]
    pub fn solve(&self, b: &mut [L]) {
        let rows = self.rows.len();
        debug_assert_eq!(b.len(), rows);
        // Windows of W rows where they fit (constant loop bounds, as in `factor`), then the
        // shorter ones at the end.
        let full = rows.saturating_sub(W - 1);
        // Forward, L z = b: each solved z(c) leaves the rows below at once.
        for c in 0..full {
            let window: &[[L; W]; W] = (&self.rows[c..c + W]).try_into().expect("W rows");
            let below: &mut [L; W] = (&mut b[c..c + W]).try_into().expect("W rows");
            forward(window, below);
        }
        for c in full..rows {
            forward(&self.rows[c..], &mut b[c..]);
        }
        // D w = z, then back, Lᵀ y = w.
        for r in (full..rows).rev() {
            back(&self.rows[r..], &mut b[r..], self.inv_pivot[r]);
        }
        for r in (0..full).rev() {
            let window: &[[L; W]; W] = (&self.rows[r..r + W]).try_into().expect("W rows");
            let below: &mut [L; W] = (&mut b[r..r + W]).try_into().expect("W rows");
            back(window, below, self.inv_pivot[r]);
        }
    }
}

/// Forward substitution of one column: `below[0]` is solved (`z(c)`); the rows below it in
/// `window` lose their `L(c + i, c) z(c)`.
#[inline(always)]
fn forward<L: Lane, const W: usize>(window: &[[L; W]], below: &mut [L]) {
    let z = below[0];
    for (i, row) in window.iter().enumerate().skip(1) {
        below[i] -= row[i] * z;
    }
}

/// Back substitution of one row: `below[0]` becomes `w(r) − Σ L(r + m, r) y(r + m)` with
/// `w(r) = z(r) / D(r)` (`inv_pivot` is `1 / D(r)`), the newest term `y(r + 1)` last.
#[inline(always)]
fn back<L: Lane, const W: usize>(window: &[[L; W]], below: &mut [L], inv_pivot: L) {
    let mut acc = below[0] * inv_pivot;
    for (m, row) in window.iter().enumerate().skip(1).rev() {
        acc -= row[m] * below[m];
    }
    below[0] = acc;
}

/// Eliminates the column of `window[0]`'s pivot from the rows below it in `window` (at most
/// `W − 1`): `D(c)` from the updated diagonal (floored at `10⁻⁶` of the matrix's `diagonal`
/// there), `L(c + i, c) = A(c + i, c) / D(c)` and `A(c + i, c + j) −= L(c + i, c) A(c + j, c)`.
/// Returns `1 / D(c)`.
#[inline(always)]
fn eliminate<L: Lane, const W: usize>(window: &mut [[L; W]], diagonal: L) -> L {
    let pivot = window[0][0].max(diagonal * splat(1e-6));
    let inv = splat::<L>(1.0) / pivot;
    window[0][0] = pivot;
    // `A(c + i, c)` before scaling: the updates need the unscaled column.
    let mut column = [L::default(); W];
    for (i, row) in window.iter().enumerate().skip(1) {
        column[i] = row[i];
    }
    for (i, row) in window.iter_mut().enumerate().skip(1) {
        let l = column[i] * inv;
        for j in 1..i + 1 {
            row[i - j] -= l * column[j];
        }
        row[i] = l;
    }
    inv
}

#[cfg(test)]
mod tests {
    use super::super::lanes::Baseline;
    use super::*;

    /// A random symmetric positive definite matrix of half-width `W − 1`, solved by
    /// [`BandLdlt`], satisfies `A y = b` (multiplied back densely).
    fn solves_random_band<const W: usize>(rows: usize) {
        let mut seed = 2468u32;
        let mut rand = || {
            seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
            (seed >> 8) as f32 / (1u32 << 24) as f32 - 0.5
        };
        let mut dense = vec![vec![0.0f32; rows]; rows];
        #[allow(clippy::needless_range_loop)] // (r, c) and (c, r): both indices needed
        for r in 0..rows {
            for c in r.saturating_sub(W - 1)..r {
                let v = rand();
                dense[r][c] = v;
                dense[c][r] = v;
            }
            // Diagonally dominant, so positive definite.
            dense[r][r] = 2.0 * W as f32 + rand();
        }
        let mut band = BandLdlt::<Baseline, W>::default();
        band.reset(rows);
        for r in 0..rows {
            for d in 0..=r.min(W - 1) {
                band.row_mut(r)[d] = splat(dense[r][r - d]);
            }
        }
        let b: Vec<f32> = (0..rows).map(|_| rand()).collect();
        let mut y: Vec<Baseline> = b.iter().map(|&v| splat(v)).collect();
        band.factor();
        band.solve(&mut y);
        for r in 0..rows {
            let back: f32 = (0..rows).map(|c| dense[r][c] * y[c].to_array()[0]).sum();
            assert!(
                (back - b[r]).abs() < 1e-5,
                "row {r}: {back} against {}",
                b[r]
            );
        }
    }

    #[test]
    fn band_cholesky_solves_random_banded_systems() {
        solves_random_band::<9>(21);
        solves_random_band::<12>(64);
        solves_random_band::<12>(5);
    }

    /// A matrix singular along one direction (rank-deficient by round-off) gives a finite solve.
    #[test]
    fn singular_matrix_gives_a_finite_solution() {
        let mut band = BandLdlt::<Baseline, 2>::default();
        band.reset(2);
        // [[1, 1], [1, 1]]: the second pivot is 0.
        band.row_mut(0)[0] = splat(1.0);
        band.row_mut(1)[0] = splat(1.0);
        band.row_mut(1)[1] = splat(1.0);
        band.factor();
        let mut y = [splat::<Baseline>(1.0), splat(1.0)];
        band.solve(&mut y);
        assert!(y.iter().all(|v| v.to_array().iter().all(|x| x.is_finite())));
    }
}
