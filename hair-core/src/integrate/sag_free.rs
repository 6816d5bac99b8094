//! Sag-free initialisation of the mass-spring model: rest directions that make the groomed shape
//! a static equilibrium under gravity, so hair does not sag or collapse when a simulation starts.
//!
//! # The problem
//!
//! A groom gives the shape hair should have *under gravity*. The solver's springs are at rest in
//! that shape, so at frame 1 the only force is gravity and every strand sags until its springs
//! carry its weight: by centimetres for the default bending stiffness. Hsu, Wang, Wu and Yuksel
//! ("Sag-Free Initialization for Strand-Based Hybrid Hair Simulation", ACM TOG 42(4), SIGGRAPH
//! 2023) instead solve for rest data whose elastic forces cancel gravity in the groomed shape.
//! For hairsys's mass-spring chain that solve is explicit and exact, derived here for the
//! discrete forces the kernel applies (not a continuum beam).
//!
//! # The forces at the groomed shape
//!
//! At `v = 0` damping and drag vanish, and a free point `i` feels (kernel, `super::kernel`):
//! gravity `m_i g`, goal springs, stretch `T_i t_i − T_{i−1} t_{i−1}` with
//! `T_j = k_s (len_j − l_j)`, and bending. Bending is the curvature energy of
//! [`super::curvature`]: joint `j` (at point `j`, between `a = t_{j−1}` — the root normal for
//! `j = 0` — and `b = t_j`) has the curvature binormal `κ_j = 2 a × b/(1 + a·b)` and the moment
//! `m_j = k_j (κ_j − K_j)`, `K_j = D_j (0, κ⁰_u, κ⁰_w)` its rest curvature in the previous
//! segment's transported frame `D_j = [t_{j−1} u_{j−1} w_{j−1}]`. With `χ_j = 1/(1 + a·b)` and
//! `μ_j = χ_j m_j·κ_j` it exerts
//!
//! - `−A_j` on point `j + 1` and `+A_j` on point `j`, `A_j = (2χ_j m_j × a − μ_j (a + b))/len_j`;
//! - `−Γ_j` on point `j` and `+Γ_j` on point `j − 1`, `Γ_j = (2χ_j b × m_j − μ_j (a + b))/len_{j−1}`
//!   (none for `j = 0`: the root frame is kinematic);
//! - through the twist of parallel transport: `s_j = a·(m_j × κ_j)`, `S_k = Σ_{j>k} s_j`,
//!   `β_k = κ_k/2`, and `τ_k = (β_k S_k + β_{k+1} S_{k+1})/len_k` acts as `+τ_k` on point `k + 1`
//!   and `−τ_k` on point `k`.
//!
//! The bending force on point `i` is therefore
//! `B_i = −A_{i−1} + A_i − Γ_i + Γ_{i+1} + τ_{i−1} − τ_i`.
//!
//! # The solve: one sweep from tip to root
//!
//! At the groomed positions every frame, tangent, length and `κ_j` is fixed, so all these forces
//! are **linear in the moments** `m_j` (`m_j ⟂ a`, two unknowns per joint), and the stretch forces
//! linear in the tensions `T_j`. Equilibrium asks `B_i + T_i t_i − T_{i−1} t_{i−1} = −P_i` with
//! `P_i = m_i g + goal_i` for every free point. In it only `m_{i−1}` (through `A_{i−1}`) and
//! `T_{i−1}` are unknown once the joints and segments beyond are: `A_i, Γ_i, Γ_{i+1}` belong to
//! later joints, and `τ_{i−1}` needs `S_{i−1} = s_i + S_i`, not `s_{i−1}`. Writing
//! `m_{i−1} = μ_u u_{i−2} + μ_w w_{i−2}` in the joint's frame, point `i` gives the 3 × 3 system
//!
//! `A_{i−1}(μ_u, μ_w) + T_{i−1} t_{i−1} = P_i + A_i − Γ_i + Γ_{i+1} + τ_{i−1} − τ_i + T_i t_i`
//!
//! (the sideways part is carried by the joint's moment, the along-segment part by the tension);
//! at the root joint, whose energy is `2 k_0 tan²(φ/2)` in the angle `φ` between the first
//! segment and its rest direction `d_0` (see [`super::curvature`]), the sideways force fixes the
//! plane and the size `dE/dφ = 2 k_0 τ (1 + τ²)`, `τ = tan(φ/2)`, a cubic solved by Newton
//! (`root_rest_direction`),
//! so a sweep from the tip (point `n − 1`) to the root gives every moment and tension exactly —
//! "each segment carries what lies beyond it", with the couples and twists of this discrete
//! model. Away from the root the system is linear, so no Newton iteration is needed there: the
//! rest curvature enters the energy only through `m_j`. It is singular only for a segment folded straight back onto the
//! previous one (`A` vanishes there), which is reported unbalanced. A kinematic point carries its
//! own load: the joint before it keeps its groomed rest (`m = 0`) and the segment before it its
//! rest length.
//!
//! The new rest data follow: the rest curvature `(κ⁰_u, κ⁰_w) = ((κ − m/k)·u, (κ − m/k)·w)`,
//! stored as the unit [`RestDirection`] that describes it
//! ([`super::curvature::direction_of_curvature`]), and the rest length `l_j = len_j − T_j/k_s`.
//!
//! **Rest lengths change** (unlike for a chord spring, which also acts along its segment and can
//! carry the along-segment load in its rest vector): the curvature energy
//! exerts no force along a segment, so only a pre-stretch of the stretch spring can hold the
//! weight below it. The groomed segment is then longer than its rest length by
//! `T_j/(k_s l_j)` (for 25 cm of 10⁻³ kg/m hair on 200 N/m springs of 1.6 cm, under 0.1 %), which
//! the strain limit allows as long as it is below `max_strain`; the inextensibility projection
//! (seed 002, `MassSpringSolver::with_inextensibility`) would pull it back to `l_j` and does not go
//! with sag-free initialisation. Each rest length is rounded to f32 before the sweep moves on, and
//! the next point uses the tension of the rounded length, so the rounding leaves a residual only
//! along that segment (`k_s` times half an f32 ulp of `l_j`) instead of accumulating.
//!
//! The solve is done in f64 from the f32 state and stored in f32, so the residual force at the
//! groomed shape is f32 round-off ([`residual_forces`] evaluates it forwards, independently of the
//! sweep).
//!
//! # Limits
//!
//! - `bend_stiffness = 0`: nothing can hold a sideways load; every strand with a free point is
//!   reported unbalanced and left as groomed. Likewise `stretch_stiffness = 0` cannot hold the
//!   along-segment load.
//! - A strand whose correction would turn some rest direction by more than
//!   [`SagFreeLimits::max_turn`] (a bending far too weak for its weight: the rest shape would have
//!   to fold back on itself), or shorten a rest length by half or more, is left as groomed and
//!   listed in the report, rather than given an absurd rest shape.
//! - Equilibrium is not stability: a long strand standing up against gravity balanced by weak
//!   springs is an equilibrium that may buckle under the first disturbance.
//! - Force fields, hair–hair forces and air drag are not part of the balance; fields and
//!   hair–hair forces are disturbances. Contacts are, where the caller says which points rest on
//!   a collider ([`make_sag_free_supported`]): at such a point the collider takes the outward
//!   part of the force the spring before it would have to supply (a unilateral push, solved in
//!   the same sweep), so hair lying on a head is carried by the head, as real hair is.
//! - Goal springs are included (their force at the groomed shape is zero when positions are the
//!   rest shape placed by the root frames).
//! - Only the mass-spring kernel is covered (the strip model's edge strands run the same kernel
//!   on a [`StrandSet`], so it applies there too); the rod model has its own energy.

