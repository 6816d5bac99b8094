//! Animated guides at run time (seed 001, "Hair Levels": animated guide hairs define the rest
//! positions): each frame the sim hairs' rest shapes follow the guides' pose, and a
//! sim weight hands the hair between simulation and the animated guides.
//!
//! **Rest shapes follow the pose.** A pose (root-local guide shapes, from the scene's keys,
//! interpolated between them like [`crate::scene::motion`], or set by the host) is
//! re-interpolated to every sim hair with the weights chosen at build
//! ([`hair_groom::GuideBlend`], O(points · k)). The change from the groom is added to the
//! hair's built rest shape (which may have been lifted out of the scalp at build), so goal
//! springs and pinned points follow the pose; each segment's rest direction (bending, and for
//! the first segment the direction held in the root frame) is turned by the smallest rotation
//! that takes the groom's direction to the posed one, which keeps the sag-free correction the
//! build solved. Rest lengths stay: an animated guide bends hair, it does not stretch it. A pose
//! equal to the groom leaves every rest value bit for bit as built.
//!
//! **Sim weight.** After the frame's simulation, a hair with weight `w` is moved onto its
//! animated position `x_a = root.to_world(rest)`: `x ← (1 − w) x + w x_a`, and its velocity
//! likewise onto the animated velocity `(x_a(t) − x_a(t − 1)) · fps`. `w = 0` leaves the
//! simulation untouched (no arithmetic at all), `w = 1` puts the hair exactly on the animated
//! guides, values between hand the shot back and forth (Maya nHair's and Houdini Vellum's
//! "blend to animation"). Hold-out hair is pinned at every point and has weight 1: it follows
//! the guides exactly and takes no part in the dynamics.
//!
//! **Posed hair keeps its lengths.** The posed shape of a hair is its built shape moved by the
//! change of its interpolated guides, re-walked from the root with each segment at its built
//! length: adding a large change (a 70° sweep) point by point would otherwise stretch or
//! shorten segments, and a hair put on the pose at sim weight 1 would be stretched with it.
//!
//! **Posed hair stays out of the scalp.** With a [`PoseLift`] (`[guides] pose_clearance`), each
//! posed sim hair is then lifted out of the scalp at rest by [`hair_groom::ScalpLift`]
//! (walking the hair from its root, a point closer than the clearance is raised to it and its
//! segment re-aimed at its own length): a keyed sweep that turns hair towards the head lays it
//! over the head, at every frame between keys too. The scalp's search tree is built once, hairs
//! are lifted in parallel, and each hair remembers its last lift ([`hair_groom::LiftMemory`]):
//! only points that come within reach of the clearance since are looked up on the scalp.

use hair_core::frames::{rest_directions, RestDirection};
use hair_core::{Anchor, RootFrame, StrandSet, TriMesh};
use hair_groom::{GroomError, GuideBlend, LiftMemory, ScalpLift};
use hair_par::prelude::*;
use nalgebra::Vector3;

use crate::scene::motion::Interpolation;

/// One keyed pose: root-local shapes of every guide at `frame`.
#[derive(Debug, Clone, PartialEq)]
pub struct PoseKey {
    /// Frame of the key.
    pub frame: f32,
    /// Root-local shape of each guide, m.
    pub shapes: Vec<Vec<Vector3<f32>>>,
}

/// A keyed scalar curve over frames (holds outside its keys); no keys = 0.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct WeightCurve {
    interpolation: Interpolation,
    keys: Vec<(f32, f32)>,
}

impl WeightCurve {
    /// A curve through `keys` (frame, value), in increasing frame order.
    pub fn new(interpolation: Interpolation, keys: Vec<(f32, f32)>) -> Self {
        Self {
            interpolation,
            keys,
        }
    }

    /// The value at `frame`.
    pub fn at(&self, frame: f32) -> f32 {
        match key_span(self.keys.iter().map(|k| k.0), frame, self.interpolation) {
            None => 0.0,
            Some(Span::At(i)) => self.keys[i].1,
            Some(Span::Between(i, s)) => self.keys[i].1 + (self.keys[i + 1].1 - self.keys[i].1) * s,
        }
    }
}

