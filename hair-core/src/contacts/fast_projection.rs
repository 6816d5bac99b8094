//! An exact shortcut for projecting a point on a solid mesh near the triangle it projected on
//! last time, without walking parry's BVH from its root.
//!
//! **Certificate.** Let `T` be a triangle whose three vertices are *convex* (every edge around
//! them bends away from the outside: the fan of each vertex is the boundary of a convex cone), and
//! `c_T` its *clearance*: the smallest distance from `T` to any triangle that shares no vertex
//! with it. A point `p` outside the mesh, at height `h > 0` above `T`'s plane, whose foot on that
//! plane lies inside `T`, with `h ≤ c_T / 2`, projects on the mesh exactly at that foot:
//! - every triangle sharing a vertex with `T` lies in one of the three vertex fans, each of which
//!   lies below `T`'s plane (a convex cone lies on one side of each of its faces), so it is at
//!   least `h` from `p`;
//! - every other triangle `U` is at least `dist(T, U) − dist(p, T) ≥ c_T − h ≥ h` from `p`.
//!
//! If every vertex of the mesh is convex and the mesh is one connected piece, it bounds a convex
//! body, which lies entirely below the plane of each of its triangles: then the foot is the
//! answer at any height above it, with no clearance needed (the built-in head, a UV sphere).
//!
//! When the foot falls outside `T`, the search walks to the neighbour across the edge it fell
//! behind (on a convex body also from a triangle whose plane the point lies below: hair that
//! outran the head within a step; the edge and vertex tests below do not depend on the height,
//! only the face's does), at most [`WALK`] times (hair moves little per step), and tries the
//! certificate there.
//! On a convex body a point behind the edge it just crossed, seen from both its triangles, lies
//! in that edge's region (far from a coarse convex mesh, as often as in a face's) when its
//! projection on the edge falls between the edge's ends; beyond an end, that vertex is the answer
//! if the point makes an obtuse angle with every edge leaving it (the body lies in the cone of
//! those edges). Anything else is left to parry's search.
//! Each try costs a plane distance and a barycentric check (a few dozen flops) where parry's BVH
//! search from the root costs a few hundred nanoseconds. It is the same answer, not an
//! approximation (up to which of two equally near triangles is named).
//!
//! Vertex convexity is computed once per mesh (and again when a deforming mesh moves,
//! [`FastProjection::refresh`]). An edge counts as convex when it folds inwards by
//! at most [`FOLD`] of its length (the diagonal of a slightly non-planar quad: the built-in head
//! has such folds of up to 47 µm on 12 mm edges); the answer is then exact up to that fold
//! height. Clearances are computed lazily, the first time a triangle is asked for, by parry's triangle–triangle distance over the triangles the mesh's BVH
//! finds near it, capped at a fraction of the mesh size (enough for hair near the surface), and
//! shared between threads and clones of the set; the value depends only on the mesh, so results
//! do not depend on which thread computed it first.
//!
//! **Deforming meshes.** A clearance holds for one shape only, and computing one (parry's
//! triangle–triangle distance to every triangle within the cap) costs as much as a few hundred
//! of parry's warm-started searches. A rigid mesh computes each once for the whole run; a mesh
//! that deforms every collision step would compute them anew at every step for the few points
//! each triangle serves: on the shipped character (1,500 hairs on a skinned head and shoulders)
//! that was 40 % of the whole run. So a deformed mesh keeps only the certificate that needs no
//! clearance (a convex body) and otherwise leaves the answer to parry's search, warm-started by
//! the hint's distance as on any mesh.

use std::collections::HashMap;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;

use nalgebra::Vector3;
use parry3d::bounding_volume::BoundingVolume;
use parry3d::math::{Pose, Vector};
use parry3d::shape::{TriMesh, Triangle};

use super::math::from_glam;

/// Bits of a clearance not computed yet (a NaN no computation produces).
const UNKNOWN: u32 = 0x7fc0_dead;

