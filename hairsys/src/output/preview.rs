//! `hairsys preview`: pictures of a run on the CPU — a cached frame or sub-frame, or a scene's
//! rest state — with its scalp and colliders, from one or more camera presets, as one PNG or a
//! contact sheet (see [`hair_render::preview`] for how a frame is drawn).
//!
//! A cache carries its rig ([`Shot`]), so the scalp and the colliders are placed at each
//! frame's time exactly as the run saw them (sub-frames between the recorded frames). Every tile of a sheet shares one framing (the
//! bounds of all its frames), so motion between frames reads as motion. With `highlight`,
//! points closer to a collider than their radius and segments stretched beyond
//! [`PreviewOptions::stretch_limit`] are drawn in red on top.

use super::OutputError;
use std::path::{Path, PathBuf};

use hair_cache::Interpolation;
use hair_core::{ColliderShape, Colliders, Scalp, StrandSet, TriMesh};
use hair_render::preview::{
    contact_sheet, render_view, Bounds, Highlight, Mesh, PreviewError, PreviewImage,
    RenderSettings, Rgb, Scene, Strands, Tile, View,
};
use nalgebra::{Isometry3, Vector3};

use crate::build::Simulation;
use crate::output::shot::Shot;
use crate::scene::SceneFile;

/// Skin colour of the scalp, linear RGB.
const SCALP_RGB: Rgb = [0.62, 0.42, 0.33];
/// Colour of other colliders, linear RGB.
const COLLIDER_RGB: Rgb = [0.35, 0.45, 0.6];

/// What to draw and where to write it.
#[derive(Debug, Clone)]
pub struct PreviewOptions {
    /// Cache to read frames from; without it, the scene's rest state.
    pub cache: Option<PathBuf>,
    /// Scene file: the rest state to draw without `cache` (ignored with it: a cache carries
    /// its scalp and colliders).
    pub scene: Option<PathBuf>,
    /// Frames to draw (fractional = a sub-frame sampled by cubic Hermite with the cached
    /// velocities); empty = the cache's first frame (or the rest state).
    pub frames: Vec<f64>,
    /// Camera presets; each frame is drawn from each.
    pub views: Vec<View>,
    /// Tile size, pixels.
    pub width: u32,
    /// Tile height, pixels.
    pub height: u32,
    /// Mark points inside colliders and over-stretched segments in red.
    pub highlight: bool,
    /// Relative elongation above which `highlight` marks a segment (0.01 = 1 %).
    pub stretch_limit: f32,
    /// Tiles per row of the contact sheet (default: one row per frame, a column per view).
    pub columns: Option<u32>,
    /// The PNG to write.
    pub out: PathBuf,
}

/// What was drawn.
#[derive(Debug, Clone, serde::Serialize)]
pub struct PreviewSummary {
    /// The PNG written.
    pub out: String,
    /// Tiles drawn (frames × views).
    pub tiles: usize,
    /// Image size, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// Points marked as inside a collider, over all tiles' frames.
    pub points_inside: usize,
    /// Segments marked as over-stretched, over all tiles' frames.
    pub stretched_segments: usize,
    /// Wall-clock time per tile (render only), ms.
    pub ms_per_tile: f64,
}

/// One frame's strands and meshes, ready to draw.
struct FrameData {
    label: String,
    positions: Vec<Vector3<f32>>,
    meshes: Vec<(TriMesh, Rgb)>,
    inside: Vec<bool>,
    stretched: Vec<bool>,
}

