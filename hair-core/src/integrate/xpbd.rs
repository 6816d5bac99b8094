//! The constraint-based substep (`integrator = "xpbd"`): extended position-based dynamics with
//! small steps, compliance from the physical stiffness, and one direct solve of each strand's
//! stretch and bending constraints together.
//!
//! # Why
//!
//! The explicit kernel's substep is bounded by the stiffest spring on the lightest point
//! ([`super::stability`]). XPBD (Macklin, Müller and Chentanez, "XPBD: Position-Based Simulation
//! of Compliant Constrained Dynamics", MIG 2016) writes each elastic energy `½ k C(x)²` as a
//! constraint `C` with compliance `α = 1/k` and solves, per step, for the positions where the
//! constraint forces `∇Cᵀ λ / h²` balance the inertia: the stiff parts are treated implicitly,
//! and the step follows accuracy. Macklin et al. ("Small Steps in Physics Simulation", SCA 2019)
//! showed that few iterations per substep with more substeps beat many iterations per large
//! step. Solving the constraints one at a time (Gauss–Seidel), as XPBD usually does, converges
//! slowly along a stiff chain: a strand then sags and bends by its iteration count, not by its
//! stiffness (sweeping the bending joints so puts the default scene 18–49 mm from the reference;
//! `docs/design/xpbd.md`). Deul, Kugelstadt, Weiler and Bender ("Direct Position-Based Solver
//! for Stiff Rods", CGF 2018) observed that a rod's constraint
//! Jacobian is banded, so the whole compliant system can be solved directly in O(n); this
//! integrator does that for the chain's stretch and curvature constraints.
//!
//! # The substep
//!
//! With `h` the substep, `W` the inverse masses (0 for the root and pinned points):
//!
//! 1. **predict**: `v += h (g − drag v + a_ext)` (gravity, air drag, force fields and hair–hair
//!    repulsion), kinematic points get the velocity of their prescribed motion, `p = x + h v`;
//! 2. **constraints**, per segment `j` a block of four rows: the curvature of joint `j` (the
//!    vector `C = κ_j − K_j` of [`super::curvature`]: curvature binormal against its rest value
//!    in the previous segment's parallel-transported frame; the root joint measures the first
//!    segment against its rest direction in the root frame, as the energy does), compliance
//!    `1/k_j` (rad/(N·m)), and the stretch `C = |p_{j+1} − p_j| − l_j`, compliance
//!    `1/k_stretch` (m/N). Block `j` moves points `j − 1 … j + 1`, so blocks up to two apart
//!    share a point and the system is block-pentadiagonal (4×4 blocks, scalar half-width 11);
//! 3. per iteration (`ITERATIONS`), on the multipliers `λ` accumulated over the substep:
//!    `(G W Gᵀ + α/h²) Δλ = −C(p) − (α/h²) λ`, `λ += Δλ`, `p += W Gᵀ Δλ`, with `G` the
//!    constraint gradients at the substep's **start** `x` (see "Accuracy and damping"). The
//!    matrix is then the same in every iteration: it is assembled and factored once per
//!    substep by band `L D Lᵀ` ([`super::band`]), and each iteration is a forward and back
//!    substitution. This is a chord (simplified Newton) iteration: its fixed point is that of the
//!    compliant system, `C(p) = −α λ/h²` with `p = p̃ + W Gᵀ λ`; its rate is how far the
//!    gradients turn within the substep, small at the steps this integrator is meant for. The
//!    bending gradients leave out the turn of the transported frame (see "The frame's turn").
//! 4. **goal springs**: `C = p − target` with compliance `1/(k_goal w_goal)`, solved per point;
//! 5. the **velocity** `v = (p − x)/h` (see "Round-off"), the damping sub-loop on it
//!    ([`super::damping`]; the stretch damping's meaning is unchanged), then the contact
//!    response, the position update, the inextensibility projection and the strain limit exactly
//!    as the other integrators run them ([`super::kernel::finish_substep`]): contacts get the
//!    last word on the velocity.
//!
//! Kinematic points have `w = 0`, so no constraint moves them; the root frame, the goal targets
//! and the bending frames are taken at the substep's end, where the constraints are solved.
//!
//! # The frame's turn (the known limit)
//!
//! The rest curvature `K_j` lives in the previous segment's parallel-transported frame, which
//! turns when the strand moves: with the frame turning with its own tangent `a`
//! (`−∂K_j/∂a = a K_jᵀ`, local) and the twist that transport accumulates from the root (the
//! holonomy of Bergou et al. 2008, which makes `C_j` depend on every tangent before it). The
//! explicit kernel's forces carry both ([`super::kernel`]); `G` here carries neither, so for a
//! curved rest shape the corrections are not quite the energy's gradient and the fixed point is
//! not quite its statics. For straight rest shapes (the cantilever, the chains) nothing is lost;
//! on the default scene (a sag-free groom, curved at rest) it leaves a floor of 3.5 mm RMS
//! against the reference at every step from 2 to 32 substeps per frame (BENCHMARKS.md). Adding
//! the local term to `G` and the twist to the corrections alone (O(n) by suffix sums; in
//! `G W Gᵀ` it would fill the band) makes the chord iteration run away on the default scene at 2
//! and 3 substeps per frame; carrying both in the solve (or a material frame per segment, as
//! Deul et al.'s Cosserat rods have, which keeps the system banded) is the open fix.
//!
//! # Accuracy and damping
//!
//! First order in `h`, like semi-implicit Euler. Why the start gradients: with the gradient at
//! the predicted position (plain PBD/XPBD), the outward part of gravity's `h² g` in the
//! prediction is projected out along a direction that has turned, which shortens the swing's
//! step by `≈ (ωh)²` per substep — 13.5 % of a pendulum's amplitude per period at h = 1/96 s, as
//! much as backward Euler loses. Corrections along the start gradients are those of SHAKE
//! (Ryckaert, Ciccotti and Berendsen 1977; Goldenthal et al. 2007 compare it with the end-of-step
//! gradient): the tangential motion is semi-implicit Euler's, and the pendulum keeps its
//! amplitude and semi-implicit Euler's period (`tests/tests/xpbd.rs`). The stiff modes (stretch,
//! bending faster than `1/h`) are damped by the compliance term as in backward Euler, which is
//! what makes large steps stable.
//!
//! # Round-off
//!
//! The solve works on the displacement `d = p − x` of each point, not on `p`: segment vectors are
//! `(x_{j+1} − x_j) + (d_{j+1} − d_j)`, and the velocity is `d / h`. Taking `(p − x)/h` instead
//! divides the f32 round-off of `p` (3·10⁻⁸ m at 0.5 m) by `h`; at 1,000 substeps per frame the
//! constraint corrections are that small, and a swinging chain stopped converging as the step
//! shrank (it drifted by centimetres).

