//! `hairsys scene check`: everything a run of a scene will use, from the built scene and its
//! strand solver, without stepping — strands and frames, the model, the force substeps (what
//! `substeps = "auto"` resolves to, with the stability bound), the model components, colliders
//! (name, shape, motion), hair–hair, force fields, guides, painted maps (source, purpose, the
//! values at the roots), regions (selection, strands, parameters), and the budget figures beside
//! their limits. Printed as text or, with `--json`, one JSON object.

use hair_core::{ColliderShape, Component, FieldKind, RodParams, StrandModel, Substeps};
use hairsys::budget::{Budget, BYTES_PER_POINT};
use hairsys::build::{SceneCollider, Simulation};
use hairsys::rig::Motion;
use hairsys::scene::guide_anim::HairSelection;
use hairsys::scene::integrator::integrator_name;
use hairsys::scene::maps::MapSummary;
use hairsys::scene::regions::RegionParams;
use serde::Serialize;

use crate::error::CliError;

/// What a run of the scene will use.
#[derive(Debug, Serialize)]
pub struct SceneReport {
    /// The scene file.
    pub scene: String,
    /// Strands simulated.
    pub strands: usize,
    /// Points simulated.
    pub points: usize,
    /// First and last frame (the hair is at rest at the first).
    pub frames: [u32; 2],
    /// Frame rate, frames/s.
    pub fps: f32,
    /// Strand model: `"mass-spring"`, `"rod"` or `"strips"`.
    pub model: &'static str,
    /// The rod's material (`[rod]`), when the model is the rod.
    pub rod: Option<RodParams>,
    /// Time integrator of the mass-spring model, as the scene spells it (`None` for the rod and
    /// the strips).
    pub integrator: Option<&'static str>,
    /// Why `[solver] integrator = "auto"` chose it (`None` when the scene named it).
    pub integrator_reason: Option<String>,
    /// Where the scene named an implicit integrator at a substep it was measured not to hold on
    /// hair this sharply bent (`hairsys::scene::integrator::sharp_joint_warning`).
    pub integrator_warning: Option<String>,
    /// Collision steps per frame (`[solver] steps`).
    pub steps: u32,
    /// Force substeps per step the run will take.
    pub substeps: u32,
    /// Whether `substeps` was resolved from `"auto"`.
    pub substeps_auto: bool,
    /// Substep length, s.
    pub dt: f64,
    /// Stability bound 2/ω, s.
    pub dt_bound: f64,
    /// Model components that will run.
    pub components: Vec<&'static str>,
    /// Colliders: the scalp (with `[scalp.collider]`) and every `[[colliders]]`.
    pub colliders: Vec<ColliderReport>,
    /// `[hair_hair]`, if on: cell size (m), friction, repulsion (m²/s²), target density.
    pub hair_hair: Option<hair_core::HairHairSettings>,
    /// `[[fields]]` kinds, in file order.
    pub fields: Vec<&'static str>,
    /// What `[guides]` and `[sim_hairs]` built, in words.
    pub guides: Option<String>,
    /// The `[maps.NAME]` sections: source, purpose, values at the scalp-rooted strands' roots.
    pub maps: Vec<MapSummary>,
    /// The `[[regions]]`, in file order.
    pub regions: Vec<RegionReport>,
    /// The budget figures checked before work.
    pub budget: BudgetReport,
}

/// One collider of the run.
#[derive(Debug, Serialize)]
pub struct ColliderReport {
    /// Its name (`scalp` for the scalp collider, `#i` for an unnamed `[[colliders]]` entry).
    pub name: String,
    /// Shape in words, sizes in m.
    pub shape: String,
    /// Motion in words: still, or its keys.
    pub motion: String,
    /// Thickness kept on top of the hair radius, m.
    pub thickness: f32,
    /// Coulomb friction coefficient.
    pub friction: f32,
}

/// One `[[regions]]` entry of the run.
#[derive(Debug, Serialize)]
pub struct RegionReport {
    /// Its name.
    pub name: String,
    /// How it selects hair (`guides`, `strands`, `region`, `map`), as the scene gives it.
    pub selection: HairSelection,
    /// Strands it holds (a strand in two regions counts in both; see "Overlaps" in
    /// `hairsys::scene::regions`).
    pub strands: usize,
    /// The parameters it sets (`[physics]` keys in their units, `mass_scale`, `radius_scale`).
    pub params: RegionParams,
}

