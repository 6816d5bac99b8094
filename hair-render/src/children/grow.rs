//! The per-child kernel both distributions share: walk a parent path, add the child's offset
//! (scaled by the clump profile), curl and roughness, write points and widths in place.
//!
//! Everything the children of one parent share is tabulated once per parent ([`Profile`]: clump,
//! root ramp, endpoint and width profiles along the normalized length). Per point, the kernel does
//! one path lookup, one quarter-turn-reduced polynomial sin/cos for the curl (no libm call) and
//! about two hashes for the noise lattices (memoised along the child, see
//! [`crate::shape::roughness`]); it allocates nothing and writes straight into the output slices.

use nalgebra::Vector3;

use crate::path::ParentPath;
use crate::rng::{ChildRng, Purpose};
use crate::shape::{length, Shape};

/// What every child of one parent shares at point `i`: the profiles along the normalized length
/// `s_i = i / (n − 1)`, tabulated once per parent instead of once per child point.
#[derive(Debug, Clone, Default)]
pub(crate) struct Profile {
    /// Normalized length of each point.
    s: Vec<f32>,
    /// Clump scale of the child's offset from the parent.
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

/// The path of the parent a child follows, at one of the child's points.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PathPoint {
    /// Fractional point index along the parent path.
    pub x: f32,
    /// The parent's point there, meters.
    pub base: Vector3<f32>,
    /// Transported normal there.
    pub u: Vector3<f32>,
    /// Binormal there.
    pub w: Vector3<f32>,
}

/// Per-thread working space of [`grow`]: one child's path samples and curl + roughness offsets,
/// kept in arrays so the curl's sin/cos runs as one branch-free loop the compiler vectorizes.
#[derive(Debug, Clone, Default)]
pub(crate) struct Scratch {
    at: Vec<PathPoint>,
    arc: Vec<f32>,
    a: Vec<f32>,
    b: Vec<f32>,
}

/// Writes one child following `path` into `points` (x y z interleaved, meters) and `widths`
/// (meters); both slices hold exactly the child's points, as many as `profile` was built for.
/// `offset` gives the child's unclumped offset from the parent's point (meters).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn grow(
    path: &ParentPath,
    profile: &Profile,
    shape: &Shape,
    rng: &ChildRng,
    scratch: &mut Scratch,
    points: &mut [f32],
    widths: &mut [f32],
    mut offset: impl FnMut(&PathPoint) -> Vector3<f32>,
) {
    let n = widths.len();
    let lf = length::factor(shape.length_variation, rng);
    let scale = lf * (path.points.len() - 1) as f32;
    widths.copy_from_slice(&profile.width);
    let Scratch { at, arc, a, b } = scratch;
    at.clear();
    arc.clear();
    for &s in &profile.s[..n] {
        let x = s * scale;
        let (base, u, w, length) = path.at(x);
        at.push(PathPoint { x, base, u, w });
        arc.push(length);
    }
    a.clear();
    b.clear();
    a.resize(n, 0.0);
    b.resize(n, 0.0);
    if !shape.curl.is_off() {
        let phase = rng.unit(Purpose::CurlPhase, 0);
        let curl = shape.curl;
        for (((a, b), &arc), &ramp) in a.iter_mut().zip(b.iter_mut()).zip(&*arc).zip(&profile.ramp)
        {
            (*a, *b) = curl.offset(arc, ramp, phase);
        }
    }
    if !shape.roughness.is_off() {
        shape
            .roughness
            .add(rng, &profile.endpoint, arc, &profile.ramp, a, b);
    }
    for (i, (p, at)) in points.chunks_exact_mut(3).zip(at.iter()).enumerate() {
        let q = at.base + offset(at) * profile.clump[i] + at.u * a[i] + at.w * b[i];
        p[0] = q.x;
        p[1] = q.y;
        p[2] = q.z;
    }
}
