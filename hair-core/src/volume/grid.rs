//! The voxel grid of hair–hair interaction: point mass, momentum and volume splatted trilinearly
//! onto the nodes of a **sparse** grid, stored as bricks of [`BRICK`]³ nodes allocated only where
//! points splat. Memory and cost follow the occupied cells, not the hair's bounding box: two
//! clumps 10 m apart cost what each clump costs alone.
//!
//! **Layout.** Node `(i, j, k)` sits at `origin + cell·(i, j, k)`, the origin a cell and a half
//! below the hair's bounding box, so the cells (and every trilinear weight) are those of a dense
//! grid over that box. A brick holds nodes `BRICK·b ..< BRICK·(b + 1)` per axis and is named by a
//! key packing its three coordinates in 16 bits each (z highest), so a grid spans at most
//! [`MAX_NODES_PER_AXIS`] nodes per axis. Grid coordinates are computed in f64, so the weights
//! keep their precision far from the origin.
//!
//! **Build, per step.**
//! 1. Every point's base cell (the cell holding it) gives its *source* brick and its *spill* (the
//!    axes along which its stencil leaves that brick); the pairs `(source key and spill, point)`
//!    are put in order, so each source brick lists its points by spill, then in point order. When
//!    the box of bricks over the span is small (at most one brick per [`POINTS_PER_DENSE_BRICK`]
//!    points plus [`DENSE_BRICKS_EXTRA`], so its histogram costs less than the pairs; hair around
//!    a head: a few hundred occupied bricks in a box of about a thousand) a counting pass does it
//!    in linear time: a histogram over every (brick of the box, spill), its running sum, and one
//!    scatter in point order. A sparse grid whose box is
//!    large (clumps far apart) sorts the pairs instead (a stable merge sort that runs through the
//!    last step's, nearly sorted, order). The pairs are distinct, so both give the same order.
//! 2. A point's 2 × 2 × 2 stencil reaches the next brick along an axis only from the last cell
//!    layer of its source brick; the allocated bricks are the sources plus those neighbours
//!    (sorted and deduplicated keys). Their storage is a `Vec` reused between steps.
//! 3. **Deterministic splat without atomics**: every brick *gathers* into its own nodes from the
//!    (up to 8) source bricks whose points reach it (only the points that spill towards it), in
//!    a fixed order of sources, then by spill, then in point order. Bricks fill in parallel and
//!    every node sums its contributions in one fixed order, bit-identical for any thread count.
//!
//! Sampling at a point of the build uses the bricks linked to its source (no search); at any
//! other position it finds them by binary search in the sorted keys (a missing brick reads as
//! empty). The grid is refused when its occupied bricks would take more than
//! [`MAX_GRID_BYTES`] or its span more than [`MAX_NODES_PER_AXIS`] nodes; the error names both
//! figures and the smallest cell size (within a factor 1.25) that fits.

use hair_par::prelude::*;
use nalgebra::Vector3;

use crate::error::{HairError, Result};

/// Nodes per brick edge.
pub const BRICK: usize = 4;

/// Nodes per brick.
const BRICK_NODES: usize = BRICK * BRICK * BRICK;

/// Bits per axis of a brick key.
const KEY_BITS: u32 = 16;

/// Most grid nodes along one axis (bricks are keyed with 16 bits per axis): 262 m at 1 mm cells.
pub const MAX_NODES_PER_AXIS: u64 = (BRICK as u64) << KEY_BITS;

/// The box of bricks over the span may hold one brick per this many points for the counting pass
/// (see the module doc; its histogram, 8 × 4 bytes per brick, then costs at most a quarter of the
/// 16-byte pairs); larger boxes are sorted.
const POINTS_PER_DENSE_BRICK: u64 = 8;

/// Bricks the box may hold for the counting pass on top of one per [`POINTS_PER_DENSE_BRICK`]
/// points (a histogram of at most 512 KiB).
const DENSE_BRICKS_EXTRA: u64 = 1 << 14;

/// Empty cells kept around the hair's bounding box on every side.
const MARGIN_CELLS: u64 = 1;

/// Largest node storage a step may allocate, bytes (the occupied bricks' node data).
pub const MAX_GRID_BYTES: u64 = 1 << 30;

/// Channels per node: mass (kg), momentum (kg·m/s, 3), hair volume (m³).
const CHANNELS: usize = 5;

/// Bytes per node.
const NODE_BYTES: u64 = (CHANNELS * std::mem::size_of::<f32>()) as u64;

/// Bytes per brick.
const BRICK_BYTES: u64 = NODE_BYTES * BRICK_NODES as u64;

