//! Post-integration projection onto the constraints (seed 002, "Constraints"; Goldenthal et al.
//! 2007, "Efficient Simulation of Inextensible Cloth", fast projection).
//!
//! After the unconstrained explicit step the strand is moved to the nearest state that satisfies
//! its constraints `C(x) = 0`, nearest in the metric of the kinetic energy of the change
//! (`Δxᵀ M Δx`). The constraints are
//!
//! - **inextensibility** of every segment: `C_j = |x_{j+1} − x_j| − l_j`;
//! - **head contact** of each node in the step's penetrating set: `C = n·x_i − d`, the node on
//!   the contact plane (normal `n`, offset `d`: the collider's surface grown by the hair radius
//!   and the collider's thickness), see [`super::collide`];
//! - **root coupling**: the root (and any pinned node) has zero inverse mass and is placed on the
//!   moving head before the projection, so constraints only move free nodes.
//!
//! Fast projection linearises the constraints at the current iterate and solves for the
//! multipliers of the closest point on that linearisation, `(∇C M⁻¹ ∇Cᵀ) δλ = C`,
//! `x ← x − M⁻¹ ∇Cᵀ δλ`, repeating until the largest residual is below the tolerance (an
//! iterated manifold projection: it converges quadratically near the manifold). Constraints are
//! ordered along the strand (segment `j − 1`, contact of node `j`, segment `j`, …), so two of
//! them share a node only if they are at most two places apart: the system matrix is banded
//! (half-bandwidth 2) and symmetric positive definite, solved by banded Cholesky in `O(n)`.

use super::frames::V3;

/// Relative diagonal shift that keeps the Cholesky factorisation of a rank-deficient system
/// (a node held by a contact and two segments in line) positive.
const REGULARISE: f64 = 1e-10;

/// One contact constraint: node `node` must lie on the plane `normal·x = offset` (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Node index within the strand.
    pub node: usize,
    /// Outward unit normal of the surface, world.
    pub normal: V3,
    /// Plane offset, m: the surface grown by radius and thickness.
    pub offset: f64,
}

/// What one projection did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Projection {
    /// Iterations run (linear solves).
    pub iterations: u32,
    /// Largest residual at the end: segment strain `|len/l − 1|` or contact depth over the
    /// shortest rest segment.
    pub residual: f64,
    /// Did the residual fall below the tolerance within the iteration limit?
    pub converged: bool,
}

/// Scratch of the projection, reused between calls.
#[derive(Debug, Clone, Default)]
pub struct Scratch {
    /// Constraint kinds in band order: `Ok(segment)` or `Err(contact index)`.
    order: Vec<Result<usize, usize>>,
    c: Vec<f64>,
    /// Banded matrix `[diagonal, first, second subdiagonal, –]`, then its LDLᵀ factor
    /// `[1/D, L_a,a−1, L_a,a−2, D]`.
    band: Vec<[f64; 4]>,
    y: Vec<f64>,
    /// Per constraint: the nodes it touches and its gradient at each.
    grad: Vec<([usize; 2], [V3; 2])>,
}

