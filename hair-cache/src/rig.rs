//! The rig of a cache: what the hair hangs on, so that outputs (render children, shot export,
//! previews, quality checks) read everything from the cache and never rebuild the scene.
//!
//! A [`CacheRig`] is written once, as the attachment [`RIG_ATTACHMENT_NAME`]: how each strand
//! is rooted ([`Anchor`]: a mesh sample on the scalp or a frame in the scalp's body space), the
//! scalp mesh at rest in its body space (with its UVs and vertex colours, which children take at
//! their roots), the colliders' shapes, thickness and friction, and each strand's factors of its
//! children's clump and curl. A [`RigFrame`] is written with every frame on the channel
//! [`RIG_TOPIC`]: the scalp's body transform and, where it deforms, its vertices; each
//! collider's pose and, where it deforms, its vertices. The byte layouts are specified in
//! [`crate::layout`] (sections "Rig attachment" and "Rig frame payload").
//!
//! Both are optional: a cache without them still holds the hair, and a reader that does not know
//! them reads the frames as before.

use std::fmt;

use hair_core::{Anchor, Collider, ColliderShape, HairError, MeshSample, RootFrame, TriMesh};
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector2, Vector3};
use thiserror::Error;

use crate::layout::{CacheLayout, LeReader, Truncated};

/// Name of the attachment holding the [`CacheRig`].
pub const RIG_ATTACHMENT_NAME: &str = "hairsys/rig.bin";
/// Topic of the channel of [`RigFrame`]s.
pub const RIG_TOPIC: &str = "/hairsys/rig";
/// Message encoding of the rig channel.
pub const RIG_MESSAGE_ENCODING: &str = "hairsys.rig.v1";
/// Name of the rig channel's schema.
pub const RIG_SCHEMA_NAME: &str = "hairsys.RigFrame";
/// Data of the rig channel's schema: a description of the payload.
pub const RIG_SCHEMA_TEXT: &str = "hairsys rig frame, version 1, little-endian:\n\
u32 version (1)\n\
u32 frame\n\
f32 scalp_body[7] (translation x y z m, rotation quaternion i j k w)\n\
u32 has_scalp_vertices; if 1: f32 scalp_vertices[3V] (m, scalp body space)\n\
u32 collider_count C; per collider: f32 pose[7], u32 has_vertices; if 1: f32 vertices[3V] (m, body space)\n\
Anchors, rest scalp, collider shapes: attachment hairsys/rig.bin.\n";
/// Version of the rig attachment and rig frame layouts.
pub const RIG_VERSION: u32 = 1;

/// The scalp a cache's strands are rooted on, at rest in its body space.
#[derive(Debug, Clone)]
pub struct RigScalp {
    /// The rest mesh (m, body space), with its UVs if it has them.
    pub mesh: TriMesh,
    /// One RGB colour (0–1) per vertex, if the scalp has vertex colours.
    pub colors: Option<Vec<[f32; 3]>>,
}

/// What a cache's hair hangs on, written once per cache. See the module docs.
#[derive(Debug, Clone)]
pub struct CacheRig {
    /// How each strand is rooted, one per strand of the layout.
    pub anchors: Vec<Anchor>,
    /// Each point's rest position in its strand's root frame (m), one per point of the layout:
    /// the shape the hair returns to, which quality reports measure against.
    pub rest_local: Vec<Vector3<f32>>,
    /// Each point's inverse mass (1/kg); 0 for points held kinematically (roots, pins).
    pub inverse_masses: Vec<f32>,
    /// The scalp mesh, if strands are rooted on one.
    pub scalp: Option<RigScalp>,
    /// When the scalp is a collider for its own hair: its thickness (m) and friction.
    pub scalp_collider: Option<(f32, f32)>,
    /// The colliders (shapes in body space, m; thickness m; friction), in id order; the
    /// scalp's own collider is not among them (it is the scalp).
    pub colliders: Vec<Collider>,
    /// Each strand's factor (0–1) of its children's clump, if maps give one.
    pub clump: Option<Vec<f32>>,
    /// Each strand's factor (0–1) of its children's curl radius, if maps give one.
    pub curl: Option<Vec<f32>>,
}

/// A collider at one frame.
#[derive(Debug, Clone, PartialEq)]
pub struct ColliderState {
    /// Body to world, m.
    pub pose: Isometry3<f32>,
    /// The deformed vertices (m, body space), for a mesh that deforms.
    pub vertices: Option<Vec<Vector3<f32>>>,
}

/// The scalp and the colliders at one frame. See the module docs.
#[derive(Debug, Clone, PartialEq)]
pub struct RigFrame {
    /// The scalp's body to world transform, m.
    pub scalp_body: Isometry3<f32>,
    /// The deformed scalp vertices (m, body space), for a scalp that deforms.
    pub scalp_vertices: Option<Vec<Vector3<f32>>>,
    /// Each collider of the rig, in id order.
    pub colliders: Vec<ColliderState>,
}

