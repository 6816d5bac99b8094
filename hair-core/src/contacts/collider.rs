//! What a collider is: an analytic sphere or capsule or a triangle mesh in the collider's own body
//! space, a thickness and a friction coefficient. A [`super::Colliders`] set places each one in the
//! world with a rigid pose per frame.
//!
//! # Meshes: solids and shells
//! A mesh whose edges are each shared by exactly two triangles with opposite windings (closed,
//! manifold and consistently oriented, after merging vertices at identical positions, which OBJ
//! files split at UV seams) is a **solid**: a point inside it is detected as inside (parry's
//! pseudo-normal test) and pushed out. A closed mesh wound inwards (negative volume) is turned
//! outwards. Any other mesh — open (a plate, a scalp cap), non-manifold (three triangles on an
//! edge) or inconsistently wound — is a two-sided **shell** with no inside: a hair point is held
//! on the side of the surface it is on at the start of each collision step, `thickness` + its
//! radius away from it. Give shells a thickness of a few hair radii. [`MeshKind`] says which one
//! a mesh became and why.
//!
//! Triangles of zero area and meshes without triangles never get here: [`TriMesh::new`] refuses
//! them, naming the triangle.

use std::collections::HashMap;

use nalgebra::Vector3;

use crate::error::{HairError, Result};
use crate::mesh::TriMesh;

/// Geometry of a collider in its body space, m.
#[derive(Debug, Clone)]
pub enum ColliderShape {
    /// A sphere of `radius` (m) centred at the body origin.
    Sphere {
        /// Radius, m (> 0).
        radius: f32,
    },
    /// A capsule along the body z axis: the points within `radius` (m) of the segment from
    /// `(0, 0, −half_height)` to `(0, 0, half_height)` (m).
    Capsule {
        /// Half the length of the axis segment, m (≥ 0; 0 is a sphere).
        half_height: f32,
        /// Radius, m (> 0).
        radius: f32,
    },
    /// A triangle mesh, vertex positions in body space (m). See the module docs for solids and
    /// shells.
    Mesh(TriMesh),
}

impl ColliderShape {
    /// Largest distance of a point of the shape from the body origin, m: how far a turn of the
    /// body can carry its surface per radian.
    pub fn bounding_radius(&self) -> f32 {
        match self {
            Self::Sphere { radius } => *radius,
            Self::Capsule {
                half_height,
                radius,
            } => half_height + radius,
            Self::Mesh(mesh) => mesh
                .positions()
                .iter()
                .map(|v| v.norm())
                .fold(0.0f32, f32::max),
        }
    }
}

/// A collider before it is placed in a [`super::Colliders`] set.
#[derive(Debug, Clone)]
pub struct Collider {
    /// Geometry in body space.
    pub shape: ColliderShape,
    /// Distance kept between the surface and hair, m (≥ 0), on top of each hair point's radius:
    /// the surface hair rests on is the shape grown by `thickness`.
    pub thickness: f32,
    /// Coulomb friction coefficient between hair and this surface (≥ 0, dimensionless):
    /// tangential velocity relative to the surface changes by at most `friction` × the normal
    /// velocity change of the contact.
    pub friction: f32,
}

impl Collider {
    /// A sphere of `radius` (m), no thickness, no friction.
    pub fn sphere(radius: f32) -> Self {
        Self::new(ColliderShape::Sphere { radius })
    }

    /// A capsule along the body z axis, `half_height` (m) from the origin to each end cap's
    /// centre, `radius` (m); no thickness, no friction.
    pub fn capsule(half_height: f32, radius: f32) -> Self {
        Self::new(ColliderShape::Capsule {
            half_height,
            radius,
        })
    }

    /// A triangle mesh in body space (m); no thickness, no friction.
    pub fn mesh(mesh: TriMesh) -> Self {
        Self::new(ColliderShape::Mesh(mesh))
    }

    fn new(shape: ColliderShape) -> Self {
        Self {
            shape,
            thickness: 0.0,
            friction: 0.0,
        }
    }

    /// Sets the thickness, m.
    pub fn with_thickness(mut self, thickness: f32) -> Self {
        self.thickness = thickness;
        self
    }

    /// Sets the friction coefficient.
    pub fn with_friction(mut self, friction: f32) -> Self {
        self.friction = friction;
        self
    }

