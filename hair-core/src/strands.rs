//! The simulation level's data: a [`StrandSet`] holds every strand structure-of-arrays and
//! strand-contiguous (an offsets array plus flat per-point and per-segment arrays), so one strand's
//! points sit together in memory and its whole substep loop stays in L1 cache.
//!
//! Per point: position and velocity (world, m and m/s), rest position in the strand's root frame
//! (m), mass (kg; 0 inverse mass = kinematic), radius (m), goal weight (0–1). Per segment: rest
//! length (m) and the rest direction expressed in the previous segment's frame (see
//! [`crate::frames`]). Per strand: its [`Anchor`].

use nalgebra::{Isometry3, Vector3};

use crate::error::{HairError, Result};
use crate::frames::{self, RestDirection};
use crate::mesh::{MeshSample, RootFrame, TriMesh};

/// What a strand root is attached to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Anchor {
    /// A point on the scalp mesh; its frame follows the mesh's deformation.
    Surface(MeshSample),
    /// A fixed frame in the scalp's body space, carried by the body's rigid transform (used for
    /// strands given as explicit point lists).
    Body(RootFrame),
}

/// Where roots come from at one instant: the scalp mesh at its current vertex positions and the
/// body's rigid transform. A host sets both every frame.
#[derive(Debug, Clone)]
pub struct Scalp {
    /// The scalp mesh at its current (world) vertex positions, if strands are rooted on a surface.
    pub mesh: Option<TriMesh>,
    /// Rigid transform of the body space, carrying [`Anchor::Body`] frames.
    pub body: Isometry3<f32>,
}

impl Scalp {
    /// A scalp with no mesh and the identity transform (explicit strands in world space).
    pub fn fixed() -> Self {
        Self {
            mesh: None,
            body: Isometry3::identity(),
        }
    }

    /// Root frame of `anchor` at this instant. Callers validate anchors first
    /// ([`StrandSet::validate_anchors`]); a surface anchor without a mesh falls back to the body.
    pub fn root_frame(&self, anchor: &Anchor) -> RootFrame {
        match (anchor, &self.mesh) {
            (Anchor::Surface(s), Some(mesh)) => mesh.evaluate(s),
            (Anchor::Surface(_), None) => RootFrame::at(self.body.translation.vector),
            (Anchor::Body(f), _) => f.moved_by(&self.body),
        }
    }
}

/// Description of one strand to add to a [`StrandSet`].
#[derive(Debug, Clone, PartialEq)]
pub struct StrandInput {
    /// Where the root is attached.
    pub anchor: Anchor,
    /// Rest shape in root-local coordinates (m); point 0 is the root, normally the origin.
    pub rest: Vec<Vector3<f32>>,
    /// Mass of each point, kg (ignored for pinned points).
    pub mass: Vec<f32>,
    /// Collision and render radius of each point, m.
    pub radius: Vec<f32>,
    /// Goal weight of each point in [0, 1]: how strongly it is pulled to its animated rest position.
    pub goal_weight: Vec<f32>,
    /// Points held kinematically at their animated rest position. Point 0 is always pinned.
    pub pinned: Vec<bool>,
}

impl StrandInput {
    /// A strand with masses lumped from a uniform linear density (kg/m: each point gets half of
    /// each adjacent segment), a constant radius (m) and goal weights linear from root to tip.
    pub fn uniform(
        anchor: Anchor,
        rest: Vec<Vector3<f32>>,
        mass_per_length: f32,
        radius: f32,
        goal_root: f32,
        goal_tip: f32,
    ) -> Self {
        let n = rest.len();
        let mut mass = vec![0.0; n];
        for i in 1..n {
            let half = 0.5 * mass_per_length * (rest[i] - rest[i - 1]).norm();
            mass[i - 1] += half;
            mass[i] += half;
        }
        let goal_weight = (0..n)
            .map(|i| {
                let s = if n > 1 {
                    i as f32 / (n - 1) as f32
                } else {
                    0.0
                };
                goal_root + (goal_tip - goal_root) * s
            })
            .collect();
        let mut pinned = vec![false; n];
        if let Some(p) = pinned.first_mut() {
            *p = true;
        }
        Self {
            anchor,
            rest,
            mass,
            radius: vec![radius; n],
            goal_weight,
            pinned,
        }
    }
}