impl CacheRig {
    /// Checks the rig against `layout`: one anchor and factor per strand, one rest position and
    /// inverse mass per point (finite; inverse masses ≥ 0), anchors on the scalp's triangles.
    pub fn validate(&self, layout: &CacheLayout) -> Result<(), RigError> {
        let (strands, points) = (layout.strand_count(), layout.point_count());
        for (field, found) in [
            (RigField::RestPositions, self.rest_local.len()),
            (RigField::InverseMasses, self.inverse_masses.len()),
        ] {
            if found != points {
                return Err(RigError::PerPoint {
                    field,
                    found,
                    points,
                });
            }
        }
        if let Some(point) = self
            .rest_local
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(RigError::RestPosition { point });
        }
        if let Some(point) = self
            .inverse_masses
            .iter()
            .position(|m| !(m.is_finite() && *m >= 0.0))
        {
            return Err(RigError::InverseMass {
                point,
                value: self.inverse_masses[point],
            });
        }
        if self.anchors.len() != strands {
            return Err(RigError::PerStrand {
                field: RigField::Anchors,
                found: self.anchors.len(),
                strands,
            });
        }
        for (field, f) in [(RigField::Clump, &self.clump), (RigField::Curl, &self.curl)] {
            if let Some(f) = f {
                if f.len() != strands {
                    return Err(RigError::PerStrand {
                        field,
                        found: f.len(),
                        strands,
                    });
                }
            }
        }
        for (strand, a) in self.anchors.iter().enumerate() {
            if let Anchor::Surface(sample) = a {
                let Some(scalp) = &self.scalp else {
                    return Err(RigError::NoScalpForAnchor { strand });
                };
                sample
                    .validate(&scalp.mesh)
                    .map_err(|source| RigError::Anchor { strand, source })?;
            }
        }
        if let Some(RigScalp {
            mesh,
            colors: Some(c),
        }) = &self.scalp
        {
            if c.len() != mesh.positions().len() {
                return Err(RigError::ColorCount {
                    found: c.len(),
                    vertices: mesh.positions().len(),
                });
            }
        }
        Ok(())
    }

    /// The attachment's bytes (layout: [`crate::layout`], "Rig attachment").
    pub fn encode(&self) -> Vec<u8> {
        let mut out = Vec::new();
        put_u32(&mut out, RIG_VERSION);
        put_u32(&mut out, self.rest_local.len() as u32);
        for p in &self.rest_local {
            put_f32s(&mut out, p.as_slice());
        }
        put_f32s(&mut out, &self.inverse_masses);
        put_u32(&mut out, self.anchors.len() as u32);
        for a in &self.anchors {
            match a {
                Anchor::Surface(s) => {
                    put_u32(&mut out, 0);
                    put_u32(&mut out, s.triangle);
                    put_f32s(&mut out, &s.weights);
                    put_f32s(&mut out, &[0.0; 3]);
                }
                Anchor::Body(f) => {
                    put_u32(&mut out, 1);
                    put_f32s(&mut out, f.origin.as_slice());
                    put_f32s(&mut out, f.rotation.coords.as_slice());
                }
            }
        }
        match &self.scalp {
            None => put_u32(&mut out, 0),
            Some(scalp) => {
                put_u32(&mut out, 1);
                put_mesh(&mut out, &scalp.mesh);
                match scalp.mesh.uvs() {
                    None => put_u32(&mut out, 0),
                    Some(uvs) => {
                        put_u32(&mut out, 1);
                        for uv in uvs {
                            put_f32s(&mut out, uv.as_slice());
                        }
                    }
                }
                match &scalp.colors {
                    None => put_u32(&mut out, 0),
                    Some(colors) => {
                        put_u32(&mut out, 1);
                        for c in colors {
                            put_f32s(&mut out, c);
                        }
                    }
                }
            }
        }
        match self.scalp_collider {
            None => put_u32(&mut out, 0),
            Some((thickness, friction)) => {
                put_u32(&mut out, 1);
                put_f32s(&mut out, &[thickness, friction]);
            }
        }
        put_u32(&mut out, self.colliders.len() as u32);
        for c in &self.colliders {
            let kind = match c.shape {
                ColliderShape::Sphere { .. } => 0,
                ColliderShape::Capsule { .. } => 1,
                ColliderShape::Mesh(_) => 2,
            };
            put_u32(&mut out, kind);
            put_f32s(&mut out, &[c.thickness, c.friction]);
            match &c.shape {
                ColliderShape::Sphere { radius } => put_f32s(&mut out, &[*radius]),
                ColliderShape::Capsule {
                    half_height,
                    radius,
                } => put_f32s(&mut out, &[*half_height, *radius]),
                ColliderShape::Mesh(mesh) => put_mesh(&mut out, mesh),
            }
        }
        for factors in [&self.clump, &self.curl] {
            match factors {
                None => put_u32(&mut out, 0),
                Some(f) => {
                    put_u32(&mut out, 1);
                    put_f32s(&mut out, f);
                }
            }
        }
        out
    }

    /// Reads the attachment's bytes and checks them against `layout` ([`CacheRig::validate`]),
    /// every count against the bytes left before it is used, and every value as the library's
    /// constructors do.
    pub fn decode(bytes: &[u8], layout: &CacheLayout) -> Result<Self, RigError> {
        let mut r = LeReader::new(bytes);
        let version = r.u32()?;
        if version != RIG_VERSION {
            return Err(RigError::Version { version });
        }
        let points = count(&mut r, 16, RigField::Points)?;
        let rest_local = floats(&mut r, points, 3, RigField::RestPositions)?
            .chunks_exact(3)
            .map(|c| Vector3::new(c[0], c[1], c[2]))
            .collect();
        let inverse_masses = floats(&mut r, points, 1, RigField::InverseMasses)?;
        let strands = count(&mut r, 32, RigField::Anchors)?;
        let mut anchors = Vec::with_capacity(strands);
        for strand in 0..strands {
            let kind = r.u32()?;
            anchors.push(match kind {
                0 => {
                    let triangle = r.u32()?;
                    let weights = f32s::<3>(&mut r)?;
                    r.take(12)?;
                    Anchor::Surface(MeshSample { triangle, weights })
                }
                1 => {
                    let origin = Vector3::from(f32s::<3>(&mut r)?);
                    let rotation = unit_quaternion(f32s::<4>(&mut r)?)
                        .ok_or(RigError::RootRotation { strand })?;
                    if !origin.iter().all(|c| c.is_finite()) {
                        return Err(RigError::RootOrigin { strand });
                    }
                    Anchor::Body(RootFrame { origin, rotation })
                }
                kind => return Err(RigError::AnchorKind { strand, kind }),
            });
        }
        let scalp = match flag(&mut r, RigField::Scalp)? {
            false => None,
            true => {
                let mesh = get_mesh(&mut r, RigMesh::Scalp)?;
                let v = mesh.positions().len();
                let mesh = match flag(&mut r, RigField::ScalpUvs)? {
                    false => mesh,
                    true => {
                        let uvs = floats(&mut r, v, 2, RigField::ScalpUvs)?
                            .chunks_exact(2)
                            .map(|c| Vector2::new(c[0], c[1]))
                            .collect();
                        mesh.with_uvs(uvs).map_err(RigError::ScalpUvs)?
                    }
                };
                let colors = match flag(&mut r, RigField::ScalpColours)? {
                    false => None,
                    true => Some(
                        floats(&mut r, v, 3, RigField::ScalpColours)?
                            .chunks_exact(3)
                            .map(|c| [c[0], c[1], c[2]])
                            .collect(),
                    ),
                };
                Some(RigScalp { mesh, colors })
            }
        };
        let scalp_collider = match flag(&mut r, RigField::ScalpCollider)? {
            false => None,
            true => {
                let [thickness, friction] = f32s::<2>(&mut r)?;
                if !(thickness.is_finite()
                    && thickness >= 0.0
                    && friction.is_finite()
                    && friction >= 0.0)
                {
                    return Err(RigError::ScalpCollider {
                        thickness,
                        friction,
                    });
                }
                if scalp.is_none() {
                    return Err(RigError::ScalpColliderWithoutScalp);
                }
                Some((thickness, friction))
            }
        };
        let n = count(&mut r, 12, RigField::Colliders)?;
        let mut colliders = Vec::with_capacity(n);
        for i in 0..n {
            let kind = r.u32()?;
            let [thickness, friction] = f32s::<2>(&mut r)?;
            let shape = match kind {
                0 => ColliderShape::Sphere { radius: r.f32()? },
                1 => {
                    let [half_height, radius] = f32s::<2>(&mut r)?;
                    ColliderShape::Capsule {
                        half_height,
                        radius,
                    }
                }
                2 => ColliderShape::Mesh(get_mesh(&mut r, RigMesh::Collider(i))?),
                kind => return Err(RigError::ShapeKind { collider: i, kind }),
            };
            let collider = Collider {
                shape,
                thickness,
                friction,
            };
            collider.validate(i).map_err(RigError::Collider)?;
            colliders.push(collider);
        }
        let mut factors = [None, None];
        for (slot, field) in factors.iter_mut().zip([RigField::Clump, RigField::Curl]) {
            if flag(&mut r, field)? {
                let f = floats(&mut r, strands, 1, field)?;
                if let Some(strand) = f.iter().position(|x| !(0.0..=1.0).contains(x)) {
                    return Err(RigError::Factor {
                        strand,
                        field,
                        value: f[strand],
                    });
                }
                *slot = Some(f);
            }
        }
        if r.remaining() != 0 {
            return Err(RigError::Trailing {
                bytes: r.remaining(),
                payload: "rig",
            });
        }
        let [clump, curl] = factors;
        let rig = Self {
            anchors,
            rest_local,
            inverse_masses,
            scalp,
            scalp_collider,
            colliders,
            clump,
            curl,
        };
        rig.validate(layout)?;
        Ok(rig)
    }
}

