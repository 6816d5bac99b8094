//! The TOML scene file: its schema, loading with clear errors, and building the library objects.
//!
//! A scene names the scalp (built-in head, UV sphere, OBJ file or none) and its keyframed rigid
//! motion, generated hair and/or explicit strands given as point lists, physics parameters, the
//! solver's time stepping, and the colliders hair collides with: `[scalp.collider]` (the scalp
//! mesh, for its own hair), `[[colliders]]` (spheres, capsules and OBJ meshes with keyframed rigid
//! motion, thickness and friction) and `[contacts]` (see `hair_core::ContactSettings`), voxel
//! hair–hair interaction `[hair_hair]` and force fields `[[fields]]` (see [`crate::scene::fields`]), and named regions of hair with their own physical parameters `[[regions]]` (see [`crate::scene::regions`]). Unknown keys are rejected; every error names the file, the field
//! and the fix. `hairsys scene init` prints the built-in default scene with every key commented.

use std::path::{Path, PathBuf};

use hair_core::model::strips::{HeadShape, StripSolver};
use hair_core::{
    Anchor, Collider, ColliderId, ColliderShape, Colliders, ContactSettings, HairError,
    HairHairSettings, HairParams, Integrator, KernelChoice, MassSpringSolver, RodParams, RodSolver,
    RootFrame, Scalp, SolverSettings, StrandInput, StrandModel, StrandScales, StrandSet,
    StrandSolver, Substeps, TriMesh,
};
use hair_groom::{GenerateOptions, ObjOptions, Region, UpAxis};

use crate::budget::Budget;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

pub mod children;
pub mod deforming;
pub mod fields;
pub mod guide_anim;
pub mod guides;
pub mod integrator;
pub mod map_primvars;
pub mod maps;
pub mod motion;
pub mod regions;
pub mod strips;
pub mod style;
pub mod version;

pub use version::SCENE_VERSION;

use deforming::{DeformingSource, MeshAnimation, ObjSequenceSection, UsdMeshSection};
use fields::FieldSection;
use guides::{GuidesSection, SimHairsSection};
use integrator::{IntegratorChoice, ResolvedIntegrator};
use motion::RigidMotion;

/// The built-in default scene, fully commented (printed by `hairsys scene init`).
pub const DEFAULT_SCENE: &str = include_str!("../../../scenes/default.toml");

/// A scene file could not be used. Displays as `FILE: message`.
#[derive(Debug, thiserror::Error)]
#[error("{file}: {message}")]
pub struct SceneError {
    /// The scene file (or `<built-in default scene>`).
    pub file: String,
    /// What is wrong, naming the field and the fix.
    pub message: String,
}

/// The whole scene file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// `version`: the scene format version, 1 to [`SCENE_VERSION`]; absent = 1 (files written
    /// before the key existed). Left out of the serialised scene when 1, so the scene hash that
    /// guards `--resume` is the same with or without the line.
    #[serde(
        default = "version::first_version",
        skip_serializing_if = "version::is_first"
    )]
    pub version: u32,
    /// `[scene]`: name, frame range, frame rate.
    pub scene: SceneSection,
    /// `[solver]`: time stepping.
    #[serde(default)]
    pub solver: SolverSection,
    /// `[physics]`: material and environment (see [`HairParams`]).
    #[serde(default)]
    pub physics: HairParams,
    /// `[scalp]`: the mesh hair grows from and its motion.
    #[serde(default)]
    pub scalp: ScalpSection,
    /// `[hair]`: hair generated on the scalp.
    #[serde(default)]
    pub hair: Option<HairSection>,
    /// `[[strands]]`: explicit strands given as point lists.
    #[serde(default)]
    pub strands: Vec<ExplicitStrand>,
    /// `[guides]`: guide hairs (imported and snapped, or generated) defining rest shapes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub guides: Option<GuidesSection>,
    /// `[sim_hairs]`: simulation hairs interpolated from the guides.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sim_hairs: Option<SimHairsSection>,
    /// `[[colliders]]`: spheres, capsules and OBJ meshes hair collides with, each with keyframed
    /// rigid motion.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub colliders: Vec<ColliderSection>,
    /// `[contacts]`: fast-motion stepping and push-out speed of hair–object collision (see
    /// [`ContactSettings`]); absent = the defaults.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contacts: Option<ContactSettings>,
    /// `[rod]`: material and projection of the rod model (see [`RodParams`]); only with
    /// `[solver] model = "rod"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rod: Option<RodParams>,
    /// `[hair_hair]`: voxel hair–hair friction and repulsion (see [`HairHairSettings`]; every key
    /// optional, `cell_size` 0.01 m by default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hair_hair: Option<HairHairSettings>,
    /// `[[fields]]`: force fields (wind, vortex, turbulence, drag, force; see [`fields`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub fields: Vec<FieldSection>,
    /// `[children]`: render children for `hairsys render-children export` (see
    /// [`crate::scene::children`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub children: Option<crate::scene::children::ChildrenSection>,
    /// `[strips]`: the hair-strip model (see [`crate::scene::strips`]); only with
    /// `[solver] model = "strips"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub strips: Option<crate::scene::strips::StripsSection>,
    /// `[maps.NAME]`: painted maps over the scalp (see [`crate::scene::maps`]).
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub maps: std::collections::BTreeMap<String, crate::scene::maps::MapSection>,
    /// `[[regions]]`: named regions of the hair with their own physical parameters (see
    /// [`crate::scene::regions`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub regions: Vec<regions::RegionPhysicsSection>,
}

/// `[scene]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneSection {
    /// Free-form name, shown in reports.
    #[serde(default)]
    pub name: String,
    /// Frames per second.
    #[serde(default = "default_fps")]
    pub fps: f32,
    /// First and last frame `[first, last]`; the hair is at rest at the first.
    pub frames: [u32; 2],
}

fn default_fps() -> f32 {
    24.0
}

/// `substeps = "auto"` or a count.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum SubstepsValue {
    /// A fixed count.
    Count(i64),
    /// `"auto"`.
    Word(String),
}

