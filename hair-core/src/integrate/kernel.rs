//! One collision step of a group of up to [`LANES`] strands with the same number of points:
//! `substeps` force substeps, each with its damping sub-loop and, for groups with a contact this
//! step, the contact response (`contacts::penalty`; the contact data is gathered into lanes once
//! per step with the rest, and only points with a contact in some lane are visited).
//!
//! Strand `l` of the group lives in SIMD lane `l` ([`super::lanes`]), so every pass — the
//! per-segment tangents, the sequential frame transport and twist sums of the curvature bending,
//! the per-point updates and the damping sub-loop — advances eight strands per instruction, and
//! the group's whole substep loop stays in L1. The group is gathered from the strand set once per
//! step and scattered back after it. Lanes a group does not fill repeat its last strand and are
//! discarded.
//!
//! Segment arrays are *padded*: segment `j` (points `j`, `j + 1`) sits at index `j + 1`, and
//! indices `0` and `n` hold zeros, so point `i` reads "the segment after" at `i + 1` and "the
//! segment before" at `i` without branches.

use std::sync::OnceLock;

use nalgebra::Vector3;

use crate::contacts::coupling::{self, Correction, CouplingScratch, Lengths, SubstepContacts};
use crate::contacts::detect::NO_CONTACT;
use crate::contacts::penalty::{respond, ContactLanes};
use crate::frames::RestDirection;
use crate::mesh::RootFrame;

use super::curvature::{joint_stiffness, rest_curvature, rigidity, root_direction};
use super::damping::damp_segments;
use super::dispatch::avx2_copy;
use super::implicit::ImplicitScratch;
use super::inextensible::{project, Inextensibility, ProjectionScratch};
use super::lanes::{div_or_zero, splat, zeroed, Lane, LANES, M3, Q4, V3};
use super::params::{HairParams, Integrator, StrandScales};
use super::strain_limit::limit_strain;
use super::xpbd::XpbdScratch;

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
    /// Decay rate of each segment's stretching speed, 1/s (0 = off; the implicit substep folds
    /// it into its solve instead of running the damping sub-loop).
    pub damp_rate: f32,
    pub damp_iterations: u32,
    pub dt: f32,
    pub substeps: u32,
    pub integrator: Integrator,
    /// Largest allowed segment length as a multiple of the rest length, if limited.
    pub max_length_ratio: Option<f32>,
    /// Largest push-out speed of a point inside a collider, m/s.
    pub max_push_speed: f32,
    /// The inextensibility projection after each substep, if on (see `super::inextensible`).
    pub inextensible: Option<Inextensibility>,
}

impl StepConstants {
    pub fn new(
        p: &HairParams,
        dt: f32,
        substeps: u32,
        damp_iterations: u32,
        integrator: Integrator,
        max_strain: Option<f32>,
    ) -> Self {
        let damp_fraction = damp_fraction(p.stretch_damping, dt, damp_iterations);
        Self {
            gravity: p.gravity(),
            stretch: p.stretch_stiffness,
            bend: p.bend_stiffness,
            goal: p.goal_stiffness,
            drag: p.air_drag,
            damp_fraction,
            damp_rate: if damp_iterations > 0 {
                p.stretch_damping
            } else {
                0.0
            },
            damp_iterations,
            dt,
            substeps,
            integrator,
            max_length_ratio: max_strain.map(|e| 1.0 + e),
            max_push_speed: f32::INFINITY,
            inextensible: None,
        }
    }
}

/// Fraction of relative segment velocity the damping sub-loop removes per iteration for the
/// decay rate `rate` (1/s) over a substep `dt` (s) in `iterations` iterations: the exact
/// exponential decay over dt/iterations of an isolated segment, capped at 1/2 so the Jacobi
/// iteration (two segments per point) never overshoots; 0 when off.
fn damp_fraction(rate: f32, dt: f32, iterations: u32) -> f32 {
    if iterations > 0 && rate > 0.0 {
        (1.0 - (-rate * dt / iterations as f32).exp()).min(0.5)
    } else {
        0.0
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
    /// This step's contacts of the strand's points, if any point has one.
    pub contacts: Option<ContactSlice<'a>>,
    /// External acceleration per point for this step (force fields, hair–hair repulsion),
    /// m/s², constant over the substeps; `None` costs nothing. Given to every strand of a step or
    /// to none.
    pub accel: Option<&'a [Vector3<f32>]>,
    /// The strand's multipliers of the step's stiffnesses, damping and drag (per-region
    /// physics; [`StrandScales::ONE`] = the scene's material).
    pub scales: StrandScales,
}

/// One strand's contacts of a step (see [`crate::contacts::detect`]), per point.
#[derive(Clone, Copy)]
pub(crate) struct ContactSlice<'a> {
    pub anchor: &'a [Vector3<f32>],
    pub size: &'a [f32],
    pub curved: &'a [bool],
    pub anchor_velocity: &'a [Vector3<f32>],
    pub surface_velocity: &'a [Vector3<f32>],
    pub friction: &'a [f32],
    pub found_depth: &'a [f32],
}

