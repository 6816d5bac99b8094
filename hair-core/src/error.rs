//! Typed errors of the simulation level.
//!
//! Messages name the item at fault (triangle, strand, point, parameter) and the fix, because a host
//! shows them to an artist as they are. File names are added by the layer that read the file.

use thiserror::Error;

/// Everything `hair-core` can refuse or detect.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum HairError {
    /// A mesh has no triangles, an index out of range or a triangle of zero area.
    #[error("mesh: {0}")]
    Mesh(#[from] MeshError),
    /// A parameter is negative, non-finite or out of its range.
    #[error("parameter `{name}` = {value}: {fix}")]
    Parameter {
        /// Name of the parameter as it appears in the scene file.
        name: String,
        /// The offending value, printed.
        value: String,
        /// What the user should do instead.
        fix: String,
    },
    /// A strand is malformed (too few points, zero-length segment, non-finite point).
    #[error("strand {strand}: {message}")]
    Strand {
        /// Index of the strand in its set.
        strand: usize,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// A collider is unusable (size, thickness, friction, pose, mesh).
    #[error("collider {collider}: {message}")]
    Collider {
        /// Index of the collider in its set (insertion order from 0).
        collider: usize,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// The solver left its stability region: the run stops instead of writing garbage.
    #[error(
        "simulation blew up at frame {frame}, strand {strand}: {cause}. {}",
        unstable_advice(*.dt, *.bound, *.auto_substeps)
    )]
    Unstable {
        /// Frame number being computed when it was detected (numbered like [`crate::FrameReport::frame`]).
        frame: u32,
        /// Strand in which it was detected first (lowest index).
        strand: usize,
        /// What was detected.
        cause: Blowup,
        /// Substep length in use, seconds.
        dt: f64,
        /// Predicted stable limit 2/ω, seconds.
        bound: f64,
        /// Substeps per step that `substeps = "auto"` would choose.
        auto_substeps: u32,
    },
}

