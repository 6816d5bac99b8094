//! `hairsys groom`: write a scene's guides to a groom file; print a groom file's summary in the
//! units it was read in.

use std::path::{Path, PathBuf};

use clap::{Subcommand, ValueEnum};
use hairsys::scene::SceneFile;
use serde_json::json;

use crate::error::CliError;
use crate::Context;

#[derive(Subcommand)]
pub enum GroomCommand {
    /// Write a scene's guides (imported and snapped, or generated) to a groom file, e.g. .hair.
    Export {
        /// Scene file with a [guides] section.
        scene: PathBuf,
        /// Output file; the format comes from the extension (.hair, .tfx, .obj, .usda).
        #[arg(short, long)]
        out: PathBuf,
    },
    /// Print a groom file's strands, points, lengths and bounds (in meters, Z up) and the units
    /// they were read in: a USD stage's own `metersPerUnit` and `upAxis`; for files without
    /// units (.hair, .tfx, .obj) 1 m per unit, Z up, unless --scale and --up-axis say otherwise,
    /// with the likely right --scale when the strands come out implausible for hair.
    Info {
        /// Groom file; the format comes from the extension.
        file: PathBuf,
        /// Meters per file unit (the Sintel sample: 0.01), replacing a USD stage's. A given
        /// scale that makes the longest strand shorter than 1 mm or longer than 10 m is refused
        /// as implausible for hair.
        #[arg(long)]
        scale: Option<f32>,
        /// The file's up axis (Y-up files are turned to Z up), replacing a USD stage's
        /// [default: the stage's; z for other files].
        #[arg(long, value_enum)]
        up_axis: Option<UpAxisArg>,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
}

/// Runs a `groom` command.
pub fn run(command: GroomCommand, ctx: &Context) -> Result<(), CliError> {
    match command {
        GroomCommand::Export { scene, out } => export_guides(&scene, &out, ctx),
        GroomCommand::Info {
            file,
            scale,
            up_axis,
            json,
        } => groom_info(&file, scale, up_axis, json),
    }
}

/// Up axis of a file.
#[derive(Clone, Copy, ValueEnum)]
pub enum UpAxisArg {
    /// Y up (Maya, most exporters); converted to Z up.
    Y,
    /// Z up (Blender).
    Z,
}

/// `groom export`: a scene's guides, in world space at rest, to a groom file.
fn export_guides(scene: &Path, out: &Path, ctx: &Context) -> Result<(), CliError> {
    let mut scene_file = SceneFile::load(scene)?;
    scene_file.budget = ctx.budget;
    let sim = scene_file.build()?;
    let (Some(mesh), false) = (sim.rest_mesh(), sim.guides.is_empty()) else {
        return Err(CliError::input(format!(
            "{}: the scene has no [guides] to export",
            scene.display()
        )));
    };
    let groom = hair_groom::guides_to_groom(mesh, &sim.guides)
        .map_err(|e| CliError::input(format!("{}: {e}", scene.display())))?;
    let opts = hair_groom::ImportOptions {
        scale: 1.0,
        up_axis: hair_groom::UpAxis::Z,
    };
    hair_groom::write_groom(out, &groom, &opts).map_err(|e| CliError::failed(e.to_string()))?;
    outln!(
        "wrote {}: {} guides, {} points (meters, Z up)",
        out.display(),
        groom.len(),
        groom.point_count()
    );
    Ok(())
}

/// `groom info`: a groom file's summary, with the units it was read in.
fn groom_info(
    file: &Path,
    scale: Option<f32>,
    up_axis: Option<UpAxisArg>,
    json: bool,
) -> Result<(), CliError> {
    let up = up_axis.map(|a| match a {
        UpAxisArg::Y => hair_groom::UpAxis::Y,
        UpAxisArg::Z => hair_groom::UpAxis::Z,
    });
    let named = |e: hair_groom::GroomError| {
        let e = e.to_string();
        // Name the file even when the reader's message does not.
        let name = file.display().to_string();
        CliError::input(if e.contains(&name) {
            e
        } else {
            format!("{name}: {e}")
        })
    };
    let is_usd = matches!(
        hair_groom::GroomFormat::of(file),
        Ok(hair_groom::GroomFormat::Usd)
    );
    let (groom, units) = if is_usd {
        // The stage's own units, replaced only where a flag is given.
        let stage =
            hair_groom::read_usd(file, &hair_groom::UsdReadOptions::default()).map_err(named)?;
        if scale.is_none() && up.is_none() {
            let units = Units {
                meters_per_unit: stage.meters_per_unit,
                up_axis: stage.up_axis,
                source: "the stage's metersPerUnit and upAxis",
            };
            (stage.groom, units)
        } else {
            let opts = hair_groom::ImportOptions {
                scale: scale.unwrap_or(stage.meters_per_unit as f32),
                up_axis: up.unwrap_or(stage.up_axis),
            };
            let groom = hair_groom::read_groom(file, &opts).map_err(named)?;
            let units = Units {
                meters_per_unit: f64::from(opts.scale),
                up_axis: opts.up_axis,
                source: "--scale and --up-axis over the stage's",
            };
            (groom, units)
        }
    } else {
        let opts = hair_groom::ImportOptions {
            scale: scale.unwrap_or(1.0),
            up_axis: up.unwrap_or(hair_groom::UpAxis::Z),
        };
        let groom = hair_groom::read_groom(file, &opts).map_err(named)?;
        let source = match scale {
            Some(_) => "--scale and --up-axis",
            None => "assumed: the file has no units",
        };
        let units = Units {
            meters_per_unit: f64::from(opts.scale),
            up_axis: opts.up_axis,
            source,
        };
        (groom, units)
    };
    let info = hair_groom::groom_info(&groom);
    // A scale the user gave is a claim to check; an assumed one is only reported on.
    if let Some(scale) = scale {
        check_scale(file, scale, info.length_max)?;
    }
    let likely = likely_scale(units.meters_per_unit, info.length_max);
    let up_name = match units.up_axis {
        hair_groom::UpAxis::Y => "y",
        hair_groom::UpAxis::Z => "z",
    };
    if json {
        let (lo, hi) = info.bounds;
        let doc = json!({
            "file": file.display().to_string(),
            "strands": info.strands,
            "points": info.points,
            "points_per_strand": [info.points_min, info.points_max],
            "length_m": { "min": info.length_min, "mean": info.length_mean, "max": info.length_max },
            "bounds_m": [[lo.x, lo.y, lo.z], [hi.x, hi.y, hi.z]],
            "units": {
                "meters_per_unit": units.meters_per_unit,
                "up_axis": up_name,
                "source": units.source,
                "plausible": likely.is_none(),
                "likely_scale": likely,
            },
        });
        outln!(
            "{}",
            serde_json::to_string_pretty(&doc).expect("summaries serialise")
        );
    } else {
        outln!("{}", file.display());
        outln!("{}", info.to_string().trim_end());
        outln!(
            "units    {} m per unit, {} up ({})",
            units.meters_per_unit,
            up_name.to_uppercase(),
            units.source
        );
        if let Some(s) = likely {
            outln!(
                "note     the longest strand is {:.3e} m, implausible for hair (1 mm – 10 m): \
                 the file's units are likely {s:e} m (read it with --scale {s:e})",
                info.length_max
            );
        }
    }
    Ok(())
}

/// The units a groom was read in, and where they came from.
struct Units {
    /// Meters per file unit.
    meters_per_unit: f64,
    /// The up axis converted from.
    up_axis: hair_groom::UpAxis,
    /// Where they came from, in words.
    source: &'static str,
}

/// The meters per unit (a power of ten times `scale`) that make the longest strand about 30 cm,
/// when at `scale` it (`longest`, m) is implausible for hair; `None` when it is plausible.
fn likely_scale(scale: f64, longest: f64) -> Option<f64> {
    let (lo, hi) = PLAUSIBLE_LONGEST_STRAND;
    if (lo..=hi).contains(&longest) || !(longest > 0.0 && longest.is_finite()) {
        return None;
    }
    let decades = (longest / 0.3).log10().round() as i32;
    Some(scale * 10f64.powi(-decades))
}

/// Shortest and longest plausible length of the longest strand of a groom, m: from stubble
/// (1 mm) to far beyond floor-length hair (10 m). A longest strand outside this range means the
/// `--scale` is off, by far more than any real groom differs (1e12 or 1e-12 still give finite
/// coordinates, so nothing else catches it).
const PLAUSIBLE_LONGEST_STRAND: (f64, f64) = (1e-3, 10.0);

/// Refuses a `--scale` that makes the longest strand (`longest`, m after scaling) implausible
/// for hair, naming the flag, the length and the scale that would make it about 30 cm.
fn check_scale(file: &Path, scale: f32, longest: f64) -> Result<(), CliError> {
    let (lo, hi) = PLAUSIBLE_LONGEST_STRAND;
    if (lo..=hi).contains(&longest) {
        return Ok(());
    }
    let hint = match likely_scale(f64::from(scale), longest) {
        Some(s) => {
            let decades = (f64::from(scale) / s).log10().round() as i32;
            format!("; the file's units are likely off by 10^{decades}: try --scale {s:.0e}")
        }
        None => String::new(),
    };
    Err(CliError::input(format!(
        "{}: --scale {scale:e} makes the longest strand {longest:e} m, outside the {lo} m – \
         {hi} m of real hair; give --scale in meters per file unit (1 for meters, 0.01 for \
         centimetres){hint}",
        file.display()
    )))
}
