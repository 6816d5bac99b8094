//! Laying hair over the scalp: a groom that is combed (and optionally parted), leaves the scalp at
//! a lift angle, follows the head at a layer height and falls under gravity past it — the shape a
//! brushed head of hair has, in place of straight strands along the surface normals.
//!
//! # How a strand is laid
//!
//! Each strand keeps its root, point count and every segment length; only directions change. It
//! is walked from the root, one segment at a time, in world space:
//!
//! 1. **Where it wants to go.** At the scalp point nearest the segment's start (parry's exact
//!    projection onto the triangle mesh, smooth normal `n` there), the *flow* is the comb
//!    direction plus, with a part, the part-plane normal pointing away from the part on the
//!    root's side; its tangential part (`flow − (flow·n) n`) is scaled by the scalp's *support*
//!    `max(0, n·up)` — a scalp facing up carries combed hair, one facing sideways or down lets
//!    it fall — and by [`StyleOptions::comb_weight`], and the gravity direction is added. On top
//!    of the head the flow wins (gravity points into the scalp there); where the head turns
//!    away, gravity wins and the hair falls.
//! 2. **How fast it may turn.** The segment direction turns towards the target by at most
//!    [`StyleOptions::max_curvature`] × segment length (radians): the strand is a smooth curve of
//!    bounded curvature, never a fold at one point.
//! 3. **How high it lies.** Each strand has a layer height `h = clearance + layer · u` (`u`
//!    uniform in [0, 1) from the seed), reached by rising at the lift angle from the root: the
//!    allowed height after an arc length `a` is `min(h, a · sin(lift))`. A point that would lie
//!    lower than that above the scalp (signed along the normal at its nearest scalp point) is
//!    lifted to it, and the segment is re-aimed through the lifted point at its own length.
//!
//! The first segment leaves the root at the lift angle from the tangent plane, towards the flow.
//! With `clearance` at least the strand radius plus the collider thickness, a laid groom starts
//! clear of the scalp collider; layers make the volume that hair–hair interaction keeps.
//!
//! A scalp whose normals point inwards lays hair inside it: the smooth normals of
//! [`TriMesh::evaluate`] must point out of the head (they do for the built-in head, the UV sphere
//! and meshes exported with outward normals).

use hair_core::{Anchor, StrandInput, TriMesh};
use hair_par::prelude::*;
use nalgebra::{Unit, UnitQuaternion, Vector3};
use parry3d::math::Vector;
use parry3d::query::PointProjection;
use parry3d::query::{PointQueryWithLocation, Ray, RayCast};
use parry3d::shape::TrianglePointLocation;

use crate::error::{parameter, GroomError};
use crate::interpolate::SimHair;
use crate::rng::{self, Purpose};
use crate::snap::Guide;
use hair_core::MeshSample;

/// A part: hair on each side of a plane is combed away from it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Part {
    /// Normal of the part plane (world, any non-zero length).
    pub normal: Vector3<f32>,
    /// A point of the part plane, m (world).
    pub point: Vector3<f32>,
    /// How strongly hair is combed away from the part, relative to the comb direction (≥ 0).
    pub weight: f32,
}

/// How hair is laid over the scalp. Angles in degrees, lengths in m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StyleOptions {
    /// World direction hair is combed towards on the scalp (any non-zero length; Z up).
    pub comb: Vector3<f32>,
    /// Weight of the combed flow against gravity (≥ 0): 0 lets hair fall straight down the scalp,
    /// larger values keep it in the comb direction further down the sides.
    pub comb_weight: f32,
    /// An optional part.
    pub part: Option<Part>,
    /// Angle at which hair leaves the scalp, from the tangent plane, degrees in (0, 90].
    pub lift_deg: f32,
    /// Least height of the hair above the scalp, m (≥ 0): the strand radius plus the scalp
    /// collider's thickness and a margin keeps a laid groom clear of the collider.
    pub clearance: f32,
    /// Depth of the hair layer above `clearance`, m (≥ 0): strand heights spread uniformly over it.
    pub layer: f32,
    /// Largest curvature of a laid strand, 1/m (> 0): the inverse of its tightest bend radius.
    pub max_curvature: f32,
    /// Gravity direction (any non-zero length), usually −Z.
    pub down: Vector3<f32>,
    /// Seed of the per-strand layer heights.
    pub seed: u64,
}

impl StyleOptions {
    /// Checks every option's range, naming the first one at fault (the scene keys under
    /// `[hair.style]`).
    fn validate(&self) -> Result<(), GroomError> {
        let vector = |name: &str, v: &Vector3<f32>| {
            let n = v.norm();
            if n.is_finite() && n > 0.0 {
                Ok(())
            } else {
                Err(parameter(
                    name,
                    format!("({}, {}, {})", v.x, v.y, v.z),
                    "must be a finite, non-zero vector (world space, Z up)",
                ))
            }
        };
        vector("comb", &self.comb)?;
        vector("down", &self.down)?;
        let non_negative = |name: &str, x: f32, what: &str| {
            if x.is_finite() && x >= 0.0 {
                Ok(())
            } else {
                Err(parameter(name, x, what))
            }
        };
        non_negative(
            "comb_weight",
            self.comb_weight,
            "must be a finite weight ≥ 0",
        )?;
        non_negative("clearance", self.clearance, "must be a finite height ≥ 0 m")?;
        non_negative("layer", self.layer, "must be a finite depth ≥ 0 m")?;
        if !(self.lift_deg > 0.0 && self.lift_deg <= 90.0) {
            return Err(parameter(
                "lift_deg",
                self.lift_deg,
                "must lie in (0, 90] degrees from the scalp's tangent plane",
            ));
        }
        if !(self.max_curvature.is_finite() && self.max_curvature > 0.0) {
            return Err(parameter(
                "max_curvature",
                self.max_curvature,
                "must be a finite curvature > 0 1/m (1 / tightest bend radius)",
            ));
        }
        if let Some(part) = self.part {
            vector("part.normal", &part.normal)?;
            if !part.point.iter().all(|c| c.is_finite()) {
                return Err(parameter(
                    "part.point",
                    format!("({}, {}, {})", part.point.x, part.point.y, part.point.z),
                    "must be a finite point (m)",
                ));
            }
            non_negative("part.weight", part.weight, "must be a finite weight ≥ 0")?;
        }
        Ok(())
    }
}

/// A nearest scalp point, m, the smooth normal there and the normal that tells the side (see
/// [`Surface::nearest_with_face`]).
type Nearest = (Vector3<f32>, Vector3<f32>, Vector3<f32>);

/// The scalp as a searchable surface: nearest point and its smooth normal.
#[derive(Debug, Clone)]
struct Surface {
    mesh: TriMesh,
    query: parry3d::shape::TriMesh,
}

