//! The runtime data that drives a simulation over time: how the scalp and the colliders move.
//!
//! The scene schema ([`crate::scene`]) says what a file asks for; the rig is what a built
//! [`crate::build::Simulation`] evaluates at a (possibly fractional) frame, whichever door built
//! it.

pub mod animated_guides;
pub mod maps;
mod motion;

pub use motion::Motion;
