//! The `[children]` scene section: render children (seed 001, "Rendering") as
//! `hairsys render-children export` makes them. Every key is optional (defaults of
//! `hair_render::ChildSettings`); the command's flags override the section.
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
    pub clump: Option<ClumpSection>,
    /// Curl radius (m) and frequency (turns per meter).
    #[serde(default)]
    pub curl: Option<CurlSection>,
    /// Roughness amplitudes and sizes, m.
    #[serde(default)]
    pub roughness: Option<RoughnessSection>,
    /// Random shortening per child, fraction of the length.
    #[serde(default)]
    pub length_variation: Option<f32>,
    /// Width (diameter) at root and tip, m, and the taper exponent.
    #[serde(default)]
    pub width: Option<WidthSection>,
    /// Fraction of the length over which curl and roughness grow from 0 at the root.
    #[serde(default)]
    pub root_ramp: Option<f32>,
    /// Display level of detail (`--display`).
    #[serde(default)]
    pub display: Option<DisplaySection>,
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

/// `clump = { factor, shape }`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClumpSection {
    /// In [−1, 1]: 1 draws the tips onto the parent.
    #[serde(default)]
    pub factor: f32,
    /// Exponent of the clump profile along the length (1 linear).
    #[serde(default = "one")]
    pub shape: f32,
}

/// `curl = { radius, frequency }`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurlSection {
    /// Helix radius, m (0 = off).
    #[serde(default)]
    pub radius: f32,
    /// Turns per meter of hair.
    #[serde(default)]
    pub frequency: f32,
}

/// `roughness = { uniform, uniform_size, endpoint, endpoint_shape, smooth, smooth_size }`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RoughnessSection {
    /// Amplitude of the short-wavelength noise, m.
    #[serde(default)]
    pub uniform: f32,
    /// Its wavelength, m.
    #[serde(default = "uniform_size")]
    pub uniform_size: f32,
    /// Tip amplitude of the splayed ends, m.
    #[serde(default)]
    pub endpoint: f32,
    /// Exponent of the endpoint roughness along the length.
    #[serde(default = "one")]
    pub endpoint_shape: f32,
    /// Amplitude of the long-wavelength noise, m.
    #[serde(default)]
    pub smooth: f32,
    /// Its wavelength, m.
    #[serde(default = "smooth_size")]
    pub smooth_size: f32,
}

/// `width = { root, tip, shape }`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WidthSection {
    /// Diameter at the root, m.
    #[serde(default = "root_width")]
    pub root: f32,
    /// Diameter at the tip, m.
    #[serde(default = "tip_width")]
    pub tip: f32,
    /// Taper exponent (1 linear).
    #[serde(default = "one")]
    pub shape: f32,
}

/// `display = { fraction, subdivisions }`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DisplaySection {
    /// Fraction of each parent's children shown, (0, 1].
    #[serde(default = "display_fraction")]
    pub fraction: f32,
    /// Catmull–Rom pieces per parent segment at display level (1 = the parent's points).
    #[serde(default = "one_u32")]
    pub subdivisions: u32,
}

fn one() -> f32 {
    1.0
}
fn one_u32() -> u32 {
    1
}
fn uniform_size() -> f32 {
    Roughness::default().uniform_size
}
fn smooth_size() -> f32 {
    Roughness::default().smooth_size
}
fn root_width() -> f32 {
    Taper::default().root
}
fn tip_width() -> f32 {
    Taper::default().tip
}
fn display_fraction() -> f32 {
    DisplayLod::default().fraction
}

/// Default neighbours of interpolated children.
pub const DEFAULT_NEIGHBOURS: u32 = 4;

impl ChildrenSection {
    /// The child settings and display level of detail of this section, checked; errors name the
    /// `[children]` key and the fix.
    pub fn settings(&self) -> Result<(ChildSettings, DisplayLod), String> {
        let base = ChildSettings::default();
        let count =
            match (self.per_parent, self.count) {
                (Some(_), Some(_)) => return Err(
                    "[children] gives both per_parent and count: keep one (children per parent, \
                     or in all)"
                        .into(),
                ),
                (Some(n), None) => ChildCount::PerParent(n),
                (None, Some(n)) => ChildCount::Total(n),
                (None, None) => base.count,
            };
        let mode =
            match (self.mode, self.neighbours) {
                (ModeValue::Simple, Some(_)) => return Err(
                    "[children] neighbours applies to mode = \"interpolated\" only: set the mode \
                     or remove neighbours"
                        .into(),
                ),
                (ModeValue::Simple, None) => ChildMode::Simple,
                (ModeValue::Interpolated, n) => ChildMode::Interpolated {
                    neighbours: n.unwrap_or(DEFAULT_NEIGHBOURS),
                },
            };
        let defaults = Shape::default();
        let shape = Shape {
            clump: self.clump.map_or(defaults.clump, |c| Clump {
                factor: c.factor,
                shape: c.shape,
            }),
            curl: self.curl.map_or(defaults.curl, |c| Curl {
                radius: c.radius,
                frequency: c.frequency,
            }),
            roughness: self.roughness.map_or(defaults.roughness, |r| Roughness {
                uniform: r.uniform,
                uniform_size: r.uniform_size,
                endpoint: r.endpoint,
                endpoint_shape: r.endpoint_shape,
                smooth: r.smooth,
                smooth_size: r.smooth_size,
            }),
            length_variation: self.length_variation.unwrap_or(defaults.length_variation),
            taper: self.width.map_or(defaults.taper, |w| Taper {
                root: w.root,
                tip: w.tip,
                shape: w.shape,
            }),
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
        let display = self.display.map_or(DisplayLod::default(), |d| DisplayLod {
            fraction: d.fraction,
            subdivisions: d.subdivisions,
        });
        settings
            .validate()
            .and_then(|()| Lod::Display(display).validate())
            .map_err(|e| format!("[children] {}", scene_key(e)))?;
        Ok((settings, display))
    }
}

/// A render error with the library's parameter name replaced by the `[children]` key.
fn scene_key(e: RenderError) -> String {
    match e {
        RenderError::Parameter { name, value, fix } => {
            let key = match name {
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
        section.settings()
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
        let stiffer = base.replacen("bend_stiffness = 0.5 ", "bend_stiffness = 0.7 ", 1);
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
