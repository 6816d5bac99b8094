//! `hairsys render-children cards`: the hair cards of a `model = "strips"` scene (seed 000) from
//! a cached frame — with motion-blur samples over a shutter, read from the cache exactly like
//! `render-children export` — or from the scene's rest state, written as a USD `Mesh` (`.usda`,
//! `st` per vertex, all samples as `points.timeSamples`, `upAxis = "Z"` declared) or OBJ (the
//! centre sample; Y up by default, the OBJ convention, see [`hair_render::export::cards_obj`]).
//!
//! The strips are grown again from the scene's `[strips]` section (the scene stored in the
//! cache, or `--scene`) on the cache's rest scalp ([`Shot`]), and their edge strands take the
//! cached positions (strip `k` = strands `2k`, `2k + 1`). When the scalp is a collider, the rest
//! scalp is the head every card vertex is kept out of.

use super::OutputError;
use std::path::PathBuf;

use hair_cache::Interpolation;
use hair_core::model::strips::HeadShape;
use hair_render::export::cards_obj::{export_cards_obj, ObjUpAxis};
#[cfg(feature = "usd")]
use hair_render::export::cards_usd::{export_cards_usda, CardSample, CardUsdOptions};
use hair_render::{build_cards, CardMesh, CardSettings};

use crate::output::shot::Shot;
use crate::scene::SceneFile;

/// Card output format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CardsFormat {
    /// USD Mesh (.usda) with st and motion samples.
    Usd,
    /// Wavefront OBJ with vt (the centre sample only).
    Obj,
}

/// What to export.
#[derive(Debug, Clone)]
pub struct CardsOptions {
    /// Cache to read (the scene stored in it gives the strips); without it, the rest state.
    pub cache: Option<PathBuf>,
    /// Scene file: the rest state to export without `cache`, or a scene overriding the cache's.
    pub scene: Option<PathBuf>,
    /// Frame to export (with a cache).
    pub frame: Option<u32>,
    /// Shutter interval (open, close) in frames around the frame.
    pub shutter: (f64, f64),
    /// Motion samples over the shutter (USD time samples); 1 = no motion blur.
    pub motion_samples: usize,
    /// Output format.
    pub format: CardsFormat,
    /// Rows of vertices per edge segment along a card.
    pub rows_per_segment: u32,
    /// Vertices across a card (≥ 2).
    pub columns: u32,
    /// Gap kept between card vertices and the head, m (with `[scalp.collider]`).
    pub clearance: f32,
    /// Up axis of an OBJ file (Y, the OBJ convention, by default); USD declares Z.
    pub up_axis: ObjUpAxis,
    /// Output file.
    pub out: PathBuf,
}

/// What was written.
#[derive(Debug, Clone, serde::Serialize)]
pub struct CardsSummary {
    /// Output path.
    pub out: String,
    /// Cards (strips) written.
    pub cards: usize,
    /// Hairs the cards stand for.
    pub represented_hairs: u64,
    /// Vertices per time sample.
    pub vertices: usize,
    /// Quads.
    pub quads: usize,
    /// Time samples written (1 without motion blur and for OBJ).
    pub time_samples: usize,
}

/// Builds and writes the cards of `args`. A file that cannot be written is an
/// [`OutputError::Write`]; every other error is about what was asked or read.
pub fn export_cards(args: &CardsOptions) -> Result<CardsSummary, OutputError> {
    #[cfg(not(feature = "usd"))]
    if args.format == CardsFormat::Usd {
        return Err(OutputError::UsdNotBuilt {
            path: args.out.clone(),
        });
    }
    let Samples {
        meshes: samples,
        represented_hairs,
        fps,
        frame,
    } = build_samples(args)?;
    let centre = &samples[samples.len() / 2].1;
    let time_samples = match args.format {
        CardsFormat::Obj => {
            export_cards_obj(&args.out, centre, args.up_axis)
                .map_err(|e| OutputError::export(&args.out, e))?;
            1
        }
        #[cfg(not(feature = "usd"))]
        CardsFormat::Usd => {
            // Refused before the cards were built; the rate and frame are for USD only.
            let _ = (fps, frame);
            return Err(OutputError::UsdNotBuilt {
                path: args.out.clone(),
            });
        }
        #[cfg(feature = "usd")]
        CardsFormat::Usd => {
            let motion: Vec<CardSample> = if samples.len() > 1 {
                samples
                    .iter()
                    .map(|(time_code, mesh)| CardSample {
                        time_code: *time_code,
                        mesh,
                    })
                    .collect()
            } else {
                Vec::new()
            };
            let opts = CardUsdOptions {
                frames_per_second: fps,
                time_code: frame as f64,
                ..CardUsdOptions::default()
            };
            export_cards_usda(&args.out, centre, &motion, &opts)
                .map_err(|e| OutputError::export(&args.out, e))?;
            samples.len()
        }
    };
    Ok(CardsSummary {
        out: args.out.display().to_string(),
        cards: centre.cards,
        represented_hairs,
        vertices: centre.positions.len(),
        quads: centre.quads.len(),
        time_samples,
    })
}

