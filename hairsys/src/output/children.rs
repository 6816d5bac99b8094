//! `hairsys render-children export`: render children generated on request from a cached frame (or
//! sub-frame samples over a shutter, for motion blur) or from the scene's rest state, written as
//! USD `BasisCurves` (`.usdc` or `.usda`) or Cem Yuksel's `.hair`. A range of frames in one
//! file is `crate::output::shot_export` with children.
//!
//! From a cache, the children's roots (mesh samples, root frames) come from the cache's rig
//! ([`Shot`]): the scalp as it was simulated, at the sampled time. The scene's `[children]`
//! section (see [`crate::scene::children`]) gives the child settings; the command's flags
//! ([`ChildOverrides`]) override it.

use super::OutputError;
use std::path::PathBuf;

use hair_cache::Interpolation;
use hair_core::{Anchor, MeshSample, Scalp, StrandSet};
#[cfg(feature = "usd")]
use hair_render::export::usd::{self, Motion, MotionSample, UsdOptions};
use hair_render::{
    generate, ChildBuffers, ChildCount, ChildMode, ChildSettings, DisplayLod, Lod, Parents,
    ScalpRoots, ShapeFactors,
};
use nalgebra::Vector3;

use crate::budget::{Budget, BYTES_PER_CHILD_POINT};
use crate::build::Simulation;
use crate::output::shot::Shot;
use crate::scene::children::DEFAULT_NEIGHBOURS;
use crate::scene::maps::ChildMapFactors;
use crate::scene::SceneFile;

/// Output format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// USD `BasisCurves`, `.usdc` binary or `.usda` text by the output's extension.
    Usd,
    /// Cem Yuksel's `.hair`.
    Hair,
}

/// What to export.
pub struct ExportOptions {
    /// Cache to read frames from; without it, the scene's rest state.
    pub cache: Option<PathBuf>,
    /// Scene file: the rest state to export without `cache`; with it, the `[children]`
    /// settings instead of the stored scene's.
    pub scene: Option<PathBuf>,
    /// Frame to export (with a cache).
    pub frame: Option<u32>,
    /// Shutter interval in frames around the frame, e.g. (−0.25, 0.25).
    pub shutter: (f64, f64),
    /// Motion samples over the shutter (1 = no motion blur).
    pub motion_samples: usize,
    /// Child settings given on the command line, overriding the scene's `[children]`.
    pub children: ChildOverrides,
    /// Display level of detail (the scene's `[children] display`) instead of render.
    pub display: bool,
    /// Output format.
    pub format: Format,
    /// Output path.
    pub out: PathBuf,
    /// Memory limit checked before the children are generated (children × points × samples).
    pub budget: Budget,
    /// Frames added to the USD time codes written (frame `f` at `f + time_offset`; finite);
    /// 0 for scene frames as they are.
    pub time_offset: f64,
}

/// Child settings that override the scene's `[children]` section (`None`: the scene's value, or
/// the library default without one).
#[derive(Debug, Clone, Copy, Default)]
pub struct ChildOverrides {
    /// Children per parent or in all.
    pub count: Option<ChildCount>,
    /// Interpolated (true) or simple (false) children.
    pub interpolated: Option<bool>,
    /// Parents blended per interpolated child.
    pub neighbours: Option<u32>,
    /// Radius of the root disc around each parent, m.
    pub spread: Option<f32>,
    /// Clump factor.
    pub clump: Option<f32>,
    /// Curl radius, m.
    pub curl_radius: Option<f32>,
    /// Curl frequency, turns per meter.
    pub curl_frequency: Option<f32>,
    /// Seed.
    pub seed: Option<u64>,
}

impl ChildOverrides {
    /// `base` with every given override applied.
    pub fn apply(&self, mut base: ChildSettings) -> Result<ChildSettings, OutputError> {
        if let Some(c) = self.count {
            base.count = c;
        }
        let current = match base.mode {
            ChildMode::Interpolated { neighbours } => Some(neighbours),
            ChildMode::Simple => None,
        };
        base.mode = match (self.interpolated, self.neighbours, current) {
            (Some(false), Some(_), _) => {
                return Err(OutputError::request("--neighbours applies to --mode interpolated only"))
            }
            (Some(false), None, _) => ChildMode::Simple,
            (None, Some(_), None) => {
                return Err(OutputError::request(
                    "--neighbours needs interpolated children: add --mode interpolated (or mode = \"interpolated\" in the scene's [children])",
                ))
            }
            (_, Some(n), _) => ChildMode::Interpolated { neighbours: n },
            (Some(true), None, n) => ChildMode::Interpolated {
                neighbours: n.unwrap_or(DEFAULT_NEIGHBOURS),
            },
            (None, None, _) => base.mode,
        };
        if let Some(v) = self.spread {
            base.spread = v;
        }
        if let Some(v) = self.clump {
            base.shape.clump.factor = v;
        }
        if let Some(v) = self.curl_radius {
            base.shape.curl.radius = v;
        }
        if let Some(v) = self.curl_frequency {
            base.shape.curl.frequency = v;
        }
        if let Some(v) = self.seed {
            base.seed = v;
        }
        Ok(base)
    }
}

