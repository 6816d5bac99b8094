//! `hairsys render-children cards`: the command's arguments and output around
//! [`hairsys::output::cards::export_cards`].

use std::path::PathBuf;

use hair_render::export::cards_obj::ObjUpAxis;
use hairsys::output::cards::{export_cards, CardsFormat, CardsOptions};
use hairsys::output::children::parse_shutter;

/// Card output format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum CardsFormatArg {
    /// USD Mesh (.usda) with st and motion samples.
    Usd,
    /// Wavefront OBJ with vt (the centre sample only).
    Obj,
}

/// Up axis of an OBJ file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ObjUpAxisArg {
    /// Y up, the OBJ convention (what Blender's OBJ importer assumes by default).
    Y,
    /// Z up, as simulated (tell the importer the file is Z up).
    Z,
}

/// Arguments of `render-children cards`.
#[derive(Debug, Clone, clap::Args)]
pub struct CardsArgs {
    /// Cache to read (its rig gives the scalp, the scene stored in it the `[strips]` section);
    /// without it, the rest state.
    #[arg(long)]
    pub cache: Option<PathBuf>,
    /// Scene file: the rest state to export without --cache; with --cache, its `[strips]`
    /// section instead of the stored scene's.
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Frame to export (with --cache).
    #[arg(long)]
    pub frame: Option<u32>,
    /// Shutter interval OPEN,CLOSE in frames around the frame.
    #[arg(long, value_parser = parse_shutter, default_value = "-0.25,0.25", allow_hyphen_values = true)]
    pub shutter: (f64, f64),
    /// Motion samples over the shutter (USD time samples); 1 = no motion blur.
    #[arg(long, default_value_t = 1)]
    pub motion_samples: usize,
    /// Output format.
    #[arg(long, value_enum, default_value_t = CardsFormatArg::Usd)]
    pub format: CardsFormatArg,
    /// Rows of vertices per edge segment along a card.
    #[arg(long, default_value_t = 4)]
    pub rows_per_segment: u32,
    /// Vertices across a card (≥ 2).
    #[arg(long, default_value_t = 3)]
    pub columns: u32,
    /// Gap kept between card vertices and the head, m (with [scalp.collider]).
    #[arg(long, default_value_t = 1e-3)]
    pub clearance: f32,
    /// Up axis of an OBJ file: Y (the OBJ convention, what Blender's importer assumes) writes
    /// simulated (x, y, z) as (x, z, -y); Z writes them as simulated. USD declares Z up.
    #[arg(long, value_enum, default_value_t = ObjUpAxisArg::Y)]
    pub up_axis: ObjUpAxisArg,
    /// Output file (.usda for usd, .obj for obj).
    #[arg(short, long)]
    pub out: PathBuf,
    /// Print a JSON summary on stdout.
    #[arg(long)]
    pub json: bool,
    /// Print nothing but errors.
    #[arg(long, conflicts_with = "json")]
    pub quiet: bool,
}

impl CardsArgs {
    /// The library's options for these arguments.
    pub fn options(&self) -> CardsOptions {
        CardsOptions {
            cache: self.cache.clone(),
            scene: self.scene.clone(),
            frame: self.frame,
            shutter: self.shutter,
            motion_samples: self.motion_samples,
            format: match self.format {
                CardsFormatArg::Usd => CardsFormat::Usd,
                CardsFormatArg::Obj => CardsFormat::Obj,
            },
            rows_per_segment: self.rows_per_segment,
            columns: self.columns,
            clearance: self.clearance,
            up_axis: match self.up_axis {
                ObjUpAxisArg::Y => ObjUpAxis::Y,
                ObjUpAxisArg::Z => ObjUpAxis::Z,
            },
            out: self.out.clone(),
        }
    }
}

/// Runs `render-children cards` and prints its summary (text, JSON or nothing).
pub fn run(args: &CardsArgs) -> Result<(), crate::error::CliError> {
    let summary = export_cards(&args.options())?;
    if args.json {
        crate::output::line(&serde_json::to_string(&summary).expect("summaries serialise"));
    } else if !args.quiet {
        crate::output::line(&format!(
            "wrote {}: {} cards ({} hairs), {} vertices, {} quads, {} time sample(s)",
            summary.out,
            summary.cards,
            summary.represented_hairs,
            summary.vertices,
            summary.quads,
            summary.time_samples
        ));
    }
    Ok(())
}
