//! One strand of the rod model: its rest data ([`RodStrand`]) and one substep of it
//! ([`RodStrand::substep`]): quasistatic elastic twist, explicit step of the bending and twisting
//! forces and gravity,
//! projection onto inextensibility, root coupling and head contacts, velocities from the
//! projected positions.

use nalgebra::{UnitQuaternion, Vector3};

use super::collide::{penetrating, Clearance};
use super::forces::{self, NodeRest};
use super::frames::{material, transport, EdgeFrames, Ghost, V3};
use super::project::{self, Contact, Projection};
use super::stiffness::Stiffness;
use super::twist::{self, Relaxation, Twist, TwistRest};
use crate::contacts::Colliders;
use crate::mesh::RootFrame;

/// Rounds of contact detection per substep: after each projection the projected strand is
/// checked again and newly penetrating nodes join the set.
const CONTACT_ROUNDS: usize = 3;

/// A root frame in f64: origin (m, world) and rotation from root-local to world.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Root {
    /// Root position, m.
    pub origin: V3,
    /// Rotation from root-local to world.
    pub rotation: UnitQuaternion<f64>,
}

impl Root {
    /// `frame` in f64.
    pub fn of(frame: &RootFrame) -> Self {
        Self {
            origin: frame.origin.cast(),
            rotation: frame.rotation.cast(),
        }
    }

    /// A root-local point (m) in world space.
    pub fn to_world(&self, local: &V3) -> V3 {
        self.origin + self.rotation * local
    }
}

/// Rest data of one strand of the rod model (f64).
#[derive(Debug, Clone)]
pub struct RodStrand {
    rest_local: Vec<V3>,
    rest_length: Vec<f64>,
    voronoi: Vec<f64>,
    bend: Vec<NodeRest>,
    twist: Vec<f64>,
    rest_theta: Vec<f64>,
    ghost_t: V3,
    ghost_u: V3,
    inv_mass: Vec<f64>,
    radius: Vec<f32>,
}

/// Positions (m) and velocities (m/s) of one strand's nodes, world, f64, the twist of its
/// segments and what contact detection remembers of them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RodState {
    /// Node positions, m.
    pub x: Vec<V3>,
    /// Node velocities, m/s.
    pub v: Vec<V3>,
    /// Twist angle per segment (rad, against its reference frame) at the last substep's start:
    /// the next relaxation starts from it (empty: from the rest twist).
    pub theta: Vec<f64>,
    /// Clearance per node and collider (see [`Clearance`]); empty until contacts are detected.
    pub clearance: Vec<Clearance>,
}

/// Reusable buffers of a substep.
#[derive(Debug, Clone, Default)]
pub struct Workspace {
    /// Frames of the current shape.
    pub frames: EdgeFrames,
    /// Twist per segment.
    pub twist: Twist,
    /// Elastic forces per node, N (of the last [`RodStrand::energies`]).
    pub force: Vec<V3>,
    x_old: Vec<V3>,
    contacts: Vec<Contact>,
    project: project::Scratch,
}

/// Everything a substep needs besides the strand and its state.
#[derive(Debug, Clone, Copy)]
pub struct Substep<'a> {
    /// Substep length, s.
    pub dt: f64,
    /// Gravitational acceleration, m/s².
    pub gravity: V3,
    /// Air drag, 1/s (velocities decay as exp(−rate·t)).
    pub air_drag: f64,
    /// Stiffness of the cross-section.
    pub stiffness: &'a Stiffness,
    /// Root frame at the substep's start.
    pub root_start: Root,
    /// Root frame at the substep's end.
    pub root_end: Root,
    /// Projection iteration limit.
    pub max_iterations: u32,
    /// Projection tolerance (relative strain).
    pub tolerance: f64,
    /// Colliders and the fraction of the frame at the substep's end they are posed at.
    pub colliders: Option<(&'a Colliders, f32)>,
    /// Extra forces per node, N (tests apply moments with them), or none.
    pub external: Option<&'a [V3]>,
    /// Twisting moments about each segment's axis, N·m (tests twist the tip with them), or none.
    pub torque: Option<&'a [f64]>,
}

/// What one substep did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SubstepOutcome {
    /// The last projection of the substep.
    pub projection: Projection,
    /// Projections run (1 + contact rounds that found new nodes).
    pub projections: u32,
    /// Iterations of all the substep's projections.
    pub iterations: u32,
    /// Contact constraints in force at the end.
    pub contacts: usize,
    /// The twist's relaxation at the substep's start.
    pub twist: Relaxation,
}

