//! `hairsys cache export CACHE -o shot.usdc [--frames A-B]`: a whole cached run as one animated
//! USD file ([`hairsys::export_shot`]), with a one-line summary.

use std::path::Path;
use std::time::Instant;

/// Exports `cache` to `out` and prints what was written; errors are messages for the user.
pub fn run(cache: &Path, out: &Path, frames: Option<(u32, u32)>) -> Result<(), String> {
    let start = Instant::now();
    let s = hairsys::export_shot::export_shot(cache, out, frames)?;
    crate::output::line(&format!(
        "wrote {}: frames {}–{} ({} time samples), {} strands, {} points, {}scalp, {} bytes in {:.2} s",
        out.display(),
        s.frames.0,
        s.frames.1,
        s.frame_count,
        s.strands,
        s.points,
        if s.scalp { "" } else { "no " },
        s.bytes,
        start.elapsed().as_secs_f64()
    ));
    Ok(())
}
