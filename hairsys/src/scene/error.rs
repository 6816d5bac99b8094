//! [`SceneError`]: why a scene file cannot be used, as a [`SceneProblem`] that names the section,
//! the key, the value and the fix, and that keeps the error of the file, parser or solver it
//! came from as its source. Each section's own checks have their own error type in its module
//! ([`MapsError`], [`GuidesError`], [`RegionError`], …), nested here with `#[from]`.

use std::path::PathBuf;

use hair_core::HairError;
use hair_groom::GroomError;

use super::children::ChildrenError;
use super::deforming::DeformingError;
use super::fields::FieldError;
use super::guides::GuidesError;
use super::maps::{MapsError, ScalpColorsError};
use super::motion::MotionError;
use super::regions::RegionError;
use super::strips::StripsError;
use super::version::VersionError;
use super::SubstepsValue;
use crate::budget::OverBudget;
use crate::build::SettleError;

/// A scene file could not be used. Displays as `FILE: problem`.
#[derive(Debug, thiserror::Error)]
#[error("{file}: {problem}")]
pub struct SceneError {
    /// The scene file (or `<built-in default scene>`).
    pub file: String,
    /// What is wrong, naming the field and the fix (boxed, so every `Result` stays small).
    #[source]
    pub problem: Box<SceneProblem>,
}

impl SceneError {
    /// The error of the scene `file` for `problem`.
    pub fn new(file: impl Into<String>, problem: impl Into<SceneProblem>) -> Self {
        Self {
            file: file.into(),
            problem: Box::new(problem.into()),
        }
    }
}

