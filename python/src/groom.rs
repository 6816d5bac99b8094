//! `Session.from_groom`'s arguments: the arrays (checked for shape and dtype) and the keyword
//! options, mapped onto [`hairsys::build::groom`].

use hair_core::{Collider, ColliderShape, HairHairSettings, StrandScales, Substeps, TriMesh};
use hairsys::build::groom::{GroomArrays, GroomOptions, SimHairs};
use hairsys::scene::integrator::IntegratorChoice;
use hairsys::scene::ScalpCollider;
use nalgebra::{Isometry3, Vector3};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::arrays::{bools, float_rows, floats, indices, isometry};
use crate::errors::argument;

/// The arrays of a groom, owned (converted from the host's dtypes).
pub struct GroomInput {
    scalp_vertices: Vec<[f32; 3]>,
    scalp_triangles: Vec<[u32; 3]>,
    scalp_uvs: Option<Vec<[f32; 2]>>,
    curve_points: Vec<[f32; 3]>,
    curve_counts: Vec<u32>,
    goal_weights: Option<Vec<f32>>,
    pinned: Option<Vec<bool>>,
    strand_scales: Option<Vec<StrandScales>>,
}

impl GroomInput {
    /// Reads the positional arrays and the `scalp_uvs`, `goal_weights`, `pinned` and
    /// `strand_scales` options.
    pub fn read(
        scalp_vertices: &Bound<'_, PyAny>,
        scalp_triangles: &Bound<'_, PyAny>,
        curve_points: &Bound<'_, PyAny>,
        curve_counts: &Bound<'_, PyAny>,
        options: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let triangles = indices(scalp_triangles, "scalp_triangles", Some(3), "(T, 3)")?;
        let scalp_uvs = match option(options, "scalp_uvs")? {
            Some(uv) => Some(float_rows::<2>(&uv, "scalp_uvs", "(V, 2)")?),
            None => None,
        };
        let goal_weights = match option(options, "goal_weights")? {
            Some(w) => Some(floats(&w, "goal_weights", "(P,)")?),
            None => None,
        };
        let pinned = match option(options, "pinned")? {
            Some(p) => Some(bools(&p, "pinned", "(P,)")?),
            None => None,
        };
        let strand_scales = match option(options, "strand_scales")? {
            Some(d) => strand_scales(&d)?,
            None => None,
        };
        Ok(Self {
            scalp_vertices: float_rows::<3>(scalp_vertices, "scalp_vertices", "(V, 3)")?,
            scalp_triangles: triangles
                .chunks_exact(3)
                .map(|t| [t[0], t[1], t[2]])
                .collect(),
            scalp_uvs,
            curve_points: float_rows::<3>(curve_points, "curve_points", "(P, 3)")?,
            curve_counts: indices(curve_counts, "curve_counts", None, "(C,)")?,
            goal_weights,
            pinned,
            strand_scales,
        })
    }

    /// The arrays as the library takes them.
    pub fn arrays(&self) -> GroomArrays<'_> {
        GroomArrays {
            scalp_vertices: &self.scalp_vertices,
            scalp_triangles: &self.scalp_triangles,
            scalp_uvs: self.scalp_uvs.as_deref(),
            curve_points: &self.curve_points,
            curve_counts: &self.curve_counts,
            goal_weights: self.goal_weights.as_deref(),
            pinned: self.pinned.as_deref(),
            strand_scales: self.strand_scales.as_deref(),
        }
    }
}

/// The factors [`StrandScales`] names, as `strand_scales` keys.
const SCALE_KEYS: [&str; 5] = ["stretch", "bend", "goal", "damping", "drag"];

/// `strand_scales={"bend": (C,), …}`: per-curve factors, each key one of [`SCALE_KEYS`] with
/// one value per curve; factors left out are 1 (an empty dict: `None`, every factor 1).
fn strand_scales(obj: &Bound<'_, PyAny>) -> PyResult<Option<Vec<StrandScales>>> {
    let d = obj.cast::<PyDict>().map_err(|_| {
        argument(
            "strand_scales",
            format!(
                "give a dict of (C,) arrays with keys {}",
                SCALE_KEYS.join(", ")
            ),
        )
    })?;
    let mut out: Option<Vec<StrandScales>> = None;
    for (key, value) in d.iter() {
        let key: String = key.extract()?;
        let name = format!("strand_scales[{key:?}]");
        if !SCALE_KEYS.contains(&key.as_str()) {
            return Err(argument(
                &name,
                format!("is not a factor; the keys are {}", SCALE_KEYS.join(", ")),
            ));
        }
        let values = floats(&value, &name, "(C,)")?;
        let scales = out.get_or_insert_with(|| vec![StrandScales::ONE; values.len()]);
        if values.len() != scales.len() {
            return Err(argument(
                &name,
                format!(
                    "has {} values but another factor has {}: give one per curve",
                    values.len(),
                    scales.len()
                ),
            ));
        }
        for (s, v) in scales.iter_mut().zip(values) {
            match key.as_str() {
                "stretch" => s.stretch = v,
                "bend" => s.bend = v,
                "goal" => s.goal = v,
                "damping" => s.damping = v,
                _ => s.drag = v,
            }
        }
    }
    Ok(out)
}

