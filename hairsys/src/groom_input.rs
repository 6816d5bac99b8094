//! [`Session::from_groom`]: a session from a groom and a scalp a host hands over as flat arrays
//! (a DCC's curves and mesh, no files), for the Python module and the Blender add-on.
//!
//! The assembly is the scene's, fed from memory instead of files: the curves are attached to the
//! scalp by [`hair_groom::snap_to_scalp`] (each root becomes a mesh sample, the rest shape is
//! stored in its root frame, exactly as `[guides] file = …` does), and either simulated as they
//! are (one strand per curve, in the host's order, so the host can write the positions back onto
//! its own curves) or used as guides from which [`hair_groom::interpolate()`] grows more simulation
//! hairs (as `[sim_hairs]` does). The strand model is mass-spring; colliders, hair–hair and
//! fields are optional, and the scalp may collide with its own hair (as `[scalp.collider]`).
//!
//! The scalp is given in world space at the first frame with an identity body transform, so a
//! host that deforms it hands the deformed world-space vertices to
//! [`Session::set_scalp_vertices`] with [`Isometry3::identity`] every frame.
//!
//! Goal (pin) weights may be given per point of the curves; with interpolated hairs each hair's
//! weight at a fraction of its length is the blend (by the interpolation's guide weights) of its
//! guides' weights at the same fraction. A host's painted maps reach the strands the same way:
//! pinned points per curve point (curves simulated as they are), and per-curve factors of the
//! material ([`StrandScales`]: stretch, bend, goal, damping, drag; interpolated hairs blend
//! their guides' factors by the same weights), which is what `[[regions]]` and
//! `[maps.stiffness]` give a scene's strands.

use hair_core::{
    Anchor, Collider, Colliders, ContactSettings, ForceField, HairHairSettings, HairParams, Scalp,
    Solver, SolverSettings, StrandInput, StrandScales, StrandSet, TriMesh,
};
use hair_groom::{Distance, Groom, Guide, InterpolateOptions, Region, SnapOptions};
use nalgebra::{Isometry3, Vector2, Vector3};

use crate::error::{Error, Result};
use crate::scene::ScalpCollider;
use crate::Session;

/// A groom and its scalp as flat arrays (m, Z up, world space at the first frame).
#[derive(Debug, Clone, Copy)]
pub struct GroomArrays<'a> {
    /// Scalp vertex positions, m.
    pub scalp_vertices: &'a [[f32; 3]],
    /// Scalp triangles as vertex indices.
    pub scalp_triangles: &'a [[u32; 3]],
    /// Scalp UVs, one per vertex (children's root UVs), if any.
    pub scalp_uvs: Option<&'a [[f32; 2]]>,
    /// Every curve's points, root first, curve after curve, m.
    pub curve_points: &'a [[f32; 3]],
    /// Points per curve (each ≥ 2); they add up to `curve_points.len()`.
    pub curve_counts: &'a [u32],
    /// Goal weight of every curve point in [0, 1] (`None`: linear from
    /// [`GroomOptions::goal_root`] to [`GroomOptions::goal_tip`]).
    pub goal_weights: Option<&'a [f32]>,
    /// Whether each curve point is pinned: held kinematically on its rest shape in the root
    /// frame, so it follows the scalp rigidly (`None`: only the roots). Only for
    /// [`SimHairs::Curves`].
    pub pinned: Option<&'a [bool]>,
    /// Each curve's factors of the material's stiffnesses, damping and drag (`None`: all 1);
    /// interpolated hairs blend their guides' factors by their interpolation weights.
    pub strand_scales: Option<&'a [StrandScales]>,
}

/// Which strands are simulated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SimHairs {
    /// One strand per curve, in the curves' order and with their points.
    Curves,
    /// `count` hairs rooted area-weighted on the scalp (from `seed`), each blended from its `k`
    /// nearest curves (as guides) measured along the surface, with `points` points (default:
    /// the first curve's count).
    Interpolated {
        /// Number of simulation hairs.
        count: usize,
        /// Guides blended per hair, ≥ 1.
        k: usize,
        /// Points per hair (≥ 2); `None`: the first curve's count.
        points: Option<usize>,
        /// Seed of the roots.
        seed: u64,
    },
}