/// A sparse grid over the hair, rebuilt every collision step (see the module doc).
///
/// Each allocated node holds the hair mass (kg), momentum (kg·m/s) and volume (m³) splatted onto
/// it with trilinear weights.
#[derive(Debug, Clone, Default)]
pub struct VoxelGrid {
    /// Node (0, 0, 0), m.
    origin: Vector3<f64>,
    cell: f32,
    inv_cell: f64,
    /// Nodes per axis of the span (the bounding box plus margins).
    dims: [u64; 3],
    /// Base cell and position within it (0–1 per axis) of every point.
    cells: Vec<([u32; 3], [f32; 3])>,
    /// `(source brick key · 8 + spill, point index)`, sorted (see [`spill`]); kept between
    /// steps, where it is nearly sorted already.
    order: Vec<(u64, u32)>,
    /// Scratch of the counting pass: the histogram over every (brick of the span's box, spill)
    /// and its running sum.
    bucket_start: Vec<u32>,
    /// Distinct source brick keys, sorted.
    sources: Vec<u64>,
    /// Where the points of source `s` with spill `m` start in `order`: entry `8·s + m` (one more
    /// entry: the end).
    source_start: Vec<u32>,
    /// Source index of every point.
    point_source: Vec<u32>,
    /// Keys of the allocated bricks, sorted.
    bricks: Vec<u64>,
    /// Per source, the index in `bricks` of the source plus `d` for `d` in {0, 1}³ (bit `a` of
    /// the entry's index: +1 along axis `a`), [`NO_BRICK`] where none is allocated.
    links: Vec<[u32; 8]>,
    /// Per brick, the source at the brick minus `d` (indexed as in `links`) whose points reach
    /// it, [`NO_BRICK`] where none does.
    feeds: Vec<[u32; 8]>,
    /// Node data, [`BRICK`]³ nodes per brick in the order of `bricks`; node `(i, j, k)` of a
    /// brick at `i + BRICK·(j + BRICK·k)`.
    nodes: Vec<[f32; CHANNELS]>,
    /// What the splat needs of each point, in the sorted order of `order`: the bricks read
    /// their points from it in sequence instead of from four per-point arrays at random.
    splat_order: Vec<SplatPoint>,
}

/// A point as the splat reads it: its base cell and position in it, and what it carries.
#[derive(Debug, Clone, Copy)]
struct SplatPoint {
    /// Base cell (global node coordinates of its lower corner).
    cell: [u32; 3],
    /// Position within the base cell, 0–1 per axis.
    frac: [f32; 3],
    /// Mass, kg.
    mass: f32,
    /// Momentum, kg·m/s.
    momentum: Vector3<f32>,
    /// Hair volume, m³.
    volume: f32,
}

/// What the grid says at one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridSample {
    /// Mass-weighted grid velocity at the point, m/s (`None` where no mass was splatted).
    pub velocity: Option<Vector3<f32>>,
    /// Hair volume fraction at the point (0–1 for non-overlapping hair; dimensionless).
    pub density: f32,
    /// Gradient of the density in excess of the target, 1/m (zero where the density around is
    /// below the target).
    pub excess_gradient: Vector3<f32>,
}

/// The hair splatted onto one grid node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridNode {
    /// Mass, kg.
    pub mass: f32,
    /// Momentum, kg·m/s.
    pub momentum: Vector3<f32>,
    /// Hair volume, m³.
    pub volume: f32,
}

/// Point data splatted onto the grid (all slices one value per point).
#[derive(Debug, Clone, Copy)]
pub struct SplatInput<'a> {
    /// Positions, m.
    pub positions: &'a [Vector3<f32>],
    /// Velocities, m/s.
    pub velocities: &'a [Vector3<f32>],
    /// Masses, kg (0 contributes no momentum).
    pub masses: &'a [f32],
    /// Hair volume each point stands for, m³.
    pub volumes: &'a [f32],
}

/// What a grid of one cell size over given points would take.
#[derive(Debug, Clone, Copy)]
struct Usage {
    /// Nodes per axis of the span.
    dims: [u64; 3],
    /// Occupied bricks (`None` when the span is beyond the keys).
    bricks: Option<u64>,
}

impl Usage {
    fn fits(&self) -> bool {
        self.dims.iter().all(|&d| d <= MAX_NODES_PER_AXIS)
            && self
                .bricks
                .is_some_and(|b| b.saturating_mul(BRICK_BYTES) <= MAX_GRID_BYTES)
    }
}

/// A link to a brick that is not allocated.
const NO_BRICK: u32 = u32::MAX;

/// The axes along which the stencil of a point in base cell `c` reaches the next brick (bit `a`
/// set when `c` is in its brick's last layer along axis `a`).
fn spill(c: [u32; 3]) -> u64 {
    (0..3).fold(0, |m, a| {
        m | (((c[a] as usize % BRICK == BRICK - 1) as u64) << a)
    })
}

/// The `order` key of a point in base cell `c`: its source brick's key times 8 plus its spill.
fn pair_key(c: [u32; 3]) -> u64 {
    (key(c.map(|c| c / BRICK as u32)) << 3) | spill(c)
}