/// Draws the frames of `opts` and writes the PNG.
pub fn preview(opts: &PreviewOptions) -> Result<PreviewSummary, OutputError> {
    if opts.views.is_empty() {
        return Err(OutputError::request(
            "give at least one view (front, side, back, three-quarter)",
        ));
    }
    let mut source = match &opts.cache {
        Some(cache) => Source::Cache(Box::new(Shot::open(cache, None)?)),
        None => match &opts.scene {
            Some(path) => {
                let scene = SceneFile::load(path)?;
                Source::Rest(Box::new(scene.build()?))
            }
            None => return Err(OutputError::request(
                "give --cache (frames of a run) or --scene (its rest state): a preview of what?",
            )),
        },
    };
    let frames = match (&source, opts.frames.is_empty()) {
        (Source::Cache(shot), true) => {
            vec![shot.cached_frames().first().copied().unwrap_or(0) as f64]
        }
        (Source::Rest(sim), true) => vec![sim.first_frame as f64],
        (_, false) => opts.frames.clone(),
    };
    let mut data = Vec::with_capacity(frames.len());
    for &frame in &frames {
        data.push(source.frame_data(frame, opts)?);
    }
    let strands = source.strands();
    let mut bounds: Option<Bounds> = None;
    for d in &data {
        let points = d.positions.iter().copied().chain(
            d.meshes
                .iter()
                .flat_map(|(m, _)| m.positions().iter().copied()),
        );
        if let Some(b) = Bounds::of_points(points) {
            bounds = Some(bounds.map_or(b, |a| a.union(&b)));
        }
    }
    let settings = RenderSettings {
        width: opts.width,
        height: opts.height,
        ..RenderSettings::default()
    };
    let started = std::time::Instant::now();
    let mut images: Vec<(PreviewImage, String)> = Vec::new();
    for d in &data {
        let strands = Strands::new(&d.positions, strands.offsets())
            .and_then(|s| s.with_radii(strands.radii()))?;
        let meshes = d
            .meshes
            .iter()
            .enumerate()
            .map(|(i, (m, rgb))| Mesh::from_trimesh(i, m, *rgb))
            .collect::<Result<Vec<_>, _>>()?;
        let highlight = match opts.highlight {
            true => Highlight {
                points: Some(&d.inside),
                segments: Some(&d.stretched),
            },
            false => Highlight::default(),
        };
        let scene = Scene {
            strands: Some(strands),
            meshes,
            highlight,
        };
        for view in &opts.views {
            let image = render_view(&scene, *view, bounds.as_ref(), &settings).map_err(|e| {
                OutputError::View {
                    at: format!("{}, {view}", d.label),
                    source: e,
                }
            })?;
            images.push((image, format!("{}, {view}", d.label)));
        }
    }
    let ms_per_tile = started.elapsed().as_secs_f64() * 1e3 / images.len().max(1) as f64;
    let image = match images.len() {
        1 => images.pop().map(|(i, _)| i).expect("one image"),
        n => {
            let columns = opts.columns.unwrap_or(opts.views.len() as u32).max(1);
            let tiles: Vec<Tile> = images
                .iter()
                .map(|(image, label)| Tile { image, label })
                .collect();
            debug_assert_eq!(tiles.len(), n);
            contact_sheet(&tiles, columns)?
        }
    };
    image.write_png(&opts.out).map_err(|e| match e {
        PreviewError::Write { source, .. } => OutputError::write(&opts.out, source),
        other => OutputError::Preview(other),
    })?;
    Ok(PreviewSummary {
        out: opts.out.display().to_string(),
        tiles: data.len() * opts.views.len(),
        width: image.width(),
        height: image.height(),
        points_inside: data.iter().map(|d| count(&d.inside)).sum(),
        stretched_segments: data.iter().map(|d| count(&d.stretched)).sum(),
        ms_per_tile,
    })
}

fn count(flags: &[bool]) -> usize {
    flags.iter().filter(|&&f| f).count()
}

/// Positions at `frame` (fractional: a Hermite sub-frame sample), refusing frames outside the
/// cache by number.
fn positions_at(shot: &mut Shot, frame: f64) -> Result<Vec<Vector3<f32>>, OutputError> {
    let reader = shot.reader();
    let numbers = reader.frame_numbers();
    let (Some(&first), Some(&last)) = (numbers.first(), numbers.last()) else {
        return Err(OutputError::request("the cache holds no frame"));
    };
    if !(frame.is_finite() && frame >= first as f64 && frame <= last as f64) {
        return Err(OutputError::Request(format!(
            "frame {frame} is outside the cache (frames {first}–{last})"
        )));
    }
    if frame.fract() == 0.0 {
        return reader
            .read_frame(frame as u32)
            .map(|f| f.positions)
            .map_err(OutputError::from);
    }
    let fps = reader.header().fps;
    reader
        .sample(frame / fps, Interpolation::Hermite)
        .map(|s| s.positions)
        .map_err(OutputError::from)
}

/// What a preview draws from: a cache, or a scene's rest state.
enum Source {
    /// A cache, with its rig.
    Cache(Box<Shot>),
    /// A scene built for its rest state.
    Rest(Box<Simulation>),
}

impl Source {
    fn strands(&self) -> &StrandSet {
        match self {
            Source::Cache(shot) => shot.strands(),
            Source::Rest(sim) => &sim.strands,
        }
    }