impl RigFrame {
    /// Checks the frame against `rig`: vertex counts of the deformed meshes, finite values.
    pub fn validate(&self, rig: &CacheRig) -> Result<(), RigError> {
        check_pose(&self.scalp_body, RigMesh::Scalp)?;
        if let Some(v) = &self.scalp_vertices {
            let Some(scalp) = &rig.scalp else {
                return Err(RigError::ScalpVerticesWithoutScalp);
            };
            check_vertices(v, scalp.mesh.positions().len(), RigMesh::Scalp)?;
        }
        if self.colliders.len() != rig.colliders.len() {
            return Err(RigError::ColliderStateCount {
                found: self.colliders.len(),
                colliders: rig.colliders.len(),
            });
        }
        for (i, (state, c)) in self.colliders.iter().zip(&rig.colliders).enumerate() {
            check_pose(&state.pose, RigMesh::Collider(i))?;
            if let Some(v) = &state.vertices {
                let ColliderShape::Mesh(mesh) = &c.shape else {
                    return Err(RigError::VerticesWithoutMesh { collider: i });
                };
                check_vertices(v, mesh.positions().len(), RigMesh::Collider(i))?;
            }
        }
        Ok(())
    }

    /// The message payload of frame `frame` (layout: [`crate::layout`], "Rig frame payload").
    pub fn encode(&self, frame: u32) -> Vec<u8> {
        let mut out = Vec::new();
        put_u32(&mut out, RIG_VERSION);
        put_u32(&mut out, frame);
        put_pose(&mut out, &self.scalp_body);
        put_vertices(&mut out, self.scalp_vertices.as_deref());
        put_u32(&mut out, self.colliders.len() as u32);
        for c in &self.colliders {
            put_pose(&mut out, &c.pose);
            put_vertices(&mut out, c.vertices.as_deref());
        }
        out
    }

