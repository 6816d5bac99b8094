//! # hair-groom
//!
//! The guide level of hairsys: the scalp meshes hair grows from ([`load_obj`], [`builtin_head`],
//! [`uv_sphere`]), seeded area-weighted root sampling on them ([`sample_area_weighted`]) and
//! generated straight hair ([`generate()`]) handed to `hair-core` as [`hair_core::StrandInput`]s.
//! Units are SI (m, kg), Z up; every random choice takes an explicit seed and gives bit-identical
//! results for it. No file I/O happens outside [`formats`], no terminal I/O anywhere; errors are
//! [`GroomError`]s that name the file or option at fault and the fix.
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
mod rng;
pub mod sampling;
pub mod shapes;

pub use error::GroomError;
pub use formats::obj::{load_obj, ObjOptions, UpAxis};
pub use generate::{generate, GenerateOptions};
pub use sampling::{sample_area_weighted, Region};
pub use shapes::{builtin_head, uv_sphere};
