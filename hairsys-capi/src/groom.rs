//! A groom session's arguments: the host's arrays and options, checked and mapped onto
//! [`hairsys::build::groom`] (the same door the Python module and a Rust host take).

use hair_core::{Collider, ColliderShape, HairHairSettings, StrandScales, Substeps, TriMesh};
use hairsys::budget::Budget;
use hairsys::build::groom::{GroomArrays, GroomOptions, SimHairs};
use hairsys::scene::integrator::IntegratorChoice;
use hairsys::scene::ScalpCollider;
use nalgebra::{Isometry3, Vector3};

use crate::check;
use crate::error::{guard, Failure, HairsysStatus};
use crate::types::{
    HairsysCollider, HairsysGroomArrays, HairsysGroomOptions, HairsysStrandScales,
    HAIRSYS_SHAPE_CAPSULE, HAIRSYS_SHAPE_MESH, HAIRSYS_SHAPE_SPHERE,
};

/// Fills `*out` with the defaults of a groom session: the default scene's material on a still
/// scalp, one strand per curve, `"auto"` integrator and substeps, no colliders, the shared
/// thread pool.
///
/// # Safety
/// `out` points to writable memory for a `HairsysGroomOptions`.
#[no_mangle]
pub unsafe extern "C" fn hairsys_groom_options_default(
    out: *mut HairsysGroomOptions,
) -> HairsysStatus {
    guard(|| {
        // SAFETY: the caller's promise.
        let out = unsafe { check::out(out, "out")? };
        out.write(default_options());
        Ok(())
    })
}

/// [`GroomOptions::default`] in the C layout.
pub fn default_options() -> HairsysGroomOptions {
    let o = GroomOptions::default();
    let p = o.physics;
    let h = HairHairSettings::default();
    HairsysGroomOptions {
        sim_hairs: 0,
        interpolate_k: 4,
        interpolate_points: 0,
        seed: 0,
        fps: o.settings.fps,
        steps: o.settings.steps,
        substeps: match o.settings.substeps {
            Substeps::Fixed(n) => n,
            Substeps::Auto => 0,
        },
        damping_iterations: o.settings.damping_iterations,
        first_frame: o.first_frame,
        integrator: std::ptr::null(),
        sag_free: u32::from(o.sag_free),
        collider_speed: o.expected_motion.collider_speed.unwrap_or(-1.0),
        gravity: p.gravity,
        stretch_stiffness: p.stretch_stiffness,
        bend_stiffness: p.bend_stiffness,
        goal_stiffness: p.goal_stiffness,
        stretch_damping: p.stretch_damping,
        air_drag: p.air_drag,
        mass_per_length: o.mass_per_length,
        radius: o.radius,
        goal_root: o.goal_root,
        goal_tip: o.goal_tip,
        max_snap_distance: o.max_snap_distance,
        scalp_collider: 0,
        scalp_thickness: 0.0,
        scalp_friction: 0.0,
        colliders: std::ptr::null(),
        collider_count: 0,
        hair_hair: 0,
        hair_hair_friction: h.friction,
        hair_hair_cell_size: h.cell_size,
        threads: 0,
    }
}

/// The groom arrays, borrowed from the host.
pub struct Arrays<'a> {
    scalp_vertices: &'a [[f32; 3]],
    scalp_triangles: &'a [[u32; 3]],
    scalp_uvs: Option<&'a [[f32; 2]]>,
    curve_points: &'a [[f32; 3]],
    curve_counts: &'a [u32],
    goal_weights: Option<&'a [f32]>,
    pinned: Option<Vec<bool>>,
    strand_scales: Option<Vec<StrandScales>>,
}

