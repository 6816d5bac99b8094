//! Interpolated children: between several parents.
//!
//! **Roots.** Each child still has a home parent (its identity is (seed, home parent, index), so
//! counts per parent or in total, determinism and the display prefix work as for simple
//! children). Its root is drawn uniformly in the disc of the spread radius around the home
//! parent's root, in the root frame's tangent plane, like a simple child's; on a scalp the point
//! is then moved onto the mesh (the triangle around the home root's triangle that contains its
//! projection, or the nearest one, weights clamped), and the mesh gives the child's position, root
//! frame, UV and vertex color. For interpolated children the spread is best about the spacing of
//! the parents, so children fill the scalp between them.
//!
//! **Shape.** The child's path is a weighted blend of its `k` nearest parents (by root distance),
//! each taken as offsets from its own root, resampled by point index to the home parent's point
//! count, turned by the smallest rotation taking that parent's surface normal onto the child's,
//! and added to the child's root: `c(x) = r + Σ w_j R_j (P_j(x_j) − P_j(0))`. Weights are
//! Franke–Little inverse distance weights `w_j ∝ ((R − d_j)/(R d_j))²` with `R` the distance to
//! the (k+1)-th nearest parent (or `2 d_k` when there are only `k`), so a parent's weight falls
//! to 0 as it leaves the neighbourhood; a child rooted within 1 µm of a parent takes that
//! parent's shape alone. The blend is linear, so it is formed once per child at the home parent's
//! points (`k` multiply-adds per point and axis over lane-padded arrays of offsets tabulated once
//! per home parent) and interpolated along the child, instead of blending `k` parents
//! at every child point. The nearest parents are searched among the `k + 8` nearest of the home
//! parent (a grid search, module `neighbours`), exact for children within the home parent's
//! neighbourhood.
//!
//! **Shaping.** Clumping draws the child towards its home parent's path (`factor = 1` puts its
//! tip on the home parent's tip); curl and roughness use the home parent's transported frames;
//! length variation, taper and level of detail are those of simple children (the same kernel).

use hair_core::{MeshSample, RootFrame, TriMesh};
use hair_par::prelude::*;
use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use wide::f32x8;

use crate::children::grow::{grow, Profile, Scratch};
use crate::children::neighbours::nearest;
use crate::children::simple::disc_offset;
use crate::parents::{ParentRoot, Parents};
use crate::path::ParentPath;
use crate::rng::ChildRng;
use crate::shape::Shape;
use crate::subdivide::catmull_rom;

/// Most parents a child blends (the largest accepted `neighbours`).
pub const MAX_NEIGHBOURS: u32 = 8;
/// Candidates searched per home parent beyond the `k + 1` a child needs.
const EXTRA_CANDIDATES: usize = 7;
/// A child rooted closer than this to a parent (m) takes that parent's shape alone.
const SAME_ROOT: f32 = 1e-6;

/// One parent's share of a child.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Share {
    /// The parent's slot among the home parent's candidates (its rows in [`Blend::table`]).
    slot: u32,
    /// The parent's weight.
    weight: f32,
    /// Weight times the rotation from the parent's normal to the child's; `None` when the normals
    /// agree (the rotation is the identity: 3 multiply-adds per point instead of 9).
    rotation: Option<Matrix3<f32>>,
}

/// Lanes of the blend loops: point arrays are padded to a multiple of this.
const LANES: usize = 8;

/// Per-thread working space of interpolated children: the home parent's candidate offsets
/// resampled to its point count (built once per home parent), one child's shares and its blended
/// offset curve.
#[derive(Debug, Clone, Default)]
pub(crate) struct Blend {
    /// Lane groups per row: the home parent's point count over [`LANES`], rounded up.
    chunks: usize,
    /// Per candidate slot, three rows (x, y, z) of `chunks` lane groups of offsets from the
    /// candidate's root, meters, at the home parent's point indices (zero padded).
    table: Vec<f32x8>,
    /// The root points of the home parent's candidates, by slot, meters.
    roots: Vec<Vector3<f32>>,
    /// The current child's shares.
    shares: Vec<Share>,
    /// The current child's blended offsets `Σ w_j R_j (P_j − P_j(0))`, three rows of `chunks`.
    curve: Vec<f32x8>,
    /// The current child's root plus its blended offsets, at the home parent's points, meters.
    points: Vec<Vector3<f32>>,
}

