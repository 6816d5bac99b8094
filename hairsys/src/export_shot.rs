//! A whole cached run as ONE animated USD file (`hairsys cache export`): the simulated strands as
//! a linear `BasisCurves` prim `/hair` whose `points`, `velocities` and `extent` carry one time
//! sample per cached frame (time code = frame number, `timeCodesPerSecond` = the cache's fps,
//! `startTimeCode`/`endTimeCode` = the frames written), `widths` (twice the cached point radii,
//! `vertex` interpolation), and the scene's scalp mesh at rest as a sibling `Mesh` prim
//! `/scalp` (with its UVs and vertex colours when the scene has them). Z up, meters.
//!
//! `.usdc` (binary) or `.usda` (text) by the output's extension, written through
//! [`hair_groom::formats::usd_write`]. Frames are read one at a time from the cache; the layer
//! holds every exported frame in memory until it is written (points + velocities: 24 bytes per
//! point per frame).

use std::path::Path;

use hair_cache::CacheReader;
use hair_groom::formats::obj::UpAxis;
use hair_groom::formats::usd_write::{
    Samples, UsdCurvesPrim, UsdEncoding, UsdLayer, UsdMeshPrim, UsdStageInfo,
};

use crate::scene::SceneFile;

/// What [`export_shot`] wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct ShotSummary {
    /// First and last frame written.
    pub frames: (u32, u32),
    /// Number of frames written (time samples per attribute).
    pub frame_count: usize,
    /// Strands (curves) in the file.
    pub strands: usize,
    /// Points per frame.
    pub points: usize,
    /// True when the scalp mesh was written as `/scalp`.
    pub scalp: bool,
    /// Size of the file written, bytes.
    pub bytes: u64,
}

/// Writes the frames of `cache` within `frames` (inclusive; `None`: every cached frame) to
/// `out` as one animated USD file (see the module docs). Errors name the file and the fix.
pub fn export_shot(
    cache: &Path,
    out: &Path,
    frames: Option<(u32, u32)>,
) -> Result<ShotSummary, String> {
    if UsdEncoding::of(out).is_none() {
        return Err(format!(
            "{}: the output's extension names no USD format; use .usdc (binary) or .usda (text)",
            out.display()
        ));
    }
    let mut reader = CacheReader::open(cache).map_err(|e| e.to_string())?;
    let header = reader.header().clone();
    let layout = reader.layout().clone();
    let cached = reader.frame_numbers().to_vec();
    let chosen: Vec<u32> = cached
        .iter()
        .copied()
        .filter(|f| frames.is_none_or(|(a, b)| (a..=b).contains(f)))
        .collect();
    let (Some(&first), Some(&last)) = (chosen.first(), chosen.last()) else {
        let have = match (cached.first(), cached.last()) {
            (Some(a), Some(b)) => format!("it holds frames {a}-{b}"),
            _ => "it holds no frame".to_string(),
        };
        return Err(format!(
            "{}: no cached frame in the range asked for; {have}",
            cache.display()
        ));
    };
    let flat = |v: &[nalgebra::Vector3<f32>]| -> Vec<f32> {
        v.iter().flat_map(|p| [p.x, p.y, p.z]).collect()
    };
    let mut points = Vec::with_capacity(chosen.len());
    let mut velocities = Vec::with_capacity(chosen.len());
    for &f in &chosen {
        let frame = reader.read_frame(f).map_err(|e| e.to_string())?;
        points.push((f64::from(f), flat(&frame.positions)));
        velocities.push((f64::from(f), flat(&frame.velocities)));
    }
    let counts: Vec<i32> = layout
        .offsets
        .windows(2)
        .map(|w| (w[1] - w[0]) as i32)
        .collect();
    let mut layer = UsdLayer::new(&UsdStageInfo {
        up_axis: UpAxis::Z,
        meters_per_unit: 1.0,
        time_codes_per_second: Some(header.fps),
        time_range: Some((f64::from(first), f64::from(last))),
    });
    let point_count = layout.radii.len();
    layer.add_curves(&UsdCurvesPrim {
        name: "hair",
        vertex_counts: counts,
        points: Samples::Times(points),
        widths: Some(Samples::Default(
            layout.radii.iter().map(|r| 2.0 * r).collect(),
        )),
        velocities: Some(Samples::Times(velocities)),
        root_uv: None,
        colors: None,
        extent: true,
        uniform_floats: Vec::new(),
        uniform_ints: Vec::new(),
    });
    layer.set_default_prim("hair");
    let scalp = scalp_mesh(cache, &header.scene_toml);
    if let Some(m) = &scalp {
        layer.add_mesh(m);
    }
    layer
        .write(out)
        .map_err(|e| format!("cannot write {}: {e}", out.display()))?;
    let bytes = std::fs::metadata(out).map(|m| m.len()).unwrap_or(0);
    Ok(ShotSummary {
        frames: (first, last),
        frame_count: chosen.len(),
        strands: layout.offsets.len().saturating_sub(1),
        points: point_count,
        scalp: scalp.is_some(),
        bytes,
    })
}

/// The rest scalp of the scene stored in the cache, as a `Mesh` prim; `None` when the scene has
/// no scalp mesh or cannot be rebuilt (e.g. its OBJ moved).
fn scalp_mesh(cache: &Path, scene_toml: &str) -> Option<UsdMeshPrim<'static>> {
    let base = cache.parent().map(Path::to_path_buf).unwrap_or_default();
    let origin = format!("{} (scene stored in the cache)", cache.display());
    let sim = SceneFile::parse(scene_toml, &origin, base)
        .ok()?
        .build()
        .ok()?;
    let mesh = sim.rest_mesh()?;
    let tris = mesh.triangles();
    Some(UsdMeshPrim {
        name: "scalp",
        face_vertex_counts: vec![3; tris.len()],
        face_vertex_indices: tris.iter().flatten().map(|&i| i as i32).collect(),
        points: Samples::Default(
            mesh.positions()
                .iter()
                .flat_map(|p| [p.x, p.y, p.z])
                .collect(),
        ),
        uv: mesh
            .uvs()
            .map(|uv| uv.iter().flat_map(|t| [t.x, t.y]).collect()),
        colors: None,
    })
}
