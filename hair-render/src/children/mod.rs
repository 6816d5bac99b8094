//! Children on request: how many, where, and the one generation pass for every level of detail.
//!
//! [`generate`] takes parents at one instant ([`Parents`]: a cached frame, a sub-frame sample or
//! the rest state), [`ChildSettings`] and a [`Lod`], and returns [`ChildBuffers`]. Two
//! distributions ([`ChildMode`]): [`simple`] children grouped around one parent, and
//! [`interpolated`] children blended from several parents. Both grow through one kernel (`grow`):
//! what the children of a parent share is tabulated once per parent, and every child is written
//! straight into its place in the output (offsets known from the counts), so memory is the output
//! plus, per thread, one parent path (simple) or every parent's path (shared) and the current
//! parent's candidates' offsets (interpolated). Parents run in parallel on the caller's rayon
//! pool; the output does not depend on the thread count.

mod grow;
pub mod interpolated;
mod neighbours;
pub mod simple;

use hair_par::prelude::*;

use crate::buffers::ChildBuffers;
use crate::error::{parameter, Result};
use crate::lod::{check_subdivisions, Lod};
use crate::parents::Parents;
use crate::path::ParentPath;
use crate::rng::{ChildRng, Purpose};
use crate::shape::Shape;
use crate::subdivide::{catmull_rom, subdivided_len};
use grow::{Profile, Scratch};
use interpolated::{Blend, Interpolator, MAX_NEIGHBOURS};

/// How children are distributed and shaped from their parents.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ChildMode {
    /// Grouped around one parent, following its path ([`simple`]).
    #[default]
    Simple,
    /// Rooted between parents, shaped as a blend of the nearest ones ([`interpolated`]).
    Interpolated {
        /// Parents blended per child, 1–8 (4 is a good start).
        neighbours: u32,
    },
}

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
    /// Simple or interpolated children.
    pub mode: ChildMode,
}

impl Default for ChildSettings {
    /// 10 simple children per parent in a 5 mm disc, seed 0, 4 pieces per segment, default
    /// shape.
    fn default() -> Self {
        Self {
            count: ChildCount::PerParent(10),
            spread: 0.005,
            seed: 0,
            subdivisions: 4,
            shape: Shape::default(),
            mode: ChildMode::Simple,
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
        if let ChildMode::Interpolated { neighbours } = self.mode {
            if !(1..=MAX_NEIGHBOURS).contains(&neighbours) {
                return Err(parameter(
                    "neighbours",
                    neighbours,
                    "blend 1 to 8 parents per interpolated child (e.g. 4)",
                ));
            }
        }
        self.shape.validate()
    }
}

/// Generates the children of `parents` at level `lod`. Refuses bad settings (naming the
/// parameter) and a total of more than 2³² − 1 curves.
pub fn generate(parents: &Parents, settings: &ChildSettings, lod: Lod) -> Result<ChildBuffers> {
    let mut out = ChildBuffers::default();
    generate_into(parents, settings, lod, &mut out)?;
    Ok(out)
}

/// [`generate`] into `out`, reusing its allocations: a host that generates children frame after
/// frame with the same counts writes into the same memory, with no new pages to map and clear.
/// Every array of `out` is overwritten (resized to the new counts); on error `out` is unchanged.
pub fn generate_into(
    parents: &Parents,
    settings: &ChildSettings,
    lod: Lod,
    out: &mut ChildBuffers,
) -> Result<()> {
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

    // Every element is written below, so sizes that already fit are left as they are.
    fit(&mut out.vertex_counts, curves);
    fit(&mut out.points, 3 * total_points);
    fit(&mut out.widths, total_points);
    fit(&mut out.parent, curves);
    fit(&mut out.random, curves);
    let optional = |v: &mut Option<Vec<f32>>, wanted: bool, len: usize| {
        if wanted {
            fit(v.get_or_insert_with(Vec::new), len);
        } else {
            *v = None;
        }
    };
    optional(&mut out.root_uv, parents.has_uvs(), 2 * curves);
    optional(&mut out.color, parents.has_colors(), 3 * curves);
    let jobs = Job::split(out, &shown, &per_child);
    let seed = settings.seed;
    match settings.mode {
        ChildMode::Simple => jobs.into_par_iter().for_each_init(
            || {
                (
                    ParentPath::default(),
                    Profile::default(),
                    Scratch::default(),
                )
            },
            |(path, profile, scratch), mut job| {
                let p = job.parent;
                path.points.clear();
                catmull_rom(parents.points(p), steps, &mut path.points);
                let root = parents.root(p);
                path.build_frames(&root.frame);
                let spread = parents.spread(p, settings.spread);
                let shape = parents.shape(p, &settings.shape);
                profile.build(&shape, per_child[p]);
                for k in 0..job.children() {
                    let rng = ChildRng::new(seed, p as u32, k as u32);
                    let (pts, wid) = job.curve(k, &rng, &root);
                    simple::grow_simple(path, profile, spread, &shape, &rng, scratch, pts, wid);
                }
            },
        ),
        ChildMode::Interpolated { neighbours } => {
            let interp = Interpolator::new(parents, steps, neighbours as usize);
            jobs.into_par_iter().for_each_init(
                || (Profile::default(), Scratch::default(), Blend::default()),
                |(profile, scratch, blend), mut job| {
                    let p = job.parent;
                    let spread = parents.spread(p, settings.spread);
                    let shape = parents.shape(p, &settings.shape);
                    profile.build(&shape, interp.path(p).points.len());
                    interp.prepare(p, blend);
                    for k in 0..job.children() {
                        let rng = ChildRng::new(seed, p as u32, k as u32);
                        let n = job.points_per_child;
                        let (pts, wid) = job.slices(k);
                        let root =
                            interp.grow(p, profile, spread, &shape, &rng, scratch, blend, pts, wid);
                        job.attributes(k, n, &rng, &root);
                    }
                },
            );
        }
    }
    Ok(())
}

/// Makes `v` `len` long. Without the capacity, a new zeroed allocation: its pages are mapped
/// lazily, by the worker that first writes them, instead of zeroed here on one thread.
fn fit<T: Copy + Default>(v: &mut Vec<T>, len: usize) {
    if v.capacity() < len {
        *v = vec![T::default(); len];
    } else {
        v.resize(len, T::default());
    }
}

/// One parent's disjoint share of the output buffers.
struct Job<'a> {
    parent: usize,
    points_per_child: usize,
    points: &'a mut [f32],
    widths: &'a mut [f32],
    counts: &'a mut [u32],
    parents: &'a mut [u32],
    random: &'a mut [f32],
    uv: Option<&'a mut [f32]>,
    color: Option<&'a mut [f32]>,
}

