//! `[maps.NAME]`: painted maps over the scalp, read from a PNG texture over the
//! scalp's UVs or from the OBJ scalp's vertex colours, and sampled at each hair's root (see
//! [`crate::rig::maps`] for the sampling).
//!
//! ```toml
//! [maps.goal]                 # scales every surface-rooted hair's goal weights
//! texture = "goal.png"        # relative to the scene file
//! channel = "r"               # r (default), g, b or a
//!
//! [maps.sim_weight]           # paints the factor of [guides.sim_weight] per sim hair
//! vertex_colors = true        # the OBJ scalp's `v x y z r g b`
//! channel = "g"
//!
//! [maps.density]              # more roots per area where brighter; [hair] count stays the count
//! texture = "density.png"
//!
//! [maps.clump]                # × [children] clump per parent (curl: × curl_radius)
//! texture = "clump.png"
//!
//! [maps.fringe]               # any other name: a map selections use
//! texture = "fringe.png"      # [guides.hold_out] map = { name = "fringe", min = 0.5 }
//!
//! [maps.stiffness]            # a USD scalp's primvar (kind = "usd"), any interpolation:
//! primvar = "stiff"           # primvars:stiff, e.g. a vertex group exported by Blender
//! ```
//!
//! Names with a purpose: `goal` multiplies the goal weight of every point of each hair grown on
//! the scalp (`[hair]` and `[sim_hairs]`) by the map at its root; `sim_weight` multiplies each
//! sim hair's factor of the `[guides.sim_weight]` curve (needs that curve); `stiffness`
//! multiplies each scalp-rooted hair's bending stiffness by the map at its root (see
//! [`crate::scene::regions`]); `length` trims each `[hair]` and `[sim_hairs]` strand to the map's
//! fraction (0, 1] of its length, keeping its groomed shape from the root (the curve is cut at
//! that arc length and resampled to the same number of points, masses lumped again at the same
//! mass per length; the resampled chords cut a curved groom's corners, so the polyline comes out
//! up to ~1 % shorter than the fraction: [`hair_groom::trim`]). A sim hair keeps its fraction
//! when animated guides re-pose it: each frame's blend is trimmed the same way before the pose
//! is applied ([`hair_groom::GuideBlend::with_length_fractions`]), so goal targets, pins,
//! hold-out and sim weight follow the trimmed hair.
//!
//! `density` spreads the roots of `[hair]` and `[sim_hairs]` over the scalp: roots grow with
//! probability density ∝ area × the map, relative to its largest value, and the `count` stays
//! the count (a map twice as bright in one place puts twice as many roots per area there; a map
//! of 0 grows nothing; see [`hair_groom::sampling`] for the rejection sampler and why a map of
//! one value everywhere gives the same roots as no map, bit for bit). With `min_distance`
//! (Poisson disk) the map thins the candidates instead: the brightest places keep the spacing.
//! Guides are not moved by it, and render children follow their parents, so they are as dense
//! as the hair they grow around. A density of 0 everywhere, or a negative value, is an error.
//!
//! `clump` and `curl` scale each parent's render children: at a hair whose root the map paints
//! `m ∈ [0, 1]`, its children's clump factor is `m × [children] clump` and their curl radius
//! `m × [children] curl_radius` (so 1 is the setting, 0 none, and the displacement clumping or
//! curl adds to a child scales linearly with `m`). Interpolated children take their home
//! parent's factors. The factors are fixed when the scene is built, in the scene's strand order,
//! and apply wherever the scene's children are made (`render-children`, shot export,
//! [`crate::Session::children`]).
//!
//! Any other name must be used by a selection (`map = { name, min, max }` in
//! `[guides.sim_weight]`, `[[guides.pin]]`, `[guides.hold_out]` or `[[regions]]`), so a
//! misspelt purpose is an error, not a silent no-op.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use hair_core::{Anchor, MeshSample, StrandInput, StrandSet, TriMesh};
use serde::{Deserialize, Serialize};

