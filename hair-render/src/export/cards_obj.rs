//! Hair cards ([`CardMesh`]) as Wavefront OBJ: one object `cards`, `v` per vertex (m, Z up as
//! simulated), `vt` per vertex (u across the card, v root → tip) and one `f v/vt …` quad per face
//! (vertex and texture indices are the same, 1-based). One file per frame; OBJ has no motion.

use std::io::Write;
use std::path::Path;

use super::write_atomically;
use crate::cards::CardMesh;
use crate::error::Result;

/// Writes `mesh` as OBJ text to `out`.
pub fn write_cards_obj<W: Write>(out: &mut W, mesh: &CardMesh) -> Result<()> {
    writeln!(
        out,
        "# hairsys hair cards: {} cards, {} rows x {} columns each; meters, Z up",
        mesh.cards, mesh.rows, mesh.columns
    )?;
    writeln!(out, "o cards")?;
    for p in &mesh.positions {
        writeln!(out, "v {:?} {:?} {:?}", p.x, p.y, p.z)?;
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

/// Writes the cards to `path` atomically (see [`super`]); errors name the file.
pub fn export_cards_obj(path: &Path, mesh: &CardMesh) -> Result<()> {
    write_atomically(path, |out| write_cards_obj(out, mesh))
}