    /// Checks sizes (finite, radius > 0, half height ≥ 0), thickness and friction (finite, ≥ 0).
    /// `collider` is the index named in the error.
    pub fn validate(&self, collider: usize) -> Result<()> {
        let bad = |what: &str, value: f32, fix: &str| {
            Err(HairError::Collider {
                collider,
                message: format!("{what} = {value}: {fix}"),
            })
        };
        match self.shape {
            ColliderShape::Sphere { radius } | ColliderShape::Capsule { radius, .. }
                if !(radius.is_finite() && radius > 0.0) =>
            {
                return bad("radius", radius, "use a finite radius > 0 m");
            }
            ColliderShape::Capsule { half_height, .. }
                if !(half_height.is_finite() && half_height >= 0.0) =>
            {
                return bad(
                    "half_height",
                    half_height,
                    "use a finite half height ≥ 0 m (0 makes a sphere)",
                );
            }
            _ => {}
        }
        if !(self.thickness.is_finite() && self.thickness >= 0.0) {
            return bad("thickness", self.thickness, "use a finite thickness ≥ 0 m");
        }
        if !(self.friction.is_finite() && self.friction >= 0.0) {
            return bad(
                "friction",
                self.friction,
                "use a finite coefficient ≥ 0 (0 = frictionless, about 0.3 for hair on skin)",
            );
        }
        Ok(())
    }
}

/// How a collider mesh is treated (see the module docs).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum MeshKind {
    /// Closed, manifold, consistently wound: it has an inside, and hair inside is pushed out.
    Solid {
        /// True if the file's triangles were wound inwards and were turned outwards.
        flipped: bool,
    },
    /// Open, non-manifold or inconsistently wound: a two-sided surface with no inside.
    Shell {
        /// Why it is not a solid, e.g. "24 boundary edges (the mesh is open)".
        reason: String,
    },
}

/// A mesh ready for parry: vertices at identical positions merged, triangles wound outwards for
/// solids, and its kind.
pub(crate) struct PreparedMesh {
    pub vertices: Vec<Vector3<f32>>,
    /// Per vertex of the given mesh: its index in `vertices`.
    pub remap: Vec<u32>,
    pub triangles: Vec<[u32; 3]>,
    pub kind: MeshKind,
    /// Smallest normal curvature per triangle, 1/m (> 0 convex along the winding normal).
    pub curvature: Vec<f32>,
    /// Smooth (area-weighted) unit normal per vertex, along the winding normal.
    pub vertex_normals: Vec<Vector3<f32>>,
    /// Per triangle and edge `k` (vertices `k`, `k + 1`): the smallest index of a triangle
    /// using that edge.
    pub edge_owner: Vec<[u32; 3]>,
    /// Per vertex: the smallest index of a triangle using it (`u32::MAX` if none).
    pub vertex_owner: Vec<u32>,
}

/// Fraction by which estimated curvatures are moved to the conservative side (see
/// `min_curvatures`).
const CURVATURE_CAUTION: f32 = 0.2;

/// Merges vertices at bit-identical positions, classifies the mesh as solid or shell and winds a
/// solid outwards.
pub(crate) fn prepare_mesh(mesh: &TriMesh) -> PreparedMesh {
    let mut index_of: HashMap<[u32; 3], u32> = HashMap::new();
    let mut vertices = Vec::new();
    let remap: Vec<u32> = mesh
        .positions()
        .iter()
        .map(|p| {
            // +0.0 and −0.0 are the same position.
            let key = [p.x, p.y, p.z].map(|c| (c + 0.0).to_bits());
            *index_of.entry(key).or_insert_with(|| {
                vertices.push(*p);
                (vertices.len() - 1) as u32
            })
        })
        .collect();
    let mut triangles: Vec<[u32; 3]> = mesh
        .triangles()
        .iter()
        .map(|t| t.map(|i| remap[i as usize]))
        .collect();

    // Each undirected edge: how often it is used along (a < b) and against its order.
    let mut edges: HashMap<(u32, u32), (u32, u32)> = HashMap::new();
    for t in &triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let entry = edges.entry((a.min(b), a.max(b))).or_default();
            if a < b {
                entry.0 += 1;
            } else {
                entry.1 += 1;
            }
        }
    }
    let (mut boundary, mut non_manifold, mut misoriented) = (0usize, 0usize, 0usize);
    for &(along, against) in edges.values() {
        match along + against {
            1 => boundary += 1,
            2 if along != 1 => misoriented += 1,
            2 => {}
            _ => non_manifold += 1,
        }
    }
    let kind = if boundary + non_manifold + misoriented == 0 {
        // Signed volume by the divergence theorem (relative to the first vertex, for precision).
        let o = vertices[0];
        let volume: f64 = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| (vertices[i as usize] - o).cast::<f64>());
                a.dot(&b.cross(&c)) / 6.0
            })
            .sum();
        let flipped = volume < 0.0;
        if flipped {
            for t in &mut triangles {
                t.swap(1, 2);
            }
        }
        MeshKind::Solid { flipped }
    } else {
        let mut parts = Vec::new();
        if boundary > 0 {
            parts.push(format!("{boundary} boundary edges (the mesh is open)"));
        }
        if non_manifold > 0 {
            parts.push(format!(
                "{non_manifold} edges shared by more than two triangles (non-manifold)"
            ));
        }
        if misoriented > 0 {
            parts.push(format!(
                "{misoriented} edges between triangles of opposite winding"
            ));
        }
        MeshKind::Shell {
            reason: parts.join(", "),
        }
    };
    let vertex_normals = smooth_normals(&vertices, &triangles);
    let curvature = min_curvatures(&vertices, &triangles, &vertex_normals);
    let (edge_owner, vertex_owner) = feature_owners(vertices.len(), &triangles);
    PreparedMesh {
        vertices,
        remap,
        triangles,
        kind,
        curvature,
        vertex_normals,
        edge_owner,
        vertex_owner,
    }
}