    /// Reads a payload of `rig`'s frame; returns the frame number it holds and the frame.
    pub fn decode(bytes: &[u8], rig: &CacheRig) -> Result<(u32, Self), RigError> {
        let mut r = LeReader::new(bytes);
        let version = r.u32()?;
        if version != RIG_VERSION {
            return Err(RigError::FrameVersion { version });
        }
        let frame = r.u32()?;
        let scalp_body = get_pose(&mut r)?;
        let scalp_points = rig.scalp.as_ref().map_or(0, |s| s.mesh.positions().len());
        let scalp_vertices = get_vertices(&mut r, scalp_points, RigMesh::Scalp)?;
        let n = count(&mut r, 32, RigField::ColliderStates)?;
        let mut colliders = Vec::with_capacity(n);
        for i in 0..n {
            let pose = get_pose(&mut r)?;
            let points = match rig.colliders.get(i).map(|c| &c.shape) {
                Some(ColliderShape::Mesh(m)) => m.positions().len(),
                _ => 0,
            };
            let vertices = get_vertices(&mut r, points, RigMesh::Collider(i))?;
            colliders.push(ColliderState { pose, vertices });
        }
        if r.remaining() != 0 {
            return Err(RigError::Trailing {
                bytes: r.remaining(),
                payload: "rig frame",
            });
        }
        let out = Self {
            scalp_body,
            scalp_vertices,
            colliders,
        };
        out.validate(rig)?;
        Ok((frame, out))
    }
}

fn put_u32(out: &mut Vec<u8>, v: u32) {
    out.extend_from_slice(&v.to_le_bytes());
}

fn put_f32s(out: &mut Vec<u8>, v: &[f32]) {
    for x in v {
        out.extend_from_slice(&x.to_le_bytes());
    }
}

fn put_mesh(out: &mut Vec<u8>, mesh: &TriMesh) {
    put_u32(out, mesh.positions().len() as u32);
    put_u32(out, mesh.triangles().len() as u32);
    for p in mesh.positions() {
        put_f32s(out, p.as_slice());
    }
    for t in mesh.triangles() {
        for &i in t {
            put_u32(out, i);
        }
    }
}

fn put_pose(out: &mut Vec<u8>, pose: &Isometry3<f32>) {
    put_f32s(out, pose.translation.vector.as_slice());
    put_f32s(out, pose.rotation.coords.as_slice());
}