/// Largest inward fold of an edge that still counts as convex, as a fraction of its length.
const FOLD: f32 = 5e-3;

/// Most edge crossings of the walk from the hint triangle.
const WALK: usize = 16;

/// Per-triangle data of the shortcut (see the module docs).
#[derive(Debug, Clone)]
pub(crate) struct FastProjection {
    /// Per triangle, what each try of the walk reads (see [`Plane`]).
    planes: Arc<[Plane]>,
    /// The triangle across each edge `k` (vertices `k`, `k + 1`); `u32::MAX` if none.
    neighbours: Arc<[[u32; 3]]>,
    /// Half the clearance of each triangle, m, as f32 bits (`UNKNOWN` until computed); empty
    /// once the mesh has deformed (module docs, "Deforming meshes").
    half_clearance: Arc<[AtomicU32]>,
    /// Largest clearance looked for, m.
    cap: f32,
    /// Does the mesh bound a convex body (every vertex convex, one connected piece)?
    convex_body: bool,
    /// Is the mesh one piece (every triangle reachable from the first across edges)?
    connected: bool,
    /// Every undirected edge, sorted by its vertices.
    edges: Arc<[Edge]>,
    /// The vertices joined to each vertex by an edge: those of vertex `v` are
    /// `adjacent[adjacent_start[v]..adjacent_start[v + 1]]`.
    adjacent: Arc<[u32]>,
    /// Start of each vertex's run in `adjacent` (one more entry than vertices).
    adjacent_start: Arc<[u32]>,
}

/// A triangle as the walk sees it, computed once per mesh: the same values, to the bit, as
/// computed from the mesh on each try, without its cross product, square root and division.
#[derive(Debug, Clone, Copy)]
struct Plane {
    /// Its corners, body space, m.
    corners: [Vector3<f32>; 3],
    /// Its outward unit normal (winding order).
    normal: Vector3<f32>,
    /// Are all three vertices convex and is the triangle not degenerate?
    usable: bool,
    /// Is `normal` the unit normal (a positive, finite area)?
    unit: bool,
}

/// An undirected edge of the mesh: its vertices (`a < b`) and its two triangles (`None` unless
/// exactly two use it).
#[derive(Debug, Clone, Copy)]
struct Edge {
    a: u32,
    b: u32,
    triangles: Option<[u32; 2]>,
}

/// Where on a mesh triangle a point projects: inside it, on its edge `k` (vertices `k`, `k + 1`)
/// or on its vertex `k`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Feature {
    Face,
    Edge(u32),
    Vertex(u32),
}

/// Where a point projects on a mesh, found through the shortcut.
pub(crate) struct FastHit {
    /// The triangle it projects on.
    pub triangle: u32,
    /// Where on it.
    pub feature: Feature,
}

