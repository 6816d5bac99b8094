//! Mechanical energy of a strand set, accumulated in f64: kinetic, spring potentials and gravity.
//! Used by tests (energy conservation) and by blow-up detection.

use nalgebra::{Matrix3, Vector3};

use crate::frames::transport;
use crate::mesh::RootFrame;
use crate::strands::StrandSet;

use super::curvature::{joint_stiffness, rest_curvature, rigidity, root_direction};
use super::params::HairParams;

/// Energy of a strand set by kind, J.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Energy {
    /// ½ m v² of free points.
    pub kinetic: f64,
    /// ½ k (len − rest)² of stretch springs.
    pub stretch: f64,
    /// ½ k_j |κ_j − κ⁰_j|² of the curvature bending (`super::curvature`).
    pub bend: f64,
    /// ½ k w |goal − x|² of goal springs.
    pub goal: f64,
    /// −m g·x of free points (zero at the origin).
    pub gravity: f64,
    /// `Σ G J (m − m̄)² / (2 l̄)` of the rod model's twist (zero for the other models).
    pub twist: f64,
}

impl Energy {
    /// Sum of all kinds, J.
    pub fn total(&self) -> f64 {
        self.kinetic + self.stretch + self.bend + self.goal + self.gravity + self.twist
    }

    fn add(&mut self, o: &Energy) {
        self.kinetic += o.kinetic;
        self.stretch += o.stretch;
        self.bend += o.bend;
        self.goal += o.goal;
        self.gravity += o.gravity;
        self.twist += o.twist;
    }
}

/// Energy of the whole set with roots at `roots` (one frame per strand), summed strand by strand
/// in index order (deterministic).
pub fn energy(strands: &StrandSet, params: &HairParams, roots: &[RootFrame]) -> Energy {
    let mut e = Energy::default();
    for (s, root) in roots.iter().enumerate().take(strands.len()) {
        e.add(&strand_energy(strands, s, params, root));
    }
    e
}

/// Energy of strand `s` with its root at `root`.
pub fn strand_energy(
    strands: &StrandSet,
    s: usize,
    params: &HairParams,
    root: &RootFrame,
) -> Energy {
    let p = strands.points(s);
    let seg = strands.segments(s);
    let x = &strands.positions[p.clone()];
    let v = &strands.velocities[p.clone()];
    let m = &strands.masses()[p.clone()];
    let rest = &strands.rest_local()[p.clone()];
    let gw = &strands.goal_weights()[p];
    let l0 = &strands.rest_lengths()[seg.clone()];
    let bend_rest = &strands.bend_rest()[seg];
    let g: Vector3<f64> = params.gravity().cast();
    let rot: Matrix3<f32> = root.rotation.to_rotation_matrix().into_inner();
    let mut e = Energy::default();
    for i in 0..x.len() {
        let mi = m[i] as f64;
        e.kinetic += 0.5 * mi * v[i].cast::<f64>().norm_squared();
        e.gravity -= mi * g.dot(&x[i].cast());
        if params.goal_stiffness > 0.0 {
            let target = root.origin + rot * rest[i];
            e.goal += 0.5
                * (params.goal_stiffness * gw[i]) as f64
                * (target - x[i]).cast::<f64>().norm_squared();
        }
    }
    // Curvature bending (`super::curvature`), in the kernel's f32 transported frames.
    let ei = rigidity(params.bend_stiffness, l0);
    let mut tp: Vector3<f32> = rot.column(2).into();
    let mut up: Vector3<f32> = rot.column(0).into();
    for j in 0..x.len() - 1 {
        let d = x[j + 1] - x[j];
        let len = d.norm();
        e.stretch += 0.5 * params.stretch_stiffness as f64 * ((len - l0[j]) as f64).powi(2);
        if params.bend_stiffness > 0.0 {
            let t = d / len;
            let u = up.cast::<f64>();
            // The root joint: the turn from the rest direction itself, against zero.
            let (a, rest) = if j == 0 {
                let d = root_direction(&bend_rest[0]);
                let d = tp * d.x + up * d.y + tp.cross(&up) * d.z;
                (d.cast::<f64>(), Vector3::zeros())
            } else {
                let a = tp.cast::<f64>();
                let (k_u, k_w) = rest_curvature(&bend_rest[j]);
                (a, u * k_u as f64 + a.cross(&u) * k_w as f64)
            };
            let b = t.cast::<f64>();
            let c = 1.0 + a.dot(&b);
            let kappa = if c > 1e-6 {
                a.cross(&b) * (2.0 / c)
            } else {
                Vector3::zeros()
            };
            let k = joint_stiffness(ei, l0, j);
            e.bend += 0.5 * k * (kappa - rest).norm_squared();
            up = transport(&up, &tp, &t);
            tp = t;
        }
    }
    e
}
