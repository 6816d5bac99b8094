//! The runtime data that drives a simulation over time: how the scalp and the colliders move.
//!
//! The scene schema ([`crate::scene`]) says what a file asks for; the rig is what a built
//! [`crate::scene::Simulation`] evaluates at a (possibly fractional) frame, whichever door built
//! it.

mod motion;

pub use motion::Motion;
