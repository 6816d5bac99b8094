//! A shot on a render farm: an [Open Job Description](https://github.com/OpenJobDescription/openjd-specifications)
//! job (`jobtemplate-2023-09`) that simulates each character, exports frame chunks in parallel
//! and stitches them into one shot stage, bit for bit what one machine would write.
//!
//! ## The job
//! [`job::write_job`] turns a [`ShotFile`] into a job bundle folder:
//! `template.yaml`, `parameter_values.yaml` and `asset_references.yaml` (the files AWS Deadline
//! Cloud's `deadline bundle submit` reads), `job_parameters.yaml` (the same values for `openjd
//! run -p file://…`) and `commands.txt` (the same tasks as one command line each, for managers that run command
//! lines). The template has three steps, each task one `hairsys farm …` command:
//!
//! | step | tasks | a task runs | writes |
//! |---|---|---|---|
//! | Simulate | one per character | [`task::simulate_character`] | `NAME/NAME.mcap` |
//! | Export (after Simulate) | characters with USD × frame chunks (`TASK_CHUNKING`, contiguous, `ChunkSize` frames) | [`task::export_chunk`] | `NAME/chunks/NAME.A-B.usdc` |
//! | Assemble (after Export) | one | [`assemble::assemble`] | `NAME/NAME.usda`, `shot.usda` |
//!
//! The shot file and the output folder are `PATH` job parameters, so the farm maps them to
//! where its workers mount them; the scenes are found relative to the shot file. Every task
//! re-reads the shot and refuses it if its SHA-256 is no longer the one the job recorded (the
//! job's task list was made from it).
//!
//! ## Why the chunks stitch bit for bit
//! A simulation is sequential in time, so each character is one task. Everything after it reads
//! the cache alone and is independent per time code: a chunk export of frames `A`–`B` writes
//! the same time codes, with the same values, as one export of the whole range writes for
//! those frames (`hairsys cache export`, [`crate::output::shot_export`]), because
//! - time codes are absolute frame numbers (plus the shot's `time_offset`), and sub-frame
//!   shutter samples around `A` and `B` are taken from the cache's interpolation, which holds
//!   every frame of the shot;
//! - the two decisions that look beyond a time code are made over the whole shot
//!   ([`ShotOptions::context`](crate::output::shot_export::ShotOptions::context)): children
//!   velocities (central differences) take their neighbours across chunk borders, and `/scalp`
//!   is animated in every chunk when it moves anywhere in the shot.
//!
//! The character layer sub-layers the first chunk (topology, widths, UVs) and stitches all
//! chunks with USD value clips on the curves prim and `/scalp`: clip `k` becomes active at the
//! first time code chunk `k` writes, and clip times map stage time to itself. So every time
//! sample of the stitched layer is the whole export's sample, from the chunk that owns it; the
//! tests compare them attribute by attribute with Pixar's `usd-core`.
//!
//! ## Failure and retry
//! - A Simulate task that finds the complete cache of this scene and frame range does nothing;
//!   one that finds `NAME.mcap.partial` from the same scene and range continues it
//!   (`simulate --resume`), so a retried task ends with the bytes of an uninterrupted run
//!   (except the rod model, which resumes to round-off); anything else starts over.
//! - An Export task writes its chunk as `….usdc.partial` and renames it when complete, so a
//!   killed or failed task leaves no half-written file under the chunk's name, and a re-run
//!   replaces the old chunk in one rename. After writing, it deletes the character's chunk files
//!   of other ranges that overlap its own (left by an earlier job with another chunk size).
//! - Assemble refuses chunk files that leave a frame uncovered or cover one twice, naming them.
//!
//! ## Limits
//! OpenJD orders steps, not tasks: every Export task waits for every Simulate task. Two tasks
//! exporting the same chunk at once (a retry while a lost worker still runs) share one
//! `.partial` name; farm managers do not run one task twice at once.

pub mod assemble;
mod error;
pub mod job;
pub mod layout;
pub mod task;
pub mod yaml;

pub use error::FarmError;
pub use layout::OutputLayout;

use std::path::Path;

use crate::shot::ShotFile;

/// The most frames one Export task takes (AWS Deadline Cloud's limit on a chunk).
pub const MAX_CHUNK_SIZE: u32 = 150;

/// The chunk size a job gets unless told otherwise, frames per Export task.
pub const DEFAULT_CHUNK_SIZE: u32 = 30;

/// Refuses `shot` when a job recorded another digest for it (`expected`: the full digest or a
/// prefix of at least 12 hex digits).
pub fn check_digest(shot: &ShotFile, expected: Option<&str>) -> Result<(), FarmError> {
    match expected {
        Some(e) if e.len() < 12 || !shot.digest.starts_with(&e.to_ascii_lowercase()) => {
            Err(FarmError::ShotChanged {
                path: shot.path.clone(),
                expected: e.chars().take(12).collect(),
                found: shot.digest[..12].to_string(),
            })
        }
        _ => Ok(()),
    }
}

/// Contiguous chunks of frames `first`–`last` with `size` frames each (the last may be
/// shorter): the tasks `commands.txt` lists. An OpenJD runner may split a `CHUNK[INT]` range
/// into other contiguous chunks of at most `size` frames (`openjd run` evens them out: 48
/// frames by 10 are 1-10, 11-20, 21-29, 30-39, 40-48); Assemble takes any that cover the shot
/// once.
pub fn chunks((first, last): (u32, u32), size: u32) -> Vec<(u32, u32)> {
    let size = size.max(1);
    let mut out = Vec::new();
    let mut a = first;
    loop {
        let b = a.saturating_add(size - 1).min(last);
        out.push((a, b));
        if b >= last {
            return out;
        }
        a = b + 1;
    }
}

/// Writes `bytes` to `path` atomically: into `path.partial` in the same folder, synced, then
/// renamed over `path`.
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), FarmError> {
    use std::io::Write as _;
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".partial");
    let partial = path.with_file_name(name);
    let result = (|| {
        let mut file = std::fs::File::create(&partial)?;
        file.write_all(bytes)?;
        file.sync_all()?;
        std::fs::rename(&partial, path)
    })();
    result.map_err(|e| {
        let _ = std::fs::remove_file(&partial);
        FarmError::io(
            path,
            format!("cannot write ({e}); check the folder and the disk"),
        )
    })
}

/// Creates folder `dir` and its parents.
pub(crate) fn create_dir(dir: &Path) -> Result<(), FarmError> {
    std::fs::create_dir_all(dir).map_err(|e| {
        FarmError::io(
            dir,
            format!("cannot create the folder ({e}); check the path and its permissions"),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunks_tile_the_range_with_a_shorter_last_chunk() {
        assert_eq!(chunks((1, 48), 10).len(), 5);
        assert_eq!(chunks((1, 48), 10)[4], (41, 48));
        assert_eq!(chunks((1, 48), 48), vec![(1, 48)]);
        assert_eq!(chunks((1, 48), 150), vec![(1, 48)]);
        assert_eq!(chunks((5, 5), 30), vec![(5, 5)]);
        assert_eq!(chunks((1, 4), 1), vec![(1, 1), (2, 2), (3, 3), (4, 4)]);
    }
}