impl<'a> Arrays<'a> {
    /// Reads and checks `a` (NULL, alignment, lengths, finite floats, 0/1 pins).
    ///
    /// # Safety
    /// Every non-NULL pointer of `a` points to as many elements as its count says.
    pub unsafe fn read(a: &HairsysGroomArrays) -> Result<Self, Failure> {
        // SAFETY (every block below): the caller's promise on `a`'s pointers and counts.
        let scalp_vertices = unsafe {
            check::array::<f32, 3>(a.scalp_vertices, a.scalp_vertex_count, "scalp_vertices")?
        };
        check::finite(scalp_vertices, "scalp_vertices")?;
        let scalp_triangles = unsafe {
            check::array::<u32, 3>(a.scalp_triangles, a.scalp_triangle_count, "scalp_triangles")?
        };
        let scalp_uvs = if a.scalp_uvs.is_null() {
            None
        } else {
            let uvs =
                unsafe { check::array::<f32, 2>(a.scalp_uvs, a.scalp_vertex_count, "scalp_uvs")? };
            check::finite(uvs, "scalp_uvs")?;
            Some(uvs)
        };
        let curve_points =
            unsafe { check::array::<f32, 3>(a.curve_points, a.curve_point_count, "curve_points")? };
        check::finite(curve_points, "curve_points")?;
        let curve_counts =
            unsafe { check::array::<u32, 1>(a.curve_counts, a.curve_count, "curve_counts")? };
        let curve_counts: &[u32] = bytemuck::cast_slice(curve_counts);
        let goal_weights = if a.goal_weights.is_null() {
            None
        } else {
            let w = unsafe {
                check::array::<f32, 1>(a.goal_weights, a.curve_point_count, "goal_weights")?
            };
            check::finite(w, "goal_weights")?;
            Some(bytemuck::cast_slice::<[f32; 1], f32>(w))
        };
        let pinned = if a.pinned.is_null() {
            None
        } else {
            let p = unsafe { check::array::<u8, 1>(a.pinned, a.curve_point_count, "pinned")? };
            let mut flags = Vec::with_capacity(p.len());
            for (i, &[b]) in p.iter().enumerate() {
                match b {
                    0 => flags.push(false),
                    1 => flags.push(true),
                    other => {
                        return Err(Failure::argument(
                            "pinned",
                            format!("point {i} is {other}: give 0 (free) or 1 (pinned)"),
                        ))
                    }
                }
            }
            Some(flags)
        };
        let strand_scales = if a.strand_scales.is_null() {
            None
        } else {
            let s = unsafe {
                check::array::<HairsysStrandScales, 1>(
                    a.strand_scales,
                    a.curve_count,
                    "strand_scales",
                )?
            };
            let scales: Vec<StrandScales> = s
                .iter()
                .map(|[s]| StrandScales {
                    stretch: s.stretch,
                    bend: s.bend,
                    goal: s.goal,
                    damping: s.damping,
                    drag: s.drag,
                })
                .collect();
            let flat: Vec<[f32; 5]> = scales
                .iter()
                .map(|s| [s.stretch, s.bend, s.goal, s.damping, s.drag])
                .collect();
            check::finite(&flat, "strand_scales")?;
            Some(scales)
        };
        Ok(Self {
            scalp_vertices,
            scalp_triangles,
            scalp_uvs,
            curve_points,
            curve_counts,
            goal_weights,
            pinned,
            strand_scales,
        })
    }

    /// The arrays as the library takes them.
    pub fn groom(&self) -> GroomArrays<'_> {
        GroomArrays {
            scalp_vertices: self.scalp_vertices,
            scalp_triangles: self.scalp_triangles,
            scalp_uvs: self.scalp_uvs,
            curve_points: self.curve_points,
            curve_counts: self.curve_counts,
            goal_weights: self.goal_weights,
            pinned: self.pinned.as_deref(),
            strand_scales: self.strand_scales.as_deref(),
        }
    }
}

/// Refuses interpolated hairs whose points would need more memory than the library's default
/// budget (8 GiB, `hairsys::budget`), before anything is allocated: `sim_hairs` comes from the
/// host unchecked.
pub fn check_budget(options: &GroomOptions, arrays: &Arrays<'_>) -> Result<(), Failure> {
    let SimHairs::Interpolated { count, points, .. } = options.sim_hairs else {
        return Ok(());
    };
    let per_hair = points.unwrap_or(arrays.curve_counts.first().map_or(0, |&c| c as usize));
    Budget::default()
        .check_points("sim_hairs × points", count as f64 * per_hair as f64)
        .map_err(|over| {
            Failure::argument(
                "sim_hairs",
                format!(
                    "{} hairs of {per_hair} points need about {:.1} GiB (limit {:.1} GiB): give \
                     fewer hairs or points",
                    count,
                    over.estimate / f64::from(1u32 << 30),
                    over.limit / f64::from(1u32 << 30)
                ),
            )
        })
}