impl FastProjection {
    /// Prepares the shortcut for a solid (closed, outward-wound) mesh; `cap` (m) is the largest
    /// clearance looked for.
    pub fn new(mesh: &TriMesh, cap: f32) -> Self {
        let vertices = mesh.vertices();
        let indices = mesh.indices();
        // Each undirected edge's two triangles (closed manifold: exactly two).
        let mut by_edge: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
        for (t, tri) in indices.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                by_edge.entry((a.min(b), a.max(b))).or_default().push(t);
            }
        }
        let neighbours: Arc<[[u32; 3]]> = indices
            .iter()
            .enumerate()
            .map(|(t, tri)| {
                std::array::from_fn(|k| {
                    let (a, b) = (tri[k], tri[(k + 1) % 3]);
                    by_edge[&(a.min(b), a.max(b))]
                        .iter()
                        .find(|&&u| u != t)
                        .map_or(u32::MAX, |&u| u as u32)
                })
            })
            .collect();
        let mut around = vec![Vec::new(); vertices.len()];
        for &(a, b) in by_edge.keys() {
            around[a as usize].push(b);
            around[b as usize].push(a);
        }
        let mut adjacent_start = vec![0u32];
        let mut adjacent = Vec::new();
        for list in &mut around {
            list.sort_unstable();
            adjacent.extend_from_slice(list);
            adjacent_start.push(adjacent.len() as u32);
        }
        let mut edges: Vec<Edge> = by_edge
            .iter()
            .map(|(&(a, b), tris)| Edge {
                a,
                b,
                triangles: match tris.as_slice() {
                    &[t1, t2] => Some([t1 as u32, t2 as u32]),
                    _ => None,
                },
            })
            .collect();
        edges.sort_unstable_by_key(|e| (e.a, e.b));
        let mut fast = Self {
            adjacent: adjacent.into(),
            adjacent_start: adjacent_start.into(),
            connected: connected(&neighbours),
            edges: edges.into(),
            planes: Arc::from([]),
            neighbours,
            half_clearance: Arc::from([]),
            cap,
            convex_body: false,
        };
        fast.refresh(mesh.vertices(), mesh.indices());
        fast.half_clearance = (0..mesh.indices().len())
            .map(|_| AtomicU32::new(UNKNOWN))
            .collect();
        fast
    }

    /// Recomputes what depends on the vertex positions (planes, vertex convexity) for a mesh
    /// whose vertices moved to `vertices` (body space, m); `indices` are its triangles, those
    /// the shortcut was made for. The clearances are dropped: a deformed mesh certifies only by
    /// the convex-body rule (module docs, "Deforming meshes"), so the answers are those of
    /// [`FastProjection::new`] on a mesh built at these positions wherever that certifies
    /// without a clearance, and parry's search elsewhere.
    pub fn refresh(&mut self, vertices: &[Vector], indices: &[[u32; 3]]) {
        let triangle = |t: u32| {
            let [a, b, c] = indices[t as usize].map(|i| vertices[i as usize]);
            Triangle::new(a, b, c)
        };
        let mut convex_vertex = vec![true; vertices.len()];
        for &Edge { a, b, triangles } in self.edges.iter() {
            let bends_out = match triangles {
                Some([t1, t2]) => {
                    let tri1 = triangle(t1);
                    let n1 = from_glam(tri1.scaled_normal());
                    // The vertex of t2 not on the edge lies on or below t1's plane.
                    let other = indices[t2 as usize]
                        .iter()
                        .find(|&&v| v != a && v != b)
                        .map(|&v| from_glam(vertices[v as usize]));
                    let edge =
                        (from_glam(vertices[b as usize]) - from_glam(vertices[a as usize])).norm();
                    other.is_some_and(|d| {
                        n1.dot(&(d - from_glam(tri1.a))) <= FOLD * edge * n1.norm()
                    })
                }
                None => false,
            };
            if !bends_out {
                convex_vertex[a as usize] = false;
                convex_vertex[b as usize] = false;
            }
        }
        self.planes = indices
            .iter()
            .enumerate()
            .map(|(t, idx)| {
                let tri = triangle(t as u32);
                let corners = [from_glam(tri.a), from_glam(tri.b), from_glam(tri.c)];
                let scaled = (corners[1] - corners[0]).cross(&(corners[2] - corners[0]));
                let area2 = scaled.norm();
                Plane {
                    corners,
                    normal: scaled / area2,
                    // Exactly where the walk gave up on a degenerate triangle (not on a NaN).
                    usable: idx.iter().all(|&v| convex_vertex[v as usize])
                        && (area2 > 0.0 || area2.is_nan()),
                    unit: area2 > 0.0 && area2.is_finite(),
                }
            })
            .collect();
        self.half_clearance = Arc::from([]);
        self.convex_body = convex_vertex.iter().all(|&c| c) && self.connected;
    }

    /// Drops the clearances, as a deformation does, for a mesh about to deform: only the
    /// convex-body certificate is left.
    pub fn drop_clearances(&mut self) {
        self.half_clearance = Arc::from([]);
    }

    /// Where body-space point `p` projects on `mesh` (the triangle, and the edge if on one), if
    /// triangle `t` or one a short walk away certifies it.
    pub fn project(&self, mesh: &TriMesh, t: u32, p: &Vector3<f32>) -> Option<FastHit> {
        // A deformed mesh that is not a convex body has no certificate left: skip the walk.
        if !self.convex_body && self.half_clearance.is_empty() {
            return None;
        }
        let mut t = t;
        let mut previous = u32::MAX;
        for _ in 0..=WALK {
            let plane = self.planes.get(t as usize)?;
            if !plane.usable {
                return None;
            }
            let (corners, normal) = (&plane.corners, plane.normal);
            let height = normal.dot(&(p - corners[0]));
            // Below a triangle's plane a point may be inside; on a convex body the walk goes on
            // (the edge and vertex tests do not depend on the height), elsewhere it gives up.
            if height <= 0.0 && !self.convex_body {
                return None;
            }
            let foot = p - normal * height;
            // The foot is inside when it is on the inner side of all three edges; otherwise walk
            // across the first edge it is behind.
            let behind = (0..3).find(|&k| {
                let (u, v) = (corners[k], corners[(k + 1) % 3]);
                (v - u).cross(&(foot - u)).dot(&normal) < 0.0
            });
            if let (Some(k), true) = (behind, self.convex_body) {
                let (a, b) = (corners[k], corners[(k + 1) % 3]);
                let ab = b - a;
                let s = (p - a).dot(&ab) / ab.norm_squared();
                // Beyond an end of the edge: that vertex, if the point lies in its region.
                let end = if s <= 0.0 {
                    Some(k)
                } else if s >= 1.0 {
                    Some((k + 1) % 3)
                } else {
                    None
                };
                if let Some(e) = end {
                    if self.vertex_region(mesh, mesh.indices()[t as usize][e], p) {
                        return Some(FastHit {
                            triangle: t,
                            feature: Feature::Vertex(e as u32),
                        });
                    }
                } else if self.neighbours[t as usize][k] == previous
                    && (p - a - ab * s).norm() > 0.0
                {
                    // Behind the edge it came across: behind it seen from both its triangles,
                    // so in the edge's region.
                    return Some(FastHit {
                        triangle: t,
                        feature: Feature::Edge(k as u32),
                    });
                }
            }
            match behind {
                // Back to the triangle it came from: the walk would cycle between the two (a
                // point in the region of their edge on a body that is not convex).
                Some(k) if self.neighbours[t as usize][k] == previous => return None,
                Some(k) => {
                    previous = t;
                    t = self.neighbours[t as usize][k];
                }
                None if height > 0.0
                    && (self.convex_body || height <= self.half_clearance(mesh, t)) =>
                {
                    return Some(FastHit {
                        triangle: t,
                        feature: Feature::Face,
                    })
                }
                None => return None,
            }
            if t == u32::MAX {
                return None;
            }
        }
        None
    }

    /// The unit normal of triangle `t` (winding order), exactly as `(b − a) × (c − a)` divided by
    /// its norm gives it, if that norm is positive and finite.
    pub fn unit_normal(&self, t: u32) -> Option<Vector3<f32>> {
        self.planes
            .get(t as usize)
            .filter(|p| p.unit)
            .map(|p| p.normal)
    }

    /// Is vertex `v` of a convex body the nearest point to `p`? It is when `p − v` makes an
    /// obtuse (or right) angle with every edge leaving `v`: the body lies in the cone of those
    /// edges.
    fn vertex_region(&self, mesh: &TriMesh, v: u32, p: &Vector3<f32>) -> bool {
        let at = from_glam(mesh.vertices()[v as usize]);
        let d = p - at;
        let run =
            self.adjacent_start[v as usize] as usize..self.adjacent_start[v as usize + 1] as usize;
        d.norm_squared() > 0.0
            && self.adjacent[run]
                .iter()
                .all(|&w| d.dot(&(from_glam(mesh.vertices()[w as usize]) - at)) <= 0.0)
    }

    /// Half the clearance of triangle `t`, m, computed on first use; −∞ (no certificate) on a
    /// deformed mesh.
    fn half_clearance(&self, mesh: &TriMesh, t: u32) -> f32 {
        let Some(slot) = self.half_clearance.get(t as usize) else {
            return f32::NEG_INFINITY;
        };
        let bits = slot.load(Ordering::Relaxed);
        if bits != UNKNOWN {
            return f32::from_bits(bits);
        }
        let value = 0.5 * clearance(mesh, t, self.cap);
        slot.store(value.to_bits(), Ordering::Relaxed);
        value
    }
}