/// Fills `order` with the pairs `(pair key, point)` of the points in base cells `cells`, in
/// increasing order, by counting: `box_bricks` are the bricks per axis of the span's box, `start`
/// a buffer for the histogram over every (brick, spill) of the box and its running sum. A brick's
/// index in the box (x fastest) increases with its key (z highest), so counting by (box index,
/// spill) and scattering in point order gives the sorted order.
fn counting_order(
    cells: &[([u32; 3], [f32; 3])],
    box_bricks: [u64; 3],
    start: &mut Vec<u32>,
    order: &mut Vec<(u64, u32)>,
) {
    let [nx, ny, nz] = box_bricks.map(|b| b as usize);
    let bucket = |c: [u32; 3]| {
        let b = c.map(|c| (c / BRICK as u32) as usize);
        (((b[2] * ny + b[1]) * nx + b[0]) << 3) | spill(c) as usize
    };
    start.clear();
    start.resize(8 * nx * ny * nz + 1, 0);
    for (c, _) in cells {
        start[bucket(*c) + 1] += 1;
    }
    for b in 1..start.len() {
        start[b] += start[b - 1];
    }
    order.resize(cells.len(), (0, 0));
    for (i, (c, _)) in cells.iter().enumerate() {
        let slot = &mut start[bucket(*c)];
        order[*slot as usize] = (pair_key(*c), i as u32);
        *slot += 1;
    }
}

/// Adds to `out` the stencil nodes of `p` that lie in its source brick plus `along` (bit `a`:
/// +1 along axis `a`), the point's spill being `spill` (`along` within it). Along a spilled axis
/// the stencil's upper corners lie in the next brick and its lower ones in the source; along any
/// other axis both lie in the source: so corner `k` (bit `a`: upper along axis `a`) lands in
/// that brick exactly when `k & spill == along`.
fn splat_point(p: &SplatPoint, spill: usize, along: usize, out: &mut [[f32; CHANNELS]]) {
    for (k, (corner, w)) in stencil(p.frac).enumerate() {
        if k & spill != along {
            continue;
        }
        let n: [u32; 3] = std::array::from_fn(|a| p.cell[a] + corner[a]);
        let o = &mut out[local(n)];
        o[0] += w * p.mass;
        o[1] += w * p.momentum.x;
        o[2] += w * p.momentum.y;
        o[3] += w * p.momentum.z;
        o[4] += w * p.volume;
    }
}

/// The key of brick `b` (coordinates below 2^16).
fn key(b: [u32; 3]) -> u64 {
    ((b[2] as u64) << (2 * KEY_BITS)) | ((b[1] as u64) << KEY_BITS) | b[0] as u64
}

/// The brick coordinates of `key`.
fn unkey(key: u64) -> [u32; 3] {
    let mask = (1u64 << KEY_BITS) - 1;
    [
        (key & mask) as u32,
        ((key >> KEY_BITS) & mask) as u32,
        (key >> (2 * KEY_BITS)) as u32,
    ]
}

/// Index of node `n` (global node coordinates) within its brick.
fn local(n: [u32; 3]) -> usize {
    let b = BRICK as u32;
    ((n[0] % b) + b * ((n[1] % b) + b * (n[2] % b))) as usize
}

impl VoxelGrid {
    /// Rebuilds the grid with cell size `cell` (m) over the points of `input` and splats every
    /// point. Refuses a grid whose occupied bricks need more than [`MAX_GRID_BYTES`] or whose
    /// span exceeds [`MAX_NODES_PER_AXIS`], naming both and a cell size that fits, and input
    /// slices of different lengths.
    pub fn build(&mut self, cell: f32, input: &SplatInput) -> Result<()> {
        let n = input.positions.len();
        for (name, len) in [
            ("velocities", input.velocities.len()),
            ("masses", input.masses.len()),
            ("volumes", input.volumes.len()),
        ] {
            if len != n {
                return Err(HairError::Parameter {
                    name: format!("hair_hair grid input {name}"),
                    value: format!("{len} values for {n} positions"),
                    fix: "give one value per point".into(),
                });
            }
        }
        self.plan_checked(cell, input.positions)?;
        self.nodes.clear();
        self.nodes
            .resize(self.bricks.len() * BRICK_NODES, [0.0; CHANNELS]);
        self.splat_all(input);
        Ok(())
    }

    /// Checks that a grid of cell size `cell` (m) over `positions` fits (see [`Self::build`]);
    /// the error names the nodes and bytes it would need and a cell size that fits.
    pub fn check(cell: f32, positions: &[Vector3<f32>]) -> Result<()> {
        VoxelGrid::default().plan_checked(cell, positions)
    }