/// Per-thread work buffers of one group, refitted to each group.
#[derive(Default)]
pub(crate) struct Scratch<L: Lane> {
    pub(super) x: Vec<V3<L>>,
    pub(super) v: Vec<V3<L>>,
    pub(super) v_old: Vec<V3<L>>,
    pub(super) force: Vec<V3<L>>,
    pub(super) rest_local: Vec<V3<L>>,
    pub(super) target: Vec<V3<L>>,
    /// Inverse masses, 1/kg (0 pinned).
    pub(super) inv_mass: Vec<L>,
    /// Each lane's stretch stiffness (the step's × its strand's scale), N/m.
    pub(super) stretch_k: L,
    /// Each lane's air drag rate, 1/s.
    pub(super) drag: L,
    /// Each lane's stretch damping rate, 1/s (0 when the damping sub-loop is off).
    pub(super) damp_rate: L,
    /// 1 for free points, 0 for pinned ones.
    pub(super) free: Vec<L>,
    pub(super) goal_k: Vec<L>,
    /// Rest lengths per segment (unpadded), m.
    pub(super) rest_length: Vec<L>,
    /// Joint stiffness per joint (unpadded, joint j before segment j), N·m
    /// (`super::curvature::joint_stiffness`).
    pub(super) joint_k: Vec<L>,
    /// Unit rest direction of the first segment in the root frame (t, u, w components).
    pub(super) root_rest: V3<L>,
    /// Rest moment `k_j κ⁰_j` per joint (unpadded) as (unused, u, w) components in the previous
    /// segment's frame, N·m.
    pub(super) rest_moment: Vec<V3<L>>,
    /// Points pinned in at least one lane.
    pub(super) pinned: Vec<usize>,
    // Padded segment arrays (index j + 1 = segment j).
    pub(super) tangent: Vec<V3<L>>,
    pub(super) inv_len: Vec<L>,
    pub(super) tension: Vec<L>,
    pub(super) bend: Vec<V3<L>>,
    pub(super) react: Vec<V3<L>>,
    pub(super) beta: Vec<V3<L>>,
    /// Per joint (padded like `bend`), `k K`: the joint's stiffness times its rest curvature
    /// (dimensionless) in the transported frame, world axes, in `joint_k`'s units. Filled by
    /// [`elastic_forces`] only where `gauss_newton_bending` is set.
    pub(super) rest_bend: Vec<V3<L>>,
    /// Does the implicit kernel take bending's Gauss–Newton Hessian for this group (set by it
    /// after [`Scratch::fit`], which clears it)? Its Jacobian turns `rest_bend` with the frame.
    pub(super) gauss_newton_bending: bool,
    pub(super) twist: Vec<L>,
    pub(super) damp_coef: Vec<L>,
    pub(super) impulse: Vec<L>,
    /// Contacts per point (only filled when `has_contacts`).
    pub(super) contact: Vec<ContactLanes<L>>,
    /// Extra velocity of the position update per point (along the contact normal), m/s.
    pub(super) push: Vec<V3<L>>,
    /// Per point, BDF2 only: 1 where the contact response stopped the point in the last
    /// substep (an impact, see [`IMPACT_RATIO`]), 0 elsewhere; written for `contact_points`.
    /// The next BDF2 substep restarts those points' history (`super::implicit`).
    pub(super) impacted: Vec<L>,
    /// Does any strand of the group have a contact this step?
    pub(super) has_contacts: bool,
    /// External acceleration per point (only filled when `has_accel`), m/s².
    pub(super) accel: Vec<V3<L>>,
    /// Do the strands of the group have an external acceleration this step?
    pub(super) has_accel: bool,
    /// Points with a contact in at least one lane (when `has_contacts`).
    pub(super) contact_points: Vec<usize>,
    pub(super) q_start: Q4<L>,
    pub(super) q_end: Q4<L>,
    pub(super) o_start: V3<L>,
    pub(super) o_end: V3<L>,
    /// Buffers of the inextensibility projection and the strain limit.
    pub(super) projection: ProjectionScratch<L>,
    /// Buffers of the contacts solved with them (`contacts::coupling`).
    pub(super) coupling: CouplingScratch<L>,
    /// Buffers of the implicit (backward Euler) substep (`super::implicit`).
    pub(super) implicit: ImplicitScratch<L>,
    /// Buffers of the XPBD substep (`super::xpbd`).
    pub(super) xpbd: XpbdScratch<L>,
}

/// A contact response that changes a point's velocity by more than this many times what
/// gravity and the external acceleration add to it over the substep is an **impact**: it
/// stopped the point's approach, where the support of resting contact only cancels what those
/// forces add. BDF2 restarts an impacted point's history (`super::implicit`, "Contacts and the
/// history"), and leaves resting contact's alone.
pub(super) const IMPACT_RATIO: f32 = 2.0;

/// Refills `buf` with `values` (no zeroing first, for buffers written whole).
#[inline(always)]
fn rebuild<T>(buf: &mut Vec<T>, values: impl Iterator<Item = T>) {
    buf.clear();
    buf.extend(values);
}

/// Each lane's strand's slice `field`, cut to its first `n` entries (lanes the group does not
/// fill take the last strand's). Cut once per group, the slices let the gathers below index
/// every lane without a bounds check or a lookup of its strand per entry.
#[inline(always)]
fn lane_slices<'a, T>(
    views: &'a [StrandView<'_>],
    n: usize,
    field: impl Fn(&'a StrandView<'_>) -> &'a [T],
) -> [&'a [T]; LANES] {
    let last = views.len() - 1;
    std::array::from_fn(|l| &field(&views[l.min(last)])[..n])
}

/// Refills `buf` with point `i`'s vector of every lane's slice, for `i` below the slices' length.
#[inline(always)]
fn gather_v3<L: Lane>(buf: &mut Vec<V3<L>>, lanes: [&[Vector3<f32>]; LANES]) {
    let n = lanes[0].len();
    rebuild(
        buf,
        (0..n).map(|i| V3 {
            x: L::new(std::array::from_fn(|l| lanes[l][i].x)),
            y: L::new(std::array::from_fn(|l| lanes[l][i].y)),
            z: L::new(std::array::from_fn(|l| lanes[l][i].z)),
        }),
    );
}

