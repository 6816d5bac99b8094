//! # hair-groom
//!
//! The guide level of hairsys (seed 001, "Hair Levels"): the scalp meshes hair grows from
//! ([`load_obj`], [`builtin_head`], [`uv_sphere`]), seeded points on them ([`sample_area_weighted`],
//! [`sample_roots`] and [`sample_poisson_disk`] with an optional [`RootDensity`]), generated straight hair
//! handed to `hair-core` directly ([`generate()`]), and the guide workflow:
//!
//! 1. a [`Groom`] (world-space curves, m, Z up) read from a file ([`read_groom`]: Cem Yuksel
//!    `.hair`, TressFX `.tfx`, OBJ polylines, USD `BasisCurves` (`.usd`, `.usda`, `.usdc`, `.usdz`), with [`ImportOptions`]
//!    for unit scale and up axis) and summarised by [`groom_info`];
//! 2. [`Guide`]s — a root [`hair_core::MeshSample`] and a rest shape in the root frame — from
//!    [`snap_to_scalp`] (roots moved to the nearest scalp point, distances reported, far roots
//!    refused) or [`generate_guides`] (along the normal or combed, straight or curled), edited by
//!    the operators of [`ops`] and written back with [`guides_to_groom`] and [`write_groom`];
//! 3. simulation hairs whose rest shapes are interpolated from the nearest enabled guides
//!    ([`interpolate()`]), and guides as strands ([`Guide::to_strand_input`]).
//!
//! Units are SI (m, kg), Z up; every random choice takes an explicit seed and gives bit-identical
//! results for it. No file I/O happens outside [`formats`] and [`input_file`] (which refuses
//! directories, FIFOs and devices by name and caps what is read whole), no terminal I/O anywhere;
//! errors are [`GroomError`]s that name the file (and byte offset or line) or option at fault and
//! the fix.
//!
//! ```
//! use hair_core::StrandSet;
//! use hair_groom::{builtin_head, generate, GenerateOptions, Region};
//! use nalgebra::Vector3;
//!
//! let head = builtin_head();
//! let opts = GenerateOptions {
//!     count: 100,
//!     length: 0.15,
//!     segments: 12,
//!     seed: 1,
//!     radius: 0.002,
//!     mass_per_length: 1e-4,
//!     goal_root: 0.5,
//!     goal_tip: 0.0,
//!     region: Region::Cone { direction: Vector3::z(), max_angle_deg: 70.0 },
//!     length_variation: 0.2,
//! };
//! let mut strands = StrandSet::new();
//! for strand in generate(&head, &opts).unwrap() {
//!     strands.push(strand).unwrap();
//! }
//! assert_eq!(strands.point_count(), 100 * 13);
//! ```

pub mod error;
pub mod formats;
pub mod generate;
pub mod groom;
pub mod guides;
pub mod input_file;
pub mod interpolate;
pub mod ops;
pub mod reinterpolate;
mod rng;
pub mod sampling;
pub mod shapes;
pub mod snap;
pub mod style;
mod surface_distance;
pub mod trim;

pub use error::{FarRoot, FileLocation, GroomError};
pub use formats::hair::{read_hair, write_hair};
pub use formats::obj::{load_obj, load_obj_vertex_colors, ObjOptions, ObjParseError, UpAxis};
pub use formats::obj_curves::{read_obj_curves, write_obj_curves};
pub use formats::obj_sequence::ObjSequence;
pub use formats::tfx::{read_tfx, write_tfx};
#[cfg(feature = "usd")]
pub use formats::usd::{read_usd, read_usda, write_usda, UsdCurves, UsdReadOptions};
#[cfg(feature = "usd")]
pub use formats::usd_mesh::{CornerValues, PrimvarInterpolation, UsdMeshOptions, UsdMeshSource};
pub use formats::{read_groom, write_groom, GroomFormat, ImportOptions};
pub use generate::{generate, generate_with_density, GenerateOptions};
pub use groom::{groom_info, Groom, GroomInfo};
pub use guides::{generate_guides, Curl, GrowDirection, GuideOptions};
pub use interpolate::{interpolate, Distance, GuideWeight, InterpolateOptions, SimHair};
pub use reinterpolate::{GuideBlend, PoseError};
pub use sampling::{
    sample_area_weighted, sample_poisson_disk, sample_roots, DensityError, DensityValueError,
    Region, RootDensity, RootSampler, VertexDensity,
};
pub use shapes::{builtin_head, uv_sphere};
pub use snap::{guides_to_groom, snap_to_scalp, Guide, SnapOptions, Snapped};
pub use style::{
    hairs_turned_off_their_guides, lay_over_scalp, lift_out_of_scalp, strands_through_scalp,
    LiftMemory, Part, ScalpLift, StyleOptions,
};
pub use trim::{check_length_fractions, trim_polyline};