enum Span {
    At(usize),
    Between(usize, f32),
}

/// Where `frame` falls among key frames: on a key (or held before/after), or between two with
/// the (eased) fraction.
fn key_span(
    frames: impl Iterator<Item = f32> + Clone,
    frame: f32,
    how: Interpolation,
) -> Option<Span> {
    let n = frames.clone().count();
    let first = frames.clone().next()?;
    let last = frames.clone().last()?;
    if frame <= first {
        return Some(Span::At(0));
    }
    if frame >= last {
        return Some(Span::At(n - 1));
    }
    let i = frames.clone().take_while(|&f| f <= frame).count() - 1;
    let a = frames.clone().nth(i)?;
    let b = frames.clone().nth(i + 1)?;
    if frame == a {
        return Some(Span::At(i));
    }
    let mut s = (frame - a) / (b - a);
    if how == Interpolation::Ease {
        s = s * s * (3.0 - 2.0 * s);
    }
    Some(Span::Between(i, s))
}

/// Lifts posed sim hairs out of the scalp at rest (see the module docs): the scalp's search
/// tree is built once, when the scene is, and posed hairs are lifted in parallel.
#[derive(Debug, Clone)]
pub struct PoseLift(ScalpLift);

impl PoseLift {
    /// Lifts posed hair out of `mesh` (the scalp at rest the roots refer to) to `clearance` m;
    /// errors as [`ScalpLift::new`].
    pub(crate) fn new(mesh: &TriMesh, clearance: f32) -> Result<Self, GroomError> {
        ScalpLift::new(mesh, clearance).map(Self)
    }

    /// Height above the scalp posed hair is lifted to, m.
    pub fn clearance(&self) -> f32 {
        self.0.clearance()
    }

    /// Lifts the root-local shapes in `shapes` (`n` points each, rooted at `anchors`) whose
    /// flag in `moved` is set, in place, each remembering its last lift in `memory` (one per
    /// shape; see [`ScalpLift::lift_remembering`]); returns the number of points walked.
    fn lift(
        &self,
        anchors: &[Anchor],
        shapes: &mut [Vector3<f32>],
        n: usize,
        moved: &[bool],
        memory: &mut [LiftMemory],
    ) -> u64 {
        shapes
            .par_chunks_mut(n)
            .zip(memory.par_iter_mut())
            .zip(anchors.par_iter().zip(moved.par_iter()))
            .filter(|(_, (_, &m))| m)
            .map(|((shape, memory), (anchor, _))| {
                self.0.lift_remembering(anchor, shape, memory);
                n as u64
            })
            .sum()
    }

    /// Fills `memory` (one per shape) from the root-local `shapes` (`n` points each, rooted at
    /// `anchors`) without changing them: a lift of a copy of each, so the first posed frame
    /// after it looks up only what moved near the scalp.
    fn remember(
        &self,
        anchors: &[Anchor],
        shapes: &[Vector3<f32>],
        n: usize,
        memory: &mut [LiftMemory],
    ) {
        shapes
            .par_chunks(n)
            .zip(memory.par_iter_mut())
            .zip(anchors.par_iter())
            .for_each(|((shape, memory), anchor)| {
                self.0.lift_remembering(anchor, &mut shape.to_vec(), memory);
            });
    }
}

/// Workspace of [`GuideAnimation::apply_pose`], kept from frame to frame: the sim hairs
/// re-interpolated to the last pose, and what the pose lift remembers of each sim hair (where
/// its points ended and how high above the scalp), which spares most look-ups of hair that
/// moved little since. Results never depend on it.
#[derive(Debug, Clone, Default)]
pub(crate) struct PoseScratch {
    blended: Vec<Vector3<f32>>,
    lift: Vec<LiftMemory>,
}

impl PartialEq for PoseLift {
    fn eq(&self, other: &Self) -> bool {
        let (a, b) = (self.0.mesh(), other.0.mesh());
        self.clearance() == other.clearance()
            && a.positions() == b.positions()
            && a.triangles() == b.triangles()
    }
}