use super::band::BandLdlt;
use super::damping::damp_segments;
use super::dispatch::avx2_copy;
use super::kernel::{
    finish_substep, kinematic_velocity, transport, Scratch, StepConstants, StrandView, SubstepClock,
};
use super::lanes::{div_or_zero, splat, Lane, LANES, M3, V3};
use crate::mesh::RootFrame;

/// Longest substep `substeps = "auto"` takes with this integrator, s: 16 substeps per frame at
/// 24 fps, chosen by measurement on the default scene (head collider, hair–hair, 1 % strain
/// limit; against the converged inextensible reference, `tests/tests/xpbd_default_scene.rs`):
/// the fewest measured substeps at which the position error has reached this method's floor
/// (3.49 mm RMS; 3.53 at 8, 3.77 at 4) *and* the p99 of `|len/rest − 1|` is at most 1 % (1.000 %;
/// 1.18 % at 12, 1.60 % at 8). The 1.5 mm RMS that the implicit integrators hold on this scene
/// is not met at any step (module docs, "The frame's turn").
pub(crate) const AUTO_DT: f64 = 1.0 / 384.0;

/// Chord iterations of the direct solve per substep (module docs, step 3), each on the
/// multipliers accumulated so far.
const ITERATIONS: u32 = 4;

/// Constraint rows per segment: joint `j`'s three curvature components, then segment `j`'s
/// stretch.
const ROWS: usize = 4;

/// Width of the scalar band (diagonal included): block `j` shares a point with blocks `j − 2 …
/// j + 2`, so row `4j + 3` reaches column `4(j − 2)`, 11 to its left.
const BAND_WIDTH: usize = 2 * ROWS + ROWS;

/// Gradients of one segment's four constraint rows in the three points they move:
/// `[r][o] = ∂C_r/∂p_{j−1+o}` (the root joint's `o = 0` is zero: there is no point before the
/// root).
type BlockGradient<L> = [[V3<L>; 3]; ROWS];

