//! The host door of the assembly ([`crate::build`]): a groom and a scalp a host hands over as
//! flat arrays (a DCC's curves and mesh, no files), for [`Session::from_groom`](crate::Session::from_groom), the Python
//! module and the Blender add-on.
//!
//! The curves are attached to the scalp by [`hair_groom::snap_to_scalp`] (each root becomes a
//! mesh sample, the rest shape is stored in its root frame, exactly as `[guides] file = …` does),
//! and either simulated as they are (one strand per curve, in the host's order, so the host can
//! write the positions back onto its own curves) or used as guides from which
//! [`hair_groom::interpolate()`] grows more simulation hairs (as `[sim_hairs]` does). From there
//! the assembly is a scene file's: the integrator is chosen by the same rule (`"auto"` by
//! default, from the strands and how fast [`ExpectedMotion`] says the colliders move), sag-free rest
//! shapes are solved on request, and the session is made by the same constructor.
//!
//! The scalp is given in world space at the first frame with an identity body transform, so a
//! host that deforms it hands the deformed world-space vertices to
//! [`Session::set_scalp_vertices`](crate::Session::set_scalp_vertices) with [`Isometry3::identity`] every frame.
//!
//! Goal (pin) weights may be given per point of the curves; with interpolated hairs each hair's
//! weight at a fraction of its length is the blend (by the interpolation's guide weights) of its
//! guides' weights at the same fraction. A host's painted maps reach the strands the same way:
//! pinned points per curve point (curves simulated as they are), and per-curve factors of the
//! material ([`StrandScales`]: stretch, bend, goal, damping, drag; interpolated hairs blend
//! their guides' factors by the same weights), which is what `[[regions]]` and
//! `[maps.stiffness]` give a scene's strands.

use hair_core::{
    Anchor, Collider, ContactSettings, ForceField, HairHairSettings, HairParams, RodParams,
    SolverSettings, StrandInput, StrandModel, StrandScales, StrandSet, TriMesh,
};
use hair_groom::{Distance, Groom, Guide, InterpolateOptions, Region, SnapOptions};
use nalgebra::{Isometry3, Vector2, Vector3};

use crate::build::{choose_integrator, SettleError};
use crate::build::{SceneCollider, Simulation};
use crate::error::{Error, Result};
use crate::rig::Motion;
use crate::scene::integrator::{ContactLoad, IntegratorChoice};
use crate::scene::ScalpCollider;

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
    /// Time stepping (fps, steps, substeps, damping iterations); its `integrator` is used only
    /// when [`Self::integrator`] names one.
    pub settings: SolverSettings,
    /// `"auto"` (the default: the same rule as a scene file's `[solver] integrator`) or a named
    /// integrator.
    pub integrator: IntegratorChoice,
    /// Solve rest shapes so the groom is a static equilibrium under gravity at the first frame
    /// (as a scene's `[solver] sag_free`): hair holds its groomed shape instead of sagging when
    /// the simulation starts. Mass-spring with one material (no `strand_scales`).
    pub sag_free: bool,
    /// How fast the host will move its colliders, for `"auto"`'s contact rule.
    pub expected_motion: ExpectedMotion,
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
            integrator: IntegratorChoice::Auto,
            sag_free: false,
            expected_motion: ExpectedMotion::default(),
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

/// How fast a host will move its colliders over the shot. A scene file's keyframes and meshes
/// say this by themselves; a host that drives a session frame by frame says it here, so
/// `"auto"` takes the integrator a scene with the same motion would take. What the host does not
/// say (`None`) is taken at its hardest: colliders that may move at any speed. The scalp does not
/// count: the hair is rooted on it and moves with it, however it deforms.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ExpectedMotion {
    /// Fastest speed of any point of a collider's surface over the shot, rigid motion and
    /// deformation together, m/s (0: still colliders).
    pub collider_speed: Option<f64>,
}

/// How a host's groom session names itself in errors.
pub(crate) const ORIGIN: &str = "groom session";

