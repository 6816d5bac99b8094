//! A whole cached run as ONE animated USD file (`hairsys cache export`, and `hairsys
//! render-children export --frames A-B`).
//!
//! The curves are one linear `BasisCurves` prim: `/hair`, the simulated strands, or with
//! [`ShotOptions::children`] `/children`, render children generated at every time code from the
//! cache's parents (the scene's `[children]` section with the command's overrides, the same
//! generation as `render-children export`). `points`, `velocities` and `extent` carry one time
//! sample per time code; `widths` (`vertex`), the per-curve `primvars:id` (strand or child index),
//! the root UV (`primvars:surface_uv_coordinate` and `primvars:st`) and `primvars:displayColor`
//! (the scalp's vertex colours at the root) are written once. The scalp mesh is the sibling
//! `Mesh` prim `/scalp`: with time-sampled `points` when it moves or deforms (as the cache's rig
//! recorded it, [`Shot::scalp_at`]), else one static value. Everything comes from the cache
//! ([`Shot`]): the scene's mesh files are not read.
//!
//! Time codes are frame numbers plus [`ShotOptions::time_offset`] (`timeCodesPerSecond` = the
//! cache's fps; `startTimeCode` and `endTimeCode` = the first and last time code written): a
//! scene simulated over frames 1–48 for a shot that starts at 1001 is exported with an offset of
//! 1000 and lands on time codes 1001–1048 (`--time-offset 1000`). The offset is whole frames
//! or not; it moves the time codes only, never which cached frames are read. With a shutter ([`Shutter`]), each frame
//! gets its sub-frame samples at fractional time codes, `frame + offset`, positions and
//! velocities taken from the cache's cubic Hermite interpolation
//! ([`hair_cache::CacheReader::sample`]); samples outside the cached frames are left out (the
//! cache holds nothing there to interpolate), and coinciding samples of neighbouring frames are
//! written once. Strand velocities are the cache's; children velocities are the central
//! difference of the children at the neighbouring time codes (one-sided at the ends).
//!
//! Because time codes are absolute frame numbers and the prim paths never change, the files of
//! `--frames 1-60` and `--frames 61-120` are two value clips of one shot: a small stage with
//! `clips` metadata on `/hair` and `/scalp` stitches them (`docs/usd.md`).
//!
//! `.usdc` (binary) or `.usda` (text) by the output's extension, written through
//! [`hair_groom::formats::usd_write`]. Frames are read one at a time from the cache; the layer
//! holds every time sample in memory until it is written (points + velocities: 24 bytes per
//! point per sample), which [`crate::budget::Budget`] bounds for children.

use super::OutputError;
use std::path::{Path, PathBuf};

use hair_cache::{Interpolation, Shutter};
use hair_core::{Anchor, TriMesh};
use hair_groom::formats::obj::UpAxis;
use hair_groom::formats::usd_write::{
    Samples, UsdCurvesPrim, UsdEncoding, UsdLayer, UsdMeshPrim, UsdStageInfo,
};
use hair_render::buffers::ChildBuffers;
use hair_render::export::usd::curves_prim;
use nalgebra::Vector3;

use crate::budget::Budget;
use crate::output::children::{check_children_memory, child_settings, children_of, ChildOverrides};
use crate::output::shot::Shot;
use crate::scene::maps::ChildMapFactors;

/// Render children instead of the simulated strands.
#[derive(Debug, Clone, Copy, Default)]
pub struct ShotChildren {
    /// Child settings overriding the scene's `[children]` section.
    pub overrides: ChildOverrides,
    /// The section's display level of detail instead of render.
    pub display: bool,
}