use crate::rig::maps::{Channel, MapDensity, MapError, MapSource, ScalpMap, Texture};
use crate::scene::map_primvars::PrimvarError;

/// Map names with a purpose that hairsys applies, with that purpose in words.
pub const APPLIED: [(&str, &str); 7] = [
    ("goal", "scales goal weights"),
    ("sim_weight", "scales each sim hair's sim weight"),
    ("stiffness", "scales bending stiffness"),
    (
        "length",
        "trims [hair] and [sim_hairs] strands to a fraction of their length",
    ),
    ("density", "spreads the roots of [hair] and [sim_hairs]"),
    ("clump", "scales the render children's clump"),
    ("curl", "scales the render children's curl radius"),
];

/// `[maps.NAME]`: where one map's values come from. Give `texture`, `vertex_colors` or
/// `primvar`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MapSection {
    /// PNG image over the scalp's UVs, relative to the scene file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texture: Option<PathBuf>,
    /// The OBJ scalp's vertex colours (`v x y z r g b`).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub vertex_colors: bool,
    /// A primvar of the USD scalp's `Mesh` prim by name (`"density"` reads
    /// `primvars:density`): float values, or one `channel` of a color3f/float3 primvar, of any
    /// interpolation (see [`super::map_primvars`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub primvar: Option<String>,
    /// Colour channel: `"r"` (default), `"g"`, `"b"` or `"a"` (textures only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub channel: Option<String>,
}

/// Selects the hairs whose map value at the root lies in `[min, max]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MapSelection {
    /// The map's name (a `[maps.NAME]` section).
    pub name: String,
    /// Least value selected (default 0.5: the painted half of a 0–1 map).
    #[serde(default = "half")]
    pub min: f32,
    /// Largest value selected (default: no limit).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max: Option<f32>,
}

fn half() -> f32 {
    0.5
}

impl MapSelection {
    /// True when `value` is selected.
    pub fn contains(&self, value: f32) -> bool {
        value >= self.min && self.max.is_none_or(|m| value <= m)
    }
}

/// The scene's maps, read and checked against the scalp at rest.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ScalpMaps {
    maps: BTreeMap<String, ScalpMap>,
    /// Each map's source in words (file and channel), for reports.
    sources: BTreeMap<String, String>,
}

/// Each strand's factors of its render children's clump factor and curl radius, from the
/// `clump` and `curl` maps at its root (`None`: no such map, factor 1 everywhere).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ChildMapFactors {
    /// Factor of `[children] clump` per strand, in [0, 1].
    pub clump: Option<Vec<f32>>,
    /// Factor of `[children] curl_radius` per strand, in [0, 1].
    pub curl: Option<Vec<f32>>,
}

/// One map as `scene check` reports it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MapSummary {
    /// The map's name (`[maps.NAME]`).
    pub name: String,
    /// Where its values come from, in words (texture file and channel, or vertex colours).
    pub source: String,
    /// What hairsys does with it, in words.
    pub purpose: String,
    /// Scalp-rooted strands of the run it was sampled at.
    pub roots: usize,
    /// Least and largest value at those roots (`None` when there are none).
    pub range: Option<[f32; 2]>,
}

/// The purpose of a map named `name`, in words, if the name has one.
fn purpose(name: &str) -> Option<&'static str> {
    APPLIED.iter().find(|(n, _)| *n == name).map(|(_, p)| *p)
}

/// A map section's source in words.
fn describe(section: &MapSection, channel: Channel) -> String {
    let channel = match channel {
        Channel::R => "r",
        Channel::G => "g",
        Channel::B => "b",
        Channel::A => "a",
    };
    match (&section.texture, &section.primvar) {
        (Some(file), _) => format!("texture {} (channel {channel})", file.display()),
        (None, Some(name)) => format!("the USD scalp's primvars:{name}"),
        (None, None) => format!("the scalp's vertex colours (channel {channel})"),
    }
}

impl ScalpMaps {
    /// No maps.
    pub fn none() -> Self {
        Self::default()
    }

