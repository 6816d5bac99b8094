//! The `[children]` scene section: render children (seed 001, "Rendering") as
//! `hairsys render-children export` makes them. Every key is optional (defaults of
//! `hair_render::ChildSettings`); the command's flags override the section.
//!
//! The inline tables are hair-render's own types read through its `serde` feature: `clump` is
//! `hair_render::Clump`, `curl` `Curl`, `roughness` `Roughness`, `width` `Taper` and `display`
//! `DisplayLod` (each key optional, defaults of the type). The section itself is not
//! `ChildSettings`, on purpose: the file says `per_parent` or `count` where the library has the
//! [`ChildCount`] enum, `mode` and `neighbours` where it has [`ChildMode`], and flattens
//! `ChildSettings::shape`'s fields into the section; and every key may be left out.
//!
//! ```toml
//! [children]
//! mode = "interpolated"     # "simple" (around one parent) or "interpolated" (between parents)
//! per_parent = 20           # children per parent strand, or `count` = children in all
//! neighbours = 4            # interpolated: parents blended per child (1–8)
//! spread = 0.005            # m, radius of the disc around a parent's root children are rooted in
//! seed = 0
//! subdivisions = 4          # Catmull–Rom pieces per parent segment at render level (1–64)
//! clump = { factor = 0.5, shape = 1.0 }      # tips drawn to the parent (−1…1), profile exponent
//! curl = { radius = 0.002, frequency = 40 }  # m, turns per meter
//! roughness = { uniform = 1e-4, uniform_size = 0.002, endpoint = 1e-3, endpoint_shape = 1.0, smooth = 5e-4, smooth_size = 0.05 }  # m
//! length_variation = 0.2    # random shortening, fraction (0–0.99)
//! width = { root = 8e-5, tip = 2e-5, shape = 1.0 }  # m, diameters; taper exponent
//! root_ramp = 0.05          # fraction of the length over which curl and roughness grow in
//! display = { fraction = 0.1, subdivisions = 1 }  # `--display`: fraction of children, pieces per segment
//! ```

use hair_render::{
    ChildCount, ChildMode, ChildSettings, Clump, Curl, DisplayLod, Lod, RenderError, Roughness,
    Shape, Taper,
};
use serde::{Deserialize, Serialize};

/// `[children]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct ChildrenSection {
    /// `"simple"` or `"interpolated"`.
    #[serde(default)]
    pub mode: ModeValue,
    /// Children per parent strand (or give `count`).
    #[serde(default)]
    pub per_parent: Option<u32>,
    /// Children in all, spread evenly over the parents (or give `per_parent`).
    #[serde(default)]
    pub count: Option<u64>,
    /// Interpolated mode: parents blended per child, 1–8.
    #[serde(default)]
    pub neighbours: Option<u32>,
    /// Radius of the disc children are rooted in around their parent's root, m.
    #[serde(default)]
    pub spread: Option<f32>,
    /// Seed of the children's random values.
    #[serde(default)]
    pub seed: Option<u64>,
    /// Catmull–Rom pieces per parent segment at render level.
    #[serde(default)]
    pub subdivisions: Option<u32>,
    /// Clump factor and shape.
    #[serde(default)]
    pub clump: Option<Clump>,
    /// Curl radius (m) and frequency (turns per meter).
    #[serde(default)]
    pub curl: Option<Curl>,
    /// Roughness amplitudes and sizes, m.
    #[serde(default)]
    pub roughness: Option<Roughness>,
    /// Random shortening per child, fraction of the length.
    #[serde(default)]
    pub length_variation: Option<f32>,
    /// Width (diameter) at root and tip, m, and the taper exponent.
    #[serde(default)]
    pub width: Option<Taper>,
    /// Fraction of the length over which curl and roughness grow from 0 at the root.
    #[serde(default)]
    pub root_ramp: Option<f32>,
    /// Display level of detail (`--display`).
    #[serde(default)]
    pub display: Option<DisplayLod>,
}