impl Surface {
    fn new(mesh: &TriMesh) -> Result<Self, GroomError> {
        Ok(Self {
            mesh: mesh.clone(),
            query: crate::snap::searchable(mesh)?,
        })
    }

    /// Does the segment from `a` to `b` (m) meet the scalp's surface?
    fn crosses(&self, a: &Vector3<f32>, b: &Vector3<f32>) -> bool {
        let d = b - a;
        let ray = Ray::new(Vector::new(a.x, a.y, a.z), Vector::new(d.x, d.y, d.z));
        self.query.cast_local_ray(&ray, 1.0, false).is_some()
    }

    /// The nearest scalp point to `p` and the smooth normal there.
    fn nearest(&self, p: &Vector3<f32>) -> (Vector3<f32>, Vector3<f32>) {
        let (c, n, _) = self.nearest_with_face(p);
        (c, n)
    }

    /// The nearest scalp point to `p`, the smooth normal there and the normal that tells which
    /// side of the scalp `p` is on (outward for a consistently wound scalp): its triangle's own
    /// unit normal where `p` projects inside the triangle, the smooth normal where it projects
    /// on an edge or a vertex. There one triangle's normal does not tell: beyond a thin flap's
    /// rim (an ear) the triangle the search names can face away from a point outside — its
    /// normal at right angles to the offset or worse — and the point was taken to be inside
    /// and dragged onto the rim (a hook at the tip of 3 of Sintel's sim hairs that came within
    /// 23 mm of her ear). The smooth normal there lies between the faces meeting at the
    /// feature, like the angle-weighted pseudo-normal (Bærentzen and Aanæs 2005) it stands for.
    fn nearest_with_face(&self, p: &Vector3<f32>) -> Nearest {
        let (proj, (triangle, location)) = self
            .query
            .project_local_point_and_get_location(Vector::new(p.x, p.y, p.z), false);
        self.describe(&proj, triangle, &location)
    }

    /// [`Surface::nearest_with_face`] if the scalp comes within `reach` m of `p`, else `None`.
    /// The search skips every part of the tree farther than `reach`, so asking whether a point
    /// a few millimetres off the scalp is clear of a clearance costs a fraction of a full search.
    fn nearest_within(&self, p: &Vector3<f32>, reach: f32) -> Option<Nearest> {
        let (proj, (triangle, location)) = self
            .query
            .project_local_point_and_get_location_with_max_dist(
                Vector::new(p.x, p.y, p.z),
                false,
                reach,
            )?;
        Some(self.describe(&proj, triangle, &location))
    }

    /// The nearest point `proj` found on `triangle` at `location`, with its smooth normal and
    /// the normal that tells the side (see [`Surface::nearest_with_face`]).
    fn describe(
        &self,
        proj: &PointProjection,
        triangle: u32,
        location: &TrianglePointLocation,
    ) -> Nearest {
        let w = location
            .barycentric_coordinates()
            .unwrap_or([1.0, 0.0, 0.0])
            .map(|x| x.clamp(0.0, 1.0));
        let sum: f32 = w.iter().sum();
        let frame = self.mesh.evaluate(&MeshSample {
            triangle,
            weights: w.map(|x| x / sum),
        });
        let smooth = frame.rotation * Vector3::z();
        let [a, b, c] = self.mesh.corners(triangle as usize);
        let face = (b - a).cross(&(c - a));
        let on_face = matches!(location, TrianglePointLocation::OnFace(..));
        let face = if on_face && face.norm() > 0.0 {
            face.normalize()
        } else {
            smooth
        };
        (
            Vector3::new(proj.point.x, proj.point.y, proj.point.z),
            smooth,
            face,
        )
    }

    /// Signed distance of `p` from the scalp (negative behind the nearest triangle), m, and the
    /// point at `height` above the scalp nearest `p`: along `p`'s offset from the surface when
    /// `p` is outside, along the triangle's normal otherwise.
    fn height_and_lift(&self, p: &Vector3<f32>, height: f32) -> (f32, Vector3<f32>) {
        lift_from(p, self.nearest_with_face(p), height)
    }

    /// [`Surface::height_and_lift`] if the scalp comes within `reach` m of `p`
    /// ([`Surface::nearest_within`]), else `None`.
    fn height_and_lift_within(
        &self,
        p: &Vector3<f32>,
        height: f32,
        reach: f32,
    ) -> Option<(f32, Vector3<f32>)> {
        Some(lift_from(p, self.nearest_within(p, reach)?, height))
    }
}

/// Signed height of `p` over its nearest scalp point `(c, _, face)` and the point at `height`
/// above the scalp nearest `p` (see [`Surface::height_and_lift`]).
fn lift_from(p: &Vector3<f32>, (c, _, face): Nearest, height: f32) -> (f32, Vector3<f32>) {
    let offset = p - c;
    let distance = offset.norm();
    let outside = offset.dot(&face) >= 0.0;
    let signed = if outside { distance } else { -distance };
    let direction = if outside && distance > 1e-7 {
        offset / distance
    } else {
        face
    };
    (signed, c + direction * height)
}

/// Lays every surface-rooted strand of `strands` over `mesh` (the scalp at the rest pose the
/// strands' anchors refer to) as `opts` says; strands anchored in body space (explicit point
/// lists) are left as given. Roots, point counts and segment lengths are kept.
pub fn lay_over_scalp(
    strands: &mut [StrandInput],
    mesh: &TriMesh,
    opts: &StyleOptions,
) -> Result<(), GroomError> {
    opts.validate()?;
    let surface = Surface::new(mesh)?;
    // Each surface-rooted strand's layer height, drawn in strand order, so the strands can then
    // be laid in parallel with the same result on any number of threads.
    let mut heights = rng::stream(opts.seed, Purpose::Layers);
    let layered: Vec<_> = strands
        .iter_mut()
        .filter_map(|strand| match strand.anchor {
            Anchor::Surface(sample) => Some((strand, sample, rng::unit_f32(&mut heights))),
            _ => None,
        })
        .collect();
    layered.into_par_iter().for_each(|(strand, sample, u)| {
        let frame = mesh.evaluate(&sample);
        let world: Vec<Vector3<f32>> = strand.rest.iter().map(|p| frame.to_world(p)).collect();
        let laid = lay_strand(&surface, &world, opts, opts.clearance + opts.layer * u);
        strand.rest = laid.iter().map(|p| frame.to_local(p)).collect();
    });
    Ok(())
}

