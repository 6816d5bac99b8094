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
//! `T_j = k_s (len_j − l_j)`, and bending. Bending spring `j` pulls point `j + 1` towards
//! `x_j + l_j D_j r_j`, where `D_j = [t_{j−1} u_{j−1} w_{j−1}]` is the previous segment's
//! transported frame (the root frame for `j = 0`) and `r_j` the [`RestDirection`]. Its force on
//! point `j + 1` is `f_j = k_b (x_j + l_j D_j r_j − x_{j+1})`, `−f_j` on point `j`, plus the exact
//! energy-gradient terms the kernel adds because `D_j` turns with the earlier tangents:
//!
//! - the opposite couple on segment `j − 1`: with `C_j = (x_{j+1} − x_j) × f_j` (the kernel's
//!   `l_j d_j × f_j`, since `l_j d_j = x_{j+1} − x_j + f_j/k_b` and `f_j × f_j = 0`),
//!   `R_j = C_j × t_{j−1} / len_{j−1}` acts as `+R_j` on point `j − 1` and `−R_j` on point `j`
//!   (none for `j = 0`: the root frame is kinematic);
//! - the twist of parallel transport: `s_j = t_{j−1}·C_j`, `S_m = Σ_{j>m} s_j`,
//!   `β_m = t_{m−1} × t_m / (1 + t_{m−1}·t_m)`, and `τ_m = (β_m S_m + β_{m+1} S_{m+1}) / len_m`
//!   acts as `+τ_m` on point `m + 1` and `−τ_m` on point `m`.
//!
//! The bending force on point `i` is therefore
//! `B_i = f_{i−1} − f_i + τ_{i−1} − τ_i − R_i + R_{i+1}`.
//!
//! # The solve: one sweep from tip to root
//!
//! At the groomed positions every frame `D_j`, tangent and length is fixed, so the forces are
//! *linear* in the unknown spring forces `f_j`, and equilibrium asks `B_i = −P_i` with
//! `P_i = m_i g + goal_i + stretch_i` for every free point. In `B_i` only `f_{i−1}` is unknown
//! once `f_i, f_{i+1}, …` are: `R_i, R_{i+1}` and `τ_i` depend on later springs only, and so does
//! `τ_{i−1}` (`S_{i−1} = s_i + S_i`). So a sweep from the tip (`f_{n−2} = −P_{n−1}`) to the root
//! gives every `f_j` exactly — "each segment carries what lies beyond it", with the couples and
//! twists of this particular discrete model. A kinematic point carries its own load: the spring
//! before it keeps its groomed rest (`f = 0`). The new rest direction is then
//! `r_j = D_jᵀ (x_{j+1} − x_j + f_j / k_b) / l_j`.
//!
//! Rest **lengths are left unchanged**: the along-segment share of the weight goes into the
//! bending spring's rest vector (which then has a length `≠ 1`; the kernel does not require unit
//! rest directions), not into a pre-stretch `l_j = len_j − T_j/k_s`. Both balance the same
//! forces (an along-segment `f_j` has no couple, `C_j = 0`, and acts exactly as a tension), but
//! keeping the lengths means the strain limit and the inextensibility projection, which hold
//! segments to their rest length, find nothing to correct in the groomed shape.
//!
//! The solve is done in f64 from the f32 state and stored in f32, so the residual force at the
//! groomed shape is f32 round-off ([`residual_forces`] evaluates it forwards, independently of the
//! sweep).
//!
//! # Limits
//!
//! - `bend_stiffness = 0`: nothing can hold a sideways load; every strand with a free point is
//!   reported unbalanced and left as groomed.
//! - A strand whose correction would turn some rest direction by more than
//!   [`SagFreeLimits::max_turn`] (a bending far too weak for its weight: the rest shape would have
//!   to fold back on itself) is left as groomed and listed in the report, rather than given an
//!   absurd rest shape.
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
    /// Largest change of a rest direction's length, `| |r| − 1 |` (the along-segment load).
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
    /// Frame of each bending spring `j`: columns (t, u, w) of segment `j − 1` (root for `j = 0`).
    frame: Vec<Matrix3<f64>>,
    /// `β_j` per segment (index `j`), with a zero appended for `j = n − 1`.
    beta: Vec<Vector3<f64>>,
}