/// The rest state of the animated sim hairs as built (before any pose), bound to a strand set.
#[derive(Debug, Clone, PartialEq)]
struct Base {
    /// Sim hairs re-interpolated from the groom pose.
    interpolated: Vec<Vector3<f32>>,
    /// The built rest shapes (root-local).
    rest: Vec<Vector3<f32>>,
    /// The built rest directions (sag-free corrected when the scene asks for it).
    bend: Vec<RestDirection>,
    /// The rest directions of `rest` itself.
    directions: Vec<RestDirection>,
}

/// Animated guides of a scene: poses over frames, sim weights, hold-outs. See the module docs.
#[derive(Debug, Clone, PartialEq)]
pub struct GuideAnimation {
    blend: GuideBlend,
    /// Root frames of the guides on the scalp at rest (host poses are given in that space).
    frames: Vec<RootFrame>,
    /// Groom shapes of the guides, root-local.
    groom: Vec<Vec<Vector3<f32>>>,
    poses: Vec<PoseKey>,
    interpolation: Interpolation,
    sim_weight: WeightCurve,
    /// Per sim hair: the factor the curve is multiplied by (0 or 1 from the scene's selection,
    /// any value in [0, 1] from a host).
    factor: Vec<f32>,
    hold_out: Vec<bool>,
    /// Lifts every pose out of the scalp (`[guides] pose_clearance`).
    lift: Option<PoseLift>,
    /// First strand of the sim hairs in the strand set.
    first_strand: usize,
    base: Option<Base>,
}