/// `mode = "simple" | "interpolated"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum ModeValue {
    /// Grouped around one parent.
    #[default]
    Simple,
    /// Between several parents.
    Interpolated,
}

/// Default neighbours of interpolated children.
pub const DEFAULT_NEIGHBOURS: u32 = 4;

impl ChildrenSection {
    /// The child settings and display level of detail of this section, checked; errors name the
    /// `[children]` key and the fix.
    pub fn settings(&self) -> Result<(ChildSettings, DisplayLod), ChildrenError> {
        let base = ChildSettings::default();
        let count = match (self.per_parent, self.count) {
            (Some(_), Some(_)) => return Err(ChildrenError::CountTwice),
            (Some(n), None) => ChildCount::PerParent(n),
            (None, Some(n)) => ChildCount::Total(n),
            (None, None) => base.count,
        };
        let mode = match (self.mode, self.neighbours) {
            (ModeValue::Simple, Some(_)) => return Err(ChildrenError::NeighboursWhenSimple),
            (ModeValue::Simple, None) => ChildMode::Simple,
            (ModeValue::Interpolated, n) => ChildMode::Interpolated {
                neighbours: n.unwrap_or(DEFAULT_NEIGHBOURS),
            },
        };
        let defaults = Shape::default();
        let shape = Shape {
            clump: self.clump.unwrap_or(defaults.clump),
            curl: self.curl.unwrap_or(defaults.curl),
            roughness: self.roughness.unwrap_or(defaults.roughness),
            length_variation: self.length_variation.unwrap_or(defaults.length_variation),
            taper: self.width.unwrap_or(defaults.taper),
            root_ramp: self.root_ramp.unwrap_or(defaults.root_ramp),
        };
        let settings = ChildSettings {
            count,
            spread: self.spread.unwrap_or(base.spread),
            seed: self.seed.unwrap_or(base.seed),
            subdivisions: self.subdivisions.unwrap_or(base.subdivisions),
            shape,
            mode,
        };
        let display = self.display.unwrap_or_default();
        settings
            .validate()
            .and_then(|()| Lod::Display(display).validate())
            .map_err(ChildrenError::Invalid)?;
        Ok((settings, display))
    }
}

/// Why a `[children]` section is refused.
#[derive(Debug, thiserror::Error)]
pub enum ChildrenError {
    /// Both `per_parent` and `count` are given.
    #[error(
        "[children] gives both per_parent and count: keep one (children per parent, or in all)"
    )]
    CountTwice,
    /// `neighbours` is given for simple children.
    #[error(
        "[children] neighbours applies to mode = \"interpolated\" only: set the mode or remove \
         neighbours"
    )]
    NeighboursWhenSimple,
    /// A setting is out of range (the renderer's check, in the section's keys).
    #[error("[children] {}", scene_key(.0))]
    Invalid(#[source] RenderError),
}