use nalgebra::{Matrix3, Vector3};

use crate::error::{HairError, Result};
use crate::frames::{transport, RestDirection};
use crate::mesh::RootFrame;
use crate::strands::StrandSet;

use super::curvature::{
    direction_of_curvature, joint_stiffness, rest_curvature, rigidity, root_direction,
};
use super::params::HairParams;

/// When a strand counts as not balanceable.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SagFreeLimits {
    /// Largest angle between a corrected rest direction and the groomed one, rad. A strand
    /// needing more is left as groomed and reported.
    pub max_turn: f32,
}

impl Default for SagFreeLimits {
    /// 60°: a correction beyond that means the bending springs are far too weak to hold the
    /// strand's weight; its rest shape would be a different hairstyle.
    fn default() -> Self {
        Self {
            max_turn: 60f32.to_radians(),
        }
    }
}

/// What [`make_sag_free`] did.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SagFreeReport {
    /// Strands whose rest directions were corrected.
    pub balanced: usize,
    /// Strands left as groomed because they could not be balanced (see [`SagFreeLimits`]).
    pub unbalanced: Vec<usize>,
    /// Largest turn of a corrected rest direction from the groomed one, rad (balanced strands).
    pub max_turn: f32,
    /// Largest relative change of a rest length, `|l_new/l_old − 1|` (the along-segment load,
    /// now carried by the stretch springs as a pre-stretch).
    pub max_length_change: f32,
    /// Largest residual force at a free point after the correction, N (f32 round-off).
    pub max_residual: f32,
    /// Largest weight of a free point, N, for scale.
    pub max_weight: f32,
}