impl GuideAnimation {
    /// Assembles the animation (see [`crate::scene::guide_anim::build`]).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        blend: GuideBlend,
        frames: Vec<RootFrame>,
        groom: Vec<Vec<Vector3<f32>>>,
        poses: Vec<PoseKey>,
        interpolation: Interpolation,
        sim_weight: WeightCurve,
        factor: Vec<f32>,
        hold_out: Vec<bool>,
        lift: Option<PoseLift>,
    ) -> Self {
        Self {
            lift,
            blend,
            frames,
            groom,
            poses,
            interpolation,
            sim_weight,
            factor,
            hold_out,
            first_strand: 0,
            base: None,
        }
    }

    /// Sets where the sim hairs start in the strand set.
    pub(crate) fn set_first_strand(&mut self, first: usize) {
        self.first_strand = first;
    }

    /// Number of guides.
    pub fn guide_count(&self) -> usize {
        self.groom.len()
    }

    /// The fixed weights that re-interpolate the sim hairs from a pose (trimmed to their painted
    /// lengths when the scene has a `[maps.length]`).
    pub fn blend(&self) -> &GuideBlend {
        &self.blend
    }

    /// Point count of each guide (a pose gives exactly these).
    pub fn guide_points(&self) -> &[usize] {
        self.blend.guide_points()
    }

    /// Strands `first..first + hairs` of the strand set are the animated sim hairs.
    pub fn strands(&self) -> std::ops::Range<usize> {
        self.first_strand..self.first_strand + self.blend.hairs()
    }

    /// True when a keyed pose drives the rest shapes.
    pub fn has_poses(&self) -> bool {
        !self.poses.is_empty()
    }

    /// The scene's sim weight at `frame`, before the per-hair factor.
    pub fn sim_weight_at(&self, frame: f32) -> f32 {
        self.sim_weight.at(frame)
    }

    /// Per sim hair: the factor of the sim weight curve.
    pub fn factors(&self) -> &[f32] {
        &self.factor
    }

    /// Replaces the per-hair factors (values in [0, 1], one per sim hair; checked by the caller).
    pub(crate) fn set_factors(&mut self, factors: Vec<f32>) {
        self.factor = factors;
    }

    /// Per sim hair: held out of the simulation (follows the guides exactly).
    pub fn hold_out(&self) -> &[bool] {
        &self.hold_out
    }

    /// The lift applied to posed hair, if the scene asks for one.
    pub fn pose_lift(&self) -> Option<&PoseLift> {
        self.lift.as_ref()
    }

    /// The keyed pose at `frame` (between keys each segment's vector is blended and given the
    /// blended length, so guides swing without shrinking), or `None` without keys.
    pub fn pose_at(&self, frame: f32) -> Option<Vec<Vec<Vector3<f32>>>> {
        match key_span(
            self.poses.iter().map(|k| k.frame),
            frame,
            self.interpolation,
        )? {
            Span::At(i) => Some(self.poses[i].shapes.clone()),
            Span::Between(i, s) => Some(
                self.poses[i]
                    .shapes
                    .iter()
                    .zip(&self.poses[i + 1].shapes)
                    .map(|(a, b)| between(a, b, s))
                    .collect(),
            ),
        }
    }

    /// The guides' groom in the space [`GuideAnimation::pose_from_points`] takes (body space of
    /// the scalp at rest, m), every guide's points in order: a host reads it, edits it and
    /// gives it back as a pose.
    pub fn groom_points(&self) -> Vec<[f32; 3]> {
        self.groom
            .iter()
            .zip(&self.frames)
            .flat_map(|(shape, frame)| {
                let root = frame.to_world(&shape[0]);
                shape
                    .iter()
                    .map(move |p| (root + frame.rotation * (p - shape[0])).into())
            })
            .collect()
    }

    /// Host-given guide points (body space of the scalp at rest, the guides in order, each with
    /// its point count, flat) as root-local shapes. Errors name what is wrong and the fix.
    pub fn pose_from_points(
        &self,
        points: &[[f32; 3]],
    ) -> Result<Vec<Vec<Vector3<f32>>>, GuidePointsError> {
        let total: usize = self.guide_points().iter().sum();
        if points.len() != total {
            return Err(GuidePointsError::Count {
                given: points.len(),
                total,
                first_guides: self.guide_points()[..self.guide_count().min(4)].to_vec(),
                guides: self.guide_count(),
            });
        }
        let mut shapes = Vec::with_capacity(self.guide_count());
        let mut at = 0;
        for (g, (&n, frame)) in self.guide_points().iter().zip(&self.frames).enumerate() {
            let curve = &points[at..at + n];
            at += n;
            if let Some(i) = curve.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
                return Err(GuidePointsError::NotFinite { guide: g, point: i });
            }
            let root = Vector3::from(curve[0]);
            let inv = frame.rotation.inverse();
            shapes.push(
                curve
                    .iter()
                    .map(|p| inv * (Vector3::from(*p) - root))
                    .collect(),
            );
        }
        Ok(shapes)
    }

    /// Remembers the built rest state of the sim hairs in `strands` (after sag-free), the base
    /// every pose is applied to.
    pub(crate) fn bind(&mut self, strands: &StrandSet) {
        let range = self.strands();
        let n = self.blend.points();
        let p0 = strands.points(range.start).start;
        let s0 = strands.segments(range.start).start;
        let count = range.len();
        let rest = strands.rest_local()[p0..p0 + count * n].to_vec();
        let bend = strands.bend_rest()[s0..s0 + count * (n - 1)].to_vec();
        let directions = rest.chunks_exact(n).flat_map(rest_directions).collect();
        let mut interpolated = vec![Vector3::zeros(); count * n];
        self.blend.apply(&self.groom, &mut interpolated);
        self.base = Some(Base {
            interpolated,
            rest,
            bend,
            directions,
        });
    }

    /// Sets the sim hairs' rest shapes and rest directions in `strands` to `pose` (root-local
    /// guide shapes, checked): lengths kept, and lifted out of the scalp with a [`PoseLift`]
    /// (see the module docs). Returns the work done (blend operations plus points written:
    /// linear in the points). Call [`GuideAnimation::bind`] first.
    pub(crate) fn apply_pose(
        &self,
        pose: &[Vec<Vector3<f32>>],
        strands: &mut StrandSet,
        scratch: &mut PoseScratch,
    ) -> u64 {
        let Some(base) = &self.base else {
            return 0;
        };
        let n = self.blend.points();
        let range = self.strands();
        let p0 = strands.points(range.start).start;
        let s0 = strands.segments(range.start).start;
        let PoseScratch { blended, lift } = scratch;
        blended.resize(base.interpolated.len(), Vector3::zeros());
        let mut work = self.blend.apply(pose, blended);
        // Hairs are independent here and below: each pass runs over them in parallel (the
        // same bits whatever the thread count).
        let mut posed = base.rest.clone();
        let moved: Vec<bool> = posed
            .par_chunks_exact_mut(n)
            .enumerate()
            .map_init(
                || Vec::with_capacity(n),
                |along, (h, shape)| {
                    let at = h * n..(h + 1) * n;
                    let (built, groom, now) = (
                        &base.rest[at.clone()],
                        &base.interpolated[at.clone()],
                        &blended[at],
                    );
                    if groom == now {
                        return false;
                    }
                    keep_lengths(shape, built, groom, now, along);
                    true
                },
            )
            .collect();
        if let Some(pose_lift) = &self.lift {
            let anchors = &strands.anchors()[range.clone()];
            if lift.len() != moved.len() {
                // The first pose: remember the hair as built, once, so this and later frames
                // look up only what the pose moves near the scalp.
                *lift = vec![LiftMemory::default(); moved.len()];
                pose_lift.remember(anchors, &base.rest, n, lift);
            }
            work += pose_lift.lift(anchors, &mut posed, n, &moved, lift);
        }
        strands.rest_local_mut()[p0..p0 + posed.len()].copy_from_slice(&posed);
        let bend = &mut strands.bend_rest_mut()[s0..s0 + range.len() * (n - 1)];
        // (A hair of one point has no segment to turn; chunks of 0 would not be defined.)
        let segments = (n - 1).max(1);
        bend.par_chunks_exact_mut(segments)
            .zip(base.bend.par_chunks_exact(segments))
            .zip(base.directions.par_chunks_exact(segments))
            .zip(posed.par_chunks_exact(n))
            .for_each(|(((bend, built), groom), shape)| {
                let now = rest_directions(shape);
                for (((out, built), groom), d) in bend.iter_mut().zip(built).zip(groom).zip(&now) {
                    *out = turned(built, groom, d);
                }
            });
        work += 2 * posed.len() as u64;
        work
    }

    /// Effective sim weight of each sim hair at `frame`: the curve (or the host's `weight`) times
    /// the hair's factor; 1 for hold-out hair.
    pub(crate) fn weights(&self, frame: f32, weight: Option<f32>) -> Vec<f32> {
        let w = weight.unwrap_or_else(|| self.sim_weight.at(frame));
        self.factor
            .iter()
            .zip(&self.hold_out)
            .map(|(&f, &h)| if h { 1.0 } else { f * w })
            .collect()
    }

    /// Animated positions of the sim hairs: `roots` (one per strand) placing the current rest
    /// shapes of `strands`.
    pub(crate) fn animated_positions(
        &self,
        strands: &StrandSet,
        roots: &[RootFrame],
    ) -> Vec<Vector3<f32>> {
        let mut out = Vec::new();
        for s in self.strands() {
            for i in strands.points(s) {
                out.push(roots[s].to_world(&strands.rest_local()[i]));
            }
        }
        out
    }

    /// Moves each sim hair by its weight onto the animated guides (see the module docs):
    /// `before` are the animated positions at the previous frame, `fps` the frame rate.
    pub(crate) fn blend_onto(
        &self,
        strands: &mut StrandSet,
        roots: &[RootFrame],
        before: &[Vector3<f32>],
        weights: &[f32],
        fps: f32,
    ) {
        let now = self.animated_positions(strands, roots);
        let n = self.blend.points();
        let p0 = strands.points(self.first_strand).start;
        for (h, &w) in weights.iter().enumerate() {
            if w <= 0.0 {
                continue;
            }
            for j in h * n..(h + 1) * n {
                let (xa, va) = (now[j], (now[j] - before[j]) * fps);
                let (x, v) = (
                    &mut strands.positions[p0 + j],
                    &mut strands.velocities[p0 + j],
                );
                if w >= 1.0 {
                    *x = xa;
                    *v = va;
                } else {
                    *x = *x * (1.0 - w) + xa * w;
                    *v = *v * (1.0 - w) + va * w;
                }
            }
        }
    }
}

