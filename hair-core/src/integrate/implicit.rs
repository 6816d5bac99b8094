//! The implicit substeps (`integrator = "implicit-euler"` and `"bdf2"`): linearised backward
//! Euler, or the second-order backward differentiation formula built on it, along each strand,
//! with one banded direct solve per strand per substep.
//!
//! # Why
//!
//! The explicit kernel's substep is bounded by the stiffest spring on the lightest point
//! ([`super::stability`]): on the default scene that is ~160 substeps per frame, although the
//! motion the eye sees (swinging, the head's turn) needs far fewer. Backward Euler is
//! unconditionally stable for the stiff stretch and bending modes, so the substep can follow
//! accuracy instead of stability. This is the scheme of Baraff and Witkin ("Large Steps in Cloth
//! Simulation", SIGGRAPH 1998) — one Newton step of backward Euler per substep — applied to a
//! chain, where the system is banded and solved exactly in O(n) instead of by conjugate gradients
//! (as in Hadap's and Selle et al.'s strand solvers, which also exploit the chain's band).
//!
//! # The step
//!
//! With `h` the substep, `M` the (lumped) masses, `f` the forces at the substep's start,
//! `K = −∂f/∂x` and `D = −∂f/∂v`, backward Euler linearised about the substep's start,
//! `M Δv = h f(x + h v', v')` with `v' = v + Δv`, becomes
//!
//! `(M + h D + h² K) Δv = h f(x, v) − (h D + h² K) v`,   then `x += h v'`.
//!
//! What is in `f`, `K` and `D`:
//!
//! - **stretch springs**, force `k (|d| − l) d/|d|`: their exact Jacobian `k (t tᵀ + α (I − t tᵀ))`,
//!   `α = 1 − l/|d|`, with `α` clamped at 0 for a compressed segment (the standard definiteness
//!   fix: a compressed spring's negative transverse stiffness would make the system indefinite),
//! - **stretch damping** (`stretch_damping`, 1/s) as a viscous force along each segment with
//!   coefficient `rate / (w_j + w_{j+1})`, which damps an isolated segment's stretching speed at
//!   `rate`, the meaning the explicit kernel's damping sub-loop gives it; the sub-loop does not
//!   run,
//! - **bending**: the force is the exact curvature gradient of [`super::curvature`] (computed by
//!   the same code as the explicit kernel); the matrix takes one of two approximations of its
//!   Hessian, per group of strands:
//!   - **small-angle**, about a straight strand: joint `j` turns by `θ_j = (δ_{j+1} − δ_j)/l_j −
//!     (δ_j − δ_{j−1})/l_{j−1}` for sideways displacements `δ`, so it adds `k_j e eᵀ ⊗ P` with
//!     `e = (1/l_{j−1}, −1/l_{j−1} − 1/l_j, 1/l_j)` on points `j − 1, j, j + 1` and `P = I − t̄ t̄ᵀ`
//!     the projection across the joint's mean tangent; the root joint adds `k_0/l_0² P` on the
//!     first segment's relative motion. It leaves out the terms of a curved rest shape, which
//!     is right where joints turn little at rest and wrong where they turn much: on the bench's
//!     curly hair (46° joints) implicit Euler blew up below 16 substeps per frame with it;
//!   - **Gauss–Newton**, for groups with a joint turning more than [`SHARP_REST_TURN_DEG`] at
//!     rest: `k Jᵀ J` with `J` the exact Jacobian of each joint's residual `κ − K` at the
//!     current shape (`bending_hessian`), including the turn of the transported frame that
//!     carries `K` as the joint's first tangent turns. It costs a third more per substep (its
//!     blocks coupling two points are unsymmetric 3×3 products) and halves the substeps
//!     implicit Euler and BDF2 need on the curly hair (3 % stretch at 32 substeps per frame
//!     became 0.2 %);
//!
//!   both are positive semi-definite and couple points two apart (the band's second
//!   off-diagonal), and both leave out the twist that parallel transport accumulates from the
//!   root (approximating the Jacobian changes only how the stiff modes are damped, not the
//!   equilibrium),
//! - **goal springs** (`k_goal w I` on the diagonal) and **air drag** (`m · drag · I`), implicit,
//! - gravity, force fields and hair–hair repulsion as explicit forces (constant over the
//!   substep).
//!
//! Kinematic points (the root, pinned points) get the velocity of their prescribed motion; their
//! rows are replaced by the identity and their known `Δv` moved to the right-hand side.
//!
//! The contact response (`crate::contacts::penalty`), the position update, the inextensibility
//! projection and the strain limit then run as in the explicit kernel
//! ([`super::kernel::finish_substep`]): contacts act on the solved velocity, as they act on the
//! explicit kernel's updated velocity; hair–hair friction acts between steps, as it does for the
//! explicit kernel.
//!
//! # The solve
//!
//! The matrix is symmetric positive definite (masses plus positive semi-definite stiffness and
//! damping), block-pentadiagonal with 3×3 blocks, i.e. a scalar band of half-width 8 over the
//! `3n` velocity components. It is factored as block `L D Lᵀ` on the 3×3 blocks the assembly
//! writes ([`super::block_band`]) in `≈ 160 n` multiply–adds, eight strands per SIMD instruction
//! like the explicit kernel, and solved for `Δv` (not `v'`, so rounding is relative to the
//! change).
//!
//! # Artificial damping
//!
//! Backward Euler multiplies the amplitude of an undamped mode of angular frequency `ω` by
//! `1/sqrt(1 + (ωh)²)` per substep: the stiff modes are damped out (what makes it stable), and
//! the swing of the hair too, by `≈ exp(−π ω h)` per period (`2π/(ωh)` substeps of
//! `1 − (ωh)²/2`): 10 % per period for a 1 s swing at 192 substeps per second, 5 % at 384.
//! The pendulum test in `tests/tests/implicit_euler.rs` measures it against this formula.
//!
//! # BDF2
//!
//! Backward Euler's error is first order, and most of it on hair is that damping. BDF2 (the
//! second-order backward differentiation formula, as Choi and Ko used it for cloth, "Stable but
//! Responsive Cloth", SIGGRAPH 2002) is as stable (A- and L-stable: the stiff modes are still
//! damped out) but second order: per substep it takes `≈ (ωh)⁴/4` of a swing's amplitude
//! instead of `(ωh)²/2`. Its step, `y' = (4 y − y_prev)/3 + (2h/3) ẏ'` for `y = x, v`, is a backward
//! Euler step of length `2h/3` from the extrapolated state `((4 x − x_prev)/3, (4 v − v_prev)/3)`,
//! so it reuses everything above: one assembly and one banded solve per substep, the same
//! linearisation about where the substep starts (here the extrapolated positions), and the same
//! contact response, kinematic points and strain limit with `2h/3` as the position update's
//! step. The extrapolation is computed as `y + (y − y_prev)/3`, whose coefficients sum to one
//! exactly; the textbook `(4 y − y_prev)·⅓` in f32 scales the state by `1 + 3·10⁻⁸` a substep, a
//! drift that caps the measured order.
//!
//! BDF2 needs the state one substep back, which a collision step does not have at its start
//! (hair–hair friction and the contacts change between steps, and a resumed run starts there).
//! With two or more substeps a step therefore starts with the linearised **implicit midpoint
//! rule** (the trapezoidal rule on this linear system, the first stage of Bank et al.'s TR-BDF2,
//! 1985) over its first substep, and continues with BDF2: the midpoint substep is a backward
//! Euler solve over `h/2`, whose velocity `v + Δv` moves the points over the whole substep, and
//! the velocity ends at `v + 2Δv` (the contact response and the length limits act on it as on
//! any substep). It is second order and A-stable, and costs one solve, so a step costs as many
//! solves as it has substeps. It does not damp the stiff modes (their amplitude changes sign);
//! the BDF2 substeps after it do. A step of one substep has no BDF2 substep after it, so it
//! starts instead with a backward Euler substep of `h/3` and continues with variable-step BDF2
//! (step ratio `r`: `y' = ((1 + r)² y − r² y_prev)/(1 + 2r) + h_n (1 + r)/(1 + 2r) ẏ'`,
//! zero-stable for `r < 1 + √2`) over `2h/3` (`r = 2`): two solves, a first-order start that
//! loses `(ωh/3)²/2` of a swing per step, and the stiff modes damped within the step.
//!
//! Why the midpoint start rather than the backward Euler third on every step: it takes less of
//! a swing, and less time for the error `"auto"` asks for. The pendulum at h = 1/96 s loses
//! 1.8 % per period (with the `h/3` backward Euler start 2.2 %, a full-length backward Euler
//! start 6.7 %, backward Euler throughout 13.5 %); the swinging chain's error at 8, 16, 32, 64
//! substeps per frame is 4.7, 0.82, 0.17, 0.058 mm (with the `h/3` start 5.4, 1.06, 0.20,
//! 0.054); the default scene's strand phase is 8 % cheaper at 1.25 mm RMS over the shot (1.28
//! with the `h/3` start). It is not better everywhere: at 4 and 6 substeps per frame the default
//! scene is 2.31 and 1.55 mm off (2.09 and 1.52 with the `h/3` start), and on the bench's curly
//! hair at 32 substeps per frame the slow rise of energy that both starts show (below, flutter)
//! is a little faster, its largest stretch 0.18 % against 0.15 %. The full comparison:
//! `docs/design/implicit-integrators.md`.
//!
//! **Contacts and the history.** The contact response changes a point's velocity within a
//! substep (`crate::contacts::penalty`), and BDF2's next start `y + b (y − y_prev)` extrapolates
//! that change: a point that hit the surface at normal speed `v_n` and was stopped starts the
//! next substep leaving it at `b·v_n`, and its position carries on the approach into the
//! surface. So before each BDF2 substep the points the response **stopped** in the substep just
//! taken (an impact: a velocity change of more than [`super::kernel::IMPACT_RATIO`] times what
//! gravity and the external forces add over the substep) get the history of a point that has
//! always moved at its present velocity, `(x − h_prev v, v)`: the substep is then a BDF2 step of
//! a point in uniform motion, first order for that point in that substep only. Resting contact,
//! whose response only cancels what gravity added, keeps its history: restarting every point
//! the response touches lets free points on a sphere slide off it at two substeps per frame
//! (`tests/tests/collision_drop_on_sphere.rs`), and taking the impulse out of the remembered
//! velocity, or cutting the extrapolated outward velocity, raises the default scene's stretch or
//! error. With the restart, free points dropped on a sphere stop on it (without it they leave it
//! at 31 % of the impact speed at one substep per frame and 3 % at seven); the default scene at
//! 7 substeps per frame is 1.33 mm RMS from the reference (1.36 without; p99 stretch 0.763 %
//! against 0.760 %), the parity scene with its collider 48.6 mm at 7 (52.6 without) and 114.4 at
//! 1 (114.6). The variants measured: `docs/design/implicit-integrators.md`.
//!
//! The linearisation's bending matrix is approximate (above), and it multiplies the whole
//! velocity of the substep: that leaves a first-order term, small against the second-order
//! one at the steps hair uses (the order measured on a swinging chain is 2.1, 2.5, 2.3 from 4 to
//! 32 substeps per frame, 1.6 to 64, 1.3 beyond). Evaluating the forces at the predicted end
//! `x̂ + (2h/3) v̂` instead, so that the approximate matrix multiplies only the correction,
//! would remove that term, but the stiff cantilever at two substeps per frame then diverges from
//! predictions far along the stiff modes, so the step linearises about its start.
//!
//! **Flutter at fine steps (a limit of BDF2 here).** What the approximate matrix leaves out
//! acts as an explicit force within the substep, and an explicit force can feed a mode a
//! little energy every substep, at a rate that shrinks only like `h`. Backward Euler's own
//! damping (`(ωh)²/2` per substep) outweighs that at every step; BDF2's (`(ωh)⁴/4`) outweighs
//! it only at long steps, and the physical damping only at very short ones. In between, the
//! bench's curly hair (Gauss–Newton bending, 46° joints) flutters under BDF2: it settles at 64
//! substeps per frame and from 1,024, but at 128–512 its energy climbs from frame 5 and its
//! segments stretch 2–5 % for the rest of the run, where implicit Euler settles at every count
//! (`bench/src/curly.rs`, `flutter_study`). It is not BDF2's second root (restarting
//! BDF2 with backward Euler every 8 substeps flutters alike) and it grows with the matrix's
//! error (the small-angle Hessian flutters from 64). The bench's straighter hair (drape, head
//! turn, cantilever, chain) holds at every count up to 512. `integrator = "auto"` stays outside
//! the window: it gives a groom whose rest joints turn more than 45° BDF2 only at the 1/768 s
//! substep of `substeps = "auto"` and, at a fixed count, semi-implicit Euler. A scene that names
//! BDF2 with fine steps on sharply bent hair should take implicit Euler instead; the scene
//! layer warns of it (`hairsys::scene::integrator::sharp_joint_warning`).
//!
//! **No Newton correction.** One simplified Newton iteration per substep (the residual
//! `M Δv − h f(x + h v', v')` with the forces at the substep's end, solved with the factor
//! already computed) removes the flutter (the curly hair settles under BDF2 at 64–512 substeps
//! per frame) but makes large steps worse, where the approximate matrix is furthest from the
//! true Jacobian: without a safeguard the curly hair blows up at 8 and 16 substeps per frame and
//! stretches up to 77 % at 32; keeping the correction only where it is under half the first
//! change of velocity stops the blow-ups, but BDF2 at 32 (the step `"auto"` gives such hair)
//! then stretches 2.1 % instead of 0.15 %. On the default scene it lets BDF2 take 6 substeps per
//! frame for the error of 8 (1.20 mm against 1.28 mm over the shot) at 15–31 % more per
//! substep, no net saving, so the substep has none. The prototype and its figures:
//! `docs/design/implicit-integrators.md`. A complete Jacobian (the bending Hessian's
//! second-derivative terms, made definite) is the alternative not yet measured.

