//! One strand's whole collision step: `substeps` force substeps, each with its damping sub-loop.
//!
//! The strand is copied once per step into strand-local structure-of-arrays scratch (separate
//! x, y, z lanes), so every pass over points or segments is a plain loop over equal-length slices
//! that the compiler vectorises, and the whole substep loop stays in L1. Segment arrays are
//! *padded*: segment `j` (points `j`, `j + 1`) sits at index `j + 1`, and indices `0` and `n` hold
//! zeros, so point `i` reads "the segment after" at `i + 1` and "the segment before" at `i`
//! without branches. The sequential passes are those of the bending springs: the frame transport
//! down the strand and the suffix sum of their twisting torques back up, a short recursion each.

// Index loops over several equal-length lanes are the point of this module: they vectorise.
#![allow(clippy::needless_range_loop)]

use nalgebra::{Matrix3, Vector3};

use crate::frames::{transport, RestDirection};
use crate::mesh::RootFrame;

use super::damping::damp_segments;
use super::params::{HairParams, Integrator};

/// Constants of a step shared by every strand.
#[derive(Debug, Clone, Copy)]
pub(crate) struct StepConstants {
    pub gravity: Vector3<f32>,
    pub stretch: f32,
    pub bend: f32,
    pub goal: f32,
    pub drag: f32,
    /// Fraction of relative segment velocity removed per damping iteration (0 = off).
    pub damp_fraction: f32,
    pub damp_iterations: u32,
    pub dt: f32,
    pub substeps: u32,
    pub integrator: Integrator,
}

impl StepConstants {
    pub fn new(
        p: &HairParams,
        dt: f32,
        substeps: u32,
        damp_iterations: u32,
        integrator: Integrator,
    ) -> Self {
        let damp_fraction = if damp_iterations > 0 && p.stretch_damping > 0.0 {
            // Exact exponential decay over dt/iterations for an isolated segment, capped at 1/2 so
            // the Jacobi iteration (two segments per point) never overshoots.
            (1.0 - (-p.stretch_damping * dt / damp_iterations as f32).exp()).min(0.5)
        } else {
            0.0
        };
        Self {
            gravity: p.gravity(),
            stretch: p.stretch_stiffness,
            bend: p.bend_stiffness,
            goal: p.goal_stiffness,
            drag: p.air_drag,
            damp_fraction,
            damp_iterations,
            dt,
            substeps,
            integrator,
        }
    }
}

/// Borrowed data of one strand.
pub(crate) struct StrandView<'a> {
    pub x: &'a mut [Vector3<f32>],
    pub v: &'a mut [Vector3<f32>],
    pub rest_local: &'a [Vector3<f32>],
    pub inv_mass: &'a [f32],
    pub goal_weight: &'a [f32],
    pub rest_length: &'a [f32],
    pub bend_rest: &'a [RestDirection],
}

/// Three f32 lanes of equal length.
#[derive(Default)]
pub(crate) struct Lanes {
    pub x: Vec<f32>,
    pub y: Vec<f32>,
    pub z: Vec<f32>,
}

impl Lanes {
    fn fit(&mut self, len: usize) {
        for lane in [&mut self.x, &mut self.y, &mut self.z] {
            lane.clear();
            lane.resize(len, 0.0);
        }
    }

    fn load(&mut self, from: &[Vector3<f32>]) {
        for (i, p) in from.iter().enumerate() {
            self.x[i] = p.x;
            self.y[i] = p.y;
            self.z[i] = p.z;
        }
    }

    fn store(&self, to: &mut [Vector3<f32>]) {
        for (i, p) in to.iter_mut().enumerate() {
            *p = Vector3::new(self.x[i], self.y[i], self.z[i]);
        }
    }

    #[inline(always)]
    fn get(&self, i: usize) -> Vector3<f32> {
        Vector3::new(self.x[i], self.y[i], self.z[i])
    }

    #[inline(always)]
    fn set(&mut self, i: usize, p: Vector3<f32>) {
        self.x[i] = p.x;
        self.y[i] = p.y;
        self.z[i] = p.z;
    }
}

