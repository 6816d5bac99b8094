//! # hair-render
//!
//! The render level of hairsys: child hairs (clumping, curl) generated on request from simulation
//! frames. Not built yet: this crate reserves its place in the data flow
//! groom → solver → cache → children (see `DESIGN.md`).