impl RodStrand {
    /// Rest data of a strand with rest shape `rest_local` (root-local, m), inverse masses
    /// (1/kg, 0 = kinematic) and radii (m). The rest twist and curvature are those of the rest
    /// shape with its major axes along its bending axes. Returns the index of a zero-length
    /// segment as the error.
    pub fn new(
        rest_local: &[Vector3<f32>],
        inv_mass: &[f32],
        radius: &[f32],
        stiffness: &Stiffness,
    ) -> Result<Self, usize> {
        let x: Vec<V3> = rest_local.iter().map(|p| p.cast()).collect();
        let n = x.len() - 1;
        let rest_length: Vec<f64> = x.windows(2).map(|w| (w[1] - w[0]).norm()).collect();
        if let Some(j) = rest_length
            .iter()
            .position(|&l| !(l > 0.0 && l.is_finite()))
        {
            return Err(j);
        }
        let ghost_t = (x[1] - x[0]) / rest_length[0];
        // As crate::frames: the root frame's x axis carried from its normal (z) to segment 0.
        let mut ghost_u = transport(&V3::x(), &V3::z(), &ghost_t);
        ghost_u -= ghost_t * ghost_u.dot(&ghost_t);
        ghost_u = if ghost_u.norm() > 1e-9 {
            ghost_u.normalize()
        } else {
            super::frames::perpendicular(&ghost_t)
        };
        let voronoi: Vec<f64> = (0..n)
            .map(|i| {
                if i == 0 {
                    0.5 * rest_length[0]
                } else {
                    0.5 * (rest_length[i - 1] + rest_length[i])
                }
            })
            .collect();
        let mut strand = Self {
            rest_local: x,
            rest_length,
            voronoi,
            bend: vec![NodeRest::default(); n],
            twist: vec![0.0; n],
            rest_theta: Vec::with_capacity(n),
            ghost_t,
            ghost_u,
            inv_mass: inv_mass.iter().map(|&w| w as f64).collect(),
            radius: radius.to_vec(),
        };
        // The rest shape's material frame: the reference frame for a round section, the major
        // axes on the rest bending axes for an elliptical one (see twist::rest_angles).
        let ghost = strand.ghost(&Root {
            origin: V3::zeros(),
            rotation: UnitQuaternion::identity(),
        });
        let mut frames = EdgeFrames::default();
        frames.update(&strand.rest_local, &ghost);
        twist::rest_angles(&frames, &strand.voronoi, stiffness, &mut strand.rest_theta);
        let mut prev = 0.0;
        for (twist, &th) in strand.twist.iter_mut().zip(&strand.rest_theta) {
            *twist = th - prev;
            prev = th;
        }
        let axes: Vec<(V3, V3)> = (0..n)
            .map(|j| material(&frames.u[j], &frames.v[j], strand.rest_theta[j]))
            .collect();
        for i in 0..n {
            let [(a1, a2), (b1, b2)] = forces::node_axes(i, &axes, &ghost);
            let kb = frames.kb[i];
            strand.bend[i] = NodeRest {
                a: [kb.dot(&a1), kb.dot(&a2)],
                b: [kb.dot(&b1), kb.dot(&b2)],
            };
        }
        Ok(strand)
    }

    /// Number of nodes.
    pub fn nodes(&self) -> usize {
        self.rest_local.len()
    }

    /// Segment rest lengths, m.
    pub fn rest_lengths(&self) -> &[f64] {
        &self.rest_length
    }

    /// The ghost edge for the root frame `root`.
    pub fn ghost(&self, root: &Root) -> Ghost {
        Ghost {
            t: root.rotation * self.ghost_t,
            u: root.rotation * self.ghost_u,
            length: self.rest_length[0],
        }
    }