/// Refills `buf` with `f` of point `i`'s value of every lane's slice.
#[inline(always)]
fn gather<L: Lane>(buf: &mut Vec<L>, lanes: [&[f32]; LANES], f: impl Fn(f32) -> f32) {
    let n = lanes[0].len();
    rebuild(
        buf,
        (0..n).map(|i| L::new(std::array::from_fn(|l| f(lanes[l][i])))),
    );
}

/// `f` of each lane's strand: strand `l`, or the last strand for lanes the group does not fill.
/// For cheap loads; see [`per_strand`] for costly values.
#[inline(always)]
fn per_lane<T>(views: &[StrandView], f: impl Fn(&StrandView) -> T) -> [T; LANES] {
    let last = views.len() - 1;
    std::array::from_fn(|l| f(&views[l.min(last)]))
}

/// Like [`per_lane`], but `f(l, strand)` runs once per strand `l` of the group, not once per
/// lane: lanes the group does not fill copy the last strand's value.
#[inline(always)]
fn per_strand<T: Copy + Default>(
    views: &[StrandView],
    mut f: impl FnMut(usize, &StrandView) -> T,
) -> [T; LANES] {
    let mut out = [T::default(); LANES];
    for (l, (o, s)) in out.iter_mut().zip(views).enumerate() {
        *o = f(l, s);
    }
    let last = out[views.len() - 1];
    out[views.len()..].fill(last);
    out
}

impl<L: Lane> Scratch<L> {
    pub(super) fn fit(
        &mut self,
        views: &[StrandView],
        starts: &[RootFrame],
        ends: &[RootFrame],
        c: &StepConstants,
    ) {
        let n = views[0].x.len();
        for buf in [&mut self.v_old, &mut self.force, &mut self.target] {
            zeroed(buf, n);
        }
        for buf in [
            &mut self.tangent,
            &mut self.bend,
            &mut self.react,
            &mut self.beta,
        ] {
            zeroed(buf, n + 1);
        }
        for buf in [
            &mut self.inv_len,
            &mut self.tension,
            &mut self.twist,
            &mut self.damp_coef,
            &mut self.impulse,
        ] {
            zeroed(buf, n + 1);
        }
        zeroed(&mut self.joint_k, n - 1);
        zeroed(&mut self.rest_moment, n - 1);
        // Per-strand parameters: each lane loads its own strand's scaled values (a unit scale
        // gives the step's value bit for bit).
        self.stretch_k = L::new(per_lane(views, |s| c.stretch * s.scales.stretch));
        self.drag = L::new(per_lane(views, |s| c.drag * s.scales.drag));
        self.damp_rate = L::new(per_lane(views, |s| c.damp_rate * s.scales.damping));
        let damp_fraction = L::new(per_strand(views, |_, s| {
            damp_fraction(c.damp_rate * s.scales.damping, c.dt, c.damp_iterations)
        }));
        // Per-point data, gathered into buffers written whole.
        gather_v3(&mut self.x, lane_slices(views, n, |s| &*s.x));
        gather_v3(&mut self.v, lane_slices(views, n, |s| &*s.v));
        gather_v3(
            &mut self.rest_local,
            lane_slices(views, n, |s| s.rest_local),
        );
        let inv_mass = lane_slices(views, n, |s| s.inv_mass);
        gather(&mut self.inv_mass, inv_mass, |w| w);
        gather(
            &mut self.free,
            inv_mass,
            |w| if w > 0.0 { 1.0 } else { 0.0 },
        );
        let goal_scale = per_lane(views, |s| c.goal * s.scales.goal);
        let goal_weight = lane_slices(views, n, |s| s.goal_weight);
        let goal_k = (0..n).map(|i| {
            L::new(std::array::from_fn(|l| {
                if inv_mass[l][i] > 0.0 {
                    goal_scale[l] * goal_weight[l][i]
                } else {
                    0.0
                }
            }))
        });
        rebuild(&mut self.goal_k, goal_k);
        gather(
            &mut self.rest_length,
            lane_slices(views, n - 1, |s| s.rest_length),
            |l| l,
        );
        if c.bend > 0.0 {
            // In f64, once per strand: the rigidity, and per joint its stiffness and rest moment.
            let rigidity = per_strand(views, |_, s| {
                rigidity(c.bend * s.scales.bend, s.rest_length)
            });
            for j in 0..n - 1 {
                let joint = per_strand(views, |l, s| {
                    let k = joint_stiffness(rigidity[l], s.rest_length, j) as f32;
                    let (k_u, k_w) = rest_curvature(&s.bend_rest[j]);
                    (k, Vector3::new(0.0, k * k_u, k * k_w))
                });
                self.joint_k[j] = L::new(joint.map(|(k, _)| k));
                self.rest_moment[j] = V3::from_lanes(&joint.map(|(_, m)| m));
            }
        }
        self.root_rest = V3::from_lanes(&per_lane(views, |s| root_direction(&s.bend_rest[0])));
        if c.damp_fraction > 0.0 {
            for j in 0..n - 1 {
                let w = L::new(per_lane(views, |s| s.inv_mass[j] + s.inv_mass[j + 1]));
                self.damp_coef[j + 1] = div_or_zero(damp_fraction, w, 0.0);
            }
        }
        // The step's external acceleration is given to every strand of a step or to none.
        self.has_accel = views.iter().all(|s| s.accel.is_some());
        debug_assert!(self.has_accel || views.iter().all(|s| s.accel.is_none()));
        if self.has_accel {
            gather_v3(
                &mut self.accel,
                lane_slices(views, n, |s| s.accel.unwrap_or_default()),
            );
        }
        self.gauss_newton_bending = false;
        self.has_contacts = views.iter().any(|s| s.contacts.is_some());
        self.contact_points.clear();
        if self.has_contacts {
            zeroed(&mut self.contact, n);
            zeroed(&mut self.push, n);
            zeroed(&mut self.impacted, n);
            self.contact_points.extend((0..n).filter(|&i| {
                views
                    .iter()
                    .any(|s| s.contacts.is_some_and(|c| c.size[i] != NO_CONTACT))
            }));
            for &i in &self.contact_points {
                self.contact[i] = gather_contact(views, i);
            }
        }
        self.pinned.clear();
        self.pinned
            .extend((0..n).filter(|&i| views.iter().any(|s| s.inv_mass[i] == 0.0)));
        let quat = |frames: &[RootFrame]| {
            let q = |l: usize| frames[l.min(frames.len() - 1)].rotation;
            Q4 {
                w: L::new(std::array::from_fn(|l| q(l).w)),
                i: L::new(std::array::from_fn(|l| q(l).i)),
                j: L::new(std::array::from_fn(|l| q(l).j)),
                k: L::new(std::array::from_fn(|l| q(l).k)),
            }
        };
        let origin = |frames: &[RootFrame]| {
            V3::from_lanes(&std::array::from_fn(|l| {
                frames[l.min(frames.len() - 1)].origin
            }))
        };
        self.q_start = quat(starts);
        self.q_end = quat(ends);
        self.o_start = origin(starts);
        self.o_end = origin(ends);
    }

