//! # hair-render
//!
//! The render level of hairsys (seed 001, "Rendering"): child hairs generated on request from the
//! simulation level at any instant, so every renderer and the viewport get the same hair.
//!
//! - [`Parents`]: parent polylines at one instant (flat positions + offsets, as
//!   `hair_core::StrandSet` and the cache hold them), their root frames and scalp attributes;
//! - [`generate`] with [`ChildSettings`] (mode, count, spread, seed, subdivision, [`Shape`]: clump,
//!   curl, roughness, length variation, taper) and a [`Lod`] (render, or display: a fraction of
//!   the children with fewer points) → [`ChildBuffers`], flat arrays a host renderer consumes;
//! - [`export`]: USD `BasisCurves` (`.usdc`/`.usda`, with time samples or velocities for motion blur)
//!   and Cem Yuksel's `.hair`;
//! - [`preview`]: a CPU renderer of strands and meshes to PNG (shaded meshes, anti-aliased
//!   Kajiya–Kay hair, preset cameras, contact sheets) for previews without a GPU (Cargo feature
//!   `preview`, on by default).
//!
//! `export` and `preview::PreviewImage::write_png` are the only code that does I/O.
//!
//! ```
//! use hair_render::{generate, ChildCount, ChildSettings, Lod, Parents};
//! use nalgebra::Vector3;
//!
//! // Two straight parents of 5 points, 10 cm long.
//! let positions: Vec<_> = (0..2)
//!     .flat_map(|p| (0..5).map(move |i| Vector3::new(0.01 * p as f32, 0.0, 0.025 * i as f32)))
//!     .collect();
//! let parents = Parents::new(&positions, &[0, 5, 10]).unwrap();
//! let settings = ChildSettings { count: ChildCount::PerParent(20), ..Default::default() };
//! let children = generate(&parents, &settings, Lod::Render).unwrap();
//! assert_eq!(children.curve_count(), 40);
//! assert_eq!(children.point_count(), 40 * 17); // 4 segments × 4 pieces + 1
//! ```
//!
//! Two distributions ([`ChildMode`]): *simple* children grouped around one parent (the
//! distribution seed 001 prefers) and *interpolated* children rooted between parents, each a blend
//! of its nearest parents.

pub mod buffers;
pub mod cards;
pub mod children;
pub mod error;
pub mod export;
pub mod lod;
pub mod parents;
mod path;
#[cfg(feature = "preview")]
pub mod preview;
mod rng;
pub mod shape;
pub mod subdivide;

pub use buffers::{ChildBuffers, Extent};
pub use cards::{build_cards, CardMesh, CardSettings};
pub use children::{generate, generate_into, ChildCount, ChildMode, ChildSettings};
pub use error::{InputError, RenderError, Result};
pub use lod::{DisplayLod, Lod};
pub use parents::{Parents, ScalpRoots, ShapeFactors};
pub use shape::{Clump, Curl, Roughness, Shape, Taper};
