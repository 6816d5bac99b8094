//! `[maps.NAME] primvar = "…"`: a painted map read from a primvar of the USD scalp's `Mesh`
//! prim (issue 20), the way a DCC hands over its paint: Blender's USD export writes a vertex
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
//! The primvar is read at the time code of the scene's first frame (its default value when it
//! has no time samples) by [`hair_groom::UsdMeshSource::primvar`], which follows USD's
//! interpolations (`constant`, `uniform`, `vertex`, `varying`, `faceVarying`, indexed or not)
//! to one value at each corner of each scalp triangle; each root then takes the blend of its
//! triangle's three corner values by its barycentric weights ([`crate::maps`]). Only a USD
//! scalp has primvars: a primvar map on any other scalp is refused, naming the scalp and what
//! to use instead.

use crate::maps::Channel;

use super::{ScalpMesh, SceneFile};

/// The primvar `name` (its `channel` if given) of the scene's USD scalp at the scene's first
/// frame, as values at the corners of every scalp triangle (see the module docs). Errors name
/// the scalp file, the prim, the primvar and the fix.
pub fn scalp_primvar(
    scene: &SceneFile,
    name: &str,
    channel: Option<Channel>,
) -> Result<Vec<[f32; 3]>, String> {
    let section = match &scene.scene.scalp.mesh {
        ScalpMesh::Usd(section) => section,
        ScalpMesh::Obj { path, .. } => {
            return Err(format!(
                "the scalp is the OBJ file {}, which has no primvars (only a USD scalp, \
                 [scalp.mesh] kind = \"usd\", has); paint the OBJ's vertex colours and use \
                 `vertex_colors = true`, or a texture over its UVs",
                scene.base_dir.join(path).display()
            ))
        }
        other => {
            let kind = match other {
                ScalpMesh::None => "none",
                ScalpMesh::BuiltinHead => "builtin-head",
                ScalpMesh::UvSphere { .. } => "uv-sphere",
                _ => "obj-sequence",
            };
            return Err(format!(
                "the scalp ([scalp.mesh] kind = \"{kind}\") has no primvars (only a USD scalp, \
                 kind = \"usd\", has); use a texture over the scalp's UVs instead"
            ));
        }
    };
    let path = scene.base_dir.join(&section.path);
    let source =
        hair_groom::UsdMeshSource::open(&path, &section.options()).map_err(|e| e.to_string())?;
    let component = channel.map(|c| match c {
        Channel::R => 0,
        Channel::G => 1,
        Channel::B => 2,
        Channel::A => 3,
    });
    let time = section.time_code(f64::from(scene.scene.scene.frames[0]));
    source
        .primvar(name, component, time)
        .map(|corners| corners.values)
        .map_err(|e| e.to_string())
}