impl Blend {
    /// Blends the rows of every share into `curve`: per lane group and axis, `3k` multiply-adds
    /// on [`LANES`] points at once.
    #[inline(always)]
    fn blend(&mut self) {
        let c = self.chunks;
        self.curve.clear();
        self.curve.resize(3 * c, f32x8::ZERO);
        let (ox, oyz) = self.curve.split_at_mut(c);
        let (oy, oz) = oyz.split_at_mut(c);
        for s in &self.shares {
            let rows = &self.table[3 * s.slot as usize * c..][..3 * c];
            let (x, yz) = rows.split_at(c);
            let (y, z) = yz.split_at(c);
            match s.rotation {
                None => {
                    let w = f32x8::splat(s.weight);
                    for i in 0..c {
                        ox[i] += w * x[i];
                        oy[i] += w * y[i];
                        oz[i] += w * z[i];
                    }
                }
                Some(m) => {
                    let m = m.map(f32x8::splat);
                    for i in 0..c {
                        let (x, y, z) = (x[i], y[i], z[i]);
                        ox[i] += m[(0, 0)] * x + m[(0, 1)] * y + m[(0, 2)] * z;
                        oy[i] += m[(1, 0)] * x + m[(1, 1)] * y + m[(1, 2)] * z;
                        oz[i] += m[(2, 0)] * x + m[(2, 1)] * y + m[(2, 2)] * z;
                    }
                }
            }
        }
    }

    /// Writes `origin` plus the blended offset at each of the home parent's `n` points into
    /// `points`.
    #[inline(always)]
    fn place(&mut self, origin: &Vector3<f32>, n: usize) {
        let c = self.chunks;
        let (x, yz) = self.curve.split_at(c);
        let (y, z) = yz.split_at(c);
        self.points.clear();
        self.points.extend((0..n).map(|i| {
            let (g, l) = (i / LANES, i % LANES);
            origin + Vector3::new(x[g].as_array()[l], y[g].as_array()[l], z[g].as_array()[l])
        }));
    }
}

/// Everything interpolated children of any parent need: every parent's path and root, the
/// candidate neighbours of every parent, the scalp's vertex → triangles map.
pub(crate) struct Interpolator<'a> {
    parents: &'a Parents<'a>,
    paths: Vec<ParentPath>,
    roots: Vec<ParentRoot>,
    /// Every parent's root normal (its root frame's z axis).
    normals: Vec<Vector3<f32>>,
    candidates: Vec<u32>,
    m: usize,
    k: usize,
    around: Option<VertexTriangles>,
}

impl<'a> Interpolator<'a> {
    /// Prepares `parents` subdivided with `steps` for children blending `k ≥ 1` parents.
    pub(crate) fn new(parents: &'a Parents<'a>, steps: u32, k: usize) -> Self {
        let np = parents.len();
        let roots: Vec<ParentRoot> = (0..np).map(|p| parents.root(p)).collect();
        let paths: Vec<ParentPath> = (0..np)
            .into_par_iter()
            .map(|p| {
                let mut path = ParentPath::default();
                catmull_rom(parents.points(p), steps, &mut path.points);
                path.build_frames(&roots[p].frame);
                path
            })
            .collect();
        let normals = roots
            .iter()
            .map(|r| r.frame.rotation * Vector3::z())
            .collect();
        let k = k.min(np);
        let m = (k + 1 + EXTRA_CANDIDATES).min(np);
        let starts: Vec<Vector3<f32>> = paths.iter().map(|p| p.points[0]).collect();
        let candidates = nearest(&starts, m);
        let around = parents
            .scalp()
            .filter(|s| s.samples.iter().any(Option::is_some))
            .map(|s| VertexTriangles::new(s.mesh));
        Self {
            parents,
            paths,
            roots,
            normals,
            candidates,
            m,
            k,
            around,
        }
    }

    /// The subdivided path of parent `p`.
    pub(crate) fn path(&self, p: usize) -> &ParentPath {
        &self.paths[p]
    }

    /// Tabulates, into `blend`, the offsets from their roots of home parent `p`'s candidate
    /// parents resampled by point index to `p`'s point count: once per home parent, shared by
    /// all its children.
    pub(crate) fn prepare(&self, p: usize, blend: &mut Blend) {
        let n = self.paths[p].points.len();
        let c = n.div_ceil(LANES);
        let m = self.m;
        blend.chunks = c;
        blend.table.clear();
        blend.table.resize(3 * m * c, f32x8::ZERO);
        blend.roots.clear();
        let home_len = (n - 1) as f32;
        for (slot, &j) in self.candidates[p * m..(p + 1) * m].iter().enumerate() {
            let path = &self.paths[j as usize];
            let root = path.points[0];
            blend.roots.push(root);
            let ratio = (path.points.len() - 1) as f32 / home_len;
            let rows = &mut blend.table[3 * slot * c..3 * (slot + 1) * c];
            for i in 0..n {
                let q = if ratio == 1.0 {
                    path.points[i]
                } else {
                    path.point_at(i as f32 * ratio)
                } - root;
                let (g, l) = (i / LANES, i % LANES);
                for (axis, v) in q.iter().enumerate() {
                    rows[axis * c + g].as_mut_array()[l] = *v;
                }
            }
        }
    }

