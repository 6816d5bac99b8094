//! The constraint-based substep (`integrator = "xpbd"`): extended position-based dynamics with
//! small steps, compliance from the physical stiffness, a direct solve of each strand's stretch
//! constraints and a Gauss–Seidel sweep of its bending joints.
//!
//! # Why
//!
//! The explicit kernel's substep is bounded by the stiffest spring on the lightest point
//! ([`super::stability`]). XPBD (Macklin, Müller and Chentanez, "XPBD: Position-Based Simulation
//! of Compliant Constrained Dynamics", MIG 2016) writes each elastic energy `½ k C(x)²` as a
//! constraint `C` with compliance `α = 1/k` and solves, per step, for the positions where the
//! constraint forces `∇Cᵀ λ / h²` balance the inertia: the stiff parts are treated implicitly
//! (a constraint's local solve is exact, so none overshoots), and the step follows accuracy.
//! Macklin et al. ("Small Steps in Physics Simulation", SCA 2019) showed that one iteration per
//! substep with many substeps beats many iterations per large step: the error is that of the
//! substep, the iteration count no longer sets the stiffness, and the damping is small. This
//! follows that scheme with a few ([`ITERATIONS`]) rounds per substep of (stretch solve, bending
//! sweep), each on the multipliers accumulated so far: one round left the bending far from
//! converged (see "Accuracy and damping"). The stretch constraints along a strand are solved *directly*, all at once, by one
//! tridiagonal (Thomas) solve per strand, as Deul, Kugelstadt, Weiler and Bender ("Direct
//! Position-Based Solver for Stiff Rods", CGF 2018) solve a rod's constraints with an O(n) direct
//! solver instead of Gauss–Seidel, whose convergence along a stiff chain is slow (a hanging
//! strand would sag by its iteration count, not by its stiffness).
//!
//! # The substep
//!
//! With `h` the substep, `w` the inverse masses (0 for the root and pinned points):
//!
//! 1. **predict**: `v += h (g − drag v + a_ext)` (gravity, air drag, force fields and hair–hair
//!    repulsion), kinematic points get the velocity of their prescribed motion, `p = x + h v`;
//! 2. **stretch**: constraints `C_j = |p_{j+1} − p_j| − l_j` with compliance `α = 1/k_stretch`
//!    (m/N); per round, one Newton step of the compliant system
//!    `(G(p) W G(x)ᵀ + α/h²) Δλ = −C(p) − (α/h²) λ`, `λ += Δλ`, then
//!    `p += W G(x)ᵀ Δλ`: the corrections act along each segment's direction at the substep's
//!    *start* `x`, as in SHAKE (Ryckaert, Ciccotti and Berendsen 1977; Goldenthal et al. 2007
//!    compare it with the end-of-step direction). The matrix is tridiagonal, solved by the Thomas
//!    algorithm: diagonal `(w_j + w_{j+1}) ĉ_j·t_j + α/h²`, off-diagonals `−w_{j+1} ĉ_j·t_{j+1}`
//!    and `−w_{j+1} ĉ_{j+1}·t_j` (`ĉ` current, `t` start directions). At a fixed point at rest
//!    this gives exactly the spring's statics `len − l = T/k` (the hanging-chain test checks it);
//!    a segment that turns by more than 60° in one substep (far beyond any step this method is
//!    meant for) takes its current direction instead, where the linearisation about the start
//!    would be ill-conditioned;
//! 3. **bending**: per round, one Gauss–Seidel sweep root to tip over the joints of [`super::curvature`],
//!    each a vector constraint `C_j = κ_j − K_j` (curvature binormal against its rest value in
//!    the previous segment's frame, parallel-transported from the root frame along the sweep)
//!    with compliance `1/k_j` (rad/(N·m)): the 3×3 system
//!    `(J W Jᵀ + I/(k_j h²)) Δλ = −C_j − λ_j/(k_j h²)`, `λ_j += Δλ`,
//!    with `J` the gradient of `κ_j` in the joint's three points (`∂κ/∂b = χ (2[a]× − κ aᵀ)`,
//!    `∂κ/∂a = −χ (2[b]× + κ bᵀ)`, `χ = 1/(1 + a·b)`, times the tangents' derivatives
//!    `(I − t tᵀ)/len`), solved by Cholesky; the root joint measures the first segment against its
//!    rest direction in the root frame, as the energy does;
//! 4. **goal springs**: `C = p − target` with compliance `1/(k_goal w_goal)`, solved per point;
//! 5. the **velocity** `v = (p − x)/h` (see "Round-off"), the damping sub-loop on it ([`super::damping`]; the
//!    stretch damping's meaning is unchanged), then the contact response, the position update,
//!    the inextensibility projection and the strain limit exactly as the other integrators run
//!    them ([`super::kernel::finish_substep`]): contacts get the last word on the velocity.
//!
//! Kinematic points have `w = 0`, so no constraint moves them; the root frame, the goal targets
//! and the bending frames are taken at the substep's end, where the constraints are solved.
//!
//! # Accuracy and damping
//!
//! First order in `h`, like semi-implicit Euler. Why the start direction: with the direction at
//! the predicted position (plain PBD/XPBD), the outward part of gravity's `h² g` in the
//! prediction is projected out along a direction that has turned, which shortens the swing's
//! step by `≈ (ωh)²` per substep — 13.5 % of a pendulum's amplitude per period at h = 1/96 s,
//! as much as backward Euler loses. With the start direction, the tangential motion is
//! semi-implicit Euler's and the pendulum keeps its amplitude and semi-implicit Euler's period
//! (`tests/tests/xpbd.rs`). The stiff modes (stretch, bending faster than `1/h`) are damped by the
//! compliance term as in backward Euler, which is what makes large steps stable.
//!
//! The bending sweeps are Gauss–Seidel passes with end-of-step gradients, so each joint's
//! correction is exact for that joint alone. Where a joint is stiff for the step
//! (`J W Jᵀ ≫ 1/(k h²)`: on the default scene at 12 substeps per frame by a factor of ~100) a few
//! sweeps do not converge along the strand: its statics carry an error that vanishes with `h` but
//! is large at the steps this method is meant for (a stiff cantilever at 16 substeps per frame
//! hangs 5 cm lower than its equilibrium with 4 rounds, 9 cm with 1), and the sweeps damp bending
//! motion (an undamped swinging chain with bending loses a third of its energy in 10 s at
//! h = 1/192 s; the test reports it). On the default scene this is 18–49 mm RMS from the
//! reference at 4–16 substeps per frame (issue 22; the branch notes), so this integrator is not
//! yet competitive: a direct (banded) solve of the bending constraints with the stretch ones, as
//! Deul et al. 2018 do, is the next step.
//!
//! # Round-off
//!
//! The solve works on the displacement `d = p − x` of each point, not on `p`: segment vectors are
//! `(x_{j+1} − x_j) + (d_{j+1} − d_j)`, and the velocity is `d / h`. Taking `(p − x)/h` instead
//! divides the f32 round-off of `p` (3·10⁻⁸ m at 0.5 m) by `h`; at 1,000 substeps per frame the
//! constraint corrections are that small, and a swinging chain stopped converging as the step
//! shrank (it drifted by centimetres).