fn put_vertices(out: &mut Vec<u8>, vertices: Option<&[Vector3<f32>]>) {
    match vertices {
        None => put_u32(out, 0),
        Some(v) => {
            put_u32(out, 1);
            for p in v {
                put_f32s(out, p.as_slice());
            }
        }
    }
}

/// A `u32` count of items of at least `min_bytes` each, refused when the bytes left cannot
/// hold them (so nothing is allocated from a damaged count).
fn count(r: &mut LeReader, min_bytes: usize, field: RigField) -> Result<usize, RigError> {
    let count = r.u32()? as usize;
    if count.saturating_mul(min_bytes) > r.remaining() {
        return Err(RigError::Count {
            field,
            count,
            remaining: r.remaining(),
        });
    }
    Ok(count)
}

fn flag(r: &mut LeReader, field: RigField) -> Result<bool, RigError> {
    match r.u32()? {
        0 => Ok(false),
        1 => Ok(true),
        value => Err(RigError::Flag { field, value }),
    }
}

fn f32s<const N: usize>(r: &mut LeReader) -> Result<[f32; N], Truncated> {
    let mut out = [0.0; N];
    for x in &mut out {
        *x = r.f32()?;
    }
    Ok(out)
}

/// `n × per` finite `f32`s (bounds checked before anything is allocated).
fn floats(r: &mut LeReader, n: usize, per: usize, field: RigField) -> Result<Vec<f32>, RigError> {
    let len = n
        .checked_mul(per)
        .and_then(|c| c.checked_mul(4))
        .ok_or(RigError::ValuesOverflow { field, count: n })?;
    let bytes = r
        .take(len)
        .map_err(|source| RigError::FieldTruncated { field, source })?;
    let values: Vec<f32> = bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    if let Some(index) = values.iter().position(|x| !x.is_finite()) {
        return Err(RigError::NonFinite { field, index });
    }
    Ok(values)
}

fn get_mesh(r: &mut LeReader, mesh: RigMesh) -> Result<TriMesh, RigError> {
    let v = count(r, 4, RigField::Vertices(mesh))?;
    let t = r.u32()? as usize;
    let positions = floats(r, v, 3, RigField::Vertices(mesh))?
        .chunks_exact(3)
        .map(|c| Vector3::new(c[0], c[1], c[2]))
        .collect();
    let len = t
        .checked_mul(12)
        .ok_or(RigError::TrianglesOverflow { mesh, count: t })?;
    let triangles = r
        .take(len)
        .map_err(|source| RigError::TrianglesTruncated { mesh, source })?
        .chunks_exact(12)
        .map(|b| {
            let i = |k: usize| u32::from_le_bytes([b[k], b[k + 1], b[k + 2], b[k + 3]]);
            [i(0), i(4), i(8)]
        })
        .collect();
    TriMesh::new(positions, triangles).map_err(|source| RigError::Mesh { mesh, source })
}

fn unit_quaternion([i, j, k, w]: [f32; 4]) -> Option<UnitQuaternion<f32>> {
    let q = Quaternion::new(w, i, j, k);
    let norm = q.norm();
    (norm.is_finite() && (norm - 1.0).abs() < 1e-3).then(|| UnitQuaternion::new_unchecked(q))
}

fn get_pose(r: &mut LeReader) -> Result<Isometry3<f32>, RigError> {
    let t = f32s::<3>(r)?;
    let rotation = unit_quaternion(f32s::<4>(r)?).ok_or(RigError::PoseRotation)?;
    if !t.iter().all(|c| c.is_finite()) {
        return Err(RigError::PoseTranslation);
    }
    Ok(Isometry3::from_parts(
        Translation3::from(Vector3::from(t)),
        rotation,
    ))
}

fn get_vertices(
    r: &mut LeReader,
    points: usize,
    mesh: RigMesh,
) -> Result<Option<Vec<Vector3<f32>>>, RigError> {
    if !flag(r, RigField::Vertices(mesh))? {
        return Ok(None);
    }
    Ok(Some(
        floats(r, points, 3, RigField::Vertices(mesh))?
            .chunks_exact(3)
            .map(|c| Vector3::new(c[0], c[1], c[2]))
            .collect(),
    ))
}

fn check_pose(pose: &Isometry3<f32>, mesh: RigMesh) -> Result<(), RigError> {
    let finite = pose.translation.vector.iter().all(|c| c.is_finite())
        && pose.rotation.coords.iter().all(|c| c.is_finite());
    if finite {
        Ok(())
    } else {
        Err(RigError::Pose { mesh })
    }
}

fn check_vertices(v: &[Vector3<f32>], expected: usize, mesh: RigMesh) -> Result<(), RigError> {
    if v.len() != expected {
        return Err(RigError::VertexCount {
            mesh,
            found: v.len(),
            expected,
        });
    }
    match v.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
        Some(vertex) => Err(RigError::Vertex { mesh, vertex }),
        None => Ok(()),
    }
}