use super::block_band::solve_in_place;
use super::blocks::{Mat3, Sym3};
use super::dispatch::avx2_copy;
use super::kernel::{
    elastic_forces, finish_substep, kinematic_velocity, Scratch, StepConstants, StrandView,
    SubstepClock,
};
use super::lanes::{div_or_zero, splat, zeroed, Lane, LANES, M3, V3};
use super::params::Integrator;
use crate::mesh::RootFrame;

/// Longest substep `substeps = "auto"` takes with this integrator, s. Stability sets no bound
/// here; accuracy does: on the default scene (head turn, collider, hair–hair, strain limit) 16
/// substeps per frame at 24 fps (h = 1/384 s) measure 0.92 mm RMS against the converged
/// inextensible reference over the shot's first 24 frames, 8 measure 1.64 mm, beyond the
/// default scene's 1.5 mm target; and backward Euler's artificial damping of a 1 s swing is 5 % per
/// period (`exp(−π ω h)`).
pub(crate) const AUTO_DT: f64 = 1.0 / 384.0;

/// Longest substep `substeps = "auto"` takes with [`crate::Integrator::Bdf2`], s: the longest
/// that keeps the default scene's targets (1.5 mm RMS against the converged reference, p99
/// stretch 1 %). Measured like [`AUTO_DT`] (`implicit_euler_default_scene`, `STUDY_FRAMES=48`:
/// the whole shot, both turns and the nod): substeps per frame at 24 fps 6, 7, 8 give 1.55, 1.36,
/// 1.25 mm RMS (worst frame 2.36, 2.03, 1.82 mm) with p99 stretch 0.89, 0.76, 0.67 %; 4 and 5
/// give 2.31 and 1.81 mm (implicit Euler at 16: 1.86 mm, 0.50 %). 7 keeps both targets over the
/// whole shot; 6 misses the first. (These figures leave out the contact restart of the module
/// docs, which takes 7 to 1.33 mm; when each was measured: `docs/design/implicit-integrators.md`.)
pub(crate) const AUTO_DT_BDF2: f64 = 1.0 / 168.0;