/// Per-thread buffers of the XPBD substep, refitted to each group.
#[derive(Default)]
pub(crate) struct XpbdScratch<L: Lane> {
    /// Displacement of each point over the substep, m: the solve's positions are `x + disp`,
    /// kept apart so that the velocity `disp / h` does not take the round-off of `x` (module
    /// docs, "Round-off").
    disp: Vec<V3<L>>,
    /// Per segment: its rows' gradients at the substep's start (the directions of the
    /// corrections and the matrix's factors).
    gradient: Vec<BlockGradient<L>>,
    /// Per row: `α/h²`, 1/kg for stretch rows, 1/(kg·m²) for curvature rows (1 on rows of a
    /// constraint that is off, whose gradient and residual are zero).
    compliance: Vec<L>,
    /// Per row: the multiplier accumulated over the substep's iterations (kg·m for stretch,
    /// kg·m² for curvature).
    lambda: Vec<L>,
    /// Per row: the right-hand side `−C − α̃ λ`, then the solution `Δλ`.
    rhs: Vec<L>,
    /// The matrix `G W Gᵀ + α̃` of the substep, then its `L D Lᵀ` factor.
    band: BandLdlt<L, BAND_WIDTH>,
    /// Rest curvature `K_j` per joint in the previous segment's frame: (unused, u, w), 1
    /// (`rest_moment / joint_k`).
    rest_curvature: Vec<V3<L>>,
}