/// Per-strand geometry at the current positions, f64.
struct Geometry {
    /// Unit tangents; index `j + 1` holds segment `j`, index 0 the root normal.
    t: Vec<Vector3<f64>>,
    /// Segment lengths, m.
    len: Vec<f64>,
    /// Frame of each joint `j`: columns (t, u, w) of segment `j − 1` (root for `j = 0`).
    frame: Vec<Matrix3<f64>>,
    /// `χ_j = 1/(1 + a·b)` per joint (0 for a segment folded straight back).
    chi: Vec<f64>,
    /// `β_j = χ_j a × b` per joint (half the transport's curvature binormal), with a zero
    /// appended.
    beta: Vec<Vector3<f64>>,
    /// The root joint's reference: the first segment's rest direction in the world (see
    /// [`super::curvature`]), with its `χ` and `β` against the first tangent.
    root_dir: Vector3<f64>,
    root_chi: f64,
    root_beta: Vector3<f64>,
}

fn geometry(x: &[Vector3<f32>], root: &RootFrame) -> Geometry {
    let rot: Matrix3<f32> = root.rotation.to_rotation_matrix().into_inner();
    let n = x.len();
    let mut t = Vec::with_capacity(n);
    let mut len = Vec::with_capacity(n - 1);
    let mut frame = Vec::with_capacity(n - 1);
    let mut chi = Vec::with_capacity(n - 1);
    let mut beta = Vec::with_capacity(n);
    // The frames are transported in f32 with the kernel's own formula, so they are the kernel's.
    let mut tp: Vector3<f32> = rot.column(2).into();
    let mut up: Vector3<f32> = rot.column(0).into();
    t.push(tp.cast::<f64>());
    for j in 0..n - 1 {
        frame.push(Matrix3::from_columns(&[tp, up, tp.cross(&up)]).cast::<f64>());
        let d = x[j + 1] - x[j];
        let l = d.cast::<f64>().norm();
        let tj = d / d.norm();
        len.push(l);
        t.push(d.cast::<f64>() / l);
        up = transport(&up, &tp, &tj);
        tp = tj;
    }
    for j in 0..n - 1 {
        let (a, b) = (t[j], t[j + 1]);
        let c = 1.0 + a.dot(&b);
        let x = if c > 1e-6 { 1.0 / c } else { 0.0 };
        chi.push(x);
        beta.push(a.cross(&b) * x);
    }
    beta.push(Vector3::zeros());
    let mut g = Geometry {
        root_dir: t[0],
        root_chi: chi[0],
        root_beta: beta[0],
        t,
        len,
        frame,
        chi,
        beta,
    };
    g.set_root_dir(g.t[0]);
    g
}

impl Geometry {
    /// Sets the root joint's reference direction (unit, world).
    fn set_root_dir(&mut self, d: Vector3<f64>) {
        let c = 1.0 + d.dot(&self.t[1]);
        self.root_chi = if c > 1e-6 { 1.0 / c } else { 0.0 };
        self.root_beta = d.cross(&self.t[1]) * self.root_chi;
        self.root_dir = d;
    }

    /// The bending energy's `a`, `χ` and `β` of joint `j`: the previous tangent's, or for the
    /// root joint the rest direction's.
    fn energy_terms(&self, j: usize) -> (Vector3<f64>, f64, Vector3<f64>) {
        if j == 0 {
            (self.root_dir, self.root_chi, self.root_beta)
        } else {
            (self.t[j], self.chi[j], self.beta[j])
        }
    }

