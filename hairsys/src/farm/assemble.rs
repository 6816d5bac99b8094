//! The Assemble task (`hairsys farm assemble`): per character a layer that stitches its chunk
//! files with USD value clips, and the shot stage referencing every character.
//!
//! A character layer (`NAME/NAME.usda`, text) sub-layers its first chunk, which defines the
//! prims and everything not animated (topology, widths, UVs, ids, a still scalp), and puts
//! `clips` on the curves prim (`/hair` or `/children`) and on `/scalp`:
//!
//! ```usda
//! over "hair" (
//!     clips = {
//!         dictionary default = {
//!             double2[] active = [(1, 0), (10.75, 1), (20.75, 2)]
//!             asset[] assetPaths = [@chunks/alice.0001-0010.usdc@, …]
//!             string primPath = "/hair"
//!             double2[] times = [(1, 1), (48, 48)]
//!         }
//!     }
//! )
//! ```
//!
//! Clip `k` is active from the first time code its chunk writes (its first frame, or the first
//! shutter sample before it), so each time code reads the chunk that wrote it; `times` maps
//! stage time to itself over the whole shot. The shot stage `shot.usda` holds an `Xform` per
//! character, `/NAME`, whose children reference the character layer's prims
//! (`/NAME/hair` → `@NAME/NAME.usda@</hair>`, `/NAME/scalp`), with the stage's frame rate,
//! time range, Z up and meters.

use std::fmt::Write as _;
use std::path::PathBuf;

use super::task::chunk_files;
use super::{write_atomic, FarmError, OutputLayout};
use crate::output::shot_export::time_codes;
use crate::output::Shot;
use crate::shot::ShotFile;

/// What [`assemble`] wrote.
#[derive(Debug, Clone, serde::Serialize)]
pub struct AssembleSummary {
    /// The shot stage.
    pub stage: PathBuf,
    /// Each character layer, with the chunks it stitches.
    pub characters: Vec<CharacterLayer>,
    /// First and last time code of the stage.
    pub time_codes: (f64, f64),
}

/// One character layer.
#[derive(Debug, Clone, serde::Serialize)]
pub struct CharacterLayer {
    /// The character.
    pub name: String,
    /// The layer.
    pub path: PathBuf,
    /// The chunks it stitches, in order: (first frame, last frame).
    pub chunks: Vec<(u32, u32)>,
    /// The prims it animates (the curves prim, and `scalp` when there is a scalp mesh).
    pub prims: Vec<String>,
}

/// Writes every character layer and the shot stage under `layout` from the chunk files the
/// Export tasks wrote.
pub fn assemble(shot: &ShotFile, layout: &OutputLayout) -> Result<AssembleSummary, FarmError> {
    let (first, last) = shot.frames();
    let offset = shot.shot.output.time_offset;
    let mut characters = Vec::new();
    let mut range = (f64::INFINITY, f64::NEG_INFINITY);
    for c in shot.usd_characters() {
        let name = c.name.as_str();
        let dir = layout.chunk_dir(name);
        let files = chunk_files(&dir, name)?;
        let chunks: Vec<(u32, u32)> = files.iter().map(|f| f.frames).collect();
        if let Some(problem) = tiling_problem(&chunks, (first, last)) {
            return Err(FarmError::Chunks {
                dir,
                character: name.to_string(),
                problem,
            });
        }
        let cache = layout.cache(name);
        if !cache.exists() {
            return Err(FarmError::MissingCache {
                path: cache,
                character: name.to_string(),
            });
        }
        let opened = Shot::open(&cache, None).map_err(|e| FarmError::Export {
            character: name.to_string(),
            source: Box::new(e.into()),
        })?;
        let cached = opened.cached_frames();
        let (lo, hi) = match (cached.first(), cached.last()) {
            (Some(&a), Some(&b)) => (f64::from(a), f64::from(b)),
            _ => {
                return Err(FarmError::MissingCache {
                    path: cache,
                    character: name.to_string(),
                })
            }
        };
        let frames_of = |(a, b): (u32, u32)| -> Vec<u32> {
            cached
                .iter()
                .copied()
                .filter(|f| (a..=b).contains(f))
                .collect()
        };
        let shutter = shot.shutter.as_ref();
        let whole = time_codes(&frames_of((first, last)), shutter, (lo, hi)).0;
        let (Some(&t0), Some(&t1)) = (whole.first(), whole.last()) else {
            return Err(FarmError::MissingCache {
                path: cache,
                character: name.to_string(),
            });
        };
        let starts: Vec<f64> = chunks
            .iter()
            .map(|&r| {
                time_codes(&frames_of(r), shutter, (lo, hi))
                    .0
                    .first()
                    .copied()
                    .unwrap_or(f64::from(r.0))
                    + offset
            })
            .collect();
        let curves = shot
            .usd_of(c)
            .prim()
            .expect("characters with USD have a curves prim");
        let mut prims = vec![curves.to_string()];
        if opened.rest_scalp().is_some() {
            prims.push("scalp".into());
        }
        let assets: Vec<String> = chunks
            .iter()
            .map(|&r| format!("chunks/{}", super::layout::chunk_file_name(name, r)))
            .collect();
        let (t0, t1) = (t0 + offset, t1 + offset);
        let text = character_layer(&prims, &assets, &starts, (t0, t1), f64::from(shot.fps()));
        let path = layout.character_layer(name);
        write_atomic(&path, text.as_bytes())?;
        range = (range.0.min(t0), range.1.max(t1));
        characters.push(CharacterLayer {
            name: name.to_string(),
            path,
            chunks,
            prims,
        });
    }
    let stage = layout.stage();
    write_atomic(
        &stage,
        shot_stage(&characters, range, f64::from(shot.fps())).as_bytes(),
    )?;
    Ok(AssembleSummary {
        stage,
        characters,
        time_codes: range,
    })
}

