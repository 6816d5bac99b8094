//! The 3×3 blocks of the implicit substep's matrix, eight strands per SIMD lane like the rest of
//! the kernel: [`Sym3`] for the diagonal blocks (symmetric), [`Mat3`] for the blocks coupling
//! two points, which bending's Gauss–Newton Hessian makes unsymmetric (block `(i, j)` is
//! `J_iᵀ J_j`, and `(j, i)` its transpose).

use super::lanes::{Lane, V3};

/// A symmetric 3×3 matrix per lane.
#[derive(Clone, Copy, Default, Debug)]
pub(super) struct Sym3<L> {
    pub xx: L,
    pub yy: L,
    pub zz: L,
    pub xy: L,
    pub xz: L,
    pub yz: L,
}

impl<L: Lane> Sym3<L> {
    /// `a I + b t tᵀ`.
    #[inline(always)]
    pub fn iso_outer(a: L, b: L, t: &V3<L>) -> Self {
        let (bx, by) = (b * t.x, b * t.y);
        Self {
            xx: a + bx * t.x,
            yy: a + by * t.y,
            zz: a + b * t.z * t.z,
            xy: bx * t.y,
            xz: bx * t.z,
            yz: by * t.z,
        }
    }

    /// `s` times this matrix.
    #[inline(always)]
    pub fn scaled(&self, s: L) -> Self {
        Self {
            xx: self.xx * s,
            yy: self.yy * s,
            zz: self.zz * s,
            xy: self.xy * s,
            xz: self.xz * s,
            yz: self.yz * s,
        }
    }

    /// Adds `o`.
    #[inline(always)]
    pub fn add(&mut self, o: &Self) {
        self.xx += o.xx;
        self.yy += o.yy;
        self.zz += o.zz;
        self.xy += o.xy;
        self.xz += o.xz;
        self.yz += o.yz;
    }

    /// Subtracts `o`.
    #[inline(always)]
    pub fn sub(&mut self, o: &Self) {
        self.xx -= o.xx;
        self.yy -= o.yy;
        self.zz -= o.zz;
        self.xy -= o.xy;
        self.xz -= o.xz;
        self.yz -= o.yz;
    }

    /// Adds `s I`.
    #[inline(always)]
    pub fn add_diagonal(&mut self, s: L) {
        self.xx += s;
        self.yy += s;
        self.zz += s;
    }

    /// `S v`.
    #[inline(always)]
    pub fn mul(&self, v: &V3<L>) -> V3<L> {
        V3 {
            x: self.xx * v.x + self.xy * v.y + self.xz * v.z,
            y: self.xy * v.x + self.yy * v.y + self.yz * v.z,
            z: self.xz * v.x + self.yz * v.y + self.zz * v.z,
        }
    }
}

/// A general 3×3 matrix per lane, by rows.
#[derive(Clone, Copy, Default, Debug)]
pub(super) struct Mat3<L> {
    /// Row `r` of the matrix.
    pub rows: [V3<L>; 3],
}

impl<L: Lane> Mat3<L> {
    /// The symmetric matrix `s` in full.
    #[inline(always)]
    pub fn from_sym(s: &Sym3<L>) -> Self {
        Self {
            rows: [
                V3 {
                    x: s.xx,
                    y: s.xy,
                    z: s.xz,
                },
                V3 {
                    x: s.xy,
                    y: s.yy,
                    z: s.yz,
                },
                V3 {
                    x: s.xz,
                    y: s.yz,
                    z: s.zz,
                },
            ],
        }
    }

    /// The cross-product matrix `[a]×` (`[a]× v = a × v`).
    #[inline(always)]
    pub fn cross(a: &V3<L>) -> Self {
        let zero = L::default();
        Self {
            rows: [
                V3 {
                    x: zero,
                    y: -a.z,
                    z: a.y,
                },
                V3 {
                    x: a.z,
                    y: zero,
                    z: -a.x,
                },
                V3 {
                    x: -a.y,
                    y: a.x,
                    z: zero,
                },
            ],
        }
    }

    /// The outer product `u wᵀ`.
    #[inline(always)]
    pub fn outer(u: &V3<L>, w: &V3<L>) -> Self {
        Self {
            rows: [*w * u.x, *w * u.y, *w * u.z],
        }
    }

    // Rows are written out, not mapped: closures passed to `array::map` and iterator adaptors
    // are not always inlined, and a lane operation that is not inlined runs without the AVX2
    // the kernel is compiled for (`super::dispatch`).

    /// `s` times this matrix.
    #[inline(always)]
    pub fn scaled(&self, s: L) -> Self {
        let [r0, r1, r2] = self.rows;
        Self {
            rows: [r0 * s, r1 * s, r2 * s],
        }
    }

    /// This matrix minus `o`.
    #[inline(always)]
    pub fn minus(&self, o: &Self) -> Self {
        let ([a0, a1, a2], [b0, b1, b2]) = (self.rows, o.rows);
        Self {
            rows: [a0 - b0, a1 - b1, a2 - b2],
        }
    }

    /// Adds `o`.
    #[inline(always)]
    pub fn add(&mut self, o: &Self) {
        self.rows[0] += o.rows[0];
        self.rows[1] += o.rows[1];
        self.rows[2] += o.rows[2];
    }

    /// Subtracts `o`.
    #[inline(always)]
    pub fn sub(&mut self, o: &Self) {
        self.rows[0] -= o.rows[0];
        self.rows[1] -= o.rows[1];
        self.rows[2] -= o.rows[2];
    }