    /// `A_j`: the force of joint `j`'s moment `m` on point `j` (`−A_j` on point `j + 1`), N.
    fn push_far(&self, j: usize, m: &Vector3<f64>) -> Vector3<f64> {
        let ((a, chi, beta), b) = (self.energy_terms(j), self.t[j + 1]);
        let mu = 2.0 * chi * m.dot(&beta);
        (m.cross(&a) * (2.0 * chi) - (a + b) * mu) / self.len[j]
    }

    /// `Γ_j`: the force of joint `j`'s moment `m` on point `j − 1` (`−Γ_j` on point `j`), N;
    /// zero for the root joint.
    fn push_near(&self, j: usize, m: &Vector3<f64>) -> Vector3<f64> {
        if j == 0 {
            return Vector3::zeros();
        }
        let (a, b, chi) = (self.t[j], self.t[j + 1], self.chi[j]);
        let mu = 2.0 * chi * m.dot(&self.beta[j]);
        (b.cross(m) * (2.0 * chi) - (a + b) * mu) / self.len[j - 1]
    }

    /// `s_j = a·(m × κ_j)`: the twisting torque of joint `j`'s moment, N·m.
    fn twist(&self, j: usize, m: &Vector3<f64>) -> f64 {
        2.0 * self.t[j].dot(&m.cross(&self.beta[j]))
    }

    /// `τ_k` from the twist sums `S_k`, `S_{k+1}`: on point `k + 1` (`−τ_k` on point `k`), N.
    fn transport_twist(&self, k: usize, s_k: f64, s_next: f64) -> Vector3<f64> {
        (self.beta[k] * s_k + self.beta[k + 1] * s_next) / self.len[k]
    }

    /// Curvature binormal `κ_j` (for the root joint: of the turn from the rest direction).
    fn kappa(&self, j: usize) -> Vector3<f64> {
        self.energy_terms(j).2 * 2.0
    }
}

/// Bending force on every point from the joint moments `m` (one per joint), with the twist
/// terms of the kernel's energy gradient.
fn bending_forces(g: &Geometry, m: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
    let joints = m.len();
    // S[k] = Σ_{j>k} s_j, with S[joints − 1] = S[joints] = 0.
    let mut suffix = vec![0.0; joints + 1];
    for k in (0..joints.saturating_sub(1)).rev() {
        suffix[k] = suffix[k + 1] + g.twist(k + 1, &m[k + 1]);
    }
    let mut out = vec![Vector3::zeros(); joints + 1];
    for j in 0..joints {
        let far = g.push_far(j, &m[j]);
        out[j + 1] -= far;
        out[j] += far;
        if j > 0 {
            let near = g.push_near(j, &m[j]);
            out[j] -= near;
            out[j - 1] += near;
        }
        let tau = g.transport_twist(j, suffix[j], suffix[j + 1]);
        out[j + 1] += tau;
        out[j] -= tau;
    }
    out
}

/// Force on every point of strand `s` except bending and stretch, at `v = 0`: gravity on free
/// points and goal springs, N.
fn load(strands: &StrandSet, s: usize, params: &HairParams, root: &RootFrame) -> Vec<Vector3<f64>> {
    let p = strands.points(s);
    let x = &strands.positions[p.clone()];
    let inv_mass = &strands.inverse_masses()[p.clone()];
    let rest = &strands.rest_local()[p.clone()];
    let gw = &strands.goal_weights()[p];
    let g: Vector3<f64> = params.gravity().cast();
    (0..x.len())
        .map(|i| {
            if inv_mass[i] > 0.0 {
                let goal = (root.to_world(&rest[i]) - x[i]).cast::<f64>()
                    * (params.goal_stiffness * gw[i]) as f64;
                g / inv_mass[i] as f64 + goal
            } else {
                Vector3::zeros()
            }
        })
        .collect()
}

/// Joint moments `m_j = k_j (κ_j − K_j)` of the stored rest data, N·m (the root joint's against
/// zero; set its reference direction first).
fn moments(g: &Geometry, rest: &[RestDirection], l0: &[f32], kb: f32) -> Vec<Vector3<f64>> {
    let ei = rigidity(kb, l0);
    (0..rest.len())
        .map(|j| {
            if j == 0 {
                return g.kappa(0) * joint_stiffness(ei, l0, 0);
            }
            let (k_u, k_w) = rest_curvature(&rest[j]);
            let rest = g.frame[j] * Vector3::new(0.0, k_u as f64, k_w as f64);
            (g.kappa(j) - rest) * joint_stiffness(ei, l0, j)
        })
        .collect()
}

