//! The scene-file door of the assembly ([`crate::build`]): [`SceneFile::build`] turns a parsed
//! scene into a [`Simulation`] — the scalp mesh and its motion, generated hair, guides and
//! simulation hairs, explicit strands, regions and painted maps, colliders, fields, the
//! integrator by the shared rule, then [`Simulation::settle`]. Every error names the scene
//! file, the section and key, and the fix.

use std::path::Path;

use hair_core::{
    Anchor, Collider, ColliderShape, Integrator, KernelChoice, RootFrame, SolverSettings,
    StrandInput, StrandModel, StrandSet, Substeps, TriMesh,
};
use hair_groom::{GenerateOptions, ObjOptions, Region, UpAxis};
use nalgebra::Vector3;

use super::{SceneCollider, Simulation};
use crate::scene::deforming::{self, DeformingSource, MeshAnimation};
use crate::scene::error::{ColliderError, MeshSourceError, StrandError};
use crate::scene::integrator::IntegratorChoice;
use crate::scene::maps::{MapsError, ScalpColorsError};
use crate::scene::{
    guides, integrator, map_primvars, ColliderShapeSection, ExplicitStrand, ScalpMesh, SceneError,
    SceneFile, SceneProblem, SubstepsValue,
};
use crate::scene::{maps, regions};

impl SceneFile {
    /// Refuses, before anything is generated, hair whose point count (from `[hair]`, generated
    /// `[guides]` and `[sim_hairs]`) is over [`Self::budget`]'s memory.
    fn check_point_budget(&self) -> Result<(), SceneError> {
        let s = &self.scene;
        let over = |e| self.error(SceneProblem::Budget(e));
        if let Some(h) = &s.hair {
            let points = h.count as f64 * (f64::from(h.segments) + 1.0);
            self.budget
                .check_points(
                    &format!(
                        "[hair] count = {} × (segments + 1 = {}) points",
                        h.count,
                        u64::from(h.segments) + 1
                    ),
                    points,
                )
                .map_err(over)?;
        }
        let mut per_guide = None;
        if let Some(g) = &s.guides {
            let per = f64::from(g.segments.unwrap_or(0)) + 1.0;
            per_guide = Some(per);
            if let Some(count) = g.count {
                self.budget
                    .check_points(
                        &format!("[guides] count = {count} × (segments + 1 = {per}) points"),
                        count as f64 * per,
                    )
                    .map_err(over)?;
            }
        }
        if let Some(h) = &s.sim_hairs {
            if let Some(count) = h.count {
                let per = h.points.map(|p| p as f64).or(per_guide).unwrap_or(1.0);
                self.budget
                    .check_points(
                        &format!("[sim_hairs] count = {count} × {per} points"),
                        count as f64 * per,
                    )
                    .map_err(over)?;
            }
        }
        Ok(())
    }

    /// Refuses a run whose force substeps (explicit or resolved from `"auto"` for its
    /// integrator, with the stability bound `bound` of its strands) exceed
    /// [`crate::budget::MAX_SUBSTEPS`], or whose work (`points` × substeps × their
    /// [`crate::budget::substep_weight`] × steps × frames) is over [`Self::budget`].
    fn check_work_budget(
        &self,
        settings: &SolverSettings,
        bound: &hair_core::StabilityBound,
        points: usize,
    ) -> Result<(), SceneError> {
        use crate::budget::MAX_SUBSTEPS;
        let s = &self.scene;
        let substeps = match settings.substeps {
            Substeps::Fixed(n) => f64::from(n),
            Substeps::Auto => {
                let wanted = f64::from(settings.resolved_substeps(bound));
                if wanted > f64::from(MAX_SUBSTEPS) {
                    return Err(self.error(SceneProblem::AutoSubsteps {
                        wanted,
                        bound: bound.dt_max,
                        stretch_stiffness: s.physics.stretch_stiffness,
                    }));
                }
                wanted.max(1.0)
            }
        };
        if settings.steps > MAX_SUBSTEPS {
            return Err(self.error(SceneProblem::Steps {
                steps: settings.steps,
            }));
        }
        let [first, last] = s.scene.frames;
        let frames = f64::from(last.saturating_sub(first));
        let work = crate::budget::RunWork {
            points,
            substeps,
            integrator: settings.integrator,
            steps: settings.steps,
            frames,
        };
        self.budget
            .check_run("", &work)
            .map_err(|e| self.error(SceneProblem::Budget(e)))
    }