    pub(super) fn scatter(&self, views: &mut [StrandView]) {
        for (i, (x, v)) in self.x.iter().zip(&self.v).enumerate() {
            let (x, v) = (x.to_lanes(), v.to_lanes());
            for (l, s) in views.iter_mut().enumerate() {
                s.x[i] = x[l];
                s.v[i] = v[l];
            }
        }
    }
}

/// Lane `l`'s contact data of point `i` (lanes a group does not fill repeat its last strand;
/// strands without contacts this step get none).
fn gather_contact<L: Lane>(views: &[StrandView], i: usize) -> ContactLanes<L> {
    let zero = Vector3::zeros();
    let mut anchor = [zero; LANES];
    let mut anchor_velocity = [zero; LANES];
    let mut surface_velocity = [zero; LANES];
    let mut size = [NO_CONTACT; LANES];
    let mut curved = [0.0; LANES];
    let mut friction = [0.0; LANES];
    let mut found_depth = [0.0; LANES];
    for l in 0..LANES {
        if let Some(c) = views[l.min(views.len() - 1)].contacts {
            anchor[l] = c.anchor[i];
            anchor_velocity[l] = c.anchor_velocity[i];
            surface_velocity[l] = c.surface_velocity[i];
            size[l] = c.size[i];
            curved[l] = if c.curved[i] { 1.0 } else { 0.0 };
            friction[l] = c.friction[i];
            found_depth[l] = c.found_depth[i];
        }
    }
    ContactLanes {
        anchor: V3::from_lanes(&anchor),
        size: L::new(size),
        curved: L::new(curved),
        anchor_velocity: V3::from_lanes(&anchor_velocity),
        surface_velocity: V3::from_lanes(&surface_velocity),
        friction: L::new(friction),
        found_depth: L::new(found_depth),
    }
}

/// Parallel transport of `u` from unit tangent `tp` to `t` (see [`crate::frames::transport`]).
#[inline(always)]
pub(super) fn transport<L: Lane>(u: &V3<L>, tp: &V3<L>, t: &V3<L>) -> V3<L> {
    let c = splat::<L>(1.0) + tp.dot(t);
    *u - (*tp + *t) * div_or_zero(u.dot(t), c, 1e-6)
}

/// A compiled copy of the kernel for lane type `L`: [`step_group`] or [`step_group_avx2`].
pub(crate) type GroupKernel<L> =
    fn(&mut [StrandView], &[RootFrame], &[RootFrame], &StepConstants, &mut Scratch<L>);

/// Does the solver run [`step_group_avx2`], the kernel compiled for 256-bit registers? On
/// x86-64 CPUs with AVX2 unless `choice` asks for the baseline; elsewhere the solver runs
/// [`step_group`] on [`super::lanes::Baseline`].
pub(crate) fn wide_registers(choice: super::KernelChoice) -> bool {
    choice == super::KernelChoice::Auto && cpu_has_avx2()
}

/// Whether this CPU has AVX2 (detected once; a fact of the machine, not a setting).
fn cpu_has_avx2() -> bool {
    static AVX2: OnceLock<bool> = OnceLock::new();
    *AVX2.get_or_init(|| {
        #[cfg(target_arch = "x86_64")]
        return std::arch::is_x86_feature_detected!("avx2");
        #[cfg(not(target_arch = "x86_64"))]
        return false;
    })
}

avx2_copy!(
    /// [`step_group`] on [`super::lanes::F8`] lanes compiled for AVX2: eight lanes per instruction instead of
    /// four, the same bits. On a CPU without AVX2 it runs the same kernel compiled for the
    /// target's baseline (correct, but slower than [`step_group`] on `Baseline`; the solver picks
    /// that instead, see `wide_registers`).
    pub(crate) fn step_group_avx2 => step_group
);