/// A mesh of the rig, as errors name it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RigMesh {
    /// The scalp.
    Scalp,
    /// The mesh collider with this index.
    Collider(usize),
}

impl RigMesh {
    /// The mesh in a sentence: "the scalp", "collider 3".
    fn in_sentence(self) -> String {
        match self {
            RigMesh::Scalp => "the scalp".into(),
            RigMesh::Collider(i) => format!("collider {i}"),
        }
    }
}

impl fmt::Display for RigMesh {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RigMesh::Scalp => f.write_str("scalp"),
            RigMesh::Collider(i) => write!(f, "collider {i}"),
        }
    }
}

/// A field of the rig attachment or a rig frame, as errors name it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RigField {
    /// The point count.
    Points,
    /// The points' rest positions.
    RestPositions,
    /// The points' inverse masses.
    InverseMasses,
    /// The strands' anchors.
    Anchors,
    /// The scalp mesh.
    Scalp,
    /// The scalp's UVs.
    ScalpUvs,
    /// The scalp's vertex colours.
    ScalpColours,
    /// The scalp's collider settings.
    ScalpCollider,
    /// The colliders.
    Colliders,
    /// A rig frame's collider states.
    ColliderStates,
    /// The strands' clump factors.
    Clump,
    /// The strands' curl factors.
    Curl,
    /// A mesh's vertices.
    Vertices(RigMesh),
}

impl fmt::Display for RigField {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = match self {
            RigField::Points => "points",
            RigField::RestPositions => "rest positions",
            RigField::InverseMasses => "inverse masses",
            RigField::Anchors => "anchors",
            RigField::Scalp => "scalp",
            RigField::ScalpUvs => "scalp UVs",
            RigField::ScalpColours => "scalp colours",
            RigField::ScalpCollider => "scalp collider",
            RigField::Colliders => "colliders",
            RigField::ColliderStates => "collider states",
            RigField::Clump => "clump",
            RigField::Curl => "curl",
            RigField::Vertices(mesh) => return write!(f, "{mesh} vertices"),
        };
        f.write_str(name)
    }
}