/// The simulation of the groom `input` on its scalp (see [`Session::from_groom`](crate::Session::from_groom)).
pub fn simulation(input: &GroomArrays<'_>, options: &GroomOptions) -> Result<Simulation> {
    let mesh = scalp_mesh(input)?;
    let curves = curves(input)?;
    let weights = goal_weights(input, options)?;
    let pinned = pinned(input, options)?;
    let groom = Groom::new(curves).map_err(|e| Error::argument("curve_points", e.to_string()))?;
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
    let contact = contact_load(options);
    let mut settings = options.settings;
    let (integrator, _) = choose_integrator(
        options.integrator,
        StrandModel::MassSpring,
        &mut settings,
        &strands,
        &options.physics,
        scales.as_deref().unwrap_or(&[]),
        &contact,
    );
    let colliders = options
        .colliders
        .iter()
        .enumerate()
        .map(|(i, (collider, pose))| SceneCollider {
            name: format!("colliders[{i}]"),
            collider: collider.clone(),
            motion: Motion::Fixed(*pose),
            animation: None,
        })
        .collect();
    let mut sim = Simulation {
        strands,
        settings,
        integrator,
        params: options.physics,
        first_frame: options.first_frame,
        last_frame: options.first_frame,
        rest_mesh: Some(mesh),
        scalp_colors: None,
        scalp_animation: None,
        motion: Motion::Fixed(Isometry3::identity()),
        colliders,
        scalp_collider: options.scalp_collider,
        contact_settings: options.contacts,
        guides: Vec::new(),
        guides_report: None,
        hair_hair: options.hair_hair,
        fields: options.fields.clone(),
        model: StrandModel::MassSpring,
        rod: RodParams::default(),
        inextensibility: None,
        strips: None,
        guide_animation: None,
        regions: Default::default(),
        strand_scales: scales,
        child_maps: Default::default(),
        maps: Vec::new(),
    };
    sim.settle(options.sag_free)
        .map_err(|e| settle_error(e, options.colliders.len()))?;
    Ok(sim)
}

/// `"auto"`'s contact load for a host's session: the speed the host gives against the size of
/// its smallest collider.
fn contact_load(options: &GroomOptions) -> ContactLoad {
    if options.colliders.is_empty() {
        return ContactLoad::default();
    }
    let Some(speed) = options.expected_motion.collider_speed else {
        return ContactLoad {
            unknown_collider_speed: true,
            ..ContactLoad::default()
        };
    };
    ContactLoad::from_colliders(
        options
            .colliders
            .iter()
            .map(|(c, _)| (speed, f64::from(c.shape.bounding_radius()))),
    )
}

/// A [`SettleError`] in a host's words: the options it gave (`colliders`: how many it gave).
fn settle_error(e: SettleError, colliders: usize) -> Error {
    match e {
        SettleError::SagFreeWithFactors => Error::argument(
            "sag_free",
            "solves rest shapes for one material, but strand_scales give curves their own: \
             leave out sag_free or strand_scales",
        ),
        SettleError::SagFreeModel => Error::argument("sag_free", "is for the mass-spring model"),
        SettleError::Unbalanced {
            count,
            total,
            first,
        } => Error::argument(
            "sag_free",
            format!(
                "{count} of {total} strands (first: strand {first}) cannot be held in their \
                 groomed shape by the bending springs without turning a rest direction more \
                 than 60°: raise bend_stiffness, shorten the hair or groom it to hang"
            ),
        ),
        SettleError::HairHairGrid(e) => Error::argument("hair_hair_cell_size", e.to_string()),
        SettleError::Collider { source, .. } => match source {
            // The scalp collider comes after the host's colliders.
            hair_core::HairError::Collider { collider, message } if collider >= colliders => {
                Error::argument("scalp_collider", message)
            }
            hair_core::HairError::Collider { collider, message } => {
                Error::argument(format!("colliders[{collider}]"), message)
            }
            other => Error::argument("colliders", other.to_string()),
        },
        SettleError::Anchor(e) => Error::argument("curve_points", e.to_string()),
        SettleError::SagFree(e) => Error::Solver {
            scene: ORIGIN.into(),
            source: e,
        },
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