/// Advances a group of strands (equal point counts, at most [`LANES`]) by one collision step:
/// roots move from `starts` to `ends` (interpolated per substep), pinned points follow their
/// animated rest positions. Always inlined, so that each caller compiles its own copy for its
/// CPU features ([`step_group_avx2`]).
#[inline(always)]
pub(crate) fn step_group<L: Lane>(
    views: &mut [StrandView],
    starts: &[RootFrame],
    ends: &[RootFrame],
    c: &StepConstants,
    g: &mut Scratch<L>,
) {
    debug_assert!(!views.is_empty() && views.len() <= LANES);
    g.fit(views, starts, ends, c);
    let n = views[0].x.len();
    let (dt, inv_dt) = (splat(c.dt), splat(1.0 / c.dt));
    let drag = g.drag;
    let gravity = V3::splat(&c.gravity);
    let explicit = c.integrator == Integrator::ExplicitEuler;
    let zero = splat(0.0);
    let mut clock = SubstepClock::new(g);
    for k in 0..c.substeps {
        let (origin, rot) = clock.end_of(g, k, c.substeps);
        elastic_forces(g, c, &clock);
        if explicit {
            g.v_old.copy_from_slice(&g.v);
        }
        // Velocity update (w = 0 and free = 0 leave pinned points unchanged here).
        for i in 0..n {
            let a = g.force[i] * g.inv_mass[i] + (gravity - g.v[i] * drag) * g.free[i];
            g.v[i] += a * dt;
        }
        if g.has_accel {
            for i in 0..n {
                g.v[i] += g.accel[i] * (dt * g.free[i]);
            }
        }
        for &i in &g.pinned {
            let kinematic = kinematic_velocity(g, i, &origin, &rot, inv_dt);
            g.v[i] = V3::select(g.free[i].simd_gt(zero), &g.v[i], &kinematic);
        }

        if c.damp_fraction > 0.0 {
            damp_segments(
                &mut g.v,
                &g.inv_mass,
                &g.tangent,
                &g.damp_coef,
                &mut g.impulse,
                c.damp_iterations,
            );
        }

        finish_substep(g, c, (k + 1) as f32 * c.dt, &origin, &rot, explicit);
        clock.advance(origin, rot);
    }
    g.scatter(views);
}

/// Where the root frame is at a substep's start (`origin_now`, `rot_now`), carried through the
/// substep loop. Forces of substep k are evaluated at its start, where the positions are: goal
/// targets and the root frame of the bending springs use the scalp at t_k. Kinematic points move
/// to where the scalp puts them at the substep's end, t_{k+1}. (Goal targets taken at t_{k+1}
/// would lead the strand by its velocity × dt.)
pub(super) struct SubstepClock<L: Lane> {
    pub origin_now: V3<L>,
    pub rot_now: M3<L>,
}

impl<L: Lane> SubstepClock<L> {
    /// The clock at the step's start.
    #[inline(always)]
    pub fn new(g: &Scratch<L>) -> Self {
        Self {
            origin_now: g.o_start,
            rot_now: g.q_start.matrix(),
        }
    }

    /// The root frame at the end of substep `k` of `substeps` (origin, rotation).
    #[inline(always)]
    pub fn end_of(&self, g: &Scratch<L>, k: u32, substeps: u32) -> (V3<L>, M3<L>) {
        self.at(g, (k + 1) as f32 / substeps as f32)
    }

    /// The root frame at the fraction `s` (0–1) of the step (origin, rotation).
    #[inline(always)]
    pub fn at(&self, g: &Scratch<L>, s: f32) -> (V3<L>, M3<L>) {
        let rot = Q4::nlerp(&g.q_start, &g.q_end, s).matrix();
        let origin = g.o_start * splat(1.0 - s) + g.o_end * splat(s);
        (origin, rot)
    }

    /// Moves the clock to the next substep's start.
    #[inline(always)]
    pub fn advance(&mut self, origin: V3<L>, rot: M3<L>) {
        self.origin_now = origin;
        self.rot_now = rot;
    }
}