/// A render-children parameter error in the section's keys: `key = value: fix`.
fn scene_key(e: &RenderError) -> String {
    match e {
        RenderError::Parameter { name, value, fix } => {
            let key = match *name {
                "children_per_parent" => "per_parent".to_string(),
                n => n.trim_start_matches("shape.").replace("taper.", "width."),
            };
            format!("{key} = {value}: {fix}")
        }
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<(ChildSettings, DisplayLod), String> {
        let section: ChildrenSection = toml::from_str(text).map_err(|e| e.to_string())?;
        section.settings().map_err(|e| e.to_string())
    }

    #[test]
    fn every_key_reaches_the_settings() {
        let (s, d) = parse(
            r#"
            mode = "interpolated"
            count = 5000
            neighbours = 3
            spread = 0.01
            seed = 9
            subdivisions = 2
            clump = { factor = 0.5, shape = 2.0 }
            curl = { radius = 0.002, frequency = 40 }
            roughness = { uniform = 1e-4, endpoint = 1e-3, smooth = 5e-4, smooth_size = 0.1 }
            length_variation = 0.2
            width = { root = 1e-4, tip = 1e-5 }
            root_ramp = 0.1
            display = { fraction = 0.5, subdivisions = 2 }
            "#,
        )
        .unwrap();
        assert_eq!(s.count, ChildCount::Total(5000));
        assert_eq!(s.mode, ChildMode::Interpolated { neighbours: 3 });
        assert_eq!((s.spread, s.seed, s.subdivisions), (0.01, 9, 2));
        assert_eq!((s.shape.clump.factor, s.shape.clump.shape), (0.5, 2.0));
        assert_eq!((s.shape.curl.radius, s.shape.curl.frequency), (0.002, 40.0));
        assert_eq!(s.shape.roughness.smooth_size, 0.1);
        assert_eq!(s.shape.roughness.uniform_size, 0.002);
        assert_eq!((s.shape.taper.root, s.shape.taper.tip), (1e-4, 1e-5));
        assert_eq!((s.shape.length_variation, s.shape.root_ramp), (0.2, 0.1));
        assert_eq!((d.fraction, d.subdivisions), (0.5, 2));
        let (s, d) = parse("").unwrap();
        assert_eq!(s, ChildSettings::default());
        assert_eq!(d, DisplayLod::default());
    }

    #[test]
    fn children_settings_do_not_change_the_scene_hash_that_guards_resume() {
        let hash = |text: &str| {
            crate::scene::SceneFile::parse(text, "test.toml", std::path::PathBuf::from("."))
                .unwrap()
                .hash()
                .unwrap()
        };
        let base = crate::scene::DEFAULT_SCENE;
        let with_children = format!("{base}\n[children]\ncount = 5000\nseed = 3\n");
        assert_eq!(hash(base), hash(&with_children));
        let stiffer = base.replacen("bend_stiffness = 5.0 ", "bend_stiffness = 5.5 ", 1);
        assert_ne!(stiffer, base);
        assert_ne!(
            hash(base),
            hash(&stiffer),
            "a physics change must change the hash"
        );
    }

    #[test]
    fn commented_children_section_of_the_default_scene_parses() {
        let block: String = crate::scene::DEFAULT_SCENE
            .lines()
            .skip_while(|l| !l.starts_with("# [children]"))
            .skip(1)
            .take_while(|l| l.starts_with("# ") && !l.starts_with("# ["))
            .map(|l| format!("{}\n", &l[2..]))
            .collect();
        assert!(block.contains("display"), "{block}");
        let (s, d) = parse(&block).unwrap();
        assert_eq!(
            s,
            ChildSettings {
                mode: ChildMode::Interpolated { neighbours: 4 },
                ..ChildSettings::default()
            }
        );
        assert_eq!(d, DisplayLod::default());
    }

    #[test]
    fn bad_children_keys_are_named_with_their_fix() {
        let e = parse("curls = 1").unwrap_err();
        assert!(e.contains("unknown field `curls`"), "{e}");
        let e = parse("clump = { factor = 2.0 }").unwrap_err();
        assert!(
            e.contains("[children] clump.factor = 2") && e.contains("[-1, 1]"),
            "{e}"
        );
        let e = parse("width = { root = -1.0 }").unwrap_err();
        assert!(e.contains("width.root"), "{e}");
        let e = parse("per_parent = 0").unwrap_err();
        assert!(
            e.contains("per_parent = 0") && e.contains("at least 1"),
            "{e}"
        );
        let e = parse("per_parent = 3\ncount = 9").unwrap_err();
        assert!(e.contains("keep one"), "{e}");
        let e = parse("neighbours = 3").unwrap_err();
        assert!(e.contains("interpolated"), "{e}");
        let e = parse("mode = \"interpolated\"\nneighbours = 20").unwrap_err();
        assert!(e.contains("neighbours = 20"), "{e}");
        let e = parse("display = { fraction = 0.0 }").unwrap_err();
        assert!(e.contains("display.fraction"), "{e}");
        let e = parse("mode = \"nearest\"").unwrap_err();
        assert!(e.contains("simple") && e.contains("interpolated"), "{e}");
    }
}
