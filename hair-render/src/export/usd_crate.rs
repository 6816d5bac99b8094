//! Render children as a binary USD crate file (`.usdc`), through the same layer writer as every
//! hairsys USD export ([`hair_groom::formats::usd_write`]): the stage and attributes of
//! [`super::usd`]'s `.usda` (one linear `BasisCurves` prim, Z up, meters, `points` or their
//! motion time samples, `velocities`, `widths` per vertex, `extent`, `primvars:st`,
//! `primvars:displayColor`, `primvars:random`, `primvars:parent`), in the binary encoding that
//! imports in a fraction of the text's time. `.usda` stays with [`super::usd::write_usda`]
//! (shortest round-trip floats in one buffered pass).

use std::path::Path;

use hair_groom::formats::obj::UpAxis;
use hair_groom::formats::usd_write::{
    Samples, UsdCurvesPrim, UsdLayer, UsdStageInfo, UsdWriteError,
};

use super::usd::{check_export, Motion, UsdOptions};
use crate::buffers::ChildBuffers;
use crate::error::{RenderError, Result};

/// Writes `children` to the `.usdc` file at `path` (through a `.partial` sibling renamed into
/// place), with `motion` blur; refuses what [`super::usd::write_usda`] refuses.
pub fn export_usdc(
    path: &Path,
    children: &ChildBuffers,
    motion: &Motion,
    opts: &UsdOptions,
) -> Result<()> {
    check_export(children, motion, opts)?;
    let (start, end) = match motion {
        Motion::TimeSamples(s) => (s[0].time_code, s[s.len() - 1].time_code),
        _ => (opts.time_code, opts.time_code),
    };
    let mut layer = UsdLayer::new(&UsdStageInfo {
        up_axis: UpAxis::Z,
        meters_per_unit: 1.0,
        time_codes_per_second: Some(opts.frames_per_second),
        time_range: Some((start, end)),
    });
    let points = match motion {
        // The frame's points as the default too, as the `.usda` writer does.
        Motion::TimeSamples(s) => Samples::DefaultAndTimes(
            children.points.clone(),
            s.iter()
                .map(|m| (m.time_code, m.children.points.clone()))
                .collect(),
        ),
        _ => Samples::Default(children.points.clone()),
    };
    let velocities = match motion {
        Motion::Velocities(v) => Some(Samples::Default(v.to_vec())),
        _ => None,
    };
    layer.add_curves(&UsdCurvesPrim {
        name: &opts.prim,
        vertex_counts: children.vertex_counts.iter().map(|&c| c as i32).collect(),
        points,
        widths: Some(Samples::Default(children.widths.clone())),
        velocities,
        root_uv: children.root_uv.clone(),
        colors: children.color.clone(),
        extent: true,
        uniform_floats: vec![("random", children.random.clone())],
        uniform_ints: vec![(
            "parent",
            children.parent.iter().map(|&p| p as i32).collect(),
        )],
    });
    layer.set_default_prim(&opts.prim);
    layer.write(path).map_err(|e| match e {
        UsdWriteError::Io(source) => RenderError::Write {
            path: path.to_path_buf(),
            source,
        },
        UsdWriteError::Encode(m) => RenderError::Write {
            path: path.to_path_buf(),
            source: std::io::Error::other(m),
        },
    })
}