/// Rest turn of a joint (degrees) beyond which a group of strands takes bending's Gauss–Newton
/// Hessian instead of the small-angle one (module docs). The small-angle form serves the default
/// groom (joints up to 27°); on the bench's curly hair (46°) implicit Euler with it stretched 3 %
/// at 32 substeps per frame and needed 64 to stay under 1 %, and with the Gauss–Newton form 0.2 %
/// at 32. The Gauss–Newton form makes the default scene's strand phase a third slower when forced
/// on it (one thread), so straighter grooms keep the small-angle form, bit for bit.
const SHARP_REST_TURN_DEG: f32 = 30.0;

/// Per-thread buffers of the implicit substep, refitted to each group.
#[derive(Default)]
pub(crate) struct ImplicitScratch<L: Lane> {
    /// Point masses, kg (0 where pinned).
    mass: Vec<L>,
    /// `1 / rest length` per segment, 1/m.
    inv_rest: Vec<L>,
    /// Viscous coefficient of each segment's stretch damping, kg/s.
    damp: Vec<L>,
    /// Block `(i, i)` of `h D + h² K` per point.
    diag: Vec<Sym3<L>>,
    /// Block `(i + 1, i)` (its transpose is block `(i, i + 1)`).
    next: Vec<Mat3<L>>,
    /// Block `(i + 2, i)` (bending only; its transpose is block `(i, i + 2)`).
    skip: Vec<Mat3<L>>,
    /// Right-hand side per point, then the solution `Δv`.
    rhs: Vec<V3<L>>,
    /// `Δv` of each point the group pins in some lane (in the order of `Scratch::pinned`), kept
    /// while their rows are replaced.
    known: Vec<V3<L>>,
    /// The previous substep's state, for BDF2.
    history: History<L>,
}