/// `shape` (a copy of `built`) moved by the change from `groom` to `now` (its interpolated
/// guides then and now) and re-walked from the root with each segment at its built length and
/// the moved segment's direction (the built one where the moved segment vanishes).
///
/// The change is taken between points at the same fraction of arc length along `groom` and
/// `now` (`along` holds `now` resampled so), not between points of the same index: the blend
/// of swept guides spaces its points unevenly (averaged tip directions shorten the tip
/// segments, the rescale to the mean guide length stretches the root ones: 42 mm at the root to
/// 14 mm at the tip against 25 mm built on one gust hair), and re-walking those index-matched
/// directions at the built lengths bent the posed hair more than its guides (that hair's tip
/// ended 8 cm below the blend's).
fn keep_lengths(
    shape: &mut [Vector3<f32>],
    built: &[Vector3<f32>],
    groom: &[Vector3<f32>],
    now: &[Vector3<f32>],
    along: &mut Vec<Vector3<f32>>,
) {
    resample_like(now, groom, along);
    let moved = |j: usize| built[j] + (along[j] - groom[j]);
    shape[0] = moved(0);
    for j in 1..shape.len() {
        let length = (built[j] - built[j - 1]).norm();
        let d = moved(j) - moved(j - 1);
        let n = d.norm();
        let step = if n > 1e-12 {
            d * (length / n)
        } else {
            built[j] - built[j - 1]
        };
        shape[j] = shape[j - 1] + step;
    }
}

