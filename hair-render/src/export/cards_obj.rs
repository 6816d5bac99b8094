//! Hair cards ([`CardMesh`]) as Wavefront OBJ: one object `cards`, `v` per vertex (m), `vt` per
//! vertex (u across the card, v root → tip) and one `f v/vt …` quad per face (vertex and texture
//! indices are the same, 1-based). One file per frame; OBJ has no motion.
//!
//! OBJ has no way to declare its up axis, and its convention — the one Blender's importer, Maya
//! and most tools assume by default — is **Y up** (Blender's importer maps file `(x, y, z)` to
//! its Z-up `(x, -z, y)`). The cards are simulated Z up, so [`ObjUpAxis::Y`] (the default)
//! writes each point `(x, y, z)` as `(x, z, -y)`: a proper rotation of −90° about X, so lengths,
//! UVs and the faces' winding are unchanged and an importer's Y-up → Z-up turn gives back the
//! simulated positions. [`ObjUpAxis::Z`] writes them as simulated, for tools told the file is
//! Z up.

use std::io::Write;
use std::path::Path;

use nalgebra::Vector3;

use super::write_atomically;
use crate::cards::CardMesh;
use crate::error::Result;

/// The up axis an OBJ file is written with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ObjUpAxis {
    /// Y up, the OBJ convention (Blender's importer default): `(x, y, z)` written `(x, z, -y)`.
    #[default]
    Y,
    /// Z up, as simulated.
    Z,
}

impl ObjUpAxis {
    /// `p` (m, Z up) in this up axis.
    pub fn apply(self, p: &Vector3<f32>) -> [f32; 3] {
        match self {
            ObjUpAxis::Y => [p.x, p.z, -p.y],
            ObjUpAxis::Z => [p.x, p.y, p.z],
        }
    }

    /// The axis letter, as the file's header comment names it.
    pub fn name(self) -> &'static str {
        match self {
            ObjUpAxis::Y => "Y",
            ObjUpAxis::Z => "Z",
        }
    }
}

/// Writes `mesh` as OBJ text to `out` with `up` as the up axis.
pub fn write_cards_obj<W: Write>(out: &mut W, mesh: &CardMesh, up: ObjUpAxis) -> Result<()> {
    writeln!(
        out,
        "# hairsys hair cards: {} cards, {} rows x {} columns each; meters, {} up",
        mesh.cards,
        mesh.rows,
        mesh.columns,
        up.name()
    )?;
    writeln!(out, "o cards")?;
    for p in &mesh.positions {
        let [x, y, z] = up.apply(p);
        writeln!(out, "v {x:?} {y:?} {z:?}")?;
    }
    for uv in &mesh.uvs {
        writeln!(out, "vt {:?} {:?}", uv[0], uv[1])?;
    }
    for q in &mesh.quads {
        let [a, b, c, d] = q.map(|i| i + 1);
        writeln!(out, "f {a}/{a} {b}/{b} {c}/{c} {d}/{d}")?;
    }
    Ok(())
}

/// Writes the cards to `path` atomically (see [`super`]) with `up` as the up axis; errors name
/// the file.
pub fn export_cards_obj(path: &Path, mesh: &CardMesh, up: ObjUpAxis) -> Result<()> {
    write_atomically(path, |out| write_cards_obj(out, mesh, up))
}