/// A run's estimates beside the limits they were checked against (see [`hairsys::budget`]).
#[derive(Debug, Serialize)]
pub struct BudgetReport {
    /// Estimated memory of the hair, bytes (points × [`BYTES_PER_POINT`]).
    pub memory_bytes: f64,
    /// The memory limit, bytes (`null` with `--allow-large`).
    pub memory_limit: Option<f64>,
    /// Estimated work, point-substeps (points × substeps × their weight, see
    /// [`hairsys::budget::substep_weight`], × steps × frames stepped).
    pub point_substeps: f64,
    /// The work limit (`null` with `--allow-large`).
    pub point_substeps_limit: Option<f64>,
}

/// The report of the built scene `sim` loaded from `scene`, checked against `budget`; an error
/// when the strand solver refuses the scene.
pub fn report(scene: &str, sim: &Simulation, budget: Budget) -> Result<SceneReport, CliError> {
    let solver = sim
        .strand_solver()
        .map_err(|e| CliError::input(format!("{scene}: {e}")))?;
    let mut components = solver.components(&sim.strands);
    let mut colliders = Vec::new();
    if let Some(c) = &sim.scalp_collider {
        colliders.push(ColliderReport {
            name: "scalp".into(),
            shape: "the scalp mesh".into(),
            motion: if sim.scalp_deforms() {
                "the scalp's deformation ([scalp.mesh]) and [scalp.motion]".into()
            } else {
                "the scalp's [scalp.motion]".into()
            },
            thickness: c.thickness,
            friction: c.friction,
        });
    }
    for (i, c) in sim.colliders.iter().enumerate() {
        colliders.push(collider(i, c));
    }
    if !colliders.is_empty() {
        components.insert(Component::Contacts);
    }
    let points = sim.strands.point_count();
    let substeps = solver.substeps();
    let steps = sim.settings.steps;
    let frames = sim.last_frame - sim.first_frame;
    let limit = |x: f64| x.is_finite().then_some(x);
    Ok(SceneReport {
        scene: scene.to_string(),
        strands: sim.strands.len(),
        points,
        frames: [sim.first_frame, sim.last_frame],
        fps: sim.settings.fps,
        model: sim.model.name(),
        rod: (sim.model == StrandModel::Rod).then_some(sim.rod),
        integrator: (sim.model == StrandModel::MassSpring)
            .then(|| integrator_name(sim.integrator.integrator)),
        integrator_reason: (sim.model == StrandModel::MassSpring && sim.integrator.auto)
            .then(|| sim.integrator.reason()),
        integrator_warning: sim.integrator.warning.clone(),
        steps,
        substeps,
        substeps_auto: matches!(sim.settings.substeps, Substeps::Auto),
        dt: solver.dt(),
        dt_bound: solver.dt_bound(),
        components: components.names(),
        colliders,
        hair_hair: sim.hair_hair,
        fields: sim.fields.iter().map(|f| field_kind(&f.kind)).collect(),
        guides: sim.guides_report.clone(),
        maps: sim.maps.clone(),
        regions: sim
            .regions
            .regions
            .iter()
            .map(|r| RegionReport {
                name: r.name.clone(),
                selection: r.selection.clone(),
                strands: r.strands.len(),
                params: r.params,
            })
            .collect(),
        budget: BudgetReport {
            memory_bytes: points as f64 * BYTES_PER_POINT as f64,
            memory_limit: (budget.memory_bytes != u64::MAX).then_some(budget.memory_bytes as f64),
            point_substeps: hairsys::budget::RunWork {
                points,
                substeps: f64::from(substeps),
                integrator: sim.integrator.integrator,
                steps,
                frames: f64::from(frames),
            }
            .point_substeps(),
            point_substeps_limit: limit(budget.point_substeps),
        },
    })
}

/// The report of `[[colliders]]` entry `i`.
fn collider(i: usize, c: &SceneCollider) -> ColliderReport {
    let shape = match &c.collider.shape {
        ColliderShape::Sphere { radius } => format!("sphere, radius {radius} m"),
        ColliderShape::Capsule {
            half_height,
            radius,
        } => format!("capsule, half height {half_height} m, radius {radius} m"),
        ColliderShape::Mesh(mesh) => match &c.animation {
            Some(a) => {
                let (first, last) = a.frames();
                format!(
                    "mesh, {} triangles, deforming: {} (frames {first}–{last})",
                    mesh.triangles().len(),
                    a.source
                )
            }
            None => format!("mesh, {} triangles", mesh.triangles().len()),
        },
    };
    let motion = match &c.motion {
        Motion::Fixed(pose) => format!("still at {pose}"),
        Motion::Keyed(m) => match m.keys.as_slice() {
            [] => "still".to_string(),
            [k] => format!(
                "still at translation {:?} m, rotation {:?}°",
                k.translation, k.rotation_deg
            ),
            keys => format!(
                "{} keys, frames {}–{}",
                keys.len(),
                keys[0].frame,
                keys[keys.len() - 1].frame
            ),
        },
    };
    ColliderReport {
        name: if c.name.is_empty() {
            format!("#{i}")
        } else {
            c.name.clone()
        },
        shape,
        motion,
        thickness: c.collider.thickness,
        friction: c.collider.friction,
    }
}