/// The triangle that speaks for each edge and vertex: the smallest index of the triangles using
/// it. A point nearest to an edge or a vertex is nearest to all their triangles alike; contact
/// detection names this one, so its answer does not depend on which of them a search met first.
fn feature_owners(vertex_count: usize, triangles: &[[u32; 3]]) -> (Vec<[u32; 3]>, Vec<u32>) {
    let mut edge: HashMap<(u32, u32), u32> = HashMap::new();
    let mut vertex_owner = vec![u32::MAX; vertex_count];
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let owner = edge.entry((a.min(b), a.max(b))).or_insert(t as u32);
            *owner = (*owner).min(t as u32);
            let v = &mut vertex_owner[tri[k] as usize];
            *v = (*v).min(t as u32);
        }
    }
    let edge_owner = triangles
        .iter()
        .map(|tri| {
            std::array::from_fn(|k| {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                edge[&(a.min(b), a.max(b))]
            })
        })
        .collect();
    (edge_owner, vertex_owner)
}

/// Area-weighted unit normal of every vertex, along the triangles' winding (zero for a vertex
/// of zero-area triangles only).
pub(crate) fn smooth_normals(
    vertices: &[Vector3<f32>],
    triangles: &[[u32; 3]],
) -> Vec<Vector3<f32>> {
    let mut normals = vec![Vector3::zeros(); vertices.len()];
    for t in triangles {
        let [a, b, c] = t.map(|i| vertices[i as usize]);
        let n = (b - a).cross(&(c - a));
        for &i in t {
            normals[i as usize] += n;
        }
    }
    for n in &mut normals {
        let len = n.norm();
        if len > 0.0 {
            *n /= len;
        }
    }
    normals
}

