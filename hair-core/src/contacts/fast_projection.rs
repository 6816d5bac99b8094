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
//! answer at any height, with no clearance needed (the built-in head, a UV sphere).
//!
//! When the foot falls outside `T`, the search walks to the neighbour across the edge it fell
//! behind (at most [`WALK`] times: hair moves little per step) and tries the certificate there.
//! Each try costs a plane distance and a barycentric check (a few dozen flops) where parry's BVH
//! search from the root costs a few hundred nanoseconds. It is the same answer, not an
//! approximation (up to which of two equally near triangles is named).
//!
//! Vertex convexity is computed once per mesh. An edge counts as convex when it folds inwards by
//! at most [`FOLD`] of its length (the diagonal of a slightly non-planar quad: the built-in head
//! has such folds of up to 47 µm on 12 mm edges); the answer is then exact up to that fold
//! height. Clearances are computed lazily, the first time a triangle is asked for, by parry's triangle–triangle distance over the triangles the mesh's BVH
//! finds near it, capped at a fraction of the mesh size (enough for hair near the surface), and
//! shared between threads and clones of the set; the value depends only on the mesh, so results
//! do not depend on which thread computed it first.

use std::collections::HashMap;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;

use nalgebra::Vector3;
use parry3d::bounding_volume::BoundingVolume;
use parry3d::math::Pose;
use parry3d::shape::TriMesh;

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
    /// Are all three vertices of the triangle convex?
    convex: Arc<[bool]>,
    /// The triangle across each edge `k` (vertices `k`, `k + 1`); `u32::MAX` if none.
    neighbours: Arc<[[u32; 3]]>,
    /// Half the clearance of each triangle, m, as f32 bits (`UNKNOWN` until computed).
    half_clearance: Arc<[AtomicU32]>,
    /// Largest clearance looked for, m.
    cap: f32,
    /// Does the mesh bound a convex body (every vertex convex, one connected piece)?
    convex_body: bool,
}

/// A point's projection on a mesh triangle through the shortcut, body space.
pub(crate) struct FastHit {
    /// The foot of the point on the triangle, m.
    pub point: Vector3<f32>,
    /// The triangle's outward unit normal.
    pub normal: Vector3<f32>,
    /// Height of the point above the triangle, m (> 0).
    pub height: f32,
    /// The triangle it projects on.
    pub triangle: u32,
}

impl FastProjection {
    /// Prepares the shortcut for a solid (closed, outward-wound) mesh; `cap` (m) is the largest
    /// clearance looked for.
    pub fn new(mesh: &TriMesh, cap: f32) -> Self {
        let vertices = mesh.vertices();
        let indices = mesh.indices();
        // Each undirected edge's two triangles (closed manifold: exactly two).
        let mut edges: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
        for (t, tri) in indices.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                edges.entry((a.min(b), a.max(b))).or_default().push(t);
            }
        }
        let mut convex_vertex = vec![true; vertices.len()];
        for (&(a, b), tris) in &edges {
            let bends_out = match tris.as_slice() {
                &[t1, t2] => {
                    let tri1 = mesh.triangle(t1 as u32);
                    let n1 = from_glam(tri1.scaled_normal());
                    // The vertex of t2 not on the edge lies on or below t1's plane.
                    let other = indices[t2]
                        .iter()
                        .find(|&&v| v != a && v != b)
                        .map(|&v| from_glam(vertices[v as usize]));
                    let edge =
                        (from_glam(vertices[b as usize]) - from_glam(vertices[a as usize])).norm();
                    other.is_some_and(|d| {
                        n1.dot(&(d - from_glam(tri1.a))) <= FOLD * edge * n1.norm()
                    })
                }
                _ => false,
            };
            if !bends_out {
                convex_vertex[a as usize] = false;
                convex_vertex[b as usize] = false;
            }
        }
        let convex: Arc<[bool]> = indices
            .iter()
            .map(|t| t.iter().all(|&v| convex_vertex[v as usize]))
            .collect();
        let neighbours: Arc<[[u32; 3]]> = indices
            .iter()
            .enumerate()
            .map(|(t, tri)| {
                std::array::from_fn(|k| {
                    let (a, b) = (tri[k], tri[(k + 1) % 3]);
                    edges[&(a.min(b), a.max(b))]
                        .iter()
                        .find(|&&u| u != t)
                        .map_or(u32::MAX, |&u| u as u32)
                })
            })
            .collect();
        let half_clearance = (0..indices.len())
            .map(|_| AtomicU32::new(UNKNOWN))
            .collect();
        let convex_body = convex_vertex.iter().all(|&c| c) && connected(&neighbours);
        Self {
            convex,
            neighbours,
            half_clearance,
            cap,
            convex_body,
        }
    }

    /// The exact projection of body-space point `p` on `mesh`, if triangle `t` or one a short
    /// walk away certifies it.
    pub fn project(&self, mesh: &TriMesh, t: u32, p: &Vector3<f32>) -> Option<FastHit> {
        let mut t = t;
        for _ in 0..=WALK {
            if !*self.convex.get(t as usize)? {
                return None;
            }
            let tri = mesh.triangle(t);
            let corners = [from_glam(tri.a), from_glam(tri.b), from_glam(tri.c)];
            let scaled = (corners[1] - corners[0]).cross(&(corners[2] - corners[0]));
            let area2 = scaled.norm();
            if area2 <= 0.0 {
                return None;
            }
            let normal = scaled / area2;
            let height = normal.dot(&(p - corners[0]));
            if height <= 0.0 {
                return None;
            }
            let foot = p - normal * height;
            // The foot is inside when it is on the inner side of all three edges; otherwise walk
            // across the first edge it is behind.
            let behind = (0..3).find(|&k| {
                let (u, v) = (corners[k], corners[(k + 1) % 3]);
                (v - u).cross(&(foot - u)).dot(&normal) < 0.0
            });
            match behind {
                Some(k) => t = self.neighbours[t as usize][k],
                None if self.convex_body || height <= self.half_clearance(mesh, t) => {
                    return Some(FastHit {
                        point: foot,
                        normal,
                        height,
                        triangle: t,
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

    /// Half the clearance of triangle `t`, m, computed on first use.
    fn half_clearance(&self, mesh: &TriMesh, t: u32) -> f32 {
        let slot = &self.half_clearance[t as usize];
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
                    assert!((hit.height - exact_dist).abs() < 1e-5, "{k} {t}");
                    assert!((hit.point - from_glam(exact.point)).norm() < 1e-5);
                }
            }
        }
        assert!(answered > 100, "the shortcut answered {answered} times");
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
        assert!(fast.convex[..4].iter().all(|&c| !c));
        assert!(!fast.convex_body);
        assert!(FastProjection::new(&octahedron(), 0.5).convex_body);
    }
}