    /// Reads every `[maps.NAME]` section: textures relative to `base_dir`, vertex colours from
    /// `colors` (the OBJ scalp's, `None` for another scalp), primvars from `primvar` (the map's
    /// name, the primvar's name and the channel, if one is given, to per-triangle corner values
    /// of the scalp), each checked
    /// against `mesh`. `used` are the names selections use. Errors name the section, the file
    /// and the fix.
    pub fn load(
        sections: &BTreeMap<String, MapSection>,
        base_dir: &Path,
        mesh: &TriMesh,
        colors: impl FnOnce() -> Result<Option<Vec<[f32; 3]>>, ScalpColorsError>,
        primvar: impl Fn(&str, &str, Option<Channel>) -> Result<Vec<[f32; 3]>, PrimvarError>,
        used: &[&str],
    ) -> Result<Self, MapsError> {
        let mut colors = Some(colors);
        let mut read_colors: Option<Option<Vec<[f32; 3]>>> = None;
        let mut maps = BTreeMap::new();
        let mut sources = BTreeMap::new();
        for (name, s) in sections {
            let map_name = name.as_str();
            let map = || name.clone();
            if purpose(name).is_none() && !used.contains(&name.as_str()) {
                return Err(MapsError::Unused { map: map() });
            }
            let channel = match s.channel.as_deref() {
                None => Channel::R,
                Some(c) => Channel::parse(c).ok_or_else(|| MapsError::Channel {
                    map: map(),
                    channel: c.to_string(),
                })?,
            };
            if s.primvar.is_some() && (s.texture.is_some() || s.vertex_colors) {
                return Err(MapsError::PrimvarAndOther { map: map() });
            }
            let source = match (&s.texture, s.vertex_colors) {
                (Some(_), true) => return Err(MapsError::TextureAndVertexColors { map: map() }),
                (None, false) => {
                    let Some(name) = &s.primvar else {
                        return Err(MapsError::NoValues { map: map() });
                    };
                    if channel == Channel::A {
                        return Err(MapsError::PrimvarAlpha { map: map() });
                    }
                    let given = s.channel.is_some().then_some(channel);
                    MapSource::Corners(primvar(map_name, name, given).map_err(|source| {
                        MapsError::Primvar {
                            map: map(),
                            primvar: name.clone(),
                            source: Box::new(source),
                        }
                    })?)
                }
                (Some(file), false) => {
                    let path = base_dir.join(file);
                    let texture =
                        Texture::read_png(&path, channel).map_err(|source| MapsError::Texture {
                            map: map(),
                            path: path.clone(),
                            source: Box::new(source),
                        })?;
                    MapSource::Texture { path, texture }
                }
                (None, true) => {
                    if channel == Channel::A {
                        return Err(MapsError::VertexColorsAlpha { map: map() });
                    }
                    if read_colors.is_none() {
                        let read = colors.take().map_or(Ok(None), |f| f())?;
                        read_colors = Some(read);
                    }
                    let Some(Some(rgb)) = &read_colors else {
                        return Err(MapsError::NoVertexColors { map: map() });
                    };
                    let c = match channel {
                        Channel::G => 1,
                        Channel::B => 2,
                        _ => 0,
                    };
                    MapSource::Vertex(rgb.iter().map(|v| v[c]).collect())
                }
            };
            maps.insert(name.clone(), ScalpMap::new(name, source, mesh)?);
            sources.insert(name.clone(), describe(s, channel));
        }
        Ok(Self { maps, sources })
    }

    /// The `density` map as the density of roots on `mesh` (`None` without that map). Errors
    /// name the map: a negative value, or 0 everywhere.
    pub fn density<'a>(&'a self, mesh: &'a TriMesh) -> Result<Option<MapDensity<'a>>, MapError> {
        self.get("density")
            .map(|m| MapDensity::new(m, mesh))
            .transpose()
    }