    fn twist_rest(&self) -> TwistRest<'_> {
        TwistRest {
            bend: &self.bend,
            twist: &self.twist,
            voronoi: &self.voronoi,
        }
    }

    /// The rest shape placed by `root`, at rest.
    pub fn rest_state(&self, root: &Root) -> RodState {
        RodState {
            x: self.rest_local.iter().map(|p| root.to_world(p)).collect(),
            v: vec![V3::zeros(); self.nodes()],
            theta: self.rest_theta.clone(),
            clearance: Vec::new(),
        }
    }

    /// The rest shape's twist angle per segment, rad, against its reference frame.
    pub fn rest_twist(&self) -> &[f64] {
        &self.rest_theta
    }

    /// Updates the frames of `ws` for positions `x` and root `root`, and relaxes the twist of
    /// `ws` (starting from `ws.twist.theta`, or from the rest twist if its length is not the
    /// segment count) to the minimum of the elastic energy, with twisting moments `torque`
    /// (N·m per segment, or empty).
    pub fn update_twist(
        &self,
        x: &[V3],
        root: &Root,
        stiffness: &Stiffness,
        torque: &[f64],
        ws: &mut Workspace,
    ) -> Relaxation {
        let ghost = self.ghost(root);
        ws.frames.update(x, &ghost);
        if ws.twist.theta.len() != self.rest_theta.len() {
            ws.twist.theta.clone_from(&self.rest_theta);
        }
        twist::relax(
            &ws.frames,
            &self.twist_rest(),
            stiffness,
            torque,
            &mut ws.twist,
        )
    }

    /// Bending energy (J) and twist energy (J) of `x` with the frames and twist of `ws` (call
    /// [`RodStrand::update_twist`] first), and their forces (N, `−dE/dx` at that twist) into
    /// `ws`'s force buffer ([`Workspace::force`]).
    pub fn energies(
        &self,
        x: &[V3],
        root: &Root,
        stiffness: &Stiffness,
        ws: &mut Workspace,
    ) -> (f64, f64) {
        let ghost = self.ghost(root);
        ws.force.clear();
        ws.force.resize(x.len(), V3::zeros());
        let bend = forces::bending(
            x,
            &ws.frames,
            &ghost,
            &ws.twist.axes,
            &self.bend,
            &self.voronoi,
            stiffness,
            &mut ws.force,
        );
        let twist = forces::twisting(
            &ws.frames,
            &ws.twist.theta,
            &self.twist,
            &self.voronoi,
            stiffness,
            &mut ws.force,
        );
        (bend, twist)
    }

    /// Largest bending over the minor axis relative to the largest bending, over the interior
    /// nodes, for the twist of `ws` (see [`twist::minor_axis_bending`]).
    /// `from` is the first node counted (nodes near the clamped root bend partly over the minor
    /// axis where the twist cannot yet turn).
    pub fn minor_axis_bending(&self, ws: &Workspace, from: usize) -> f64 {
        twist::minor_axis_bending(&ws.frames, &ws.twist, from)
    }

    /// The material axes `(m1, m2)` of segment `j` for the twist of `ws`.
    pub fn material_axes(&self, j: usize, ws: &Workspace) -> (V3, V3) {
        ws.twist.axes[j]
    }

    /// Advances `state` by one substep (see the module docs).
    pub fn substep(
        &self,
        state: &mut RodState,
        input: &Substep,
        ws: &mut Workspace,
    ) -> SubstepOutcome {
        let n = self.nodes();
        let dt = input.dt;
        // The relaxation starts from the state's twist (update_twist falls back on the rest
        // twist while the state has none).
        ws.twist.theta.clone_from(&state.theta);
        let relaxation = self.update_twist(
            &state.x,
            &input.root_start,
            input.stiffness,
            input.torque.unwrap_or(&[]),
            ws,
        );
        state.theta.clone_from(&ws.twist.theta);
        self.energies(&state.x, &input.root_start, input.stiffness, ws);
        if let Some(external) = input.external {
            for (f, e) in ws.force.iter_mut().zip(external) {
                *f += e;
            }
        }
        let decay = (-input.air_drag * dt).exp();
        ws.x_old.clear();
        ws.x_old.extend_from_slice(&state.x);
        for i in 0..n {
            let w = self.inv_mass[i];
            if w == 0.0 {
                let target = input.root_end.to_world(&self.rest_local[i]);
                state.x[i] = target;
            } else {
                let v = (state.v[i] + (ws.force[i] * w + input.gravity) * dt) * decay;
                state.x[i] += v * dt;
            }
        }
        ws.contacts.clear();
        let mut outcome = SubstepOutcome {
            twist: relaxation,
            ..Default::default()
        };
        for round in 0..CONTACT_ROUNDS {
            let added = match input.colliders {
                Some((colliders, s)) => penetrating(
                    colliders,
                    s,
                    &state.x,
                    &self.radius,
                    &self.inv_mass,
                    &mut state.clearance,
                    &mut ws.contacts,
                ),
                None => 0,
            };
            if round > 0 && added == 0 {
                break;
            }
            let p = project::project(
                &mut state.x,
                &self.inv_mass,
                &self.rest_length,
                &ws.contacts,
                input.max_iterations,
                input.tolerance,
                &mut ws.project,
            );
            outcome.projection = p;
            outcome.projections += 1;
            outcome.iterations += p.iterations;
            if input.colliders.is_none() {
                break;
            }
        }
        outcome.contacts = ws.contacts.len();
        for i in 0..n {
            state.v[i] = (state.x[i] - ws.x_old[i]) / dt;
        }
        outcome
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Elastic energy (J) of `x` with the twist re-minimised from `theta`.
    fn relaxed_energy(
        rod: &RodStrand,
        x: &[V3],
        root: &Root,
        s: &Stiffness,
        theta: &[f64],
        ws: &mut Workspace,
    ) -> f64 {
        ws.twist.theta = theta.to_vec();
        let r = rod.update_twist(x, root, s, &[], ws);
        assert!(r.converged, "{r:?}");
        let (bend, twist) = rod.energies(x, root, s, ws);
        bend + twist
    }

    #[test]
    fn elastic_force_is_the_gradient_of_the_energy_with_the_twist_re_minimised() {
        // A curled rest shape (a helix round root-local z), bent now out of its curl's plane
        // and twisted: bending and twist both loaded. The force must be −dE/dx of the energy
        // whose twist is minimised again at every perturbed shape, for an elliptical and a
        // round section.
        let n = 9;
        let rest: Vec<Vector3<f32>> = (0..=n)
            .map(|i| {
                let a = 0.6 * i as f64;
                Vector3::new(
                    (0.03 * (1.0 - a.cos())) as f32,
                    (0.03 * a.sin()) as f32,
                    (0.012 * i as f64) as f32,
                )
            })
            .collect();
        let root = Root {
            origin: V3::new(0.1, -0.2, 0.3),
            rotation: UnitQuaternion::from_euler_angles(0.3, -0.5, 0.9),
        };
        for s in [
            Stiffness {
                major: 1e-4,
                minor: 2.5e-4,
                twist: 0.7e-4,
            },
            Stiffness::isotropic(1e-4, 0.77e-4),
        ] {
            let rod = RodStrand::new(&rest, &vec![1.0; n + 1], &vec![1e-3; n + 1], &s).unwrap();
            let mut x = rod.rest_state(&root).x;
            for (i, p) in x.iter_mut().enumerate().skip(1) {
                let f = i as f64;
                *p += V3::new(
                    0.004 * (1.3 * f).sin(),
                    -0.006 * (0.7 * f).cos(),
                    0.005 * f.sqrt(),
                ) * (f / n as f64);
            }
            let mut ws = Workspace::default();
            let theta0 = rod.rest_twist().to_vec();
            let e0 = relaxed_energy(&rod, &x, &root, &s, &theta0, &mut ws);
            let theta = ws.twist.theta.clone();
            let (bend, twist) = rod.energies(&x, &root, &s, &mut ws);
            let force = ws.force.clone();
            assert!((bend + twist - e0).abs() < 1e-15);
            assert!(
                twist > 0.01 * bend,
                "twist {twist} J, bend {bend} J: the test must load twist"
            );
            let scale = force.iter().skip(1).fold(0.0f64, |a, f| a.max(f.norm()));
            let h = 1e-7;
            for k in 1..=n {
                for c in 0..3 {
                    let (mut xp, mut xm) = (x.clone(), x.clone());
                    xp[k][c] += h;
                    xm[k][c] -= h;
                    let fd = -(relaxed_energy(&rod, &xp, &root, &s, &theta, &mut ws)
                        - relaxed_energy(&rod, &xm, &root, &s, &theta, &mut ws))
                        / (2.0 * h);
                    assert!(
                        (fd - force[k][c]).abs() < 1e-6 * scale,
                        "{s:?} node {k} axis {c}: finite difference {fd}, force {} (largest {scale})",
                        force[k][c]
                    );
                }
            }
        }
    }
}