/// The state at the start of the previous substep, which a BDF2 substep extrapolates from.
#[derive(Default)]
struct History<L: Lane> {
    /// Positions, m.
    x: Vec<V3<L>>,
    /// Velocities, m/s.
    v: Vec<V3<L>>,
}

impl<L: Lane> History<L> {
    /// Remembers the state `(x, v)` at a substep's start.
    #[inline(always)]
    fn remember(&mut self, x: &[V3<L>], v: &[V3<L>]) {
        self.x.clear();
        self.x.extend_from_slice(x);
        self.v.clear();
        self.v.extend_from_slice(v);
    }

    /// Before a BDF2 substep: gives the points a contact stopped in the substep just taken
    /// (`g.impacted`; `h_prev` s long) the history of a point that has moved at its present
    /// velocity all along, `(x − h_prev v, v)`, so that the extrapolation neither re-applies
    /// the stop as a bounce nor carries on the approach it ended (module docs, "Contacts and the
    /// history").
    #[inline(always)]
    fn restart_impacted(&mut self, g: &Scratch<L>, h_prev: f32) {
        let zero = splat::<L>(0.0);
        let h_prev = splat::<L>(h_prev);
        for &i in &g.contact_points {
            let stopped = g.impacted[i].simd_gt(zero);
            if L::any(stopped) {
                let moved_on = g.x[i] - g.v[i] * h_prev;
                self.x[i] = V3::select(stopped, &moved_on, &self.x[i]);
                self.v[i] = V3::select(stopped, &g.v[i], &self.v[i]);
            }
        }
    }

    /// Before a BDF2 substep `r` times as long as the previous one: remembers the state `(x, v)`
    /// at its start and replaces it by `((1 + r)² y − r² y_prev) / (1 + 2r)` for `y = x, v` (with
    /// `r = 1`, `(4 y − y_prev)/3`), from which the substep is backward Euler over
    /// `(1 + r)/(1 + 2r)` of its length (the variable-step BDF2 formula).
    #[inline(always)]
    fn extrapolate(&mut self, x: &mut [V3<L>], v: &mut [V3<L>], r: f32) {
        // As `y + b (y − y_prev)`: the coefficients sum to 1 exactly whatever their rounding, so
        // round-off does not scale the state a little every substep.
        let b = splat::<L>(r * r / (1.0 + 2.0 * r));
        for (now, prev) in x
            .iter_mut()
            .zip(&mut self.x)
            .chain(v.iter_mut().zip(&mut self.v))
        {
            let hat = *now + (*now - *prev) * b;
            *prev = *now;
            *now = hat;
        }
    }
}

impl<L: Lane> ImplicitScratch<L> {
    /// Sizes the buffers for `n` points and takes the per-step constants from the gathered group.
    fn fit(&mut self, g: &Scratch<L>) {
        let one = splat::<L>(1.0);
        self.mass.clear();
        self.mass
            .extend(g.inv_mass.iter().map(|&w| div_or_zero(one, w, 0.0)));
        self.inv_rest.clear();
        self.inv_rest.extend(g.rest_length.iter().map(|&l| one / l));
        let rate = g.damp_rate;
        self.damp.clear();
        self.damp.extend(
            g.inv_mass
                .windows(2)
                .map(|w| div_or_zero(rate, w[0] + w[1], 0.0)),
        );
    }
}