impl<L: Lane> XpbdScratch<L> {
    /// Sizes the buffers for the gathered group `g`, takes the rest curvatures from it and the
    /// compliances of the step's substep.
    fn fit(&mut self, g: &Scratch<L>, c: &StepConstants) {
        let n = g.x.len();
        let rows = ROWS * (n - 1);
        self.disp.clear();
        self.disp.resize(n, V3::default());
        self.gradient.clear();
        self.gradient.resize(n - 1, [[V3::default(); 3]; ROWS]);
        for buf in [&mut self.compliance, &mut self.lambda, &mut self.rhs] {
            buf.clear();
            buf.resize(rows, L::default());
        }
        let one = splat::<L>(1.0);
        let inv_h2 = splat::<L>(1.0 / (c.dt * c.dt));
        let stretch = if c.stretch > 0.0 {
            // Compliance 1/k, m/N.
            inv_h2 * (one / g.stretch_k)
        } else {
            one
        };
        for j in 0..n - 1 {
            let bend = if c.bend > 0.0 {
                inv_h2 * div_or_zero(one, g.joint_k[j], 0.0)
            } else {
                one
            };
            self.compliance[ROWS * j..ROWS * j + 3].fill(bend);
            self.compliance[ROWS * j + 3] = stretch;
        }
        self.rest_curvature.clear();
        if c.bend > 0.0 {
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
    let drag = g.drag;
    let gravity = V3::splat(&c.gravity);
    let zero = splat::<L>(0.0);
    let constrained = c.stretch > 0.0 || c.bend > 0.0;
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
        // 2–3. Stretch and bending, one direct solve per iteration.
        if constrained {
            start_gradients(g, &mut s, &rot, c);
            assemble(g, &mut s);
            s.band.factor();
            s.lambda.fill(zero);
            for _ in 0..ITERATIONS {
                residual(g, &mut s, &rot, c);
                s.band.solve(&mut s.rhs);
                correct(g, &mut s);
            }
        }
        // 4. Goal springs.
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
        finish_substep(g, c, (k + 1) as f32 * c.dt, &origin, &rot, false);
        clock.advance(origin, rot);
    }
    g.xpbd = s;
    g.scatter(views);
}

/// A unit vector along `d` and `1/|d|` (both zero for a segment shorter than 1 nm, which then
/// takes no constraint direction).
#[inline(always)]
fn unit<L: Lane>(d: V3<L>) -> (V3<L>, L) {
    let inv = div_or_zero(splat(1.0), d.dot(&d).sqrt(), 1e-9);
    (d * inv, inv)
}

/// The root joint's reference: the first segment's unit rest direction in the root frame `rot`.
#[inline(always)]
fn root_direction<L: Lane>(g: &Scratch<L>, rot: &M3<L>) -> V3<L> {
    let (t, u) = (rot.cols[2], rot.cols[0]);
    let r = g.root_rest;
    t * r.x + u * r.y + t.cross(&u) * r.z
}

/// The gradients of every constraint row at the substep's start positions `g.x` into
/// `s.gradient` (module docs, step 3); `rot` is the root frame at the substep's end.
#[inline(always)]
fn start_gradients<L: Lane>(
    g: &Scratch<L>,
    s: &mut XpbdScratch<L>,
    rot: &M3<L>,
    c: &StepConstants,
) {
    let n = g.x.len();
    let (zero, one) = (splat::<L>(0.0), splat::<L>(1.0));
    let none = V3::<L>::default();
    let mut a = root_direction(g, rot);
    let mut inv_a = zero;
    for j in 0..n - 1 {
        let (b, inv_b) = unit(g.x[j + 1] - g.x[j]);
        let grad = &mut s.gradient[j];
        if c.stretch > 0.0 {
            grad[3] = [none, none - b, b];
        }
        if c.bend > 0.0 {
            // ∂κ/∂b = χ (2[a]× − κ aᵀ) and ∂κ/∂a = −χ (2[b]× + κ bᵀ) = χ (2[−b]× + κ (−b)ᵀ):
            // both of the form χ (2[e]× + κ' eᵀ), with (e, κ') = (a, −κ) and (−b, κ); point
            // j − 1 moves a, point j + 1 moves b, point j both.
            let chi = div_or_zero(one, one + a.dot(&b), 1e-6);
            let kappa = a.cross(&b) * (chi * splat(2.0));
            let jb = Rows::curvature_gradient(chi, &a, &(none - kappa), &b, inv_b);
            let ja = Rows::curvature_gradient(chi, &(none - b), &kappa, &a, inv_a);
            let jm = ja.minus(&jb);
            for (r, row) in grad.iter_mut().take(3).enumerate() {
                *row = [none - ja.0[r], jm.0[r], jb.0[r]];
            }
        }
        a = b;
        inv_a = inv_b;
    }
}

/// The inverse mass of point `j − 1 + o`, the `o`-th point segment `j`'s rows move (zero before
/// the root).
#[inline(always)]
fn weight<L: Lane>(g: &Scratch<L>, j: usize, o: usize) -> L {
    if j + o == 0 {
        L::default()
    } else {
        g.inv_mass[j + o - 1]
    }
}

/// Assembles `G W Gᵀ + α̃` (module docs, step 3) into the band from the start gradients.
#[inline(always)]
fn assemble<L: Lane>(g: &Scratch<L>, s: &mut XpbdScratch<L>) {
    let blocks = s.gradient.len();
    s.band.reset(ROWS * blocks);
    for j in 0..blocks {
        let gj = &s.gradient[j];
        for r in 0..ROWS {
            let row_index = ROWS * j + r;
            let row = s.band.row_mut(row_index);
            // Blocks j − d, d = 0, 1, 2, share points j − 1 + o (o ≤ 2 − d) with block j, where
            // they are their point o + d.
            for d in 0..=j.min(2) {
                let gk = &s.gradient[j - d];
                let cols = if d == 0 { r + 1 } else { ROWS };
                for col in 0..cols {
                    let mut sum = L::default();
                    for o in 0..=2 - d {
                        sum += weight(g, j, o) * gj[r][o].dot(&gk[col][o + d]);
                    }
                    row[ROWS * d + r - col] = sum;
                }
            }
            row[0] += s.compliance[row_index];
        }
    }
}

/// The right-hand side `−C(p) − α̃ λ` of every row at the current positions `x + disp` (module
/// docs, steps 2–3); `rot` is the root frame at the substep's end.
#[inline(always)]
fn residual<L: Lane>(g: &Scratch<L>, s: &mut XpbdScratch<L>, rot: &M3<L>, c: &StepConstants) {
    let n = g.x.len();
    let one = splat::<L>(1.0);
    // The previous segment's frame (tangent, u), carried from the root frame down the strand.
    let mut tp = rot.cols[2];
    let mut up = rot.cols[0];
    let mut a = root_direction(g, rot);
    for j in 0..n - 1 {
        let d = (g.x[j + 1] - g.x[j]) + (s.disp[j + 1] - s.disp[j]);
        let base = ROWS * j;
        if c.stretch > 0.0 {
            let len = d.dot(&d).sqrt();
            s.rhs[base + 3] = g.rest_length[j] - len - s.compliance[base + 3] * s.lambda[base + 3];
        }
        if c.bend > 0.0 {
            let (b, _) = unit(d);
            let rest = if j == 0 {
                V3::default()
            } else {
                up = transport(&up, &tp, &a);
                tp = a;
                let k = s.rest_curvature[j];
                up * k.y + a.cross(&up) * k.z
            };
            let chi = div_or_zero(one, one + a.dot(&b), 1e-6);
            let kappa = a.cross(&b) * (chi * splat(2.0));
            let err = kappa - rest;
            let alpha = s.compliance[base];
            s.rhs[base] = L::default() - err.x - alpha * s.lambda[base];
            s.rhs[base + 1] = L::default() - err.y - alpha * s.lambda[base + 1];
            s.rhs[base + 2] = L::default() - err.z - alpha * s.lambda[base + 2];
            a = b;
        }
    }
}

/// Adds the solved `Δλ` (in `s.rhs`) to the multipliers and moves the points by `W Gᵀ Δλ`.
#[inline(always)]
fn correct<L: Lane>(g: &Scratch<L>, s: &mut XpbdScratch<L>) {
    for j in 0..s.gradient.len() {
        let grad = &s.gradient[j];
        let mut push = [V3::<L>::default(); 3];
        for (r, row) in grad.iter().enumerate() {
            let dl = s.rhs[ROWS * j + r];
            s.lambda[ROWS * j + r] += dl;
            for (p, d) in push.iter_mut().zip(row) {
                *p += *d * dl;
            }
        }
        for (o, p) in push.iter().enumerate() {
            if j + o > 0 {
                s.disp[j + o - 1] += *p * weight(g, j, o);
            }
        }
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

    /// The zero vector in every lane.
    fn zero_v() -> V3<L> {
        V3::default()
    }

    fn v3(x: f32, y: f32, z: f32) -> V3<L> {
        V3::splat(&Vector3::new(x, y, z))
    }

    /// The curvature binormal of points `p` (joint at `p[1]`).
    fn kappa(p: &[Vector3<f64>; 3]) -> Vector3<f64> {
        let a = (p[1] - p[0]).normalize();
        let b = (p[2] - p[1]).normalize();
        2.0 * a.cross(&b) / (1.0 + a.dot(&b))
    }

    /// The rows `start_gradients` builds for a joint are the derivatives of `κ` in its three points
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
        let jb = Rows::curvature_gradient(chi, &a, &(zero_v() - kap), &b, inv_b);
        let ja = Rows::curvature_gradient(chi, &(zero_v() - b), &kap, &a, inv_a);
        let grads = [Rows(ja.0.map(|r| zero_v() - r)), ja.minus(&jb), jb];
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

    /// A group of one bent strand (the same in every lane) of `n` points at rest: 2 cm
    /// segments turning by 0.3 rad each about alternating axes, root pinned, 1 g points, the
    /// step's stretch stiffness, its rest curvatures those of its shape, and its root frame
    /// (identity).
    fn bent_strand(n: usize, c: &StepConstants) -> (Scratch<L>, XpbdScratch<L>, M3<L>) {
        let mut g = Scratch::<L> {
            stretch_k: splat(c.stretch),
            ..Default::default()
        };
        let mut p = Vector3::new(0.0f32, 0.0, 0.0);
        let mut dir = Vector3::new(0.0f32, 0.0, 1.0);
        for i in 0..n {
            g.x.push(v3(p.x, p.y, p.z));
            g.inv_mass.push(splat(if i == 0 { 0.0 } else { 1000.0 }));
            g.free.push(splat(if i == 0 { 0.0 } else { 1.0 }));
            let axis = if i % 2 == 0 {
                Vector3::x()
            } else {
                Vector3::y()
            };
            dir = nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), 0.3)
                * dir;
            p += dir * 0.02;
        }
        for _ in 0..n - 1 {
            g.rest_length.push(splat(0.02));
            g.joint_k.push(splat(c.bend * 0.02 * 0.02));
            g.rest_moment.push(V3::default());
        }
        let rot = M3 {
            cols: [v3(1.0, 0.0, 0.0), v3(0.0, 1.0, 0.0), v3(0.0, 0.0, 1.0)],
        };
        // Root rest direction (t, u, w) = (z, x, y) components of the first segment.
        let (d0, _) = unit(g.x[1] - g.x[0]);
        g.root_rest = V3 {
            x: d0.z,
            y: d0.x,
            z: d0.y,
        };
        let mut s = XpbdScratch::<L>::default();
        s.fit(&g, c);
        let (mut tp, mut up) = (rot.cols[2], rot.cols[0]);
        for j in 1..n - 1 {
            let (a, _) = unit(g.x[j] - g.x[j - 1]);
            let (b, _) = unit(g.x[j + 1] - g.x[j]);
            up = transport(&up, &tp, &a);
            tp = a;
            let kappa = a.cross(&b) * (splat::<L>(2.0) / (splat::<L>(1.0) + a.dot(&b)));
            s.rest_curvature[j] = V3 {
                x: splat(0.0),
                y: kappa.dot(&up),
                z: kappa.dot(&a.cross(&up)),
            };
        }
        (g, s, rot)
    }