/// What is wrong with a scene: the section and key, the value given and the fix; the error of
/// the file, parser or solver underneath is the source.
#[derive(Debug, thiserror::Error)]
pub enum SceneProblem {
    /// The scene file cannot be read (missing, not a regular file, too large).
    #[error("cannot read the scene file: {0}")]
    Read(#[source] hair_groom::input_file::InputFileError),
    /// The scene file is not UTF-8 text.
    #[error("not a text file (byte {byte} is not UTF-8); a scene is TOML text")]
    NotText {
        /// The offset of the first byte that is not UTF-8.
        byte: usize,
    },
    /// The `version` key is refused.
    #[error("{0}")]
    Version(#[from] VersionError),
    /// The text is not a scene: TOML syntax, an unknown key, a value of the wrong type.
    #[error("not a valid scene: {}", .0.to_string().trim_end())]
    Syntax(#[source] toml::de::Error),
    /// A file the scene names cannot be read.
    #[error("{field}: cannot read {} ({source}); fix the path (relative to the scene file)", path.display())]
    Unreadable {
        /// The section and key naming the file (`[scalp.mesh] path = scalp.obj`).
        field: String,
        /// The file, resolved against the scene's directory.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A deforming mesh's files cannot be listed.
    #[error("{field}: {source}")]
    Deforming {
        /// The section (`[scalp.mesh]`, `[[colliders]] #i (name)`).
        field: String,
        /// Why.
        source: DeformingError,
    },
    /// `[scene] fps` is not a finite frame rate > 0.
    #[error("[scene] fps = {fps}: use a finite frame rate > 0, e.g. 24")]
    Fps {
        /// The value given.
        fps: f32,
    },
    /// `[scene] frames` does not end after it starts.
    #[error("[scene] frames = [{first}, {last}]: the last frame must come after the first")]
    Frames {
        /// The first frame given.
        first: u32,
        /// The last frame given.
        last: u32,
    },
    /// `[solver] substeps` is neither `"auto"` nor a count from 1 to 1000000.
    #[error(
        "[solver] substeps = {}: use \"auto\" or a whole number from 1 to 1000000",
        substeps_text(.given)
    )]
    Substeps {
        /// The value given.
        given: SubstepsValue,
    },
    /// A `[solver]` setting is out of range.
    #[error("[solver] {0}")]
    Solver(#[source] HairError),
    /// A `[physics]` parameter is out of range.
    #[error("[physics] {0}")]
    Physics(#[source] HairError),
    /// `[rod]` with the mass-spring model.
    #[error(
        "[rod] is given but [solver] model = \"mass-spring\"; set model = \"rod\" or remove [rod]"
    )]
    RodWithMassSpring,
    /// A `[rod]` parameter is out of range.
    #[error("[rod] {0}")]
    Rod(#[source] HairError),
    /// `[scalp.motion]` is refused.
    #[error("[scalp.motion] {0}")]
    ScalpMotion(#[source] MotionError),
    /// The hair or the run is over the memory or time budget.
    #[error("{0}")]
    Budget(#[source] OverBudget),
    /// `substeps = "auto"` resolves to more force substeps than a run can take.
    #[error(
        "[solver] substeps = \"auto\" resolves to {wanted:.3e} force substeps per step (limit \
         {limit}): the stability bound {bound:.3e} s is set by [physics] stretch_stiffness = \
         {stretch_stiffness} N over the mass of a segment (mass_per_length × segment length); \
         lower stretch_stiffness, raise mass_per_length, or use [solver] model = \"rod\"",
        limit = crate::budget::MAX_SUBSTEPS
    )]
    AutoSubsteps {
        /// The substeps `"auto"` resolves to.
        wanted: f64,
        /// The stability bound, s.
        bound: f64,
        /// `[physics] stretch_stiffness`, N.
        stretch_stiffness: f32,
    },
    /// `[solver] steps` is more than a run can take.
    #[error(
        "[solver] steps = {steps}: more than {limit} collision steps per frame never finishes; \
         use a few (1–8)",
        limit = crate::budget::MAX_SUBSTEPS
    )]
    Steps {
        /// The value given.
        steps: u32,
    },
    /// `[scalp.mesh]` cannot be read or made.
    #[error("[scalp.mesh] {0}")]
    ScalpMesh(#[source] MeshSourceError),
    /// The OBJ scalp's vertex colours cannot be used.
    #[error("{0}")]
    ScalpColors(#[from] ScalpColorsError),
    /// `[maps.NAME]` cannot be read, checked or applied.
    #[error("{0}")]
    Maps(#[from] MapsError),
    /// `[hair]` without a scalp mesh.
    #[error(
        "[hair] generates hair on the scalp, but [scalp.mesh] kind = \"none\"; choose a scalp \
         mesh or give [[strands]] instead"
    )]
    HairWithoutScalp,
    /// `[hair]` cannot be generated.
    #[error("[hair] {0}")]
    Hair(#[source] GroomError),
    /// `[hair.style]` cannot lay the hair.
    #[error("[hair.style] {0}")]
    HairStyle(#[source] GroomError),
    /// A generated strand is refused by the strand set.
    #[error("[hair] {0}")]
    HairStrand(#[source] HairError),
    /// `[guides]` without a scalp mesh.
    #[error(
        "[guides] puts guides on the scalp, but [scalp.mesh] kind = \"none\"; choose a scalp mesh"
    )]
    GuidesWithoutScalp,
    /// `[guides]` and `[sim_hairs]` cannot be built.
    #[error("{0}")]
    Guides(#[from] GuidesError),
    /// Animated guides with a model other than mass-spring.
    #[error(
        "[guides] pose, sim_weight, pin and hold_out animate the mass-spring model's rest \
         shapes; remove them or set [solver] model = \"mass-spring\""
    )]
    GuideAnimationOfModel,
    /// A sim hair is refused by the strand set.
    #[error("[sim_hairs] {0}")]
    SimHairStrand(#[source] HairError),
    /// `[sim_hairs]` without `[guides]`.
    #[error("[sim_hairs] interpolates from guides: add a [guides] section")]
    SimHairsWithoutGuides,
    /// A `[[strands]]` entry is refused.
    #[error("[[strands]] #{index}: {source}")]
    Strand {
        /// The strand's index in `[[strands]]`.
        index: usize,
        /// Why.
        source: StrandError,
    },
    /// `[strips]` (or the strips model) is refused.
    #[error("{0}")]
    Strips(#[from] StripsError),
    /// The scene makes no hair.
    #[error("the scene has no hair: add a [hair] section or [[strands]]")]
    NoHair,
    /// `[[regions]]` (or `[maps.stiffness]`) with a model other than mass-spring.
    #[error(
        "[[regions]] and [maps.stiffness] give hair its own mass-spring parameters; the rod and \
         strip models have one material: remove them or set [solver] model = \"mass-spring\""
    )]
    RegionsOfModel,
    /// `[[regions]]` are refused.
    #[error("{0}")]
    Regions(#[from] RegionError),
    /// The regions' factors of the scene's material are refused.
    #[error("[[regions]] {0}")]
    RegionScales(#[source] RegionError),
    /// A `[[colliders]]` entry is refused.
    #[error("[[colliders]] #{index}{}: {source}", named(.name))]
    Collider {
        /// The collider's index in `[[colliders]]`.
        index: usize,
        /// Its `name` (may be empty).
        name: String,
        /// Why.
        source: ColliderError,
    },
    /// The scalp as a collider is refused.
    #[error("[scalp.collider]: {}", collider_text(.0))]
    ScalpCollider(#[source] HairError),
    /// The colliders cannot be placed (an error of no one collider).
    #[error("{0}")]
    Colliders(#[source] HairError),
    /// `[scalp.collider]` without a scalp mesh.
    #[error(
        "[scalp.collider] makes the scalp mesh a collider, but [scalp.mesh] kind = \"none\"; \
         choose a scalp mesh or remove [scalp.collider]"
    )]
    ScalpColliderWithoutScalp,
    /// A `[contacts]` setting is out of range.
    #[error("[contacts] {0}")]
    Contacts(#[source] HairError),
    /// `[children]` is refused.
    #[error("{0}")]
    Children(#[from] ChildrenError),
    /// A `[hair_hair]` setting is out of range.
    #[error("[hair_hair] {0}")]
    HairHair(#[source] HairError),
    /// A `[[fields]]` entry is refused.
    #[error("{0}")]
    Field(#[from] FieldError),
    /// `[hair_hair]` or `[[fields]]` with the rod model.
    #[error(
        "[hair_hair] and [[fields]] act on the mass-spring model only; remove them or set \
         [solver] model = \"mass-spring\""
    )]
    MassSpringOnly,
    /// A field that moves the air with no air drag to carry it to the hair.
    #[error(
        "[[fields]] #{field}: wind, vortex and turbulence move the air, which pushes hair \
         through [physics] air_drag = 0; set air_drag > 0"
    )]
    MovingAirWithoutDrag {
        /// The field's index in `[[fields]]`.
        field: usize,
    },
    /// The built hair cannot be settled (roots, sag-free rest shapes, the hair–hair grid).
    #[error("{}", settle_text(.0))]
    Settle(#[source] SettleError),
}

/// Why a `[[strands]]` entry is refused.
#[derive(Debug, thiserror::Error)]
pub enum StrandError {
    /// Fewer than two points.
    #[error("points has {points} point(s); give at least 2, root first")]
    TooFewPoints {
        /// Points given.
        points: usize,
    },
    /// A point is not finite.
    #[error("points[{point}] is not finite")]
    NotFinite {
        /// The point.
        point: usize,
    },
    /// `mass_per_length` is not a finite density > 0.
    #[error("mass_per_length = {value}: use a finite density > 0 kg/m")]
    MassPerLength {
        /// The value given, kg/m.
        value: f32,
    },
    /// `masses` does not give one mass per point.
    #[error("masses has {given} values for {points} points; give one per point")]
    Masses {
        /// Masses given.
        given: usize,
        /// Points of the strand.
        points: usize,
    },
    /// `pinned` names a point the strand does not have.
    #[error(
        "pinned names point {point} but the strand has {points} points (0–{})",
        .points - 1
    )]
    Pinned {
        /// The point named.
        point: usize,
        /// Points of the strand.
        points: usize,
    },
    /// The strand set refuses the strand.
    #[error("{0}")]
    Invalid(#[source] HairError),
}

/// Why a `[[colliders]]` entry is refused; [`SceneProblem::Collider`] names the collider.
#[derive(Debug, thiserror::Error)]
pub enum ColliderError {
    /// Its shape's mesh cannot be read.
    #[error("shape: {0}")]
    Shape(#[source] MeshSourceError),
    /// Its shape, thickness or friction is out of range.
    #[error("{}", collider_text(.0))]
    Invalid(#[source] HairError),
    /// Its `[colliders.motion]` is refused.
    #[error("motion: {0}")]
    Motion(#[source] MotionError),
}

/// Why a mesh the scene names (the scalp, a collider's shape) cannot be read or made.
#[derive(Debug, thiserror::Error)]
pub enum MeshSourceError {
    /// A deforming mesh (USD, OBJ sequence) cannot be read over the scene's frames.
    #[error("{0}")]
    Deforming(#[from] DeformingError),
    /// The UV sphere's sizes are refused.
    #[error("uv-sphere: {0}")]
    UvSphere(#[source] GroomError),
    /// The OBJ file cannot be read.
    #[error("{0}")]
    Obj(#[source] GroomError),
}

/// ` (name)` for a named collider, nothing otherwise.
pub(crate) fn named(name: &str) -> String {
    if name.is_empty() {
        String::new()
    } else {
        format!(" ({name})")
    }
}

/// `substeps` as the scene wrote it.
fn substeps_text(given: &SubstepsValue) -> String {
    match given {
        SubstepsValue::Count(n) => n.to_string(),
        SubstepsValue::Word(w) => format!("{w:?}"),
    }
}

/// A collider's error without the solver's collider number (the scene names the collider).
fn collider_text(e: &HairError) -> String {
    match e {
        HairError::Collider { message, .. } => message.clone(),
        other => other.to_string(),
    }
}

/// A [`SettleError`] in the scene's words: its sections, keys and fixes.
fn settle_text(e: &SettleError) -> String {
    match e {
        SettleError::SagFreeWithFactors => {
            "[solver] sag_free solves rest shapes for one material, but [[regions]] or \
             [maps.stiffness] give hair its own: remove sag_free or the regions"
                .into()
        }
        SettleError::SagFreeModel => "[solver] sag_free is for the mass-spring model; remove it \
                                      or set model = \"mass-spring\""
            .into(),
        SettleError::Unbalanced {
            count,
            total,
            first,
        } => format!(
            "[solver] sag_free: {count} of {total} strands (first: strand {first}) cannot be \
             held in their groomed shape by the bending springs without turning a rest \
             direction more than 60°; raise [physics] bend_stiffness, shorten the hair or groom \
             it to hang"
        ),
        SettleError::HairHairGrid(e) => format!("[hair_hair] {e}"),
        SettleError::Collider { message, .. } => message.clone(),
        SettleError::Anchor(e) | SettleError::SagFree(e) => e.to_string(),
    }
}
