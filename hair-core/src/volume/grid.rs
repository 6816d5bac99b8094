//! The voxel grid of hair–hair interaction: point mass, momentum and volume splatted trilinearly
//! onto the nodes of a dense grid over the hair's bounding box.
//!
//! **Deterministic splat without atomics.** Points are binned by the z-slab of their cell
//! ([`SLAB`] cell layers per slab, a constant, so the binning never depends on the thread count),
//! keeping point order within a slab. A point of slab `k` writes node layers `kS ..= (k+1)S`, so
//! even slabs touch disjoint node ranges, and so do odd slabs: the even slabs splat in parallel,
//! then the odd slabs. Every node therefore sums its contributions in one fixed order (its even
//! slab's points in point order, then its odd slab's), bit-identical for any number of threads.

use nalgebra::Vector3;
use rayon::prelude::*;

use crate::error::{HairError, Result};

/// Cell layers along z per slab of the deterministic splat.
const SLAB: usize = 4;

/// Empty cells kept around the hair's bounding box on every side.
const MARGIN_CELLS: f32 = 1.0;

/// Largest grid a step may allocate, bytes (node data only).
pub const MAX_GRID_BYTES: u64 = 1 << 30;

/// Channels per node: mass (kg), momentum (kg·m/s, 3), hair volume (m³).
const CHANNELS: usize = 5;

/// Bytes per node.
const NODE_BYTES: u64 = (CHANNELS * std::mem::size_of::<f32>()) as u64;

/// A dense grid over the hair's bounding box plus a margin, rebuilt every collision step.
///
/// Node `(i, j, k)` sits at `origin + cell·(i, j, k)`. Each node holds the hair mass (kg),
/// momentum (kg·m/s) and volume (m³) splatted onto it with trilinear weights.
#[derive(Debug, Clone, Default)]
pub struct VoxelGrid {
    origin: Vector3<f32>,
    cell: f32,
    inv_cell: f32,
    dims: [usize; 3],
    nodes: Vec<[f32; CHANNELS]>,
    /// Point indices binned by slab, and where each slab starts in it.
    order: Vec<u32>,
    slab_start: Vec<u32>,
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

impl VoxelGrid {
    /// Node data bytes a grid of cell size `cell` (m) over the box `lo..hi` (m) would need.
    pub fn bytes_for(lo: &Vector3<f32>, hi: &Vector3<f32>, cell: f32) -> (u64, [u64; 3]) {
        let dims: [u64; 3] = std::array::from_fn(|a| {
            let extent = ((hi[a] - lo[a]) as f64).max(0.0);
            (extent / cell as f64).ceil() as u64 + 2 * MARGIN_CELLS as u64 + 2
        });
        let nodes = dims[0].saturating_mul(dims[1]).saturating_mul(dims[2]);
        (nodes.saturating_mul(NODE_BYTES), dims)
    }

    /// Rebuilds the grid with cell size `cell` (m) over the bounding box of `input.positions`
    /// and splats every point. Refuses a grid over [`MAX_GRID_BYTES`], naming the nodes and bytes
    /// it would need and the smallest cell size that fits.
    pub fn build(&mut self, cell: f32, input: &SplatInput) -> Result<()> {
        let n = input.positions.len();
        let (lo, hi) = bounds(input.positions);
        let dims = Self::check_fits(cell, &lo, &hi)?;
        self.cell = cell;
        self.inv_cell = 1.0 / cell;
        self.origin = lo - Vector3::repeat(cell * (MARGIN_CELLS + 0.5));
        self.dims = dims;
        let layer = dims[0] * dims[1];
        self.nodes.clear();
        self.nodes.resize(layer * dims[2], [0.0; CHANNELS]);
        self.splat_all(n, input);
        Ok(())
    }

    /// Checks that a grid of cell size `cell` (m) over the bounding box of `positions` fits in
    /// [`MAX_GRID_BYTES`]; the error names the nodes and bytes it would need and a cell size
    /// that fits.
    pub fn check(cell: f32, positions: &[Vector3<f32>]) -> Result<()> {
        let (lo, hi) = bounds(positions);
        Self::check_fits(cell, &lo, &hi).map(|_| ())
    }