/// How a groom is simulated; [`Default`] is the default scene's material on a still scalp.
#[derive(Debug, Clone)]
pub struct GroomOptions {
    /// Which strands are simulated.
    pub sim_hairs: SimHairs,
    /// Material and environment.
    pub physics: HairParams,
    /// Time stepping (fps, steps, substeps, damping iterations).
    pub settings: SolverSettings,
    /// Frame number of the rest state (the first frame).
    pub first_frame: u32,
    /// Linear density, kg/m.
    pub mass_per_length: f32,
    /// Strand (wisp) radius, m: collision sphere and render width.
    pub radius: f32,
    /// Goal weight at the root when no per-point weights are given, 0–1.
    pub goal_root: f32,
    /// Goal weight at the tip when no per-point weights are given, 0–1.
    pub goal_tip: f32,
    /// Largest distance a curve's root may be moved onto the scalp, m.
    pub max_snap_distance: f32,
    /// The scalp as a collider for its own hair, if given.
    pub scalp_collider: Option<ScalpCollider>,
    /// Further colliders with their poses at the first frame; their ids are 0, 1, … in this
    /// order (the scalp collider, if any, comes after them).
    pub colliders: Vec<(Collider, Isometry3<f32>)>,
    /// Fast-motion stepping of contacts.
    pub contacts: ContactSettings,
    /// Voxel hair–hair friction and repulsion, if on.
    pub hair_hair: Option<HairHairSettings>,
    /// Force fields.
    pub fields: Vec<ForceField>,
}

impl Default for GroomOptions {
    fn default() -> Self {
        Self {
            sim_hairs: SimHairs::Curves,
            physics: HairParams::default(),
            settings: SolverSettings::default(),
            first_frame: 1,
            mass_per_length: 1e-3,
            radius: 1e-3,
            goal_root: 0.0,
            goal_tip: 0.0,
            max_snap_distance: 0.025,
            scalp_collider: None,
            colliders: Vec::new(),
            contacts: ContactSettings::default(),
            hair_hair: None,
            fields: Vec::new(),
        }
    }
}

impl Session {
    /// A session of the groom `input` on its scalp (see the module docs), at rest at
    /// `options.first_frame`. Bad arrays are [`Error::Argument`]s naming the argument and the
    /// expected shape; a root farther than `max_snap_distance` from the scalp is refused by
    /// curve index.
    pub fn from_groom(input: &GroomArrays<'_>, options: &GroomOptions) -> Result<Self> {
        let mesh = scalp_mesh(input)?;
        let curves = curves(input)?;
        let weights = goal_weights(input, options)?;
        let pinned = pinned(input, options)?;
        let groom =
            Groom::new(curves).map_err(|e| Error::argument("curve_points", e.to_string()))?;
        let snapped = hair_groom::snap_to_scalp(
            &groom,
            &mesh,
            &SnapOptions {
                max_distance: options.max_snap_distance,
            },
        )
        .map_err(|e| Error::argument("curve_points", e.to_string()))?;
        let (mut inputs, scales) = strand_inputs(
            &mesh,
            &snapped.guides,
            &weights,
            input.strand_scales,
            options,
        )?;
        if let Some(pinned) = pinned {
            for (s, p) in inputs.iter_mut().zip(pinned) {
                s.pinned = p;
                s.pinned[0] = true;
            }
        }
        let mut strands = StrandSet::new();
        for (i, s) in inputs.into_iter().enumerate() {
            strands
                .push(s)
                .map_err(|e| Error::argument("curve_points", format!("strand {i}: {e}")))?;
        }
        let scalp = Scalp {
            mesh: Some(mesh.clone()),
            body: Isometry3::identity(),
        };
        strands.reset_to_rest(&scalp);
        let solver_error = |source| Error::Solver {
            scene: "groom session".into(),
            source,
        };
        let mut solver = Solver::new(
            options.settings,
            options.physics,
            &strands,
            &scalp,
            options.first_frame,
        )
        .map_err(solver_error)?;
        if let Some(scales) = scales {
            solver = solver
                .with_strand_scales(scales, &strands)
                .map_err(|e| Error::argument("strand_scales", e.to_string()))?;
        }
        if let Some(h) = options.hair_hair {
            solver = solver.with_hair_hair(h, &strands).map_err(solver_error)?;
        }
        if !options.fields.is_empty() {
            solver = solver
                .with_fields(options.fields.clone())
                .map_err(solver_error)?;
        }
        let mut colliders = Colliders::new();
        colliders.settings = options.contacts;
        for (i, (c, pose)) in options.colliders.iter().enumerate() {
            colliders
                .insert(c.clone(), *pose)
                .map_err(|e| Error::argument(format!("colliders[{i}]"), e.to_string()))?;
        }
        let scalp_collider = match options.scalp_collider {
            Some(sc) => Some(
                colliders
                    .insert_scalp_rest(
                        mesh.clone(),
                        Isometry3::identity(),
                        sc.thickness,
                        sc.friction,
                    )
                    .map_err(|e| Error::argument("scalp_collider", e.to_string()))?,
            ),
            None => None,
        };
        Session::new(
            strands,
            solver.into(),
            colliders,
            scalp,
            Some(mesh),
            scalp_collider,
        )
    }
}

