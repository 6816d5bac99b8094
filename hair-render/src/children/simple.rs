//! Simple children: grouped around one parent.
//!
//! A child's root is drawn uniformly in a disc of the parent's spread radius in the tangent plane
//! of the parent's root frame (offset `(a, b)` along the frame's x and y axes). Along the length
//! the offset is carried by the parent's parallel-transported frames (`a u + b w`, see
//! `path`) and scaled by the clump profile; curl and roughness follow
//! ([`crate::shape`]). A shortened child (length variation) follows its parent's path up to its
//! own length, its points spread evenly in the parent's point parameter.

use std::f32::consts::TAU;

use crate::path::ParentPath;
use crate::rng::{ChildRng, Purpose};
use crate::shape::{length, Shape};

/// What every child of one parent shares at point `i`: the profiles along the normalized length
/// `s_i = i / (n − 1)`, tabulated once per parent instead of once per child point.
#[derive(Debug, Clone, Default)]
pub(crate) struct Profile {
    /// Normalized length of each point.
    s: Vec<f32>,
    /// Clump scale of the root offset.
    clump: Vec<f32>,
    /// Root ramp of curl and roughness.
    ramp: Vec<f32>,
    /// Endpoint roughness profile.
    endpoint: Vec<f32>,
    /// Width, meters.
    width: Vec<f32>,
}

impl Profile {
    /// Tabulates `shape` for children of `n ≥ 2` points.
    pub(crate) fn build(&mut self, shape: &Shape, n: usize) {
        let inv = 1.0 / (n - 1) as f32;
        self.s.clear();
        self.s.extend((0..n).map(|i| i as f32 * inv));
        let fill = |v: &mut Vec<f32>, f: &dyn Fn(f32) -> f32, s: &[f32]| {
            v.clear();
            v.extend(s.iter().map(|&x| f(x)));
        };
        fill(&mut self.clump, &|x| shape.clump.offset_scale(x), &self.s);
        fill(&mut self.ramp, &|x| shape.ramp(x), &self.s);
        fill(
            &mut self.endpoint,
            &|x| shape.roughness.endpoint_profile(x),
            &self.s,
        );
        fill(&mut self.width, &|x| shape.taper.width(x), &self.s);
    }
}

/// Writes one child of `path` into `points` (x y z interleaved, meters) and `widths` (meters);
/// both slices hold exactly the child's points, as many as `profile` was built for.
pub(crate) fn grow(
    path: &ParentPath,
    profile: &Profile,
    spread: f32,
    shape: &Shape,
    rng: &ChildRng,
    points: &mut [f32],
    widths: &mut [f32],
) {
    let r = spread * rng.unit(Purpose::DiscRadius, 0).sqrt();
    let (sin, cos) = (TAU * rng.unit(Purpose::DiscAngle, 0)).sin_cos();
    let (a, b) = (r * cos, r * sin);
    let lf = length::factor(shape.length_variation, rng);
    let phase = TAU * rng.unit(Purpose::CurlPhase, 0);
    let end = shape.roughness.endpoint_direction(rng);
    let scale = lf * (path.points.len() - 1) as f32;
    let curl = !shape.curl.is_off();
    let rough = !shape.roughness.is_off();
    widths.copy_from_slice(&profile.width);
    for (i, p) in points.chunks_exact_mut(3).enumerate() {
        let (base, u, v, arc) = path.at(profile.s[i] * scale);
        let mut q = base + (u * a + v * b) * profile.clump[i];
        let ramp = profile.ramp[i];
        if curl {
            q += shape.curl.offset(arc, ramp, phase, &u, &v);
        }
        if rough {
            q += shape
                .roughness
                .offset(rng, end, profile.endpoint[i], arc, ramp, &u, &v);
        }
        p.copy_from_slice(q.as_slice());
    }
}