fn geometry(x: &[Vector3<f32>], root: &RootFrame) -> Geometry {
    let rot: Matrix3<f32> = root.rotation.to_rotation_matrix().into_inner();
    let n = x.len();
    let mut t = Vec::with_capacity(n);
    let mut len = Vec::with_capacity(n - 1);
    let mut frame = Vec::with_capacity(n - 1);
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
        beta.push(if c > 1e-6 {
            a.cross(&b) / c
        } else {
            Vector3::zeros()
        });
    }
    beta.push(Vector3::zeros());
    Geometry {
        t,
        len,
        frame,
        beta,
    }
}

/// Bending force on every point from spring forces `f` (one per segment), with the couple and
/// twist terms of the kernel's energy gradient.
fn bending_forces(g: &Geometry, f: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
    let m = f.len();
    let couple = |j: usize| g.t[j + 1].cross(&f[j]) * g.len[j];
    let react = |j: usize| {
        if j == 0 || j >= m {
            Vector3::zeros()
        } else {
            couple(j).cross(&g.t[j]) / g.len[j - 1]
        }
    };
    // S[j] = Σ_{k>j} s_k, with S[m] = 0.
    let mut suffix = vec![0.0; m + 1];
    for j in (0..m).rev() {
        let s_next = if j + 1 < m {
            g.t[j + 1].dot(&couple(j + 1))
        } else {
            0.0
        };
        suffix[j] = suffix[j + 1] + s_next;
    }
    let tau = |j: usize| (g.beta[j] * suffix[j] + g.beta[j + 1] * suffix[j + 1]) / g.len[j];
    let mut out = vec![Vector3::zeros(); m + 1];
    for j in 0..m {
        let along = f[j] + tau(j);
        out[j + 1] += along;
        out[j] -= along + react(j);
        if j > 0 {
            out[j - 1] += react(j);
        }
    }
    out
}

/// Force on every point of strand `s` except bending, at `v = 0`: gravity on free points, goal
/// springs and stretch springs, N.
fn load(strands: &StrandSet, s: usize, params: &HairParams, root: &RootFrame) -> Vec<Vector3<f64>> {
    let p = strands.points(s);
    let x = &strands.positions[p.clone()];
    let inv_mass = &strands.inverse_masses()[p.clone()];
    let rest = &strands.rest_local()[p.clone()];
    let gw = &strands.goal_weights()[p];
    let l0 = &strands.rest_lengths()[strands.segments(s)];
    let g: Vector3<f64> = params.gravity().cast();
    let mut out: Vec<Vector3<f64>> = (0..x.len())
        .map(|i| {
            if inv_mass[i] > 0.0 {
                let goal = (root.to_world(&rest[i]) - x[i]).cast::<f64>()
                    * (params.goal_stiffness * gw[i]) as f64;
                g / inv_mass[i] as f64 + goal
            } else {
                Vector3::zeros()
            }
        })
        .collect();
    for j in 0..x.len() - 1 {
        let d = (x[j + 1] - x[j]).cast::<f64>();
        let len = d.norm();
        let tension = d * (params.stretch_stiffness as f64 * (len - l0[j] as f64) / len);
        out[j] += tension;
        out[j + 1] -= tension;
    }
    out
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
    let g = geometry(x, root);
    let kb = params.bend_stiffness as f64;
    let f: Vec<Vector3<f64>> = (0..x.len() - 1)
        .map(|j| {
            let r = Vector3::new(rest[j].t, rest[j].u, rest[j].w).cast::<f64>();
            let target = x[j].cast::<f64>() + g.frame[j] * r * l0[j] as f64;
            (target - x[j + 1].cast::<f64>()) * kb
        })
        .collect();
    let bend = bending_forces(&g, &f);
    let inv_mass = &strands.inverse_masses()[strands.points(s)];
    load(strands, s, params, root)
        .iter()
        .zip(&bend)
        .zip(inv_mass)
        .map(|((p, b), &w)| if w > 0.0 { p + b } else { Vector3::zeros() })
        .collect()
}