/// Every keyword `from_groom` takes.
const KEYS: &[&str] = &[
    "scalp_uvs",
    "goal_weights",
    "pinned",
    "strand_scales",
    "sim_hairs",
    "k",
    "points",
    "seed",
    "fps",
    "first_frame",
    "steps",
    "substeps",
    "integrator",
    "sag_free",
    "collider_speed",
    "damping_iterations",
    "max_strain",
    "gravity",
    "stretch_stiffness",
    "bend_stiffness",
    "goal_stiffness",
    "stretch_damping",
    "air_drag",
    "mass_per_length",
    "radius",
    "goal_root",
    "goal_tip",
    "max_snap_distance",
    "scalp_collider",
    "scalp_thickness",
    "scalp_friction",
    "colliders",
    "hair_hair_friction",
    "hair_hair_cell_size",
    "threads",
];

fn option<'py>(
    options: Option<&Bound<'py, PyDict>>,
    key: &str,
) -> PyResult<Option<Bound<'py, PyAny>>> {
    match options {
        Some(d) => Ok(d.get_item(key)?.filter(|v| !v.is_none())),
        None => Ok(None),
    }
}

fn value<'py, T: pyo3::conversion::FromPyObjectOwned<'py>>(
    options: Option<&Bound<'py, PyDict>>,
    key: &str,
) -> PyResult<Option<T>> {
    match option(options, key)? {
        Some(v) => v.extract::<T>().map(Some).map_err(|e| {
            let e: PyErr = e.into();
            argument(key, format!("has the wrong type ({e})"))
        }),
        None => Ok(None),
    }
}