    fn constants(dt: f32) -> StepConstants {
        let p = crate::HairParams {
            stretch_stiffness: 1.0e4,
            bend_stiffness: 20.0,
            ..Default::default()
        };
        StepConstants::new(&p, dt, 1, 0, crate::Integrator::Xpbd, None)
    }

    /// The band `assemble` builds is `G W Gᵀ + α̃` multiplied out densely from the same
    /// gradients: every entry within the band, at its place.
    #[test]
    fn assembled_band_is_the_dense_compliant_matrix() {
        let n = 6;
        let c = constants(1.0 / 96.0);
        let (g, mut s, rot) = bent_strand(n, &c);
        start_gradients(&g, &mut s, &rot, &c);
        assemble(&g, &mut s);
        let rows = ROWS * (n - 1);
        // Dense gradient of row R in point i.
        let grad = |r: usize, i: usize| -> Vector3<f64> {
            let (j, row) = (r / ROWS, r % ROWS);
            if i + 1 < j || i > j + 1 {
                return Vector3::zeros();
            }
            s.gradient[j][row][i + 1 - j].lane(0).cast()
        };
        for r in 0..rows {
            for col in r.saturating_sub(BAND_WIDTH - 1)..=r {
                let mut dense: f64 = (0..n)
                    .map(|i| g.inv_mass[i].to_array()[0] as f64 * grad(r, i).dot(&grad(col, i)))
                    .sum();
                if r == col {
                    dense += s.compliance[r].to_array()[0] as f64;
                }
                let band = s.band.row_mut(r)[r - col].to_array()[0] as f64;
                let mut diagonal = |q: usize| s.band.row_mut(q)[0].to_array()[0] as f64;
                // f32 round-off relative to the entries of rows r and col.
                let scale = (diagonal(r) * diagonal(col)).sqrt();
                assert!(
                    (band - dense).abs() <= 1e-5 * scale,
                    "A({r}, {col}) = {band} in the band, {dense} dense"
                );
            }
        }
    }

