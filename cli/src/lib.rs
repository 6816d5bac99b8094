//! The `hairsys` command as a library: what only the command has (progress display, the card
//! export's arguments and the bench), so that the cross-crate tests can run the bench's cases.
//! Scenes, runs, sessions and exports are the [`hairsys`] library's.

pub mod bench;
pub mod cache_export;
pub mod cards;
pub mod output;
pub mod plan;
pub mod progress;
pub mod quality_text;
pub mod scene_check;