/// The library's options of `o`, and the requested thread count (0: the shared pool).
///
/// # Safety
/// `o.integrator`, if non-NULL, is NUL-terminated; `o.colliders` points to `o.collider_count`
/// colliders whose mesh pointers point to as many elements as their counts say.
pub unsafe fn options(o: &HairsysGroomOptions) -> Result<(GroomOptions, u32), Failure> {
    let floats = [
        ("fps", o.fps),
        ("stretch_stiffness", o.stretch_stiffness),
        ("bend_stiffness", o.bend_stiffness),
        ("goal_stiffness", o.goal_stiffness),
        ("stretch_damping", o.stretch_damping),
        ("air_drag", o.air_drag),
        ("mass_per_length", o.mass_per_length),
        ("radius", o.radius),
        ("goal_root", o.goal_root),
        ("goal_tip", o.goal_tip),
        ("max_snap_distance", o.max_snap_distance),
        ("scalp_thickness", o.scalp_thickness),
        ("scalp_friction", o.scalp_friction),
        ("hair_hair_friction", o.hair_hair_friction),
        ("hair_hair_cell_size", o.hair_hair_cell_size),
    ];
    for (name, v) in floats {
        check::finite_scalar(v, name)?;
    }
    check::finite(&[o.gravity], "gravity")?;
    if !o.collider_speed.is_finite() {
        return Err(Failure::NotFinite {
            argument: "collider_speed".into(),
            index: 0,
        });
    }
    let mut g = GroomOptions::default();
    if o.sim_hairs > 0 {
        g.sim_hairs = SimHairs::Interpolated {
            count: o.sim_hairs as usize,
            k: o.interpolate_k as usize,
            points: (o.interpolate_points > 0).then_some(o.interpolate_points as usize),
            seed: o.seed,
        };
    }
    g.settings.fps = o.fps;
    g.settings.steps = o.steps;
    g.settings.substeps = match o.substeps {
        0 => Substeps::Auto,
        n => Substeps::Fixed(n),
    };
    g.settings.damping_iterations = o.damping_iterations;
    g.first_frame = o.first_frame;
    if !o.integrator.is_null() {
        // SAFETY: the caller's promise.
        let word = unsafe { check::string(o.integrator, "integrator")? };
        g.integrator = word
            .parse::<IntegratorChoice>()
            .map_err(|e| Failure::argument("integrator", e.to_string()))?;
    }
    g.sag_free = check::flag(o.sag_free, "sag_free")?;
    g.expected_motion.collider_speed = (o.collider_speed >= 0.0).then_some(o.collider_speed);
    g.physics.gravity = o.gravity;
    g.physics.stretch_stiffness = o.stretch_stiffness;
    g.physics.bend_stiffness = o.bend_stiffness;
    g.physics.goal_stiffness = o.goal_stiffness;
    g.physics.stretch_damping = o.stretch_damping;
    g.physics.air_drag = o.air_drag;
    g.mass_per_length = o.mass_per_length;
    g.radius = o.radius;
    g.goal_root = o.goal_root;
    g.goal_tip = o.goal_tip;
    g.max_snap_distance = o.max_snap_distance;
    if check::flag(o.scalp_collider, "scalp_collider")? {
        g.scalp_collider = Some(ScalpCollider {
            thickness: o.scalp_thickness,
            friction: o.scalp_friction,
        });
    }
    if check::flag(o.hair_hair, "hair_hair")? {
        g.hair_hair = Some(HairHairSettings {
            friction: o.hair_hair_friction,
            cell_size: o.hair_hair_cell_size,
            ..HairHairSettings::default()
        });
    }
    // SAFETY: the caller's promise.
    let colliders =
        unsafe { check::array::<HairsysCollider, 1>(o.colliders, o.collider_count, "colliders")? };
    for (i, [c]) in colliders.iter().enumerate() {
        // SAFETY: the caller's promise on each collider's arrays.
        g.colliders.push(unsafe { collider(c, i)? });
    }
    Ok((g, o.threads))
}

/// Collider `i` of a groom's options.
///
/// # Safety
/// `c`'s mesh pointers point to as many elements as its counts say.
unsafe fn collider(c: &HairsysCollider, i: usize) -> Result<(Collider, Isometry3<f32>), Failure> {
    let name = format!("colliders[{i}]");
    for (field, v) in [
        ("radius", c.radius),
        ("half_height", c.half_height),
        ("thickness", c.thickness),
        ("friction", c.friction),
    ] {
        check::finite_scalar(v, &format!("{name}.{field}"))?;
    }
    let shape = match c.shape {
        HAIRSYS_SHAPE_SPHERE => ColliderShape::Sphere { radius: c.radius },
        HAIRSYS_SHAPE_CAPSULE => ColliderShape::Capsule {
            half_height: c.half_height,
            radius: c.radius,
        },
        HAIRSYS_SHAPE_MESH => {
            // SAFETY: the caller's promise.
            let v = unsafe {
                check::array::<f32, 3>(c.vertices, c.vertex_count, "colliders[].vertices")?
            };
            check::finite(v, &format!("{name}.vertices"))?;
            // SAFETY: the caller's promise.
            let t = unsafe {
                check::array::<u32, 3>(c.triangles, c.triangle_count, "colliders[].triangles")?
            };
            let mesh = TriMesh::new(v.iter().map(|p| Vector3::from(*p)).collect(), t.to_vec())
                .map_err(|e| Failure::argument(&name, e.to_string()))?;
            ColliderShape::Mesh(mesh)
        }
        other => {
            return Err(Failure::argument(
                format!("{name}.shape"),
                format!(
                    "= {other}: give HAIRSYS_SHAPE_SPHERE (0), HAIRSYS_SHAPE_CAPSULE (1) or \
                     HAIRSYS_SHAPE_MESH (2)"
                ),
            ))
        }
    };
    let pose = check::transform(&c.pose, &format!("{name}.pose"))?;
    Ok((
        Collider {
            shape,
            thickness: c.thickness,
            friction: c.friction,
        },
        pose,
    ))
}