    /// Validates the scene and builds everything a run needs.
    pub fn build(&self) -> Result<Simulation, SceneError> {
        let s = &self.scene;
        let err = |p: SceneProblem| self.error(p);
        let [first, last] = s.scene.frames;
        if !(s.scene.fps.is_finite() && s.scene.fps > 0.0) {
            return Err(err(SceneProblem::Fps { fps: s.scene.fps }));
        }
        if last <= first {
            return Err(err(SceneProblem::Frames { first, last }));
        }
        let substeps = match &s.solver.substeps {
            SubstepsValue::Word(w) if w == "auto" => Substeps::Auto,
            SubstepsValue::Count(n) if *n >= 1 && *n <= 1_000_000 => Substeps::Fixed(*n as u32),
            other => {
                return Err(err(SceneProblem::Substeps {
                    given: other.clone(),
                }))
            }
        };
        let mut settings = SolverSettings {
            fps: s.scene.fps,
            steps: s.solver.steps,
            substeps,
            damping_iterations: s.solver.damping_iterations,
            // `"auto"` is resolved once the strands and their regions are built.
            integrator: match s.solver.integrator {
                IntegratorChoice::Named(i) => i,
                IntegratorChoice::Auto => Integrator::SemiImplicitEuler,
            },
            max_strain: s.solver.max_strain,
            // The kernel copy changes speed, not bits: a run option, not part of the scene.
            kernel: KernelChoice::Auto,
        };
        settings
            .validate()
            .map_err(|e| err(SceneProblem::Solver(e)))?;
        s.physics
            .validate()
            .map_err(|e| err(SceneProblem::Physics(e)))?;
        match (s.solver.model, &s.rod) {
            (StrandModel::MassSpring, Some(_)) => return Err(err(SceneProblem::RodWithMassSpring)),
            (_, Some(rod)) => rod.validate().map_err(|e| err(SceneProblem::Rod(e)))?,
            _ => {}
        }
        s.scalp
            .motion
            .validate()
            .map_err(|e| err(SceneProblem::ScalpMotion(e)))?;

        self.check_point_budget()?;
        let (rest_mesh, scalp_animation) = self.scalp_mesh()?;
        let maps = self
            .scalp_maps(rest_mesh.as_ref())
            .map_err(|e| self.error(e))?;
        let mut strands = StrandSet::new();
        if let Some(hair) = &s.hair {
            let Some(mesh) = &rest_mesh else {
                return Err(err(SceneProblem::HairWithoutScalp));
            };
            let opts = GenerateOptions {
                count: hair.count,
                length: hair.length,
                segments: hair.segments,
                seed: hair.seed,
                radius: hair.radius,
                mass_per_length: hair.mass_per_length,
                goal_root: hair.goal_root,
                goal_tip: hair.goal_tip,
                length_variation: hair.length_variation,
                region: match hair.region {
                    None => Region::All,
                    Some(r) => Region::Cone {
                        direction: Vector3::from(r.direction),
                        max_angle_deg: r.max_angle_deg,
                    },
                },
            };
            let density = maps
                .density(mesh)
                .map_err(|e| self.error(MapsError::Map(e)))?;
            let mut inputs = hair_groom::generate_with_density(
                mesh,
                &opts,
                density.as_ref().map(|d| d as &dyn hair_groom::RootDensity),
            )
            .map_err(|e| err(SceneProblem::Hair(e)))?;
            if let Some(style) = &hair.style {
                let opts = style.options(&s.physics.gravity(), hair.seed);
                hair_groom::lay_over_scalp(&mut inputs, mesh, &opts)
                    .map_err(|e| err(SceneProblem::HairStyle(e)))?;
            }
            maps.scale_goal(&mut inputs, mesh, "[hair] strand")
                .map_err(|e| self.error(e))?;
            maps.trim_length(&mut inputs, mesh, "[hair] strand")
                .map_err(|e| self.error(e))?;
            for input in inputs {
                strands
                    .push(input)
                    .map_err(|e| err(SceneProblem::HairStrand(e)))?;
            }
        }
        let mut guided = None;
        // Each strand's nearest guide (sim hairs only), for `[[regions]]` selections.
        let mut nearest_guide = vec![None; strands.len()];
        if let Some(guides) = &s.guides {
            let Some(mesh) = &rest_mesh else {
                return Err(err(SceneProblem::GuidesWithoutScalp));
            };
            let mut built = guides::build(
                guides,
                s.sim_hairs.as_ref(),
                mesh,
                &self.base_dir,
                &s.physics.gravity(),
                &maps,
            )
            .map_err(|e| self.error(e))?;
            maps.scale_goal(&mut built.inputs, mesh, "sim hair")
                .map_err(|e| self.error(e))?;
            if s.solver.model != StrandModel::MassSpring {
                if guides.animation_keys().any() {
                    return Err(err(SceneProblem::GuideAnimationOfModel));
                }
                built.animation = None;
            }
            if let Some(a) = &mut built.animation {
                a.set_first_strand(strands.len());
            }
            for input in &built.inputs {
                strands
                    .push(input.clone())
                    .map_err(|e| err(SceneProblem::SimHairStrand(e)))?;
            }
            nearest_guide.extend(built.nearest_guide.iter().copied());
            guided = Some(built);
        } else if s.sim_hairs.is_some() {
            return Err(err(SceneProblem::SimHairsWithoutGuides));
        }
        for (i, st) in s.strands.iter().enumerate() {
            let strand = |source| err(SceneProblem::Strand { index: i, source });
            let input = explicit_strand(st).map_err(strand)?;
            strands
                .push(input)
                .map_err(|e| strand(StrandError::Invalid(e)))?;
        }
        let strips = crate::scene::strips::build_into(s, rest_mesh.as_ref(), &mut strands)
            .map_err(|e| self.error(e))?;
        if strands.is_empty() {
            return Err(err(SceneProblem::NoHair));
        }
        nearest_guide.resize(strands.len(), None);
        let regions = self.regions(
            &mut strands,
            rest_mesh.as_ref(),
            &nearest_guide,
            guided.as_ref(),
            &maps,
        )?;
        let scales = regions
            .scales(&s.physics, strands.len())
            .map_err(|e| err(SceneProblem::RegionScales(e)))?;
        let child_maps = maps
            .child_factors(&strands, rest_mesh.as_ref())
            .map_err(|e| self.error(e))?;
        let map_summaries = maps
            .summaries(&strands, rest_mesh.as_ref())
            .map_err(|e| self.error(MapsError::Map(e)))?;
        let colliders = self.colliders()?;
        let contact = self.collider_motion(&colliders);
        let (integrator, bound) = crate::build::choose_integrator(
            s.solver.integrator,
            s.solver.model,
            &mut settings,
            &strands,
            &s.physics,
            &scales,
            &contact,
        );
        self.check_work_budget(&settings, &bound, strands.point_count())?;
        if let Some(c) = &s.contacts {
            c.validate().map_err(|e| err(SceneProblem::Contacts(e)))?;
        }
        if let Some(c) = &s.children {
            c.settings().map_err(|e| self.error(e))?;
        }
        if s.scalp.collider.is_some() && rest_mesh.is_none() {
            return Err(err(SceneProblem::ScalpColliderWithoutScalp));
        }
        let hair_hair = s.hair_hair;
        if let Some(h) = &hair_hair {
            h.validate().map_err(|e| err(SceneProblem::HairHair(e)))?;
        }
        let fields = s
            .fields
            .iter()
            .enumerate()
            .map(|(i, f)| f.field(i))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| self.error(e))?;
        if s.solver.model == StrandModel::Rod && (hair_hair.is_some() || !fields.is_empty()) {
            return Err(err(SceneProblem::MassSpringOnly));
        }
        if let Some(i) = fields.iter().position(|f| f.moves_air()) {
            if s.physics.air_drag <= 0.0 {
                return Err(err(SceneProblem::MovingAirWithoutDrag { field: i }));
            }
        }
        let mut sim = Simulation {
            strands,
            settings,
            integrator,
            params: s.physics,
            first_frame: first,
            last_frame: last,
            rest_mesh,
            scalp_colors: self.scalp_colors().map_err(|e| self.error(e))?,
            scalp_animation,
            motion: crate::rig::Motion::Keyed(s.scalp.motion.clone()),
            colliders,
            scalp_collider: s.scalp.collider,
            contact_settings: s.contacts.unwrap_or_default(),
            guides_report: guided.as_ref().map(|g| g.report.clone()),
            guide_animation: guided.as_mut().and_then(|g| g.animation.take()),
            guides: guided.map(|g| g.guides).unwrap_or_default(),
            hair_hair,
            fields,
            model: s.solver.model,
            rod: s.rod.unwrap_or_default(),
            inextensibility: s
                .solver
                .inextensibility
                .then(hair_core::Inextensibility::default),
            strips,
            regions,
            strand_scales: None,
            child_maps,
            maps: map_summaries,
        };
        sim.settle(s.solver.sag_free)
            .map_err(|e| err(SceneProblem::Settle(e)))?;
        Ok(sim)
    }

    /// Resolves `[[regions]]` and `[maps.stiffness]` over `strands` (applying their mass and
    /// radius factors); refused for the rod and strip models.
    fn regions(
        &self,
        strands: &mut StrandSet,
        mesh: Option<&TriMesh>,
        nearest_guide: &[Option<usize>],
        guided: Option<&guides::GuidedHair>,
        maps: &maps::ScalpMaps,
    ) -> Result<regions::Regions, SceneError> {
        let s = &self.scene;
        if s.regions.is_empty() && maps.get("stiffness").is_none() {
            return Ok(regions::Regions::default());
        }
        if s.solver.model != StrandModel::MassSpring {
            return Err(self.error(SceneProblem::RegionsOfModel));
        }
        let roots = regions::StrandRoots {
            mesh,
            nearest_guide,
            guide_count: guided.map_or(0, |g| g.guides.len()),
        };
        regions::Regions::build(&s.regions, &s.physics, strands, &roots, maps)
            .map_err(|e| self.error(e))
    }

    /// How fast `colliders` move against their size over the shot, for `"auto"`'s contact
    /// condition ([`integrator`]): per collider the fastest point of its rigid motion plus the
    /// fastest vertex of its deformation, against its bounding radius.
    fn collider_motion(&self, colliders: &[SceneCollider]) -> integrator::ContactLoad {
        let [first, last] = self.scene.scene.frames;
        let fps = f64::from(self.scene.scene.fps);
        integrator::ContactLoad::from_colliders(colliders.iter().map(|c| {
            let radius = f64::from(c.collider.shape.bounding_radius());
            let rigid =
                integrator::fastest_surface_speed(|f| c.motion.at(f), radius, first, last, fps);
            let deforming = c
                .animation
                .as_ref()
                .map_or(0.0, |a| a.fastest_vertex_speed(fps));
            (rigid + deforming, radius)
        }))
    }

    /// Loads and checks the `[[colliders]]`.
    fn colliders(&self) -> Result<Vec<SceneCollider>, SceneError> {
        let mut out = Vec::new();
        for (i, c) in self.scene.colliders.iter().enumerate() {
            let err = |source| {
                self.error(SceneProblem::Collider {
                    index: i,
                    name: c.name.clone(),
                    source,
                })
            };
            let mut animation = None;
            let shape = match &c.shape {
                ColliderShapeSection::Sphere { radius } => {
                    ColliderShape::Sphere { radius: *radius }
                }
                ColliderShapeSection::Capsule {
                    half_height,
                    radius,
                } => ColliderShape::Capsule {
                    half_height: *half_height,
                    radius: *radius,
                },
                ColliderShapeSection::Obj {
                    path,
                    scale,
                    up_axis,
                } => ColliderShape::Mesh(
                    self.load_obj(path, *scale, *up_axis)
                        .map_err(|e| err(ColliderError::Shape(MeshSourceError::Obj(e))))?,
                ),
                ColliderShapeSection::Usd(_) | ColliderShapeSection::ObjSequence(_) => {
                    let source = c.shape.deforming().expect("a deforming shape");
                    let (rest, anim) = self
                        .load_deforming(source)
                        .map_err(|e| err(ColliderError::Shape(e.into())))?;
                    animation = Some(anim);
                    ColliderShape::Mesh(rest)
                }
            };
            let collider = Collider {
                shape,
                thickness: c.thickness,
                friction: c.friction,
            };
            collider
                .validate(i)
                .map_err(|e| err(ColliderError::Invalid(e)))?;
            c.motion
                .validate()
                .map_err(|e| err(ColliderError::Motion(e)))?;
            out.push(SceneCollider {
                name: c.name.clone(),
                collider,
                motion: crate::rig::Motion::Keyed(c.motion.clone()),
                animation,
            });
        }
        Ok(out)
    }

    /// The per-vertex colors (`v x y z r g b`) of the scene's OBJ scalp, in the vertex order of the
    /// scalp mesh the scene builds; `None` for another scalp or an OBJ without colors on every vertex.
    fn scalp_colors(&self) -> Result<Option<Vec<[f32; 3]>>, ScalpColorsError> {
        let ScalpMesh::Obj { path, .. } = &self.scene.scalp.mesh else {
            return Ok(None);
        };
        let path = self.base_dir.join(path);
        // The same bounded OBJ reader the scalp itself is loaded with (vertices in its order; a
        // hostile face index is an error, not a panic).
        let Some(colors) =
            hair_groom::load_obj_vertex_colors(&path).map_err(|source| ScalpColorsError::Read {
                path: path.clone(),
                source,
            })?
        else {
            return Ok(None);
        };
        if let Some(i) = colors.iter().position(|c| !c.iter().all(|x| x.is_finite())) {
            return Err(ScalpColorsError::NotFinite {
                path,
                vertex: i,
                color: colors[i],
            });
        }
        Ok(Some(colors))
    }

    /// The scene's `[maps.NAME]`, read and checked against the scalp at rest `mesh`.
    fn scalp_maps(&self, mesh: Option<&TriMesh>) -> Result<maps::ScalpMaps, MapsError> {
        let sections = &self.scene.maps;
        if sections.is_empty() {
            return Ok(maps::ScalpMaps::none());
        }
        let Some(mesh) = mesh else {
            return Err(MapsError::NoScalp);
        };
        if sections.contains_key("density")
            && self.scene.hair.is_none()
            && self.scene.sim_hairs.is_none()
        {
            return Err(MapsError::DensityWithoutHair);
        }
        if sections.contains_key("sim_weight") && self.scene.guides.is_none() {
            return Err(MapsError::SimWeightWithoutGuides);
        }
        let mut used: Vec<&str> = self
            .scene
            .guides
            .as_ref()
            .map(|g| g.animation_keys().map_names())
            .unwrap_or_default();
        used.extend(
            self.scene
                .regions
                .iter()
                .filter_map(|r| r.select.map.as_ref().map(|m| m.name.as_str())),
        );
        maps::ScalpMaps::load(
            sections,
            &self.base_dir,
            mesh,
            || self.scalp_colors(),
            |map, name, channel| map_primvars::scalp_primvar(self, map, name, channel),
            &used,
        )
    }

    fn scalp_mesh(&self) -> Result<(Option<TriMesh>, Option<MeshAnimation>), SceneError> {
        let err = |e: MeshSourceError| self.error(SceneProblem::ScalpMesh(e));
        if let Some(source) = self.scene.scalp.mesh.deforming() {
            let (rest, animation) = self.load_deforming(source).map_err(|e| err(e.into()))?;
            return Ok((Some(rest), Some(animation)));
        }
        let rest = match &self.scene.scalp.mesh {
            ScalpMesh::None => None,
            ScalpMesh::BuiltinHead => Some(hair_groom::builtin_head()),
            ScalpMesh::UvSphere {
                radius,
                segments,
                rings,
            } => Some(
                hair_groom::uv_sphere(*radius, *segments, *rings)
                    .map_err(|e| err(MeshSourceError::UvSphere(e)))?,
            ),
            ScalpMesh::Obj {
                path,
                scale,
                up_axis,
            } => Some(
                self.load_obj(path, *scale, *up_axis)
                    .map_err(|e| err(MeshSourceError::Obj(e)))?,
            ),
            ScalpMesh::Usd(_) | ScalpMesh::ObjSequence(_) => None,
        };
        Ok((rest, None))
    }

    /// Reads a deforming mesh over the scene's frames (see [`deforming`]).
    fn load_deforming(
        &self,
        source: DeformingSource<'_>,
    ) -> Result<(TriMesh, MeshAnimation), deforming::DeformingError> {
        let [first, last] = self.scene.scene.frames;
        deforming::load(source, &self.base_dir, (first, last), &self.budget)
    }

    /// Loads an OBJ mesh named in the scene (path relative to the scene file).
    fn load_obj(
        &self,
        path: &Path,
        scale: f32,
        up_axis: UpAxis,
    ) -> Result<TriMesh, hair_groom::GroomError> {
        let opts = ObjOptions { scale, up_axis };
        hair_groom::load_obj(&self.base_dir.join(path), &opts)
    }
}