/// `[solver]`.
///
/// Not [`SolverSettings`] itself, on purpose: the frame rate comes from `[scene] fps`,
/// `substeps` is spelled `"auto"` or a count (checked with a range in the error), the kernel
/// copy is a run option rather than part of the scene, and the section also chooses the strand
/// model and its projections (`model`, `inextensibility`, `sag_free`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SolverSection {
    /// `"auto"` (default: the cheaper of semi-implicit Euler and BDF2 for the scene, see
    /// [`integrator`]), `"semi-implicit-euler"`, `"bdf2"`, `"implicit-euler"`, `"xpbd"` or
    /// `"explicit-euler"`.
    pub integrator: IntegratorChoice,
    /// Collision steps per frame.
    pub steps: u32,
    /// Force substeps per step: a count or `"auto"`.
    pub substeps: SubstepsValue,
    /// Iterations of the damping sub-loop per substep (0 = off).
    pub damping_iterations: u32,
    /// Strain limit after each substep (0 = inextensible); absent = off.
    pub max_strain: Option<f32>,
    /// Strand model: `"mass-spring"` (default) or `"rod"` (seed 002's discrete rod, material
    /// in `[rod]`).
    #[serde(skip_serializing_if = "StrandModel::is_mass_spring")]
    pub model: StrandModel,
    /// Inextensibility projection after each substep (seed 002, "Constraints"; mass-spring model
    /// only): segment lengths restored, stretching velocities removed. Off by default.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub inextensibility: bool,
    /// Sag-free initialisation (mass-spring model): rest directions solved so that the groom is
    /// a static equilibrium under gravity at the first frame (see
    /// `hair_core::integrate::sag_free`); hair within two strand radii of a collider (the scalp
    /// collider included) rests on it, which carries the outward part of its weight. Off by
    /// default.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub sag_free: bool,
}

impl Default for SolverSection {
    fn default() -> Self {
        Self {
            integrator: IntegratorChoice::Auto,
            steps: 1,
            substeps: SubstepsValue::Word("auto".into()),
            damping_iterations: 10,
            max_strain: None,
            model: StrandModel::MassSpring,
            inextensibility: false,
            sag_free: false,
        }
    }
}

/// `[scalp]`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScalpSection {
    /// `[scalp.mesh]`: which mesh.
    #[serde(default)]
    pub mesh: ScalpMesh,
    /// `[scalp.motion]`: keyframed rigid motion of the scalp (and of explicit strands' roots).
    #[serde(default)]
    pub motion: RigidMotion,
    /// `[scalp.collider]`: present = the scalp mesh is a collider for its own hair.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub collider: Option<ScalpCollider>,
}

/// `[scalp.collider]`: the scalp mesh as a collider for the hair rooted on it (it follows the
/// scalp's motion).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScalpCollider {
    /// Distance kept between hair and the scalp, m, on top of the hair radius.
    #[serde(default)]
    pub thickness: f32,
    /// Coulomb friction coefficient (≥ 0).
    #[serde(default)]
    pub friction: f32,
}

/// `[[colliders]]`: one collider.
///
/// Not [`Collider`] itself: the file names an OBJ path (relative to the scene file) where the
/// library holds the loaded mesh, and adds a name and keyframed motion.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ColliderSection {
    /// Free-form name, shown in messages.
    #[serde(default)]
    pub name: String,
    /// `[colliders.shape]`: the geometry, in the collider's body space.
    pub shape: ColliderShapeSection,
    /// Distance kept between hair and the surface, m, on top of the hair radius (≥ 0). Open
    /// meshes (shells) should have a few hair radii.
    #[serde(default)]
    pub thickness: f32,
    /// Coulomb friction coefficient (≥ 0): 0 frictionless, about 0.3 hair on skin.
    #[serde(default)]
    pub friction: f32,
    /// `[colliders.motion]`: keyframed rigid motion (no keys = fixed at the origin).
    #[serde(default)]
    pub motion: RigidMotion,
}

/// `[colliders.shape]`, chosen by `kind`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum ColliderShapeSection {
    /// A sphere centred at the body origin.
    Sphere {
        /// Radius, m.
        radius: f32,
    },
    /// A capsule along the body z axis, centred at the body origin.
    Capsule {
        /// Distance from the origin to each end cap's centre, m.
        half_height: f32,
        /// Radius, m.
        radius: f32,
    },
    /// A triangle mesh from an OBJ file. Closed meshes are solids; open or non-manifold meshes
    /// are two-sided shells (see `hair_core::contacts::collider`).
    Obj {
        /// Path, relative to the scene file.
        path: PathBuf,
        /// Multiplier from file units to meters.
        #[serde(default = "one")]
        scale: f32,
        /// The file's up axis: `"z"` (default) or `"y"` (converted to Z up).
        #[serde(default)]
        up_axis: UpAxis,
    },
    /// A deforming (or moving) USD `Mesh` prim, read at every frame (see [`deforming`]); its
    /// vertices are the collider's body space, placed by `[colliders.motion]`.
    Usd(UsdMeshSection),
    /// A numbered OBJ sequence `body.####.obj`, one file per frame (see [`deforming`]).
    ObjSequence(ObjSequenceSection),
}

impl ColliderShapeSection {
    /// The deforming source of this shape, if it is one.
    pub fn deforming(&self) -> Option<DeformingSource<'_>> {
        match self {
            Self::Usd(s) => Some(DeformingSource::Usd(s)),
            Self::ObjSequence(s) => Some(DeformingSource::ObjSequence(s)),
            _ => None,
        }
    }
}

/// `[scalp.mesh]`, chosen by `kind`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum ScalpMesh {
    /// No mesh: only explicit strands (rooted in body space).
    #[default]
    None,
    /// The built-in head (meters, Z up, crown at about 0.22 m).
    BuiltinHead,
    /// A UV sphere centred at the origin.
    UvSphere {
        /// Radius, m.
        radius: f32,
        /// Segments around the equator.
        segments: u32,
        /// Rings from pole to pole.
        rings: u32,
    },
    /// A triangle mesh from an OBJ file.
    Obj {
        /// Path, relative to the scene file.
        path: PathBuf,
        /// Multiplier from file units to meters.
        #[serde(default = "one")]
        scale: f32,
        /// The file's up axis: `"z"` (default) or `"y"` (converted to Z up).
        #[serde(default)]
        up_axis: UpAxis,
    },
    /// A deforming USD `Mesh` prim, read at every frame (see [`deforming`]): roots follow
    /// their mesh samples on it.
    Usd(UsdMeshSection),
    /// A deforming mesh as a numbered OBJ sequence `body.####.obj` (see [`deforming`]).
    ObjSequence(ObjSequenceSection),
}

impl ScalpMesh {
    /// The deforming source of this scalp, if it is one.
    pub fn deforming(&self) -> Option<DeformingSource<'_>> {
        match self {
            Self::Usd(s) => Some(DeformingSource::Usd(s)),
            Self::ObjSequence(s) => Some(DeformingSource::ObjSequence(s)),
            _ => None,
        }
    }
}

fn one() -> f32 {
    1.0
}