    /// The strands at `frame` with the scalp and colliders there, and the highlight flags.
    fn frame_data(&mut self, frame: f64, opts: &PreviewOptions) -> Result<FrameData, OutputError> {
        let f = frame as f32;
        let (label, positions, scalp, shapes, colliders) = match self {
            Source::Cache(shot) => {
                let positions = positions_at(shot, frame)?;
                let scalp = shot.scalp_at(frame)?;
                let shapes = shot.collider_shapes_at(frame)?;
                let colliders = match opts.highlight {
                    true => Some(shot.colliders_at(frame, shot.scalp_collider())?),
                    false => None,
                };
                (
                    format!("frame {frame}"),
                    positions,
                    scalp,
                    shapes,
                    colliders,
                )
            }
            Source::Rest(sim) => {
                let shapes = sim
                    .colliders
                    .iter()
                    .map(|c| {
                        // A deforming collider is drawn at the frame's vertices.
                        let shape = match c.mesh_at(f) {
                            Some(mesh) => ColliderShape::Mesh(mesh),
                            None => c.collider.shape.clone(),
                        };
                        (shape, c.motion.at(f))
                    })
                    .collect();
                let colliders = match opts.highlight {
                    true => Some(
                        sim.colliders_at(f)
                            .map_err(|e| OutputError::Request(sim.collider_message(&e)))?,
                    ),
                    false => None,
                };
                let positions = sim.strands.positions.clone();
                (
                    "rest".to_string(),
                    positions,
                    sim.scalp_at(f),
                    shapes,
                    colliders,
                )
            }
        };
        draw_data(
            self.strands(),
            label,
            positions,
            scalp,
            &shapes,
            colliders.as_ref(),
            opts,
        )
    }
}

/// One frame ready to draw: the scalp and collider meshes, and with `colliders` the highlight
/// flags of `positions`.
fn draw_data(
    strands: &StrandSet,
    label: String,
    positions: Vec<Vector3<f32>>,
    scalp: Scalp,
    shapes: &[(ColliderShape, Isometry3<f32>)],
    colliders: Option<&Colliders>,
    opts: &PreviewOptions,
) -> Result<FrameData, OutputError> {
    let mut meshes = Vec::new();
    if let Some(mesh) = scalp.mesh {
        meshes.push((mesh, SCALP_RGB));
    }
    for (shape, pose) in shapes {
        meshes.push((collider_mesh(shape, pose)?, COLLIDER_RGB));
    }
    let (inside, stretched) = match colliders {
        Some(colliders) => {
            let inside = hair_core::quality::inside_flags(
                colliders,
                &positions,
                strands.radii(),
                strands.inverse_masses(),
                hair_core::QualityOptions::default().contact_tolerance,
            );
            let stretched = stretched_flags(strands, &positions, opts.stretch_limit);
            (inside, stretched)
        }
        None => (Vec::new(), Vec::new()),
    };
    Ok(FrameData {
        label,
        positions,
        meshes,
        inside,
        stretched,
    })
}

/// Per segment (numbered as `StrandSet::segments`): longer than `(1 + limit) ×` its rest length?
fn stretched_flags(strands: &StrandSet, positions: &[Vector3<f32>], limit: f32) -> Vec<bool> {
    let rest = strands.rest_lengths();
    let mut flags = Vec::with_capacity(rest.len());
    for s in 0..strands.len() {
        let p = strands.points(s);
        for (j, seg) in strands.segments(s).enumerate() {
            let len = (positions[p.start + j + 1] - positions[p.start + j]).norm();
            flags.push(len > (1.0 + limit) * rest[seg]);
        }
    }
    flags
}

/// A triangle mesh of an analytic collider (or the collider's own mesh), placed at `pose`.
fn collider_mesh(shape: &ColliderShape, pose: &Isometry3<f32>) -> Result<TriMesh, OutputError> {
    let mesh = match shape {
        ColliderShape::Sphere { radius } => TriMesh::uv_sphere(*radius, 32, 16)?,
        ColliderShape::Capsule {
            half_height,
            radius,
        } => {
            // A sphere split at its equator, the halves moved apart along z.
            let sphere = TriMesh::uv_sphere(*radius, 32, 16)?;
            let moved: Vec<Vector3<f32>> = sphere
                .positions()
                .iter()
                .map(|v| v + Vector3::z() * half_height.copysign(v.z))
                .collect();
            let mut capsule = sphere.clone();
            capsule.set_positions(&moved)?;
            capsule
        }
        ColliderShape::Mesh(mesh) => mesh.clone(),
    };
    Ok(mesh.transformed(pose))
}

/// The PNG path's folder exists? (A clear error before any work.)
pub fn check_output(out: &Path) -> Result<(), OutputError> {
    match out.parent() {
        Some(dir) if !dir.as_os_str().is_empty() && !dir.is_dir() => {
            Err(OutputError::Request(format!(
                "{}: the folder {} does not exist",
                out.display(),
                dir.display()
            )))
        }
        _ => Ok(()),
    }
}