/// `curve` resampled into `out` at the fractions of arc length of `like`'s points (same point
/// count): the root and the tip stay, and a curve spaced like `like` comes back unchanged. A
/// curve or a `like` of zero length is copied as it is.
fn resample_like(curve: &[Vector3<f32>], like: &[Vector3<f32>], out: &mut Vec<Vector3<f32>>) {
    out.clear();
    let length = |c: &[Vector3<f32>]| -> f32 { c.windows(2).map(|w| (w[1] - w[0]).norm()).sum() };
    let (total, total_like) = (length(curve), length(like));
    if !(total > 0.0 && total_like > 0.0) || curve.len() != like.len() {
        out.extend_from_slice(curve);
        return;
    }
    let last = curve.len() - 1;
    let (mut segment, mut start) = (0usize, 0.0f32);
    let mut reached = 0.0f32;
    for j in 0..=last {
        if j > 0 {
            reached += (like[j] - like[j - 1]).norm();
        }
        if j == last {
            out.push(curve[last]);
            break;
        }
        let s = reached / total_like * total;
        // Advance to the segment of `curve` holding arc length `s`.
        while segment < last - 1 && start + (curve[segment + 1] - curve[segment]).norm() < s {
            start += (curve[segment + 1] - curve[segment]).norm();
            segment += 1;
        }
        let l = (curve[segment + 1] - curve[segment]).norm();
        let t = if l > 0.0 {
            ((s - start) / l).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(curve[segment].lerp(&curve[segment + 1], t));
    }
}

/// The guide shape a fraction `s` of the way from `a` to `b` (same point counts): each segment
/// vector blended and given the blended length, the root kept; equal keys give the key exactly. Blending positions instead would
/// shorten a guide that swings through an arc (its tip cuts the chord).
fn between(a: &[Vector3<f32>], b: &[Vector3<f32>], s: f32) -> Vec<Vector3<f32>> {
    if a == b {
        return a.to_vec();
    }
    let mut out = Vec::with_capacity(a.len());
    let mut p = a[0].lerp(&b[0], s);
    out.push(p);
    for (ea, eb) in a.windows(2).zip(b.windows(2)) {
        let (da, db) = (ea[1] - ea[0], eb[1] - eb[0]);
        let d = da.lerp(&db, s);
        let len = da.norm() + (db.norm() - da.norm()) * s;
        let n = d.norm();
        p += if n > 1e-12 { d * (len / n) } else { d };
        out.push(p);
    }
    out
}

/// `built` turned by the smallest rotation taking `from` to `to` (unit directions); `built`
/// itself when they are equal, `to` when they are opposite (no unique rotation).
fn turned(built: &RestDirection, from: &RestDirection, to: &RestDirection) -> RestDirection {
    if from == to {
        return *built;
    }
    let v = |d: &RestDirection| Vector3::new(d.t, d.u, d.w);
    let (a, b, x) = (v(from), v(to), v(built));
    let c = a.dot(&b);
    if c <= -1.0 + 1e-6 {
        return *to;
    }
    let w = a.cross(&b);
    let r = x * c + w.cross(&x) + w * (w.dot(&x) / (1.0 + c));
    RestDirection {
        t: r.x,
        u: r.y,
        w: r.z,
    }
}

/// Why a host's guide points cannot pose the guides ([`GuideAnimation::pose_from_points`]).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum GuidePointsError {
    /// Not every guide's points, or not in the groom's point counts.
    #[error(
        "{given} points, but the {guides} guides have {total} ({first_guides:?}…): give every \
         guide's points in order, keeping each guide's point count"
    )]
    Count {
        /// Points given.
        given: usize,
        /// Points of all the guides.
        total: usize,
        /// The point counts of the first (up to four) guides.
        first_guides: Vec<usize>,
        /// The number of guides.
        guides: usize,
    },
    /// A point is not finite.
    #[error("guide {guide} point {point} is not finite")]
    NotFinite {
        /// The guide.
        guide: usize,
        /// The point on it.
        point: usize,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weight_curve_holds_and_eases() {
        let c = WeightCurve::new(Interpolation::Linear, vec![(1.0, 0.0), (11.0, 1.0)]);
        assert_eq!(c.at(0.0), 0.0);
        assert_eq!(c.at(6.0), 0.5);
        assert_eq!(c.at(30.0), 1.0);
        let e = WeightCurve::new(Interpolation::Ease, vec![(1.0, 0.0), (11.0, 1.0)]);
        assert!(e.at(1.5) < 0.05 * 0.5);
        assert_eq!(WeightCurve::default().at(3.0), 0.0);
    }

    /// The regression: a guide blend bent into a quarter circle but with its points spaced
    /// unevenly (long segments at the root, short at the tip, as a blend of swept guides
    /// spaces them) poses a straight hair onto that quarter circle. Index-matched re-walking at
    /// the hair's even lengths put its points off the arc by centimetres.
    #[test]
    fn a_posed_hair_follows_its_blend_by_arc_length_not_by_point_index() {
        let n = 8;
        let (radius, length) = (0.1f32, 0.1 * std::f32::consts::FRAC_PI_2);
        // Straight up the z axis, evenly spaced: the hair as built, and its blend at groom time.
        let built: Vec<_> = (0..=n)
            .map(|i| Vector3::new(0.0, 0.0, length * i as f32 / n as f32))
            .collect();
        // The pose: the same length bent over a quarter circle about (r, 0, 0), its points at
        // uneven angles (the first segments cover more of the arc than the last).
        let arc =
            |angle: f32| Vector3::new(radius * (1.0 - angle.cos()), 0.0, radius * angle.sin());
        let now: Vec<_> = (0..=n)
            .map(|i| {
                let u = i as f32 / n as f32;
                arc(std::f32::consts::FRAC_PI_2 * (2.0 * u - u * u))
            })
            .collect();
        let mut shape = built.clone();
        let mut along = Vec::new();
        keep_lengths(&mut shape, &built, &built, &now, &mut along);
        // Every posed point lies on the arc within the sag of the blend's coarsest chord,
        // r (1 − cos(Δθ/2)) with Δθ its first segment's 2/8 − 1/64 of the quarter turn (the
        // pose can be no truer than the polygon it is given), with 5 % for the re-walk.
        let first = std::f32::consts::FRAC_PI_2 * (2.0 / n as f32 - 1.0 / (n * n) as f32);
        let sag = 1.05 * radius * (1.0 - (first / 2.0).cos());
        let centre = Vector3::new(radius, 0.0, 0.0);
        for (j, p) in shape.iter().enumerate() {
            let off = ((p - centre).norm() - radius).abs();
            assert!(
                off <= sag + 1e-5,
                "point {j} is {off} m off the arc (sag {sag})"
            );
            if j > 0 {
                let l = (shape[j] - shape[j - 1]).norm();
                assert!((l - length / n as f32).abs() < 1e-6, "segment {j}: {l}");
            }
        }
        // Index-matched (the old walk): a centimetre off the arc.
        let mut old = built.clone();
        keep_lengths(&mut old, &built, &built, &built, &mut along);
        let moved = |j: usize| built[j] + (now[j] - built[j]);
        old[0] = moved(0);
        for j in 1..=n {
            let d = moved(j) - moved(j - 1);
            old[j] = old[j - 1] + d * ((built[j] - built[j - 1]).norm() / d.norm());
        }
        let worst = old
            .iter()
            .map(|p| ((p - centre).norm() - radius).abs())
            .fold(0.0, f32::max);
        assert!(worst > 5e-3, "{worst}");
    }

    #[test]
    fn resampling_keeps_ends_and_an_evenly_spaced_curve() {
        let curve: Vec<_> = (0..6)
            .map(|i| Vector3::new(0.02 * i as f32, 0.01 * (i * i) as f32, 0.0))
            .collect();
        let mut out = Vec::new();
        resample_like(&curve, &curve, &mut out);
        for (a, b) in out.iter().zip(&curve) {
            assert!((a - b).norm() < 1e-6);
        }
        let even: Vec<_> = (0..6).map(|i| Vector3::new(i as f32, 0.0, 0.0)).collect();
        resample_like(&curve, &even, &mut out);
        assert_eq!(out[0], curve[0]);
        assert_eq!(out[5], curve[5]);
    }

    #[test]
    fn poses_between_keys_keep_segment_lengths() {
        // A straight guide swung by 90°: halfway, blended positions would shorten it to 71 %.
        let a: Vec<_> = (0..5)
            .map(|i| Vector3::new(0.0, 0.0, 0.1 * i as f32))
            .collect();
        let b: Vec<_> = (0..5)
            .map(|i| Vector3::new(0.1 * i as f32, 0.0, 0.0))
            .collect();
        let mid = between(&a, &b, 0.5);
        for w in mid.windows(2) {
            assert!(((w[1] - w[0]).norm() - 0.1).abs() < 1e-6);
        }
        // Equal keys give the key itself, bit for bit (a held pose changes no rest value).
        assert_eq!(between(&a, &a, 0.3), a);
    }

    #[test]
    fn turned_is_the_smallest_rotation() {
        let d = |t: f32, u: f32, w: f32| RestDirection { t, u, w };
        // Groom along t, pose along u: a built direction along t goes to u, one along w stays.
        let r = turned(&d(1.0, 0.0, 0.0), &d(1.0, 0.0, 0.0), &d(0.0, 1.0, 0.0));
        assert!(
            (r.t).abs() < 1e-6 && (r.u - 1.0).abs() < 1e-6 && r.w.abs() < 1e-6,
            "{r:?}"
        );
        let r = turned(&d(0.0, 0.0, 1.0), &d(1.0, 0.0, 0.0), &d(0.0, 1.0, 0.0));
        assert!((r.w - 1.0).abs() < 1e-6, "{r:?}");
        // Equal directions keep the built one bit for bit.
        let b = d(0.3, 0.4, 0.5);
        assert_eq!(turned(&b, &d(1.0, 0.0, 0.0), &d(1.0, 0.0, 0.0)), b);
    }
}