/// Splits the first `n` items off `slice`.
fn take<'a, T>(slice: &mut &'a mut [T], n: usize) -> &'a mut [T] {
    let (a, b) = std::mem::take(slice).split_at_mut(n);
    *slice = b;
    a
}

impl<'a> Job<'a> {
    /// One job per parent with children, over `out` laid out by `shown` and `per_child`.
    fn split(out: &'a mut ChildBuffers, shown: &[u32], per_child: &[usize]) -> Vec<Job<'a>> {
        let mut points = out.points.as_mut_slice();
        let mut widths = out.widths.as_mut_slice();
        let mut counts = out.vertex_counts.as_mut_slice();
        let mut parents = out.parent.as_mut_slice();
        let mut random = out.random.as_mut_slice();
        let mut uv = out.root_uv.as_deref_mut();
        let mut color = out.color.as_deref_mut();
        let mut jobs = Vec::with_capacity(shown.len());
        for (p, (&c, &n)) in shown.iter().zip(per_child).enumerate() {
            if c == 0 {
                continue;
            }
            let c = c as usize;
            jobs.push(Job {
                parent: p,
                points_per_child: n,
                points: take(&mut points, 3 * c * n),
                widths: take(&mut widths, c * n),
                counts: take(&mut counts, c),
                parents: take(&mut parents, c),
                random: take(&mut random, c),
                uv: uv.as_mut().map(|s| take(s, 2 * c)),
                color: color.as_mut().map(|s| take(s, 3 * c)),
            });
        }
        jobs
    }

    /// Number of children of this job.
    fn children(&self) -> usize {
        self.counts.len()
    }

    /// Points and widths of child `k`.
    fn slices(&mut self, k: usize) -> (&mut [f32], &mut [f32]) {
        let n = self.points_per_child;
        (
            &mut self.points[3 * k * n..3 * (k + 1) * n],
            &mut self.widths[k * n..(k + 1) * n],
        )
    }

    /// Writes child `k`'s per-curve attributes (`n` points, root `root`).
    fn attributes(
        &mut self,
        k: usize,
        n: usize,
        rng: &ChildRng,
        root: &crate::parents::ParentRoot,
    ) {
        self.counts[k] = n as u32;
        self.parents[k] = self.parent as u32;
        self.random[k] = rng.unit(Purpose::Value, 0);
        if let Some(uv) = self.uv.as_deref_mut() {
            let v = root.uv.unwrap_or_default();
            uv[2 * k..2 * k + 2].copy_from_slice(&[v.x, v.y]);
        }
        if let Some(c) = self.color.as_deref_mut() {
            c[3 * k..3 * k + 3].copy_from_slice(&root.color.unwrap_or([1.0; 3]));
        }
    }

    /// Writes child `k`'s attributes and returns its points and widths.
    fn curve(
        &mut self,
        k: usize,
        rng: &ChildRng,
        root: &crate::parents::ParentRoot,
    ) -> (&mut [f32], &mut [f32]) {
        let n = self.points_per_child;
        self.attributes(k, n, rng, root);
        self.slices(k)
    }
}