/// Does a joint of the gathered group turn by more than [`SHARP_REST_TURN_DEG`] at rest, in any
/// lane? Its bending then takes the Gauss–Newton Hessian instead of the small-angle one (module
/// docs).
fn has_sharp_rest_joint<L: Lane>(g: &Scratch<L>) -> bool {
    // |k K| > k |K_sharp|, with |K| = 2 tan(θ/2) for a joint turning by θ.
    let sharp = splat::<L>(2.0 * (SHARP_REST_TURN_DEG.to_radians() / 2.0).tan());
    (1..g.x.len() - 1).any(|j| {
        let (rest, limit) = (g.rest_moment[j], g.joint_k[j] * sharp);
        L::any(rest.dot(&rest).simd_gt(limit * limit))
    })
}

avx2_copy!(
    /// [`step_group_implicit`] on [`super::lanes::F8`] lanes compiled for AVX2 where the CPU has it (the same
    /// bits as the baseline copy; see [`super::dispatch`]).
    pub(crate) fn step_group_implicit_avx2 => step_group_implicit
);

/// Advances a group of strands (equal point counts, at most [`LANES`]) by one collision step of
/// implicit substeps (module docs): backward Euler, or BDF2 with
/// [`Integrator::Bdf2`]; roots and pinned points move as in the explicit kernel.
#[inline(always)]
pub(crate) fn step_group_implicit<L: Lane>(
    views: &mut [StrandView],
    starts: &[RootFrame],
    ends: &[RootFrame],
    c: &StepConstants,
    g: &mut Scratch<L>,
) {
    debug_assert!(!views.is_empty() && views.len() <= LANES);
    g.fit(views, starts, ends, c);
    g.gauss_newton_bending = c.bend > 0.0 && has_sharp_rest_joint(g);
    let mut s = std::mem::take(&mut g.implicit);
    s.fit(g);
    let mut clock = SubstepClock::new(g);
    if c.integrator == Integrator::Bdf2 {
        bdf2_substeps(g, &mut s, c, &mut clock);
    } else {
        for k in 0..c.substeps {
            let end = clock.end_of(g, k, c.substeps);
            substep(g, &mut s, c, &mut clock, (k + 1) as f32 * c.dt, end, false);
        }
    }
    g.implicit = s;
    g.scatter(views);
}

/// The substeps of one collision step by BDF2 (`c.substeps` of `h = c.dt`; module docs): with
/// two or more, an implicit midpoint substep, then BDF2 substeps of ratio 1 ending at `2h, 3h,
/// …`; with one, a backward Euler substep of `h/3`, then a BDF2 substep of `2h/3` (ratio 2).
#[inline(always)]
fn bdf2_substeps<L: Lane>(
    g: &mut Scratch<L>,
    s: &mut ImplicitScratch<L>,
    c: &StepConstants,
    clock: &mut SubstepClock<L>,
) {
    let h = c.dt;
    let n = c.substeps;
    s.history.remember(&g.x, &g.v);
    // Per substep: how it starts (BDF2 with its ratio to the previous substep's length), the
    // solve's dt (s), its end (s from the step's start) and that end as a fraction of the step.
    // One call site, so the inlined substep is compiled once.
    let third = (1.0 / 3.0) * h;
    let one_substep = [
        (Start::BackwardEuler, third, third, 1.0 / 3.0),
        // BDF2 over 2h/3 after a substep r = 2 times shorter: backward Euler over
        // (1 + r)/(1 + 2r) of its length from the extrapolated state.
        (Start::Bdf2(2.0), (2.0 / 3.0) * h * 3.0 / 5.0, h, 1.0),
    ];
    let midpoint = std::iter::once((Start::Midpoint, h, h, 1.0 / n as f32));
    let rest = (2..=n).map(|k| {
        (
            Start::Bdf2(1.0),
            h * 2.0 / 3.0,
            k as f32 * h,
            k as f32 / n as f32,
        )
    });
    let plan: &mut dyn Iterator<Item = (Start, f32, f32, f32)> = if n == 1 {
        &mut one_substep.into_iter()
    } else {
        &mut midpoint.chain(rest)
    };
    // Start and end (s from the step's start) of the substep last taken.
    let mut last = (0.0, 0.0);
    for (start, dt, t_end, end) in plan {
        let at_end = clock.at(g, end);
        if let Start::Bdf2(r) = start {
            if g.has_contacts {
                s.history.restart_impacted(g, last.1 - last.0);
            }
            s.history.extrapolate(&mut g.x, &mut g.v, r);
        }
        let c = StepConstants { dt, ..*c };
        substep(g, s, &c, clock, t_end, at_end, start == Start::Midpoint);
        last = (last.1, t_end);
    }
}

/// How a BDF2 substep starts (module docs).
#[derive(Clone, Copy, PartialEq)]
enum Start {
    /// Backward Euler from the current state.
    BackwardEuler,
    /// The implicit midpoint rule from the current state.
    Midpoint,
    /// BDF2 from the state extrapolated with this ratio to the previous substep's length.
    Bdf2(f32),
}