    /// `A v`.
    #[inline(always)]
    pub fn mul(&self, v: &V3<L>) -> V3<L> {
        V3 {
            x: self.rows[0].dot(v),
            y: self.rows[1].dot(v),
            z: self.rows[2].dot(v),
        }
    }

    /// `Aᵀ v`.
    #[inline(always)]
    pub fn mul_transposed(&self, v: &V3<L>) -> V3<L> {
        self.rows[0] * v.x + self.rows[1] * v.y + self.rows[2] * v.z
    }

    /// The product `A B`.
    #[inline(always)]
    pub fn times(&self, b: &Self) -> Self {
        let [r0, r1, r2] = self.rows;
        Self {
            rows: [
                b.mul_transposed(&r0),
                b.mul_transposed(&r1),
                b.mul_transposed(&r2),
            ],
        }
    }

    /// The product `Aᵀ B`.
    #[inline(always)]
    pub fn transposed_times(&self, b: &Self) -> Self {
        let [a0, a1, a2] = self.rows;
        let [b0, b1, b2] = b.rows;
        Self {
            rows: [
                b0 * a0.x + b1 * a1.x + b2 * a2.x,
                b0 * a0.y + b1 * a1.y + b2 * a2.y,
                b0 * a0.z + b1 * a1.z + b2 * a2.z,
            ],
        }
    }

    /// The product `A Bᵀ`: entry `(r, c)` is `a_r · b_c`.
    #[inline(always)]
    pub fn times_transposed(&self, b: &Self) -> Self {
        Self {
            rows: [
                b.mul(&self.rows[0]),
                b.mul(&self.rows[1]),
                b.mul(&self.rows[2]),
            ],
        }
    }

    /// The product `A Bᵀ` where it is known to be symmetric (`A = B S` for a symmetric `S`, as
    /// `W D⁻¹` and `W` in the block solve, or `A = B`): the six dot products of its lower
    /// triangle.
    #[inline(always)]
    pub fn times_transposed_sym(&self, b: &Self) -> Sym3<L> {
        let ([a0, a1, a2], [b0, b1, b2]) = (self.rows, b.rows);
        Sym3 {
            xx: a0.dot(&b0),
            yy: a1.dot(&b1),
            zz: a2.dot(&b2),
            xy: a1.dot(&b0),
            xz: a2.dot(&b0),
            yz: a2.dot(&b1),
        }
    }

    /// `Aᵀ A`, symmetric positive semi-definite.
    #[inline(always)]
    pub fn gram(&self) -> Sym3<L> {
        // Aᵀ A = T Tᵀ for T = Aᵀ, whose rows are A's columns.
        let [a0, a1, a2] = self.rows;
        let t = Self {
            rows: [
                V3 {
                    x: a0.x,
                    y: a1.x,
                    z: a2.x,
                },
                V3 {
                    x: a0.y,
                    y: a1.y,
                    z: a2.y,
                },
                V3 {
                    x: a0.z,
                    y: a1.z,
                    z: a2.z,
                },
            ],
        };
        t.times_transposed_sym(&t)
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{Matrix3, Vector3};

    use super::super::lanes::{splat, Baseline};
    use super::*;

    fn lanes(m: &Matrix3<f32>) -> Mat3<Baseline> {
        Mat3 {
            rows: std::array::from_fn(|r| {
                V3::splat(&Vector3::new(m[(r, 0)], m[(r, 1)], m[(r, 2)]))
            }),
        }
    }

    fn lane0(m: &Mat3<Baseline>) -> Matrix3<f32> {
        let r: [Vector3<f32>; 3] = m.rows.map(|r| r.lane(0));
        Matrix3::from_rows(&[r[0].transpose(), r[1].transpose(), r[2].transpose()])
    }

    #[test]
    fn products_match_nalgebra() {
        let a = Matrix3::new(1.0, -2.0, 0.5, 3.0, 0.25, -1.0, 2.0, 4.0, -0.75);
        let b = Matrix3::new(-1.5, 0.5, 2.0, 1.0, -3.0, 0.125, 0.75, 2.5, 1.0);
        let v = Vector3::new(0.3, -1.2, 2.0);
        let (la, lb, lv) = (lanes(&a), lanes(&b), V3::<Baseline>::splat(&v));
        let close = |x: Matrix3<f32>, y: Matrix3<f32>| (x - y).norm() < 1e-5 * (1.0 + y.norm());
        assert!(close(lane0(&la.times(&lb)), a * b));
        assert!(close(lane0(&la.transposed_times(&lb)), a.transpose() * b));
        assert!(close(lane0(&Mat3::from_sym(&la.gram())), a.transpose() * a));
        assert!((la.mul(&lv).lane(0) - a * v).norm() < 1e-5);
        assert!((la.mul_transposed(&lv).lane(0) - a.transpose() * v).norm() < 1e-5);
        let cross = lane0(&Mat3::cross(&lv));
        let w = Vector3::new(-0.4, 0.9, 1.1);
        assert!((cross * w - v.cross(&w)).norm() < 1e-6);
        let outer = lane0(&Mat3::outer(&lv, &V3::splat(&w)));
        assert!(close(outer, v * w.transpose()));
        let s = la.gram();
        assert!((s.mul(&lv).lane(0) - a.transpose() * a * v).norm() < 1e-4);
        assert!(close(lane0(&la.scaled(splat(2.0))), a * 2.0));
        assert!(close(lane0(&la.times_transposed(&lb)), a * b.transpose()));
        // A Aᵀ is symmetric.
        assert!(close(
            lane0(&Mat3::from_sym(&la.times_transposed_sym(&la))),
            a * a.transpose()
        ));
    }
}
