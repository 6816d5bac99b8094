//! One strand's whole collision step: `substeps` force substeps, each with its damping sub-loop.
//!
//! The strand's points stay in L1 for the whole loop. Every pass but one runs over independent
//! points or segments (the compiler can vectorise them); the exception is the frame transport in
//! the bending pass, a short recursion of one division per segment.

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

/// Per-thread work buffers, grown to the longest strand seen.
#[derive(Default)]
pub(crate) struct Scratch {
    tangent: Vec<Vector3<f32>>,
    length: Vec<f32>,
    force: Vec<Vector3<f32>>,
    v_old: Vec<Vector3<f32>>,
    damp_coef: Vec<f32>,
    impulse: Vec<f32>,
}

impl Scratch {
    fn fit(&mut self, points: usize) {
        let segs = points - 1;
        self.tangent.resize(segs, Vector3::zeros());
        self.length.resize(segs, 0.0);
        self.force.resize(points, Vector3::zeros());
        self.v_old.resize(points, Vector3::zeros());
        self.damp_coef.resize(segs, 0.0);
        self.impulse.resize(segs, 0.0);
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
    scratch.fit(n);
    let Scratch {
        tangent,
        length,
        force,
        v_old,
        damp_coef,
        impulse,
    } = scratch;
    let dt = c.dt;
    let inv_dt = 1.0 / dt;
    if c.damp_fraction > 0.0 {
        for j in 0..n - 1 {
            let w = s.inv_mass[j] + s.inv_mass[j + 1];
            damp_coef[j] = if w > 0.0 { c.damp_fraction / w } else { 0.0 };
        }
    }
    for k in 0..c.substeps {
        let root = start.interpolate(end, (k + 1) as f32 / c.substeps as f32);
        let rot: Matrix3<f32> = root.rotation.to_rotation_matrix().into_inner();

        // Segment directions and lengths.
        for j in 0..n - 1 {
            let d = s.x[j + 1] - s.x[j];
            let l = d.norm();
            length[j] = l;
            tangent[j] = d / l;
        }

        // Stretch springs.
        force.fill(Vector3::zeros());
        for j in 0..n - 1 {
            let f = tangent[j] * (c.stretch * (length[j] - s.rest_length[j]));
            force[j] += f;
            force[j + 1] -= f;
        }

        // Bending springs towards the rest direction in the previous segment's frame; the frame
        // before segment 0 is the root frame, which holds the first segment to the scalp.
        if c.bend > 0.0 {
            let mut tp: Vector3<f32> = rot.column(2).into();
            let mut up: Vector3<f32> = rot.column(0).into();
            for j in 0..n - 1 {
                let wp = tp.cross(&up);
                let dir = s.bend_rest[j].in_frame(&tp, &up, &wp);
                let f = (s.x[j] + dir * s.rest_length[j] - s.x[j + 1]) * c.bend;
                force[j + 1] += f;
                force[j] -= f;
                up = transport(&up, &tp, &tangent[j]);
                tp = tangent[j];
            }
        }

        // Goal springs towards the animated rest position.
        if c.goal > 0.0 {
            for i in 0..n {
                let target = root.origin + rot * s.rest_local[i];
                force[i] += (target - s.x[i]) * (c.goal * s.goal_weight[i]);
            }
        }

        if c.integrator == Integrator::ExplicitEuler {
            v_old.copy_from_slice(s.v);
        }
        for i in 0..n {
            let w = s.inv_mass[i];
            if w > 0.0 {
                let a = force[i] * w + c.gravity - s.v[i] * c.drag;
                s.v[i] += a * dt;
            } else {
                let target = root.origin + rot * s.rest_local[i];
                s.v[i] = (target - s.x[i]) * inv_dt;
            }
        }

        if c.damp_fraction > 0.0 {
            damp_segments(
                s.v,
                s.inv_mass,
                tangent,
                damp_coef,
                impulse,
                c.damp_iterations,
            );
        }

        let moved_by = if c.integrator == Integrator::ExplicitEuler {
            &*v_old
        } else {
            &*s.v
        };
        for i in 0..n {
            if s.inv_mass[i] > 0.0 {
                s.x[i] += moved_by[i] * dt;
            } else {
                s.x[i] = root.origin + rot * s.rest_local[i];
            }
        }
    }
}
