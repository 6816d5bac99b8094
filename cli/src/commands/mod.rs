//! One module per subcommand: its arguments (clap), its `run`, and what it prints.

pub mod bench;
pub mod cache;
mod cache_export;
mod cards;
pub mod farm;
pub mod groom;
pub mod plan;
pub mod preview;
pub mod render_children;
pub mod scene;
mod scene_check;
pub mod shot;
pub mod simulate;
