//! Children on request: how many, where, and the one generation pass for every level of detail.
//!
//! [`generate`] takes parents at one instant ([`Parents`]: a cached frame, a sub-frame sample or
//! the rest state), [`ChildSettings`] and a [`Lod`], and returns [`ChildBuffers`]. Per parent it
//! subdivides the polyline ([`crate::subdivide`]), builds the transported frames
//! (`path`) and grows each child ([`simple`]). Parents run in parallel on the caller's
//! rayon pool; the output does not depend on the thread count. Memory is the output plus one
//! parent path per thread.

pub mod simple;

use rayon::prelude::*;

use crate::buffers::ChildBuffers;
use crate::error::{parameter, Result};
use crate::lod::{check_subdivisions, Lod};
use crate::parents::Parents;
use crate::path::ParentPath;
use crate::rng::{ChildRng, Purpose};
use crate::shape::Shape;
use crate::subdivide::{catmull_rom, subdivided_len};

/// How many children to make.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChildCount {
    /// This many children around every parent (≥ 1).
    PerParent(u32),
    /// This many children in all (≥ 1), spread evenly over the parents (parent `p` gets
    /// `⌊N(p+1)/P⌋ − ⌊Np/P⌋`).
    Total(u64),
}

impl ChildCount {
    /// Children of parent `p` out of `parents` (at render level).
    pub fn for_parent(&self, p: usize, parents: usize) -> u32 {
        match *self {
            ChildCount::PerParent(n) => n,
            ChildCount::Total(n) => {
                let at = |q: usize| (u128::from(n) * q as u128 / parents as u128) as u64;
                (at(p + 1) - at(p)) as u32
            }
        }
    }
}

/// Settings of child generation (render level; [`Lod`] reduces them for display).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChildSettings {
    /// How many children.
    pub count: ChildCount,
    /// Radius of the disc around each parent's root that its children are rooted in, meters
    /// (per-parent radii given with [`Parents::with_spread_radii`] take precedence).
    pub spread: f32,
    /// Seed: the same seed gives bit-identical children, another seed other children.
    pub seed: u64,
    /// Catmull–Rom pieces per parent segment at render level (1–64; 1 keeps the parent's points).
    pub subdivisions: u32,
    /// Clump, curl, roughness, length variation and taper.
    pub shape: Shape,
}

impl Default for ChildSettings {
    /// 10 children per parent in a 5 mm disc, seed 0, 4 pieces per segment, default shape.
    fn default() -> Self {
        Self {
            count: ChildCount::PerParent(10),
            spread: 0.005,
            seed: 0,
            subdivisions: 4,
            shape: Shape::default(),
        }
    }
}

impl ChildSettings {
    /// Checks every setting, naming the first bad one and its fix.
    pub fn validate(&self) -> Result<()> {
        match self.count {
            ChildCount::PerParent(0) => {
                return Err(parameter(
                    "children_per_parent",
                    0,
                    "give at least 1 child per parent",
                ))
            }
            ChildCount::Total(0) => {
                return Err(parameter("count", 0, "give at least 1 child in all"))
            }
            _ => {}
        }
        if !(self.spread.is_finite() && (0.0..=1.0).contains(&self.spread)) {
            return Err(parameter(
                "spread",
                self.spread,
                "use a radius in meters in [0, 1], e.g. 0.005",
            ));
        }
        check_subdivisions("subdivisions", self.subdivisions)?;
        self.shape.validate()
    }
}

/// Generates the children of `parents` at level `lod`. Refuses bad settings (naming the
/// parameter) and a total of more than 2³² − 1 curves.
pub fn generate(parents: &Parents, settings: &ChildSettings, lod: Lod) -> Result<ChildBuffers> {
    settings.validate()?;
    lod.validate()?;
    let np = parents.len();
    let steps = lod.subdivisions(settings.subdivisions);
    let shown: Vec<u32> = (0..np)
        .map(|p| lod.children_shown(settings.count.for_parent(p, np)))
        .collect();
    let per_child: Vec<usize> = (0..np)
        .map(|p| subdivided_len(parents.points(p).len(), steps))
        .collect();
    let curves: u64 = shown.iter().map(|&c| u64::from(c)).sum();
    if curves > u64::from(u32::MAX) {
        return Err(parameter(
            "count",
            curves,
            "at most 4 294 967 295 children per export: lower the count",
        ));
    }
    let total_points: usize = (0..np).map(|p| shown[p] as usize * per_child[p]).sum();
    let curves = curves as usize;

    let mut out = ChildBuffers {
        vertex_counts: Vec::with_capacity(curves),
        points: vec![0.0; 3 * total_points],
        widths: vec![0.0; total_points],
        parent: Vec::with_capacity(curves),
        random: Vec::with_capacity(curves),
        root_uv: parents.has_uvs().then(|| Vec::with_capacity(2 * curves)),
        color: parents.has_colors().then(|| Vec::with_capacity(3 * curves)),
    };
    for p in 0..np {
        let root = parents.root(p);
        for k in 0..shown[p] {
            out.vertex_counts.push(per_child[p] as u32);
            out.parent.push(p as u32);
            let rng = ChildRng::new(settings.seed, p as u32, k);
            out.random.push(rng.unit(Purpose::Value, 0));
            if let Some(uv) = &mut out.root_uv {
                let v = root.uv.unwrap_or_default();
                uv.extend_from_slice(&[v.x, v.y]);
            }
            if let Some(c) = &mut out.color {
                c.extend_from_slice(&root.color.unwrap_or([1.0; 3]));
            }
        }
    }

    // One disjoint slice of points and widths per parent, grown in parallel.
    let mut jobs = Vec::with_capacity(np);
    let (mut pts, mut wid) = (out.points.as_mut_slice(), out.widths.as_mut_slice());
    for p in 0..np {
        let n = shown[p] as usize * per_child[p];
        let (a, rest_p) = pts.split_at_mut(3 * n);
        let (b, rest_w) = wid.split_at_mut(n);
        pts = rest_p;
        wid = rest_w;
        jobs.push((p, a, b));
    }
    jobs.into_par_iter().for_each_init(
        || (ParentPath::default(), simple::Profile::default()),
        |(path, profile), (p, pts, wid)| {
            if wid.is_empty() {
                return;
            }
            path.points.clear();
            catmull_rom(parents.points(p), steps, &mut path.points);
            path.build_frames(&parents.root(p).frame);
            let spread = parents.spread(p, settings.spread);
            let n = per_child[p];
            profile.build(&settings.shape, n);
            for (k, (cp, cw)) in pts.chunks_mut(3 * n).zip(wid.chunks_mut(n)).enumerate() {
                let rng = ChildRng::new(settings.seed, p as u32, k as u32);
                simple::grow(path, profile, spread, &settings.shape, &rng, cp, cw);
            }
        },
    );
    Ok(out)
}