/// Are all triangles reachable from the first across edges?
fn connected(neighbours: &[[u32; 3]]) -> bool {
    let mut seen = vec![false; neighbours.len()];
    let mut stack = vec![0usize];
    let mut count = 0;
    while let Some(t) = stack.pop() {
        if t >= seen.len() || seen[t] {
            continue;
        }
        seen[t] = true;
        count += 1;
        stack.extend(
            neighbours[t]
                .iter()
                .filter(|&&u| u != u32::MAX)
                .map(|&u| u as usize),
        );
    }
    count == neighbours.len()
}

/// Smallest distance (m) from triangle `t` to a triangle sharing no vertex with it, at most `cap`.
fn clearance(mesh: &TriMesh, t: u32, cap: f32) -> f32 {
    let tri = mesh.triangle(t);
    let own = mesh.indices()[t as usize];
    let region = tri.local_aabb().loosened(cap);
    let mut nearest = cap;
    for u in mesh.bvh().leaves(|node| node.aabb().intersects(&region)) {
        let other = mesh.indices()[u as usize];
        if u == t || other.iter().any(|v| own.contains(v)) {
            continue;
        }
        let d = parry3d::query::distance(&Pose::IDENTITY, &tri, &Pose::IDENTITY, &mesh.triangle(u))
            .map_or(0.0, |d| d.distance);
        nearest = nearest.min(d);
    }
    nearest
}

