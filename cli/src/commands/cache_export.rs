//! `hairsys cache export CACHE -o shot.usdc [--frames A-B] [--shutter …] [--children …]` (and
//! `render-children export --frames A-B`): a whole cached run as one animated USD file
//! ([`hairsys::output::shot_export`]), with a one-line or JSON summary.

use std::path::Path;
use std::time::Instant;

use hairsys::output::shot_export::{export_shot, ShotOptions};

use crate::error::CliError;

/// Exports `cache` to `out` and prints what was written (nothing when `quiet`, JSON when
/// `json`).
pub fn run(
    cache: &Path,
    out: &Path,
    opts: &ShotOptions,
    quiet: bool,
    json: bool,
) -> Result<(), CliError> {
    let start = Instant::now();
    let s = export_shot(cache, out, opts)?;
    let seconds = start.elapsed().as_secs_f64();
    if json {
        let mut v = serde_json::to_value(&s).expect("summaries serialise");
        v["out"] = out.display().to_string().into();
        v["seconds"] = seconds.into();
        crate::output::line(&v.to_string());
        return Ok(());
    }
    if !s.dropped_samples.is_empty() && !quiet {
        eprintln!(
            "note: shutter sample(s) at time code(s) {:?} lie outside the cached frames and were \
             left out",
            s.dropped_samples
        );
    }
    if quiet {
        return Ok(());
    }
    let scalp = match s.scalp_animated {
        Some(true) => "animated scalp",
        Some(false) => "static scalp",
        None => "no scalp",
    };
    let offset = if opts.time_offset == 0.0 {
        String::new()
    } else {
        format!(" at time codes {}–{}", s.time_codes.0, s.time_codes.1)
    };
    crate::output::line(&format!(
        "wrote {}: frames {}–{}{offset} ({} time samples), {} {} curves, {} points, {scalp}, {} \
         bytes in {seconds:.2} s",
        out.display(),
        s.frames.0,
        s.frames.1,
        s.time_samples,
        s.curves,
        s.prim,
        s.points,
        s.bytes,
    ));
    Ok(())
}