/// `[hair]`: hair generated on the scalp (see [`GenerateOptions`]).
///
/// Not [`GenerateOptions`] itself, on purpose: `count`, `length` and `segments` are required
/// here (a scene that grows hair says how much), and `region` is an optional cone table where
/// the library has the [`Region`] enum.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HairSection {
    /// Number of strands.
    pub count: usize,
    /// Strand length, m.
    pub length: f32,
    /// Segments per strand.
    pub segments: u32,
    /// Seed of the root distribution.
    #[serde(default)]
    pub seed: u64,
    /// Strand (wisp) radius, m.
    #[serde(default = "default_radius")]
    pub radius: f32,
    /// Linear density, kg/m.
    #[serde(default = "default_density")]
    pub mass_per_length: f32,
    /// Goal weight at the root, 0–1.
    #[serde(default)]
    pub goal_root: f32,
    /// Goal weight at the tip, 0–1.
    #[serde(default)]
    pub goal_tip: f32,
    /// Random shortening, fraction of the length in [0, 1).
    #[serde(default)]
    pub length_variation: f32,
    /// Where on the scalp hair grows: `{ direction = [x, y, z], max_angle_deg = a }`.
    #[serde(default)]
    pub region: Option<RegionSection>,
    /// `[hair.style]`: lay the hair over the scalp (combed, parted, lifted, falling) instead of
    /// growing it straight along the normals.
    #[serde(default)]
    pub style: Option<style::StyleSection>,
}

fn default_radius() -> f32 {
    1e-3
}

fn default_density() -> f32 {
    1e-3
}

/// A cone of surface normals: `{ direction = [x, y, z], max_angle_deg = a }` (absent = the whole
/// scalp, [`Region::All`]; TOML has no spelling for an enum's unit variant beside a table).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionSection {
    /// Axis of the cone (any length).
    pub direction: [f32; 3],
    /// Half-angle, degrees.
    pub max_angle_deg: f32,
}

impl RegionSection {
    /// The cone as a unit axis and the cosine of its half-angle (a root normal `n` is in it
    /// when `n · axis ≥ cos`), for selections named `what` in errors: a zero or non-finite
    /// direction, or a half-angle outside [0, 180] degrees, is refused.
    pub(crate) fn cone(&self, what: &str) -> Result<(Vector3<f32>, f32), String> {
        let axis = Vector3::from(self.direction);
        if !(axis.iter().all(|c| c.is_finite())
            && axis.norm() > 0.0
            && (0.0..=180.0).contains(&self.max_angle_deg))
        {
            return Err(format!(
                "{what} region: give a non-zero direction and max_angle_deg in [0, 180]"
            ));
        }
        Ok((axis.normalize(), self.max_angle_deg.to_radians().cos()))
    }
}

/// `[[strands]]`: one strand given as a point list (world coordinates at the first frame, m).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExplicitStrand {
    /// Points from root to tip, m.
    pub points: Vec<[f32; 3]>,
    /// Indices of points held at their rest position (the root, 0, always is).
    #[serde(default)]
    pub pinned: Vec<usize>,
    /// Linear density, kg/m (masses lumped at the points), unless `masses` is given.
    #[serde(default = "default_density")]
    pub mass_per_length: f32,
    /// Per-point masses, kg (overrides `mass_per_length`).
    #[serde(default)]
    pub masses: Option<Vec<f32>>,
    /// Radius, m.
    #[serde(default = "default_radius")]
    pub radius: f32,
    /// Goal weight at root and tip `[root, tip]`, 0–1.
    #[serde(default)]
    pub goal: [f32; 2],
}

/// A loaded scene: where it came from, its text, the parsed schema and its hash.
#[derive(Debug, Clone)]
pub struct SceneFile {
    /// The file path, or `<built-in default scene>`.
    pub origin: String,
    /// Directory relative paths in the scene resolve against.
    pub base_dir: PathBuf,
    /// The scene text as read.
    pub text: String,
    /// The parsed scene.
    pub scene: Scene,
    /// Memory and time limits [`Self::build`] checks before allocating (default
    /// [`Budget::default`]; a host or `--allow-large` lifts them).
    pub budget: Budget,
}

/// Largest scene file read, bytes (16 MiB): a scene is a page of TOML text (the default is
/// under 10 KiB); anything larger is the wrong file, and is refused before it is read.
pub const MAX_SCENE_FILE_BYTES: u64 = 16 << 20;

impl SceneFile {
    /// The built-in default scene.
    pub fn builtin_default() -> Self {
        Self::parse(
            DEFAULT_SCENE,
            "<built-in default scene>",
            PathBuf::from("."),
        )
        .expect("the built-in default scene parses (checked by a test)")
    }

