//! The `hairsys` command as a library: scene files and the subcommands, so that the cross-crate
//! tests can load scenes and run the same code paths as the binary.

pub mod bench;
pub mod model;
pub mod motion;
pub mod progress;
pub mod render_cards;
pub mod render_children;
pub mod resume;
pub mod scene;
pub mod scene_children;
pub mod scene_fields;
pub mod scene_guides;
pub mod scene_strips;
pub mod simulate;
