//! The shot file (`shot.toml`): the characters of one shot, its frame range, and what to make of
//! them — the input of `hairsys shot check` and `hairsys farm job` ([`crate::farm`]).
//!
//! ```toml
//! version = 1
//!
//! [shot]
//! name = "sq010_sh020"
//! frames = [1001, 1096]          # every character is simulated over these frames
//!
//! [output]
//! usd = "strands"                # "strands", "children" or "none" (caches only)
//! shutter = [-0.25, 0.25]        # sub-frame samples, frames around each frame (optional)
//! motion_samples = 3             # samples over the shutter (default 3 with a shutter)
//! time_offset = 0                # frames added to every USD time code
//!
//! [[characters]]
//! name = "alice"                 # output name: cache, USD layer and prim (a USD identifier)
//! scene = "alice.toml"           # scene file, relative to the shot file
//! usd = "children"               # optional: this character's own `usd`
//! ```
//!
//! A shot is versioned like a scene ([`crate::scene::version`]): the top-level `version` is
//! absent (= 1) or a whole number up to [`SHOT_VERSION`]; a newer one is refused by its
//! version before any other key is read. Unknown keys are refused. Every error names the shot
//! file, the key and the fix ([`ShotError`]).
//!
//! The shot's frame range replaces each scene's `[scene] frames` (the hair is at rest at the
//! first frame, as `hairsys simulate --frames` does). Every character's scene must have the same
//! frame rate, since the shot stage has one `timeCodesPerSecond`. Loading a shot parses each
//! scene and reads every file it references (through the scene hash, which guards `--resume`);
//! it does not build the scenes.

use std::path::{Path, PathBuf};

use hair_cache::Shutter;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::scene::{SceneError, SceneFile};

/// The newest shot format version this build reads.
pub const SHOT_VERSION: u32 = 1;

/// Largest shot file read, bytes (1 MiB): a shot is a page of TOML.
pub const MAX_SHOT_FILE_BYTES: u64 = 1 << 20;

/// Why a shot file cannot be used. Every message names the shot file, the key and the fix.
#[derive(Debug, thiserror::Error)]
pub enum ShotError {
    /// The file cannot be read.
    #[error("{}: cannot read the shot file: {reason}", path.display())]
    Read {
        /// The shot file.
        path: PathBuf,
        /// Why, as the system said.
        reason: String,
    },
    /// The text is not a valid shot (TOML syntax, a missing or unknown key, a wrong type).
    #[error("{}: not a valid shot: {message}", path.display())]
    Parse {
        /// The shot file.
        path: PathBuf,
        /// The TOML parser's message (it names the key and the line).
        message: String,
    },
    /// The `version` key is newer than this build reads, or not a version at all.
    #[error(
        "{}: version = {found}: the shot format version is a whole number from 1 to \
         {SHOT_VERSION}; {fix}", path.display()
    )]
    Version {
        /// The shot file.
        path: PathBuf,
        /// The value found.
        found: String,
        /// What to do.
        fix: &'static str,
    },
    /// `[shot] frames` is not a range.
    #[error(
        "{}: [shot] frames = [{first}, {last}]: the last frame comes before the first; write \
         [FIRST, LAST] with FIRST ≤ LAST", path.display()
    )]
    Frames {
        /// The shot file.
        path: PathBuf,
        /// First frame given.
        first: u32,
        /// Last frame given.
        last: u32,
    },
    /// No `[[characters]]`.
    #[error(
        "{}: the shot has no [[characters]]; add one per character: [[characters]] name = \
         \"alice\", scene = \"alice.toml\"", path.display()
    )]
    NoCharacters {
        /// The shot file.
        path: PathBuf,
    },
    /// A character's name is not a USD identifier (it names files and the USD prim).
    #[error(
        "{}: [[characters]] #{index} name = {name:?}: a character's name is its USD prim and \
         file names; use letters, digits and `_`, not starting with a digit (e.g. \"alice_hair\")",
        path.display()
    )]
    Name {
        /// The shot file.
        path: PathBuf,
        /// Index of the character in `[[characters]]`, from 0.
        index: usize,
        /// The name given.
        name: String,
    },
    /// Two characters share a name.
    #[error(
        "{}: [[characters]] name = {name:?} is given twice; every character needs its own name \
         (its cache and USD files are named after it)", path.display()
    )]
    DuplicateName {
        /// The shot file.
        path: PathBuf,
        /// The name.
        name: String,
    },
    /// A character's scene cannot be used.
    #[error("{}: [[characters]] {character:?} scene: {source}", path.display())]
    Scene {
        /// The shot file.
        path: PathBuf,
        /// The character.
        character: String,
        /// Why the scene cannot be used (names the scene file, its key and the fix).
        source: SceneError,
    },
    /// Two characters' scenes run at different frame rates.
    #[error(
        "{}: [[characters]] {first:?} runs at {first_fps} fps and {other:?} at {other_fps} fps; \
         a shot has one frame rate: set the same [scene] fps in both scenes", path.display()
    )]
    Fps {
        /// The shot file.
        path: PathBuf,
        /// The first character.
        first: String,
        /// Its frame rate, frames per second.
        first_fps: f32,
        /// A character with another rate.
        other: String,
        /// Its frame rate, frames per second.
        other_fps: f32,
    },
    /// `[output] shutter` or `motion_samples` is not a shutter.
    #[error("{}: [output] shutter: {source}", path.display())]
    Shutter {
        /// The shot file.
        path: PathBuf,
        /// What is wrong.
        source: hair_cache::sample::InvalidShutter,
    },
    /// `motion_samples` without `shutter`.
    #[error(
        "{}: [output] motion_samples = {samples} without a shutter; add shutter = [OPEN, CLOSE] \
         (e.g. [-0.25, 0.25]) or remove motion_samples", path.display()
    )]
    SamplesWithoutShutter {
        /// The shot file.
        path: PathBuf,
        /// The samples given.
        samples: usize,
    },
    /// `time_offset` is not a finite number.
    #[error(
        "{}: [output] time_offset = {value}: give a finite number of frames (e.g. 1000 writes \
         frame 1 at time code 1001)", path.display()
    )]
    TimeOffset {
        /// The shot file.
        path: PathBuf,
        /// The value given.
        value: f64,
    },
}