    /// Reads and parses a scene file: a regular file of at most [`MAX_SCENE_FILE_BYTES`] (a
    /// device, FIFO or directory is refused by name before it is opened).
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let origin = path.display().to_string();
        let bytes =
            hair_groom::input_file::read_regular_file(path, MAX_SCENE_FILE_BYTES).map_err(|e| {
                SceneError {
                    file: origin.clone(),
                    message: format!("cannot read the scene file: {e}"),
                }
            })?;
        let text = String::from_utf8(bytes).map_err(|e| SceneError {
            file: origin.clone(),
            message: format!(
                "not a text file (byte {} is not UTF-8); a scene is TOML text",
                e.utf8_error().valid_up_to()
            ),
        })?;
        let base_dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Self::parse(&text, &origin, base_dir)
    }

    /// Parses scene text; `origin` names it in errors. A `version` newer than [`SCENE_VERSION`]
    /// is refused (see [`version`]).
    pub fn parse(text: &str, origin: &str, base_dir: PathBuf) -> Result<Self, SceneError> {
        version::check(text).map_err(|message| SceneError {
            file: origin.to_string(),
            message,
        })?;
        let scene: Scene = toml::from_str(text).map_err(|e| SceneError {
            file: origin.to_string(),
            message: format!("not a valid scene: {}", e.to_string().trim_end()),
        })?;
        Ok(Self {
            origin: origin.to_string(),
            base_dir,
            text: text.to_string(),
            scene,
            budget: Budget::default(),
        })
    }

    /// SHA-256 (hex) of the parsed scene and the bytes of every file it references, so edits to
    /// comments do not change it but any change to what is simulated does.
    pub fn hash(&self) -> Result<String, SceneError> {
        let mut h = Sha256::new();
        // `[children]` shapes render children only, never the simulation: a cache stays valid
        // for resuming when the children settings change.
        let simulated = Scene {
            children: None,
            ..self.scene.clone()
        };
        h.update(serde_json::to_vec(&simulated).expect("a scene always serialises"));
        if let ScalpMesh::Obj { path, .. } = &self.scene.scalp.mesh {
            let full = self.base_dir.join(path);
            let bytes = std::fs::read(&full).map_err(|e| self.error(format!(
                "[scalp.mesh] path = {}: cannot read {} ({e}); fix the path (relative to the scene file)",
                path.display(),
                full.display()
            )))?;
            h.update(bytes);
        }
        let frames = (self.scene.scene.frames[0], self.scene.scene.frames[1]);
        let sources = std::iter::once((
            "[scalp.mesh]".to_string(),
            self.scene.scalp.mesh.deforming(),
        ))
        .chain(
            self.scene
                .colliders
                .iter()
                .enumerate()
                .map(|(i, c)| (format!("[[colliders]] #{i} shape"), c.shape.deforming())),
        );
        for (field, source) in sources {
            let Some(source) = source else { continue };
            let files = deforming::hashed_files(source, &self.base_dir, frames)
                .map_err(|e| self.error(format!("{field}: {e}")))?;
            for full in files {
                let bytes = std::fs::read(&full).map_err(|e| {
                    self.error(format!(
                        "{field}: cannot read {} ({e}); fix the path (relative to the scene file)",
                        full.display()
                    ))
                })?;
                h.update(bytes);
            }
        }
        for (i, c) in self.scene.colliders.iter().enumerate() {
            if let ColliderShapeSection::Obj { path, .. } = &c.shape {
                let full = self.base_dir.join(path);
                let bytes = std::fs::read(&full).map_err(|e| {
                    self.error(format!(
                        "[[colliders]] #{i} shape path = {}: cannot read {} ({e}); fix the path \
                         (relative to the scene file)",
                        path.display(),
                        full.display()
                    ))
                })?;
                h.update(bytes);
            }
        }
        Ok(h.finalize().iter().map(|b| format!("{b:02x}")).collect())
    }

    /// Refuses, before anything is generated, hair whose point count (from `[hair]`, generated
    /// `[guides]` and `[sim_hairs]`) is over [`Self::budget`]'s memory.
    fn check_point_budget(&self) -> Result<(), SceneError> {
        let s = &self.scene;
        let over = |e: crate::budget::OverBudget| self.error(e.to_string());
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
                    return Err(self.error(format!(
                        "[solver] substeps = \"auto\" resolves to {wanted:.3e} force substeps per \
                         step (limit {MAX_SUBSTEPS}): the stability bound {:.3e} s is set by \
                         [physics] stretch_stiffness = {} N over the mass of a segment \
                         (mass_per_length × segment length); lower stretch_stiffness, raise \
                         mass_per_length, or use [solver] model = \"rod\"",
                        bound.dt_max, s.physics.stretch_stiffness
                    )));
                }
                wanted.max(1.0)
            }
        };
        if settings.steps > MAX_SUBSTEPS {
            return Err(self.error(format!(
                "[solver] steps = {}: more than {MAX_SUBSTEPS} collision steps per frame never \
                 finishes; use a few (1–8)",
                settings.steps
            )));
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
            .map_err(|e| self.error(e.to_string()))
    }

    /// A [`crate::build::SettleError`] in the scene's words: its sections, keys and fixes.
    fn settle_message(&self, e: crate::build::SettleError) -> String {
        use crate::build::SettleError;
        match e {
            SettleError::SagFreeWithFactors => {
                "[solver] sag_free solves rest shapes for one material, but [[regions]] or \
                 [maps.stiffness] give hair its own: remove sag_free or the regions"
                    .into()
            }
            SettleError::SagFreeModel => {
                "[solver] sag_free is for the mass-spring model; remove it or set \
                 model = \"mass-spring\""
                    .into()
            }
            SettleError::Unbalanced {
                count,
                total,
                first,
            } => format!(
                "[solver] sag_free: {count} of {total} strands (first: strand {first}) cannot be \
                 held in their groomed shape by the bending springs without turning a rest \
                 direction more than 60°; raise [physics] bend_stiffness, shorten the hair or \
                 groom it to hang"
            ),
            SettleError::HairHairGrid(e) => format!("[hair_hair] {e}"),
            SettleError::Collider { message, .. } => message,
            SettleError::Anchor(e) | SettleError::SagFree(e) => e.to_string(),
        }
    }

    fn error(&self, message: String) -> SceneError {
        SceneError {
            file: self.origin.clone(),
            message,
        }
    }

    /// Validates the scene and builds everything a run needs.
    pub fn build(&self) -> Result<Simulation, SceneError> {
        let s = &self.scene;
        let err = |m: String| self.error(m);
        let [first, last] = s.scene.frames;
        if !(s.scene.fps.is_finite() && s.scene.fps > 0.0) {
            return Err(err(format!(
                "[scene] fps = {}: use a finite frame rate > 0, e.g. 24",
                s.scene.fps
            )));
        }
        if last <= first {
            return Err(err(format!(
                "[scene] frames = [{first}, {last}]: the last frame must come after the first"
            )));
        }
        let substeps = match &s.solver.substeps {
            SubstepsValue::Word(w) if w == "auto" => Substeps::Auto,
            SubstepsValue::Count(n) if *n >= 1 && *n <= 1_000_000 => Substeps::Fixed(*n as u32),
            other => {
                return Err(err(format!(
                    "[solver] substeps = {}: use \"auto\" or a whole number from 1 to 1000000",
                    match other {
                        SubstepsValue::Count(n) => n.to_string(),
                        SubstepsValue::Word(w) => format!("{w:?}"),
                    }
                )))
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
            .map_err(|e| err(format!("[solver] {e}")))?;
        s.physics
            .validate()
            .map_err(|e| err(format!("[physics] {e}")))?;
        match (s.solver.model, &s.rod) {
            (StrandModel::MassSpring, Some(_)) => {
                return Err(err(
                    "[rod] is given but [solver] model = \"mass-spring\"; set model = \"rod\" \
                     or remove [rod]"
                        .into(),
                ))
            }
            (_, Some(rod)) => rod.validate().map_err(|e| err(format!("[rod] {e}")))?,
            _ => {}
        }
        s.scalp
            .motion
            .validate()
            .map_err(|e| err(format!("[scalp.motion] {e}")))?;

        self.check_point_budget()?;
        let (rest_mesh, scalp_animation) = self.scalp_mesh()?;
        let maps = self.scalp_maps(rest_mesh.as_ref()).map_err(err)?;
        let mut strands = StrandSet::new();
        if let Some(hair) = &s.hair {
            let Some(mesh) = &rest_mesh else {
                return Err(err(
                    "[hair] generates hair on the scalp, but [scalp.mesh] kind = \"none\"; choose a scalp mesh \
                     or give [[strands]] instead"
                        .into(),
                ));
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
            let density = maps.density(mesh).map_err(err)?;
            let mut inputs = hair_groom::generate_with_density(
                mesh,
                &opts,
                density.as_ref().map(|d| d as &dyn hair_groom::RootDensity),
            )
            .map_err(|e| err(format!("[hair] {e}")))?;
            if let Some(style) = &hair.style {
                let opts = style.options(&s.physics.gravity(), hair.seed);
                hair_groom::lay_over_scalp(&mut inputs, mesh, &opts)
                    .map_err(|e| err(format!("[hair.style] {e}")))?;
            }
            maps.scale_goal(&mut inputs, mesh, "[hair] strand")
                .map_err(err)?;
            maps.trim_length(&mut inputs, mesh, "[hair] strand")
                .map_err(err)?;
            for input in inputs {
                strands
                    .push(input)
                    .map_err(|e| err(format!("[hair] {e}")))?;
            }
        }
        let mut guided = None;
        // Each strand's nearest guide (sim hairs only), for `[[regions]]` selections.
        let mut nearest_guide = vec![None; strands.len()];
        if let Some(guides) = &s.guides {
            let Some(mesh) = &rest_mesh else {
                return Err(err("[guides] puts guides on the scalp, but [scalp.mesh] kind = \"none\"; choose a scalp mesh".into()));
            };
            let mut built = guides::build(
                guides,
                s.sim_hairs.as_ref(),
                mesh,
                &self.base_dir,
                &s.physics.gravity(),
                &maps,
            )
            .map_err(err)?;
            maps.scale_goal(&mut built.inputs, mesh, "sim hair")
                .map_err(err)?;
            if s.solver.model != StrandModel::MassSpring {
                if guides.animation_keys().any() {
                    return Err(err(
                        "[guides] pose, sim_weight, pin and hold_out animate the \
                         mass-spring model's rest shapes; remove them or set [solver] model = \
                         \"mass-spring\""
                            .into(),
                    ));
                }
                built.animation = None;
            }
            if let Some(a) = &mut built.animation {
                a.set_first_strand(strands.len());
            }
            for input in &built.inputs {
                strands
                    .push(input.clone())
                    .map_err(|e| err(format!("[sim_hairs] {e}")))?;
            }
            nearest_guide.extend(built.nearest_guide.iter().copied());
            guided = Some(built);
        } else if s.sim_hairs.is_some() {
            return Err(err(
                "[sim_hairs] interpolates from guides: add a [guides] section".into(),
            ));
        }
        for (i, st) in s.strands.iter().enumerate() {
            let input = explicit_strand(st).map_err(|m| err(format!("[[strands]] #{i}: {m}")))?;
            strands
                .push(input)
                .map_err(|e| err(format!("[[strands]] #{i}: {e}")))?;
        }
        let strips =
            crate::scene::strips::build_into(s, rest_mesh.as_ref(), &mut strands).map_err(err)?;
        if strands.is_empty() {
            return Err(err(
                "the scene has no hair: add a [hair] section or [[strands]]".into(),
            ));
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
            .map_err(|m| err(format!("[[regions]] {m}")))?;
        let child_maps = maps
            .child_factors(&strands, rest_mesh.as_ref())
            .map_err(err)?;
        let map_summaries = maps.summaries(&strands, rest_mesh.as_ref()).map_err(err)?;
        let colliders = self.colliders()?;
        let contact = integrator::ContactLoad {
            deforming: scalp_animation.is_some() && s.scalp.collider.is_some()
                || colliders.iter().any(|c| c.animation.is_some()),
            animated_guides: guided
                .as_ref()
                .and_then(|g| g.animation.as_ref())
                .is_some_and(|a| a.has_poses()),
            ..self.collider_motion(&colliders, &strands)
        };
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
            c.validate().map_err(|e| err(format!("[contacts] {e}")))?;
        }
        if let Some(c) = &s.children {
            c.settings().map_err(err)?;
        }
        if s.scalp.collider.is_some() && rest_mesh.is_none() {
            return Err(err(
                "[scalp.collider] makes the scalp mesh a collider, but [scalp.mesh] kind = \"none\"; \
                 choose a scalp mesh or remove [scalp.collider]"
                    .into(),
            ));
        }
        let hair_hair = s.hair_hair;
        if let Some(h) = &hair_hair {
            h.validate().map_err(|e| err(format!("[hair_hair] {e}")))?;
        }
        let fields = s
            .fields
            .iter()
            .enumerate()
            .map(|(i, f)| f.field(i))
            .collect::<Result<Vec<_>, _>>()
            .map_err(err)?;
        if s.solver.model == StrandModel::Rod && (hair_hair.is_some() || !fields.is_empty()) {
            return Err(err(
                "[hair_hair] and [[fields]] act on the mass-spring model only; remove them or \
                 set [solver] model = \"mass-spring\""
                    .into(),
            ));
        }
        if let Some(i) = fields.iter().position(|f| f.moves_air()) {
            if s.physics.air_drag <= 0.0 {
                return Err(err(format!(
                    "[[fields]] #{i}: wind, vortex and turbulence move the air, which pushes hair \
                     through [physics] air_drag = 0; set air_drag > 0"
                )));
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
            scalp_colors: self.scalp_colors().map_err(err)?,
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
            .map_err(|e| err(self.settle_message(e)))?;
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
            return Err(self.error(
                "[[regions]] and [maps.stiffness] give hair its own mass-spring parameters; the \
                 rod and strip models have one material: remove them or set [solver] model = \
                 \"mass-spring\""
                    .into(),
            ));
        }
        let roots = regions::StrandRoots {
            mesh,
            nearest_guide,
            guide_count: guided.map_or(0, |g| g.guides.len()),
        };
        regions::Regions::build(&s.regions, &s.physics, strands, &roots, maps)
            .map_err(|m| self.error(m))
    }

    /// The fastest surface speed of `colliders` over the shot and the distance one may move in
    /// a substep (its thickness plus the thinnest hair radius of `strands`), for `"auto"`'s
    /// contact condition ([`integrator`]).
    fn collider_motion(
        &self,
        colliders: &[SceneCollider],
        strands: &StrandSet,
    ) -> integrator::ContactLoad {
        let [first, last] = self.scene.scene.frames;
        let fps = f64::from(self.scene.scene.fps);
        let hair = strands
            .radii()
            .iter()
            .copied()
            .fold(f32::INFINITY, f32::min);
        let mut load = integrator::ContactLoad {
            margin: f64::INFINITY,
            ..Default::default()
        };
        for c in colliders {
            let radius = f64::from(c.collider.shape.bounding_radius());
            let speed =
                integrator::fastest_surface_speed(|f| c.motion.at(f), radius, first, last, fps);
            if speed > 0.0 {
                load.collider_speed = load.collider_speed.max(speed);
                load.margin = load
                    .margin
                    .min(f64::from(c.collider.thickness + hair.max(0.0)));
            }
        }
        load
    }

    /// Loads and checks the `[[colliders]]`.
    fn colliders(&self) -> Result<Vec<SceneCollider>, SceneError> {
        let mut out = Vec::new();
        for (i, c) in self.scene.colliders.iter().enumerate() {
            let err = |m: String| self.error(format!("[[colliders]] #{i}{}: {m}", named(&c.name)));
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
                        .map_err(|e| err(format!("shape: {e}")))?,
                ),
                ColliderShapeSection::Usd(_) | ColliderShapeSection::ObjSequence(_) => {
                    let source = c.shape.deforming().expect("a deforming shape");
                    let (rest, anim) = self
                        .load_deforming(source)
                        .map_err(|e| err(format!("shape: {e}")))?;
                    animation = Some(anim);
                    ColliderShape::Mesh(rest)
                }
            };
            let collider = Collider {
                shape,
                thickness: c.thickness,
                friction: c.friction,
            };
            collider.validate(i).map_err(|e| match e {
                HairError::Collider { message, .. } => err(message),
                other => err(other.to_string()),
            })?;
            c.motion
                .validate()
                .map_err(|m| err(format!("motion: {m}")))?;
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
    fn scalp_colors(&self) -> Result<Option<Vec<[f32; 3]>>, String> {
        let ScalpMesh::Obj { path, .. } = &self.scene.scalp.mesh else {
            return Ok(None);
        };
        let path = self.base_dir.join(path);
        // The same bounded OBJ reader the scalp itself is loaded with (vertices in its order; a
        // hostile face index is an error, not a panic).
        let Some(colors) = hair_groom::load_obj_vertex_colors(&path).map_err(|e| {
            format!(
                "[scalp.mesh] {}: cannot read its vertex colors ({e})",
                path.display()
            )
        })?
        else {
            return Ok(None);
        };
        if let Some(i) = colors.iter().position(|c| !c.iter().all(|x| x.is_finite())) {
            return Err(format!(
                "[scalp.mesh] {}: vertex {i} has a non-finite color {:?}; fix its `v x y z r g b` line",
                path.display(),
                colors[i]
            ));
        }
        Ok(Some(colors))
    }

    /// The scene's `[maps.NAME]`, read and checked against the scalp at rest `mesh`.
    fn scalp_maps(&self, mesh: Option<&TriMesh>) -> Result<maps::ScalpMaps, String> {
        let sections = &self.scene.maps;
        if sections.is_empty() {
            return Ok(maps::ScalpMaps::none());
        }
        let Some(mesh) = mesh else {
            return Err(
                "[maps] paint values over the scalp, but [scalp.mesh] kind = \"none\"; \
                        choose a scalp mesh or remove [maps]"
                    .into(),
            );
        };
        if sections.contains_key("density")
            && self.scene.hair.is_none()
            && self.scene.sim_hairs.is_none()
        {
            return Err(
                "[maps.density] spreads the roots of [hair] and [sim_hairs], but the scene has \
                 neither: grow hair with [hair] or [guides] + [sim_hairs], or remove the map"
                    .into(),
            );
        }
        if sections.contains_key("sim_weight") && self.scene.guides.is_none() {
            return Err(
                "[maps.sim_weight] paints the sim weight of hair grown from guides, but \
                        the scene has no [guides]: add [guides] and [sim_hairs] or remove the map"
                    .into(),
            );
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
        let err = |m: String| self.error(format!("[scalp.mesh] {m}"));
        if let Some(source) = self.scene.scalp.mesh.deforming() {
            let (rest, animation) = self.load_deforming(source).map_err(err)?;
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
                    .map_err(|e| err(format!("uv-sphere: {e}")))?,
            ),
            ScalpMesh::Obj {
                path,
                scale,
                up_axis,
            } => Some(
                self.load_obj(path, *scale, *up_axis)
                    .map_err(|e| err(e.to_string()))?,
            ),
            ScalpMesh::Usd(_) | ScalpMesh::ObjSequence(_) => None,
        };
        Ok((rest, None))
    }

    /// Reads a deforming mesh over the scene's frames (see [`deforming`]).
    fn load_deforming(
        &self,
        source: DeformingSource<'_>,
    ) -> Result<(TriMesh, MeshAnimation), String> {
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
fn explicit_strand(st: &ExplicitStrand) -> Result<StrandInput, String> {
    let n = st.points.len();
    if n < 2 {
        return Err(format!(
            "points has {n} point(s); give at least 2, root first"
        ));
    }
    if let Some(i) = st
        .points
        .iter()
        .position(|p| !p.iter().all(|c| c.is_finite()))
    {
        return Err(format!("points[{i}] is not finite"));
    }
    let root = Vector3::from(st.points[0]);
    let rest: Vec<Vector3<f32>> = st.points.iter().map(|p| Vector3::from(*p) - root).collect();
    let anchor = Anchor::Body(RootFrame::at(root));
    if !(st.mass_per_length.is_finite() && st.mass_per_length > 0.0) {
        return Err(format!(
            "mass_per_length = {}: use a finite density > 0 kg/m",
            st.mass_per_length
        ));
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
            return Err(format!(
                "masses has {} values for {n} points; give one per point",
                masses.len()
            ));
        }
        input.mass.clone_from(masses);
    }
    for &i in &st.pinned {
        if i >= n {
            return Err(format!(
                "pinned names point {i} but the strand has {n} points (0–{})",
                n - 1
            ));
        }
        input.pinned[i] = true;
    }
    Ok(input)
}

/// ` (name)` for a named collider, nothing otherwise.
fn named(name: &str) -> String {
    if name.is_empty() {
        String::new()
    } else {
        format!(" ({name})")
    }
}

/// A collider of a simulation: its geometry, thickness, friction and rigid motion.
#[derive(Debug, Clone)]
pub struct SceneCollider {
    /// The name from the scene file (may be empty).
    pub name: String,
    /// Geometry (meshes loaded), thickness and friction.
    pub collider: Collider,
    /// Rigid motion: keyframed in a scene, fixed at a host's first-frame pose.
    pub motion: crate::rig::Motion,
    /// For a deforming mesh (`kind = "usd"` or `"obj-sequence"`): its body-space vertices at
    /// every frame.
    pub animation: Option<MeshAnimation>,
}

impl SceneCollider {
    /// The collider's mesh (body space) at (possibly fractional) `frame`: deformed for a
    /// deforming collider; `None` for analytic shapes.
    pub fn mesh_at(&self, frame: f32) -> Option<TriMesh> {
        let ColliderShape::Mesh(rest) = &self.collider.shape else {
            return None;
        };
        let mut mesh = rest.clone();
        if let Some(a) = &self.animation {
            // The vertices were checked (count, finite) when read.
            mesh.set_positions(&a.vertices_at(frame)).ok()?;
        }
        Some(mesh)
    }
}

/// Everything a run needs, built from a scene.
#[derive(Debug, Clone)]
pub struct Simulation {
    /// Strands at rest at the first frame.
    pub strands: StrandSet,
    /// Time stepping (`integrator` resolved: see [`Self::integrator`]).
    pub settings: SolverSettings,
    /// The integrator `settings` carries, whether `[solver] integrator = "auto"` chose it, and
    /// the substep counts it compared.
    pub integrator: ResolvedIntegrator,
    /// Physics parameters.
    pub params: HairParams,
    /// First frame (hair at rest).
    pub first_frame: u32,
    /// Last frame.
    pub last_frame: u32,
    pub(crate) rest_mesh: Option<TriMesh>,
    /// One RGB colour (0–1) per scalp vertex, if the scalp has vertex colours (an OBJ's
    /// `v x y z r g b`): the colours of the children's roots.
    pub scalp_colors: Option<Vec<[f32; 3]>>,
    /// For a deforming scalp: its vertices (body space) at every frame.
    pub(crate) scalp_animation: Option<MeshAnimation>,
    /// The scalp's rigid motion.
    pub(crate) motion: crate::rig::Motion,
    /// The `[[colliders]]`, in file order (their [`ColliderId`]s are 0, 1, …).
    pub colliders: Vec<SceneCollider>,
    /// `[scalp.collider]`, if the scalp collides with its hair.
    pub scalp_collider: Option<ScalpCollider>,
    /// `[contacts]`.
    pub contact_settings: ContactSettings,
    /// The `[guides]` on the scalp, if the scene has them.
    pub guides: Vec<hair_groom::Guide>,
    /// What `[guides]` and `[sim_hairs]` built, in words (snap distances included).
    pub guides_report: Option<String>,
    /// `[hair_hair]`, if on.
    pub hair_hair: Option<hair_core::HairHairSettings>,
    /// `[[fields]]`, validated, in file order.
    pub fields: Vec<hair_core::ForceField>,
    /// `[solver] model`: which strand solver runs.
    pub model: StrandModel,
    /// `[rod]` (the defaults when absent); used when `model` is the rod.
    pub rod: RodParams,
    /// `[solver] inextensibility`: the projection of the mass-spring model, if on.
    pub inextensibility: Option<hair_core::Inextensibility>,
    /// `[strips]` settings when `[solver] model = "strips"` (strip `k` = strands `2k`, `2k + 1`).
    pub strips: Option<hair_core::model::strips::StripSettings>,
    /// Animated guides (`[[guides.pose]]`, `[guides.sim_weight]`, pins, hold-outs), if keyed.
    pub guide_animation: Option<crate::animated_guides::GuideAnimation>,
    /// `[[regions]]` and `[maps.stiffness]` resolved to strands (empty: one material).
    pub regions: regions::Regions,
    /// Per-strand factors of the material a host gave with its strands
    /// ([`crate::build::groom`]); `None` for a scene, whose factors come from `regions`.
    pub strand_scales: Option<Vec<StrandScales>>,
    /// `[maps.clump]` and `[maps.curl]` at each strand's root: factors of its render children's
    /// clump and curl.
    pub child_maps: maps::ChildMapFactors,
    /// The `[maps.NAME]` sections as built: source, purpose, values at the roots.
    pub maps: Vec<maps::MapSummary>,
}

impl Simulation {
    /// The strand solver of the scene's `[solver] model` for its first frame: mass-spring with
    /// the scene's hair–hair, fields and inextensibility projection; the rod with `[rod]`; the
    /// strips with `[strips]` (with `[scalp.collider]` the rest scalp is the head of their
    /// two-stage collision).
    pub fn strand_solver(&self) -> Result<StrandSolver, HairError> {
        let scalp = self.scalp_at(self.first_frame as f32);
        Ok(match self.model {
            StrandModel::MassSpring => {
                let mut solver = MassSpringSolver::new(
                    self.settings,
                    self.params,
                    &self.strands,
                    &scalp,
                    self.first_frame,
                )?;
                if !self.regions.is_empty() {
                    let scales = self
                        .regions
                        .scales(&self.params, self.strands.len())
                        .map_err(|fix| HairError::Parameter {
                            name: "regions".into(),
                            value: "their parameters".into(),
                            fix,
                        })?;
                    solver = solver.with_strand_scales(scales, &self.strands)?;
                } else if let Some(scales) = &self.strand_scales {
                    solver = solver.with_strand_scales(scales.clone(), &self.strands)?;
                }
                self.with_inextensibility(self.with_interactions(solver)?)?
                    .into()
            }
            StrandModel::Rod => RodSolver::new(
                self.settings,
                self.params,
                self.rod,
                &self.strands,
                &scalp,
                self.first_frame,
            )?
            .into(),
            StrandModel::Strips => {
                let settings = self.strips.ok_or_else(|| HairError::Parameter {
                    name: "strips".into(),
                    value: "absent".into(),
                    fix: "[solver] model = \"strips\" needs a [strips] section".into(),
                })?;
                let head = match (self.scalp_collider.is_some(), self.rest_mesh()) {
                    (true, Some(mesh)) => Some(HeadShape::new(mesh)?),
                    _ => None,
                };
                StripSolver::new(
                    self.settings,
                    self.params,
                    &self.strands,
                    &scalp,
                    self.first_frame,
                    settings,
                    head,
                )?
                .into()
            }
        })
    }

    /// `solver` with the scene's inextensibility projection (`[solver] inextensibility`) on, if
    /// the scene asks for it.
    pub fn with_inextensibility(
        &self,
        solver: hair_core::MassSpringSolver,
    ) -> Result<hair_core::MassSpringSolver, HairError> {
        match self.inextensibility {
            Some(p) => solver.with_inextensibility(p),
            None => Ok(solver),
        }
    }

    /// The scalp mesh at rest (before the scalp's motion), if the scene has one.
    pub fn rest_mesh(&self) -> Option<&TriMesh> {
        self.rest_mesh.as_ref()
    }

    /// True when the scene has any collider (scene colliders or the scalp).
    pub fn has_colliders(&self) -> bool {
        !self.colliders.is_empty() || self.scalp_collider.is_some()
    }

    /// The colliders placed at (possibly fractional) `frame`: the `[[colliders]]` in file order,
    /// then the scalp if `[scalp.collider]` is given.
    pub fn colliders_at(&self, frame: f32) -> Result<Colliders, HairError> {
        let mut set = Colliders::new();
        set.settings = self.contact_settings;
        for c in &self.colliders {
            let id = set.insert(c.collider.clone(), c.motion.at(frame))?;
            if let Some(a) = &c.animation {
                set.place_vertices(id, &a.vertices_at(frame))?;
            }
        }
        if let Some(sc) = &self.scalp_collider {
            // From the rest mesh, so a resumed run builds the same shape bits.
            match &self.rest_mesh {
                Some(rest) => {
                    set.insert_scalp_rest(
                        rest.clone(),
                        self.motion.at(frame),
                        sc.thickness,
                        sc.friction,
                    )?;
                    if self.scalp_animation.is_some() {
                        set.place_scalp(&self.scalp_at(frame))?;
                    }
                }
                None => {
                    set.insert_scalp(&self.scalp_at(frame), sc.thickness, sc.friction)?;
                }
            };
        }
        Ok(set)
    }

    /// Per point, the outward normal of the collider surface the hair rests on at the first
    /// frame, or zero (see [`hair_core::quality::resting_normals`]): what sag-free lets the
    /// colliders carry. A point rests on a collider when it is within two strand radii (the
    /// largest in the set) of touching it — a layered groom's lower layers.
    pub fn resting_supports(&self) -> Result<Vec<Vector3<f32>>, HairError> {
        let colliders = self.colliders_at(self.first_frame as f32)?;
        let reach = 2.0 * self.strands.radii().iter().fold(0.0f32, |a, &r| a.max(r));
        Ok(hair_core::quality::resting_normals(
            &colliders,
            &self.strands.positions,
            self.strands.radii(),
            self.strands.inverse_masses(),
            reach,
        ))
    }

    /// Sets every scene collider's pose, and a deforming collider's vertices, at the end of
    /// the frame to be stepped, (possibly fractional) `frame` (the scalp collider follows the
    /// scalp by itself).
    pub fn pose_colliders(&self, set: &mut Colliders, frame: f32) -> Result<(), HairError> {
        for i in 0..self.colliders.len() {
            self.pose_collider(set, i, frame)?;
        }
        Ok(())
    }

    /// Sets scene collider `i`'s pose, and its vertices if it deforms, at the end of the frame
    /// to be stepped, `frame`.
    pub fn pose_collider(
        &self,
        set: &mut Colliders,
        i: usize,
        frame: f32,
    ) -> Result<(), HairError> {
        let Some(c) = self.colliders.get(i) else {
            return Ok(());
        };
        let id = ColliderId(i as u32);
        set.set_pose(id, c.motion.at(frame))?;
        if let Some(a) = &c.animation {
            set.set_vertices(id, &a.vertices_at(frame))?;
        }
        Ok(())
    }

    /// Puts every scene collider (pose and, if it deforms, vertices) and the scalp collider at
    /// `frame` now, with no motion into it: for measuring frames out of order.
    pub fn place_colliders(&self, set: &mut Colliders, frame: f32) -> Result<(), HairError> {
        for (i, c) in self.colliders.iter().enumerate() {
            let id = ColliderId(i as u32);
            set.set_pose(id, c.motion.at(frame))?;
            if let Some(a) = &c.animation {
                set.place_vertices(id, &a.vertices_at(frame))?;
            }
        }
        set.place_scalp(&self.scalp_at(frame))
    }

    /// Refuses a run over frames `first..=last` that leaves the frames a deforming scalp or
    /// collider was read for (see [`deforming`]).
    pub fn check_deforming_frames(&self, first: u32, last: u32) -> Result<(), String> {
        let scalp = self
            .scalp_animation
            .iter()
            .map(|a| ("[scalp.mesh]".to_string(), a));
        let colliders = self.colliders.iter().enumerate().filter_map(|(i, c)| {
            let a = c.animation.as_ref()?;
            Some((format!("[[colliders]] #{i}{}", named(&c.name)), a))
        });
        for (field, a) in scalp.chain(colliders) {
            a.check_covers(first, last)
                .map_err(|e| format!("{field}: {e}"))?;
        }
        Ok(())
    }

    /// True when the scalp mesh deforms (a USD or OBJ-sequence scalp).
    pub fn scalp_deforms(&self) -> bool {
        self.scalp_animation.is_some()
    }

    /// A collider error in the scene's terms: `[[colliders]] #i (name)` or `[scalp.collider]`.
    pub fn collider_message(&self, e: &HairError) -> String {
        match e {
            HairError::Collider { collider, message } => match self.colliders.get(*collider) {
                Some(c) => format!("[[colliders]] #{collider}{}: {message}", named(&c.name)),
                None => format!("[scalp.collider]: {message}"),
            },
            other => other.to_string(),
        }
    }

    /// The deformed scalp's vertices (body space, m) at (possibly fractional) `frame`, for a
    /// deforming scalp; `None` for a rigid one.
    pub fn scalp_vertices_at(&self, frame: f32) -> Option<Vec<Vector3<f32>>> {
        self.scalp_animation.as_ref().map(|a| a.vertices_at(frame))
    }

    /// The scalp at (possibly fractional) `frame`: the rest mesh, deformed to the frame's
    /// vertices for a deforming scalp, moved by the rigid motion.
    pub fn scalp_at(&self, frame: f32) -> Scalp {
        let body = self.motion.at(frame);
        let mesh = self
            .rest_mesh
            .as_ref()
            .map(|rest| match &self.scalp_animation {
                Some(a) => {
                    let mut m = rest.clone();
                    // The vertices were checked (count, finite) when read; keep the rest otherwise.
                    if m.set_positions(&a.vertices_at(frame)).is_err() {
                        m = rest.clone();
                    }
                    m.transformed(&body)
                }
                None => rest.transformed(&body),
            });
        Scalp { mesh, body }
    }

    /// Restricts the run to frames `first..=last` (the hair starts at rest at `first`).
    pub fn set_frames(&mut self, first: u32, last: u32) {
        self.first_frame = first;
        self.last_frame = last;
        let scalp = self.scalp_at(first as f32);
        self.strands.reset_to_rest(&scalp);
    }
}