/// Residual force (N) at every point of strand `s` in its current positions at `v = 0`: the sum
/// of gravity, goal, stretch and bending forces evaluated forwards from the stored rest data, as
/// the kernel does (but in f64). Kinematic points report zero. Zero everywhere means the strand
/// is at rest under gravity.
pub fn residual_forces(
    strands: &StrandSet,
    s: usize,
    params: &HairParams,
    root: &RootFrame,
) -> Vec<Vector3<f64>> {
    let x = &strands.positions[strands.points(s)];
    let seg = strands.segments(s);
    let l0 = &strands.rest_lengths()[seg.clone()];
    let rest = &strands.bend_rest()[seg];
    let mut g = geometry(x, root);
    let d = root_direction(&rest[0]).cast::<f64>();
    g.set_root_dir(g.frame[0] * d);
    let mut force = load(strands, s, params, root);
    if params.bend_stiffness > 0.0 {
        let bend = bending_forces(&g, &moments(&g, rest, l0, params.bend_stiffness));
        for (f, b) in force.iter_mut().zip(&bend) {
            *f += b;
        }
    }
    let ks = params.stretch_stiffness as f64;
    for j in 0..x.len() - 1 {
        let tension = g.t[j + 1] * (ks * (g.len[j] - l0[j] as f64));
        force[j] += tension;
        force[j + 1] -= tension;
    }
    let inv_mass = &strands.inverse_masses()[strands.points(s)];
    force
        .iter()
        .zip(inv_mass)
        .map(|(f, &w)| if w > 0.0 { *f } else { Vector3::zeros() })
        .collect()
}

/// What balances a strand: a moment per joint (N·m) and a rest length per segment (m, f32 as
/// stored).
struct Balance {
    moment: Vec<Vector3<f64>>,
    rest_length: Vec<f32>,
    /// The root joint's rest direction, world (unit).
    root_dir: Vector3<f64>,
}

/// Joint moments and rest lengths that balance `load` at every free point exactly, solved from
/// the tip to the root (see the module docs); the joint and segment before a kinematic point
/// keep their rest (`m = 0`, rest length `l0`). `None` if some point cannot be balanced: a
/// segment folded straight back, or stretch springs of zero stiffness under load.
fn balance(
    g: &Geometry,
    load: &[Vector3<f64>],
    free: &[bool],
    l0: &[f32],
    ks: f64,
    kb: f32,
    support: &[Vector3<f64>],
) -> Option<Balance> {
    let n = load.len();
    let joints = n - 1;
    let mut moment = vec![Vector3::zeros(); joints];
    let mut rest_length = l0.to_vec();
    let mut tension = vec![0.0f64; joints];
    // suffix[k] = S_k = Σ_{j>k} s_j, filled as the joints beyond k are solved.
    let mut suffix = vec![0.0f64; n];
    let mut root_dir = g.t[1];
    for i in (1..n).rev() {
        let j = i - 1; // the joint and segment solved at point i
        if free[i] {
            let mut rhs = load[i];
            if i < joints {
                rhs += g.push_far(i, &moment[i]) - g.push_near(i, &moment[i])
                    + g.t[i + 1] * tension[i]
                    - g.transport_twist(i, suffix[i], suffix[i + 1]);
            }
            if i + 1 < joints {
                rhs += g.push_near(i + 1, &moment[i + 1]);
            }
            rhs += g.transport_twist(j, suffix[j], suffix[i]);
            if let Some(n) = support.get(i).filter(|n| n.norm_squared() > 0.0) {
                // A collider under the point pushes (never pulls): it takes the part of the
                // load that presses the point into it, and the joint carries the rest.
                let pressed = rhs.dot(n);
                if pressed < 0.0 {
                    rhs -= n * pressed;
                }
            }
            if j == 0 {
                // The root joint: its force is nonlinear in its rest direction, solved below.
                let t = rhs.dot(&g.t[1]);
                rest_length[0] = if t != 0.0 {
                    if ks <= 0.0 {
                        return None;
                    }
                    (g.len[0] - t / ks) as f32
                } else {
                    g.len[0] as f32
                };
                let sideways = (rhs - g.t[1] * t) * g.len[0];
                let k = joint_stiffness(rigidity(kb, &rest_length), &rest_length, 0);
                root_dir = root_rest_direction(g.t[1], sideways, k)?;
                continue;
            }
            // A_j(μ_u u + μ_w w) + T t_j = rhs.
            let (u, w): (Vector3<f64>, Vector3<f64>) =
                (g.frame[j].column(1).into(), g.frame[j].column(2).into());
            let system = Matrix3::from_columns(&[g.push_far(j, &u), g.push_far(j, &w), g.t[i]]);
            let solution = system.lu().solve(&rhs)?;
            if !solution.iter().all(|c| c.is_finite()) {
                return None;
            }
            moment[j] = u * solution.x + w * solution.y;
            let t = solution.z;
            if t != 0.0 {
                if ks <= 0.0 {
                    return None;
                }
                // Stored in f32; the next point works with the tension of the stored length.
                rest_length[j] = (g.len[j] - t / ks) as f32;
            } else {
                rest_length[j] = g.len[j] as f32;
            }
        }
        tension[j] = ks * (g.len[j] - rest_length[j] as f64);
        if j > 0 {
            suffix[j - 1] = suffix[j] + g.twist(j, &moment[j]);
        }
    }
    Some(Balance {
        moment,
        rest_length,
        root_dir,
    })
}