/// What [`export_shot`] writes.
#[derive(Debug, Clone, Default)]
pub struct ShotOptions {
    /// Frames to write, inclusive; `None`: every cached frame.
    pub frames: Option<(u32, u32)>,
    /// Sub-frame samples around each frame (frames relative to it); `None`: the frames only.
    pub shutter: Option<Shutter>,
    /// Render children instead of the simulated strands.
    pub children: Option<ShotChildren>,
    /// Scene file whose `[children]` settings apply instead of those of the scene stored in
    /// the cache.
    pub scene: Option<PathBuf>,
    /// Memory limit on the children held until written (children × points × samples).
    pub budget: Budget,
    /// Added to every time code written (frames; finite): frame `f` is written at `f +
    /// time_offset`. 0 writes scene frames as they are.
    pub time_offset: f64,
    /// The frames of the whole export this file is a chunk of (a value clip; `None`: the file
    /// stands alone). Children velocities at the chunk's first and last time codes take their
    /// neighbours from the whole export's time codes, and whether `/scalp` is animated is decided
    /// over the whole export, so the chunk holds exactly the whole export's values.
    pub context: Option<(u32, u32)>,
}

/// What [`export_shot`] wrote.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ShotSummary {
    /// First and last frame written.
    pub frames: (u32, u32),
    /// Frames written.
    pub frame_count: usize,
    /// Time samples per animated attribute (frames, plus sub-frame samples with a shutter).
    pub time_samples: usize,
    /// Sub-frame samples left out because they lie outside the cached frames, as scene frames
    /// (before the time offset).
    pub dropped_samples: Vec<f64>,
    /// First and last time code written (the frames plus the time offset).
    pub time_codes: (f64, f64),
    /// Path of the curves prim (`/hair` or `/children`).
    pub prim: String,
    /// Curves in the file.
    pub curves: usize,
    /// Points per time sample.
    pub points: usize,
    /// `None` without a scalp mesh; `Some(true)` when `/scalp` is animated, `Some(false)` static.
    pub scalp_animated: Option<bool>,
    /// Size of the file written, bytes.
    pub bytes: u64,
}

/// Writes `cache` (the frames and samples `opts` asks for) to `out` as one animated USD file
/// (see the module docs). Errors name the file, the option and the fix.
pub fn export_shot(
    cache: &Path,
    out: &Path,
    opts: &ShotOptions,
) -> Result<ShotSummary, OutputError> {
    if UsdEncoding::of(out).is_none() {
        return Err(OutputError::Request(format!(
            "{}: the output's extension names no USD format; use .usdc (binary) or .usda (text)",
            out.display()
        )));
    }
    let mut shot = Shot::open(cache, opts.scene.as_deref())?;
    let fps = shot.fps();
    let cached = shot.cached_frames().to_vec();
    let chosen: Vec<u32> = cached
        .iter()
        .copied()
        .filter(|f| opts.frames.is_none_or(|(a, b)| (a..=b).contains(f)))
        .collect();
    let (Some(&first), Some(&last)) = (chosen.first(), chosen.last()) else {
        let have = match (cached.first(), cached.last()) {
            (Some(a), Some(b)) => format!("it holds frames {a}-{b}"),
            _ => "it holds no frame".to_string(),
        };
        return Err(OutputError::Request(format!(
            "{}: no cached frame in the range asked for; {have}",
            cache.display()
        )));
    };
    let (lo, hi) = (f64::from(cached[0]), f64::from(cached[cached.len() - 1]));
    if !opts.time_offset.is_finite() {
        return Err(OutputError::Request(format!(
            "time offset {}: give a finite number of frames, e.g. 1000 for a shot starting at \
             frame 1001",
            opts.time_offset
        )));
    }
    let (times, dropped) = time_codes(&chosen, opts.shutter.as_ref(), (lo, hi));
    // The whole export's time codes, when this file is a chunk of one.
    let whole: Vec<f64> = match opts.context {
        Some((a, b)) => {
            let frames: Vec<u32> = cached
                .iter()
                .copied()
                .filter(|f| (a..=b).contains(f))
                .collect();
            time_codes(&frames, opts.shutter.as_ref(), (lo, hi)).0
        }
        None => times.clone(),
    };
    let time_range = (
        times[0] + opts.time_offset,
        times[times.len() - 1] + opts.time_offset,
    );
    let stage = UsdStageInfo {
        up_axis: UpAxis::Z,
        meters_per_unit: 1.0,
        time_codes_per_second: Some(fps),
        time_range: Some(time_range),
    };
    let mut layer = UsdLayer::new(&stage);
    let offset = opts.time_offset;
    let (prim, curves, points) = match &opts.children {
        Some(request) => {
            let (curves, points) =
                add_children(&mut layer, &mut shot, request, &times, &whole, opts)?;
            ("children", curves, points)
        }
        None => {
            let (curves, points) = add_strands(&mut layer, &mut shot, &times, offset)?;
            ("hair", curves, points)
        }
    };
    layer.set_default_prim(prim);
    let scalp_animated = add_scalp(&mut layer, &mut shot, &times, &whole, offset)?;
    layer.write(out).map_err(|e| OutputError::write(out, e))?;
    let bytes = std::fs::metadata(out).map(|m| m.len()).unwrap_or(0);
    Ok(ShotSummary {
        frames: (first, last),
        frame_count: chosen.len(),
        time_samples: times.len(),
        dropped_samples: dropped,
        time_codes: time_range,
        prim: format!("/{prim}"),
        curves,
        points,
        scalp_animated,
        bytes,
    })
}