use super::damping::damp_segments;
use super::dispatch::avx2_copy;
use super::kernel::{
    finish_substep, kinematic_velocity, transport, Scratch, StepConstants, StrandView, SubstepClock,
};
use super::lanes::{div_or_zero, splat, Lane, LANES, M3, V3};
use crate::mesh::RootFrame;

/// Longest substep `substeps = "auto"` takes with this integrator, s: 12 substeps per frame at
/// 24 fps, the implicit integrator's cost class. Not an accuracy limit: on the default scene this
/// step gives 24 mm RMS against the converged reference (module docs), far from issue 22's
/// 1.5 mm target.
pub(crate) const AUTO_DT: f64 = 1.0 / 288.0;

/// Substeps per step of length `step_dt` (s) that `substeps = "auto"` chooses with this
/// integrator: the fewest keeping the substep at most [`AUTO_DT`], at least 1.
pub(crate) fn auto_substeps(step_dt: f64) -> u32 {
    (step_dt / AUTO_DT * (1.0 - 1e-9))
        .ceil()
        .clamp(1.0, u32::MAX as f64) as u32
}

/// Iterations of the stretch solve and the bending sweep per substep, each on the multipliers
/// accumulated so far (XPBD's `Δλ = −(C + α̃ λ) / (∇C W ∇Cᵀ + α̃)`).
const ITERATIONS: u32 = 4;

