//! The `hairsys` command as a library: scene files and the subcommands, so that the cross-crate
//! tests can load scenes and run the same code paths as the binary.

pub mod motion;
pub mod progress;
pub mod render_children;
pub mod resume;
pub mod scene;
pub mod scene_guides;
pub mod simulate;