/// What USD a character gets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum UsdOutput {
    /// The simulated strands as `/hair` (what `hairsys cache export` writes).
    #[default]
    Strands,
    /// Render children generated at every time code as `/children` (the scene's `[children]`,
    /// what `hairsys cache export --children` writes).
    Children,
    /// No USD: the cache only.
    None,
}

impl UsdOutput {
    /// The curves prim of the character's USD files (`None` without USD).
    pub fn prim(self) -> Option<&'static str> {
        match self {
            UsdOutput::Strands => Some("hair"),
            UsdOutput::Children => Some("children"),
            UsdOutput::None => None,
        }
    }
}

/// The whole shot file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Shot {
    /// `version`: the shot format version, 1 to [`SHOT_VERSION`]; absent = 1.
    #[serde(default = "first_version")]
    pub version: u32,
    /// `[shot]`: name and frame range.
    pub shot: ShotSection,
    /// `[output]`: what to make of every character.
    #[serde(default)]
    pub output: OutputSection,
    /// `[[characters]]`: the characters, each a scene and an output name.
    #[serde(default)]
    pub characters: Vec<Character>,
}

fn first_version() -> u32 {
    1
}

/// `[shot]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShotSection {
    /// Free-form name, shown in reports and the job's name.
    #[serde(default)]
    pub name: String,
    /// First and last frame `[first, last]`, inclusive; the hair is at rest at the first.
    pub frames: [u32; 2],
}

/// `[output]`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSection {
    /// The USD every character gets unless it names its own (default strands).
    #[serde(default)]
    pub usd: UsdOutput,
    /// Sub-frame samples `[open, close]`, frames around each frame (motion blur); absent = the
    /// frames only.
    #[serde(default)]
    pub shutter: Option<[f64; 2]>,
    /// Samples over the shutter (default 3 with a shutter).
    #[serde(default)]
    pub motion_samples: Option<usize>,
    /// Frames added to every USD time code (default 0).
    #[serde(default)]
    pub time_offset: f64,
}

/// `[[characters]]`: one character.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Character {
    /// Output name: the cache `NAME.mcap`, the USD layer `NAME.usda` and the prim `/NAME` of
    /// the shot stage. A USD identifier.
    pub name: String,
    /// Scene file, relative to the shot file.
    pub scene: PathBuf,
    /// This character's USD (default: `[output] usd`).
    #[serde(default)]
    pub usd: Option<UsdOutput>,
}

/// A loaded and checked shot: where it came from, its digest, the schema and every character's
/// scene.
#[derive(Debug, Clone)]
pub struct ShotFile {
    /// The shot file as given.
    pub path: PathBuf,
    /// SHA-256 (hex) of the file's bytes: a farm job records it, and its tasks refuse a shot
    /// file that changed since ([`crate::farm`]).
    pub digest: String,
    /// The parsed shot.
    pub shot: Shot,
    /// Each character's scene, in `[[characters]]` order.
    pub scenes: Vec<SceneFile>,
    /// The motion-blur samples of `[output]`, if any.
    pub shutter: Option<Shutter>,
}

