//! The scene format version: the top-level `version` key of a scene file.
//!
//! The key lets the format change without silently misreading old files. The rules:
//! - absent = version 1: every scene written before the key existed is a version 1 file, and
//!   keeps loading unchanged;
//! - 1 to [`SCENE_VERSION`]: read;
//! - newer: refused before any other key is read, naming the file, `version` and the fix
//!   (a newer format's keys would otherwise show as "unknown field" errors that hide the cause);
//! - anything else (0, negative, not an integer): refused, naming the key and the fix.
//!
//! `hairsys scene init` and every scene under `scenes/` carry `version = 1` on their first line.

use serde::Deserialize;

/// The newest scene format version this build reads (and the one `hairsys scene init` writes).
pub const SCENE_VERSION: u32 = 1;

/// `version` of a scene file without the key.
pub(crate) fn first_version() -> u32 {
    1
}

/// Is `v` version 1 (left out when a scene is serialised)?
pub(crate) fn is_first(v: &u32) -> bool {
    *v == 1
}

/// Reads the top-level `version` key alone (every other key ignored), so that a scene of a newer
/// format is refused by its version rather than by the first key this build does not know.
#[derive(Deserialize)]
struct VersionProbe {
    #[serde(default)]
    version: Option<toml::Value>,
}

/// Checks the top-level `version` of scene `text`: absent, or a whole number from 1 to
/// [`SCENE_VERSION`]. Text that is not valid TOML passes (the full parse reports it).
pub(crate) fn check(text: &str) -> Result<(), VersionError> {
    let Ok(VersionProbe {
        version: Some(value),
    }) = toml::from_str::<VersionProbe>(text)
    else {
        return Ok(());
    };
    match value.as_integer() {
        Some(v) if (1..=i64::from(SCENE_VERSION)).contains(&v) => Ok(()),
        Some(v) if v > i64::from(SCENE_VERSION) => Err(VersionError::Newer { version: v }),
        _ => Err(VersionError::Invalid { given: value }),
    }
}

/// Why a scene's `version` key is refused (checked before the rest of the scene is read, so a
/// newer scene's new keys are not reported as unknown).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum VersionError {
    /// The scene is written for a newer scene format than this hairsys reads: update hairsys.
    #[error(
        "version = {version}: this scene is written for scene format {version}, but this \
         hairsys reads format {max} at most; update hairsys, or rewrite the scene for format \
         {max} and set version = {max}",
        max = SCENE_VERSION
    )]
    Newer {
        /// The scene's `version`.
        version: i64,
    },
    /// `version` is not a whole number from 1 to [`SCENE_VERSION`].
    #[error(
        "version = {given}: the scene format version is a whole number from 1 to {max}; write \
         version = {max} (or leave it out: absent = 1)",
        max = SCENE_VERSION
    )]
    Invalid {
        /// The value given, as written.
        given: toml::Value,
    },
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{SceneFile, DEFAULT_SCENE};
    use std::path::PathBuf;

    fn parse(text: &str) -> Result<SceneFile, String> {
        SceneFile::parse(text, "v.toml", PathBuf::from(".")).map_err(|e| e.to_string())
    }

    /// The default scene without its `version` line: a file from before the key existed.
    fn unversioned() -> String {
        DEFAULT_SCENE
            .lines()
            .filter(|l| !l.starts_with("version"))
            .collect::<Vec<_>>()
            .join("\n")
    }

    #[test]
    fn scene_init_output_starts_with_the_current_version() {
        let first = DEFAULT_SCENE.lines().next().unwrap();
        assert!(
            first.starts_with(&format!("version = {SCENE_VERSION} ")),
            "{first}"
        );
        assert_eq!(parse(DEFAULT_SCENE).unwrap().scene.version, SCENE_VERSION);
    }

    #[test]
    fn every_shipped_scene_names_its_version_and_parses() {
        let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../scenes");
        let mut files = Vec::new();
        for dir in [root.clone(), root.join("validation")] {
            for entry in std::fs::read_dir(&dir).unwrap() {
                let path = entry.unwrap().path();
                if path.extension().is_some_and(|e| e == "toml") {
                    files.push(path);
                }
            }
        }
        assert!(files.len() >= 10, "{files:?}");
        for path in files {
            let text = std::fs::read_to_string(&path).unwrap();
            assert!(
                text.lines().any(|l| l.starts_with("version = 1 ")),
                "{} has no version line",
                path.display()
            );
            let scene = SceneFile::load(&path).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(scene.scene.version, 1, "{}", path.display());
        }
    }

    #[test]
    fn a_scene_without_version_is_read_as_version_1_with_the_same_hash() {
        let old = parse(&unversioned()).unwrap();
        let new = parse(DEFAULT_SCENE).unwrap();
        assert_eq!(old.scene.version, 1);
        assert_eq!(old.scene, new.scene);
        assert_eq!(old.hash().unwrap(), new.hash().unwrap());
    }

    #[test]
    fn newer_version_is_refused_naming_file_key_and_fix_before_its_new_keys() {
        let newer = format!(
            "version = {}\n{}\nkey_of_a_future_format = true\n",
            SCENE_VERSION + 1,
            unversioned()
        );
        let e = parse(&newer).unwrap_err();
        assert!(e.starts_with("v.toml: version = 2"), "{e}");
        assert!(e.contains("update hairsys"), "{e}");
        assert!(!e.contains("unknown field"), "{e}");
    }

    #[test]
    fn version_that_is_not_a_positive_whole_number_is_refused() {
        for bad in ["0", "-1", "1.5", "\"1\""] {
            let e = parse(&format!("version = {bad}\n{}", unversioned())).unwrap_err();
            assert!(
                e.starts_with(&format!("v.toml: version = {bad}")) && e.contains("whole number"),
                "{bad}: {e}"
            );
        }
    }
}