/// Per-thread buffers of the XPBD substep, refitted to each group.
#[derive(Default)]
pub(crate) struct XpbdScratch<L: Lane> {
    /// Displacement of each point over the substep, m: the solve's positions are `x + disp`,
    /// kept apart so that the velocity `disp / h` does not take the round-off of `x` (module
    /// docs, "Round-off").
    disp: Vec<V3<L>>,
    /// Per segment: unit direction at the substep's start (the direction of its corrections).
    tangent: Vec<V3<L>>,
    /// Per segment: unit direction at the current positions (its constraint's gradient).
    current: Vec<V3<L>>,
    /// Per segment: right-hand side `−C`, then the Thomas solve's modified right-hand side and
    /// the solution `Δλ`.
    rhs: Vec<L>,
    /// Per segment: the Thomas solve's modified upper diagonal.
    factor: Vec<L>,
    /// Per segment: the stretch multiplier accumulated over the substep's iterations, kg·m.
    stretch_lambda: Vec<L>,
    /// Per joint: the bending multiplier accumulated over the substep's iterations.
    bend_lambda: Vec<V3<L>>,
    /// Rest curvature `K_j` per joint in the previous segment's frame: (unused, u, w), 1
    /// (`rest_moment / joint_k`).
    rest_curvature: Vec<V3<L>>,
}

impl<L: Lane> XpbdScratch<L> {
    /// Sizes the buffers for the gathered group `g` and takes the rest curvatures from it.
    fn fit(&mut self, g: &Scratch<L>, c: &StepConstants) {
        let n = g.x.len();
        self.disp.clear();
        self.disp.resize(n, V3::default());
        for buf in [&mut self.tangent, &mut self.current] {
            buf.clear();
            buf.resize(n - 1, V3::default());
        }
        self.bend_lambda.clear();
        self.bend_lambda.resize(n - 1, V3::default());
        for buf in [&mut self.rhs, &mut self.factor, &mut self.stretch_lambda] {
            buf.clear();
            buf.resize(n - 1, L::default());
        }
        self.rest_curvature.clear();
        if c.bend > 0.0 {
            let one = splat::<L>(1.0);
            self.rest_curvature.extend(
                g.rest_moment
                    .iter()
                    .zip(&g.joint_k)
                    .map(|(m, &k)| *m * div_or_zero(one, k, 0.0)),
            );
        }
    }
}

avx2_copy!(
    /// [`step_group_xpbd`] on [`super::lanes::F8`] lanes compiled for AVX2 where the CPU has it
    /// (the same bits as the baseline copy; see [`super::dispatch`]).
    pub(crate) fn step_group_xpbd_avx2 => step_group_xpbd
);