impl ShotFile {
    /// Reads, parses and checks a shot file and loads every character's scene (see the module
    /// docs).
    pub fn load(path: &Path) -> Result<Self, ShotError> {
        let bytes =
            hair_groom::input_file::read_regular_file(path, MAX_SHOT_FILE_BYTES).map_err(|e| {
                ShotError::Read {
                    path: path.to_path_buf(),
                    reason: e.to_string(),
                }
            })?;
        let text = String::from_utf8(bytes.clone()).map_err(|e| ShotError::Read {
            path: path.to_path_buf(),
            reason: format!(
                "byte {} is not UTF-8; a shot is TOML text",
                e.utf8_error().valid_up_to()
            ),
        })?;
        let shot = parse(&text, path)?;
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let digest = hex(&Sha256::digest(&bytes));
        Self::check(path, &base, shot, digest)
    }

    /// Checks `shot` (read from `path`, scenes relative to `base`).
    fn check(path: &Path, base: &Path, shot: Shot, digest: String) -> Result<Self, ShotError> {
        let p = || path.to_path_buf();
        let [first, last] = shot.shot.frames;
        if last < first {
            return Err(ShotError::Frames {
                path: p(),
                first,
                last,
            });
        }
        if shot.characters.is_empty() {
            return Err(ShotError::NoCharacters { path: p() });
        }
        for (index, c) in shot.characters.iter().enumerate() {
            if !is_identifier(&c.name) {
                return Err(ShotError::Name {
                    path: p(),
                    index,
                    name: c.name.clone(),
                });
            }
            if shot.characters[..index].iter().any(|o| o.name == c.name) {
                return Err(ShotError::DuplicateName {
                    path: p(),
                    name: c.name.clone(),
                });
            }
        }
        let out = &shot.output;
        if !out.time_offset.is_finite() {
            return Err(ShotError::TimeOffset {
                path: p(),
                value: out.time_offset,
            });
        }
        let shutter = match (out.shutter, out.motion_samples) {
            (None, None) => None,
            (None, Some(samples)) => {
                return Err(ShotError::SamplesWithoutShutter { path: p(), samples })
            }
            (Some([open, close]), samples) => Some(
                Shutter::new(open, close, samples.unwrap_or(3))
                    .map_err(|source| ShotError::Shutter { path: p(), source })?,
            ),
        };
        let mut scenes = Vec::with_capacity(shot.characters.len());
        for c in &shot.characters {
            let scene_error = |source| ShotError::Scene {
                path: p(),
                character: c.name.clone(),
                source,
            };
            let scene = SceneFile::load(&base.join(&c.scene)).map_err(scene_error)?;
            // Reads every file the scene references: a missing mesh shows now, not on the farm.
            scene.hash().map_err(scene_error)?;
            scenes.push(scene);
        }
        let fps = |i: usize| scenes[i].scene.scene.fps;
        if let Some(i) = (1..scenes.len()).find(|&i| fps(i) != fps(0)) {
            return Err(ShotError::Fps {
                path: p(),
                first: shot.characters[0].name.clone(),
                first_fps: fps(0),
                other: shot.characters[i].name.clone(),
                other_fps: fps(i),
            });
        }
        Ok(Self {
            path: path.to_path_buf(),
            digest,
            shot,
            scenes,
            shutter,
        })
    }

    /// First and last frame of the shot, inclusive.
    pub fn frames(&self) -> (u32, u32) {
        (self.shot.shot.frames[0], self.shot.shot.frames[1])
    }

    /// Frames per second (every character's scene has the same).
    pub fn fps(&self) -> f32 {
        self.scenes[0].scene.scene.fps
    }

    /// The character named `name` and its scene.
    pub fn character(&self, name: &str) -> Option<(&Character, &SceneFile)> {
        self.shot
            .characters
            .iter()
            .position(|c| c.name == name)
            .map(|i| (&self.shot.characters[i], &self.scenes[i]))
    }

    /// The USD `character` gets (its own `usd`, else `[output] usd`).
    pub fn usd_of(&self, character: &Character) -> UsdOutput {
        character.usd.unwrap_or(self.shot.output.usd)
    }

    /// The characters that get USD, in `[[characters]]` order.
    pub fn usd_characters(&self) -> impl Iterator<Item = &Character> {
        self.shot
            .characters
            .iter()
            .filter(|c| self.usd_of(c) != UsdOutput::None)
    }
}

