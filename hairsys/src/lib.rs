//! # hairsys
//!
//! The hairsys library: what a host needs to run hair on a character, above the domain crates
//! (`hair-core` physics, `hair-groom` grooms, `hair-cache` point caches, `hair-render` children).
//! The `hairsys` command, the Python module and the Blender add-on all go through it.
//!
//! - [`scene`]: the scene model (TOML, versioned by its keys, unknown keys refused, errors that
//!   name the file, the key and the fix) and its assembly into a [`build::Simulation`]: strands
//!   from guides or generated hair, the strand model, colliders, scalp, fields, hair–hair.
//! - [`Session`]: the one front door a host drives frame by frame (scalp as a transform or
//!   deformed vertices, collider poses, animatable parameters, `step()`, flat positions and
//!   velocities, snapshots for scrubbing, an optional cache).
//! - [`run`]: the batch run of a scene into a cache (`hairsys simulate`), with [`resume`].
//! - [`build`]: the one assembly path every door takes (a scene file, a host's arrays).
//! - [`output`]: render children, the shot export, cards, previews and quality reports, each
//!   opened from a cache alone ([`output::Shot`]).
//! - [`shot`] and [`farm`]: a shot of several characters (`shot.toml`) as an Open Job
//!   Description job that simulates per character, exports frame chunks and stitches them.
//!
//! ## Common tasks
//! | task | where |
//! |---|---|
//! | simulate a scene file into a cache | [`run::simulate`] |
//! | drive a groom frame by frame on a moving or deforming mesh | [`Session::from_scene`], [`Session::set_scalp_vertices`], [`Session::step`] |
//! | scrub: go back to an earlier frame | [`Session::snapshot`], [`Session::restore`] |
//! | continue a killed run | [`run::SimulateOptions::resume`] |
//! | export render children of a cached frame | [`output::children::export`] |
//! | children of the session's current frame, in memory | [`Session::children`] |
//! | simulate a host's curves on its mesh, given as arrays | [`Session::from_groom`] |
//! | hair cards of a strips scene | [`output::cards::export_cards`] |
//! | a shot's job for a render farm (OpenJD) | [`shot::ShotFile::load`], [`farm::job::write_job`] |
//!
//! ## Cargo features
//! | feature | default | what it brings |
//! |---|---|---|
//! | `parallel` | on | strands, contacts, guides and children on rayon's worker threads (off: the calling thread, or a host's pool through `Session::set_thread_pool`; the same bits either way) |
//! | `preview` | on | `output::preview`: PNG pictures of cached frames (CPU renderer, font, PNG encoder) |
//! | `usd` | on | USD stages in and out (openusd): grooms, scalps, deforming meshes and primvar maps read from USD; children and cards exported as USD; `output::shot_export`; [`farm`] |
//!
//! A host that draws and caches hair itself can build with `default-features = false`: without
//! `usd`, a scene naming a USD file is refused with an error that names the feature.
//!
//! ```no_run
//! use hairsys::{scene::SceneFile, Session};
//! let scene = SceneFile::load("scenes/default.toml".as_ref())?;
//! let mut session = Session::from_scene(&scene)?;
//! for _ in 0..24 {
//!     session.step()?; // the scene's keyframes move the head
//!     let first_point = session.positions()[0];
//!     println!("frame {}: {first_point:?}", session.frame());
//! }
//! # Ok::<(), hairsys::Error>(())
//! ```

pub mod accuracy;
pub mod budget;
pub mod build;
pub mod error;
#[cfg(feature = "usd")]
pub mod farm;
pub mod output;
pub mod plan;
pub mod resume;
pub mod rig;
pub mod run;
pub mod scene;
pub mod session;
pub mod shot;

pub use error::{Error, Result};
pub use session::{FrameView, Session, Snapshot};