/// One backward Euler substep of `c.dt` from the state in `g` (which BDF2 has extrapolated),
/// ending `t_end` (s) after the step's start with the root frame `(origin, rot)`; with
/// `midpoint`, the linearised implicit midpoint rule (the trapezoidal rule) instead: the backward
/// Euler solve over `c.dt / 2` gives the midpoint velocity `v_m = v + Δv`, which moves the
/// points over the whole substep (contacts and length limits acting on it as on any substep),
/// and the velocity ends at `v_m + Δv` (`2 v_m − v` before those corrections).
#[inline(always)]
fn substep<L: Lane>(
    g: &mut Scratch<L>,
    s: &mut ImplicitScratch<L>,
    c: &StepConstants,
    clock: &mut SubstepClock<L>,
    t_end: f32,
    (origin, rot): (V3<L>, M3<L>),
    midpoint: bool,
) {
    elastic_forces(g, c, clock);
    let solved_over = if midpoint { c.dt / 2.0 } else { c.dt };
    assemble(
        g,
        s,
        &StepConstants {
            dt: solved_over,
            ..*c
        },
        clock,
    );
    // Kinematic points take the velocity that reaches the scalp over the whole substep.
    solve_velocities(g, s, c, &origin, &rot);
    if midpoint {
        // Δv, into the right-hand side's buffer (rebuilt by the next assembly).
        for (dv, (v, v0)) in s.rhs.iter_mut().zip(g.v.iter().zip(&s.history.v)) {
            *dv = *v - *v0;
        }
    }
    finish_substep(g, c, t_end, &origin, &rot, false);
    if midpoint {
        for (v, (dv, free)) in g.v.iter_mut().zip(s.rhs.iter().zip(&g.free)) {
            *v += *dv * *free;
        }
    }
    clock.advance(origin, rot);
}

/// Solves the assembled substep for `Δv` and adds it to `g.v`, with kinematic points (the root,
/// pinned points) given the velocity that takes them to the scalp at the substep's end
/// (`origin`, `rot`) over `c.dt`.
#[inline(always)]
fn solve_velocities<L: Lane>(
    g: &mut Scratch<L>,
    s: &mut ImplicitScratch<L>,
    c: &StepConstants,
    origin: &V3<L>,
    rot: &M3<L>,
) {
    let inv_dt = splat::<L>(1.0 / c.dt);
    let one = splat::<L>(1.0);
    // Kinematic points: their Δv is known; move it to the right-hand side of their
    // neighbours, then make their rows and columns the identity (lanes where a point is free
    // are untouched: `pinned` is zero there).
    let n = g.x.len();
    s.known.clear();
    for &p in &g.pinned {
        let kinematic = kinematic_velocity(g, p, origin, rot, inv_dt);
        let pinned = one - g.free[p];
        let dv = (kinematic - g.v[p]) * pinned;
        if p >= 2 {
            s.rhs[p - 2] -= s.skip[p - 2].mul_transposed(&dv);
        }
        if p >= 1 {
            s.rhs[p - 1] -= s.next[p - 1].mul_transposed(&dv);
        }
        if p + 1 < n {
            s.rhs[p + 1] -= s.next[p].mul(&dv);
        }
        if p + 2 < n {
            s.rhs[p + 2] -= s.skip[p].mul(&dv);
        }
        // Kept until every neighbour is adjusted: a pinned neighbour's own row is replaced
        // below.
        s.known.push(dv);
    }
    for (&p, dv) in g.pinned.iter().zip(&s.known) {
        let (free, pinned) = (g.free[p], one - g.free[p]);
        s.rhs[p] = s.rhs[p] * free + *dv;
        s.diag[p] = s.diag[p].scaled(free);
        s.diag[p].add_diagonal(pinned);
        if p >= 2 {
            s.skip[p - 2] = s.skip[p - 2].scaled(free);
        }
        if p >= 1 {
            s.next[p - 1] = s.next[p - 1].scaled(free);
        }
        if p + 1 < n {
            s.next[p] = s.next[p].scaled(free);
        }
        if p + 2 < n {
            s.skip[p] = s.skip[p].scaled(free);
        }
    }
    solve_in_place(&mut s.diag, &mut s.next, &mut s.skip, &mut s.rhs);
    for (v, dv) in g.v.iter_mut().zip(&s.rhs) {
        *v += *dv;
    }
}