/// The root joint's rest direction `d` (unit, world) whose energy `2 k tan²(φ/2)`, `φ = ∠(d, b)`,
/// has the gradient `g` (⟂ `b`, N·m) with respect to the first tangent `b`: `g` points away from
/// `d` with magnitude `dE/dφ = 2 k τ (1 + τ²)`, `τ = tan(φ/2)`. Newton on the increasing, convex
/// cubic `τ³ + τ − |g|/2k`, from the right of its root (monotone convergence). `None` without
/// bending stiffness under a load.
fn root_rest_direction(b: Vector3<f64>, g: Vector3<f64>, k: f64) -> Option<Vector3<f64>> {
    let size = g.norm();
    if size == 0.0 {
        return Some(b);
    }
    if k <= 0.0 {
        return None;
    }
    let q = size / (2.0 * k);
    let mut tau = q.min(q.cbrt());
    for _ in 0..60 {
        let step = (tau * tau * tau + tau - q) / (3.0 * tau * tau + 1.0);
        tau -= step;
        if step.abs() <= 1e-16 * tau {
            break;
        }
    }
    let phi = 2.0 * tau.atan();
    Some(b * phi.cos() - g * (phi.sin() / size))
}

/// Replaces the rest curvatures and rest lengths of every strand so that its current positions
/// (the groom, at rest) are a static equilibrium under gravity with `params`, the roots at
/// `roots` (one frame per strand, e.g. [`StrandSet::root_frames`]). Strands that cannot be
/// balanced within `limits` keep their groomed rest data and are listed in the report.
///
/// Call it after [`StrandSet::reset_to_rest`] (or with any positions that should hold still) and
/// before the first step. Cost: one pass over the points (a few µs per strand). Nothing rests on
/// a collider here; see [`make_sag_free_supported`].
pub fn make_sag_free(
    strands: &mut StrandSet,
    params: &HairParams,
    roots: &[RootFrame],
    limits: SagFreeLimits,
) -> Result<SagFreeReport> {
    make_sag_free_supported(strands, params, roots, &[], limits)
}