/// The cards of one export, before they are written.
struct Samples {
    /// The cards at each motion sample: (USD time code, mesh).
    meshes: Vec<(f64, CardMesh)>,
    /// Hairs the cards stand for.
    represented_hairs: u64,
    /// Frame rate, frames/s.
    fps: f64,
    /// The frame exported.
    frame: u32,
}

/// The cards of `args` at each motion sample; errors are bad input.
fn build_samples(args: &CardsOptions) -> Result<Samples, OutputError> {
    if args.motion_samples == 0 {
        return Err(OutputError::request(
            "--motion-samples 0: use at least 1 sample",
        ));
    }
    let (open, close) = args.shutter;
    if !(open.is_finite() && close.is_finite() && open <= close) {
        return Err(OutputError::Request(format!(
            "--shutter {open},{close}: give OPEN,CLOSE in frames with OPEN ≤ CLOSE"
        )));
    }
    let (mut shot, scene, sim) = match &args.cache {
        Some(cache) => {
            let shot = Shot::open(cache, args.scene.as_deref())?;
            (Some(shot), None, None)
        }
        None => {
            let Some(path) = &args.scene else {
                return Err(OutputError::request(
                    "give --cache or --scene: the cards of which strips?",
                ));
            };
            let scene = SceneFile::load(path)?;
            let sim = scene.build()?;
            (None, Some(scene), Some(sim))
        }
    };
    let scene = match (&shot, &scene) {
        (Some(shot), _) => shot.scene(),
        (None, scene) => scene.as_ref(),
    };
    let mesh = match (&shot, &sim) {
        (Some(shot), _) => shot.rest_scalp(),
        (None, Some(sim)) => sim.rest_mesh(),
        (None, None) => None,
    };
    let (Some(scene), Some(mesh)) = (scene, mesh) else {
        return Err(OutputError::request(
            "cards need a scene with [solver] model = \"strips\", a [strips] section and a scalp \
             mesh",
        ));
    };
    let Some(section) = &scene.scene.strips else {
        return Err(OutputError::Request(format!(
            "{}: cards need a scene with [solver] model = \"strips\" and a [strips] section",
            scene.origin
        )));
    };
    let mut strips = section.build(mesh)?;
    let scalp_collides = match (&shot, &sim) {
        (Some(shot), _) => shot.scalp_collider().is_some(),
        (None, Some(sim)) => sim.scalp_collider.is_some(),
        (None, None) => false,
    };
    let head = match scalp_collides {
        true => Some(HeadShape::new(mesh)?),
        false => None,
    };
    let settings = CardSettings {
        rows_per_segment: args.rows_per_segment,
        columns: args.columns,
        clearance: args.clearance,
    };
    let (fps, frame) = match (&shot, &sim, args.frame) {
        (Some(shot), _, Some(f)) => (shot.fps(), f),
        (Some(_), _, None) => {
            return Err(OutputError::request(
                "--cache needs --frame N: the frame to export",
            ))
        }
        (None, _, Some(_)) => {
            return Err(OutputError::request(
                "--frame needs --cache: without a cache the rest state is exported",
            ))
        }
        (None, Some(sim), None) => (f64::from(sim.settings.fps), sim.first_frame),
        (None, None, None) => unreachable!("a rest export has a scene"),
    };
    let n = args.motion_samples;
    let offsets: Vec<f64> = if n == 1 {
        vec![0.5 * (open + close)]
    } else {
        (0..n)
            .map(|i| open + (close - open) * i as f64 / (n - 1) as f64)
            .collect()
    };
    let mut samples: Vec<(f64, CardMesh)> = Vec::with_capacity(n);
    for offset in offsets {
        let time_code = frame as f64 + offset;
        if let Some(shot) = shot.as_mut() {
            let positions = shot
                .reader()
                .sample(time_code / fps, Interpolation::Hermite)?
                .positions;
            if positions.len() != strips.strands.point_count() {
                return Err(OutputError::Request(format!(
                    "the cache has {} points per frame but the scene's strips have {}; export \
                     with the scene that made the cache",
                    positions.len(),
                    strips.strands.point_count()
                )));
            }
            strips.strands.positions = positions;
        }
        let scalp = match (shot.as_mut(), &sim) {
            (Some(shot), _) => shot.scalp_at(time_code)?,
            (None, Some(sim)) => sim.scalp_at(time_code as f32),
            (None, None) => unreachable!("a rest export has a scene"),
        };
        let cards = build_cards(&strips, &scalp, &settings, head.as_ref())?;
        samples.push((time_code, cards));
    }
    Ok(Samples {
        meshes: samples,
        represented_hairs: strips.represented_hairs(),
        fps,
        frame,
    })
}