/// Builds the blocks of `h D + h² K` and the right-hand side `h f − (h D + h² K) v` (module
/// docs) from the forces, tangents, tensions and rest curvatures [`elastic_forces`] left in `g`;
/// `clock` gives the root frame the forces were taken in.
#[inline(always)]
fn assemble<L: Lane>(
    g: &Scratch<L>,
    s: &mut ImplicitScratch<L>,
    c: &StepConstants,
    clock: &SubstepClock<L>,
) {
    let n = g.x.len();
    zeroed(&mut s.diag, n);
    zeroed(&mut s.next, n);
    zeroed(&mut s.skip, n);
    let h = splat::<L>(c.dt);
    let h2 = h * h;
    let (zero, one) = (splat::<L>(0.0), splat::<L>(1.0));
    let h2k = h2 * g.stretch_k;
    // Stretch springs and their damping, per segment j (points j, j + 1; padded index j + 1).
    for j in 0..n - 1 {
        let t = g.tangent[j + 1];
        let alpha = (one - g.rest_length[j] * g.inv_len[j + 1]).max(zero);
        let block = Sym3::iso_outer(h2k * alpha, h2k * (one - alpha) + h * s.damp[j], &t);
        s.diag[j].add(&block);
        s.diag[j + 1].add(&block);
        s.next[j].sub(&Mat3::from_sym(&block));
    }
    if c.bend > 0.0 {
        if g.gauss_newton_bending {
            bending_hessian(g, s, h, clock);
        } else {
            small_angle_bending_hessian(g, s, h);
        }
    }
    // Goal springs and air drag on the diagonal (zero on pinned points).
    let drag = g.drag;
    for i in 0..n {
        s.diag[i].add_diagonal(h2 * g.goal_k[i] + h * drag * s.mass[i]);
    }
    zeroed(&mut s.rhs, n);
    let gravity = V3::splat(&c.gravity);
    for i in 0..n {
        let mut f = g.force[i] + gravity * s.mass[i];
        if g.has_accel {
            f += g.accel[i] * s.mass[i];
        }
        let mut sv = s.diag[i].mul(&g.v[i]);
        if i + 1 < n {
            sv += s.next[i].mul_transposed(&g.v[i + 1]);
        }
        if i >= 1 {
            sv += s.next[i - 1].mul(&g.v[i - 1]);
        }
        if i + 2 < n {
            sv += s.skip[i].mul_transposed(&g.v[i + 2]);
        }
        if i >= 2 {
            sv += s.skip[i - 2].mul(&g.v[i - 2]);
        }
        s.rhs[i] = f * h - sv;
    }
    // The matrix M + h D + h² K: masses on the diagonal.
    for i in 0..n {
        s.diag[i].add_diagonal(s.mass[i]);
    }
}

/// Adds bending's small-angle Hessian about a straight strand (module docs) to the blocks, `h`
/// the substep (s): joint `j` adds `h² k_j e eᵀ ⊗ P` across its mean tangent.
#[inline(always)]
fn small_angle_bending_hessian<L: Lane>(g: &Scratch<L>, s: &mut ImplicitScratch<L>, h: L) {
    let n = g.x.len();
    let h2 = h * h;
    let (zero, one) = (splat::<L>(0.0), splat::<L>(1.0));
    let t0 = g.tangent[1];
    let b = h2 * g.joint_k[0] * s.inv_rest[0] * s.inv_rest[0];
    let block = Sym3::iso_outer(b, -b, &t0);
    s.diag[0].add(&block);
    s.diag[1].add(&block);
    s.next[0].sub(&Mat3::from_sym(&block));
    for j in 1..n - 1 {
        let mean = g.tangent[j] + g.tangent[j + 1];
        let across = Sym3::iso_outer(one, -div_or_zero(one, mean.dot(&mean), 1e-12), &mean);
        let (ia, ib) = (s.inv_rest[j - 1], s.inv_rest[j]);
        let e = [ia, zero - ia - ib, ib];
        let beta = h2 * g.joint_k[j];
        s.diag[j - 1].add(&across.scaled(beta * e[0] * e[0]));
        s.diag[j].add(&across.scaled(beta * e[1] * e[1]));
        s.diag[j + 1].add(&across.scaled(beta * e[2] * e[2]));
        s.next[j - 1].add(&Mat3::from_sym(&across.scaled(beta * e[0] * e[1])));
        s.next[j].add(&Mat3::from_sym(&across.scaled(beta * e[1] * e[2])));
        s.skip[j - 1].add(&Mat3::from_sym(&across.scaled(beta * e[0] * e[2])));
    }
}

/// The Jacobians of a joint's curvature residual `r = κ − K` (`bending_hessian`'s notation):
/// `A` (`−∂r/∂x_{j−1}`) and `B` (`∂r/∂x_{j+1}`), for unit tangents `a`, `b`, their segments'
/// inverse lengths (1/m) and the rest curvature `K` in the transported frame, world (`K = 0`:
/// no frame term). (A function, not a closure: closures are not compiled for the kernel's AVX2.)
#[inline(always)]
fn joint_jacobians<L: Lane>(
    a: &V3<L>,
    b: &V3<L>,
    inv_len_a: L,
    inv_len_b: L,
    rest: &V3<L>,
) -> (Mat3<L>, Mat3<L>) {
    let (one, two) = (splat::<L>(1.0), splat::<L>(2.0));
    let chi = div_or_zero(one, one + a.dot(b), 1e-6);
    let kappa = a.cross(b) * (two * chi);
    let sum = Mat3::outer(&kappa, &(*a + *b));
    let mut bm = Mat3::cross(a).scaled(two);
    bm.sub(&sum);
    // κ(a, b) = −κ(b, a) gives κ's Jacobian in a; the frame turns by a × δa.
    let mut am = Mat3::cross(b).scaled(-two);
    am.sub(&sum);
    let mut am = am.scaled(chi);
    am.add(&Mat3::cross(rest).times(&Mat3::cross(a)));
    (am.scaled(inv_len_a), bm.scaled(chi * inv_len_b))
}