/// Parses shot `text` read from `path`: the version first, then the schema.
fn parse(text: &str, path: &Path) -> Result<Shot, ShotError> {
    #[derive(Deserialize)]
    struct Probe {
        #[serde(default)]
        version: Option<toml::Value>,
    }
    if let Ok(Probe {
        version: Some(value),
    }) = toml::from_str::<Probe>(text)
    {
        match value.as_integer() {
            Some(v) if (1..=i64::from(SHOT_VERSION)).contains(&v) => {}
            Some(v) if v > i64::from(SHOT_VERSION) => {
                return Err(ShotError::Version {
                    path: path.to_path_buf(),
                    found: v.to_string(),
                    fix: "this shot is written for a newer hairsys: update hairsys, or rewrite \
                          the shot for this format",
                })
            }
            _ => {
                return Err(ShotError::Version {
                    path: path.to_path_buf(),
                    found: value.to_string(),
                    fix: "write version = 1 (or leave it out: absent = 1)",
                })
            }
        }
    }
    toml::from_str(text).map_err(|e| ShotError::Parse {
        path: path.to_path_buf(),
        message: e.to_string().trim_end().to_string(),
    })
}

/// Whether `name` is a USD identifier: ASCII letters, digits and `_`, not starting with a digit.
pub fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// Lower-case hex of `bytes`.
pub(crate) fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Writes `shot` and a small scene beside it in a fresh folder; returns the shot's path.
    fn write(name: &str, shot: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("hairsys-shot-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let scene = "version = 1\n[scene]\nframes = [1, 4]\n\n[[strands]]\npoints = [[0.0, 0.0, \
                     0.0], [0.0, 0.0, -0.1]]\n";
        std::fs::write(dir.join("a.toml"), scene).unwrap();
        std::fs::write(
            dir.join("fast.toml"),
            scene.replace("[scene]", "[scene]\nfps = 30.0"),
        )
        .unwrap();
        std::fs::write(dir.join("shot.toml"), shot).unwrap();
        dir.join("shot.toml")
    }

    fn load(name: &str, shot: &str) -> Result<ShotFile, String> {
        ShotFile::load(&write(name, shot)).map_err(|e| e.to_string())
    }

    const GOOD: &str = "version = 1\n[shot]\nframes = [1, 8]\n[output]\nshutter = [-0.25, 0.25]\n\
                        [[characters]]\nname = \"a\"\nscene = \"a.toml\"\n[[characters]]\nname = \
                        \"b\"\nscene = \"a.toml\"\nusd = \"none\"\n";

    #[test]
    fn a_good_shot_loads_with_its_scenes_shutter_and_usd_choices() {
        let shot = ShotFile::load(&write("good", GOOD)).unwrap();
        assert_eq!(shot.frames(), (1, 8));
        assert_eq!(shot.scenes.len(), 2);
        assert_eq!(shot.shutter.unwrap().samples, 3);
        let usd: Vec<_> = shot.usd_characters().map(|c| c.name.as_str()).collect();
        assert_eq!(usd, ["a"]);
        assert_eq!(shot.digest.len(), 64);
    }

    #[test]
    fn bad_shots_are_refused_naming_the_file_the_key_and_the_fix() {
        let cases = [
            (
                "version = 2",
                GOOD.replace("version = 1", "version = 2"),
                "update hairsys",
            ),
            (
                "frames",
                GOOD.replace("[1, 8]", "[8, 1]"),
                "[shot] frames = [8, 1]",
            ),
            (
                "unknown",
                GOOD.replace("[output]", "[output]\ncolour = 1"),
                "unknown field",
            ),
            (
                "name",
                GOOD.replace("\"a\"\nscene", "\"1a\"\nscene"),
                "name = \"1a\"",
            ),
            ("dup", GOOD.replace("\"b\"", "\"a\""), "given twice"),
            (
                "scene",
                GOOD.replace("scene = \"a.toml\"\nusd", "scene = \"x.toml\"\nusd"),
                "x.toml",
            ),
            (
                "fps",
                GOOD.replace("scene = \"a.toml\"\nusd", "scene = \"fast.toml\"\nusd"),
                "30 fps",
            ),
            (
                "shutter",
                GOOD.replace("[-0.25, 0.25]", "[0.25, -0.25]"),
                "[output] shutter",
            ),
            (
                "samples",
                GOOD.replace("shutter = [-0.25, 0.25]", "motion_samples = 3"),
                "without a shutter",
            ),
            (
                "none",
                "[shot]\nframes = [1, 2]\n".to_string(),
                "no [[characters]]",
            ),
        ];
        for (name, text, expected) in cases {
            let e = load(name, &text).unwrap_err();
            assert!(e.contains("shot.toml"), "{name}: {e}");
            assert!(e.contains(expected), "{name}: {e}");
        }
    }

    #[test]
    fn usd_identifiers() {
        for good in ["a", "_x", "alice_hair2"] {
            assert!(is_identifier(good), "{good}");
        }
        for bad in ["", "2a", "a-b", "a b", "é"] {
            assert!(!is_identifier(bad), "{bad}");
        }
    }
}
