//! Exporters of [`crate::ChildBuffers`], one file per format: `usd` (`BasisCurves` as `.usdc` or
//! `.usda`, through `hair_groom`'s one USD layer writer) and [`hair`] (Cem Yuksel's `.hair`); and
//! of hair cards ([`crate::CardMesh`]): `cards_usd` (`Mesh` in `.usda`) and [`cards_obj`] (OBJ).
//! The only module of the crate that does I/O. The USD exporters are the Cargo feature `usd` (on
//! by default).
//!
//! Each format writes to any `Write` (`write_*`) or to a path (`export_*`). A path is written as
//! `<path>.partial` beside it and renamed into place only when complete, so a failed export leaves
//! neither a half-written file nor a clobbered previous one; the partial file is removed on error.

pub mod cards_obj;
#[cfg(feature = "usd")]
pub mod cards_usd;
pub mod hair;
#[cfg(feature = "usd")]
pub mod usd;

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::error::{RenderError, Result};

/// Writes `path` atomically with `body`: to `<path>.partial`, flushed and synced, then renamed.
pub(crate) fn write_atomically(
    path: &Path,
    body: impl FnOnce(&mut BufWriter<File>) -> Result<()>,
) -> Result<()> {
    let mut partial = path.as_os_str().to_owned();
    partial.push(".partial");
    let partial = PathBuf::from(partial);
    let io = |source| RenderError::Write {
        path: path.to_path_buf(),
        source,
    };
    let file = File::create(&partial).map_err(io)?;
    let mut out = BufWriter::with_capacity(1 << 20, file);
    let written = body(&mut out)
        .and_then(|()| out.flush().map_err(io))
        .and_then(|()| out.get_ref().sync_all().map_err(io))
        .and_then(|()| std::fs::rename(&partial, path).map_err(io));
    if written.is_err() {
        let _ = std::fs::remove_file(&partial);
    }
    written.map_err(|e| match e {
        RenderError::Stream(source) => RenderError::Write {
            path: path.to_path_buf(),
            source,
        },
        other => other,
    })
}
