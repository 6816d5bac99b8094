//! `hairsys preview`: PNG pictures of cached frames or sub-frames (or a scene's rest state),
//! with the quality report on request.

use std::path::PathBuf;

use crate::error::CliError;
use crate::{output, quality_text};

/// Arguments of `preview`.
#[derive(clap::Args)]
pub struct PreviewArgs {
    /// Cache to draw frames of (its rig places the scalp and colliders as the run saw them).
    #[arg(long)]
    cache: Option<PathBuf>,
    /// Scene file: its rest state, drawn without --cache.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Frames to draw, comma-separated; fractional frames are sub-frame samples (cubic Hermite
    /// with the cached velocities) [default: the cache's first frame].
    #[arg(long, value_delimiter = ',')]
    frames: Vec<f64>,
    /// Camera presets, comma-separated: front, side, back, three-quarter.
    #[arg(long, value_delimiter = ',', default_value = "three-quarter")]
    views: Vec<String>,
    /// Tile width, pixels.
    #[arg(long, default_value_t = 800)]
    width: u32,
    /// Tile height, pixels.
    #[arg(long, default_value_t = 800)]
    height: u32,
    /// Mark points inside colliders and segments stretched beyond --stretch-limit in red.
    #[arg(long)]
    highlight: bool,
    /// Relative elongation --highlight marks (0.01 = 1 %).
    #[arg(long, default_value_t = 0.01)]
    stretch_limit: f32,
    /// Tiles per row of a contact sheet [default: one per view].
    #[arg(long)]
    columns: Option<u32>,
    /// The PNG to write.
    #[arg(short, long)]
    out: PathBuf,
    /// Also measure every frame of --cache and print its quality report: points inside
    /// colliders and the deepest, stretch and compression (p50/p99/max), hairpins, drift from
    /// the groom at the first stepped and the last frame, velocity–position mismatch.
    #[arg(long)]
    report: bool,
    /// Print the summary as JSON.
    #[arg(long)]
    json: bool,
}

/// `preview`: draws the frames and writes the PNG.
pub fn run(a: &PreviewArgs) -> Result<(), CliError> {
    let views = a
        .views
        .iter()
        .map(|v| {
            hair_render::preview::View::parse(v)
                .map_err(|e| CliError::input(format!("--views {v}: {e}")))
        })
        .collect::<Result<Vec<_>, _>>()?;
    hairsys::output::preview::check_output(&a.out)?;
    if a.report && a.cache.is_none() {
        return Err(CliError::input(
            "--report measures the frames of a run: give --cache",
        ));
    }
    let opts = hairsys::output::preview::PreviewOptions {
        cache: a.cache.clone(),
        scene: a.scene.clone(),
        frames: a.frames.clone(),
        views,
        width: a.width,
        height: a.height,
        highlight: a.highlight,
        stretch_limit: a.stretch_limit,
        columns: a.columns,
        out: a.out.clone(),
    };
    let summary = hairsys::output::preview::preview(&opts)?;
    let quality = match (&a.cache, a.report) {
        (Some(cache), true) => Some(hairsys::output::quality::cache_quality(cache)?),
        _ => None,
    };
    if a.json {
        let mut value = serde_json::to_value(&summary).expect("summaries serialise");
        if let Some(q) = &quality {
            value["quality"] = serde_json::to_value(q).expect("reports serialise");
        }
        output::line(&value.to_string());
    } else {
        output::line(&format!(
            "wrote {}: {} tile(s), {}×{} px, {:.0} ms per tile{}",
            summary.out,
            summary.tiles,
            summary.width,
            summary.height,
            summary.ms_per_tile,
            if a.highlight {
                format!(
                    "; marked {} point(s) inside colliders, {} stretched segment(s)",
                    summary.points_inside, summary.stretched_segments
                )
            } else {
                String::new()
            }
        ));
        if let Some(q) = &quality {
            output::line(&quality_text::describe(q));
        }
    }
    Ok(())
}