/// All strands of a hair system, structure-of-arrays and strand-contiguous.
#[derive(Debug, Clone, Default)]
pub struct StrandSet {
    offsets: Vec<u32>,
    /// Point positions, m, world space.
    pub positions: Vec<Vector3<f32>>,
    /// Point velocities, m/s, world space.
    pub velocities: Vec<Vector3<f32>>,
    rest_local: Vec<Vector3<f32>>,
    mass: Vec<f32>,
    inv_mass: Vec<f32>,
    radius: Vec<f32>,
    goal_weight: Vec<f32>,
    rest_length: Vec<f32>,
    bend_rest: Vec<RestDirection>,
    anchors: Vec<Anchor>,
}

impl StrandSet {
    /// An empty set.
    pub fn new() -> Self {
        Self {
            offsets: vec![0],
            ..Default::default()
        }
    }

    /// Validates and appends a strand. Positions start at the rest shape placed by the identity
    /// frame; call [`StrandSet::reset_to_rest`] once the scalp is known.
    pub fn push(&mut self, input: StrandInput) -> Result<()> {
        let strand = self.len();
        let err = |message: String| HairError::Strand { strand, message };
        let n = input.rest.len();
        if n < 2 {
            return Err(err(format!("has {n} point(s); a strand needs at least 2")));
        }
        for (name, len) in [
            ("mass", input.mass.len()),
            ("radius", input.radius.len()),
            ("goal_weight", input.goal_weight.len()),
            ("pinned", input.pinned.len()),
        ] {
            if len != n {
                return Err(err(format!("{len} values of `{name}` for {n} points")));
            }
        }
        if let Some(i) = input
            .rest
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(err(format!("point {i} has a non-finite coordinate")));
        }
        // Geometry before masses: a duplicate point also leaves a zero lumped mass behind it.
        let lengths: Vec<f32> = input
            .rest
            .windows(2)
            .map(|w| (w[1] - w[0]).norm())
            .collect();
        let scale = lengths.iter().sum::<f32>();
        if let Some(j) = lengths
            .iter()
            .position(|&l| l.is_nan() || l <= 1e-6 * scale.max(1e-6) || l < 1e-9)
        {
            return Err(err(format!(
                "segment {j} (points {j}–{}) has zero length; merge or remove duplicate points",
                j + 1
            )));
        }
        for i in 0..n {
            let pinned = i == 0 || input.pinned[i];
            let valid_mass = input.mass[i].is_finite() && input.mass[i] > 0.0;
            if !pinned && !valid_mass {
                return Err(err(format!(
                    "point {i} has mass {}; free points need a finite mass > 0 kg",
                    input.mass[i]
                )));
            }
            if !(input.radius[i].is_finite() && input.radius[i] >= 0.0) {
                return Err(err(format!(
                    "point {i} has radius {}; use a finite value ≥ 0 m",
                    input.radius[i]
                )));
            }
            let w = input.goal_weight[i];
            if !(w.is_finite() && (0.0..=1.0).contains(&w)) {
                return Err(err(format!(
                    "point {i} has goal weight {w}; use a value in [0, 1]"
                )));
            }
        }
        self.bend_rest.extend(frames::rest_directions(&input.rest));
        self.rest_length.extend(lengths);
        for i in 0..n {
            let pinned = i == 0 || input.pinned[i];
            self.inv_mass
                .push(if pinned { 0.0 } else { 1.0 / input.mass[i] });
            self.mass.push(if pinned { 0.0 } else { input.mass[i] });
        }
        self.positions.extend(input.rest.iter().copied());
        self.velocities
            .extend(std::iter::repeat_n(Vector3::zeros(), n));
        self.rest_local.extend(input.rest);
        self.radius.extend(input.radius);
        self.goal_weight.extend(input.goal_weight);
        self.anchors.push(input.anchor);
        self.offsets.push(self.positions.len() as u32);
        Ok(())
    }

    /// Multiplies strand `s`'s free points' masses by `mass` and every point's radius by
    /// `radius` (per-region material). Both factors must be finite, the mass factor
    /// > 0 and the radius factor ≥ 0; kinematic points keep mass 0.
    pub fn scale_strand(&mut self, s: usize, mass: f32, radius: f32) -> Result<()> {
        if s >= self.len() {
            return Err(HairError::Strand {
                strand: s,
                message: format!("does not exist: the set has {} strands", self.len()),
            });
        }
        if !(mass.is_finite() && mass > 0.0 && radius.is_finite() && radius >= 0.0) {
            return Err(HairError::Parameter {
                name: format!("strand {s} mass and radius factors"),
                value: format!("{mass}, {radius}"),
                fix: "give a finite mass factor > 0 and radius factor ≥ 0".into(),
            });
        }
        for i in self.points(s) {
            if self.inv_mass[i] > 0.0 {
                self.mass[i] *= mass;
                self.inv_mass[i] = 1.0 / self.mass[i];
            }
            self.radius[i] *= radius;
        }
        Ok(())
    }

    /// Number of strands.
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// True when the set holds no strand.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Total number of points.
    pub fn point_count(&self) -> usize {
        self.positions.len()
    }

    /// Point offsets: strand `s` owns points `offsets[s]..offsets[s + 1]`.
    pub fn offsets(&self) -> &[u32] {
        &self.offsets
    }

    /// Range of point indices of strand `s`.
    pub fn points(&self, s: usize) -> std::ops::Range<usize> {
        self.offsets[s] as usize..self.offsets[s + 1] as usize
    }

    /// Range of segment indices of strand `s` (segment `j` joins points `j` and `j + 1` of it).
    pub fn segments(&self, s: usize) -> std::ops::Range<usize> {
        let p = self.points(s);
        p.start - s..p.end - s - 1
    }

    /// Anchors, one per strand.
    pub fn anchors(&self) -> &[Anchor] {
        &self.anchors
    }

    /// Rest positions in each strand's root frame, m.
    pub fn rest_local(&self) -> &[Vector3<f32>] {
        &self.rest_local
    }

    /// Mutable rest positions in each strand's root frame (m), for animated rest shapes (seed
    /// 001: animated guides define the rest positions). Goal springs and pinned points follow
    /// them from the next step; rest lengths are not changed.
    pub fn rest_local_mut(&mut self) -> &mut [Vector3<f32>] {
        &mut self.rest_local
    }

    /// Point masses, kg (0 for pinned points).
    pub fn masses(&self) -> &[f32] {
        &self.mass
    }

    /// Inverse point masses, 1/kg (0 for pinned points).
    pub fn inverse_masses(&self) -> &[f32] {
        &self.inv_mass
    }

    /// Point radii, m.
    pub fn radii(&self) -> &[f32] {
        &self.radius
    }

    /// Goal weights in [0, 1].
    pub fn goal_weights(&self) -> &[f32] {
        &self.goal_weight
    }

    /// Segment rest lengths, m (indexed by [`StrandSet::segments`]).
    pub fn rest_lengths(&self) -> &[f32] {
        &self.rest_length
    }

    /// Rest direction of each segment in its predecessor's frame (see [`crate::frames`]).
    pub fn bend_rest(&self) -> &[RestDirection] {
        &self.bend_rest
    }

    /// Mutable rest directions, for rest-state solvers such as sag-free initialisation
    /// ([`crate::integrate::sag_free`]). Only a rest direction's direction matters (it describes
    /// the rest curvature, [`crate::integrate::curvature`]); its length is ignored.
    pub fn bend_rest_mut(&mut self) -> &mut [RestDirection] {
        &mut self.bend_rest
    }

    /// Mutable segment rest lengths (m, > 0), for rest-state solvers such as sag-free
    /// initialisation, which pre-stretches segments to carry the weight below them.
    pub fn rest_lengths_mut(&mut self) -> &mut [f32] {
        &mut self.rest_length
    }

    /// Checks every anchor against the scalp (mesh present, sample on a valid triangle).
    pub fn validate_anchors(&self, scalp: &Scalp) -> Result<()> {
        for (strand, anchor) in self.anchors.iter().enumerate() {
            if let Anchor::Surface(sample) = anchor {
                let Some(mesh) = &scalp.mesh else {
                    return Err(HairError::Strand {
                        strand,
                        message: "is rooted on the scalp surface but no scalp mesh was given"
                            .into(),
                    });
                };
                sample.validate(mesh).map_err(|e| HairError::Strand {
                    strand,
                    message: e.to_string(),
                })?;
            }
        }
        Ok(())
    }

    /// Root frames of every strand on `scalp`.
    pub fn root_frames(&self, scalp: &Scalp) -> Vec<RootFrame> {
        self.anchors.iter().map(|a| scalp.root_frame(a)).collect()
    }

    /// Places every strand at its rest shape on `scalp`, at rest (zero velocity).
    pub fn reset_to_rest(&mut self, scalp: &Scalp) {
        let roots = self.root_frames(scalp);
        for (s, root) in roots.iter().enumerate() {
            for i in self.points(s) {
                self.positions[i] = root.to_world(&self.rest_local[i]);
                self.velocities[i] = Vector3::zeros();
            }
        }
    }

    /// Largest relative segment elongation `len/rest − 1` over all segments (0 if none is longer
    /// than at rest).
    pub fn max_stretch(&self) -> f32 {
        (0..self.len())
            .map(|s| {
                let p = self.points(s);
                let seg = self.segments(s);
                self.positions[p]
                    .windows(2)
                    .zip(&self.rest_length[seg])
                    .map(|(w, l)| (w[1] - w[0]).norm() / l - 1.0)
                    .fold(0.0f32, f32::max)
            })
            .fold(0.0, f32::max)
    }

    /// Splits the set into its mutable state (positions, velocities) and its read-only data, so the
    /// solver can hand disjoint pieces to threads.
    pub(crate) fn split_for_solver(
        &mut self,
    ) -> (&mut [Vector3<f32>], &mut [Vector3<f32>], SolverData<'_>) {
        let data = SolverData {
            offsets: &self.offsets,
            rest_local: &self.rest_local,
            mass: &self.mass,
            inv_mass: &self.inv_mass,
            goal_weight: &self.goal_weight,
            rest_length: &self.rest_length,
            bend_rest: &self.bend_rest,
            radii: &self.radius,
        };
        (&mut self.positions, &mut self.velocities, data)
    }

    /// Length of strand `s` at rest, m.
    pub fn rest_strand_length(&self, s: usize) -> f32 {
        self.rest_length[self.segments(s)].iter().sum()
    }
}

