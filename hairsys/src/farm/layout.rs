//! Where a farm job's tasks write, under the job's output folder (the `OutputDir` job parameter):
//!
//! ```text
//! OUT/shot.usda                              the shot stage: one prim per character
//! OUT/NAME/NAME.mcap                         the character's cache (Simulate)
//! OUT/NAME/NAME.usda                         the character's layer: its chunks as value clips
//! OUT/NAME/chunks/NAME.FIRST-LAST.usdc       one Export task's frames (4-digit, zero-padded)
//! ```

use std::path::PathBuf;

/// The paths of a job's outputs under one folder.
#[derive(Debug, Clone)]
pub struct OutputLayout {
    /// The output folder.
    pub root: PathBuf,
}

impl OutputLayout {
    /// The layout under `root`.
    pub fn new(root: impl Into<PathBuf>) -> Self {
        Self { root: root.into() }
    }

    /// The character's folder.
    pub fn character_dir(&self, name: &str) -> PathBuf {
        self.root.join(name)
    }

    /// The character's cache.
    pub fn cache(&self, name: &str) -> PathBuf {
        self.character_dir(name).join(format!("{name}.mcap"))
    }

    /// The folder of the character's chunk files.
    pub fn chunk_dir(&self, name: &str) -> PathBuf {
        self.character_dir(name).join("chunks")
    }

    /// The chunk file of frames `first`–`last` of the character.
    pub fn chunk(&self, name: &str, (first, last): (u32, u32)) -> PathBuf {
        self.chunk_dir(name)
            .join(chunk_file_name(name, (first, last)))
    }

    /// The character's layer (its chunks stitched by value clips).
    pub fn character_layer(&self, name: &str) -> PathBuf {
        self.character_dir(name).join(format!("{name}.usda"))
    }

    /// The shot stage.
    pub fn stage(&self) -> PathBuf {
        self.root.join("shot.usda")
    }
}

/// `NAME.FIRST-LAST.usdc`, frames zero-padded to 4 digits.
pub fn chunk_file_name(name: &str, (first, last): (u32, u32)) -> String {
    format!("{name}.{first:04}-{last:04}.usdc")
}

/// The frames of chunk file `file_name` of character `name` (`None` for any other file, such
/// as a `.partial` left by a killed export).
pub fn parse_chunk_file_name(name: &str, file_name: &str) -> Option<(u32, u32)> {
    let range = file_name
        .strip_prefix(name)?
        .strip_prefix('.')?
        .strip_suffix(".usdc")?;
    let (a, b) = range.split_once('-')?;
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|c| c.is_ascii_digit());
    if !(digits(a) && digits(b)) {
        return None;
    }
    Some((a.parse().ok()?, b.parse().ok()?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunk_names_round_trip_and_other_files_are_not_chunks() {
        let name = chunk_file_name("alice", (1, 10));
        assert_eq!(name, "alice.0001-0010.usdc");
        assert_eq!(parse_chunk_file_name("alice", &name), Some((1, 10)));
        assert_eq!(
            parse_chunk_file_name("alice", "alice.1001-12000.usdc"),
            Some((1001, 12000))
        );
        for other in [
            "alice.0001-0010.usdc.partial",
            "bob.0001-0010.usdc",
            "alice_b.0001-0010.usdc",
            "alice.0001.usdc",
            "alice.a-b.usdc",
        ] {
            assert_eq!(parse_chunk_file_name("alice", other), None, "{other}");
        }
    }
}