/// The elastic forces of a substep at the current positions into `g.force`: stretch springs,
/// curvature bending and goal springs (goal targets into `g.target`); segment tangents, inverse
/// lengths and tensions stay in `g.tangent`, `g.inv_len` and `g.tension` for later passes.
#[inline(always)]
pub(super) fn elastic_forces<L: Lane>(
    g: &mut Scratch<L>,
    c: &StepConstants,
    clock: &SubstepClock<L>,
) {
    let n = g.x.len();
    let k_stretch = g.stretch_k;
    let needs_targets = c.goal > 0.0;
    let zero = splat::<L>(0.0);
    let (origin_now, rot_now) = (clock.origin_now, clock.rot_now);
    if needs_targets {
        for i in 0..n {
            g.target[i] = origin_now + rot_now.mul(&g.rest_local[i]);
        }
    }
    // Segment tangents and stretch tensions.
    for j in 0..n - 1 {
        let d = g.x[j + 1] - g.x[j];
        let len = d.dot(&d).sqrt();
        // A collider can press two neighbours onto the same spot (a strand hanging straight
        // down onto a rising plate): such a segment has no direction, and takes no stretch or
        // bending direction this substep instead of dividing by zero. Any real segment is
        // far longer than 1 nm, so this leaves every other result bit-identical.
        let inv = div_or_zero(splat(1.0), len, 1e-9);
        g.tangent[j + 1] = d * inv;
        g.inv_len[j + 1] = inv;
        g.tension[j + 1] = k_stretch * (len - g.rest_length[j]);
    }

    // Bending: the curvature energy of `super::curvature`. The previous segment's frame is
    // carried down the strand from the root frame by parallel transport; joint i − 1 (between
    // tangents a = t_{i−2}, or the root normal, and b = t_{i−1}) has the curvature binormal
    // κ = 2β, β = a × b χ, χ = 1/(1 + a·b), and the moment m = k (κ − K) against its rest
    // curvature K in that frame. Its gradient in the tangent planes of b and a,
    // g_b = 2χ m × a − μ (a + b) and g_a = 2χ b × m − μ (a + b) with μ = χ m·κ, acts as
    // −g_b/len on point i (+ on i − 1) and −g_a/len_prev on point i − 1 (+ on i − 2; the root
    // frame is kinematic and takes none).
    //
    // K turns with the transported frame, which turns with every earlier tangent: under a
    // change of the tangents frame i − 1 rotates by `a × δa` (no work: the torque m × K =
    // m × κ lies along a) plus a twist about a that parallel transport accumulates from the
    // root, `ψ_k = −Σ_{i≤k} β_i·(δt_{i−1} + δt_i)` (the holonomy of the reference twist in
    // Bergou et al. 2008). With the twisting torque `s_i = a·(m × κ)` and `S_m = Σ_{j>m} s_j`,
    // the tangent t_m gets the gradient `−β_m S_m − β_{m+1} S_{m+1}`, applied as −G/len_m on
    // x_{m+1} and +G/len_m on x_m. These are the exact energy gradient (what `energy`
    // reports), so bending neither creates nor destroys energy; without the twist terms an
    // undamped strand gains energy (flutter). A segment folded straight back has χ = 0: no
    // curvature, no transport, no force.
    //
    // The bending array ends up holding, per segment, the force its far point receives (its
    // near point gets the opposite); `react` the force of joint i − 1 on the far point of the
    // segment before it.
    if c.bend > 0.0 {
        let keep_rest = g.gauss_newton_bending;
        if keep_rest {
            g.rest_bend.resize(n + 1, V3::default());
        }
        let root_t = rot_now.cols[2];
        let mut tp = root_t;
        let mut up = rot_now.cols[0];
        let (one, two) = (splat::<L>(1.0), splat::<L>(2.0));
        // The root joint measures the turn from the rest direction in the root frame itself
        // (a hanging strand's first segment may turn 180° from the normal at rest, which no
        // curvature can hold); the root frame is kinematic, so it takes no reaction.
        let r = g.root_rest;
        let root_dir = tp * r.x + up * r.y + tp.cross(&up) * r.z;
        for i in 1..n {
            let inv_len_prev = if i == 1 { zero } else { g.inv_len[i - 1] };
            let t = g.tangent[i];
            let chi = div_or_zero(one, one + tp.dot(&t), 1e-6);
            let beta = tp.cross(&t) * chi;
            let (a, chi_e, beta_e, m) = if i == 1 {
                let chi_e = div_or_zero(one, one + root_dir.dot(&t), 1e-6);
                let beta_e = root_dir.cross(&t) * chi_e;
                (root_dir, chi_e, beta_e, beta_e * (two * g.joint_k[0]))
            } else {
                let rest = g.rest_moment[i - 1];
                let m = beta * (two * g.joint_k[i - 1]) - up * rest.y - tp.cross(&up) * rest.z;
                if keep_rest {
                    g.rest_bend[i] = up * rest.y + tp.cross(&up) * rest.z;
                }
                (tp, chi, beta, m)
            };
            let two_chi = two * chi_e;
            let sum = (a + t) * (two_chi * m.dot(&beta_e));
            g.bend[i] = (sum - m.cross(&a) * two_chi) * g.inv_len[i];
            g.react[i] = (t.cross(&m) * two_chi - sum) * inv_len_prev;
            g.twist[i] = two * tp.dot(&m.cross(&beta_e));
            g.beta[i] = beta;
            up = transport(&up, &tp, &t);
            tp = t;
        }
        // Suffix sums in place: twist[i] becomes S for segment i − 1 (sum over i' > i).
        let mut acc = zero;
        for i in (1..n).rev() {
            let here = g.twist[i];
            g.twist[i] = acc;
            acc += here;
        }
        // Index n holds zeros in react, beta and twist.
        for i in 1..n {
            let twist = (g.beta[i] * g.twist[i] + g.beta[i + 1] * g.twist[i + 1]) * g.inv_len[i];
            g.bend[i] = g.bend[i] + twist - g.react[i + 1];
        }
    }

    // Forces per point: stretch from the segments after and before, bending, goal.
    for i in 0..n {
        g.force[i] = g.tangent[i + 1] * g.tension[i + 1] - g.tangent[i] * g.tension[i] + g.bend[i]
            - g.bend[i + 1];
    }
    if needs_targets {
        for i in 0..n {
            g.force[i] += (g.target[i] - g.x[i]) * g.goal_k[i];
        }
    }
}

/// The velocity of point `i`'s prescribed motion over a substep (in lanes where it is pinned):
/// from where it is to where the scalp puts it at the substep's end (`origin`, `rot`).
#[inline(always)]
pub(super) fn kinematic_velocity<L: Lane>(
    g: &Scratch<L>,
    i: usize,
    origin: &V3<L>,
    rot: &M3<L>,
    inv_dt: L,
) -> V3<L> {
    let goal = *origin + rot.mul(&g.rest_local[i]);
    (goal - g.x[i]) * inv_dt
}