/// The flow at a scalp point with normal `n` for a strand rooted at `root`: the comb (and part)
/// direction made tangential and scaled by the scalp's support there (at most unit length), or
/// `None` where nothing of it is left.
fn tangential_flow(
    opts: &StyleOptions,
    root: &Vector3<f32>,
    n: &Vector3<f32>,
) -> Option<Vector3<f32>> {
    let mut flow = opts.comb.normalize();
    if let Some(part) = opts.part {
        let m = part.normal.normalize();
        let side = if (root - part.point).dot(&m) >= 0.0 {
            1.0
        } else {
            -1.0
        };
        flow += m * (side * part.weight);
    }
    // Combed hair follows the flow where the scalp carries it (its normal points up, against
    // gravity) and falls where the scalp turns away: the flow is weighted by that support.
    let support = (-n.dot(&opts.down.normalize())).max(0.0);
    let t = (flow - n * flow.dot(n)) * support;
    let len = t.norm();
    (len > 1e-6).then(|| t / len.max(1.0))
}

/// Lifts every surface-rooted strand of `strands` out of `mesh` (the scalp at the rest pose the
/// anchors refer to) to `clearance` m: [`ScalpLift::lift`] on each. For grooms that dip into a
/// scalp they were not made on: interpolated hair between guides on a curved head, a groom
/// fitted to a finer mesh than the collider. Returns the number of points lifted.
pub fn lift_out_of_scalp(
    strands: &mut [StrandInput],
    mesh: &TriMesh,
    clearance: f32,
) -> Result<usize, GroomError> {
    Ok(ScalpLift::new(mesh, clearance)?.lift_all(strands))
}

/// A scalp at rest made searchable once, to lift strands out of it to a clearance as often as
/// they are posed (animated guides lift every frame's pose; building the search tree is the
/// costly part).
///
/// Walking a strand from its root, a point lying less than the clearance above the scalp —
/// measured along the smooth normal at its nearest scalp point, negative inside — is lifted to
/// that height and its segment re-aimed through it at its own length, so roots, point counts
/// and segment lengths are kept. Points within the first clearance of arc length from the root
/// rise with it (a hair leaves the scalp where it grows).
#[derive(Debug, Clone)]
pub struct ScalpLift {
    surface: Surface,
    clearance: f32,
}

impl ScalpLift {
    /// Prepares `mesh` (the scalp at the rest pose anchors refer to) for lifting strands to
    /// `clearance` m above it. Errors: a clearance that is not a finite height ≥ 0, a mesh that
    /// cannot be searched.
    pub fn new(mesh: &TriMesh, clearance: f32) -> Result<Self, GroomError> {
        if !(clearance.is_finite() && clearance >= 0.0) {
            return Err(parameter(
                "clearance",
                clearance,
                "must be a finite height ≥ 0 m",
            ));
        }
        Ok(Self {
            surface: Surface::new(mesh)?,
            clearance,
        })
    }

    /// The scalp this lifts out of.
    pub fn mesh(&self) -> &TriMesh {
        &self.surface.mesh
    }

    /// Height above the scalp strands are lifted to, m.
    pub fn clearance(&self) -> f32 {
        self.clearance
    }

    /// Lifts one strand's root-local rest shape `rest`, rooted at `anchor`, in place (see the
    /// type's docs); strands anchored in body space are left as given. Returns the number of
    /// points lifted.
    ///
    /// A point is only looked up on the scalp when it may be near it: the distance to a surface
    /// changes by at most the distance moved, so a point whose predecessor stands higher above
    /// the scalp than the clearance plus the segment between them is outside and clear of it
    /// (the segment cannot reach the surface, so it cannot cross into a closed scalp) and is
    /// skipped, carrying that lower bound on to the next point. Hair hanging away from the head
    /// costs a query every few points instead of one per point.
    pub fn lift(&self, anchor: &Anchor, rest: &mut [Vector3<f32>]) -> usize {
        self.lift_points(anchor, rest, true, None)
    }

    /// How far below its allowed height (the clearance, or the arc length from the root where
    /// that is less) the lowest point of the root-local rest shape `rest`, rooted at `anchor`,
    /// lies, m: 0 when every point is clear — as after a [`ScalpLift::lift`] that succeeded.
    /// Strands anchored in body space give 0.
    pub fn shortfall(&self, anchor: &Anchor, rest: &[Vector3<f32>]) -> f32 {
        let Anchor::Surface(sample) = *anchor else {
            return 0.0;
        };
        let frame = self.surface.mesh.evaluate(&sample);
        let world: Vec<Vector3<f32>> = rest.iter().map(|p| frame.to_world(p)).collect();
        let mut arc = 0.0f32;
        let mut worst = 0.0f32;
        for w in world.windows(2) {
            arc += (w[1] - w[0]).norm();
            let allowed = self.clearance.min(arc);
            let (height, _) = self.surface.height_and_lift(&w[1], allowed);
            worst = worst.max(allowed - height);
        }
        worst
    }

    /// [`ScalpLift::lift`] on every strand of `strands`; returns the number of points lifted.
    pub fn lift_all(&self, strands: &mut [StrandInput]) -> usize {
        strands
            .iter_mut()
            .map(|strand| self.lift(&strand.anchor, &mut strand.rest))
            .sum()
    }

    /// The strands of `strands` (indices, increasing) whose rest shape passes through the
    /// scalp: see [`strands_through_scalp`].
    pub fn strands_through(&self, strands: &[StrandInput]) -> Vec<usize> {
        let surface = &self.surface;
        strands
            .iter()
            .enumerate()
            .filter(|(_, strand)| {
                let Anchor::Surface(sample) = strand.anchor else {
                    return false;
                };
                let frame = surface.mesh.evaluate(&sample);
                let world: Vec<Vector3<f32>> =
                    strand.rest.iter().map(|p| frame.to_world(p)).collect();
                world
                    .windows(2)
                    .skip(1)
                    .any(|w| surface.crosses(&w[0], &w[1]))
            })
            .map(|(i, _)| i)
            .collect()
    }

    /// The strands of `strands` (indices, increasing) that a lift could not clear: a point
    /// after the root lies more than `tolerance` m lower than the lift allows it
    /// ([`ScalpLift::shortfall`]). Lifting pushes a point away from its nearest scalp point; in
    /// a gap narrower than twice the clearance — between Sintel's right ear and her head, where
    /// three blended wisps start — every push away from one wall is a push into the other, and
    /// the point stays low. A scalp collider of the clearance's reach (hair radius plus
    /// thickness) would start with that point inside and keep it there, pressed between the
    /// walls, for the whole run. Errors: a tolerance that is not a finite depth ≥ 0 m.
    pub fn strands_below(
        &self,
        strands: &[StrandInput],
        tolerance: f32,
    ) -> Result<Vec<usize>, GroomError> {
        if !(tolerance.is_finite() && tolerance >= 0.0) {
            return Err(parameter(
                "tolerance",
                tolerance,
                "must be a finite depth ≥ 0 m",
            ));
        }
        Ok(strands
            .iter()
            .enumerate()
            .filter(|(_, strand)| self.shortfall(&strand.anchor, &strand.rest) > tolerance)
            .map(|(i, _)| i)
            .collect())
    }