/// Per-thread work buffers, refitted to each strand.
#[derive(Default)]
pub(crate) struct Scratch {
    x: Lanes,
    v: Lanes,
    v_old: Lanes,
    force: Lanes,
    /// Padded unit tangents (index j + 1 = segment j).
    tangent: Lanes,
    /// Padded bending forces on the far point of each segment.
    bend: Lanes,
    /// Animated rest positions (goal and pinned targets) of the current substep.
    target: Lanes,
    /// Padded stretch force magnitudes, N.
    tension: Vec<f32>,
    /// Padded damping coefficients β / (w_j + w_{j+1}).
    damp_coef: Vec<f32>,
    /// Padded damping impulses.
    impulse: Vec<f32>,
    /// Padded rest directions of the bending springs in their reference frames (unit).
    dir: Lanes,
    /// Padded reactions of the bending springs on the segment before theirs, N.
    react: Lanes,
    /// Padded holonomy vectors β of the transported frames (dimensionless).
    beta: Lanes,
    /// Padded twisting torques of the bending springs, then their suffix sums, N·m.
    twist: Vec<f32>,
    /// Padded inverse segment lengths, 1/m.
    inv_len: Vec<f32>,
    /// 1 for free points, 0 for pinned ones.
    free: Vec<f32>,
    goal_k: Vec<f32>,
    pinned: Vec<usize>,
}

impl Scratch {
    fn fit(&mut self, s: &StrandView, c: &StepConstants) {
        let n = s.x.len();
        for lanes in [
            &mut self.x,
            &mut self.v,
            &mut self.v_old,
            &mut self.force,
            &mut self.target,
        ] {
            lanes.fit(n);
        }
        for lanes in [
            &mut self.tangent,
            &mut self.bend,
            &mut self.dir,
            &mut self.react,
            &mut self.beta,
        ] {
            lanes.fit(n + 1);
        }
        for buf in [
            &mut self.tension,
            &mut self.damp_coef,
            &mut self.impulse,
            &mut self.twist,
            &mut self.inv_len,
        ] {
            buf.clear();
            buf.resize(n + 1, 0.0);
        }
        self.x.load(s.x);
        self.v.load(s.v);
        self.free.clear();
        self.free
            .extend(s.inv_mass.iter().map(|&w| if w > 0.0 { 1.0 } else { 0.0 }));
        self.pinned.clear();
        self.pinned.extend((0..n).filter(|&i| s.inv_mass[i] == 0.0));
        self.goal_k.clear();
        self.goal_k
            .extend(s.goal_weight.iter().zip(s.inv_mass).map(|(&g, &w)| {
                if w > 0.0 {
                    c.goal * g
                } else {
                    0.0
                }
            }));
        if c.damp_fraction > 0.0 {
            for j in 0..n - 1 {
                let w = s.inv_mass[j] + s.inv_mass[j + 1];
                self.damp_coef[j + 1] = if w > 0.0 { c.damp_fraction / w } else { 0.0 };
            }
        }
    }
}