/// The end of a substep after the velocity update: the contact response, the position update,
/// kinematic points put where the scalp moves them (`origin`, `rot`: the root frame at the
/// substep's end), then the inextensibility projection and the strain limit if on. `c.dt` is the
/// position update's step (s; the BDF2 substep's is 2/3 of its length) and `t_end` the time of
/// the substep's end from the step's start (s), where time-varying contacts are evaluated.
#[inline(always)]
pub(super) fn finish_substep<L: Lane>(
    g: &mut Scratch<L>,
    c: &StepConstants,
    t_end: f32,
    origin: &V3<L>,
    rot: &M3<L>,
    explicit: bool,
) {
    let n = g.x.len();
    let (dt, inv_dt) = (splat::<L>(c.dt), splat::<L>(1.0 / c.dt));
    let zero = splat::<L>(0.0);
    // Contact response (see `contacts::penalty`): after the velocity update and the damping
    // sub-loop, before the position update. Explicit Euler moves points with the old
    // velocity, so the response applies to that one too.
    if g.has_contacts {
        let t_end = splat(t_end);
        let max_push = splat(c.max_push_speed);
        let bdf2 = c.integrator == Integrator::Bdf2;
        let impact_dt = splat::<L>(IMPACT_RATIO * c.dt);
        let gravity = splat::<L>(c.gravity.norm());
        for &i in &g.contact_points {
            let moving = if explicit {
                &mut g.v_old[i]
            } else {
                &mut g.v[i]
            };
            let before = *moving;
            g.push[i] = respond(moving, &g.x[i], &g.contact[i], t_end, inv_dt, max_push);
            if bdf2 {
                let applied = if g.has_accel {
                    gravity + g.accel[i].dot(&g.accel[i]).sqrt()
                } else {
                    gravity
                };
                let (dv, limit) = (*moving - before, applied * impact_dt);
                let stopped = dv.dot(&dv).simd_gt(limit * limit);
                g.impacted[i] = L::select(stopped, splat(1.0), zero);
            }
        }
        if explicit {
            for &i in &g.contact_points {
                respond(&mut g.v[i], &g.x[i], &g.contact[i], t_end, inv_dt, max_push);
            }
        }
    }

    for i in 0..n {
        let moved_by = if explicit { g.v_old[i] } else { g.v[i] };
        g.x[i] += moved_by * (dt * g.free[i]);
    }
    // With a length constraint, contacts are solved together with it (`contacts::coupling`),
    // which also applies the push-out; without one the push is a plain position correction.
    let coupled = g.has_contacts && (c.inextensible.is_some() || c.max_length_ratio.is_some());
    if !coupled {
        for &i in &g.contact_points {
            g.x[i] += g.push[i] * (dt * g.free[i]);
        }
    }
    for &i in &g.pinned {
        let goal = *origin + rot.mul(&g.rest_local[i]);
        g.x[i] = V3::select(g.free[i].simd_gt(zero), &g.x[i], &goal);
    }
    let mut lengths = LengthConstraints {
        c,
        inv_mass: &g.inv_mass,
        rest_length: &g.rest_length,
        projection: &mut g.projection,
        inv_dt,
    };
    if coupled {
        let contacts = SubstepContacts {
            points: &g.contact_points,
            contact: &g.contact,
            push: &g.push,
            free: &g.free,
            t_end: splat(t_end),
            dt: c.dt,
        };
        coupling::solve(&mut g.x, &mut g.v, &contacts, &mut g.coupling, &mut lengths);
    } else {
        lengths.apply(&mut g.x, &mut g.v, Correction::Motion);
    }
}

/// The substep's length constraints (the inextensibility projection, the strain limit) as
/// `contacts::coupling` calls them between its contact projections.
///
/// A struct with an `#[inline(always)]` method rather than a closure: a closure's body is its
/// own function, compiled for the baseline x86-64 target when it is not inlined, so the strain
/// limit ran in SSE outside the kernel's AVX2 copy (measured: 37 % of the parity scene's strand
/// phase). A method the compiler must inline lands in the AVX2 copy.
struct LengthConstraints<'a, L: Lane> {
    c: &'a StepConstants,
    inv_mass: &'a [L],
    rest_length: &'a [L],
    projection: &'a mut ProjectionScratch<L>,
    /// 1/dt of the position update, 1/s.
    inv_dt: L,
}