/// [`make_sag_free`] for a groom that rests on colliders: `supports` holds, per point of
/// `strands` (or is empty for none), the outward unit normal of the collider surface the point
/// rests on, or zero (see [`crate::quality::resting_normals`]). A resting point's collider takes
/// the outward part of its load — a unilateral contact pushes, never pulls — so the bending
/// springs carry only what the head does not: hair lying on a scalp keeps a nearly unbent rest
/// shape instead of one pre-curved against its whole weight, which would curl up wherever the
/// hair later leaves the scalp. At frame 1 the contact response supplies that push once gravity
/// has pressed the point into the contact zone (by a fraction of the contact tolerance).
pub fn make_sag_free_supported(
    strands: &mut StrandSet,
    params: &HairParams,
    roots: &[RootFrame],
    supports: &[Vector3<f32>],
    limits: SagFreeLimits,
) -> Result<SagFreeReport> {
    params.validate()?;
    if roots.len() != strands.len() {
        return Err(HairError::Parameter {
            name: "roots".into(),
            value: roots.len().to_string(),
            fix: format!("give one root frame per strand ({})", strands.len()),
        });
    }
    if !supports.is_empty() && supports.len() != strands.positions.len() {
        return Err(HairError::Parameter {
            name: "supports".into(),
            value: supports.len().to_string(),
            fix: format!(
                "give one normal per point ({}) or none",
                strands.positions.len()
            ),
        });
    }
    let kb = params.bend_stiffness;
    let ks = params.stretch_stiffness as f64;
    let mut report = SagFreeReport::default();
    for (s, root) in roots.iter().enumerate() {
        let p = strands.points(s);
        let x = &strands.positions[p.clone()];
        let free: Vec<bool> = strands.inverse_masses()[p.clone()]
            .iter()
            .map(|&w| w > 0.0)
            .collect();
        let mut g = geometry(x, root);
        let load = load(strands, s, params, root);
        for (w, &m) in free.iter().zip(&strands.masses()[p.clone()]) {
            if *w {
                report.max_weight = report.max_weight.max(m * params.gravity().norm());
            }
        }
        let support: Vec<Vector3<f64>> = if supports.is_empty() {
            Vec::new()
        } else {
            supports[p.clone()].iter().map(|n| n.cast()).collect()
        };
        let seg = strands.segments(s);
        let l0 = &strands.rest_lengths()[seg.clone()];
        let Some(balance) = balance(&g, &load, &free, l0, ks, kb, &support) else {
            report.unbalanced.push(s);
            continue;
        };
        let needs_bending = balance.moment.iter().any(|m| *m != Vector3::zeros());
        if needs_bending && kb == 0.0 {
            report.unbalanced.push(s);
            continue;
        }
        // Joint stiffnesses of the new rest lengths, as the kernel will see them.
        let ei = rigidity(kb, &balance.rest_length);
        let old = &strands.bend_rest()[seg.clone()];
        let mut new = Vec::with_capacity(old.len());
        let (mut turn, mut stretch) = (0.0f64, 0.0f64);
        g.set_root_dir(balance.root_dir);
        for j in 0..old.len() {
            let k = joint_stiffness(ei, &balance.rest_length, j);
            let rest = g.kappa(j) - balance.moment[j] / k;
            let (u, w): (Vector3<f64>, Vector3<f64>) =
                (g.frame[j].column(1).into(), g.frame[j].column(2).into());
            let r = if j == 0 {
                let d = g.frame[0].transpose() * balance.root_dir;
                RestDirection {
                    t: d.x as f32,
                    u: d.y as f32,
                    w: d.z as f32,
                }
            } else {
                direction_of_curvature(rest.dot(&u), rest.dot(&w))
            };
            let r_new = Vector3::new(r.t, r.u, r.w).cast::<f64>();
            let r_old = Vector3::new(old[j].t, old[j].u, old[j].w).cast::<f64>();
            turn = turn.max(r_new.angle(&r_old));
            stretch = stretch.max((balance.rest_length[j] as f64 / l0[j] as f64 - 1.0).abs());
            new.push(r);
        }
        let finite = new
            .iter()
            .all(|r| r.t.is_finite() && r.u.is_finite() && r.w.is_finite());
        if !finite || turn > limits.max_turn as f64 || stretch >= 0.5 {
            report.unbalanced.push(s);
            continue;
        }
        strands.bend_rest_mut()[seg.clone()].copy_from_slice(&new);
        strands.rest_lengths_mut()[seg].copy_from_slice(&balance.rest_length);
        report.balanced += 1;
        report.max_turn = report.max_turn.max(turn as f32);
        report.max_length_change = report.max_length_change.max(stretch as f32);
        let residual = residual_forces(strands, s, params, root)
            .iter()
            .enumerate()
            .map(|(i, r)| match support.get(i) {
                // What presses a resting point into its collider is the contact's to carry.
                Some(n) if r.dot(n) < 0.0 => r - n * r.dot(n),
                _ => *r,
            })
            .fold(0.0f64, |a, r| a.max(r.norm()));
        report.max_residual = report.max_residual.max(residual as f32);
    }
    Ok(report)
}
