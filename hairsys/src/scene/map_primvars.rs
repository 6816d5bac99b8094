//! `[maps.NAME] primvar = "…"`: a painted map read from a primvar of the USD scalp's `Mesh`
//! prim, the way a DCC hands over its paint: Blender's USD export writes a vertex
//! group or a float attribute `density` as `float[] primvars:density` (`interpolation =
//! "vertex"`), Houdini and Maya write point or vertex attributes the same way.
//!
//! ```toml
//! [scalp.mesh]
//! kind = "usd"
//! path = "head.usdc"
//! prim = "/head/scalp"
//!
//! [maps.stiffness]
//! primvar = "stiff"          # primvars:stiff on /head/scalp
//!
//! [maps.goal]
//! primvar = "displayColor"   # one channel of a color3f/float3 primvar
//! channel = "g"
//! ```
//!
//! **Time samples.** A map is read once, when the scene is built, at the time code of the
//! scene's first frame (its default value when it has no time samples; USD holds the first or
//! last sample outside them and interpolates between them). What a time-sampled primvar means
//! depends on the map's purpose:
//!
//! - `density`, `length`, `clump`, `curl` and maps that select hair (pins, hold-out, regions,
//!   the `[guides.sim_weight]` selection) shape the groom: where hair grows, how long it is, its
//!   children, which hair a setting applies to. The groom is built once, so they take the
//!   first frame's values and the later samples are not used (a primvar keyed over a shot grows
//!   the hair of its first frame).
//! - `goal`, `stiffness` and `sim_weight` are dynamics an animator would expect to follow the
//!   keys over a shot. The solver takes each strand's goal weights and stiffness when it is
//!   built (varying them per frame would mean rebuilding its per-strand lanes every frame), so
//!   a primvar of one of these whose samples differ is **refused**, naming the primvar, the
//!   prim, the file, its sample times and the frame rule, with the ways hairsys does animate
//!   them (`Session::params_mut` for the goal and bend stiffness, `[[regions]]` with
//!   `Session::set_region_params`, `[guides.sim_weight]` keys and
//!   `Session::set_strand_sim_weights`). Samples that are all equal are read as one value.
//!
//! The primvar is read by [`hair_groom::UsdMeshSource::primvar`], which follows USD's
//! interpolations (`constant`, `uniform`, `vertex`, `varying`, `faceVarying`, indexed or not)
//! to one value at each corner of each scalp triangle; each root then takes the blend of its
//! triangle's three corner values by its barycentric weights ([`crate::rig::maps`]). Only a USD
//! scalp has primvars: a primvar map on any other scalp is refused, naming the scalp and what
//! to use instead.

use std::path::PathBuf;

use crate::rig::maps::Channel;

use super::{ScalpMesh, SceneFile};

/// Map purposes that would vary over a shot, so a time-sampled primvar of one is refused
/// rather than read at the first frame only, each with the ways hairsys does animate it.
#[cfg(feature = "usd")]
const FOLLOWS_THE_SHOT: [(&str, &str); 3] = [
    (
        "goal",
        "animate the goal springs' strength instead (a host sets \
         Session::params_mut().goal_stiffness each frame)",
    ),
    (
        "stiffness",
        "animate the stiffness instead ([[regions]] with Session::set_region_params each \
         frame, or Session::params_mut().bend_stiffness)",
    ),
    (
        "sim_weight",
        "key [guides.sim_weight] instead, or set each hair's factor every frame with \
         Session::set_strand_sim_weights",
    ),
];