/// What was written.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ExportSummary {
    /// Output path.
    pub out: String,
    /// Child curves written.
    pub curves: usize,
    /// Points written per time sample.
    pub points: usize,
    /// Time samples written (1 without motion blur).
    pub time_samples: usize,
    /// Motion samples that fell outside the cached frames and were clamped to the first or
    /// last cached frame (the hair held still there), with the frames they asked for.
    pub clamped_samples: Vec<f64>,
}

/// Parses `--shutter OPEN,CLOSE` (frames relative to the sampled frame, e.g. `-0.25,0.25`).
pub fn parse_shutter(s: &str) -> Result<(f64, f64), ShutterError> {
    let (a, b) = s.split_once(',').ok_or_else(|| ShutterError::NotAPair {
        given: s.to_string(),
    })?;
    let num = |t: &str| {
        t.trim()
            .parse::<f64>()
            .map_err(|source| ShutterError::NotANumber {
                given: t.to_string(),
                source,
            })
    };
    Ok((num(a)?, num(b)?))
}

/// Why a `--shutter` value cannot be read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ShutterError {
    /// Not two values separated by a comma.
    #[error("`{given}` is not OPEN,CLOSE, e.g. -0.25,0.25")]
    NotAPair {
        /// The value given.
        given: String,
    },
    /// One of the two is not a number.
    #[error("`{given}` is not a number")]
    NotANumber {
        /// The part given.
        given: String,
        /// The parser's error.
        source: std::num::ParseFloatError,
    },
}