/// The time codes of `frames` with `shutter`'s offsets around each (just the frames without
/// one), in increasing order, each once, inside `cached` (first and last cached frame); and the
/// samples left out because they lie outside it.
pub(crate) fn time_codes(
    frames: &[u32],
    shutter: Option<&Shutter>,
    (lo, hi): (f64, f64),
) -> (Vec<f64>, Vec<f64>) {
    let offsets = shutter.map_or_else(|| vec![0.0], Shutter::offsets);
    let mut times = Vec::with_capacity(frames.len() * offsets.len());
    let mut dropped = Vec::new();
    for &f in frames {
        for o in &offsets {
            let t = f64::from(f) + o;
            if !(lo..=hi).contains(&t) {
                dropped.push(t);
            } else if times.last().is_none_or(|&prev| t > prev) {
                times.push(t);
            }
        }
    }
    (times, dropped)
}

/// The simulated strands as `/hair`; returns (curves, points).
fn add_strands(
    layer: &mut UsdLayer,
    shot: &mut Shot,
    times: &[f64],
    offset: f64,
) -> Result<(usize, usize), OutputError> {
    let fps = shot.fps();
    let layout = shot.reader().layout().clone();
    let mut points = Vec::with_capacity(times.len());
    let mut velocities = Vec::with_capacity(times.len());
    for &t in times {
        let s = shot.reader().sample(t / fps, Interpolation::Hermite)?;
        points.push((t + offset, flat(&s.positions)));
        velocities.push((t + offset, flat(&s.velocities)));
    }
    let counts: Vec<i32> = layout
        .offsets
        .windows(2)
        .map(|w| (w[1] - w[0]) as i32)
        .collect();
    let curves = counts.len();
    let (root_uv, colors) = root_attributes(shot);
    layer.add_curves(UsdCurvesPrim {
        name: "hair",
        vertex_counts: counts,
        points: Samples::Times(points),
        widths: Some(Samples::Default(
            layout.radii.iter().map(|r| 2.0 * r).collect(),
        )),
        velocities: Some(Samples::Times(velocities)),
        root_uv,
        colors,
        extent: true,
        uniform_floats: Vec::new(),
        uniform_ints: vec![("id", (0..curves as i32).collect())],
    });
    Ok((curves, layout.radii.len()))
}

/// Root UV (u, v) and colour (r, g, b) per strand, flat, from the rest scalp at the strands'
/// surface anchors; `None` where the scalp has no UVs or colours, or a strand is not anchored
/// on it.
fn root_attributes(shot: &Shot) -> (Option<Vec<f32>>, Option<Vec<f32>>) {
    let Some(scalp) = &shot.rig().scalp else {
        return (None, None);
    };
    let mesh = &scalp.mesh;
    let anchors = &shot.rig().anchors;
    let samples: Option<Vec<_>> = anchors
        .iter()
        .map(|a| match a {
            Anchor::Surface(s) => mesh.triangles().get(s.triangle as usize).map(|t| (t, s)),
            Anchor::Body(_) => None,
        })
        .collect();
    let Some(samples) = samples else {
        return (None, None);
    };
    let blend = |values: &dyn Fn(u32) -> Vec<f32>, arity: usize| -> Vec<f32> {
        let mut out = Vec::with_capacity(samples.len() * arity);
        for (tri, s) in &samples {
            let mut v = vec![0.0f32; arity];
            for (corner, w) in tri.iter().zip(s.weights) {
                for (acc, x) in v.iter_mut().zip(values(*corner)) {
                    *acc += w * x;
                }
            }
            out.extend(v);
        }
        out
    };
    let uv = mesh.uvs().map(|uvs| {
        blend(
            &|i| {
                let t = uvs[i as usize];
                vec![t.x, t.y]
            },
            2,
        )
    });
    let colors = scalp
        .colors
        .as_ref()
        .map(|c| blend(&|i| c[i as usize].to_vec(), 3));
    (uv, colors)
}