/// Projects `x` (m) onto inextensible segments of rest lengths `rest` (m) and the `contacts`,
/// weighting node moves by `inv_mass` (1/kg, 0 = kinematic). At most `max_iterations` solves,
/// until the residual is below `tolerance`.
pub fn project(
    x: &mut [V3],
    inv_mass: &[f64],
    rest: &[f64],
    contacts: &[Contact],
    max_iterations: u32,
    tolerance: f64,
    scratch: &mut Scratch,
) -> Projection {
    let n = x.len() - 1;
    let s = scratch;
    s.order.clear();
    let mut k = 0;
    let shortest = rest.iter().cloned().fold(f64::INFINITY, f64::min);
    for i in 0..=n {
        while k < contacts.len() && contacts[k].node == i {
            if inv_mass[i] > 0.0 {
                s.order.push(Err(k));
            }
            k += 1;
        }
        if i < n && (inv_mass[i] > 0.0 || inv_mass[i + 1] > 0.0) {
            s.order.push(Ok(i));
        }
    }
    let m = s.order.len();
    let mut out = Projection::default();
    loop {
        // Residuals and constraint gradients at the current iterate: constraint `a` touches
        // nodes `n[0]`, `n[1]` with gradients `g[0]`, `g[1]` (a contact: one node, `g[1] = 0`).
        s.c.clear();
        s.grad.clear();
        let mut residual = 0.0f64;
        for &kind in &s.order {
            match kind {
                Ok(j) => {
                    let e = x[j + 1] - x[j];
                    let len = e.norm();
                    let c = len - rest[j];
                    residual = residual.max(c.abs() / rest[j]);
                    s.c.push(c);
                    let d = if len > 0.0 { e / len } else { V3::zeros() };
                    s.grad.push(([j, j + 1], [-d, d]));
                }
                Err(ci) => {
                    let ct = &contacts[ci];
                    let c = ct.normal.dot(&x[ct.node]) - ct.offset;
                    residual = residual.max(c.abs() / shortest);
                    s.c.push(c);
                    s.grad.push(([ct.node, ct.node], [ct.normal, V3::zeros()]));
                }
            }
        }
        out.residual = residual;
        if !residual.is_finite() {
            out.converged = false;
            return out;
        }
        if residual <= tolerance {
            out.converged = true;
            return out;
        }
        if out.iterations >= max_iterations {
            return out;
        }
        out.iterations += 1;
        // A = ∇C M⁻¹ ∇Cᵀ, banded: constraints two or more places apart share no node.
        let entry = |a: &([usize; 2], [V3; 2]), b: &([usize; 2], [V3; 2])| -> f64 {
            let mut sum = 0.0;
            for p in 0..2 {
                for q in 0..2 {
                    if a.0[p] == b.0[q] {
                        sum += inv_mass[a.0[p]] * a.1[p].dot(&b.1[q]);
                    }
                }
            }
            sum
        };
        s.band.clear();
        for a in 0..m {
            let ga = &s.grad[a];
            let mut row = [entry(ga, ga), 0.0, 0.0, 0.0];
            if a >= 1 {
                row[1] = entry(ga, &s.grad[a - 1]);
            }
            if a >= 2 {
                row[2] = entry(ga, &s.grad[a - 2]);
            }
            s.band.push(row);
        }
        // Banded LDLᵀ in place (one division per row).
        for a in 0..m {
            let diag = s.band[a][0];
            let d2 = if a >= 2 { s.band[a - 2][3] } else { 0.0 };
            let d1 = if a >= 1 { s.band[a - 1][3] } else { 0.0 };
            let l2 = if a >= 2 {
                s.band[a][2] * s.band[a - 2][0]
            } else {
                0.0
            };
            let l1 = if a >= 1 {
                let cross = if a >= 2 {
                    l2 * d2 * s.band[a - 1][1]
                } else {
                    0.0
                };
                (s.band[a][1] - cross) * s.band[a - 1][0]
            } else {
                0.0
            };
            let pivot = diag * (1.0 + REGULARISE) - l1 * l1 * d1 - l2 * l2 * d2;
            // Also refuses a NaN pivot.
            if pivot.is_nan() || pivot <= REGULARISE * diag.abs() {
                return out;
            }
            s.band[a] = [1.0 / pivot, l1, l2, pivot];
        }
        // L y = C, then Lᵀ δλ = D⁻¹ y.
        s.y.clear();
        for a in 0..m {
            let mut r = s.c[a];
            if a >= 1 {
                r -= s.band[a][1] * s.y[a - 1];
            }
            if a >= 2 {
                r -= s.band[a][2] * s.y[a - 2];
            }
            s.y.push(r);
        }
        for a in (0..m).rev() {
            let mut r = s.y[a] * s.band[a][0];
            if a + 1 < m {
                r -= s.band[a + 1][1] * s.y[a + 1];
            }
            if a + 2 < m {
                r -= s.band[a + 2][2] * s.y[a + 2];
            }
            s.y[a] = r;
        }
        // x ← x − M⁻¹ ∇Cᵀ δλ.
        for ((nodes, grads), &lambda) in s.grad.iter().zip(&s.y) {
            for (&i, g) in nodes.iter().zip(grads) {
                x[i] -= g * (inv_mass[i] * lambda);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stretched_chain_is_projected_to_its_rest_lengths() {
        let mut x: Vec<V3> = (0..11)
            .map(|i| V3::new(0.0101 * i as f64, 0.0005 * (i as f64).sin(), 0.0))
            .collect();
        let mut w = vec![1.0; 11];
        w[0] = 0.0;
        let rest = vec![0.01; 10];
        let p = project(&mut x, &w, &rest, &[], 20, 1e-10, &mut Scratch::default());
        assert!(p.converged, "{p:?}");
        assert!(p.iterations <= 4, "converges quadratically: {p:?}");
        assert_eq!(x[0], V3::zeros(), "the root does not move");
        for j in 0..10 {
            assert!(((x[j + 1] - x[j]).norm() / 0.01 - 1.0).abs() < 1e-10);
        }
    }

    #[test]
    fn contact_holds_a_node_on_its_plane_while_lengths_are_kept() {
        // A hanging chain whose node 5 is pushed onto the plane x = 0.003.
        let mut x: Vec<V3> = (0..9)
            .map(|i| V3::new(0.0, 0.0, -0.01 * i as f64))
            .collect();
        let mut w = vec![1.0; 9];
        w[0] = 0.0;
        let rest = vec![0.01; 8];
        let contacts = [Contact {
            node: 5,
            normal: V3::x(),
            offset: 0.003,
        }];
        let p = project(
            &mut x,
            &w,
            &rest,
            &contacts,
            30,
            1e-10,
            &mut Scratch::default(),
        );
        assert!(p.converged, "{p:?}");
        assert!((x[5].x - 0.003).abs() < 1e-10);
        for j in 0..8 {
            assert!(((x[j + 1] - x[j]).norm() / 0.01 - 1.0).abs() < 1e-9);
        }
    }

    #[test]
    fn impossible_constraints_report_their_residual() {
        // Node 1 on a plane 2 cm away from the pinned root, with a 1 cm segment: no solution.
        let mut x = vec![
            V3::zeros(),
            V3::new(0.01, 0.0, 0.0),
            V3::new(0.02, 0.0, 0.0),
        ];
        let w = [0.0, 1.0, 1.0];
        let contacts = [Contact {
            node: 1,
            normal: V3::x(),
            offset: 0.02,
        }];
        let p = project(
            &mut x,
            &w,
            &[0.01, 0.01],
            &contacts,
            10,
            1e-8,
            &mut Scratch::default(),
        );
        assert!(!p.converged);
        assert!(p.residual.is_finite() && p.residual > 1e-3, "{p:?}");
        assert!(x.iter().all(|v| v.iter().all(|c| c.is_finite())));
    }
}