    /// Lays out the grid over `positions` (bricks found, no node data) or refuses it.
    fn plan_checked(&mut self, cell: f32, positions: &[Vector3<f32>]) -> Result<()> {
        if !cell.is_finite() || cell <= 0.0 {
            return Err(HairError::Parameter {
                name: "hair_hair.cell_size".into(),
                value: format!("{cell} m"),
                fix: "use a cell size > 0 m (a few hair radii to a few cm)".into(),
            });
        }
        let usage = self.plan(cell, positions);
        if usage.fits() {
            return Ok(());
        }
        // The smallest cell size (in steps of 1.25) that fits, starting where the span fits.
        let (lo, hi) = bounds(positions);
        let extent = hi - lo;
        let widest = extent.max() as f64;
        let slots = (MAX_NODES_PER_AXIS - 2 * MARGIN_CELLS - 3) as f64;
        let mut fit = (cell as f64).max(widest / slots * 1.001) as f32;
        let mut scratch = VoxelGrid::default();
        for _ in 0..200 {
            if scratch.plan(fit, positions).fits() {
                break;
            }
            fit *= 1.25;
        }
        let [nx, ny, nz] = usage.dims;
        let occupied = match usage.bricks {
            Some(b) => format!(
                " and its points occupy {b} bricks of {BRICK}³ = {} grid nodes ({} bytes)",
                b.saturating_mul(BRICK_NODES as u64),
                b.saturating_mul(BRICK_BYTES)
            ),
            None => String::new(),
        };
        Err(HairError::Parameter {
            name: "hair_hair.cell_size".into(),
            value: format!("{cell} m"),
            fix: format!(
                "the hair's bounding box ({:.3} × {:.3} × {:.3} m) spans {nx} × {ny} × {nz} grid \
                 nodes{occupied}; a grid may span at most {MAX_NODES_PER_AXIS} grid nodes per \
                 axis and its occupied bricks may take at most {MAX_GRID_BYTES} bytes; use a \
                 cell size of at least {fit:.2e} m",
                extent.x, extent.y, extent.z
            ),
        })
    }

    /// Lays out the grid with cell size `cell` (m, > 0) over `positions`: base cells, sorted
    /// sources and allocated brick keys (these only when the span fits the keys).
    fn plan(&mut self, cell: f32, positions: &[Vector3<f32>]) -> Usage {
        let (lo, hi) = bounds(positions);
        let cell64 = cell as f64;
        self.cell = cell;
        self.inv_cell = 1.0 / cell64;
        self.origin = lo.cast::<f64>() - Vector3::repeat(cell64 * (MARGIN_CELLS as f64 + 0.5));
        self.dims = std::array::from_fn(|a| {
            let extent = (hi[a] as f64 - lo[a] as f64).max(0.0);
            let cells = (extent / cell64).ceil();
            // Saturates far beyond the limit (the conversion clamps to u64::MAX).
            (cells as u64).saturating_add(2 * MARGIN_CELLS + 2)
        });
        self.bricks.clear();
        if self.dims.iter().any(|&d| d > MAX_NODES_PER_AXIS) {
            return Usage {
                dims: self.dims,
                bricks: None,
            };
        }
        let mut cells = std::mem::take(&mut self.cells);
        let this = &*self;
        positions
            .par_iter()
            .map(|x| this.base_cell(x))
            .collect_into_vec(&mut cells);
        let n = positions.len();
        let mut order = std::mem::take(&mut self.order);
        // Bricks per axis of the span's box: base cells lie below `dims − 1` and their stencils
        // reach `dims − 1` (below 2^16 each, so the product fits).
        let box_bricks = self.dims.map(|d| d.div_ceil(BRICK as u64));
        if box_bricks.iter().product::<u64>()
            <= n as u64 / POINTS_PER_DENSE_BRICK + DENSE_BRICKS_EXTRA
        {
            counting_order(&cells, box_bricks, &mut self.bucket_start, &mut order);
        } else {
            if order.len() != n {
                order.clear();
                order.extend((0..n as u32).map(|i| (0, i)));
            }
            order.par_iter_mut().for_each(|(k, i)| {
                *k = pair_key(cells[*i as usize].0);
            });
            // The pairs are distinct, so the sorted order is unique whatever the thread count;
            // the last step's order is nearly sorted for this one, which the merge sort runs
            // through.
            order.par_sort();
        }
        // Sources, their points by spill, and the neighbours their points reach.
        self.sources.clear();
        self.source_start.clear();
        self.point_source.resize(n, 0);
        let mut at = 0;
        while at < n {
            let k = order[at].0 >> 3;
            let source = self.sources.len() as u32;
            self.sources.push(k);
            let mut reach = 0;
            for m in 0..8 {
                self.source_start.push(at as u32);
                while at < n && order[at].0 == (k << 3) | m {
                    self.point_source[order[at].1 as usize] = source;
                    reach |= m;
                    at += 1;
                }
            }
            let b = unkey(k);
            for d in (0..8).filter(|d| d & !reach == 0) {
                self.bricks
                    .push(key(std::array::from_fn(|a| b[a] + ((d >> a) as u32 & 1))));
            }
        }
        self.source_start.push(n as u32);
        self.bricks.sort_unstable();
        self.bricks.dedup();
        let bricks = &self.bricks;
        let starts = &self.source_start;
        self.links.clear();
        self.links
            .extend(self.sources.iter().enumerate().map(|(s, &k)| {
                let b = unkey(k);
                // The axes some point of this source spills along.
                let reach = (0..8)
                    .filter(|m| starts[8 * s + m] < starts[8 * s + m + 1])
                    .fold(0, |r, m| r | m);
                std::array::from_fn(|d| {
                    if d & !reach != 0 {
                        return NO_BRICK;
                    }
                    let next = key(std::array::from_fn(|a| b[a] + ((d >> a) as u32 & 1)));
                    bricks.binary_search(&next).map_or(NO_BRICK, |i| i as u32)
                })
            }));
        self.feeds.clear();
        self.feeds.resize(self.bricks.len(), [NO_BRICK; 8]);
        for (s, links) in self.links.iter().enumerate() {
            for (d, &b) in links.iter().enumerate() {
                if b != NO_BRICK {
                    self.feeds[b as usize][d] = s as u32;
                }
            }
        }
        self.cells = cells;
        self.order = order;
        Usage {
            dims: self.dims,
            bricks: Some(self.bricks.len() as u64),
        }
    }