/// Advances a group of strands (equal point counts, at most [`LANES`]) by one collision step of
/// XPBD substeps (module docs); roots and pinned points move as in the explicit kernel.
#[inline(always)]
pub(crate) fn step_group_xpbd<L: Lane>(
    views: &mut [StrandView],
    starts: &[RootFrame],
    ends: &[RootFrame],
    c: &StepConstants,
    g: &mut Scratch<L>,
) {
    debug_assert!(!views.is_empty() && views.len() <= LANES);
    g.fit(views, starts, ends, c);
    let mut s = std::mem::take(&mut g.xpbd);
    s.fit(g, c);
    let n = g.x.len();
    let h = splat::<L>(c.dt);
    let inv_h = splat::<L>(1.0 / c.dt);
    let inv_h2 = splat::<L>(1.0 / (c.dt * c.dt));
    let drag = g.drag;
    let gravity = V3::splat(&c.gravity);
    let zero = splat::<L>(0.0);
    let mut clock = SubstepClock::new(g);
    for k in 0..c.substeps {
        let (origin, rot) = clock.end_of(g, k, c.substeps);
        // 1. Predict: external accelerations, kinematic points on their prescribed path.
        for i in 0..n {
            let a = (gravity - g.v[i] * drag) * g.free[i];
            g.v[i] += a * h;
        }
        if g.has_accel {
            for i in 0..n {
                g.v[i] += g.accel[i] * (h * g.free[i]);
            }
        }
        for &i in &g.pinned {
            let kinematic = kinematic_velocity(g, i, &origin, &rot, inv_h);
            g.v[i] = V3::select(g.free[i].simd_gt(zero), &g.v[i], &kinematic);
        }
        for i in 0..n {
            s.disp[i] = g.v[i] * h;
        }
        // 2–4. The constraints, on the predicted positions.
        s.stretch_lambda.fill(zero);
        s.bend_lambda.fill(V3::default());
        for _ in 0..ITERATIONS {
            if c.stretch > 0.0 {
                solve_stretch(g, &mut s, inv_h2 * g.stretch_compliance);
            }
            if c.bend > 0.0 {
                sweep_bending(g, &mut s, &rot, inv_h2);
            }
        }
        if c.goal > 0.0 {
            pull_to_goals(g, &mut s, &origin, &rot, h * h);
        }
        // 5. The velocity that moves each free point there; the shared end of the substep
        // (contacts, position update, projections) runs on it as after any other integrator's
        // velocity update.
        for i in 0..n {
            let moved = s.disp[i] * inv_h;
            g.v[i] = V3::select(g.free[i].simd_gt(zero), &moved, &g.v[i]);
        }
        if c.damp_fraction > 0.0 {
            for j in 0..n - 1 {
                let d = (g.x[j + 1] - g.x[j]) + (s.disp[j + 1] - s.disp[j]);
                g.tangent[j + 1] = d * div_or_zero(splat(1.0), d.dot(&d).sqrt(), 1e-9);
            }
            damp_segments(
                &mut g.v,
                &g.inv_mass,
                &g.tangent,
                &g.damp_coef,
                &mut g.impulse,
                c.damp_iterations,
            );
        }
        finish_substep(g, c, k, &origin, &rot, false);
        clock.advance(origin, rot);
    }
    g.xpbd = s;
    g.scatter(views);
}

/// One Newton step of every stretch constraint of the strand at once (module docs, step 2):
/// the compliant tridiagonal system solved by the Thomas algorithm, `compliance` = `α/h²`
/// (1/kg: `1/(k h²)`).
#[inline(always)]
fn solve_stretch<L: Lane>(g: &Scratch<L>, s: &mut XpbdScratch<L>, compliance: L) {
    let m = g.rest_length.len();
    let one = splat::<L>(1.0);
    for j in 0..m {
        let start = g.x[j + 1] - g.x[j];
        let d = start + (s.disp[j + 1] - s.disp[j]);
        let len = d.dot(&d).sqrt();
        let before = start * div_or_zero(one, start.dot(&start).sqrt(), 1e-9);
        s.current[j] = d * div_or_zero(one, len, 1e-9);
        // A segment that turns by more than 60° within the substep takes its current direction
        // (the linearisation about the start would be ill-conditioned; module docs).
        let turned = s.current[j].dot(&before).simd_gt(splat(0.5));
        s.tangent[j] = V3::select(turned, &before, &s.current[j]);
        s.rhs[j] = g.rest_length[j] - len - compliance * s.stretch_lambda[j];
    }
    // Forward elimination of the tridiagonal G(p) W G(x)ᵀ + α̃ (rows: current gradients,
    // columns: start directions): diagonal (w_j + w_{j+1}) ĉ_j·t_j + α̃, upper (j, j + 1)
    // −w_{j+1} ĉ_j·t_{j+1}, lower (j + 1, j) −w_{j+1} ĉ_{j+1}·t_j.
    for j in 0..m {
        let diag =
            (g.inv_mass[j] + g.inv_mass[j + 1]) * s.current[j].dot(&s.tangent[j]) + compliance;
        let (den, rhs) = if j == 0 {
            (diag, s.rhs[0])
        } else {
            let lower = L::default() - g.inv_mass[j] * s.current[j].dot(&s.tangent[j - 1]);
            (
                diag - lower * s.factor[j - 1],
                s.rhs[j] - lower * s.rhs[j - 1],
            )
        };
        let inv = div_or_zero(one, den, 0.0);
        let upper = if j + 1 < m {
            L::default() - g.inv_mass[j + 1] * s.current[j].dot(&s.tangent[j + 1])
        } else {
            L::default()
        };
        s.factor[j] = upper * inv;
        s.rhs[j] = rhs * inv;
    }
    for j in (0..m.saturating_sub(1)).rev() {
        s.rhs[j] = s.rhs[j] - s.factor[j] * s.rhs[j + 1];
    }
    // p_i += w_i (t_{i−1} Δλ_{i−1} − t_i Δλ_i).
    for j in 0..m {
        s.stretch_lambda[j] += s.rhs[j];
        let push = s.tangent[j] * s.rhs[j];
        s.disp[j] -= push * g.inv_mass[j];
        s.disp[j + 1] += push * g.inv_mass[j + 1];
    }
}