/// What is wrong with a mesh, a sample on it, or its use for strips.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum MeshError {
    /// The mesh has no triangle.
    #[error("the mesh has no triangles")]
    NoTriangles,
    /// A triangle uses a vertex the mesh does not have.
    #[error("triangle {triangle} uses vertex {vertex} but the mesh has only {vertices} vertices")]
    VertexIndex {
        /// The triangle.
        triangle: usize,
        /// The vertex index it uses.
        vertex: u32,
        /// Number of vertices of the mesh.
        vertices: u32,
    },
    /// A triangle has (numerically) zero area.
    #[error(
        "triangle {triangle} (vertices {}, {}, {}) is degenerate (area {area:.3e}); remove \
         degenerate faces before use (Blender: Mesh > Clean Up > Merge by Distance / Degenerate \
         Dissolve)",
        .corners[0], .corners[1], .corners[2]
    )]
    Degenerate {
        /// The triangle.
        triangle: usize,
        /// Its vertices.
        corners: [u32; 3],
        /// Its area, m².
        area: f32,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate {position:?}")]
    NonFiniteVertex {
        /// The vertex.
        vertex: usize,
        /// Its position, m.
        position: [f32; 3],
    },
    /// Not one UV per vertex.
    #[error("{uvs} UVs for {vertices} vertices: give one UV per vertex")]
    UvCount {
        /// Number of UVs given.
        uvs: usize,
        /// Number of vertices of the mesh.
        vertices: usize,
    },
    /// A texture coordinate is NaN or infinite.
    #[error(
        "vertex {vertex} has a non-finite texture coordinate {uv:?}; fix or remove the `vt` line"
    )]
    NonFiniteUv {
        /// The vertex.
        vertex: usize,
        /// Its texture coordinate.
        uv: [f32; 2],
    },
    /// A vertex colour is NaN or infinite.
    #[error("vertex {vertex} has a non-finite colour {color:?}; fix its `v x y z r g b` line")]
    NonFiniteColor {
        /// The vertex.
        vertex: usize,
        /// Its RGB colour.
        color: [f32; 3],
    },
    /// New vertex positions do not match the mesh's vertex count.
    #[error(
        "{positions} new vertex positions for a mesh of {vertices} vertices: the topology cannot \
         change"
    )]
    PositionCount {
        /// Number of positions given.
        positions: usize,
        /// Number of vertices of the mesh.
        vertices: usize,
    },
    /// A mesh sample lies on a triangle the mesh does not have.
    #[error("mesh sample on triangle {triangle} but the mesh has {triangles} triangles")]
    SampleTriangle {
        /// The sample's triangle.
        triangle: u32,
        /// Number of triangles of the mesh.
        triangles: usize,
    },
    /// A mesh sample's barycentric weights are not in [0, 1] or do not sum to 1.
    #[error("mesh sample weights {weights:?} must lie in [0, 1] and sum to 1")]
    SampleWeights {
        /// The weights.
        weights: [f32; 3],
    },
    /// No triangle is selected for strips.
    #[error("no scalp triangle selected for strips; widen the strip region")]
    NoStripTriangle,
    /// A strip triangle is not a triangle of the scalp.
    #[error("strip triangle {triangle} is out of range: the scalp has {triangles} triangles")]
    StripTriangle {
        /// The triangle asked for.
        triangle: u32,
        /// Number of triangles of the scalp.
        triangles: usize,
    },
    /// A strip triangle is too small to carry a strip.
    #[error(
        "scalp triangle {triangle} (area {area:.3e} m²) is too small for a strip (width \
         {width:.3e} m < {:e} m); remove degenerate faces or leave the triangle out of the strip \
         region",
        crate::model::strips::MIN_STRIP_WIDTH
    )]
    StripTooSmall {
        /// The triangle.
        triangle: u32,
        /// Its area, m².
        area: f32,
        /// The strip's width there, m.
        width: f32,
    },
    /// parry cannot build an oriented mesh of the head for strip collision.
    #[error(
        "the head mesh cannot be used for strip collision ({0}); give a closed, consistently \
         oriented mesh"
    )]
    Head(#[source] parry3d::shape::TriMeshBuilderError),
    /// parry cannot build a searchable mesh of the scalp.
    #[error("the scalp cannot be searched: {0}")]
    Unsearchable(#[source] parry3d::shape::TriMeshBuilderError),
}

/// What showed that a strand left the solver's stability region.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum Blowup {
    /// A point's position or velocity is NaN or infinite.
    #[error("non-finite position or velocity at point {point}")]
    NonFinite {
        /// The first free point that is not finite (index in its strand).
        point: usize,
    },
    /// The strand's kinetic and stretch energy per unit mass passed its limit.
    #[error("energy ran away ({specific:.3e} J/kg, limit {limit:.3e} J/kg)")]
    Energy {
        /// Energy per unit mass, J/kg.
        specific: f64,
        /// The limit, J/kg.
        limit: f64,
    },
    /// The rod model produced a non-finite position.
    #[error(
        "rod model: non-finite position at substep {substep} (the bound is the stiffest bending \
         on the lightest node)"
    )]
    RodNonFinite {
        /// The substep of the frame, from 1.
        substep: u32,
    },
    /// The rod model's projection failed to converge.
    #[error(
        "rod model: the projection did not converge (residual {residual:.3e} after {iterations} \
         iterations, limit rod.projection_iterations = {limit})"
    )]
    RodProjection {
        /// The residual left, m.
        residual: f64,
        /// Iterations done.
        iterations: u32,
        /// The iteration limit (`rod.projection_iterations`).
        limit: u32,
    },
}

/// Shorthand for results of this crate.
pub type Result<T, E = HairError> = std::result::Result<T, E>;

/// Checks that `value` is finite and ≥ 0, naming `name` in the error.
pub fn check_non_negative(name: &str, value: f32) -> Result<()> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(HairError::Parameter {
            name: name.to_string(),
            value: value.to_string(),
            fix: "must be a finite number ≥ 0".to_string(),
        })
    }
}

/// Checks that `value` is finite and > 0, naming `name` in the error.
pub fn check_positive(name: &str, value: f32) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(HairError::Parameter {
            name: name.to_string(),
            value: value.to_string(),
            fix: "must be a finite number > 0".to_string(),
        })
    }
}

/// What to do about a run that blew up with substep `dt` (s), small-angle stability bound
/// `bound` (s) and the substep count `"auto"` would pick.
fn unstable_advice(dt: f64, bound: f64, auto_substeps: u32) -> String {
    if dt > bound {
        format!(
            "The substep is {dt:.3e} s but the stability bound of the stiffest spring on the \
             lightest point is dt < 2/ω = {bound:.3e} s; use substeps = \"auto\" (it would pick \
             {auto_substeps}) or lower the stiffness"
        )
    } else {
        format!(
            "The substep {dt:.3e} s is within the stability bound for gently bent hair \
             (2/ω = {bound:.3e} s), but bending stiffens as a joint turns sharply (hair crushed \
             or folded by a fast collider): give more substeps than \"auto\" picks ({auto_substeps}; \
             try 4×), more [solver] steps, or a lower bend_stiffness"
        )
    }
}