#[cfg(test)]
mod tests {
    use super::super::math::to_glam;
    use super::*;
    use parry3d::query::PointQuery;
    use parry3d::shape::TriMeshFlags;

    /// An octahedron of radius 1 (closed, convex, outward).
    fn octahedron() -> TriMesh {
        let v = [
            Vector3::x(),
            -Vector3::x(),
            Vector3::y(),
            -Vector3::y(),
            Vector3::z(),
            -Vector3::z(),
        ]
        .map(|p| to_glam(&p))
        .to_vec();
        let t = vec![
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ];
        TriMesh::with_flags(v, t, TriMeshFlags::ORIENTED).unwrap()
    }

    /// The nearest point to `p` on the triangle or edge the shortcut named.
    fn nearest_on(mesh: &TriMesh, hit: &FastHit, p: &Vector3<f32>) -> Vector3<f32> {
        let tri = mesh.triangle(hit.triangle);
        let c = [from_glam(tri.a), from_glam(tri.b), from_glam(tri.c)];
        match hit.feature {
            Feature::Edge(k) => {
                let (a, b) = (c[k as usize], c[(k as usize + 1) % 3]);
                a + (b - a) * ((p - a).dot(&(b - a)) / (b - a).norm_squared())
            }
            Feature::Vertex(k) => c[k as usize],
            Feature::Face => {
                let n = (c[1] - c[0]).cross(&(c[2] - c[0])).normalize();
                p - n * n.dot(&(p - c[0]))
            }
        }
    }