/// The primvar `name` (its `channel` if given) of the scene's USD scalp at the scene's first
/// frame, as values at the corners of every scalp triangle, for the map `[maps.MAP]` (see the
/// module docs: a time-sampled primvar whose values change is refused for a map that would
/// follow the shot). Errors name the scalp file, the prim, the primvar and the fix.
pub fn scalp_primvar(
    scene: &SceneFile,
    map: &str,
    name: &str,
    channel: Option<Channel>,
) -> Result<Vec<[f32; 3]>, PrimvarError> {
    let section = match &scene.scene.scalp.mesh {
        ScalpMesh::Usd(section) => section,
        ScalpMesh::Obj { path, .. } => {
            return Err(PrimvarError::ObjScalp {
                path: scene.base_dir.join(path),
            })
        }
        other => {
            let kind = match other {
                ScalpMesh::None => "none",
                ScalpMesh::BuiltinHead => "builtin-head",
                ScalpMesh::UvSphere { .. } => "uv-sphere",
                _ => "obj-sequence",
            };
            return Err(PrimvarError::NotUsd { kind });
        }
    };
    let path = scene.base_dir.join(&section.path);
    #[cfg(not(feature = "usd"))]
    {
        let _ = (map, name, channel);
        Err(hair_groom::GroomError::usd_not_built(&path).into())
    }
    #[cfg(feature = "usd")]
    {
        let source = hair_groom::UsdMeshSource::open(&path, &section.options())?;
        let component = channel.map(|c| match c {
            Channel::R => 0,
            Channel::G => 1,
            Channel::B => 2,
            Channel::A => 3,
        });
        let first_frame = scene.scene.scene.frames[0];
        let time = section.time_code(f64::from(first_frame));
        let read = |t: f64| {
            source
                .primvar(name, component, t)
                .map(|corners| corners.values)
        };
        let values = read(time)?;
        if let Some((_, instead)) = FOLLOWS_THE_SHOT.iter().find(|(m, _)| *m == map) {
            let times = source.primvar_sample_times(name)?;
            for &t in times.iter().skip(usize::from(times.len() == 1)) {
                if read(t)? != values {
                    let name = name.strip_prefix("primvars:").unwrap_or(name);
                    return Err(PrimvarError::Changes(Box::new(PrimvarChanges {
                        primvar: name.to_string(),
                        prim: source.prim().to_string(),
                        path,
                        samples: times.len(),
                        range: (times[0], times[times.len() - 1]),
                        at: t,
                        first: time,
                        map: map.to_string(),
                        first_frame,
                        instead,
                    })));
                }
            }
        }
        Ok(values)
    }
}

/// Why a USD scalp's primvar cannot be read as a map; the caller names the map.
#[derive(Debug, thiserror::Error)]
pub enum PrimvarError {
    /// The scalp is an OBJ file, which has no primvars.
    #[error(
        "the scalp is the OBJ file {}, which has no primvars (only a USD scalp, [scalp.mesh] \
         kind = \"usd\", has); paint the OBJ's vertex colours and use `vertex_colors = true`, \
         or a texture over its UVs",
        path.display()
    )]
    ObjScalp {
        /// The OBJ file.
        path: PathBuf,
    },
    /// The scalp is not a USD mesh.
    #[error(
        "the scalp ([scalp.mesh] kind = \"{kind}\") has no primvars (only a USD scalp, kind = \
         \"usd\", has); use a texture over the scalp's UVs instead"
    )]
    NotUsd {
        /// The scalp's `kind`.
        kind: &'static str,
    },
    /// The stage, the prim or the primvar cannot be read.
    #[error("{0}")]
    Read(#[from] hair_groom::GroomError),
    /// The primvar's time samples change, but the map is read once.
    #[error("{0}")]
    Changes(Box<PrimvarChanges>),
}

/// A time-sampled primvar whose values change, read as a map that is read once.
#[derive(Debug, thiserror::Error)]
#[error(
    "primvars:{primvar} of prim {prim} in {} has {samples} time samples (time codes {} to {}) \
     whose values change (at time code {at}, from those at the first frame's time code {first}); \
     a {map} map is read once, at the scene's first frame (frame {first_frame}), because the \
     solver takes it when the scene is built: author one value (a default, or the same at every \
     sample), or {instead}",
    path.display(),
    .range.0,
    .range.1
)]
pub struct PrimvarChanges {
    /// The primvar's name, without `primvars:`.
    pub primvar: String,
    /// The scalp's prim.
    pub prim: String,
    /// The USD file.
    pub path: PathBuf,
    /// Its number of time samples.
    pub samples: usize,
    /// The first and last time code sampled.
    pub range: (f64, f64),
    /// The time code whose values differ.
    pub at: f64,
    /// The time code of the scene's first frame.
    pub first: f64,
    /// The map's name.
    pub map: String,
    /// The scene's first frame.
    pub first_frame: u32,
    /// What to do instead, for this map.
    pub instead: &'static str,
}
