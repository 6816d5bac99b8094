//! Simple children: grouped around one parent.
//!
//! A child's root is drawn uniformly in a disc of the parent's spread radius in the tangent plane
//! of the parent's root frame (offset `(a, b)` along the frame's x and y axes). Along the length
//! the offset is carried by the parent's parallel-transported frames (`a u + b w`, see
//! `path`) and scaled by the clump profile; curl and roughness follow
//! ([`crate::shape`]). A shortened child (length variation) follows its parent's path up to its
//! own length, its points spread evenly in the parent's point parameter.

use crate::children::grow::{grow, Profile, Scratch};
use crate::path::ParentPath;
use crate::rng::{ChildRng, Purpose};
use crate::shape::curl::sin_cos_turns;
use crate::shape::Shape;

/// The child's root offset `(a, b)` in the root frame's tangent plane: uniform in the disc of
/// radius `spread` (meters).
#[inline(always)]
pub(crate) fn disc_offset(spread: f32, rng: &ChildRng) -> (f32, f32) {
    let r = spread * rng.unit(Purpose::DiscRadius, 0).sqrt();
    let (sin, cos) = sin_cos_turns(rng.unit(Purpose::DiscAngle, 0));
    (r * cos, r * sin)
}

/// Writes one simple child of `path` into `points` (x y z interleaved, meters) and `widths`
/// (meters); both slices hold exactly the child's points, as many as `profile` was built for.
#[allow(clippy::too_many_arguments)]
pub(crate) fn grow_simple(
    path: &ParentPath,
    profile: &Profile,
    spread: f32,
    shape: &Shape,
    rng: &ChildRng,
    scratch: &mut Scratch,
    points: &mut [f32],
    widths: &mut [f32],
) {
    let (a, b) = disc_offset(spread, rng);
    grow(path, profile, shape, rng, scratch, points, widths, |at| {
        at.u * a + at.w * b
    });
}