    #[test]
    fn shortcut_agrees_with_parry_where_it_answers() {
        let mesh = octahedron();
        let fast = FastProjection::new(&mesh, 0.5);
        let mut answered = 0;
        for k in 0..400 {
            let a = k as f32 * 0.61;
            let dir = Vector3::new(a.cos(), a.sin(), (k as f32 * 0.37).sin()).normalize();
            let p = dir * (0.6 + 0.02 * (k % 50) as f32);
            let exact = mesh.project_local_point(to_glam(&p), false);
            let exact_dist = (from_glam(exact.point) - p).norm();
            for t in 0..8 {
                if let Some(hit) = fast.project(&mesh, t, &p) {
                    assert!(hit.triangle < 8);
                    answered += 1;
                    assert!(!exact.is_inside);
                    let point = nearest_on(&mesh, &hit, &p);
                    assert!(((point - p).norm() - exact_dist).abs() < 1e-5, "{k} {t}");
                    assert!((point - from_glam(exact.point)).norm() < 1e-5);
                }
            }
        }
        assert!(answered > 100, "the shortcut answered {answered} times");
    }

    #[test]
    fn points_in_edge_and_vertex_regions_of_a_convex_body_project_there() {
        // Nearest to the middle of the edge from +x to +y, starting from the face above it.
        let mesh = octahedron();
        let fast = FastProjection::new(&mesh, 0.5);
        let p = Vector3::new(0.8, 0.8, 0.0);
        let hit = fast.project(&mesh, 0, &p).expect("the edge answers");
        assert!(matches!(hit.feature, Feature::Edge(_)));
        assert!((nearest_on(&mesh, &hit, &p) - Vector3::new(0.5, 0.5, 0.0)).norm() < 1e-6);
        // Nearest to the vertex +x.
        let p = Vector3::new(2.0, 0.1, 0.05);
        let hit = fast.project(&mesh, 0, &p).expect("the vertex answers");
        assert!(matches!(hit.feature, Feature::Vertex(_)));
        assert_eq!(nearest_on(&mesh, &hit, &p), Vector3::x());
    }

    #[test]
    fn on_a_convex_body_the_walk_crosses_triangles_a_point_lies_below() {
        // The hint is the face of +x, +y, +z; the point lies above the face of +x, −y, +z and
        // below the hint's plane (hair that slid past its old triangle within one step).
        let mesh = octahedron();
        let fast = FastProjection::new(&mesh, 0.5);
        let p = Vector3::new(0.9, -0.5, 0.4);
        assert!(p.sum() < 1.0, "below the hint's plane x + y + z = 1");
        let hit = fast
            .project(&mesh, 0, &p)
            .expect("the walk reaches the next face");
        assert_eq!((hit.triangle, hit.feature), (3, Feature::Face));
        let exact = mesh.project_local_point(to_glam(&p), false);
        assert!((nearest_on(&mesh, &hit, &p) - from_glam(exact.point)).norm() < 1e-6);
        // Inside the body, under the hint's own face: no certificate, parry decides.
        assert!(fast
            .project(&mesh, 0, &Vector3::new(0.1, 0.1, 0.1))
            .is_none());
    }

    #[test]
    fn concave_vertices_disable_the_shortcut() {
        // A square pyramid pushed in at its apex (a dent): the apex is not convex.
        let v = [
            Vector3::new(1.0, 1.0, 0.0),
            Vector3::new(-1.0, 1.0, 0.0),
            Vector3::new(-1.0, -1.0, 0.0),
            Vector3::new(1.0, -1.0, 0.0),
            Vector3::new(0.0, 0.0, -0.5),
            Vector3::new(0.0, 0.0, -2.0),
        ]
        .map(|p| to_glam(&p))
        .to_vec();
        let t = vec![
            [0, 1, 4],
            [1, 2, 4],
            [2, 3, 4],
            [3, 0, 4],
            [1, 0, 5],
            [2, 1, 5],
            [3, 2, 5],
            [0, 3, 5],
        ];
        let mesh = TriMesh::with_flags(v, t, TriMeshFlags::ORIENTED).unwrap();
        let fast = FastProjection::new(&mesh, 0.5);
        assert!(fast.planes[..4].iter().all(|p| !p.usable));
        assert!(!fast.convex_body);
        assert!(FastProjection::new(&octahedron(), 0.5).convex_body);
    }
}