    /// Each strand's factors of its render children's clump and curl from the `clump` and
    /// `curl` maps at its root on `mesh` (1 for a strand not rooted on the scalp; `None` for a
    /// map the scene does not have). Errors name the map and the strand: a value outside
    /// [0, 1].
    pub fn child_factors(
        &self,
        strands: &StrandSet,
        mesh: Option<&TriMesh>,
    ) -> Result<ChildMapFactors, MapsError> {
        let factors = |name: &'static str| -> Result<Option<Vec<f32>>, MapsError> {
            let (Some(map), Some(mesh)) = (self.get(name), mesh) else {
                return Ok(None);
            };
            let mut out = vec![1.0; strands.len()];
            for (s, f) in out.iter_mut().enumerate() {
                let Anchor::Surface(sample) = strands.anchors()[s] else {
                    continue;
                };
                let v = map.at(mesh, &sample, &format!("strand {s}"))?;
                if !(0.0..=1.0).contains(&v) {
                    return Err(MapsError::ChildFactor {
                        map: name,
                        value: v,
                        strand: s,
                    });
                }
                *f = v;
            }
            Ok(Some(out))
        };
        Ok(ChildMapFactors {
            clump: factors("clump")?,
            curl: factors("curl")?,
        })
    }

    /// What each map is, where it comes from, what it does, and its values at the roots of
    /// `strands` on `mesh` (the scalp-rooted ones), for `scene check`.
    pub fn summaries(
        &self,
        strands: &StrandSet,
        mesh: Option<&TriMesh>,
    ) -> Result<Vec<MapSummary>, MapError> {
        let mut out = Vec::with_capacity(self.maps.len());
        for (name, map) in &self.maps {
            let mut range: Option<[f32; 2]> = None;
            let mut roots = 0;
            if let Some(mesh) = mesh {
                for (s, anchor) in strands.anchors().iter().enumerate() {
                    let Anchor::Surface(sample) = anchor else {
                        continue;
                    };
                    let v = map.at(mesh, sample, &format!("strand {s}"))?;
                    roots += 1;
                    range = Some(range.map_or([v, v], |[lo, hi]| [lo.min(v), hi.max(v)]));
                }
            }
            out.push(MapSummary {
                name: name.clone(),
                source: self.sources.get(name).cloned().unwrap_or_default(),
                purpose: purpose(name)
                    .unwrap_or("selects hair (a `map = { name, min, max }` selection)")
                    .to_string(),
                roots,
                range,
            });
        }
        Ok(out)
    }

    /// The map named `name`.
    pub fn get(&self, name: &str) -> Option<&ScalpMap> {
        self.maps.get(name)
    }

    /// The map a selection names, or an error naming `what` (the selecting section).
    pub fn selected(&self, s: &MapSelection, what: &str) -> Result<&ScalpMap, MapsError> {
        if !(s.min.is_finite() && s.max.is_none_or(|m| m.is_finite() && m >= s.min)) {
            return Err(MapsError::SelectionRange {
                selection: what.to_string(),
                min: s.min,
                max: s.max,
            });
        }
        self.get(&s.name).ok_or_else(|| MapsError::UnknownMap {
            selection: what.to_string(),
            map: s.name.clone(),
            known: self.maps.keys().cloned().collect(),
        })
    }

    /// The `length` map's fraction at each root of `roots` on `mesh` (`None` without that
    /// map). `what` names the hairs in errors: a fraction outside (0, 1].
    pub fn length_fractions<'a>(
        &self,
        mesh: &TriMesh,
        roots: impl IntoIterator<Item = &'a MeshSample>,
        what: &str,
    ) -> Result<Option<Vec<f32>>, MapsError> {
        let Some(map) = self.get("length") else {
            return Ok(None);
        };
        roots
            .into_iter()
            .enumerate()
            .map(|(i, sample)| length_fraction(map, mesh, sample, what, i))
            .collect::<Result<Vec<_>, _>>()
            .map(Some)
    }

    /// Trims every surface-rooted strand in `inputs` to the `length` map's fraction (0, 1] of
    /// its length at its root (nothing without that map): the rest curve is cut at that arc
    /// length from the root and resampled to the same number of points (uniform in arc length),
    /// and the masses are lumped again at the strand's mass per length. `what` names the hairs
    /// in errors.
    pub fn trim_length(
        &self,
        inputs: &mut [StrandInput],
        mesh: &TriMesh,
        what: &str,
    ) -> Result<(), MapsError> {
        let Some(map) = self.get("length") else {
            return Ok(());
        };
        for (i, input) in inputs.iter_mut().enumerate() {
            let Anchor::Surface(sample) = input.anchor else {
                continue;
            };
            trim_input(input, length_fraction(map, mesh, &sample, what, i)?);
        }
        Ok(())
    }

    /// Multiplies the goal weights of every surface-rooted strand in `inputs` by the `goal`
    /// map at its root (nothing without that map). `what` names the hairs in errors.
    pub fn scale_goal(
        &self,
        inputs: &mut [StrandInput],
        mesh: &TriMesh,
        what: &str,
    ) -> Result<(), MapsError> {
        let Some(map) = self.get("goal") else {
            return Ok(());
        };
        for (i, input) in inputs.iter_mut().enumerate() {
            let Anchor::Surface(sample) = input.anchor else {
                continue;
            };
            let g = map.at(mesh, &sample, &format!("{what} {i}"))?;
            if !(0.0..=1.0).contains(&g) {
                return Err(MapsError::GoalScale {
                    value: g,
                    hairs: what.to_string(),
                    index: i,
                });
            }
            input.goal_weight.iter_mut().for_each(|w| *w *= g);
        }
        Ok(())
    }
}