/// Render children at every time code as `/children`; returns (curves, points per sample).
/// `whole` holds the time codes of the whole export `times` is a chunk of (or `times` itself):
/// the children at its time codes just before and after `times` are generated too, for the
/// central-difference velocities at the chunk's ends, and not written.
fn add_children(
    layer: &mut UsdLayer,
    shot: &mut Shot,
    request: &ShotChildren,
    times: &[f64],
    whole: &[f64],
    opts: &ShotOptions,
) -> Result<(usize, usize), OutputError> {
    let fps = shot.fps();
    let (settings, lod) = child_settings(shot.scene(), &request.overrides, request.display)?;
    check_children_memory(&opts.budget, shot.strands(), &settings, times.len())?;
    let maps = ChildMapFactors {
        clump: shot.rig().clump.clone(),
        curl: shot.rig().curl.clone(),
    };
    let before = whole.iter().rev().find(|&&t| t < times[0]).copied();
    let after = whole.iter().find(|&&t| t > times[times.len() - 1]).copied();
    let generated: Vec<f64> = before
        .into_iter()
        .chain(times.iter().copied())
        .chain(after)
        .collect();
    let mut first: Option<ChildBuffers> = None;
    let mut points = Vec::with_capacity(generated.len());
    for &t in &generated {
        let s = shot.reader().sample(t / fps, Interpolation::Hermite)?;
        let scalp = shot.scalp_at(t)?;
        let colors = shot.rig().scalp.as_ref().and_then(|s| s.colors.as_deref());
        let children = children_of(
            shot.strands(),
            &s.positions,
            &scalp,
            colors,
            &maps,
            &settings,
            lod,
        )?;
        if let Some(c) = &first {
            // Compares the curves' point counts only: `first` has given up its points.
            c.check_same_topology(&children)
                .map_err(|e| OutputError::Request(format!("children at time code {t}: {e}")))?;
        }
        let (frame_points, rest) = take_points(children);
        points.push((t + opts.time_offset, frame_points));
        // The first time code's curves (less their points) carry the topology and per-curve
        // data, which every time code shares (checked above).
        first.get_or_insert(rest);
    }
    let first = first.ok_or_else(|| OutputError::request("no time code to export"))?;
    let sizes = (first.curve_count(), points[0].1.len() / 3);
    let mut velocities = central_differences(&points, fps);
    // The neighbours were generated for the velocities only.
    let skip = usize::from(before.is_some());
    let keep = skip..skip + times.len();
    let mut points: Vec<_> = points.drain(keep.clone()).collect();
    velocities = velocities.drain(keep).collect();
    points.shrink_to_fit();
    layer.add_curves(curves_prim(
        "children",
        first,
        Samples::Times(points),
        Some(Samples::Times(velocities)),
    ));
    Ok(sizes)
}

/// `children` split into its points and the rest (topology and per-curve data, no points).
fn take_points(mut children: ChildBuffers) -> (Vec<f32>, ChildBuffers) {
    (std::mem::take(&mut children.points), children)
}

/// Velocities (units per second) of the sampled `points` by central differences of the
/// neighbouring samples (one-sided at the ends; zero for a single sample). Time codes are
/// frames at `fps` frames per second.
fn central_differences(points: &[(f64, Vec<f32>)], fps: f64) -> Vec<(f64, Vec<f32>)> {
    let n = points.len();
    (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(1), (i + 1).min(n - 1));
            let (t, p) = &points[i];
            if a == b {
                return (*t, vec![0.0; p.len()]);
            }
            let inv = (fps / (points[b].0 - points[a].0)) as f32;
            let v = points[a]
                .1
                .iter()
                .zip(&points[b].1)
                .map(|(x0, x1)| (x1 - x0) * inv)
                .collect();
            (*t, v)
        })
        .collect()
}

