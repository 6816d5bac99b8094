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

use hair_core::{Anchor, Collider, ColliderShape, MeshSample, RootFrame, TriMesh};
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector2, Vector3};

use crate::layout::{CacheLayout, LeReader};

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
    pub fn validate(&self, layout: &CacheLayout) -> Result<(), String> {
        let (strands, points) = (layout.strand_count(), layout.point_count());
        for (name, n) in [
            ("rest positions", self.rest_local.len()),
            ("inverse masses", self.inverse_masses.len()),
        ] {
            if n != points {
                return Err(format!(
                    "{n} {name} for {points} points: give one per point"
                ));
            }
        }
        if let Some(i) = self
            .rest_local
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(format!("point {i}'s rest position is not finite"));
        }
        if let Some(i) = self
            .inverse_masses
            .iter()
            .position(|m| !(m.is_finite() && *m >= 0.0))
        {
            return Err(format!(
                "point {i}'s inverse mass {} is not a finite value ≥ 0",
                self.inverse_masses[i]
            ));
        }
        if self.anchors.len() != strands {
            return Err(format!(
                "{} anchors for {strands} strands: give one per strand",
                self.anchors.len()
            ));
        }
        for (name, f) in [("clump", &self.clump), ("curl", &self.curl)] {
            if let Some(f) = f {
                if f.len() != strands {
                    return Err(format!(
                        "{} {name} factors for {strands} strands: give one per strand",
                        f.len()
                    ));
                }
            }
        }
        for (s, a) in self.anchors.iter().enumerate() {
            if let Anchor::Surface(sample) = a {
                let Some(scalp) = &self.scalp else {
                    return Err(format!(
                        "strand {s} is rooted on the scalp, but the rig has no scalp mesh"
                    ));
                };
                sample
                    .validate(&scalp.mesh)
                    .map_err(|e| format!("strand {s}: {e}"))?;
            }
        }
        if let Some(RigScalp {
            mesh,
            colors: Some(c),
        }) = &self.scalp
        {
            if c.len() != mesh.positions().len() {
                return Err(format!(
                    "{} scalp colours for {} vertices: give one per vertex",
                    c.len(),
                    mesh.positions().len()
                ));
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
    pub fn decode(bytes: &[u8], layout: &CacheLayout) -> Result<Self, String> {
        let mut r = LeReader::new(bytes);
        let version = r.u32()?;
        if version != RIG_VERSION {
            return Err(format!(
                "rig version {version}; this hairsys reads version {RIG_VERSION}"
            ));
        }
        let points = count(&mut r, 16, "points")?;
        let rest_local = floats(&mut r, points, 3, "rest positions")?
            .chunks_exact(3)
            .map(|c| Vector3::new(c[0], c[1], c[2]))
            .collect();
        let inverse_masses = floats(&mut r, points, 1, "inverse masses")?;
        let strands = count(&mut r, 32, "anchors")?;
        let mut anchors = Vec::with_capacity(strands);
        for s in 0..strands {
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
                        .ok_or_else(|| format!("strand {s}'s root frame is no rotation"))?;
                    if !origin.iter().all(|c| c.is_finite()) {
                        return Err(format!("strand {s}'s root is not finite"));
                    }
                    Anchor::Body(RootFrame { origin, rotation })
                }
                k => return Err(format!("strand {s} has anchor kind {k}, not 0 or 1")),
            });
        }
        let scalp = match flag(&mut r, "scalp")? {
            false => None,
            true => {
                let mesh = get_mesh(&mut r, "scalp")?;
                let v = mesh.positions().len();
                let mesh = match flag(&mut r, "scalp UVs")? {
                    false => mesh,
                    true => {
                        let uvs = floats(&mut r, v, 2, "scalp UVs")?
                            .chunks_exact(2)
                            .map(|c| Vector2::new(c[0], c[1]))
                            .collect();
                        mesh.with_uvs(uvs).map_err(|e| format!("scalp UVs: {e}"))?
                    }
                };
                let colors = match flag(&mut r, "scalp colours")? {
                    false => None,
                    true => Some(
                        floats(&mut r, v, 3, "scalp colours")?
                            .chunks_exact(3)
                            .map(|c| [c[0], c[1], c[2]])
                            .collect(),
                    ),
                };
                Some(RigScalp { mesh, colors })
            }
        };
        let scalp_collider = match flag(&mut r, "scalp collider")? {
            false => None,
            true => {
                let [thickness, friction] = f32s::<2>(&mut r)?;
                if !(thickness.is_finite()
                    && thickness >= 0.0
                    && friction.is_finite()
                    && friction >= 0.0)
                {
                    return Err(format!(
                        "the scalp collider's thickness {thickness} and friction {friction} \
                         must be finite and ≥ 0"
                    ));
                }
                if scalp.is_none() {
                    return Err("the rig has a scalp collider but no scalp mesh".into());
                }
                Some((thickness, friction))
            }
        };
        let n = count(&mut r, 12, "colliders")?;
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
                2 => ColliderShape::Mesh(get_mesh(&mut r, &format!("collider {i}"))?),
                k => return Err(format!("collider {i} has shape kind {k}, not 0, 1 or 2")),
            };
            let collider = Collider {
                shape,
                thickness,
                friction,
            };
            collider.validate(i).map_err(|e| e.to_string())?;
            colliders.push(collider);
        }
        let mut factors = [None, None];
        for (slot, name) in factors.iter_mut().zip(["clump", "curl"]) {
            if flag(&mut r, name)? {
                let f = floats(&mut r, strands, 1, name)?;
                if let Some(i) = f.iter().position(|x| !(0.0..=1.0).contains(x)) {
                    return Err(format!("strand {i}'s {name} factor {} is not in 0–1", f[i]));
                }
                *slot = Some(f);
            }
        }
        if r.remaining() != 0 {
            return Err(format!("{} bytes after the rig", r.remaining()));
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
    pub fn validate(&self, rig: &CacheRig) -> Result<(), String> {
        check_pose(&self.scalp_body, "the scalp's transform")?;
        if let Some(v) = &self.scalp_vertices {
            let Some(scalp) = &rig.scalp else {
                return Err("scalp vertices are given, but the rig has no scalp mesh".into());
            };
            check_vertices(v, scalp.mesh.positions().len(), "the scalp")?;
        }
        if self.colliders.len() != rig.colliders.len() {
            return Err(format!(
                "{} collider states for {} colliders",
                self.colliders.len(),
                rig.colliders.len()
            ));
        }
        for (i, (state, c)) in self.colliders.iter().zip(&rig.colliders).enumerate() {
            check_pose(&state.pose, &format!("collider {i}'s pose"))?;
            if let Some(v) = &state.vertices {
                let ColliderShape::Mesh(mesh) = &c.shape else {
                    return Err(format!("collider {i} is no mesh, but vertices are given"));
                };
                check_vertices(v, mesh.positions().len(), &format!("collider {i}"))?;
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
    pub fn decode(bytes: &[u8], rig: &CacheRig) -> Result<(u32, Self), String> {
        let mut r = LeReader::new(bytes);
        let version = r.u32()?;
        if version != RIG_VERSION {
            return Err(format!(
                "rig frame version {version}; this hairsys reads version {RIG_VERSION}"
            ));
        }
        let frame = r.u32()?;
        let scalp_body = get_pose(&mut r)?;
        let scalp_points = rig.scalp.as_ref().map_or(0, |s| s.mesh.positions().len());
        let scalp_vertices = get_vertices(&mut r, scalp_points, "scalp")?;
        let n = count(&mut r, 32, "collider states")?;
        let mut colliders = Vec::with_capacity(n);
        for i in 0..n {
            let pose = get_pose(&mut r)?;
            let points = match rig.colliders.get(i).map(|c| &c.shape) {
                Some(ColliderShape::Mesh(m)) => m.positions().len(),
                _ => 0,
            };
            let vertices = get_vertices(&mut r, points, &format!("collider {i}"))?;
            colliders.push(ColliderState { pose, vertices });
        }
        if r.remaining() != 0 {
            return Err(format!("{} bytes after the rig frame", r.remaining()));
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
fn count(r: &mut LeReader, min_bytes: usize, what: &str) -> Result<usize, String> {
    let n = r.u32()? as usize;
    if n.saturating_mul(min_bytes) > r.remaining() {
        return Err(format!(
            "{n} {what} declared, but only {} bytes are left",
            r.remaining()
        ));
    }
    Ok(n)
}

fn flag(r: &mut LeReader, what: &str) -> Result<bool, String> {
    match r.u32()? {
        0 => Ok(false),
        1 => Ok(true),
        v => Err(format!("the {what} flag is {v}, not 0 or 1")),
    }
}

fn f32s<const N: usize>(r: &mut LeReader) -> Result<[f32; N], String> {
    let mut out = [0.0; N];
    for x in &mut out {
        *x = r.f32()?;
    }
    Ok(out)
}

/// `n × per` finite `f32`s (bounds checked before anything is allocated).
fn floats(r: &mut LeReader, n: usize, per: usize, what: &str) -> Result<Vec<f32>, String> {
    let len = n
        .checked_mul(per)
        .and_then(|c| c.checked_mul(4))
        .ok_or_else(|| format!("{what}: {n} values overflow"))?;
    let bytes = r.take(len).map_err(|e| format!("{what}: {e}"))?;
    let values: Vec<f32> = bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    if let Some(i) = values.iter().position(|x| !x.is_finite()) {
        return Err(format!("{what}: value {i} is not finite"));
    }
    Ok(values)
}

fn get_mesh(r: &mut LeReader, what: &str) -> Result<TriMesh, String> {
    let v = count(r, 4, &format!("{what} vertices"))?;
    let t = r.u32()? as usize;
    let positions = floats(r, v, 3, &format!("{what} vertices"))?
        .chunks_exact(3)
        .map(|c| Vector3::new(c[0], c[1], c[2]))
        .collect();
    let len = t
        .checked_mul(12)
        .ok_or_else(|| format!("{what}: {t} triangles overflow"))?;
    let triangles = r
        .take(len)
        .map_err(|e| format!("{what} triangles: {e}"))?
        .chunks_exact(12)
        .map(|b| {
            let i = |k: usize| u32::from_le_bytes([b[k], b[k + 1], b[k + 2], b[k + 3]]);
            [i(0), i(4), i(8)]
        })
        .collect();
    TriMesh::new(positions, triangles).map_err(|e| format!("{what} mesh: {e}"))
}

fn unit_quaternion([i, j, k, w]: [f32; 4]) -> Option<UnitQuaternion<f32>> {
    let q = Quaternion::new(w, i, j, k);
    let norm = q.norm();
    (norm.is_finite() && (norm - 1.0).abs() < 1e-3).then(|| UnitQuaternion::new_unchecked(q))
}

fn get_pose(r: &mut LeReader) -> Result<Isometry3<f32>, String> {
    let t = f32s::<3>(r)?;
    let rotation = unit_quaternion(f32s::<4>(r)?).ok_or("a pose's rotation is no rotation")?;
    if !t.iter().all(|c| c.is_finite()) {
        return Err("a pose's translation is not finite".into());
    }
    Ok(Isometry3::from_parts(
        Translation3::from(Vector3::from(t)),
        rotation,
    ))
}

fn get_vertices(
    r: &mut LeReader,
    points: usize,
    what: &str,
) -> Result<Option<Vec<Vector3<f32>>>, String> {
    if !flag(r, &format!("{what} vertices"))? {
        return Ok(None);
    }
    Ok(Some(
        floats(r, points, 3, &format!("{what} vertices"))?
            .chunks_exact(3)
            .map(|c| Vector3::new(c[0], c[1], c[2]))
            .collect(),
    ))
}

fn check_pose(pose: &Isometry3<f32>, what: &str) -> Result<(), String> {
    let finite = pose.translation.vector.iter().all(|c| c.is_finite())
        && pose.rotation.coords.iter().all(|c| c.is_finite());
    if finite {
        Ok(())
    } else {
        Err(format!("{what} is not finite"))
    }
}

fn check_vertices(v: &[Vector3<f32>], expected: usize, what: &str) -> Result<(), String> {
    if v.len() != expected {
        return Err(format!(
            "{} vertices for {what}, whose mesh has {expected}",
            v.len()
        ));
    }
    match v.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
        Some(i) => Err(format!("{what}'s vertex {i} is not finite")),
        None => Ok(()),
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