/// The scalp mesh of `input`, checked.
fn scalp_mesh(input: &GroomArrays<'_>) -> Result<TriMesh> {
    let positions: Vec<Vector3<f32>> = input
        .scalp_vertices
        .iter()
        .map(|v| Vector3::from(*v))
        .collect();
    let mesh = TriMesh::new(positions, input.scalp_triangles.to_vec()).map_err(|e| {
        Error::argument(
            "scalp_vertices/scalp_triangles",
            format!("{e} (vertices (V, 3) float m, triangles (T, 3) vertex indices)"),
        )
    })?;
    match input.scalp_uvs {
        None => Ok(mesh),
        Some(uvs) => mesh
            .with_uvs(uvs.iter().map(|uv| Vector2::from(*uv)).collect())
            .map_err(|e| Error::argument("scalp_uvs", format!("{e}: shape (V, 2)"))),
    }
}

/// The curves of `input`, split by `curve_counts` (checked before anything is allocated).
fn curves(input: &GroomArrays<'_>) -> Result<Vec<Vec<Vector3<f32>>>> {
    let total: u64 = input.curve_counts.iter().map(|&c| u64::from(c)).sum();
    if total != input.curve_points.len() as u64 {
        return Err(Error::argument(
            "curve_counts",
            format!(
                "add up to {total} points but curve_points has {}: give one count per curve, \
                 adding up to the rows of curve_points (P, 3)",
                input.curve_points.len()
            ),
        ));
    }
    if input.curve_counts.is_empty() {
        return Err(Error::argument(
            "curve_counts",
            "is empty: give at least one curve",
        ));
    }
    if let Some(i) = input.curve_counts.iter().position(|&c| c < 2) {
        return Err(Error::argument(
            "curve_counts",
            format!(
                "curve {i} has {} point(s): every curve needs at least 2, root first",
                input.curve_counts[i]
            ),
        ));
    }
    if let Some(i) = input
        .curve_points
        .iter()
        .position(|p| !p.iter().all(|c| c.is_finite()))
    {
        return Err(Error::argument(
            "curve_points",
            format!("point {i} is not finite ({:?})", input.curve_points[i]),
        ));
    }
    let mut out = Vec::with_capacity(input.curve_counts.len());
    let mut start = 0usize;
    for &c in input.curve_counts {
        let end = start + c as usize;
        out.push(
            input.curve_points[start..end]
                .iter()
                .map(|p| Vector3::from(*p))
                .collect(),
        );
        start = end;
    }
    Ok(out)
}

/// Goal weights per curve, one per point (`None` without per-point weights).
fn goal_weights(input: &GroomArrays<'_>, options: &GroomOptions) -> Result<Option<Vec<Vec<f32>>>> {
    for (name, v) in [
        ("goal_root", options.goal_root),
        ("goal_tip", options.goal_tip),
    ] {
        if !(0.0..=1.0).contains(&v) {
            return Err(Error::argument(
                name,
                format!("= {v}: give a goal weight from 0 to 1"),
            ));
        }
    }
    let Some(w) = input.goal_weights else {
        return Ok(None);
    };
    if w.len() != input.curve_points.len() {
        return Err(Error::argument(
            "goal_weights",
            format!(
                "{} values for {} curve points: give shape ({},), one weight per point",
                w.len(),
                input.curve_points.len(),
                input.curve_points.len()
            ),
        ));
    }
    if let Some(i) = w.iter().position(|x| !(0.0..=1.0).contains(x)) {
        return Err(Error::argument(
            "goal_weights",
            format!("point {i} has {}: give weights from 0 to 1", w[i]),
        ));
    }
    let mut out = Vec::with_capacity(input.curve_counts.len());
    let mut start = 0usize;
    for &c in input.curve_counts {
        out.push(w[start..start + c as usize].to_vec());
        start += c as usize;
    }
    Ok(Some(out))
}

/// Pinned flags per curve, one per point (`None` without them); refused with interpolated
/// hairs, whose points are not the curves'.
fn pinned(input: &GroomArrays<'_>, options: &GroomOptions) -> Result<Option<Vec<Vec<bool>>>> {
    let Some(p) = input.pinned else {
        return Ok(None);
    };
    if options.sim_hairs != SimHairs::Curves {
        return Err(Error::argument(
            "pinned",
            "pins points of the curves, which are guides when sim_hairs is given: pin with \
             sim_hairs=None (the curves simulated themselves), or hold interpolated hairs with \
             goal_weights of 1",
        ));
    }
    if p.len() != input.curve_points.len() {
        return Err(Error::argument(
            "pinned",
            format!(
                "{} values for {} curve points: give shape ({},), one flag per point",
                p.len(),
                input.curve_points.len(),
                input.curve_points.len()
            ),
        ));
    }
    let mut out = Vec::with_capacity(input.curve_counts.len());
    let mut start = 0usize;
    for &c in input.curve_counts {
        out.push(p[start..start + c as usize].to_vec());
        start += c as usize;
    }
    Ok(Some(out))
}