/// The length map `map`'s fraction at the root `sample` of hair `index` of `hairs` (named in
/// the error), checked to lie in (0, 1].
fn length_fraction(
    map: &ScalpMap,
    mesh: &TriMesh,
    sample: &MeshSample,
    hairs: &str,
    index: usize,
) -> Result<f32, MapsError> {
    let f = map.at(mesh, sample, &format!("{hairs} {index}"))?;
    if !(f > 0.0 && f <= 1.0) {
        return Err(MapsError::LengthFraction {
            value: f,
            hairs: hairs.to_string(),
            index,
        });
    }
    Ok(f)
}

/// Why the scene's `[maps.NAME]` cannot be read, checked or applied. Every variant names the
/// map's section and the fix.
#[derive(Debug, thiserror::Error)]
pub enum MapsError {
    /// A map whose name has no purpose and that no selection uses.
    #[error(
        "[maps.{map}] is used by nothing: name it after a purpose ({}), or select hair with it \
         (`map = {{ name = \"{map}\" }}` in [guides.sim_weight], [[guides.pin]], \
         [guides.hold_out] or [[regions]])",
        applied_names()
    )]
    Unused {
        /// The map's name.
        map: String,
    },
    /// A channel other than r, g, b and a.
    #[error("[maps.{map}] channel = \"{channel}\": use \"r\", \"g\", \"b\" or \"a\"")]
    Channel {
        /// The map's name.
        map: String,
        /// The channel given.
        channel: String,
    },
    /// `primvar` beside `texture` or `vertex_colors`.
    #[error("[maps.{map}]: give one of `texture`, `vertex_colors = true` and `primvar`")]
    PrimvarAndOther {
        /// The map's name.
        map: String,
    },
    /// Both `texture` and `vertex_colors`.
    #[error("[maps.{map}]: give `texture` or `vertex_colors = true`, not both")]
    TextureAndVertexColors {
        /// The map's name.
        map: String,
    },
    /// No source of values.
    #[error(
        "[maps.{map}] has no values: give `texture = \"map.png\"` (over the scalp's UVs), \
         `vertex_colors = true` (an OBJ scalp's `v x y z r g b`) or `primvar = \"NAME\"` (a \
         USD scalp's)"
    )]
    NoValues {
        /// The map's name.
        map: String,
    },
    /// The alpha channel of a primvar.
    #[error(
        "[maps.{map}] channel = \"a\": a primvar map reads a float or one channel of a \
         color3f/float3 primvar; use r, g or b"
    )]
    PrimvarAlpha {
        /// The map's name.
        map: String,
    },
    /// The primvar cannot be used.
    #[error("[maps.{map}] primvar = \"{primvar}\": {source}")]
    Primvar {
        /// The map's name.
        map: String,
        /// The primvar's name.
        primvar: String,
        /// Why.
        source: Box<PrimvarError>,
    },
    /// The texture cannot be read.
    #[error("[maps.{map}] texture {}: {source}", path.display())]
    Texture {
        /// The map's name.
        map: String,
        /// The texture file.
        path: PathBuf,
        /// Why.
        source: Box<MapError>,
    },
    /// The alpha channel of vertex colours.
    #[error("[maps.{map}] channel = \"a\": vertex colours have no alpha; use r, g or b")]
    VertexColorsAlpha {
        /// The map's name.
        map: String,
    },
    /// `vertex_colors = true` on a scalp without vertex colours.
    #[error(
        "[maps.{map}] vertex_colors: the scalp has no vertex colours; vertex colours come from \
         an OBJ scalp with `v x y z r g b` on every vertex (a USD scalp's values: \
         `primvar = \"NAME\"`): use a texture"
    )]
    NoVertexColors {
        /// The map's name.
        map: String,
    },
    /// The OBJ scalp's vertex colours cannot be read.
    #[error("{0}")]
    Colors(Box<ScalpColorsError>),
    /// A map cannot be laid over the scalp, or sampled at a root.
    #[error("{0}")]
    Map(#[from] MapError),
    /// A `clump` or `curl` map outside [0, 1] at a strand's root.
    #[error(
        "[maps.{map}] is {value} at strand {strand}: a {map} factor is in [0, 1] (1 = the \
         [children] setting, 0 = no {map}); paint values in [0, 1]"
    )]
    ChildFactor {
        /// `"clump"` or `"curl"`.
        map: &'static str,
        /// The value at the root.
        value: f32,
        /// The strand.
        strand: usize,
    },
    /// A selection's `min` and `max` are not finite with min ≤ max.
    #[error("{selection} map: min = {min} and max = {max:?} must be finite with min ≤ max")]
    SelectionRange {
        /// The selecting section.
        selection: String,
        /// `min` given.
        min: f32,
        /// `max` given.
        max: Option<f32>,
    },
    /// A selection names a map the scene does not have.
    #[error(
        "{selection} map names \"{map}\", but the scene's maps are {known:?}: add [maps.{map}] \
         or fix the name"
    )]
    UnknownMap {
        /// The selecting section.
        selection: String,
        /// The name it gives.
        map: String,
        /// The scene's maps.
        known: Vec<String>,
    },
    /// The `length` map outside (0, 1] at a hair's root.
    #[error(
        "[maps.length] is {value} at {hairs} {index}: a length fraction is in (0, 1] (1 = the \
         full length, 0.5 = half); paint values above 0 where hair grows, at most 1 (white)"
    )]
    LengthFraction {
        /// The value at the root.
        value: f32,
        /// Which hairs (`sim hair`, `[hair] strand`).
        hairs: String,
        /// The hair's index among them.
        index: usize,
    },
    /// The `goal` map outside [0, 1] at a hair's root.
    #[error(
        "[maps.goal] is {value} at {hairs} {index}: a goal weight scale is in [0, 1]; paint \
         values in [0, 1]"
    )]
    GoalScale {
        /// The value at the root.
        value: f32,
        /// Which hairs (`sim hair`, `[hair] strand`).
        hairs: String,
        /// The hair's index among them.
        index: usize,
    },
    /// The `sim_weight` map outside [0, 1] at a sim hair's root.
    #[error(
        "[maps.sim_weight] is {value} at sim hair {hair}: a sim weight factor is in [0, 1]; \
         paint values in [0, 1]"
    )]
    SimWeightFactor {
        /// The value at the root.
        value: f32,
        /// The sim hair.
        hair: usize,
    },
    /// The `stiffness` map negative or not finite at a strand's root.
    #[error(
        "[maps.stiffness] is {value} at strand {strand}: a stiffness factor is ≥ 0 (0 = no \
         bending, 1 = [physics] bend_stiffness); paint values ≥ 0"
    )]
    StiffnessFactor {
        /// The value at the root.
        value: f32,
        /// The strand.
        strand: usize,
    },
    /// `[maps]` without a scalp mesh.
    #[error(
        "[maps] paint values over the scalp, but [scalp.mesh] kind = \"none\"; choose a scalp \
         mesh or remove [maps]"
    )]
    NoScalp,
    /// `[maps.stiffness]` on hair without a scalp mesh.
    #[error("[maps.stiffness] needs a scalp mesh")]
    StiffnessWithoutScalp,
    /// `[maps.density]` without hair grown on the scalp.
    #[error(
        "[maps.density] spreads the roots of [hair] and [sim_hairs], but the scene has neither: \
         grow hair with [hair] or [guides] + [sim_hairs], or remove the map"
    )]
    DensityWithoutHair,
    /// `[maps.sim_weight]` without guides.
    #[error(
        "[maps.sim_weight] paints the sim weight of hair grown from guides, but the scene has \
         no [guides]: add [guides] and [sim_hairs] or remove the map"
    )]
    SimWeightWithoutGuides,
    /// `[maps.sim_weight]` without a `[guides.sim_weight]` curve.
    #[error(
        "[maps.sim_weight] paints each sim hair's factor of the sim weight curve, but there is \
         no [guides.sim_weight]: add its keys or remove the map"
    )]
    SimWeightWithoutCurve,
}