    /// From a bent, stiff strand at rest moved as in a substep, each chord iteration shrinks the
    /// compliant system's residual `C + α̃ λ` at least fourfold (measured: 6–50×; the rate is
    /// that of the gradients left out, the transported frame's turn under a 0.3 rad rest
    /// curvature), and a few reach its fixed point to f32 round-off.
    #[test]
    fn chord_iterations_converge_to_the_compliant_fixed_point() {
        let n = 9;
        let c = constants(1.0 / 96.0);
        let (g, mut s, rot) = bent_strand(n, &c);
        // A substep's motion: a sideways move growing along the strand, 2 mm at the tip.
        for i in 0..n {
            let t = i as f32 / (n - 1) as f32;
            s.disp[i] = v3(0.002 * t, -0.001 * t * t, 0.0) * g.free[i];
        }
        start_gradients(&g, &mut s, &rot, &c);
        assemble(&g, &mut s);
        s.band.factor();
        let mut norms = Vec::new();
        for _ in 0..6 {
            residual(&g, &mut s, &rot, &c);
            norms.push(
                s.rhs
                    .iter()
                    .map(|r| r.to_array()[0].abs())
                    .fold(0.0, f32::max),
            );
            s.band.solve(&mut s.rhs);
            correct(&g, &mut s);
        }
        residual(&g, &mut s, &rot, &c);
        norms.push(
            s.rhs
                .iter()
                .map(|r| r.to_array()[0].abs())
                .fold(0.0, f32::max),
        );
        println!("largest |C + α̃λ| per iteration: {norms:?}");
        for w in norms.windows(2).take(3) {
            assert!(w[1] < 0.25 * w[0], "residual {} then {}", w[0], w[1]);
        }
        assert!(norms[norms.len() - 1] < 1e-4 * norms[0]);
    }
}