/// A cautious smallest normal curvature of each triangle (1/m, signed: > 0 where the surface bends
/// away from its winding normal, as on a convex solid). Along each edge the normal curvature is
/// estimated from the area-weighted smooth vertex normals, `κ_e = (n_b − n_a)·(p_b − p_a)/|p_b −
/// p_a|²`; a triangle takes the smallest over the edges of every triangle sharing a vertex with
/// it, moved by [`CURVATURE_CAUTION`] of its size towards the conservative side (flatter where
/// convex, more curved where concave).
///
/// The contact model takes a sphere of this curvature tangent at the contact, so that hair sliding
/// over a smooth (finely tessellated) surface within a collision step follows its bend instead of
/// the contact's tangent plane. A sphere flatter than the surface in every direction keeps hair
/// sliding over it at worst slightly off the surface (by `(κ_true − κ) s²/2` for a slide `s`),
/// never in; an estimate that came out too curved would let fast hair in by the same amount
/// (measured on a UV sphere: single-edge estimates scatter by about ±15 % near its poles, which let
/// whipping tips sliding 30 cm per step 8 mm in, hence the neighbourhood minimum and the
/// caution). On a mesh with sharp edges the smooth normals spread the edges' bend over the flat
/// faces next to them, where the sphere can then dip below a face by up to `κ s²/2`.
pub(crate) fn min_curvatures(
    vertices: &[Vector3<f32>],
    triangles: &[[u32; 3]],
    normals: &[Vector3<f32>],
) -> Vec<f32> {
    let own: Vec<f32> = triangles
        .iter()
        .map(|t| {
            (0..3)
                .map(|k| {
                    let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
                    let e = vertices[b] - vertices[a];
                    (normals[b] - normals[a]).dot(&e) / e.norm_squared()
                })
                .fold(f32::INFINITY, f32::min)
        })
        .collect();
    // Smallest over the triangles around each vertex, then over a triangle's three vertices.
    let mut at_vertex = vec![f32::INFINITY; vertices.len()];
    for (t, &k) in triangles.iter().zip(&own) {
        for &i in t {
            at_vertex[i as usize] = at_vertex[i as usize].min(k);
        }
    }
    triangles
        .iter()
        .map(|t| {
            let k = t
                .iter()
                .map(|&i| at_vertex[i as usize])
                .fold(f32::INFINITY, f32::min);
            k - CURVATURE_CAUTION * k.abs()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetrahedron(inward: bool) -> TriMesh {
        let p = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.0, 0.0, 1.0),
        ];
        let mut t = vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
        if inward {
            for tri in &mut t {
                tri.swap(1, 2);
            }
        }
        TriMesh::new(p, t).unwrap()
    }

    #[test]
    fn closed_mesh_is_a_solid_and_inward_winding_is_turned() {
        assert_eq!(
            prepare_mesh(&tetrahedron(false)).kind,
            MeshKind::Solid { flipped: false }
        );
        let inward = prepare_mesh(&tetrahedron(true));
        assert_eq!(inward.kind, MeshKind::Solid { flipped: true });
        assert_eq!(inward.triangles[0], [0, 2, 1]);
    }

    #[test]
    fn curvature_of_a_fine_sphere_is_cautiously_below_one_over_its_radius() {
        let prepared = prepare_mesh(&TriMesh::uv_sphere(0.5, 64, 32).unwrap());
        assert_eq!(prepared.kind, MeshKind::Solid { flipped: false });
        let (lo, hi) = prepared
            .curvature
            .iter()
            .fold((f32::MAX, f32::MIN), |(lo, hi), &k| (lo.min(k), hi.max(k)));
        // The true 2 /m, taken flatter: 0.8 × the smallest estimate around each triangle.
        assert!(
            lo > 1.3 && hi < 2.0,
            "curvature {lo}..{hi} /m, expected just under 2 /m"
        );
    }

    #[test]
    fn split_seam_vertices_are_merged() {
        // The tetrahedron with vertex 0 duplicated for its last use (as an OBJ UV seam would).
        let m = tetrahedron(false);
        let mut p = m.positions().to_vec();
        p.push(p[0]);
        let t = vec![[0, 2, 1], [0, 1, 3], [4, 3, 2], [1, 2, 3]];
        let prepared = prepare_mesh(&TriMesh::new(p, t).unwrap());
        assert_eq!(prepared.vertices.len(), 4);
        assert_eq!(prepared.kind, MeshKind::Solid { flipped: false });
    }

    #[test]
    fn open_and_non_manifold_meshes_are_shells() {
        let p = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.0, -1.0, 0.0),
            Vector3::new(0.0, 0.0, 1.0),
        ];
        let open = TriMesh::new(p.clone(), vec![[0, 1, 2]]).unwrap();
        let MeshKind::Shell { reason } = prepare_mesh(&open).kind else {
            panic!("an open triangle is a shell")
        };
        assert!(reason.contains("3 boundary edges"), "{reason}");
        // Three triangles on the edge 0–1.
        let fan = TriMesh::new(p, vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]]).unwrap();
        let MeshKind::Shell { reason } = prepare_mesh(&fan).kind else {
            panic!("a non-manifold fan is a shell")
        };
        assert!(reason.contains("non-manifold"), "{reason}");
    }

    #[test]
    fn bad_sizes_are_named() {
        let err = Collider::sphere(-1.0).validate(3).unwrap_err();
        assert!(err.to_string().contains("collider 3"), "{err}");
        assert!(err.to_string().contains("radius"), "{err}");
        let err = Collider::capsule(f32::NAN, 0.1).validate(0).unwrap_err();
        assert!(err.to_string().contains("half_height"), "{err}");
        let err = Collider::sphere(1.0)
            .with_friction(-0.1)
            .validate(0)
            .unwrap_err();
        assert!(err.to_string().contains("friction"), "{err}");
        assert!(Collider::sphere(1.0)
            .with_thickness(f32::INFINITY)
            .validate(0)
            .is_err());
    }
}