/// Generates and writes the children; `on_sample` is called after each time sample. A file
/// that cannot be written is an [`OutputError::Write`]; every other error is about what was
/// asked or read.
pub fn export(
    opts: &ExportOptions,
    mut on_sample: impl FnMut(),
) -> Result<ExportSummary, OutputError> {
    #[cfg(not(feature = "usd"))]
    if opts.format == Format::Usd {
        return Err(OutputError::UsdNotBuilt {
            path: opts.out.clone(),
        });
    }
    if opts.motion_samples == 0 {
        return Err(OutputError::request(
            "--motion-samples 0: use at least 1 sample",
        ));
    }
    let mut source = match &opts.cache {
        Some(cache) => Source::Cache(Box::new(Shot::open(cache, opts.scene.as_deref())?)),
        None => {
            let scene = match &opts.scene {
                Some(path) => SceneFile::load(path)?,
                None => SceneFile::builtin_default(),
            };
            let sim = scene.build()?;
            Source::Rest(Box::new(scene), Box::new(sim))
        }
    };
    let (settings, lod) = child_settings(source.scene(), &opts.children, opts.display)?;
    let frame = match (&source, opts.frame) {
        (Source::Cache(_), Some(f)) => f,
        (Source::Cache(_), None) => {
            return Err(OutputError::request(
                "--cache needs --frame N: the frame to export",
            ))
        }
        (Source::Rest(..), Some(_)) => {
            return Err(OutputError::request(
                "--frame needs --cache: without a cache the rest state is exported",
            ))
        }
        (Source::Rest(_, sim), None) => sim.first_frame,
    };
    check_children_memory(
        &opts.budget,
        source.strands(),
        &settings,
        opts.motion_samples,
    )?;
    let fps = source.fps();
    let offsets = shutter_offsets(opts.shutter, opts.motion_samples)?;
    let cached = match &source {
        Source::Cache(shot) => {
            let numbers = shot.cached_frames();
            numbers
                .first()
                .zip(numbers.last())
                .map(|(&a, &b)| (f64::from(a), f64::from(b)))
        }
        Source::Rest(..) => None,
    };
    let mut clamped_samples = Vec::new();
    let mut samples: Vec<(f64, ChildBuffers)> = Vec::with_capacity(offsets.len());
    for offset in offsets {
        let time_code = frame as f64 + offset;
        // A sample past the first or last cached frame is taken at that frame: the cache holds
        // nothing beyond it to interpolate, and extrapolating velocities would invent motion.
        let sampled = match cached {
            // Only the samples around a cached frame: a frame outside the cache is an error.
            Some((a, b))
                if (a..=b).contains(&f64::from(frame)) && !(a..=b).contains(&time_code) =>
            {
                clamped_samples.push(time_code);
                time_code.clamp(a, b)
            }
            _ => time_code,
        };
        let (positions, scalp) = source.at(sampled, time_code)?;
        let parents = source.parents();
        samples.push((
            time_code,
            children_of(
                parents.strands,
                &positions,
                &scalp,
                parents.colors,
                &parents.maps,
                &settings,
                lod,
            )?,
        ));
        on_sample();
    }
    let centre = samples.len() / 2;
    let (curves, points) = (
        samples[centre].1.curve_count(),
        samples[centre].1.point_count(),
    );
    let out = &opts.out;
    match opts.format {
        Format::Hair => {
            hair_render::export::hair::export_hair(out, &samples[centre].1)
                .map_err(|e| OutputError::export(out, e))?;
        }
        #[cfg(not(feature = "usd"))]
        Format::Usd => {
            // Refused before the children were generated; the rate is for USD only.
            let _ = fps;
            return Err(OutputError::UsdNotBuilt { path: out.clone() });
        }
        #[cfg(feature = "usd")]
        Format::Usd => {
            let usd_opts = UsdOptions {
                frames_per_second: fps,
                time_code: frame as f64 + opts.time_offset,
                ..UsdOptions::default()
            };
            if samples.len() > 1 {
                let motion: Vec<MotionSample> = samples
                    .iter()
                    .map(|(time_code, children)| MotionSample {
                        time_code: time_code + opts.time_offset,
                        children,
                    })
                    .collect();
                // The frame is written twice (default value and a time sample): one copy.
                let frame_children = samples[centre].1.clone();
                usd::export_usd(
                    out,
                    frame_children,
                    &Motion::TimeSamples(&motion),
                    &usd_opts,
                )
            } else {
                // One sample: its buffers move into the layer, no copy of the points.
                let (_, frame_children) = samples.swap_remove(centre);
                usd::export_usd(out, frame_children, &Motion::None, &usd_opts)
            }
            .map_err(|e| OutputError::export(out, e))?;
        }
    }
    Ok(ExportSummary {
        out: out.display().to_string(),
        curves,
        points,
        time_samples: if opts.format == Format::Usd {
            samples.len()
        } else {
            1
        },
        clamped_samples,
    })
}

/// The child settings and level of detail of an export: the scene's `[children]` section (the
/// library defaults without one) with `overrides` applied; `display` picks the section's display
/// level of detail instead of render.
pub(crate) fn child_settings(
    scene: Option<&SceneFile>,
    overrides: &ChildOverrides,
    display: bool,
) -> Result<(ChildSettings, Lod), OutputError> {
    let (base, display_lod) = match scene.and_then(|s| s.scene.children.as_ref().map(|c| (s, c))) {
        Some((scene, section)) => section.settings().map_err(|e| scene.error(e))?,
        None => (ChildSettings::default(), DisplayLod::default()),
    };
    let settings = overrides.apply(base)?;
    let lod = if display {
        Lod::Display(display_lod)
    } else {
        Lod::Render
    };
    Ok((settings, lod))
}

/// Refuses `samples` time samples of the children `settings` give on the parents `strands`
/// when children × points × samples is over `budget`, before any child is generated.
pub(crate) fn check_children_memory(
    budget: &Budget,
    strands: &StrandSet,
    settings: &ChildSettings,
    samples: usize,
) -> Result<(), OutputError> {
    let parents = strands.len();
    let children = match settings.count {
        ChildCount::PerParent(n) => f64::from(n) * parents as f64,
        ChildCount::Total(n) => n as f64,
    };
    let points_per_child = strands.point_count() as f64 / parents.max(1) as f64;
    let samples = samples as f64;
    let bytes = children * points_per_child * samples * BYTES_PER_CHILD_POINT as f64;
    budget
        .check_bytes(
            &format!(
                "{children} children × {points_per_child:.0} points × {samples} motion samples"
            ),
            bytes,
        )
        .map_err(OutputError::from)
}