    /// Writes the child of home parent `p` drawn by `rng` (root disc of radius `spread`, m) into
    /// `points` and `widths`; returns its root (frame, UV, color). `blend` holds `p`'s table
    /// ([`Interpolator::prepare`]); `scratch` is working space.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn grow(
        &self,
        p: usize,
        profile: &Profile,
        spread: f32,
        shape: &Shape,
        rng: &ChildRng,
        scratch: &mut Scratch,
        blend: &mut Blend,
        points: &mut [f32],
        widths: &mut [f32],
    ) -> ParentRoot {
        let root = self.child_root(p, spread, rng);
        self.shares(p, &root.frame, blend);
        // The blend is linear, so blending the k parents once at the home parent's points and
        // interpolating the result along the child equals blending at every child point.
        blend.blend();
        let last = self.paths[p].points.len() - 1;
        blend.place(&root.frame.origin, last + 1);
        let placed = &blend.points;
        grow(
            &self.paths[p],
            profile,
            shape,
            rng,
            scratch,
            points,
            widths,
            |pt| {
                // Paths have ≥ 2 points; at f = 0 the blend below is exactly `placed[j]`.
                let x = pt.x.clamp(0.0, last as f32);
                let j = (x as usize).min(last - 1);
                let f = x - j as f32;
                placed[j] * (1.0 - f) + placed[j + 1] * f - pt.base
            },
        );
        root
    }

    /// The child's root: in the home parent's disc, moved onto the scalp when the home parent is
    /// rooted on it.
    fn child_root(&self, p: usize, spread: f32, rng: &ChildRng) -> ParentRoot {
        let home = &self.roots[p];
        let (a, b) = disc_offset(spread, rng);
        let x = self.paths[p].points[0] + home.frame.rotation * Vector3::new(a, b, 0.0);
        if let (Some(scalp), Some(sample), Some(around)) =
            (self.parents.scalp(), self.parents.sample(p), &self.around)
        {
            let snapped = around.snap(scalp.mesh, sample.triangle as usize, &x);
            return scalp.point(&snapped);
        }
        ParentRoot {
            frame: RootFrame {
                origin: x,
                rotation: home.frame.rotation,
            },
            uv: home.uv,
            color: home.color,
        }
    }

    /// The parents a child at `frame` blends, with weights and rotations, into `blend.shares`
    /// (`blend` holds the home parent's candidate roots).
    fn shares(&self, p: usize, frame: &RootFrame, blend: &mut Blend) {
        let m = self.m;
        // (squared distance bits, slot): squares are ≥ 0, so their bits sort as the distances.
        let mut near = [0u64; MAX_NEIGHBOURS as usize + 1 + EXTRA_CANDIDATES];
        for (slot, (key, root)) in near.iter_mut().zip(&blend.roots).enumerate() {
            let d2 = (root - frame.origin).norm_squared();
            *key = (u64::from(d2.to_bits()) << 32) | slot as u64;
        }
        let near = &mut near[..m];
        // Candidates come by distance from the home root, which the child is near: almost
        // sorted already, so an insertion sort moves little.
        for i in 1..m {
            let v = near[i];
            let mut j = i;
            while j > 0 && near[j - 1] > v {
                near[j] = near[j - 1];
                j -= 1;
            }
            near[j] = v;
        }
        let distance = |key: u64| f32::from_bits((key >> 32) as u32).sqrt();
        let slot = |key: u64| (key & u64::from(u32::MAX)) as usize;
        let k = self.k;
        let mut weights = [0.0f32; MAX_NEIGHBOURS as usize];
        let used = if distance(near[0]) < SAME_ROOT {
            weights[0] = 1.0;
            1
        } else {
            let r = if m > k {
                distance(near[k])
            } else {
                2.0 * distance(near[k - 1])
            };
            let mut sum = 0.0;
            for (w, &key) in weights.iter_mut().zip(near.iter()).take(k) {
                let d = distance(key);
                *w = if d < r {
                    ((r - d) / (r * d)).powi(2)
                } else {
                    0.0
                };
                sum += *w;
            }
            if sum > 0.0 && sum.is_finite() {
                weights[..k].iter_mut().for_each(|w| *w /= sum);
            } else {
                weights[..k].iter_mut().for_each(|w| *w = 1.0 / k as f32);
            }
            k
        };
        let normal = frame.rotation * Vector3::z();
        let shares = &mut blend.shares;
        shares.clear();
        for (&key, &w) in near.iter().zip(&weights).take(used) {
            if w == 0.0 {
                continue;
            }
            let j = self.candidates[p * m + slot(key)] as usize;
            let jn = self.normals[j];
            let rotation = if (jn - normal).norm_squared() < 1e-12 {
                None
            } else {
                UnitQuaternion::rotation_between(&jn, &normal)
                    .map(|q| q.to_rotation_matrix().into_inner() * w)
            };
            shares.push(Share {
                slot: slot(key) as u32,
                weight: w,
                rotation,
            });
        }
    }
}