    /// Splats every point into the cleared bricks (see the module doc for the order).
    fn splat_all(&mut self, input: &SplatInput) {
        let mut nodes = std::mem::take(&mut self.nodes);
        let mut points = std::mem::take(&mut self.splat_order);
        let cells = &self.cells;
        self.order
            .par_iter()
            .map(|&(_, i)| {
                let i = i as usize;
                let (cell, frac) = cells[i];
                let mass = input.masses[i];
                SplatPoint {
                    cell,
                    frac,
                    mass,
                    momentum: input.velocities[i] * mass,
                    volume: input.volumes[i],
                }
            })
            .collect_into_vec(&mut points);
        let this = &*self;
        nodes
            .par_chunks_mut(BRICK_NODES)
            .zip(&self.feeds)
            .for_each(|(out, feeds)| this.gather(feeds, out, &points));
        self.nodes = nodes;
        self.splat_order = points;
    }

    /// Sums into `out`, the nodes of one brick, the contributions of the points whose stencil
    /// reaches it: `feeds`, its source bricks `brick − d` for `d` in {0, 1}³ in a fixed order,
    /// the points of each source that spill along `d` by spill and then in point order.
    fn gather(&self, feeds: &[u32; 8], out: &mut [[f32; CHANNELS]], points: &[SplatPoint]) {
        for (along, &s) in feeds.iter().enumerate() {
            if s == NO_BRICK {
                continue;
            }
            let s = s as usize;
            for m in (0..8).filter(|m| m & along == along) {
                let range = self.source_start[8 * s + m] as usize
                    ..self.source_start[8 * s + m + 1] as usize;
                for point in &points[range] {
                    splat_point(point, m, along, out);
                }
            }
        }
    }

    /// The cell containing `x` (clamped into the span; a non-finite coordinate reads as 0) and
    /// the position within it (0–1 per axis).
    fn base_cell(&self, x: &Vector3<f32>) -> ([u32; 3], [f32; 3]) {
        let mut c = [0u32; 3];
        let mut f = [0.0f32; 3];
        for a in 0..3 {
            let u = (x[a] as f64 - self.origin[a]) * self.inv_cell;
            // The last base cell (the span is below 2^18 nodes, so it fits a u32).
            let top = (self.dims[a] - 2) as f64;
            let u = if u < top {
                u.max(0.0)
            } else if u <= f64::MAX {
                top
            } else {
                0.0
            };
            // 0 ≤ u ≤ top, so truncation is the floor (and needs no libm call).
            let i = u as u32;
            c[a] = i;
            f[a] = (u - i as f64) as f32;
        }
        (c, f)
    }

    /// Samples the grid at `x`: mass-weighted velocity, volume fraction, and the gradient of the
    /// volume fraction in excess of `target` (trilinear within the cell).
    pub fn sample(&self, x: &Vector3<f32>, target: f32) -> GridSample {
        let (c, f) = self.base_cell(x);
        // Most stencils lie in the base cell's brick: look it up once.
        let base = c.map(|c| c / BRICK as u32);
        let base_index = self.bricks.binary_search(&key(base)).ok();
        self.sample_cell::<true>(c, f, target, |d| {
            if d == 0 {
                base_index
            } else {
                let brick = key(std::array::from_fn(|a| base[a] + ((d >> a) as u32 & 1)));
                self.bricks.binary_search(&brick).ok()
            }
        })
    }

