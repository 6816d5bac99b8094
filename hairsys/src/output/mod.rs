//! Outputs of a simulation, each opened from a cache alone through one [`Shot`] (or built from a
//! scene's rest state where no cache is given):
//!
//! | output | command | module |
//! |---|---|---|
//! | render children of a frame, with motion-blur samples | `hairsys render-children export` | [`children`] |
//! | a whole run (strands or children) as one animated USD file (Cargo feature `usd`) | `hairsys cache export` | `shot_export` |
//! | hair cards of the strip model | `hairsys render-children cards` | [`cards`] |
//! | pictures of frames with the scalp and colliders (Cargo feature `preview`) | `hairsys preview` | `preview` |
//! | penetration, stretch, hairpins and velocities of every frame | `hairsys preview --report` | [`quality`] |

pub mod cards;
pub mod children;
#[cfg(feature = "preview")]
pub mod preview;
pub mod quality;
pub mod shot;
#[cfg(feature = "usd")]
pub mod shot_export;

mod error;

pub use error::OutputError;
pub use shot::{Shot, ShotError};