/// The triangles around each vertex of a mesh (compressed rows).
struct VertexTriangles {
    offsets: Vec<u32>,
    triangles: Vec<u32>,
}

impl VertexTriangles {
    fn new(mesh: &TriMesh) -> Self {
        let nv = mesh.positions().len();
        let mut offsets = vec![0u32; nv + 1];
        for tri in mesh.triangles() {
            for &v in tri {
                offsets[v as usize + 1] += 1;
            }
        }
        for v in 0..nv {
            offsets[v + 1] += offsets[v];
        }
        let mut fill = offsets.clone();
        let mut triangles = vec![0u32; offsets[nv] as usize];
        for (t, tri) in mesh.triangles().iter().enumerate() {
            for &v in tri {
                triangles[fill[v as usize] as usize] = t as u32;
                fill[v as usize] += 1;
            }
        }
        Self { offsets, triangles }
    }

    /// The sample on the triangles sharing a vertex with `home` nearest `x`: the one whose plane
    /// holds the projection of `x` inside it (nearest plane first), else the one `x` is least
    /// outside of, with its barycentric weights clamped.
    fn snap(&self, mesh: &TriMesh, home: usize, x: &Vector3<f32>) -> MeshSample {
        let mut best: Option<((bool, f32), MeshSample)> = None;
        for &v in &mesh.triangles()[home] {
            let (a, b) = (self.offsets[v as usize], self.offsets[v as usize + 1]);
            for &t in &self.triangles[a as usize..b as usize] {
                let Some((w, plane)) = barycentric(mesh, t as usize, x) else {
                    continue;
                };
                let outside = -w.iter().copied().fold(f32::INFINITY, f32::min);
                let key = if outside <= 0.0 {
                    (false, plane)
                } else {
                    (true, outside)
                };
                let better = best.as_ref().is_none_or(|(k, s)| {
                    (!key.0 && k.0) || (key.0 == k.0 && (key.1, t) < (k.1, s.triangle))
                });
                if better {
                    let c = w.map(|x| x.max(0.0));
                    let sum = c[0] + c[1] + c[2];
                    best = Some((
                        key,
                        MeshSample {
                            triangle: t,
                            weights: c.map(|x| x / sum),
                        },
                    ));
                }
            }
        }
        best.map_or(
            MeshSample {
                triangle: home as u32,
                weights: [1.0 / 3.0; 3],
            },
            |(_, s)| s,
        )
    }
}

/// Barycentric weights of `x` projected onto triangle `t`'s plane, and its distance to that plane
/// (m); `None` for a degenerate triangle.
fn barycentric(mesh: &TriMesh, t: usize, x: &Vector3<f32>) -> Option<([f32; 3], f32)> {
    let [a, b, c] = mesh.corners(t);
    let (e0, e1, d) = (b - a, c - a, x - a);
    let (d00, d01, d11) = (e0.dot(&e0), e0.dot(&e1), e1.dot(&e1));
    let (d20, d21) = (d.dot(&e0), d.dot(&e1));
    let den = d00 * d11 - d01 * d01;
    if den <= f32::EPSILON * d00 * d11 || den <= 0.0 {
        return None;
    }
    let v = (d11 * d20 - d01 * d21) / den;
    let w = (d00 * d21 - d01 * d20) / den;
    let n = e0.cross(&e1);
    let plane = (d.dot(&n) / n.norm()).abs();
    Some(([1.0 - v - w, v, w], plane))
}