/// What keeps `chunks` (sorted by first frame) from covering `first`–`last` once each, if
/// anything.
fn tiling_problem(chunks: &[(u32, u32)], (first, last): (u32, u32)) -> Option<String> {
    let name = |(a, b): (u32, u32)| format!("{a:04}-{b:04}");
    let mut next = first;
    let mut previous: Option<(u32, u32)> = None;
    for &(a, b) in chunks {
        if a > next {
            return Some(format!("miss frames {next}-{}", a - 1));
        }
        if a < next {
            return Some(match previous {
                Some(p) => format!("overlap: {} and {}", name(p), name((a, b))),
                None => format!("start at frame {a}, before the shot's first frame {first}"),
            });
        }
        if b > last {
            return Some(format!(
                "reach frame {b} ({}), past the shot's last frame {last}",
                name((a, b))
            ));
        }
        next = b + 1;
        previous = Some((a, b));
    }
    (next <= last).then(|| {
        if chunks.is_empty() {
            format!("are missing (none for frames {first}-{last})")
        } else {
            format!("miss frames {next}-{last}")
        }
    })
}

/// The USD text of a layer's stage metadata lines (inside its parentheses).
fn stage_metadata(out: &mut String, (t0, t1): (f64, f64), fps: f64) {
    let _ = writeln!(out, "    endTimeCode = {t1}");
    let _ = writeln!(out, "    metersPerUnit = 1");
    let _ = writeln!(out, "    startTimeCode = {t0}");
    let _ = writeln!(out, "    timeCodesPerSecond = {fps}");
    let _ = writeln!(out, "    upAxis = \"Z\"");
}

/// A character layer's text (see the module docs).
fn character_layer(
    prims: &[String],
    assets: &[String],
    starts: &[f64],
    (t0, t1): (f64, f64),
    fps: f64,
) -> String {
    let mut out = String::from("#usda 1.0\n(\n");
    let _ = writeln!(out, "    defaultPrim = \"{}\"", prims[0]);
    stage_metadata(&mut out, (t0, t1), fps);
    let _ = writeln!(out, "    subLayers = [\n        @{}@\n    ]", assets[0]);
    out.push_str(")\n");
    let active: Vec<String> = starts
        .iter()
        .enumerate()
        .map(|(k, &t)| format!("({t}, {k})"))
        .collect();
    let paths: Vec<String> = assets.iter().map(|a| format!("@{a}@")).collect();
    for prim in prims {
        let _ = write!(
            out,
            "\nover \"{prim}\" (\n    clips = {{\n        dictionary default = {{\n            \
             double2[] active = [{}]\n            asset[] assetPaths = [{}]\n            \
             string primPath = \"/{prim}\"\n            double2[] times = [({t0}, {t0}), ({t1}, \
             {t1})]\n        }}\n    }}\n)\n{{\n}}\n",
            active.join(", "),
            paths.join(", "),
        );
    }
    out
}

/// The shot stage's text (see the module docs).
fn shot_stage(characters: &[CharacterLayer], range: (f64, f64), fps: f64) -> String {
    let mut out = String::from("#usda 1.0\n(\n");
    let range = if range.0.is_finite() {
        range
    } else {
        (0.0, 0.0)
    };
    stage_metadata(&mut out, range, fps);
    out.push_str(")\n");
    for c in characters {
        let _ = write!(out, "\ndef Xform \"{}\"\n{{\n", c.name);
        for prim in &c.prims {
            let _ = writeln!(
                out,
                "    def \"{prim}\" (\n        prepend references = @{name}/{name}.usda@</{prim}>\n    )\n    {{\n    }}",
                name = c.name
            );
        }
        out.push_str("}\n");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunks_must_cover_the_shot_once_each() {
        let shot = (1, 48);
        assert_eq!(tiling_problem(&[(1, 30), (31, 48)], shot), None);
        assert_eq!(tiling_problem(&[(1, 48)], shot), None);
        let problem = |c: &[(u32, u32)]| tiling_problem(c, shot).unwrap();
        assert!(problem(&[]).contains("missing"));
        assert!(problem(&[(1, 30)]).contains("miss frames 31-48"));
        assert!(problem(&[(1, 10), (21, 48)]).contains("miss frames 11-20"));
        assert!(
            problem(&[(1, 30), (11, 20), (31, 48)]).contains("overlap: 0001-0030 and 0011-0020")
        );
        assert!(problem(&[(1, 50)]).contains("past the shot's last frame 48"));
        assert!(problem(&[(2, 48)]).contains("miss frames 1-1"));
    }

    #[test]
    fn the_character_layer_switches_clips_at_each_chunks_first_time_code() {
        let text = character_layer(
            &["hair".into(), "scalp".into()],
            &[
                "chunks/a.0001-0010.usdc".into(),
                "chunks/a.0011-0020.usdc".into(),
            ],
            &[0.75, 10.75],
            (0.75, 20.25),
            24.0,
        );
        assert!(
            text.contains("double2[] active = [(0.75, 0), (10.75, 1)]"),
            "{text}"
        );
        assert!(
            text.contains("double2[] times = [(0.75, 0.75), (20.25, 20.25)]"),
            "{text}"
        );
        assert!(text.contains("string primPath = \"/scalp\""), "{text}");
        assert!(text.contains("@chunks/a.0001-0010.usdc@\n"), "{text}");
    }
}