    /// [`Self::sample`] at point `i` of the last build, where the grid already knows the point's
    /// cell and bricks (no search).
    pub fn sample_point(&self, i: usize, target: f32) -> GridSample {
        self.sample_linked::<true>(i, target)
    }

    /// The grid velocity (m/s) of [`Self::sample_point`] alone, without the density and its
    /// gradient (the same bits; `None` where no mass was splatted).
    pub fn velocity_at_point(&self, i: usize) -> Option<Vector3<f32>> {
        self.sample_linked::<false>(i, 0.0).velocity
    }

    /// [`Self::sample_cell`] at point `i` of the last build through its source's links.
    fn sample_linked<const DENSITY: bool>(&self, i: usize, target: f32) -> GridSample {
        let (c, f) = self.cells[i];
        let links = &self.links[self.point_source[i] as usize];
        self.sample_cell::<DENSITY>(c, f, target, |d| {
            let index = links[d];
            (index != NO_BRICK).then_some(index as usize)
        })
    }

    /// Samples cell `c` at position `f` in it; `find` gives the index in `bricks` of the brick
    /// `d` (bit `a`: +1 along axis `a`) from the cell's own. Without `DENSITY` only the velocity
    /// is computed (density and gradient left zero).
    fn sample_cell<const DENSITY: bool>(
        &self,
        c: [u32; 3],
        f: [f32; 3],
        target: f32,
        find: impl Fn(usize) -> Option<usize>,
    ) -> GridSample {
        let inv_cell = self.inv_cell as f32;
        let inv_volume = inv_cell.powi(3);
        let (mut m, mut p, mut density) = (0.0f32, Vector3::zeros(), 0.0f32);
        let mut grad = Vector3::zeros();
        // Corner `k` lies in the next brick along the axes where it is upper and the cell is in
        // its brick's last layer.
        let spilled = spill(c) as usize;
        for (k, (d, w)) in stencil(f).enumerate() {
            let n: [u32; 3] = std::array::from_fn(|a| c[a] + d[a]);
            let Some(b) = find(k & spilled) else {
                continue;
            };
            let o = &self.nodes[b * BRICK_NODES + local(n)];
            m += w * o[0];
            p += Vector3::new(o[1], o[2], o[3]) * w;
            if !DENSITY {
                continue;
            }
            let phi = o[4] * inv_volume;
            density += w * phi;
            let excess = (phi - target).max(0.0);
            if excess > 0.0 {
                // d/dx of the trilinear weight: ±1/cell times the other two axes' weights.
                let wt = |a: usize| if d[a] == 1 { f[a] } else { 1.0 - f[a] };
                let sign = |a: usize| if d[a] == 1 { 1.0 } else { -1.0 };
                grad += Vector3::new(
                    sign(0) * wt(1) * wt(2),
                    sign(1) * wt(0) * wt(2),
                    sign(2) * wt(0) * wt(1),
                ) * (excess * inv_cell);
            }
        }
        GridSample {
            velocity: (m > 0.0).then(|| p / m),
            density,
            excess_gradient: grad,
        }
    }

    /// The hair at node `index` (node `(i, j, k)` sits at [`Self::origin`] + cell·`(i, j, k)`);
    /// `None` where no brick was allocated (no point within a cell of it).
    pub fn node(&self, index: [u32; 3]) -> Option<GridNode> {
        if index.iter().zip(&self.dims).any(|(&n, &d)| n as u64 >= d) {
            return None;
        }
        let brick = key(index.map(|n| n / BRICK as u32));
        let b = self.bricks.binary_search(&brick).ok()?;
        let o = self.nodes.get(b * BRICK_NODES + local(index))?;
        Some(GridNode {
            mass: o[0],
            momentum: Vector3::new(o[1], o[2], o[3]),
            volume: o[4],
        })
    }

    /// Position of node (0, 0, 0), m: a cell and a half below the hair's bounding box.
    pub fn origin(&self) -> Vector3<f64> {
        self.origin
    }

    /// Largest node volume fraction of the grid (dimensionless).
    pub fn max_density(&self) -> f32 {
        let inv_volume = (self.inv_cell as f32).powi(3);
        self.nodes.iter().fold(0.0, |a, o| a.max(o[4] * inv_volume))
    }

    /// Nodes allocated by the last build (bricks × [`BRICK`]³).
    pub fn allocated_nodes(&self) -> usize {
        self.nodes.len()
    }

    /// Nodes per axis of the span the last build covered (bounding box plus margins); a dense
    /// grid would allocate their product.
    pub fn span(&self) -> [u64; 3] {
        self.dims
    }

    /// Cell size, m.
    pub fn cell_size(&self) -> f32 {
        self.cell
    }
}