/// Rows of a 3×3 matrix per lane.
#[derive(Clone, Copy)]
struct Rows<L: Lane>([V3<L>; 3]);

impl<L: Lane> Rows<L> {
    /// `χ (2 [a]× + s κ aᵀ)` with `s = ±1` folded into `kappa`, then times `(I − t tᵀ) / len`:
    /// the gradient of the curvature binormal in one tangent, chained to that segment's points.
    #[inline(always)]
    fn curvature_gradient(chi: L, a: &V3<L>, kappa: &V3<L>, t: &V3<L>, inv_len: L) -> Self {
        let two = splat::<L>(2.0);
        let zero = splat::<L>(0.0);
        let cross = [
            V3 {
                x: zero,
                y: zero - a.z,
                z: a.y,
            },
            V3 {
                x: a.z,
                y: zero,
                z: zero - a.x,
            },
            V3 {
                x: zero - a.y,
                y: a.x,
                z: zero,
            },
        ];
        let k = [kappa.x, kappa.y, kappa.z];
        Self(std::array::from_fn(|r| {
            let row = (cross[r] * two + *a * k[r]) * chi;
            (row - *t * row.dot(t)) * inv_len
        }))
    }

    #[inline(always)]
    fn minus(&self, o: &Self) -> Self {
        Self(std::array::from_fn(|r| self.0[r] - o.0[r]))
    }

    /// `Mᵀ λ`.
    #[inline(always)]
    fn transpose_mul(&self, l: &V3<L>) -> V3<L> {
        self.0[0] * l.x + self.0[1] * l.y + self.0[2] * l.z
    }

    /// Adds `w M Mᵀ` to the symmetric `a` (entries xx, yy, zz, xy, xz, yz).
    #[inline(always)]
    fn add_gram(&self, w: L, a: &mut [L; 6]) {
        let r = &self.0;
        a[0] += w * r[0].dot(&r[0]);
        a[1] += w * r[1].dot(&r[1]);
        a[2] += w * r[2].dot(&r[2]);
        a[3] += w * r[0].dot(&r[1]);
        a[4] += w * r[0].dot(&r[2]);
        a[5] += w * r[1].dot(&r[2]);
    }
}