/// Why a [`CacheRig`] or a [`RigFrame`] is refused, written or read.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum RigError {
    /// The bytes end before a value.
    #[error(transparent)]
    Truncated(#[from] Truncated),
    /// The attachment has another version.
    #[error("rig version {version}; this hairsys reads version {RIG_VERSION}")]
    Version {
        /// The version found.
        version: u32,
    },
    /// The frame payload has another version.
    #[error("rig frame version {version}; this hairsys reads version {RIG_VERSION}")]
    FrameVersion {
        /// The version found.
        version: u32,
    },
    /// Not one value per point.
    #[error("{found} {field} for {points} points: give one per point")]
    PerPoint {
        /// The values.
        field: RigField,
        /// Number of values given.
        found: usize,
        /// Number of points of the layout.
        points: usize,
    },
    /// Not one value per strand.
    #[error("{found} {} for {strands} strands: give one per strand", per_strand(*.field))]
    PerStrand {
        /// The values.
        field: RigField,
        /// Number of values given.
        found: usize,
        /// Number of strands of the layout.
        strands: usize,
    },
    /// A rest position is not finite.
    #[error("point {point}'s rest position is not finite")]
    RestPosition {
        /// The point.
        point: usize,
    },
    /// An inverse mass is negative or not finite.
    #[error("point {point}'s inverse mass {value} is not a finite value ≥ 0")]
    InverseMass {
        /// The point.
        point: usize,
        /// Its inverse mass, 1/kg.
        value: f32,
    },
    /// A strand is rooted on the scalp of a rig without one.
    #[error("strand {strand} is rooted on the scalp, but the rig has no scalp mesh")]
    NoScalpForAnchor {
        /// The strand.
        strand: usize,
    },
    /// A strand's mesh sample does not fit the scalp.
    #[error("strand {strand}: {source}")]
    Anchor {
        /// The strand.
        strand: usize,
        /// What the sample's check said.
        source: HairError,
    },
    /// Not one colour per scalp vertex.
    #[error("{found} scalp colours for {vertices} vertices: give one per vertex")]
    ColorCount {
        /// Number of colours given.
        found: usize,
        /// Number of scalp vertices.
        vertices: usize,
    },
    /// A strand's root frame holds no rotation.
    #[error("strand {strand}'s root frame is no rotation")]
    RootRotation {
        /// The strand.
        strand: usize,
    },
    /// A strand's root is not finite.
    #[error("strand {strand}'s root is not finite")]
    RootOrigin {
        /// The strand.
        strand: usize,
    },
    /// An anchor kind is unknown.
    #[error("strand {strand} has anchor kind {kind}, not 0 or 1")]
    AnchorKind {
        /// The strand.
        strand: usize,
        /// The kind found.
        kind: u32,
    },
    /// The scalp's UVs do not fit its mesh.
    #[error("scalp UVs: {0}")]
    ScalpUvs(#[source] HairError),
    /// The scalp collider's thickness or friction is negative or not finite.
    #[error(
        "the scalp collider's thickness {thickness} and friction {friction} must be finite and ≥ 0"
    )]
    ScalpCollider {
        /// Thickness, m.
        thickness: f32,
        /// Friction coefficient.
        friction: f32,
    },
    /// The rig has a scalp collider but no scalp.
    #[error("the rig has a scalp collider but no scalp mesh")]
    ScalpColliderWithoutScalp,
    /// A collider's shape kind is unknown.
    #[error("collider {collider} has shape kind {kind}, not 0, 1 or 2")]
    ShapeKind {
        /// The collider.
        collider: usize,
        /// The kind found.
        kind: u32,
    },
    /// A collider is refused by the library's check.
    #[error(transparent)]
    Collider(HairError),
    /// A strand's clump or curl factor is not in 0–1.
    #[error("strand {strand}'s {field} factor {value} is not in 0–1")]
    Factor {
        /// The strand.
        strand: usize,
        /// [`RigField::Clump`] or [`RigField::Curl`].
        field: RigField,
        /// The factor found.
        value: f32,
    },
    /// Bytes follow the last field.
    #[error("{bytes} bytes after the {payload}")]
    Trailing {
        /// Number of bytes left.
        bytes: usize,
        /// `"rig"` or `"rig frame"`.
        payload: &'static str,
    },
    /// A count is larger than the bytes left can hold.
    #[error("{count} {field} declared, but only {remaining} bytes are left")]
    Count {
        /// What is counted.
        field: RigField,
        /// The count declared.
        count: usize,
        /// Bytes left.
        remaining: usize,
    },
    /// A flag is neither 0 nor 1.
    #[error("the {field} flag is {value}, not 0 or 1")]
    Flag {
        /// What the flag says is present.
        field: RigField,
        /// The value found.
        value: u32,
    },
    /// A count of values overflows the address space.
    #[error("{field}: {count} values overflow")]
    ValuesOverflow {
        /// The values.
        field: RigField,
        /// Number of items declared.
        count: usize,
    },
    /// The bytes end inside a field's values.
    #[error("{field}: {source}")]
    FieldTruncated {
        /// The values.
        field: RigField,
        /// Where the bytes end.
        source: Truncated,
    },
    /// A value is not finite.
    #[error("{field}: value {index} is not finite")]
    NonFinite {
        /// The values.
        field: RigField,
        /// Index of the first bad value.
        index: usize,
    },
    /// A mesh's triangle count overflows the address space.
    #[error("{mesh}: {count} triangles overflow")]
    TrianglesOverflow {
        /// The mesh.
        mesh: RigMesh,
        /// Number of triangles declared.
        count: usize,
    },
    /// The bytes end inside a mesh's triangles.
    #[error("{mesh} triangles: {source}")]
    TrianglesTruncated {
        /// The mesh.
        mesh: RigMesh,
        /// Where the bytes end.
        source: Truncated,
    },
    /// A mesh is refused by [`TriMesh::new`].
    #[error("{mesh} mesh: {source}")]
    Mesh {
        /// The mesh.
        mesh: RigMesh,
        /// What the mesh's check said.
        source: HairError,
    },
    /// A pose's rotation is not a unit quaternion.
    #[error("a pose's rotation is no rotation")]
    PoseRotation,
    /// A pose's translation is not finite.
    #[error("a pose's translation is not finite")]
    PoseTranslation,
    /// A frame's scalp transform or collider pose is not finite.
    #[error("{} is not finite", pose_name(*.mesh))]
    Pose {
        /// The scalp or the collider.
        mesh: RigMesh,
    },
    /// A rig frame gives scalp vertices for a rig without a scalp.
    #[error("scalp vertices are given, but the rig has no scalp mesh")]
    ScalpVerticesWithoutScalp,
    /// A rig frame has not one state per collider.
    #[error("{found} collider states for {colliders} colliders")]
    ColliderStateCount {
        /// Number of states given.
        found: usize,
        /// Number of colliders of the rig.
        colliders: usize,
    },
    /// A rig frame gives vertices for a collider that is no mesh.
    #[error("collider {collider} is no mesh, but vertices are given")]
    VerticesWithoutMesh {
        /// The collider.
        collider: usize,
    },
    /// A deformed mesh has not one vertex per rest vertex.
    #[error("{found} vertices for {}, whose mesh has {expected}", .mesh.in_sentence())]
    VertexCount {
        /// The mesh.
        mesh: RigMesh,
        /// Number of vertices given.
        found: usize,
        /// Number of vertices of its rest mesh.
        expected: usize,
    },
    /// A deformed vertex is not finite.
    #[error("{}'s vertex {vertex} is not finite", .mesh.in_sentence())]
    Vertex {
        /// The mesh.
        mesh: RigMesh,
        /// The first bad vertex.
        vertex: usize,
    },
}

