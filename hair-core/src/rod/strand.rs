//! One strand of the rod model: its rest data ([`RodStrand`]) and one substep of it
//! ([`RodStrand::substep`]): quasistatic twist, explicit step of the elastic forces and gravity,
//! projection onto inextensibility, root coupling and head contacts, velocities from the
//! projected positions.

use nalgebra::{UnitQuaternion, Vector3};

use super::collide::{penetrating, Clearance};
use super::forces::{self, NodeRest};
use super::frames::{transport, EdgeFrames, Ghost, V3};
use super::project::{self, Contact, Projection};
use super::stiffness::Stiffness;
use super::twist::{self, Twist, TwistRest};
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
    ghost_t: V3,
    ghost_u: V3,
    inv_mass: Vec<f64>,
    radius: Vec<f32>,
}

/// Positions (m) and velocities (m/s) of one strand's nodes, world, f64, and what contact
/// detection remembers of them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RodState {
    /// Node positions, m.
    pub x: Vec<V3>,
    /// Node velocities, m/s.
    pub v: Vec<V3>,
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
    force: Vec<V3>,
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
            ghost_t,
            ghost_u,
            inv_mass: inv_mass.iter().map(|&w| w as f64).collect(),
            radius: radius.to_vec(),
        };
        // Rest twist: the quasistatic twist of the rest shape against a straight, untwisted rest.
        let ghost = strand.ghost(&Root {
            origin: V3::zeros(),
            rotation: UnitQuaternion::identity(),
        });
        let mut frames = EdgeFrames::default();
        frames.update(&strand.rest_local, &ghost);
        let mut rest_twist = Twist::default();
        twist::quasistatic(&frames, &strand.twist_rest(), stiffness, &mut rest_twist);
        let mut prev = 0.0;
        for (twist, &th) in strand.twist.iter_mut().zip(&rest_twist.theta) {
            *twist = th - prev;
            prev = th;
        }
        for i in 0..n {
            let [(a1, a2), (b1, b2)] = forces::node_axes(i, &rest_twist.axes);
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
            clearance: Vec::new(),
        }
    }

    /// Updates the frames and the quasistatic twist of `ws` for positions `x` and root `root`.
    pub fn update_twist(&self, x: &[V3], root: &Root, stiffness: &Stiffness, ws: &mut Workspace) {
        let ghost = self.ghost(root);
        ws.frames.update(x, &ghost);
        twist::quasistatic(&ws.frames, &self.twist_rest(), stiffness, &mut ws.twist);
    }

    /// Bending energy (J) and twist energy (J) of `x` with the twist of `ws` (call
    /// [`RodStrand::update_twist`] first).
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
        (
            bend,
            twist::energy(&ws.twist.theta, &self.twist_rest(), stiffness),
        )
    }

    /// Largest bending over the minor axis relative to the largest bending, over the interior
    /// nodes, for the twist of `ws` (see [`twist::minor_axis_bending`]).
    pub fn minor_axis_bending(&self, ws: &Workspace) -> f64 {
        twist::minor_axis_bending(&ws.frames, &ws.twist)
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
        self.update_twist(&state.x, &input.root_start, input.stiffness, ws);
        let ghost = self.ghost(&input.root_start);
        ws.force.clear();
        ws.force.resize(n, V3::zeros());
        forces::bending(
            &state.x,
            &ws.frames,
            &ghost,
            &ws.twist.axes,
            &self.bend,
            &self.voronoi,
            input.stiffness,
            &mut ws.force,
        );
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
        let mut outcome = SubstepOutcome::default();
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