    /// [`ScalpLift::lift`] for a strand lifted again and again as it is posed (animated
    /// guides, every frame): `memory` keeps, from the strand's last lift, where each point ended
    /// and a lower bound on its height there, and a point that has moved by less than that
    /// height minus the clearance since is clear of the scalp without a look-up (the distance
    /// to a surface changes by at most the distance moved). Between frames of a pose hair moves
    /// millimetres, so hair lying on the head is looked up only where it comes near the
    /// clearance. Lifts exactly as [`ScalpLift::lift`] (the bound only skips look-ups that
    /// would find the point clear); a memory of another point count starts afresh. A point the
    /// memory cannot clear but that was outside at its last lift and has moved less than the
    /// clearance since is asked only whether the scalp comes within the clearance of it (a
    /// search bounded to that reach; it cannot have crossed into the scalp unseen), and is
    /// looked up in full only when it does.
    pub fn lift_remembering(
        &self,
        anchor: &Anchor,
        rest: &mut [Vector3<f32>],
        memory: &mut LiftMemory,
    ) -> usize {
        self.lift_points(anchor, rest, true, Some(memory))
    }

    /// [`ScalpLift::lift`], skipping points known to be clear (from their predecessor's height,
    /// and from `memory` when given) when `skip_clear` is set (always but in the tests that hold
    /// the skip to the full walk).
    fn lift_points(
        &self,
        anchor: &Anchor,
        rest: &mut [Vector3<f32>],
        skip_clear: bool,
        mut memory: Option<&mut LiftMemory>,
    ) -> usize {
        let Anchor::Surface(sample) = *anchor else {
            return 0;
        };
        let surface = &self.surface;
        let frame = surface.mesh.evaluate(&sample);
        let mut world: Vec<Vector3<f32>> = rest.iter().map(|p| frame.to_world(p)).collect();
        if let Some(m) = memory.as_deref_mut() {
            if m.points.len() != world.len() {
                m.points.clear();
                m.points.resize(world.len(), Vector3::zeros());
                m.heights.clear();
                m.heights.resize(world.len(), f32::NEG_INFINITY);
            }
        }
        let mut arc = 0.0f32;
        let mut lifted = 0;
        // A lower bound on the previous point's height above the scalp, m (the root is on it).
        let mut clear_by = 0.0f32;
        for j in 1..world.len() {
            let length = (world[j] - world[j - 1]).norm();
            arc += length;
            let allowed = self.clearance.min(arc);
            let mut bound = clear_by - length;
            if let Some(m) = memory.as_deref() {
                bound = bound.max(m.heights[j] - (world[j] - m.points[j]).norm());
            }
            if skip_clear && bound > self.clearance {
                clear_by = bound;
                if let Some(m) = memory.as_deref_mut() {
                    (m.points[j], m.heights[j]) = (world[j], bound);
                }
                continue;
            }
            clear_by = 0.0;
            // A point that was outside the scalp at its last lift and has moved less than
            // `allowed` since cannot be inside now (the scalp point its move crossed would lie
            // within `allowed` of it): if no scalp comes within `allowed` of it, it is clear,
            // and a search bounded to that reach says so at a fraction of a full search's cost.
            let outside_before = skip_clear
                && memory.as_deref().is_some_and(|m| {
                    m.heights[j] > 0.0 && (world[j] - m.points[j]).norm() < allowed
                });
            let mut first = None;
            if outside_before {
                match surface.height_and_lift_within(&world[j], allowed, allowed) {
                    Some(found) => first = Some(found),
                    None => {
                        clear_by = allowed;
                        if let Some(m) = memory.as_deref_mut() {
                            (m.points[j], m.heights[j]) = (world[j], allowed);
                        }
                        continue;
                    }
                }
            }
            let mut moved_any = false;
            // The height found at the point's present position (none once it has moved since).
            let mut known = f32::NEG_INFINITY;
            // Re-aiming at the lifted point keeps the segment's length, which can leave the
            // point short of it on a curved scalp: a few rounds converge.
            for _ in 0..16 {
                let (height, target) = match first.take() {
                    Some(found) => found,
                    None => surface.height_and_lift(&world[j], allowed),
                };
                known = height;
                if height >= allowed - 1e-6 || length == 0.0 {
                    if !moved_any {
                        clear_by = height.max(0.0);
                    }
                    break;
                }
                let aim = target - world[j - 1];
                if aim.norm() < 1e-9 {
                    break;
                }
                // The rest of the strand moves rigidly with this point, keeping its shape.
                let moved = world[j - 1] + aim.normalize() * length;
                let shift = moved - world[j];
                for p in &mut world[j..] {
                    *p += shift;
                }
                moved_any = true;
                known = f32::NEG_INFINITY;
            }
            if moved_any {
                lifted += 1;
            }
            // Later points move only the points after them: this one is where it ends.
            if let Some(m) = memory.as_deref_mut() {
                (m.points[j], m.heights[j]) = (world[j], known);
            }
        }
        if lifted > 0 {
            for (out, p) in rest.iter_mut().zip(&world) {
                *out = frame.to_local(p);
            }
        }
        lifted
    }
}

/// What [`ScalpLift::lift_remembering`] keeps of one strand between lifts: where each point
/// ended (scalp-at-rest space, m) and a lower bound on its height above the scalp there, m
/// (−∞ where none is known). Empty until the first lift.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LiftMemory {
    points: Vec<Vector3<f32>>,
    heights: Vec<f32>,
}