/// A per-strand field in a count: "anchors", "clump factors".
fn per_strand(field: RigField) -> String {
    match field {
        RigField::Clump | RigField::Curl => format!("{field} factors"),
        other => other.to_string(),
    }
}

/// The pose of `mesh` in a sentence: "the scalp's transform", "collider 3's pose".
fn pose_name(mesh: RigMesh) -> String {
    match mesh {
        RigMesh::Scalp => "the scalp's transform".into(),
        RigMesh::Collider(i) => format!("collider {i}'s pose"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle() -> TriMesh {
        TriMesh::new(
            vec![
                Vector3::new(0.0, 0.0, 0.0),
                Vector3::new(1.0, 0.0, 0.0),
                Vector3::new(0.0, 1.0, 0.0),
            ],
            vec![[0, 1, 2]],
        )
        .unwrap()
    }

    fn layout() -> CacheLayout {
        CacheLayout {
            offsets: vec![0, 2, 4],
            rest_lengths: vec![0.1, 0.1],
            radii: vec![1e-3; 4],
        }
    }

    fn rig() -> CacheRig {
        CacheRig {
            rest_local: (0..4)
                .map(|i| Vector3::new(0.0, 0.0, 0.1 * (i % 2) as f32))
                .collect(),
            inverse_masses: vec![0.0, 1e3, 0.0, 1e3],
            anchors: vec![
                Anchor::Surface(MeshSample {
                    triangle: 0,
                    weights: [0.2, 0.3, 0.5],
                }),
                Anchor::Body(RootFrame {
                    origin: Vector3::new(0.1, 0.2, 0.3),
                    rotation: UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3),
                }),
            ],
            scalp: Some(RigScalp {
                mesh: triangle()
                    .with_uvs(vec![Vector2::zeros(), Vector2::x(), Vector2::y()])
                    .unwrap(),
                colors: Some(vec![[1.0, 0.5, 0.0]; 3]),
            }),
            scalp_collider: Some((1e-3, 0.3)),
            colliders: vec![
                Collider::sphere(0.1).with_thickness(0.01),
                Collider::capsule(0.2, 0.05).with_friction(0.3),
                Collider::mesh(triangle()),
            ],
            clump: Some(vec![0.25, 1.0]),
            curl: None,
        }
    }

    #[test]
    fn a_rig_and_its_frames_round_trip_bit_for_bit() {
        let rig = rig();
        let bytes = rig.encode();
        let decoded = CacheRig::decode(&bytes, &layout()).unwrap();
        assert_eq!(decoded.encode(), bytes);
        assert_eq!(decoded.anchors, rig.anchors);
        assert_eq!(
            decoded.scalp.unwrap().mesh.uvs(),
            rig.scalp.as_ref().unwrap().mesh.uvs()
        );
        let pose = Isometry3::new(Vector3::new(1.0, 2.0, 3.0), Vector3::new(0.3, -0.2, 0.1));
        let frame = RigFrame {
            scalp_body: pose,
            scalp_vertices: Some(vec![Vector3::new(0.5, 0.5, 0.5); 3]),
            colliders: vec![
                ColliderState {
                    pose,
                    vertices: None,
                },
                ColliderState {
                    pose: Isometry3::identity(),
                    vertices: None,
                },
                ColliderState {
                    pose,
                    vertices: Some(vec![Vector3::new(-1.0, 0.0, 2.0); 3]),
                },
            ],
        };
        assert_eq!(
            RigFrame::decode(&frame.encode(7), &rig).unwrap(),
            (7, frame)
        );
    }

    #[test]
    fn every_truncation_and_a_huge_count_are_refused_without_panic() {
        let bytes = rig().encode();
        for len in 0..bytes.len() {
            assert!(
                CacheRig::decode(&bytes[..len], &layout()).is_err(),
                "{len} bytes"
            );
        }
        let mut huge = bytes.clone();
        huge[4..8].copy_from_slice(&u32::MAX.to_le_bytes());
        assert!(CacheRig::decode(&huge, &layout())
            .unwrap_err()
            .to_string()
            .contains("declared"));
    }

    #[test]
    fn a_frame_whose_vertex_count_differs_from_the_rig_is_refused() {
        let rig = rig();
        let frame = RigFrame {
            scalp_body: Isometry3::identity(),
            scalp_vertices: Some(vec![Vector3::zeros(); 2]),
            colliders: vec![],
        };
        assert!(frame.validate(&rig).is_err());
    }
}