    fn check_fits(cell: f32, lo: &Vector3<f32>, hi: &Vector3<f32>) -> Result<[usize; 3]> {
        let (bytes, dims) = Self::bytes_for(lo, hi, cell);
        if bytes > MAX_GRID_BYTES || !cell.is_finite() || cell <= 0.0 {
            let extent = hi - lo;
            let nodes = dims[0].saturating_mul(dims[1]).saturating_mul(dims[2]);
            let volume = (extent.x.max(cell) * extent.y.max(cell) * extent.z.max(cell)) as f64;
            let fit = (volume * NODE_BYTES as f64 / MAX_GRID_BYTES as f64).cbrt();
            return Err(HairError::Parameter {
                name: "hair_hair.cell_size".into(),
                value: format!("{cell} m"),
                fix: format!(
                    "the hair's bounding box ({:.3} × {:.3} × {:.3} m) would need {} × {} × {} = \
                     {nodes} grid nodes ({bytes} bytes), over the limit of {MAX_GRID_BYTES} bytes; \
                     use a cell size of at least {:.2e} m",
                    extent.x,
                    extent.y,
                    extent.z,
                    dims[0],
                    dims[1],
                    dims[2],
                    fit * 1.01
                ),
            });
        }
        Ok(dims.map(|d| d as usize))
    }

    /// Splats `n` points into the cleared nodes (see the module doc for the order).
    fn splat_all(&mut self, n: usize, input: &SplatInput) {
        let dims = self.dims;
        let layer = dims[0] * dims[1];
        // Bin points by slab (counting sort, stable).
        let slabs = (dims[2] - 1).div_ceil(SLAB);
        let mut order = std::mem::take(&mut self.order);
        let mut starts = std::mem::take(&mut self.slab_start);
        let mut nodes = std::mem::take(&mut self.nodes);
        let this = &*self;
        let slab_of = |x: &Vector3<f32>| this.base_cell(x).0[2] / SLAB;
        starts.clear();
        starts.resize(slabs + 1, 0);
        for x in input.positions {
            starts[slab_of(x) + 1] += 1;
        }
        for s in 0..slabs {
            starts[s + 1] += starts[s];
        }
        order.clear();
        order.resize(n, 0);
        let mut next = starts.clone();
        for (i, x) in input.positions.iter().enumerate() {
            let s = slab_of(x);
            order[next[s] as usize] = i as u32;
            next[s] += 1;
        }

        // Even slabs, then odd slabs: each chunk of 2·SLAB layers holds one slab's writes.
        let chunk = 2 * SLAB * layer;
        for parity in 0..2 {
            let skip = parity * SLAB * layer;
            if skip >= nodes.len() {
                break;
            }
            nodes[skip..]
                .par_chunks_mut(chunk)
                .enumerate()
                .for_each(|(c, out)| {
                    let slab = 2 * c + parity;
                    if slab < slabs {
                        let points = &order[starts[slab] as usize..starts[slab + 1] as usize];
                        this.splat(points, slab * SLAB * layer, out, input);
                    }
                });
        }
        self.order = order;
        self.slab_start = starts;
        self.nodes = nodes;
    }

    /// Splats `points` (indices into `p`) into `out`, which starts at global node `first`.
    fn splat(&self, points: &[u32], first: usize, out: &mut [[f32; CHANNELS]], p: &SplatInput) {
        for &i in points {
            let i = i as usize;
            let (c, f) = self.base_cell(&p.positions[i]);
            let m = p.masses[i];
            let mv = p.velocities[i] * m;
            let vol = p.volumes[i];
            for (node, w) in self.stencil(c, f) {
                let o = &mut out[node - first];
                o[0] += w * m;
                o[1] += w * mv.x;
                o[2] += w * mv.y;
                o[3] += w * mv.z;
                o[4] += w * vol;
            }
        }
    }

    /// The cell containing `x` (clamped into the grid) and the position within it (0–1 per axis).
    fn base_cell(&self, x: &Vector3<f32>) -> ([usize; 3], [f32; 3]) {
        let mut c = [0usize; 3];
        let mut f = [0.0f32; 3];
        for a in 0..3 {
            let u = (x[a] - self.origin[a]) * self.inv_cell;
            let top = (self.dims[a] - 2) as f32;
            let u = if u.is_finite() {
                u.clamp(0.0, top)
            } else {
                0.0
            };
            // u ≥ 0, so truncation is the floor (and needs no libm call).
            let i = (u as usize).min(self.dims[a] - 2);
            c[a] = i;
            f[a] = u - i as f32;
        }
        (c, f)
    }