/// Solves the symmetric positive definite `a y = b` (entries xx, yy, zz, xy, xz, yz) by
/// Cholesky.
#[inline(always)]
fn solve_sym3<L: Lane>(a: &[L; 6], b: &V3<L>) -> V3<L> {
    let one = splat::<L>(1.0);
    let l00 = a[0].sqrt();
    let i00 = div_or_zero(one, l00, 0.0);
    let l10 = a[3] * i00;
    let l20 = a[4] * i00;
    let l11 = (a[1] - l10 * l10).max(splat(0.0)).sqrt();
    let i11 = div_or_zero(one, l11, 0.0);
    let l21 = (a[5] - l20 * l10) * i11;
    let l22 = (a[2] - l20 * l20 - l21 * l21).max(splat(0.0)).sqrt();
    let i22 = div_or_zero(one, l22, 0.0);
    let y0 = b.x * i00;
    let y1 = (b.y - l10 * y0) * i11;
    let y2 = (b.z - l20 * y0 - l21 * y1) * i22;
    let z = y2 * i22;
    let y = (y1 - l21 * z) * i11;
    let x = (y0 - l10 * y - l20 * z) * i00;
    V3 { x, y, z }
}

/// One Gauss–Seidel sweep of the bending joints root to tip (module docs, step 3); `inv_h2` is
/// `1/h²`, `rot` the root frame at the substep's end.
#[inline(always)]
fn sweep_bending<L: Lane>(g: &Scratch<L>, s: &mut XpbdScratch<L>, rot: &M3<L>, inv_h2: L) {
    let n = g.x.len();
    let (zero, one) = (splat::<L>(0.0), splat::<L>(1.0));
    let unit = |d: V3<L>| {
        let len = d.dot(&d).sqrt();
        let inv = div_or_zero(one, len, 1e-9);
        (d * inv, inv)
    };
    // The previous segment's frame (tangent, u), from the root frame down the strand.
    let mut tp = rot.cols[2];
    let mut up = rot.cols[0];
    let r = g.root_rest;
    let root_dir = tp * r.x + up * r.y + tp.cross(&up) * r.z;
    for j in 0..n - 1 {
        let (b, inv_b) = unit((g.x[j + 1] - g.x[j]) + (s.disp[j + 1] - s.disp[j]));
        let (a, inv_a, rest) = if j == 0 {
            (root_dir, zero, V3::default())
        } else {
            let (a, inv_a) = unit((g.x[j] - g.x[j - 1]) + (s.disp[j] - s.disp[j - 1]));
            up = transport(&up, &tp, &a);
            tp = a;
            let k = s.rest_curvature[j];
            (a, inv_a, up * k.y + a.cross(&up) * k.z)
        };
        let chi = div_or_zero(one, one + a.dot(&b), 1e-6);
        let kappa = a.cross(&b) * (chi * splat(2.0));
        let c = kappa - rest;
        // ∂κ/∂b = χ (2[a]× − κ aᵀ) and ∂κ/∂a = −χ (2[b]× + κ bᵀ) = χ (2[−b]× + κ (−b)ᵀ):
        // both of the form χ (2[e]× + κ' eᵀ), with (e, κ') = (a, −κ) and (−b, κ).
        let jb = Rows::curvature_gradient(chi, &a, &(zero_v::<L>() - kappa), &b, inv_b);
        let ja = Rows::curvature_gradient(chi, &(zero_v::<L>() - b), &kappa, &a, inv_a);
        let jm = ja.minus(&jb);
        let (w0, w1, w2) = (
            if j == 0 { zero } else { g.inv_mass[j - 1] },
            g.inv_mass[j],
            g.inv_mass[j + 1],
        );
        let compliance = inv_h2 * div_or_zero(one, g.joint_k[j], 0.0);
        let mut mat = [compliance, compliance, compliance, zero, zero, zero];
        ja.add_gram(w0, &mut mat);
        jm.add_gram(w1, &mut mat);
        jb.add_gram(w2, &mut mat);
        let lambda = solve_sym3(&mat, &(zero_v::<L>() - c - s.bend_lambda[j] * compliance));
        s.bend_lambda[j] += lambda;
        if j > 0 {
            s.disp[j - 1] -= ja.transpose_mul(&lambda) * w0;
        }
        s.disp[j] += jm.transpose_mul(&lambda) * w1;
        s.disp[j + 1] += jb.transpose_mul(&lambda) * w2;
    }
}

/// The zero vector in every lane.
#[inline(always)]
fn zero_v<L: Lane>() -> V3<L> {
    V3::default()
}