impl<L: Lane> Lengths<L> for LengthConstraints<'_, L> {
    #[inline(always)]
    fn apply(&mut self, x: &mut [V3<L>], v: &mut [V3<L>], correction: Correction) {
        if let Some(p) = &self.c.inextensible {
            let velocities = correction == Correction::Motion;
            project(
                x,
                v,
                self.inv_mass,
                self.rest_length,
                p,
                velocities,
                self.projection,
            );
        }
        if let Some(ratio) = self.c.max_length_ratio {
            // Recovery moves positions only: velocities by 0 × the displacement.
            let rate = if correction == Correction::Motion {
                self.inv_dt
            } else {
                splat(0.0)
            };
            limit_strain(
                x,
                v,
                self.inv_mass,
                self.rest_length,
                splat(ratio),
                rate,
                self.projection,
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::UnitQuaternion;

    use super::super::lanes::{Baseline, F8};
    use super::*;

    /// Seven wavy strands of six points (the group's eighth lane repeats the last), some points
    /// in plane or sphere contact, with goal springs, an external acceleration, damping, strain
    /// limiting and a turning root frame: every branch of the kernel runs.
    struct Group {
        x: Vec<Vec<Vector3<f32>>>,
        v: Vec<Vec<Vector3<f32>>>,
        rest_local: Vec<Vector3<f32>>,
        inv_mass: Vec<f32>,
        goal_weight: Vec<f32>,
        rest_length: Vec<f32>,
        bend_rest: Vec<RestDirection>,
        accel: Vec<Vector3<f32>>,
        anchor: Vec<Vector3<f32>>,
        size: Vec<f32>,
        curved: Vec<bool>,
        zero: Vec<Vector3<f32>>,
        friction: Vec<f32>,
        found_depth: Vec<f32>,
    }

    const STRANDS: usize = 7;
    const POINTS: usize = 6;

    fn group() -> Group {
        let wave = |s: usize, i: usize| {
            let (s, i) = (s as f32, i as f32);
            Vector3::new(
                0.1 * s + 0.02 * (i * 1.3 + s).sin(),
                0.03 * i * s.cos(),
                -0.1 * i,
            )
        };
        let contact = |i: usize| i % 2 == 1;
        Group {
            x: (0..STRANDS)
                .map(|s| (0..POINTS).map(|i| wave(s, i)).collect())
                .collect(),
            v: (0..STRANDS)
                .map(|s| (0..POINTS).map(|i| 0.3 * wave(i, s)).collect())
                .collect(),
            rest_local: (0..POINTS)
                .map(|i| Vector3::new(0.0, 0.0, -0.1 * i as f32))
                .collect(),
            inv_mass: (0..POINTS)
                .map(|i| if i == 0 { 0.0 } else { 1e3 })
                .collect(),
            goal_weight: vec![0.5; POINTS],
            rest_length: vec![0.1; POINTS - 1],
            bend_rest: (0..POINTS - 1)
                .map(|j| RestDirection {
                    t: 0.9,
                    u: 0.1 * j as f32,
                    w: -0.05,
                })
                .collect(),
            accel: (0..POINTS)
                .map(|i| Vector3::new(0.5, -0.2 * i as f32, 0.0))
                .collect(),
            anchor: (0..POINTS)
                .map(|i| Vector3::new(0.0, if contact(i) { 1.0 } else { 0.0 }, 0.0))
                .collect(),
            size: (0..POINTS)
                .map(|i| match i {
                    1 => 0.01,
                    3 => 0.2,
                    _ => crate::contacts::detect::NO_CONTACT,
                })
                .collect(),
            curved: (0..POINTS).map(|i| i == 3).collect(),
            zero: vec![Vector3::zeros(); POINTS],
            friction: vec![0.4; POINTS],
            found_depth: (0..POINTS)
                .map(|i| if i == 1 { 0.002 } else { 0.0 })
                .collect(),
        }
    }

    /// Runs `kernel` on a fresh copy of the group; returns every position and velocity.
    fn run<L: Lane>(kernel: GroupKernel<L>) -> Vec<Vector3<f32>> {
        let mut g = group();
        let h = group();
        let mut views: Vec<StrandView> =
            g.x.iter_mut()
                .zip(g.v.iter_mut())
                .map(|(x, v)| StrandView {
                    x,
                    v,
                    rest_local: &h.rest_local,
                    inv_mass: &h.inv_mass,
                    goal_weight: &h.goal_weight,
                    rest_length: &h.rest_length,
                    bend_rest: &h.bend_rest,
                    contacts: Some(ContactSlice {
                        anchor: &h.anchor,
                        size: &h.size,
                        curved: &h.curved,
                        anchor_velocity: &h.zero,
                        surface_velocity: &h.zero,
                        friction: &h.friction,
                        found_depth: &h.found_depth,
                    }),
                    accel: Some(&h.accel),
                    scales: StrandScales::ONE,
                })
                .collect();
        let frame = |angle: f32| RootFrame {
            origin: Vector3::new(0.0, 0.0, 0.01 * angle),
            rotation: UnitQuaternion::from_euler_angles(0.0, 0.0, angle),
        };
        let starts = vec![frame(0.0); STRANDS];
        let ends = vec![frame(0.2); STRANDS];
        let params = HairParams {
            goal_stiffness: 5.0,
            ..HairParams::default()
        };
        let consts = StepConstants::new(
            &params,
            1e-3,
            12,
            4,
            Integrator::SemiImplicitEuler,
            Some(0.01),
        );
        kernel(&mut views, &starts, &ends, &consts, &mut Scratch::default());
        drop(views);
        g.x.into_iter().chain(g.v).flatten().collect()
    }

    #[test]
    fn every_compiled_copy_gives_the_same_bits() {
        let baseline = run::<Baseline>(step_group::<Baseline>);
        let bits = |p: &[Vector3<f32>]| -> Vec<u32> {
            p.iter()
                .flat_map(|q| q.iter().map(|c| c.to_bits()))
                .collect()
        };
        assert!(baseline.iter().all(|p| p.iter().all(|c| c.is_finite())));
        // The strands moved (the test is not comparing two untouched copies).
        assert_ne!(bits(&baseline[..POINTS]), bits(&group().x[0]));
        // F8 lanes in the AVX2 copy where the CPU has it, and compiled for the baseline.
        assert_eq!(bits(&run::<F8>(step_group_avx2)), bits(&baseline));
        assert_eq!(bits(&run::<F8>(step_group::<F8>)), bits(&baseline));
        // The implicit substep's copies likewise (and it moves the strands differently).
        use super::super::implicit::{step_group_implicit, step_group_implicit_avx2};
        let implicit = run::<Baseline>(step_group_implicit::<Baseline>);
        assert!(implicit.iter().all(|p| p.iter().all(|c| c.is_finite())));
        assert_ne!(bits(&implicit), bits(&baseline));
        assert_eq!(bits(&run::<F8>(step_group_implicit_avx2)), bits(&implicit));
        assert_eq!(bits(&run::<F8>(step_group_implicit::<F8>)), bits(&implicit));
        // And the XPBD substep's.
        use super::super::xpbd::{step_group_xpbd, step_group_xpbd_avx2};
        let xpbd = run::<Baseline>(step_group_xpbd::<Baseline>);
        assert!(xpbd.iter().all(|p| p.iter().all(|c| c.is_finite())));
        assert_ne!(bits(&xpbd), bits(&baseline));
        assert_eq!(bits(&run::<F8>(step_group_xpbd_avx2)), bits(&xpbd));
        assert_eq!(bits(&run::<F8>(step_group_xpbd::<F8>)), bits(&xpbd));
    }
}