/// The interpolated hairs of `hairs` (indices, increasing) that their blend turns sharply off
/// their guides' shapes: by more than `max_turn_deg` degrees — the weighted mean, over the
/// guides blended, of the angle between the guide's root normal and the hair's on `mesh` (the
/// scalp both are rooted on) — over roots closer than a surface of radius `min_radius` m would
/// need for that turn (the weighted mean root distance below `turn × min_radius`).
///
/// Interpolation carries each guide's shape by the smallest rotation taking its root normal onto
/// the hair's ([`crate::interpolate()`]). Over a head's gentle curvature (radius ~0.1 m) that
/// lays a guide's combed shape along the head at the hair's root, however far apart the roots
/// are. Where the surface turns sharply between nearby roots — a hair on the rim of an ear, its
/// guides rooted on the scalp just above it — a guide combed down the head is turned out into
/// the air: a Sintel sim hair rooted on her right ear's rim, turned 82° from guides 6.5 mm away,
/// stood 4 cm out behind the ear.
pub fn hairs_turned_off_their_guides(
    hairs: &[SimHair],
    guides: &[Guide],
    mesh: &TriMesh,
    max_turn_deg: f32,
    min_radius: f32,
) -> Result<Vec<usize>, GroomError> {
    if !(max_turn_deg.is_finite() && (0.0..=180.0).contains(&max_turn_deg)) {
        return Err(parameter(
            "max_turn_deg",
            max_turn_deg,
            "must be an angle in [0, 180] degrees",
        ));
    }
    if !(min_radius.is_finite() && min_radius > 0.0) {
        return Err(parameter(
            "min_radius",
            min_radius,
            "must be a finite radius > 0 m",
        ));
    }
    // Each guide's root and normal, evaluated once for all the hairs blending it.
    let root_and_normal = |sample: &MeshSample| {
        let at = mesh.evaluate(sample);
        (at.origin, at.rotation * Vector3::z())
    };
    let guide_roots: Vec<_> = guides.iter().map(|g| root_and_normal(&g.root)).collect();
    let mut turned = Vec::new();
    for (i, hair) in hairs.iter().enumerate() {
        let (root, n) = root_and_normal(&hair.root);
        let (mut angle, mut distance, mut weights) = (0.0f32, 0.0f32, 0.0f32);
        for source in &hair.sources {
            let (g_root, g_normal) = guide_roots.get(source.guide).ok_or_else(|| {
                parameter(
                    "sources",
                    source.guide,
                    &format!("hair {i} names a guide beyond the {} given", guides.len()),
                )
            })?;
            angle += source.weight * g_normal.angle(&n);
            distance += source.weight * (g_root - root).norm();
            weights += source.weight;
        }
        if weights > 0.0 {
            let (angle, distance) = (angle / weights, distance / weights);
            if angle.to_degrees() > max_turn_deg && distance < angle * min_radius {
                turned.push(i);
            }
        }
    }
    Ok(turned)
}

/// The strands of `strands` (indices, increasing) whose rest shape passes through `mesh` (the
/// scalp at the rest pose the anchors refer to): a segment after the first one — the first
/// leaves the scalp at the root — that a ray along it meets the surface within its length.
/// Lifting ([`lift_out_of_scalp`]) moves points out of the scalp but cannot undo such a crossing:
/// interpolated hair between two guides that pass either side of a thin flap (an ear) goes
/// through it, and a simulation, whose contacts act on points, keeps the flap caught between two
/// points.
pub fn strands_through_scalp(
    strands: &[StrandInput],
    mesh: &TriMesh,
) -> Result<Vec<usize>, GroomError> {
    Ok(ScalpLift::new(mesh, 0.0)?.strands_through(strands))
}

/// One strand laid from its world points (root first) at layer height `height` (m).
fn lay_strand(
    surface: &Surface,
    world: &[Vector3<f32>],
    opts: &StyleOptions,
    height: f32,
) -> Vec<Vector3<f32>> {
    let root = world[0];
    let down = opts.down.normalize();
    let lift = opts.lift_deg.to_radians();
    let (_, n0) = surface.nearest(&root);
    let flow0 = tangential_flow(opts, &root, &n0)
        .map(|f| f.normalize())
        .unwrap_or_else(|| {
            let t = down - n0 * down.dot(&n0);
            if t.norm() > 1e-6 {
                t.normalize()
            } else {
                hair_core::mesh::any_perpendicular(&n0)
            }
        });
    let mut direction = (flow0 * lift.cos() + n0 * lift.sin()).normalize();
    let mut out = Vec::with_capacity(world.len());
    out.push(root);
    let mut p = root;
    let mut arc = 0.0f32;
    for w in world.windows(2) {
        let length = (w[1] - w[0]).norm();
        if !(length > 0.0 && length.is_finite()) {
            out.push(p);
            continue;
        }
        if out.len() > 1 {
            let (_, n) = surface.nearest(&p);
            let flow = tangential_flow(opts, &root, &n).unwrap_or_else(Vector3::zeros);
            let target = flow * opts.comb_weight + down;
            if target.norm() > 1e-6 {
                direction =
                    turn_towards(&direction, &target.normalize(), opts.max_curvature * length);
            }
        }
        arc += length;
        let allowed = height.min(arc * lift.sin());
        let mut next = p + direction * length;
        for _ in 0..3 {
            let (c, n) = surface.nearest(&next);
            let above = (next - c).dot(&n);
            if above >= allowed - 1e-6 {
                break;
            }
            let lifted = c + n * allowed;
            let d = lifted - p;
            if d.norm() < 1e-9 {
                break;
            }
            direction = d.normalize();
            next = p + direction * length;
        }
        out.push(next);
        p = next;
    }
    out
}

