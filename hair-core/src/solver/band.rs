//! A symmetric positive definite banded system `A y = b` solved directly by band Cholesky, one
//! strand per SIMD lane: the one banded solver of the strand integrators.
//!
//! Both implicit integrators reduce a strand's step to a banded system, because a strand is a
//! chain and its forces or constraints couple only points a few apart: implicit Euler
//! ([`super::implicit`]) solves a block-pentadiagonal system in the velocity change (3×3 blocks,
//! half-width 8), XPBD ([`super::xpbd`]) one in the constraint multipliers (bending and stretch,
//! 4×4 blocks, half-width 11). Dense Cholesky would cost `O(n³)`; keeping the factor inside the
//! band costs `3n · W²/2` multiply–adds for `W − 1` the half-width (Golub and Van Loan, *Matrix
//! Computations*, §4.3.5), linear in the strand's length, and each operation advances the eight
//! strands of a group at once like the rest of the kernel.
//!
//! Storage: row `r` holds `W` entries, entry `d` is `A(r, r − d)` (the lower band, diagonal
//! first), overwritten by the factor `L(r, r − d)` with `A = L Lᵀ`.
//!
//! A row whose pivot falls below `10⁻⁶` of its diagonal (a matrix singular in f32 round-off, as
//! a straight joint's curvature constraint is along its own tangent when the joint is very stiff
//! for the step) takes that floor as its pivot: the solve stays finite, and the solution is
//! that of a matrix changed by less than the round-off already in it.

use super::lanes::{splat, Lane};

/// The band Cholesky factor of a symmetric positive definite matrix whose entries vanish more
/// than `W − 1` rows off the diagonal, per lane.
#[derive(Default)]
pub(crate) struct BandCholesky<L: Lane, const W: usize> {
    /// Row `r`: entry `d` is `A(r, r − d)`, after [`Self::factor`] `L(r, r − d)`.
    rows: Vec<[L; W]>,
    /// `1 / L(r, r)` per row, after [`Self::factor`].
    inv_pivot: Vec<L>,
}

impl<L: Lane, const W: usize> BandCholesky<L, W> {
    /// Sets the matrix to zero with `rows` rows.
    #[inline(always)]
    pub fn reset(&mut self, rows: usize) {
        self.rows.clear();
        self.rows.resize(rows, [L::default(); W]);
        self.inv_pivot.clear();
        self.inv_pivot.resize(rows, L::default());
    }

    /// Row `r` of the lower band: entry `d` is `A(r, r − d)` (entries reaching before row 0 are
    /// ignored).
    #[inline(always)]
    pub fn row_mut(&mut self, r: usize) -> &mut [L; W] {
        &mut self.rows[r]
    }

    /// Factors the matrix in place, `A = L Lᵀ` (module docs).
    #[inline(always)]
    pub fn factor(&mut self) {
        let floor = splat::<L>(1e-6);
        let one = splat::<L>(1.0);
        for r in 0..self.rows.len() {
            let reach = r.min(W - 1);
            // L(r, c) = (A(r, c) − Σ_{c' < c} L(r, c') L(c, c')) / L(c, c), c = r − d.
            for d in (1..=reach).rev() {
                let c = r - d;
                let mut acc = self.rows[r][d];
                for m in d + 1..=reach {
                    acc -= self.rows[r][m] * self.rows[c][m - d];
                }
                self.rows[r][d] = acc * self.inv_pivot[c];
            }
            let diagonal = self.rows[r][0];
            let mut acc = diagonal;
            for m in 1..=reach {
                acc -= self.rows[r][m] * self.rows[r][m];
            }
            let pivot = acc.max(diagonal * floor).sqrt();
            self.rows[r][0] = pivot;
            self.inv_pivot[r] = one / pivot;
        }
    }

    /// Solves `A y = b` with the factor: `b` in, `y` out (one entry per row).
    #[inline(always)]
    pub fn solve(&self, b: &mut [L]) {
        let rows = self.rows.len();
        debug_assert_eq!(b.len(), rows);
        // Forward (L z = b) and back (Lᵀ y = z) substitution.
        for r in 0..rows {
            let mut acc = b[r];
            for m in 1..=r.min(W - 1) {
                acc -= self.rows[r][m] * b[r - m];
            }
            b[r] = acc * self.inv_pivot[r];
        }
        for r in (0..rows).rev() {
            let mut acc = b[r];
            for m in 1..=(rows - 1 - r).min(W - 1) {
                acc -= self.rows[r + m][m] * b[r + m];
            }
            b[r] = acc * self.inv_pivot[r];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::lanes::Baseline;
    use super::*;

    /// A random symmetric positive definite matrix of half-width `W − 1`, solved by
    /// [`BandCholesky`], satisfies `A y = b` (multiplied back densely).
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
        let mut band = BandCholesky::<Baseline, W>::default();
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
        let mut band = BandCholesky::<Baseline, 2>::default();
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