/// Read-only arrays of a [`StrandSet`] the solver needs while positions and velocities are
/// borrowed mutably.
#[derive(Clone, Copy)]
pub(crate) struct SolverData<'a> {
    pub offsets: &'a [u32],
    pub rest_local: &'a [Vector3<f32>],
    pub mass: &'a [f32],
    pub inv_mass: &'a [f32],
    pub goal_weight: &'a [f32],
    pub rest_length: &'a [f32],
    pub bend_rest: &'a [RestDirection],
    /// Collision radius per point, m.
    pub radii: &'a [f32],
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(n: usize) -> Vec<Vector3<f32>> {
        (0..n)
            .map(|i| Vector3::new(0.0, 0.0, 0.1 * i as f32))
            .collect()
    }

    #[test]
    fn offsets_and_segments_are_contiguous() {
        let mut set = StrandSet::new();
        for n in [3, 5] {
            let input = StrandInput::uniform(
                Anchor::Body(RootFrame::at(Vector3::zeros())),
                line(n),
                1.0,
                0.01,
                0.0,
                0.0,
            );
            set.push(input).unwrap();
        }
        assert_eq!(set.offsets(), &[0, 3, 8]);
        assert_eq!(set.segments(0), 0..2);
        assert_eq!(set.segments(1), 2..6);
        assert_eq!(set.rest_lengths().len(), 6);
        // Lumped masses: half a segment at the ends, a whole one inside; root pinned.
        assert_eq!(set.masses()[0], 0.0);
        assert!((set.masses()[1] - 0.1).abs() < 1e-6);
        assert!((set.masses()[2] - 0.05).abs() < 1e-6);
    }

    #[test]
    fn zero_length_segment_is_named() {
        let mut rest = line(4);
        rest[2] = rest[1];
        let input = StrandInput::uniform(
            Anchor::Body(RootFrame::at(Vector3::zeros())),
            rest,
            1.0,
            0.01,
            0.0,
            0.0,
        );
        let err = StrandSet::new().push(input).unwrap_err();
        assert!(err.to_string().contains("segment 1"), "{err}");
    }
}