/// `from` turned towards `to` (both unit) by at most `max_angle` radians.
fn turn_towards(from: &Vector3<f32>, to: &Vector3<f32>, max_angle: f32) -> Vector3<f32> {
    let angle = from.angle(to);
    if angle <= max_angle {
        return *to;
    }
    let axis = from.cross(to);
    match Unit::try_new(axis, 1e-9) {
        Some(axis) => UnitQuaternion::from_axis_angle(&axis, max_angle) * from,
        // Opposite directions: turn about any perpendicular axis.
        None => {
            let axis = Unit::new_normalize(hair_core::mesh::any_perpendicular(from));
            UnitQuaternion::from_axis_angle(&axis, max_angle) * from
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::uv_sphere;
    use crate::{generate, GenerateOptions, Region};

    fn options() -> StyleOptions {
        StyleOptions {
            comb: Vector3::y(),
            comb_weight: 1.0,
            part: None,
            lift_deg: 30.0,
            clearance: 0.004,
            layer: 0.01,
            max_curvature: 40.0,
            down: -Vector3::z(),
            seed: 2,
        }
    }

    fn hair(mesh: &TriMesh) -> Vec<StrandInput> {
        generate(
            mesh,
            &GenerateOptions {
                count: 200,
                length: 0.3,
                segments: 20,
                seed: 1,
                radius: 0.002,
                mass_per_length: 1e-3,
                goal_root: 0.0,
                goal_tip: 0.0,
                region: Region::Cone {
                    direction: Vector3::z(),
                    max_angle_deg: 80.0,
                },
                length_variation: 0.2,
            },
        )
        .unwrap()
    }

    fn world(mesh: &TriMesh, s: &StrandInput) -> Vec<Vector3<f32>> {
        let Anchor::Surface(sample) = s.anchor else {
            unreachable!("generated strands are surface-rooted")
        };
        let frame = mesh.evaluate(&sample);
        s.rest.iter().map(|p| frame.to_world(p)).collect()
    }

    #[test]
    fn laid_hair_keeps_roots_and_lengths_stays_above_the_scalp_and_turns_smoothly() {
        let radius = 0.1;
        let mesh = uv_sphere(radius, 48, 24).unwrap();
        let before = hair(&mesh);
        let mut after = before.clone();
        let opts = options();
        lay_over_scalp(&mut after, &mesh, &opts).unwrap();
        // The sphere's facets lie inside the true sphere by at most its sagitta.
        let sagitta = radius * (1.0 - (std::f32::consts::PI / 24.0).cos());
        for (b, a) in before.iter().zip(&after) {
            assert_eq!(a.rest[0], b.rest[0]);
            let (wb, wa) = (world(&mesh, b), world(&mesh, a));
            for (sb, sa) in wb.windows(2).zip(wa.windows(2)) {
                let (lb, la) = ((sb[1] - sb[0]).norm(), (sa[1] - sa[0]).norm());
                assert!((lb - la).abs() < 1e-5 * lb.max(1e-3), "{lb} vs {la}");
            }
            // Every point after the root lies outside the sphere (height ≥ 0 up to facets).
            for p in &wa[1..] {
                assert!(p.norm() > radius - sagitta - 1e-5, "{} inside", p.norm());
            }
            // Turns between segments stay within the curvature limit (plus a lift correction,
            // which only ever turns a segment outwards by the small angle the facets demand).
            for s in wa.windows(3) {
                let (d0, d1) = (s[1] - s[0], s[2] - s[1]);
                let turn = d0.angle(&d1);
                assert!(turn < 1.0, "turn {turn} rad at one point");
            }
        }
    }

    #[test]
    fn combed_hair_goes_the_comb_way_and_falls_past_the_head() {
        let mesh = uv_sphere(0.1, 48, 24).unwrap();
        let mut strands = hair(&mesh);
        lay_over_scalp(&mut strands, &mesh, &options()).unwrap();
        let mut tips_below = 0;
        let mut tips_back = 0;
        for s in &strands {
            let w = world(&mesh, s);
            let tip = w[w.len() - 1];
            tips_below += usize::from(tip.z < w[0].z);
            tips_back += usize::from(tip.y > w[0].y);
        }
        // 30 cm hair on a 10 cm head combed towards +Y: tips hang below and behind their roots.
        assert!(
            tips_below > 190,
            "{tips_below} of 200 tips below their roots"
        );
        assert!(
            tips_back > 150,
            "{tips_back} of 200 tips behind their roots"
        );
    }

    #[test]
    fn laying_is_the_same_on_one_thread_and_on_several() {
        let mesh = uv_sphere(0.1, 48, 24).unwrap();
        let laid = |threads: usize| {
            let mut strands = hair(&mesh);
            hair_par::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| lay_over_scalp(&mut strands, &mesh, &options()).unwrap());
            strands
        };
        let (one, four) = (laid(1), laid(4));
        for (a, b) in one.iter().zip(&four) {
            // Bit for bit: each strand's layer height is drawn in strand order before laying.
            let bits = |s: &StrandInput| -> Vec<u32> {
                s.rest
                    .iter()
                    .flat_map(|p| p.iter().map(|c| c.to_bits()))
                    .collect()
            };
            assert_eq!(bits(a), bits(b));
        }
    }

    #[test]
    fn a_part_sends_each_side_its_own_way() {
        let mesh = uv_sphere(0.1, 48, 24).unwrap();
        let mut strands = hair(&mesh);
        let mut opts = options();
        opts.comb = -Vector3::z();
        opts.part = Some(Part {
            normal: Vector3::x(),
            point: Vector3::zeros(),
            weight: 2.0,
        });
        lay_over_scalp(&mut strands, &mesh, &opts).unwrap();
        for s in &strands {
            let w = world(&mesh, s);
            if w[0].x.abs() > 0.01 {
                // The second point moves away from the part plane on the root's side.
                assert!(w[2].x * w[0].x.signum() > w[0].x.abs(), "{:?}", &w[..3]);
            }
        }
    }

    #[test]
    fn hair_dipping_into_the_scalp_is_lifted_out_keeping_roots_and_lengths() {
        let radius = 0.1;
        let mesh = uv_sphere(radius, 48, 24).unwrap();
        // Straight hair grown tangentially (along the surface's local x): it cuts into the
        // sphere's curvature right away.
        let mut strands = hair(&mesh);
        for s in &mut strands {
            let n = s.rest.len();
            s.rest = (0..n)
                .map(|i| Vector3::new(0.3 * i as f32 / (n - 1) as f32, 0.0, 0.0))
                .collect();
        }
        let before = strands.clone();
        let clearance = 0.002;
        let lifted = lift_out_of_scalp(&mut strands, &mesh, clearance).unwrap();
        assert!(lifted > 0);
        let sagitta = radius * (1.0 - (std::f32::consts::PI / 24.0).cos());
        for (b, a) in before.iter().zip(&strands) {
            let (wb, wa) = (world(&mesh, b), world(&mesh, a));
            assert!((wa[0] - wb[0]).norm() < 1e-6);
            for (sb, sa) in wb.windows(2).zip(wa.windows(2)) {
                let (lb, la) = ((sb[1] - sb[0]).norm(), (sa[1] - sa[0]).norm());
                assert!((lb - la).abs() < 1e-5, "{lb} vs {la}");
            }
            for p in &wa[2..] {
                assert!(p.norm() > radius - sagitta, "{} inside", p.norm());
            }
        }
        // Already clear: nothing moves.
        let again = lift_out_of_scalp(&mut strands, &mesh, clearance * 0.5).unwrap();
        assert_eq!(again, 0);
    }

    /// Regression: beyond a sharp rim the triangle the search names can face away from a point
    /// outside, which was then taken to be inside and lifted onto the rim. The tips of three of
    /// Sintel's sim hairs (as blended, before lifting) lie 22–23 mm beside her left ear, where
    /// the nearest scalp point is on an edge between two triangles whose normals are 90° apart;
    /// they were dragged onto the ear, a 114° hook at one point. They read outside, and a
    /// point above a triangle's interior and one inside the bust read as before.
    #[test]
    fn points_beside_a_sharp_rim_are_outside() {
        let opts = crate::formats::obj::ObjOptions {
            scale: 0.01,
            up_axis: crate::formats::obj::UpAxis::Y,
        };
        let bust = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../data/sintel/sintel_bust.obj"
        );
        let mesh = crate::formats::obj::load_obj(std::path::Path::new(bust), &opts).unwrap();
        let surface = Surface::new(&mesh).unwrap();
        for tip in [
            [-0.095_700_52, 0.040_653_005, 0.293_955_47],
            [-0.093_721_13, 0.036_482_25, 0.291_113_64],
            [-0.095_780_45, 0.040_933_44, 0.294_128_66],
        ] {
            let p = Vector3::from(tip);
            let (height, target) = surface.height_and_lift(&p, 0.0015);
            assert!(height > 0.02, "{p:?}: height {height}");
            // Already clear of the scalp: a lift would leave it where it is.
            assert!((target - p).norm() > height - 0.0015 - 1e-5);
        }
        // On the top of the head, 5 mm out and 5 mm in.
        let top =
            mesh.positions().iter().copied().fold(
                Vector3::zeros(),
                |a: Vector3<f32>, p| if p.z > a.z { p } else { a },
            );
        let (above, _) = surface.height_and_lift(&(top + Vector3::z() * 0.005), 0.0);
        let (inside, _) = surface.height_and_lift(&(top - Vector3::z() * 0.005), 0.0);
        assert!(
            (above - 0.005).abs() < 1e-3 && inside < 0.0,
            "{above} {inside}"
        );
    }

    #[test]
    fn skipping_points_clear_of_the_scalp_lifts_exactly_as_looking_up_every_point() {
        // Hair swept about in every direction around a closed head: some dips in, some hangs
        // far away; the skip must change no bit of the result.
        let mesh = crate::builtin_head();
        let lift = ScalpLift::new(&mesh, 0.0035).unwrap();
        let mut strands = hair(&mesh);
        let (mut lifted_some, mut clear_some) = (false, false);
        for (k, s) in strands.iter_mut().enumerate() {
            let n = s.rest.len();
            let (a, b) = (0.37 * k as f32, 0.11 * k as f32);
            let bend = Vector3::new(a.cos(), a.sin(), b.sin() - 0.2) * 0.02;
            s.rest = (0..n)
                .map(|i| {
                    let t = i as f32 / (n - 1) as f32;
                    Vector3::new(0.0, 0.0, 0.3 * t) * b.cos() + bend * (i * i) as f32 / n as f32
                })
                .collect();
            let (mut fast, mut full) = (s.rest.clone(), s.rest.clone());
            let lifted_fast = lift.lift_points(&s.anchor, &mut fast, true, None);
            let lifted_full = lift.lift_points(&s.anchor, &mut full, false, None);
            assert_eq!(lifted_fast, lifted_full, "strand {k}");
            assert_eq!(fast, full, "strand {k}");
            lifted_some |= lifted_full > 0;
            clear_some |= lifted_full == 0;
        }
        assert!(lifted_some && clear_some);
    }

    /// The 12 outward-wound triangles of the box from `lo` to `hi` (m), its corners numbered
    /// from `base`.
    fn cuboid(lo: Vector3<f32>, hi: Vector3<f32>, base: u32) -> (Vec<Vector3<f32>>, Vec<[u32; 3]>) {
        let corner = |i: u32| {
            Vector3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            )
        };
        let quads = [
            [0, 2, 3, 1], // −z
            [4, 5, 7, 6], // +z
            [0, 1, 5, 4], // −y
            [2, 6, 7, 3], // +y
            [0, 4, 6, 2], // −x
            [1, 3, 7, 5], // +x
        ];
        let triangles = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .map(|t| t.map(|i| i + base))
            .collect();
        ((0..8).map(corner).collect(), triangles)
    }

    /// A strand rooted at `points[0]` on triangle `triangle` of `mesh`, through the world
    /// `points` (m).
    fn strand_through(mesh: &TriMesh, triangle: u32, points: &[Vector3<f32>]) -> StrandInput {
        let [a, b, c] = mesh.corners(triangle as usize);
        let (v0, v1, v2) = (b - a, c - a, points[0] - a);
        let (d00, d01, d11) = (v0.dot(&v0), v0.dot(&v1), v1.dot(&v1));
        let (d20, d21) = (v2.dot(&v0), v2.dot(&v1));
        let det = d00 * d11 - d01 * d01;
        let (w1, w2) = ((d11 * d20 - d01 * d21) / det, (d00 * d21 - d01 * d20) / det);
        let sample = MeshSample {
            triangle,
            weights: [1.0 - w1 - w2, w1, w2],
        };
        assert!(sample.weights.iter().all(|&w| (0.0..=1.0).contains(&w)));
        let frame = mesh.evaluate(&sample);
        assert!((frame.to_world(&Vector3::zeros()) - points[0]).norm() < 1e-6);
        let rest = points.iter().map(|p| frame.to_local(p)).collect();
        StrandInput::uniform(Anchor::Surface(sample), rest, 1e-3, 1e-3, 0.0, 0.0)
    }

    /// Regression: three of Sintel's wisps rooted above her right ear started in the
    /// gap between ear and head, narrower than twice the clearance. Lifting pushed their first
    /// point off one wall into the other, and the bust collider held it 0.7–1.1 mm inside for
    /// the whole run. Here: a head (a box) with an ear (a thin slab) 2 mm beside it, and hair
    /// combed over the head's edge down the side, once into the gap and once beside the ear.
    /// With a 1.5 mm clearance no point in the gap can stand clear of both walls: that strand
    /// is named, the one beside the ear is lifted clear and is not.
    #[test]
    fn a_wisp_in_the_ear_gap_is_left_out() {
        let (mut positions, mut triangles) = cuboid(
            Vector3::new(-0.1, -0.1, -0.1),
            Vector3::new(0.0, 0.1, 0.1),
            0,
        );
        let (ear, ear_triangles) = cuboid(
            Vector3::new(0.002, -0.03, -0.05),
            Vector3::new(0.004, 0.03, 0.0),
            8,
        );
        positions.extend(ear);
        triangles.extend(ear_triangles);
        let mesh = TriMesh::new(positions, triangles).unwrap();
        // The head's top (+z) is triangles 2 and 3; both roots lie in triangle 2
        // (x ≥ y/2 − 0.05).
        let wisp = |y: f32| -> Vec<Vector3<f32>> {
            let mut points = vec![
                Vector3::new(-0.01, y, 0.1),
                Vector3::new(-0.002, y, 0.1015),
                Vector3::new(0.001, y, 0.095),
            ];
            points.extend((1..=12).map(|i| Vector3::new(0.001, y, 0.095 - 0.01 * i as f32)));
            points
        };
        let mut strands = vec![
            strand_through(&mesh, 2, &wisp(0.0)),
            strand_through(&mesh, 2, &wisp(-0.06)),
        ];
        let clearance = 0.0015;
        lift_out_of_scalp(&mut strands, &mesh, clearance).unwrap();
        let lift = ScalpLift::new(&mesh, clearance).unwrap();
        let in_gap = lift.shortfall(&strands[0].anchor, &strands[0].rest);
        let beside = lift.shortfall(&strands[1].anchor, &strands[1].rest);
        // The gap is 2 mm: a point in it lies at most 1 mm from one wall, 0.5 mm short.
        assert!(in_gap >= 0.0005 - 1e-5, "in the gap: {in_gap} m short");
        assert!(beside < 1e-5, "beside the ear: {beside} m short");
        let low = lift.strands_below(&strands, 1e-4).unwrap();
        assert_eq!(low, vec![0]);
        let err = lift.strands_below(&strands, -1.0).unwrap_err();
        assert!(err.to_string().contains("tolerance"), "{err}");
    }

    /// Regression: a Sintel sim hair rooted on her right ear's rim had its guide's
    /// shape turned 82° out into the air. On a sphere of radius R the turn between two roots'
    /// normals is the angle θ between the roots seen from the centre, over roots about R·θ
    /// apart. On a 2 cm sphere (sharper than the 3 cm radius allowed) hairs rooted more than
    /// 60° from their one guide are named and nearer ones are not (the facets' smooth normals
    /// differ from the sphere's by well under the 4° margin left either side of 60°); on a
    /// 10 cm sphere, a head's curvature, none is, however far.
    #[test]
    fn a_hair_turned_sharply_off_its_guide_is_named() {
        use crate::{sample_area_weighted, GuideWeight, Region, SimHair};
        for (radius, sharp) in [(0.02, true), (0.1, false)] {
            let mesh = uv_sphere(radius, 48, 24).unwrap();
            let roots = sample_area_weighted(&mesh, 400, 3, &Region::All).unwrap();
            let at = |s: &MeshSample| mesh.evaluate(s).to_world(&Vector3::zeros());
            let guide = Guide {
                root: roots[0],
                rest: vec![Vector3::zeros(), Vector3::new(0.0, 0.0, 0.1)],
            };
            let hairs: Vec<SimHair> = roots[1..]
                .iter()
                .map(|&root| SimHair {
                    root,
                    rest: guide.rest.clone(),
                    sources: vec![GuideWeight {
                        guide: 0,
                        weight: 1.0,
                    }],
                })
                .collect();
            let guides = std::slice::from_ref(&guide);
            let turned = hairs_turned_off_their_guides(&hairs, guides, &mesh, 60.0, 0.03).unwrap();
            let (mut far, mut near) = (0, 0);
            for (i, hair) in hairs.iter().enumerate() {
                let angle = at(&guide.root).angle(&at(&hair.root)).to_degrees();
                if angle > 64.0 {
                    assert_eq!(turned.contains(&i), sharp, "{angle}° on radius {radius}");
                    far += 1;
                } else if angle < 56.0 {
                    assert!(!turned.contains(&i), "{angle}° named on radius {radius}");
                    near += 1;
                }
            }
            assert!(far > 100 && near > 50, "{far} far, {near} near");
            let err = hairs_turned_off_their_guides(&hairs, &[], &mesh, 60.0, 0.03).unwrap_err();
            assert!(err.to_string().contains("sources"), "{err}");
            for (turn, min_radius, name) in
                [(f32::NAN, 0.03, "max_turn_deg"), (60.0, 0.0, "min_radius")]
            {
                let err = hairs_turned_off_their_guides(&hairs, guides, &mesh, turn, min_radius)
                    .unwrap_err();
                assert!(err.to_string().contains(name), "{err}");
            }
        }
    }

    #[test]
    fn lifting_with_memory_of_the_last_pose_lifts_exactly_as_without() {
        // Hair swept a little further frame by frame (as a keyed pose moves it), some of it
        // into the head: the memory of the last lift must change no bit of any frame's result.
        let mesh = crate::builtin_head();
        let lift = ScalpLift::new(&mesh, 0.0035).unwrap();
        let strands = hair(&mesh);
        let mut memories = vec![LiftMemory::default(); strands.len()];
        let (mut lifted_some, mut clear_some) = (false, false);
        for frame in 0..8 {
            let sweep = 0.004 * frame as f32;
            for (k, (s, memory)) in strands.iter().zip(&mut memories).enumerate() {
                let n = s.rest.len();
                let (a, b) = (0.37 * k as f32, 0.11 * k as f32);
                let bend = Vector3::new(a.cos(), a.sin(), b.sin() - 0.2 - sweep) * (0.02 + sweep);
                let posed: Vec<Vector3<f32>> = (0..n)
                    .map(|i| {
                        let t = i as f32 / (n - 1) as f32;
                        Vector3::new(0.0, 0.0, 0.3 * t) * b.cos() + bend * (i * i) as f32 / n as f32
                    })
                    .collect();
                let (mut with, mut without) = (posed.clone(), posed);
                let lifted_with = lift.lift_remembering(&s.anchor, &mut with, memory);
                let lifted_without = lift.lift_points(&s.anchor, &mut without, false, None);
                assert_eq!(lifted_with, lifted_without, "frame {frame}, strand {k}");
                assert_eq!(with, without, "frame {frame}, strand {k}");
                lifted_some |= lifted_without > 0;
                clear_some |= lifted_without == 0;
            }
        }
        assert!(lifted_some && clear_some);
        // The memory holds heights that can spare the next frame's look-ups.
        assert!(memories
            .iter()
            .any(|m| m.heights.iter().any(|&h| h.is_finite() && h > 0.0035)));
    }

    #[test]
    fn strands_passing_through_the_scalp_are_found_and_strands_outside_are_not() {
        let radius = 0.1;
        let mesh = uv_sphere(radius, 48, 24).unwrap();
        let mut strands = hair(&mesh);
        // Even strands: straight out along the normal. Odd strands: out 2 cm, then back
        // through the sphere and out its far side (0.3 m along −normal from 2 cm up).
        for (k, s) in strands.iter_mut().enumerate() {
            let n = s.rest.len();
            s.rest = (0..n)
                .map(|i| {
                    let t = i as f32 / (n - 1) as f32;
                    if k % 2 == 0 {
                        Vector3::new(0.0, 0.0, 0.3 * t)
                    } else if i < 2 {
                        Vector3::new(0.0, 0.0, 0.02 * i as f32)
                    } else {
                        Vector3::new(0.0, 0.0, 0.02 - 0.3 * t)
                    }
                })
                .collect();
        }
        let through = strands_through_scalp(&strands, &mesh).unwrap();
        let odd: Vec<usize> = (0..strands.len()).filter(|k| k % 2 == 1).collect();
        assert_eq!(through, odd);
    }

    #[test]
    fn bad_options_are_named() {
        let mesh = uv_sphere(0.1, 16, 8).unwrap();
        let mut strands = hair(&mesh);
        for (opts, name) in [
            (
                StyleOptions {
                    comb: Vector3::zeros(),
                    ..options()
                },
                "comb",
            ),
            (
                StyleOptions {
                    lift_deg: 0.0,
                    ..options()
                },
                "lift_deg",
            ),
            (
                StyleOptions {
                    max_curvature: f32::NAN,
                    ..options()
                },
                "max_curvature",
            ),
            (
                StyleOptions {
                    clearance: -1.0,
                    ..options()
                },
                "clearance",
            ),
        ] {
            let err = lay_over_scalp(&mut strands, &mesh, &opts)
                .unwrap_err()
                .to_string();
            assert!(err.contains(name), "{err}");
        }
    }
}