/// The 8 corners of a cell (offsets 0/1 per axis, x fastest) with the trilinear weights of
/// position `f` in it, each `(w_x · w_y) · w_z` (the x–y products computed once).
fn stencil(f: [f32; 3]) -> impl Iterator<Item = ([u32; 3], f32)> {
    let w = |a: usize| [1.0 - f[a], f[a]];
    let (wx, wy, wz) = (w(0), w(1), w(2));
    let wxy = [wx[0] * wy[0], wx[1] * wy[0], wx[0] * wy[1], wx[1] * wy[1]];
    (0..8u32).map(move |corner| {
        let d = [corner & 1, (corner >> 1) & 1, (corner >> 2) & 1];
        (d, wxy[(corner & 3) as usize] * wz[d[2] as usize])
    })
}

/// Bounding box of finite points (a box at the origin for none). One thread: vectorised, it
/// reads the points faster than a second thread wakes up.
fn bounds(points: &[Vector3<f32>]) -> (Vector3<f32>, Vector3<f32>) {
    let (lo, hi) = finite_bounds(points);
    if lo.x > hi.x {
        (Vector3::zeros(), Vector3::zeros())
    } else {
        (lo, hi)
    }
}

/// Bounding box of the finite points (lower corner above the upper one for none).
/// A point counts only when all three coordinates are finite. The fast pass takes the min and
/// max of the flat coordinates 8 points at a time (vectorised) and notes any non-finite one;
/// only then are the points scanned again point by point, leaving out those points.
fn finite_bounds(points: &[Vector3<f32>]) -> (Vector3<f32>, Vector3<f32>) {
    const LANES: usize = 24;
    let flat: &[f32] = bytemuck::cast_slice(points);
    let (mut lo, mut hi) = ([f32::INFINITY; LANES], [f32::NEG_INFINITY; LANES]);
    let mut finite = true;
    let mut groups = flat.chunks_exact(LANES);
    for group in &mut groups {
        for k in 0..LANES {
            let c = group[k];
            finite &= c.abs() < f32::INFINITY;
            lo[k] = if c < lo[k] { c } else { lo[k] };
            hi[k] = if c > hi[k] { c } else { hi[k] };
        }
    }
    for (k, &c) in groups.remainder().iter().enumerate() {
        finite &= c.abs() < f32::INFINITY;
        lo[k] = lo[k].min(c);
        hi[k] = hi[k].max(c);
    }
    if !finite {
        return points
            .iter()
            .filter(|x| x.iter().all(|c| c.is_finite()))
            .fold(
                (
                    Vector3::repeat(f32::INFINITY),
                    Vector3::repeat(f32::NEG_INFINITY),
                ),
                |(lo, hi), x| (lo.inf(x), hi.sup(x)),
            );
    }
    // Lane k holds axis k % 3.
    let fold = |v: [f32; LANES], pick: fn(f32, f32) -> f32| {
        Vector3::from_fn(|a, _| v[a..].iter().step_by(3).copied().fold(v[a], pick))
    };
    (fold(lo, f32::min), fold(hi, f32::max))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn input<'a>(
        x: &'a [Vector3<f32>],
        v: &'a [Vector3<f32>],
        m: &'a [f32],
        vol: &'a [f32],
    ) -> SplatInput<'a> {
        SplatInput {
            positions: x,
            velocities: v,
            masses: m,
            volumes: vol,
        }
    }

    #[test]
    fn splat_conserves_mass_momentum_and_volume() {
        let x: Vec<_> = (0..200)
            .map(|i| {
                let t = i as f32 * 0.37;
                Vector3::new(t.sin() * 0.1, (1.3 * t).cos() * 0.07, 0.003 * i as f32)
            })
            .collect();
        let v: Vec<_> = (0..200)
            .map(|i| Vector3::new(1.0, -0.5, i as f32 * 0.01))
            .collect();
        let m = vec![2e-4; 200];
        let vol = vec![1e-7; 200];
        let mut g = VoxelGrid::default();
        g.build(0.01, &input(&x, &v, &m, &vol)).unwrap();
        let sum = g.nodes.iter().fold([0.0f64; 5], |a, o| {
            std::array::from_fn(|c| a[c] + o[c] as f64)
        });
        let momentum: Vector3<f64> = v.iter().map(|v| (v * 2e-4).cast::<f64>()).sum();
        assert!((sum[0] - 200.0 * 2e-4).abs() < 1e-7);
        assert!((Vector3::new(sum[1], sum[2], sum[3]) - momentum).norm() < 1e-6);
        assert!((sum[4] - 200.0 * 1e-7).abs() < 1e-10);
    }

    #[test]
    fn sampling_a_point_by_index_equals_sampling_its_position() {
        let x: Vec<_> = (0..300)
            .map(|i| {
                let t = i as f32 * 0.29;
                Vector3::new(t.cos() * 0.05, t.sin() * 0.05, 0.001 * i as f32)
            })
            .collect();
        let v: Vec<_> = (0..300)
            .map(|i| Vector3::new(0.0, 0.01 * i as f32, 1.0))
            .collect();
        let (m, vol) = (vec![1e-4; 300], vec![3e-8; 300]);
        let mut g = VoxelGrid::default();
        g.build(0.004, &input(&x, &v, &m, &vol)).unwrap();
        for (i, x) in x.iter().enumerate() {
            assert_eq!(g.sample_point(i, 0.1), g.sample(x, 0.1), "point {i}");
            assert_eq!(
                g.velocity_at_point(i),
                g.sample(x, 0.1).velocity,
                "point {i}"
            );
        }
    }

    #[test]
    fn counting_order_equals_the_sorted_pairs() {
        // Base cells spread over a box of 5 × 4 × 3 bricks, several per brick and spill.
        let cells: Vec<([u32; 3], [f32; 3])> = (0..500u32)
            .map(|i| ([(i * 7) % 20, (i * 13) % 16, (i * 5) % 12], [0.5; 3]))
            .collect();
        let (mut start, mut order) = (Vec::new(), Vec::new());
        counting_order(&cells, [5, 4, 3], &mut start, &mut order);
        let mut sorted: Vec<(u64, u32)> = (0..cells.len() as u32)
            .map(|i| (pair_key(cells[i as usize].0), i))
            .collect();
        sorted.sort();
        assert_eq!(order, sorted);
    }

    #[test]
    fn bounds_leave_out_points_with_a_non_finite_coordinate() {
        // Sizes around the 8-point groups, non-finite coordinates in groups and the remainder.
        for n in [0usize, 1, 7, 8, 9, 23, 64, 101] {
            let mut x: Vec<_> = (0..n)
                .map(|i| {
                    let t = i as f32 * 0.71;
                    Vector3::new(t.sin(), (2.1 * t).cos() * 3.0, t - 20.0)
                })
                .collect();
            let reference = |x: &[Vector3<f32>]| {
                let finite: Vec<_> = x
                    .iter()
                    .filter(|p| p.iter().all(|c| c.is_finite()))
                    .collect();
                if finite.is_empty() {
                    return (Vector3::zeros(), Vector3::zeros());
                }
                let lo = Vector3::from_fn(|a, _| {
                    finite.iter().map(|p| p[a]).fold(f32::INFINITY, f32::min)
                });
                let hi = Vector3::from_fn(|a, _| {
                    finite
                        .iter()
                        .map(|p| p[a])
                        .fold(f32::NEG_INFINITY, f32::max)
                });
                (lo, hi)
            };
            assert_eq!(bounds(&x), reference(&x), "{n} finite points");
            for (k, bad) in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY]
                .into_iter()
                .enumerate()
            {
                if let Some(p) = x.get_mut((5 * k + 3) % n.max(1)) {
                    // A huge finite value elsewhere in the point: the whole point must go.
                    *p = Vector3::new(1e30, -1e30, 1e30);
                    p[k] = bad;
                }
                assert_eq!(bounds(&x), reference(&x), "{n} points, {bad} in axis {k}");
            }
        }
    }

    #[test]
    fn inputs_of_different_lengths_are_refused() {
        let x = [Vector3::zeros(); 3];
        let mut g = VoxelGrid::default();
        let e = g
            .build(0.01, &input(&x, &x[..2], &[1.0; 3], &[1.0; 3]))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("velocities") && e.contains("2 values for 3"),
            "{e}"
        );
    }

    #[test]
    fn uniform_velocity_is_sampled_back_exactly() {
        let x: Vec<_> = (0..64)
            .map(|i| Vector3::new((i % 4) as f32, ((i / 4) % 4) as f32, (i / 16) as f32) * 0.013)
            .collect();
        let v = vec![Vector3::new(0.3, -0.2, 0.1); 64];
        let (m, vol) = (vec![1e-4; 64], vec![1e-8; 64]);
        let mut g = VoxelGrid::default();
        g.build(0.02, &input(&x, &v, &m, &vol)).unwrap();
        let s = g.sample(&x[21], 0.0);
        assert!((s.velocity.unwrap() - v[0]).norm() < 1e-5);
    }

    #[test]
    fn span_beyond_the_brick_keys_is_refused_with_the_nodes_it_needs() {
        let x = [Vector3::zeros(), Vector3::new(1.0, 1.0, 1.0)];
        let z = [Vector3::zeros(); 2];
        let mut g = VoxelGrid::default();
        let e = g
            .build(1e-6, &input(&x, &z, &[1.0; 2], &[1.0; 2]))
            .unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("hair_hair.cell_size") && text.contains("1000005 × 1000005 × 1000005"),
            "{text}"
        );
        // The cell size it proposes fits.
        let fit = text.rsplit("at least ").next().unwrap();
        let fit: f32 = fit.split(' ').next().unwrap().parse().unwrap();
        g.build(fit, &input(&x, &z, &[1.0; 2], &[1.0; 2])).unwrap();
    }
}