/// The blend of the guides' factors `scales` by `sources`' weights (which sum to 1).
fn blend_scales(sources: &[hair_groom::GuideWeight], scales: &[StrandScales]) -> StrandScales {
    let mut out = StrandScales {
        stretch: 0.0,
        bend: 0.0,
        goal: 0.0,
        damping: 0.0,
        drag: 0.0,
    };
    for s in sources {
        let g = &scales[s.guide];
        out.stretch += s.weight * g.stretch;
        out.bend += s.weight * g.bend;
        out.goal += s.weight * g.goal;
        out.damping += s.weight * g.damping;
        out.drag += s.weight * g.drag;
    }
    out
}

/// `weights` (one per point along a curve) at fraction `t` ∈ [0, 1] of its points, linearly.
fn weight_at(weights: &[f32], t: f32) -> f32 {
    let x = t * (weights.len() - 1) as f32;
    let i = (x.floor() as usize).min(weights.len() - 2);
    let f = x - i as f32;
    weights[i] * (1.0 - f) + weights[i + 1] * f
}

/// The strand inputs of the simulated hairs: the guides themselves or hairs interpolated from
/// them, with masses, radius and goal weights from `options` and `weights`, and their factors
/// of the material from the curves' `scales` (one per curve, checked here).
fn strand_inputs(
    mesh: &TriMesh,
    guides: &[Guide],
    weights: &Option<Vec<Vec<f32>>>,
    scales: Option<&[StrandScales]>,
    options: &GroomOptions,
) -> Result<(Vec<StrandInput>, Option<Vec<StrandScales>>)> {
    if let Some(scales) = scales {
        if scales.len() != guides.len() {
            return Err(Error::argument(
                "strand_scales",
                format!(
                    "{} entries for {} curves: give one per curve",
                    scales.len(),
                    guides.len()
                ),
            ));
        }
        for (i, s) in scales.iter().enumerate() {
            s.validate(i)
                .map_err(|e| Error::argument("strand_scales", e.to_string()))?;
        }
    }
    let make = |anchor, rest: Vec<Vector3<f32>>, goal: Option<Vec<f32>>| {
        let mut s = StrandInput::uniform(
            anchor,
            rest,
            options.mass_per_length,
            options.radius,
            options.goal_root,
            options.goal_tip,
        );
        if let Some(g) = goal {
            s.goal_weight = g;
        }
        s
    };
    match options.sim_hairs {
        SimHairs::Curves => Ok((
            guides
                .iter()
                .enumerate()
                .map(|(i, g)| {
                    let goal = weights.as_ref().map(|w| w[i].clone());
                    make(Anchor::Surface(g.root), g.rest.clone(), goal)
                })
                .collect(),
            scales.map(<[StrandScales]>::to_vec),
        )),
        SimHairs::Interpolated {
            count,
            k,
            points,
            seed,
        } => {
            let roots = hair_groom::sample_area_weighted(mesh, count, seed, &Region::All)
                .map_err(|e| Error::argument("sim_hairs", e.to_string()))?;
            let points = points.unwrap_or(guides[0].rest.len());
            let hairs = hair_groom::interpolate(
                mesh,
                guides,
                &vec![true; guides.len()],
                &roots,
                &InterpolateOptions {
                    k,
                    points,
                    distance: Distance::Surface,
                },
            )
            .map_err(|e| Error::argument("sim_hairs", e.to_string()))?;
            let blended = scales.map(|scales| {
                hairs
                    .iter()
                    .map(|h| blend_scales(&h.sources, scales))
                    .collect()
            });
            let inputs = hairs
                .into_iter()
                .map(|h| {
                    let goal = weights.as_ref().map(|w| {
                        let n = h.rest.len();
                        (0..n)
                            .map(|j| {
                                let t = j as f32 / (n - 1) as f32;
                                h.sources
                                    .iter()
                                    .map(|s| s.weight * weight_at(&w[s.guide], t))
                                    .sum::<f32>()
                                    .clamp(0.0, 1.0)
                            })
                            .collect()
                    });
                    make(Anchor::Surface(h.root), h.rest, goal)
                })
                .collect();
            Ok((inputs, blended))
        }
    }
}