    /// The 8 nodes around cell `c` with the trilinear weights of position `f` in it.
    fn stencil(&self, c: [usize; 3], f: [f32; 3]) -> impl Iterator<Item = (usize, f32)> {
        let [nx, ny, _] = self.dims;
        (0..8).map(move |corner| {
            let (dx, dy, dz) = (corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
            let w = |d: usize, t: f32| if d == 1 { t } else { 1.0 - t };
            let node = ((c[2] + dz) * ny + c[1] + dy) * nx + c[0] + dx;
            (node, w(dx, f[0]) * w(dy, f[1]) * w(dz, f[2]))
        })
    }

    /// Samples the grid at `x`: mass-weighted velocity, volume fraction, and the gradient of the
    /// volume fraction in excess of `target` (trilinear within the cell).
    pub fn sample(&self, x: &Vector3<f32>, target: f32) -> GridSample {
        let (c, f) = self.base_cell(x);
        let inv_volume = self.inv_cell.powi(3);
        let (mut m, mut p, mut density) = (0.0f32, Vector3::zeros(), 0.0f32);
        let mut grad = Vector3::zeros();
        for (corner, (node, w)) in self.stencil(c, f).enumerate() {
            let o = &self.nodes[node];
            m += w * o[0];
            p += Vector3::new(o[1], o[2], o[3]) * w;
            let phi = o[4] * inv_volume;
            density += w * phi;
            let excess = (phi - target).max(0.0);
            if excess > 0.0 {
                // d/dx of the trilinear weight: ±1/cell times the other two axes' weights.
                let d = [corner & 1, (corner >> 1) & 1, (corner >> 2) & 1];
                let wt = |a: usize| if d[a] == 1 { f[a] } else { 1.0 - f[a] };
                let sign = |a: usize| if d[a] == 1 { 1.0 } else { -1.0 };
                grad += Vector3::new(
                    sign(0) * wt(1) * wt(2),
                    sign(1) * wt(0) * wt(2),
                    sign(2) * wt(0) * wt(1),
                ) * (excess * self.inv_cell);
            }
        }
        GridSample {
            velocity: (m > 0.0).then(|| p / m),
            density,
            excess_gradient: grad,
        }
    }

    /// Largest node volume fraction of the grid (dimensionless).
    pub fn max_density(&self) -> f32 {
        let inv_volume = self.inv_cell.powi(3);
        self.nodes.iter().fold(0.0, |a, o| a.max(o[4] * inv_volume))
    }

    /// Nodes per axis.
    pub fn dims(&self) -> [usize; 3] {
        self.dims
    }

    /// Cell size, m.
    pub fn cell_size(&self) -> f32 {
        self.cell
    }
}

/// Bounding box of finite points (a box at the origin for none).
fn bounds(points: &[Vector3<f32>]) -> (Vector3<f32>, Vector3<f32>) {
    let mut lo = Vector3::repeat(f32::INFINITY);
    let mut hi = Vector3::repeat(f32::NEG_INFINITY);
    for x in points.iter().filter(|x| x.iter().all(|c| c.is_finite())) {
        lo = lo.inf(x);
        hi = hi.sup(x);
    }
    if lo.x > hi.x {
        (Vector3::zeros(), Vector3::zeros())
    } else {
        (lo, hi)
    }
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
    fn too_small_cell_is_refused_with_the_bytes_it_needs() {
        let x = [Vector3::zeros(), Vector3::new(1.0, 1.0, 1.0)];
        let z = [Vector3::zeros(); 2];
        let mut g = VoxelGrid::default();
        let e = g
            .build(1e-4, &input(&x, &z, &[1.0; 2], &[1.0; 2]))
            .unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("hair_hair.cell_size") && text.contains("bytes"),
            "{text}"
        );
        assert!(text.contains("10005 × 10005 × 10005"), "{text}");
    }
}