/// Bending spring forces `f_j` (N, on point `j + 1`) that balance `load` at every free point
/// exactly, solved from the tip to the root; springs before kinematic points get zero. A point
/// with a non-zero `support` normal rests on a collider, which takes the outward part of the
/// force the spring before it would otherwise have to push with.
fn balancing_forces(
    g: &Geometry,
    load: &[Vector3<f64>],
    free: &[bool],
    support: &[Vector3<f64>],
) -> Vec<Vector3<f64>> {
    let n = load.len();
    let m = n - 1;
    let mut f = vec![Vector3::zeros(); m];
    // Running state: couple and twist of the springs already solved.
    let couple = |f: &[Vector3<f64>], j: usize| g.t[j + 1].cross(&f[j]) * g.len[j];
    let mut suffix_next = 0.0; // S_i
    let mut suffix_after = 0.0; // S_{i+1}
    let mut react_next = Vector3::zeros(); // R_{i+1}
    for i in (1..n).rev() {
        // Everything in B_i that does not involve f_{i−1}.
        let (f_i, c_i) = if i < m {
            (f[i], couple(&f, i))
        } else {
            (Vector3::zeros(), Vector3::zeros())
        };
        let react_i = c_i.cross(&g.t[i]) / g.len[i - 1];
        let s_i = g.t[i].dot(&c_i);
        let suffix_prev = s_i + suffix_next; // S_{i−1}
        let tau_i = if i < m {
            (g.beta[i] * suffix_next + g.beta[i + 1] * suffix_after) / g.len[i]
        } else {
            Vector3::zeros()
        };
        let tau_prev = (g.beta[i - 1] * suffix_prev + g.beta[i] * suffix_next) / g.len[i - 1];
        f[i - 1] = if free[i] {
            // B_i = f_{i−1} − f_i + τ_{i−1} − τ_i − R_i + R_{i+1} = −load_i
            -load[i] + f_i - tau_prev + tau_i + react_i - react_next
        } else {
            Vector3::zeros()
        };
        if let Some(n) = support.get(i).filter(|n| n.norm_squared() > 0.0) {
            // The collider pushes out (never pulls): it carries the outward component.
            let outward = f[i - 1].dot(n);
            if outward > 0.0 {
                f[i - 1] -= n * outward;
            }
        }
        react_next = react_i;
        suffix_after = suffix_next;
        suffix_next = suffix_prev;
    }
    f
}

/// Replaces the rest directions of every strand so that its current positions (the groom, at
/// rest) are a static equilibrium under gravity with `params`, the roots at `roots` (one frame
/// per strand, e.g. [`StrandSet::root_frames`]). Rest lengths are unchanged. Strands that cannot
/// be balanced within `limits` keep their groomed rest directions and are listed in the report.
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
    let kb = params.bend_stiffness as f64;
    let mut report = SagFreeReport::default();
    for (s, root) in roots.iter().enumerate() {
        let p = strands.points(s);
        let x = &strands.positions[p.clone()];
        let free: Vec<bool> = strands.inverse_masses()[p.clone()]
            .iter()
            .map(|&w| w > 0.0)
            .collect();
        let g = geometry(x, root);
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
        let f = balancing_forces(&g, &load, &free, &support);
        let needs_bending = f.iter().any(|f| *f != Vector3::zeros());
        let finite = f.iter().all(|f| f.iter().all(|c| c.is_finite()));
        if !finite || (needs_bending && kb == 0.0) {
            report.unbalanced.push(s);
            continue;
        }
        let seg = strands.segments(s);
        let l0 = &strands.rest_lengths()[seg.clone()];
        let old = &strands.bend_rest()[seg.clone()];
        let mut new = Vec::with_capacity(f.len());
        let (mut turn, mut stretch) = (0.0f64, 0.0f64);
        for j in 0..f.len() {
            let offset = (x[j + 1] - x[j]).cast::<f64>() + f[j] / kb.max(f64::MIN_POSITIVE);
            let r = g.frame[j].transpose() * offset / l0[j] as f64;
            let r_old = Vector3::new(old[j].t, old[j].u, old[j].w).cast::<f64>();
            turn = turn.max(r.angle(&r_old));
            stretch = stretch.max((r.norm() - 1.0).abs());
            new.push(RestDirection {
                t: r.x as f32,
                u: r.y as f32,
                w: r.z as f32,
            });
        }
        if turn > limits.max_turn as f64 {
            report.unbalanced.push(s);
            continue;
        }
        strands.bend_rest_mut()[seg].copy_from_slice(&new);
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