/// Advances one strand by one collision step: the root moves from `start` to `end` (interpolated
/// per substep), pinned points follow their animated rest positions.
pub(crate) fn step_strand(
    s: &mut StrandView,
    start: &RootFrame,
    end: &RootFrame,
    c: &StepConstants,
    scratch: &mut Scratch,
) {
    let n = s.x.len();
    scratch.fit(s, c);
    let Scratch {
        x,
        v,
        v_old,
        force,
        tangent,
        bend,
        target,
        tension,
        damp_coef,
        impulse,
        dir,
        react,
        beta,
        twist,
        inv_len,
        free,
        goal_k,
        pinned,
    } = scratch;
    let (dt, inv_dt) = (c.dt, 1.0 / c.dt);
    let w = s.inv_mass;
    let l0 = s.rest_length;
    let needs_targets = c.goal > 0.0;
    // Forces of substep k are evaluated at its start, where the positions are: goal targets and
    // the root frame of the bending springs use the scalp at t_k (`now`). Kinematic points move to
    // where the scalp puts them at the substep's end, t_{k+1} (`root`). (Goal targets taken at
    // t_{k+1} would lead the strand by its velocity × dt.)
    let mut now = *start;
    let mut rot_now: Matrix3<f32> = now.rotation.to_rotation_matrix().into_inner();
    for k in 0..c.substeps {
        let root = start.interpolate(end, (k + 1) as f32 / c.substeps as f32);
        let rot: Matrix3<f32> = root.rotation.to_rotation_matrix().into_inner();
        let to_world = |i: usize| root.origin + rot * s.rest_local[i];
        if needs_targets {
            for i in 0..n {
                target.set(i, now.origin + rot_now * s.rest_local[i]);
            }
        }

        // Segment tangents and stretch tensions (padded: segment j at j + 1).
        for j in 0..n - 1 {
            let dx = x.x[j + 1] - x.x[j];
            let dy = x.y[j + 1] - x.y[j];
            let dz = x.z[j + 1] - x.z[j];
            let len = (dx * dx + dy * dy + dz * dz).sqrt();
            let inv = 1.0 / len;
            tangent.x[j + 1] = dx * inv;
            tangent.y[j + 1] = dy * inv;
            tangent.z[j + 1] = dz * inv;
            inv_len[j + 1] = inv;
            tension[j + 1] = c.stretch * (len - l0[j]);
        }

        // Bending springs: the previous segment's frame is carried down the strand from the root
        // frame by parallel transport (sequential), pulling point j + 1 towards its rest direction
        // d_j in that frame with f_j = k (x_j + l_j d_j − x_{j+1}).
        //
        // The forces are the exact gradient of the spring energy
        // E_j = ½ k |x_j + l_j d_j − x_{j+1}|² (what `energy` reports), so bending neither creates
        // nor destroys energy. Besides f_j on x_{j+1} and −f_j on x_j: d_j turns with frame j − 1,
        // whose rotation under a change of the tangents is `t_{j−1} × δt_{j−1}` plus a twist about
        // t_{j−1} that parallel transport accumulates from the root,
        // `ψ_k = −Σ_{i≤k} β_i·(δt_{i−1} + δt_i)` with `β_i = t_{i−1} × t_i / (1 + t_{i−1}·t_i)`
        // (the holonomy of the reference twist in Bergou et al. 2008). With `c_j = l_j d_j × f_j`
        // and `s_j = t_{j−1}·c_j` (the spring's twisting torque), the energy gradient with respect
        // to tangent t_m is `G_m = c_{m+1} × t_m − β_m S_m − β_{m+1} S_{m+1}`, `S_m = Σ_{j>m} s_j`,
        // applied as −G_m/len_m on x_{m+1} and +G_m/len_m on x_m. Its first term is the opposite
        // couple on the previous segment; without these terms the springs exert a net torque and
        // an undamped strand gains energy (flutter). The root frame (t_{−1}) is kinematic and
        // takes no reaction.
        //
        // Only the transport is sequential; the rest runs per segment (padded index i = j + 1),
        // and the bending lane ends up holding, per segment, the force its far point receives
        // (its near point gets the opposite): f_j − g_{j+1} − G_j's twist part / len_j.
        if c.bend > 0.0 {
            let root_t: Vector3<f32> = rot_now.column(2).into();
            let mut tp = root_t;
            let mut up: Vector3<f32> = rot_now.column(0).into();
            for j in 0..n - 1 {
                dir.set(j + 1, s.bend_rest[j].in_frame(&tp, &up, &tp.cross(&up)));
                let t = tangent.get(j + 1);
                up = transport(&up, &tp, &t);
                tp = t;
            }
            // Per segment: f, couple c, twist torque s, reaction g = c × t_{j−1} / len_{j−1}
            // (stored with the spring, applied to segment j − 1) and β_j. A segment folded
            // straight back has no transport (see `frames::transport`): β = 0 there.
            #[inline(always)]
            #[allow(clippy::too_many_arguments)]
            fn spring(
                i: usize,
                t_prev: Vector3<f32>,
                inv_len_prev: f32,
                k_bend: f32,
                l: f32,
                x: &Lanes,
                tangent: &Lanes,
                dir: &Lanes,
                bend: &mut Lanes,
                react: &mut Lanes,
                beta: &mut Lanes,
                twist: &mut [f32],
            ) {
                let d = dir.get(i);
                let f = (x.get(i - 1) + d * l - x.get(i)) * k_bend;
                bend.set(i, f);
                let couple = d.cross(&f) * l;
                twist[i] = t_prev.dot(&couple);
                react.set(i, couple.cross(&t_prev) * inv_len_prev);
                let t = tangent.get(i);
                let cos1 = 1.0 + t_prev.dot(&t);
                let scale = if cos1 > 1e-6 { 1.0 / cos1 } else { 0.0 };
                beta.set(i, t_prev.cross(&t) * scale);
            }
            spring(
                1, root_t, 0.0, c.bend, l0[0], x, tangent, dir, bend, react, beta, twist,
            );
            for i in 2..n {
                let t_prev = tangent.get(i - 1);
                let inv = inv_len[i - 1];
                spring(
                    i,
                    t_prev,
                    inv,
                    c.bend,
                    l0[i - 1],
                    x,
                    tangent,
                    dir,
                    bend,
                    react,
                    beta,
                    twist,
                );
            }
            // Suffix sums in place: twist[i] becomes S for segment i − 1 (sum over i' > i).
            let mut acc = 0.0f32;
            for i in (1..n).rev() {
                let s_here = twist[i];
                twist[i] = acc;
                acc += s_here;
            }
            // Index n holds zeros in react, beta and twist.
            for i in 1..n {
                let (sa, sb) = (twist[i], twist[i + 1]);
                let w = inv_len[i];
                bend.x[i] += (beta.x[i] * sa + beta.x[i + 1] * sb) * w - react.x[i + 1];
                bend.y[i] += (beta.y[i] * sa + beta.y[i + 1] * sb) * w - react.y[i + 1];
                bend.z[i] += (beta.z[i] * sa + beta.z[i + 1] * sb) * w - react.z[i + 1];
            }
        }

        // Forces per point: stretch from the segments after and before, bending, goal.
        for i in 0..n {
            force.x[i] = tension[i + 1] * tangent.x[i + 1] - tension[i] * tangent.x[i] + bend.x[i]
                - bend.x[i + 1];
            force.y[i] = tension[i + 1] * tangent.y[i + 1] - tension[i] * tangent.y[i] + bend.y[i]
                - bend.y[i + 1];
            force.z[i] = tension[i + 1] * tangent.z[i + 1] - tension[i] * tangent.z[i] + bend.z[i]
                - bend.z[i + 1];
        }
        if needs_targets {
            for i in 0..n {
                force.x[i] += goal_k[i] * (target.x[i] - x.x[i]);
                force.y[i] += goal_k[i] * (target.y[i] - x.y[i]);
                force.z[i] += goal_k[i] * (target.z[i] - x.z[i]);
            }
        }

        let explicit = c.integrator == Integrator::ExplicitEuler;
        if explicit {
            v_old.x.copy_from_slice(&v.x);
            v_old.y.copy_from_slice(&v.y);
            v_old.z.copy_from_slice(&v.z);
        }
        // Velocity update of free points (w = 0 and free = 0 leave pinned points unchanged here).
        let (gx, gy, gz) = (c.gravity.x, c.gravity.y, c.gravity.z);
        for i in 0..n {
            v.x[i] += dt * (force.x[i] * w[i] + free[i] * (gx - c.drag * v.x[i]));
            v.y[i] += dt * (force.y[i] * w[i] + free[i] * (gy - c.drag * v.y[i]));
            v.z[i] += dt * (force.z[i] * w[i] + free[i] * (gz - c.drag * v.z[i]));
        }
        // Pinned points get the velocity of their prescribed motion over this substep.
        for &i in pinned.iter() {
            let goal = to_world(i);
            v.set(i, (goal - x.get(i)) * inv_dt);
        }

        if c.damp_fraction > 0.0 {
            damp_segments(v, w, tangent, damp_coef, impulse, c.damp_iterations);
        }

        let moved_by = if explicit { &*v_old } else { &*v };
        for i in 0..n {
            x.x[i] += dt * free[i] * moved_by.x[i];
            x.y[i] += dt * free[i] * moved_by.y[i];
            x.z[i] += dt * free[i] * moved_by.z[i];
        }
        for &i in pinned.iter() {
            x.set(i, to_world(i));
        }
        now = root;
        rot_now = rot;
    }
    x.store(s.x);
    v.store(s.v);
}