/// Builds an explicit strand: root frame at its first point with world axes, carried by the
/// scalp's rigid motion.
fn explicit_strand(st: &ExplicitStrand) -> Result<StrandInput, StrandError> {
    let n = st.points.len();
    if n < 2 {
        return Err(StrandError::TooFewPoints { points: n });
    }
    if let Some(i) = st
        .points
        .iter()
        .position(|p| !p.iter().all(|c| c.is_finite()))
    {
        return Err(StrandError::NotFinite { point: i });
    }
    let root = Vector3::from(st.points[0]);
    let rest: Vec<Vector3<f32>> = st.points.iter().map(|p| Vector3::from(*p) - root).collect();
    let anchor = Anchor::Body(RootFrame::at(root));
    if !(st.mass_per_length.is_finite() && st.mass_per_length > 0.0) {
        return Err(StrandError::MassPerLength {
            value: st.mass_per_length,
        });
    }
    let mut input = StrandInput::uniform(
        anchor,
        rest,
        st.mass_per_length,
        st.radius,
        st.goal[0],
        st.goal[1],
    );
    if let Some(masses) = &st.masses {
        if masses.len() != n {
            return Err(StrandError::Masses {
                given: masses.len(),
                points: n,
            });
        }
        input.mass.clone_from(masses);
    }
    for &i in &st.pinned {
        if i >= n {
            return Err(StrandError::Pinned {
                point: i,
                points: n,
            });
        }
        input.pinned[i] = true;
    }
    Ok(input)
}

pub(super) use crate::scene::error::named;