/// Adds bending's Gauss–Newton Hessian `h² k Jᵀ J` (module docs) to the blocks, `h` the
/// substep (s). A joint between tangents `a` and `b` (points `j − 1, j, j + 1`) has the
/// residual `r = κ − K`, `κ = 2 a × b / (1 + a·b)` and `K` its rest curvature in the
/// transported frame, which turns by `a × δa` as `a` does; with `χ = 1/(1 + a·b)`,
/// `P_t = I − t tᵀ` and `ι` a segment's inverse length,
///
/// `∂r/∂x_{j+1} = B = ι_b χ (2 [a]× − κ (a + b)ᵀ)` (that is `∂κ/∂b P_b ι_b`),
/// `∂r/∂x_{j−1} = −A`, `A = ι_a (χ (−2 [b]× − κ (a + b)ᵀ) + [K]× [a]×)`, and
/// `∂r/∂x_j = A − B`; the root joint measures `b` against the root frame's rest direction
/// (kinematic, `K = 0`) and has only `B`.
#[inline(always)]
fn bending_hessian<L: Lane>(
    g: &Scratch<L>,
    s: &mut ImplicitScratch<L>,
    h: L,
    clock: &SubstepClock<L>,
) {
    let n = g.x.len();
    let (zero, one) = (splat::<L>(0.0), splat::<L>(1.0));
    let rot = clock.rot_now;
    let (root_t, up) = (rot.cols[2], rot.cols[0]);
    let r = g.root_rest;
    let root_dir = root_t * r.x + up * r.y + root_t.cross(&up) * r.z;
    let (_, b0) = joint_jacobians(&root_dir, &g.tangent[1], zero, g.inv_len[1], &V3::default());
    let gram = b0.scaled(h * g.joint_k[0].sqrt()).gram();
    s.diag[0].add(&gram);
    s.diag[1].add(&gram);
    s.next[0].sub(&Mat3::from_sym(&gram));
    for j in 1..n - 1 {
        let k = g.joint_k[j];
        // `rest_bend` holds k K.
        let rest = g.rest_bend[j + 1] * div_or_zero(one, k, 1e-30);
        let (am, bm) = joint_jacobians(
            &g.tangent[j],
            &g.tangent[j + 1],
            g.inv_len[j],
            g.inv_len[j + 1],
            &rest,
        );
        let scale = h * k.sqrt();
        let (am, bm) = (am.scaled(scale), bm.scaled(scale));
        let cm = am.minus(&bm);
        s.diag[j - 1].add(&am.gram());
        s.diag[j].add(&cm.gram());
        s.diag[j + 1].add(&bm.gram());
        s.next[j - 1].sub(&cm.transposed_times(&am));
        s.next[j].add(&bm.transposed_times(&cm));
        s.skip[j - 1].sub(&bm.transposed_times(&am));
    }
}

#[cfg(test)]
mod tests {
    use super::super::lanes::Baseline;
    use super::*;

    /// `joint_jacobians` against central differences of the residual `r = κ(a, b) − K(a)` of a
    /// joint bent by 50°, with `K` carried by parallel transport as `a` turns: moving the far
    /// point changes `r` by `B δ`, the near point by `−A δ`.
    #[test]
    fn joint_jacobians_match_central_differences() {
        use nalgebra::Vector3;
        let lanes = |v: Vector3<f64>| V3::<Baseline>::splat(&v.cast::<f32>());
        let (p0, p1) = (Vector3::zeros(), Vector3::new(0.012, 0.002, -0.003));
        let turn = nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), 50f64.to_radians());
        let p2 = p1 + turn * (p1 - p0) * 0.8 + Vector3::new(0.0, 0.0, 0.002);
        let a0 = (p1 - p0).normalize();
        // The frame at a: `u` across it, and the rest curvature (0.4, −0.7) in (u, a × u).
        let u0 = a0.cross(&Vector3::z()).normalize();
        let rest_in = |a: Vector3<f64>| {
            // Parallel transport (`crate::frames::transport`) of u0 from a0 to a, in f64.
            let u = u0 - (a0 + a) * (u0.dot(&a) / (1.0 + a0.dot(&a)));
            u * 0.4 + a.cross(&u) * -0.7
        };
        let residual = |p0: Vector3<f64>, p1: Vector3<f64>, p2: Vector3<f64>| {
            let (a, b) = ((p1 - p0).normalize(), (p2 - p1).normalize());
            a.cross(&b) * (2.0 / (1.0 + a.dot(&b))) - rest_in(a)
        };
        let (a, b) = (a0, (p2 - p1).normalize());
        let inv = |d: Vector3<f64>| splat::<Baseline>(1.0 / d.norm() as f32);
        let (am, bm) = joint_jacobians(
            &lanes(a),
            &lanes(b),
            inv(p1 - p0),
            inv(p2 - p1),
            &lanes(rest_in(a)),
        );
        let eps = 1e-6;
        for axis in 0..3 {
            let d = Vector3::ith(axis, eps);
            let far = (residual(p0, p1, p2 + d) - residual(p0, p1, p2 - d)) / (2.0 * eps);
            let near = (residual(p0 + d, p1, p2) - residual(p0 - d, p1, p2)) / (2.0 * eps);
            let e = lanes(Vector3::ith(axis, 1.0));
            let (b_col, a_col) = (bm.mul(&e).lane(0).cast::<f64>(), am.mul(&e).lane(0).cast());
            assert!(
                (b_col - far).norm() < 1e-3 * far.norm().max(1.0),
                "{b_col} {far}"
            );
            assert!(
                (a_col + near).norm() < 1e-3 * near.norm().max(1.0),
                "{a_col} {near}"
            );
        }
    }
}