/// The scalp mesh as `/scalp`, animated when it moves over `whole` (the time codes of the
/// whole export `times` is a chunk of, or `times` itself), with samples at `times` (scene
/// frames, written at `offset` time codes later); returns whether it is animated, `None` without
/// a scalp mesh.
fn add_scalp(
    layer: &mut UsdLayer,
    shot: &mut Shot,
    times: &[f64],
    whole: &[f64],
    offset: f64,
) -> Result<Option<bool>, OutputError> {
    let Some(rest) = shot.rest_scalp().cloned() else {
        return Ok(None);
    };
    let tris = rest.triangles();
    let mut frames: Vec<(f64, Vec<f32>)> = Vec::with_capacity(times.len());
    for &t in times {
        let scalp = shot.scalp_at(t)?;
        let mesh: Option<TriMesh> = scalp.mesh;
        if let Some(mesh) = mesh {
            frames.push((t + offset, flat(mesh.positions())));
        }
    }
    let mut moves = frames.windows(2).any(|w| w[0].1 != w[1].1);
    if !moves && whole.len() > times.len() {
        moves = scalp_moves(shot, whole)?;
    }
    let points = if moves {
        Samples::Times(frames)
    } else {
        Samples::Default(
            frames
                .into_iter()
                .next()
                .map_or_else(|| flat(rest.positions()), |(_, p)| p),
        )
    };
    layer.add_mesh(UsdMeshPrim {
        name: "scalp",
        face_vertex_counts: vec![3; tris.len()],
        face_vertex_indices: tris.iter().flatten().map(|&i| i as i32).collect(),
        points,
        uv: rest
            .uvs()
            .map(|uv| uv.iter().flat_map(|t| [t.x, t.y]).collect()),
        colors: None,
    });
    Ok(Some(moves))
}

/// Whether the scalp's points differ between any two neighbouring time codes of `times`.
fn scalp_moves(shot: &mut Shot, times: &[f64]) -> Result<bool, OutputError> {
    let mut previous: Option<Vec<f32>> = None;
    for &t in times {
        let Some(mesh) = shot.scalp_at(t)?.mesh else {
            continue;
        };
        let points = flat(mesh.positions());
        if previous.as_ref().is_some_and(|p| *p != points) {
            return Ok(true);
        }
        previous = Some(points);
    }
    Ok(false)
}

/// Flat x, y, z of `points`.
fn flat(points: &[Vector3<f32>]) -> Vec<f32> {
    points.iter().flat_map(|p| [p.x, p.y, p.z]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shutter_samples_of_neighbouring_frames_are_written_once_and_kept_inside_the_cache() {
        let shutter = Shutter::new(-0.5, 0.5, 3).unwrap();
        let (times, dropped) = time_codes(&[1, 2, 3], Some(&shutter), (1.0, 3.0));
        assert_eq!(times, vec![1.0, 1.5, 2.0, 2.5, 3.0]);
        assert_eq!(dropped, vec![0.5, 3.5]);
        let (times, dropped) = time_codes(&[4, 5], None, (1.0, 9.0));
        assert_eq!((times, dropped), (vec![4.0, 5.0], vec![]));
    }

    #[test]
    fn central_differences_are_exact_for_linear_motion() {
        // x = 0.1 m per frame at 24 fps: 2.4 m/s everywhere, ends included.
        let points: Vec<(f64, Vec<f32>)> = [1.0, 1.25, 2.0, 3.0]
            .iter()
            .map(|&t| (t, vec![0.1 * t as f32, 0.0, 1.0]))
            .collect();
        for (_, v) in central_differences(&points, 24.0) {
            assert!(
                (v[0] - 2.4).abs() < 1e-5 && v[1] == 0.0 && v[2] == 0.0,
                "{v:?}"
            );
        }
    }
}