/// Goal springs as compliant constraints `p − target` (module docs, step 4), targets at the
/// substep's end (`origin`, `rot`); `h2` is `h²`.
#[inline(always)]
fn pull_to_goals<L: Lane>(
    g: &Scratch<L>,
    s: &mut XpbdScratch<L>,
    origin: &V3<L>,
    rot: &M3<L>,
    h2: L,
) {
    let one = splat::<L>(1.0);
    for i in 0..g.x.len() {
        // w k h² / (1 + w k h²): the share of the offset a compliant constraint removes.
        let stiff = g.inv_mass[i] * g.goal_k[i] * h2;
        let share = stiff / (one + stiff);
        let target = *origin + rot.mul(&g.rest_local[i]);
        let pull = ((target - g.x[i]) - s.disp[i]) * share;
        s.disp[i] += pull;
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;

    use super::super::lanes::Baseline;
    use super::*;

    type L = Baseline;

    fn v3(x: f32, y: f32, z: f32) -> V3<L> {
        V3::splat(&Vector3::new(x, y, z))
    }

    /// The curvature binormal of points `p` (joint at `p[1]`).
    fn kappa(p: &[Vector3<f64>; 3]) -> Vector3<f64> {
        let a = (p[1] - p[0]).normalize();
        let b = (p[2] - p[1]).normalize();
        2.0 * a.cross(&b) / (1.0 + a.dot(&b))
    }

    /// The rows `sweep_bending` builds for a joint are the derivatives of `κ` in its three points
    /// (checked against central differences in f64).
    #[test]
    fn bending_constraint_gradients_match_finite_differences() {
        let p = [
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(0.02, 0.003, -0.011),
            Vector3::new(0.031, 0.017, -0.02),
        ];
        let lanes = p.map(|q| {
            let q = q.cast::<f32>();
            v3(q.x, q.y, q.z)
        });
        let one = splat::<L>(1.0);
        let unit = |d: V3<L>| {
            let inv = one / d.dot(&d).sqrt();
            (d * inv, inv)
        };
        let (a, inv_a) = unit(lanes[1] - lanes[0]);
        let (b, inv_b) = unit(lanes[2] - lanes[1]);
        let chi = one / (one + a.dot(&b));
        let kap = a.cross(&b) * (chi * splat::<L>(2.0));
        let jb = Rows::curvature_gradient(chi, &a, &(zero_v::<L>() - kap), &b, inv_b);
        let ja = Rows::curvature_gradient(chi, &(zero_v::<L>() - b), &kap, &a, inv_a);
        let grads = [Rows(ja.0.map(|r| zero_v::<L>() - r)), ja.minus(&jb), jb];
        let eps = 1e-6;
        for (point, grad) in grads.iter().enumerate() {
            for axis in 0..3 {
                let mut plus = p;
                let mut minus = p;
                plus[point][axis] += eps;
                minus[point][axis] -= eps;
                let fd = (kappa(&plus) - kappa(&minus)) / (2.0 * eps);
                for row in 0..3 {
                    let analytic = grad.0[row].lane(0)[axis] as f64;
                    assert!(
                        (analytic - fd[row]).abs() < 1e-3 * (1.0 + fd[row].abs()),
                        "∂κ_{row}/∂x_{point},{axis}: {analytic} against {}",
                        fd[row]
                    );
                }
            }
        }
    }

    #[test]
    fn symmetric_three_by_three_solve_inverts_the_matrix() {
        let a = [4.0, 3.0, 5.0, 1.0, -0.5, 0.7].map(splat::<L>);
        let b = v3(1.0, -2.0, 0.5);
        let x = solve_sym3(&a, &b);
        let back = V3 {
            x: a[0] * x.x + a[3] * x.y + a[4] * x.z,
            y: a[3] * x.x + a[1] * x.y + a[5] * x.z,
            z: a[4] * x.x + a[5] * x.y + a[2] * x.z,
        };
        assert!((back - b).lane(0).norm() < 1e-5, "{:?}", back.lane(0));
    }
}