boxed_from!(MapsError, Colors, ScalpColorsError);

/// The names of [`APPLIED`], comma-separated.
fn applied_names() -> String {
    APPLIED
        .iter()
        .map(|(n, _)| *n)
        .collect::<Vec<_>>()
        .join(", ")
}

/// Why the OBJ scalp's vertex colours (`v x y z r g b`) cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum ScalpColorsError {
    /// The file cannot be read.
    #[error("[scalp.mesh] {}: cannot read its vertex colors ({source})", path.display())]
    Read {
        /// The OBJ file.
        path: PathBuf,
        /// Why.
        source: hair_groom::GroomError,
    },
    /// A vertex has a non-finite colour.
    #[error(
        "[scalp.mesh] {}: vertex {vertex} has a non-finite color {color:?}; fix its \
         `v x y z r g b` line",
        path.display()
    )]
    NotFinite {
        /// The OBJ file.
        path: PathBuf,
        /// The vertex.
        vertex: usize,
        /// Its colour.
        color: [f32; 3],
    },
}

/// Cuts `input`'s rest curve at `fraction` of its arc length and resamples it to the same point
/// count, uniform in arc length ([`hair_groom::trim_polyline`]); masses lumped again at its mass
/// per length (kg/m). A fraction of 1 (or more) leaves the strand as it is, bit for bit.
pub(crate) fn trim_input(input: &mut StrandInput, fraction: f32) {
    if fraction >= 1.0 {
        return;
    }
    let n = input.rest.len();
    let length: f32 = input.rest.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    if length.is_nan() || length <= 0.0 {
        // Nothing to cut; the strand set refuses a strand without length by name.
        return;
    }
    let per_length = input.mass.iter().sum::<f32>() / length;
    let mut trimmed = vec![nalgebra::Vector3::zeros(); n];
    hair_groom::trim_polyline(&input.rest, fraction, &mut trimmed);
    let mut mass = vec![0.0; n];
    for k in 1..n {
        let half = 0.5 * per_length * (trimmed[k] - trimmed[k - 1]).norm();
        mass[k - 1] += half;
        mass[k] += half;
    }
    input.rest = trimmed;
    input.mass = mass;
}