/// `value` as one line of JSON (`{"bend_stiffness":4.0}`), for the text report.
fn inline(value: &impl Serialize) -> String {
    serde_json::to_string(value).unwrap_or_else(|e| format!("({e})"))
}

/// The `[[fields]] type` of `kind`.
fn field_kind(kind: &FieldKind) -> &'static str {
    match kind {
        FieldKind::Wind { .. } => "wind",
        FieldKind::Vortex => "vortex",
        FieldKind::Turbulence { .. } => "turbulence",
        FieldKind::Drag => "drag",
        FieldKind::Force => "force",
    }
}

impl std::fmt::Display for SceneReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "{}: ok — {} strands, {} points, frames {}–{} at {} fps",
            self.scene, self.strands, self.points, self.frames[0], self.frames[1], self.fps
        )?;
        match &self.rod {
            Some(rod) => writeln!(
                f,
                "  model: {} (a = {} m, b/a = {}, E = {} Pa)",
                self.model, rod.semi_major_axis, rod.axis_ratio, rod.youngs_modulus
            )?,
            None => writeln!(f, "  model: {}", self.model)?,
        }
        if let Some(integrator) = self.integrator {
            match &self.integrator_reason {
                Some(why) => writeln!(f, "  integrator: {integrator} (\"auto\": {why})")?,
                None => writeln!(f, "  integrator: {integrator}")?,
            }
            if let Some(warning) = &self.integrator_warning {
                writeln!(f, "  warning: {warning}")?;
            }
        }
        writeln!(
            f,
            "  substeps: {} per step{} × {} step(s) per frame, dt = {:.3e} s (stability bound \
             2/ω = {:.3e} s)",
            self.substeps,
            if self.substeps_auto {
                " (\"auto\" resolved)"
            } else {
                ""
            },
            self.steps,
            self.dt,
            self.dt_bound
        )?;
        writeln!(f, "  components: {}", self.components.join(", "))?;
        if self.colliders.is_empty() {
            writeln!(f, "  colliders: none")?;
        }
        for c in &self.colliders {
            writeln!(
                f,
                "  collider {}: {}; motion: {}; thickness {} m, friction {}",
                c.name, c.shape, c.motion, c.thickness, c.friction
            )?;
        }
        match &self.hair_hair {
            Some(h) => writeln!(
                f,
                "  hair-hair: {} m cells, friction {}, repulsion {} m²/s² above volume fraction {}",
                h.cell_size, h.friction, h.repulsion, h.target_density
            )?,
            None => writeln!(f, "  hair-hair: off")?,
        }
        if self.fields.is_empty() {
            writeln!(f, "  force fields: none")?;
        } else {
            writeln!(f, "  force fields: {}", self.fields.join(", "))?;
        }
        if let Some(g) = &self.guides {
            writeln!(f, "  guides: {g}")?;
        }
        for m in &self.maps {
            let range = match m.range {
                Some([lo, hi]) => format!("{lo:.4}–{hi:.4} at {} roots", m.roots),
                None => "no scalp-rooted strands".into(),
            };
            writeln!(
                f,
                "  map {}: {}; {}; values {range}",
                m.name, m.source, m.purpose
            )?;
        }
        for r in &self.regions {
            writeln!(
                f,
                "  region {}: {} strands selected by {}; sets {}",
                r.name,
                r.strands,
                inline(&r.selection),
                inline(&r.params)
            )?;
        }
        let of = |limit: Option<f64>| match limit {
            Some(l) => format!("limit {l:.3e}"),
            None => "no limit (--allow-large)".into(),
        };
        write!(
            f,
            "  budget: memory {:.3e} bytes ({}), work {:.3e} point-substeps ({})",
            self.budget.memory_bytes,
            of(self.budget.memory_limit),
            self.budget.point_substeps,
            of(self.budget.point_substeps_limit)
        )
    }
}