/// Offsets (frames) of `n` samples evenly over the shutter, both ends included; the centre for 1.
fn shutter_offsets((open, close): (f64, f64), n: usize) -> Result<Vec<f64>, OutputError> {
    if !(open.is_finite() && close.is_finite() && open <= close) {
        return Err(OutputError::Request(format!("--shutter {open},{close}: give OPEN,CLOSE in frames with OPEN ≤ CLOSE, e.g. -0.25,0.25")));
    }
    if n == 1 {
        return Ok(vec![0.5 * (open + close)]);
    }
    Ok((0..n)
        .map(|i| open + (close - open) * i as f64 / (n - 1) as f64)
        .collect())
}

/// Children of `strands` at `positions` (m), rooted on `scalp` (mesh samples, root frames and
/// the scalp's UVs; `colors`, one RGB per scalp vertex, colour the roots), each parent's clump
/// and curl scaled by `maps` (the scene's `[maps.clump]` and `[maps.curl]`): the one generation
/// behind the export from a cache and [`crate::Session::children`].
pub(crate) fn children_of(
    strands: &StrandSet,
    positions: &[Vector3<f32>],
    scalp: &Scalp,
    colors: Option<&[[f32; 3]]>,
    maps: &ChildMapFactors,
    settings: &ChildSettings,
    lod: Lod,
) -> Result<ChildBuffers, hair_render::RenderError> {
    let roots = strands.root_frames(scalp);
    let samples: Vec<Option<MeshSample>> = strands
        .anchors()
        .iter()
        .map(|a| match a {
            Anchor::Surface(s) => Some(*s),
            Anchor::Body(_) => None,
        })
        .collect();
    let mut parents = Parents::new(positions, strands.offsets())?
        .with_root_frames(&roots)?
        .with_shape_factors(ShapeFactors {
            clump: maps.clump.as_deref(),
            curl: maps.curl.as_deref(),
        })?;
    if let Some(mesh) = &scalp.mesh {
        parents = parents.with_scalp(ScalpRoots {
            mesh,
            samples: &samples,
            colors,
        })?;
    }
    generate(&parents, settings, lod)
}

/// Where an export's parents and scalp come from: a cache, or a scene's rest state.
enum Source {
    /// A cache, with its rig.
    Cache(Box<Shot>),
    /// A scene built for its rest state.
    Rest(Box<SceneFile>, Box<Simulation>),
}

/// The parents of an export: their strands (anchors, layout), root colours and child maps.
struct ParentsOf<'a> {
    strands: &'a StrandSet,
    colors: Option<&'a [[f32; 3]]>,
    maps: ChildMapFactors,
}

impl Source {
    /// The scene whose `[children]` settings apply, if there is one.
    fn scene(&self) -> Option<&SceneFile> {
        match self {
            Source::Cache(shot) => shot.scene(),
            Source::Rest(scene, _) => Some(scene),
        }
    }

    fn strands(&self) -> &StrandSet {
        match self {
            Source::Cache(shot) => shot.strands(),
            Source::Rest(_, sim) => &sim.strands,
        }
    }

    fn fps(&self) -> f64 {
        match self {
            Source::Cache(shot) => shot.fps(),
            Source::Rest(_, sim) => f64::from(sim.settings.fps),
        }
    }

    fn parents(&self) -> ParentsOf<'_> {
        match self {
            Source::Cache(shot) => ParentsOf {
                strands: shot.strands(),
                colors: shot.rig().scalp.as_ref().and_then(|s| s.colors.as_deref()),
                maps: ChildMapFactors {
                    clump: shot.rig().clump.clone(),
                    curl: shot.rig().curl.clone(),
                },
            },
            Source::Rest(_, sim) => ParentsOf {
                strands: &sim.strands,
                colors: sim.scalp_colors.as_deref(),
                maps: sim.child_maps.clone(),
            },
        }
    }

    /// The parents' positions sampled at (possibly fractional) frame `sampled`, and the scalp
    /// at `time_code` (the rest state's, without a cache).
    fn at(
        &mut self,
        sampled: f64,
        time_code: f64,
    ) -> Result<(Vec<nalgebra::Vector3<f32>>, Scalp), OutputError> {
        match self {
            Source::Cache(shot) => {
                let fps = shot.fps();
                let positions = shot
                    .reader()
                    .sample(sampled / fps, Interpolation::Hermite)?
                    .positions;
                let scalp = shot.scalp_at(sampled)?;
                Ok((positions, scalp))
            }
            Source::Rest(_, sim) => Ok((
                sim.strands.positions.clone(),
                sim.scalp_at(time_code as f32),
            )),
        }
    }
}
