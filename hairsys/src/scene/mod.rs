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

use hair_core::{ContactSettings, HairHairSettings, HairParams, RodParams, StrandModel};
use hair_groom::UpAxis;

use crate::budget::Budget;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

/// `From<$inner>` for `$outer::$variant(Box<$inner>)`: a nested error boxed, so every
/// `Result` of the scene's helpers stays small (clippy's `result_large_err`).
macro_rules! boxed_from {
    ($outer:ty, $variant:ident, $inner:ty) => {
        impl From<$inner> for $outer {
            fn from(e: $inner) -> Self {
                Self::$variant(Box::new(e))
            }
        }
    };
}

pub mod children;
pub mod deforming;
pub mod error;
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

pub use error::{SceneError, SceneProblem};
pub use version::SCENE_VERSION;

use deforming::{DeformingSource, ObjSequenceSection, UsdMeshSection};
use fields::FieldSection;
use guides::{GuidesSection, SimHairsSection};
use integrator::IntegratorChoice;
use motion::RigidMotion;

/// The built-in default scene, fully commented (printed by `hairsys scene init`).
pub const DEFAULT_SCENE: &str = include_str!("../../../scenes/default.toml");

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
/// Not [`SolverSettings`](hair_core::SolverSettings) itself, on purpose: the frame rate comes from `[scene] fps`,
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
/// Not [`Collider`](hair_core::Collider) itself: the file names an OBJ path (relative to the scene file) where the
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

/// `[hair]`: hair generated on the scalp (see [`GenerateOptions`](hair_groom::GenerateOptions)).
///
/// Not [`GenerateOptions`](hair_groom::GenerateOptions) itself, on purpose: `count`, `length` and `segments` are required
/// here (a scene that grows hair says how much), and `region` is an optional cone table where
/// the library has the [`Region`](hair_groom::Region) enum.
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
/// scalp, [`Region::All`](hair_groom::Region::All); TOML has no spelling for an enum's unit variant beside a table).
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
    pub(crate) fn cone(
        &self,
        what: &str,
    ) -> Result<(Vector3<f32>, f32), guide_anim::SelectionError> {
        let axis = Vector3::from(self.direction);
        if !(axis.iter().all(|c| c.is_finite())
            && axis.norm() > 0.0
            && (0.0..=180.0).contains(&self.max_angle_deg))
        {
            return Err(guide_anim::SelectionError::Cone {
                selection: what.to_string(),
                direction: self.direction,
                max_angle_deg: self.max_angle_deg,
            });
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
        let bytes = hair_groom::input_file::read_regular_file(path, MAX_SCENE_FILE_BYTES)
            .map_err(|e| SceneError::new(origin.clone(), SceneProblem::Read(e)))?;
        let text = String::from_utf8(bytes).map_err(|e| {
            SceneError::new(
                origin.clone(),
                SceneProblem::NotText {
                    byte: e.utf8_error().valid_up_to(),
                },
            )
        })?;
        let base_dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Self::parse(&text, &origin, base_dir)
    }

    /// Parses scene text; `origin` names it in errors. A `version` newer than [`SCENE_VERSION`]
    /// is refused (see [`version`]).
    pub fn parse(text: &str, origin: &str, base_dir: PathBuf) -> Result<Self, SceneError> {
        version::check(text).map_err(|e| SceneError::new(origin, e))?;
        let scene: Scene =
            toml::from_str(text).map_err(|e| SceneError::new(origin, SceneProblem::Syntax(e)))?;
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
            let bytes = std::fs::read(&full).map_err(|source| {
                self.error(SceneProblem::Unreadable {
                    field: format!("[scalp.mesh] path = {}", path.display()),
                    path: full.clone(),
                    source,
                })
            })?;
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
            let files =
                deforming::hashed_files(source, &self.base_dir, frames).map_err(|source| {
                    self.error(SceneProblem::Deforming {
                        field: field.clone(),
                        source,
                    })
                })?;
            for full in files {
                let bytes = std::fs::read(&full).map_err(|source| {
                    self.error(SceneProblem::Unreadable {
                        field: field.clone(),
                        path: full.clone(),
                        source,
                    })
                })?;
                h.update(bytes);
            }
        }
        for (i, c) in self.scene.colliders.iter().enumerate() {
            if let ColliderShapeSection::Obj { path, .. } = &c.shape {
                let full = self.base_dir.join(path);
                let bytes = std::fs::read(&full).map_err(|source| {
                    self.error(SceneProblem::Unreadable {
                        field: format!("[[colliders]] #{i} shape path = {}", path.display()),
                        path: full.clone(),
                        source,
                    })
                })?;
                h.update(bytes);
            }
        }
        Ok(h.finalize().iter().map(|b| format!("{b:02x}")).collect())
    }

    /// A [`SceneError`] of this scene for `problem`.
    pub(crate) fn error(&self, problem: impl Into<SceneProblem>) -> SceneError {
        SceneError::new(self.origin.clone(), problem)
    }
}