/// The options of `from_groom` and the requested thread count; refuses unknown keys.
pub fn groom_options(
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<(GroomOptions, Option<usize>)> {
    if let Some(d) = options {
        for key in d.keys() {
            let key: String = key.extract()?;
            if !KEYS.contains(&key.as_str()) {
                return Err(argument(
                    &key,
                    format!(
                        "is not an option of from_groom; the options are {}",
                        KEYS.join(", ")
                    ),
                ));
            }
        }
    }
    let mut o = GroomOptions::default();
    macro_rules! set {
        ($target:expr, $key:literal) => {
            if let Some(v) = value(options, $key)? {
                $target = v;
            }
        };
    }
    if let Some(n) = value::<usize>(options, "sim_hairs")? {
        o.sim_hairs = SimHairs::Interpolated {
            count: n,
            k: value(options, "k")?.unwrap_or(4),
            points: value(options, "points")?,
            seed: value(options, "seed")?.unwrap_or(0),
        };
    }
    if let Some(v) = value(options, "fps")? {
        o.settings.fps = v;
    }
    if let Some(v) = value(options, "first_frame")? {
        o.first_frame = v;
    }
    if let Some(v) = value(options, "steps")? {
        o.settings.steps = v;
    }
    if let Some(v) = option(options, "substeps")? {
        o.settings.substeps = match v.extract::<u32>() {
            Ok(n) if n >= 1 => Substeps::Fixed(n),
            _ => match v.extract::<String>() {
                Ok(w) if w == "auto" => Substeps::Auto,
                _ => return Err(argument("substeps", "give \"auto\" or a whole number ≥ 1")),
            },
        };
    }
    if let Some(v) = value::<String>(options, "integrator")? {
        o.integrator = v
            .parse::<IntegratorChoice>()
            .map_err(|e| argument("integrator", &e))?;
    }
    set!(o.sag_free, "sag_free");
    o.expected_motion.collider_speed = value(options, "collider_speed")?;
    if let Some(v) = value(options, "damping_iterations")? {
        o.settings.damping_iterations = v;
    }
    if let Some(v) = value::<f32>(options, "max_strain")? {
        o.settings.max_strain = Some(v);
    }
    let p = &mut o.physics;
    if let Some(v) = value(options, "gravity")? {
        p.gravity = v;
    }
    set!(p.stretch_stiffness, "stretch_stiffness");
    set!(p.bend_stiffness, "bend_stiffness");
    set!(p.goal_stiffness, "goal_stiffness");
    set!(p.stretch_damping, "stretch_damping");
    set!(p.air_drag, "air_drag");
    set!(o.mass_per_length, "mass_per_length");
    set!(o.radius, "radius");
    set!(o.goal_root, "goal_root");
    set!(o.goal_tip, "goal_tip");
    set!(o.max_snap_distance, "max_snap_distance");
    if value::<bool>(options, "scalp_collider")?.unwrap_or(false) {
        o.scalp_collider = Some(ScalpCollider {
            thickness: value(options, "scalp_thickness")?.unwrap_or(0.0),
            friction: value(options, "scalp_friction")?.unwrap_or(0.0),
        });
    }
    if let Some(friction) = value::<f32>(options, "hair_hair_friction")? {
        let mut h = HairHairSettings {
            friction,
            ..HairHairSettings::default()
        };
        if let Some(c) = value(options, "hair_hair_cell_size")? {
            h.cell_size = c;
        }
        o.hair_hair = Some(h);
    }
    if let Some(list) = option(options, "colliders")? {
        let list = list
            .cast_into::<PyList>()
            .map_err(|_| argument("colliders", "give a list of dicts"))?;
        for (i, item) in list.iter().enumerate() {
            o.colliders.push(collider(&item, i)?);
        }
    }
    Ok((o, value(options, "threads")?))
}

/// One collider dict: `{"shape": "sphere", "radius": r}`, `{"shape": "capsule",
/// "half_height": h, "radius": r}` or `{"shape": "mesh", "vertices": (V, 3), "triangles":
/// (T, 3)}`, with optional `thickness` (m), `friction` and `matrix` (4×4 rigid pose at the
/// first frame).
fn collider(item: &Bound<'_, PyAny>, i: usize) -> PyResult<(Collider, Isometry3<f32>)> {
    let name = format!("colliders[{i}]");
    let d = item
        .cast::<PyDict>()
        .map_err(|_| argument(&name, "give a dict with a \"shape\" key"))?;
    let get = |key: &str| -> PyResult<Bound<'_, PyAny>> {
        d.get_item(key)?
            .ok_or_else(|| argument(&name, format!("needs the key {key:?}")))
    };
    let f = |key: &str| -> PyResult<f32> {
        get(key)?
            .extract::<f32>()
            .map_err(|_| argument(&format!("{name}[{key:?}]"), "give a number"))
    };
    let kind: String = get("shape")?.extract()?;
    let shape = match kind.as_str() {
        "sphere" => ColliderShape::Sphere {
            radius: f("radius")?,
        },
        "capsule" => ColliderShape::Capsule {
            half_height: f("half_height")?,
            radius: f("radius")?,
        },
        "mesh" => {
            let v = float_rows::<3>(
                &get("vertices")?,
                &format!("{name}[\"vertices\"]"),
                "(V, 3)",
            )?;
            let t = indices(
                &get("triangles")?,
                &format!("{name}[\"triangles\"]"),
                Some(3),
                "(T, 3)",
            )?;
            let mesh = TriMesh::new(
                v.iter().map(|p| Vector3::from(*p)).collect(),
                t.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
            )
            .map_err(|e| argument(&name, e))?;
            ColliderShape::Mesh(mesh)
        }
        other => {
            return Err(argument(
                &name,
                format!("shape {other:?}: give \"sphere\", \"capsule\" or \"mesh\""),
            ))
        }
    };
    let optional = |key: &str| -> PyResult<f32> {
        match d.get_item(key)? {
            Some(v) => v
                .extract::<f32>()
                .map_err(|_| argument(&format!("{name}[{key:?}]"), "give a number")),
            None => Ok(0.0),
        }
    };
    let pose = match d.get_item("matrix")? {
        Some(m) => isometry(&m, &format!("{name}[\"matrix\"]"))?,
        None => Isometry3::identity(),
    };
    Ok((
        Collider {
            shape,
            thickness: optional("thickness")?,
            friction: optional("friction")?,
        },
        pose,
    ))
}
