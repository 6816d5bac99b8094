//! `[[regions]]`: named regions of the scalp with their own physical parameters in one
//! simulation (per-region settings: a stiff short fringe beside long soft back hair),
//! and `[maps.stiffness]`, a painted factor of each hair's bending stiffness.
//!
//! ```toml
//! [[regions]]
//! name = "fringe"
//! region = { direction = [0, -1, 0.3], max_angle_deg = 35 }   # or guides, strands, map
//! bend_stiffness = 4.0        # N/m, this region's [physics] bend_stiffness
//! stretch_stiffness = 800.0   # any [physics] spring or damping key; absent = the scene's
//! mass_scale = 0.5            # factors of the hair's point masses and radii
//! ```
//!
//! A region selects hair as the other selections do ([`HairSelection`]: by nearest guide, by
//! strand index — here the run's strand order, `[hair]` strands, then sim hairs, then
//! `[[strands]]` —, by a cone of root normals on the scalp at rest, or by a painted map's value at
//! the root) and gives any of the `[physics]` keys `stretch_stiffness`, `bend_stiffness`,
//! `goal_stiffness`, `stretch_damping` and `air_drag` in the same units, plus `mass_scale` and
//! `radius_scale`. The solver runs each strand with its own parameters (see
//! `hair_core::MassSpringSolver::with_strand_scales`): they are kept as factors of `[physics]`, so
//! a host animating `[physics]` moves every region with it; `[physics]` must therefore give a
//! component a region uses (a region cannot switch on bending the scene has off).
//!
//! **Overlaps: the last region wins, key by key.** Regions apply in file order; a hair in two
//! regions takes each key from the later region that gives it, and the earlier region's value
//! (or `[physics]`) for keys the later one leaves out.
//!
//! `[maps.stiffness]` multiplies each scalp-rooted hair's bending stiffness by the map at its root
//! (after the regions, so it paints a gradient within them). With neither regions nor that map
//! the solver gets no factors at all, and runs bit for bit as a scene without them.
//!
//! With `substeps = "auto"` the stiffest region sets the substep of the whole run (one solver
//! steps every strand together), so hair outside a stiff region takes more, shorter substeps.
//! Regions are for the mass-spring model (every integrator); the rod and strip models refuse
//! them, as does `[solver] sag_free` (its solve assumes one material).

use hair_core::{Anchor, HairParams, StrandScales, StrandSet, TriMesh};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::scene::guide_anim::{HairSelection, SelectionError};
use crate::scene::maps::{MapsError, ScalpMaps};

/// `[[regions]]`: one named region and its parameters (absent keys: the scene's).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionPhysicsSection {
    /// The region's name, unique in the scene (errors and the library name it).
    pub name: String,
    /// The hair in the region.
    #[serde(flatten)]
    pub select: HairSelection,
    /// Parameters of the region's hair.
    #[serde(flatten)]
    pub params: RegionParams,
}

/// A region's parameters: `[physics]` keys (same units) and material factors; `None` = the
/// scene's value.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionParams {
    /// Stretch spring stiffness, N/m (> 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stretch_stiffness: Option<f32>,
    /// Bending stiffness, N/m (≥ 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bend_stiffness: Option<f32>,
    /// Goal spring stiffness, N/m (≥ 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub goal_stiffness: Option<f32>,
    /// Stretch damping rate, 1/s (≥ 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stretch_damping: Option<f32>,
    /// Air drag rate, 1/s (≥ 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub air_drag: Option<f32>,
    /// Factor of the hair's point masses (> 0; fixed when the scene is built).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass_scale: Option<f32>,
    /// Factor of the hair's radii (≥ 0; fixed when the scene is built).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius_scale: Option<f32>,
}

/// One `[physics]` key a region may give: its name, the region's value, and the scene's.
type SolverKey = (&'static str, Option<f32>, fn(&HairParams) -> f32);

impl RegionParams {
    /// The keys that change the solver's factors (not mass or radius).
    fn solver_keys(&self) -> [SolverKey; 5] {
        [
            ("stretch_stiffness", self.stretch_stiffness, |p| {
                p.stretch_stiffness
            }),
            ("bend_stiffness", self.bend_stiffness, |p| p.bend_stiffness),
            ("goal_stiffness", self.goal_stiffness, |p| p.goal_stiffness),
            ("stretch_damping", self.stretch_damping, |p| {
                p.stretch_damping
            }),
            ("air_drag", self.air_drag, |p| p.air_drag),
        ]
    }
}

/// One region as built: its name, the strands it holds and its parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct BuiltRegion {
    /// The region's name.
    pub name: String,
    /// How it selects its hair (as the scene gives it).
    pub selection: HairSelection,
    /// Its strands (indices into the run's strand set), increasing.
    pub strands: Vec<usize>,
    /// Its parameters.
    pub params: RegionParams,
}

/// The scene's regions and stiffness map, resolved to strands: what the solver's per-strand
/// factors are made from, kept so a host can change a region's parameters between frames
/// ([`crate::Session::set_region_params`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Regions {
    /// The regions in file order.
    pub regions: Vec<BuiltRegion>,
    /// Each strand's `[maps.stiffness]` factor of bending (empty without that map).
    pub stiffness_map: Vec<f32>,
}

/// Where the strands of a run grow, for selecting them.
pub struct StrandRoots<'a> {
    /// The scalp at rest, if the scene has one.
    pub mesh: Option<&'a TriMesh>,
    /// Each strand's nearest guide (None: not a sim hair).
    pub nearest_guide: &'a [Option<usize>],
    /// Number of guides.
    pub guide_count: usize,
}

impl Regions {
    /// True when there is nothing to apply (the solver then gets no factors).
    pub fn is_empty(&self) -> bool {
        self.regions.is_empty() && self.stiffness_map.is_empty()
    }

    /// Resolves `sections` and the `stiffness` map over `strands`, and applies the regions'
    /// mass and radius factors to `strands`. Errors name the region, the key and the fix.
    pub fn build(
        sections: &[RegionPhysicsSection],
        params: &HairParams,
        strands: &mut StrandSet,
        roots: &StrandRoots,
        maps: &ScalpMaps,
    ) -> Result<Self, RegionError> {
        let mut regions: Vec<BuiltRegion> = Vec::with_capacity(sections.len());
        for (i, r) in sections.iter().enumerate() {
            let what = format!("[[regions]] #{i} \"{}\"", r.name);
            if r.name.trim().is_empty() {
                return Err(RegionError::Unnamed { index: i });
            }
            if regions.iter().any(|b| b.name == r.name) {
                return Err(RegionError::SameName { region: what });
            }
            if r.select.is_empty() {
                return Err(SelectionError::Nothing { selection: what }.into());
            }
            check_params(&r.params, params, &what)?;
            let chosen = select(&r.select, &what, strands, roots, maps)?;
            regions.push(BuiltRegion {
                name: r.name.clone(),
                selection: r.select.clone(),
                strands: (0..chosen.len()).filter(|&s| chosen[s]).collect(),
                params: r.params,
            });
        }
        // Mass and radius, last region wins.
        let mut material = vec![(1.0f32, 1.0f32); strands.len()];
        for r in &regions {
            for &s in &r.strands {
                if let Some(m) = r.params.mass_scale {
                    material[s].0 = m;
                }
                if let Some(m) = r.params.radius_scale {
                    material[s].1 = m;
                }
            }
        }
        for (s, &(mass, radius)) in material.iter().enumerate() {
            if (mass, radius) != (1.0, 1.0) {
                strands
                    .scale_strand(s, mass, radius)
                    .map_err(RegionError::Material)?;
            }
        }
        let mut stiffness_map = Vec::new();
        if let Some(map) = maps.get("stiffness") {
            let mesh = roots.mesh.ok_or(MapsError::StiffnessWithoutScalp)?;
            stiffness_map = vec![1.0; strands.len()];
            for (s, f) in stiffness_map.iter_mut().enumerate() {
                let Anchor::Surface(sample) = strands.anchors()[s] else {
                    continue;
                };
                let v = map
                    .at(mesh, &sample, &format!("strand {s}"))
                    .map_err(MapsError::Map)?;
                if !(v.is_finite() && v >= 0.0) {
                    return Err(MapsError::StiffnessFactor {
                        value: v,
                        strand: s,
                    }
                    .into());
                }
                *f = v;
            }
        }
        Ok(Self {
            regions,
            stiffness_map,
        })
    }

    /// Each strand's factors of `params` for `strand_count` strands: the regions in order (last
    /// wins, key by key), then the stiffness map. Empty when [`Self::is_empty`].
    pub fn scales(
        &self,
        params: &HairParams,
        strand_count: usize,
    ) -> Result<Vec<StrandScales>, RegionError> {
        if self.is_empty() {
            return Ok(Vec::new());
        }
        let mut scales = vec![StrandScales::ONE; strand_count];
        for r in &self.regions {
            let what = format!("region \"{}\"", r.name);
            let factors = factors(&r.params, params, &what)?;
            for &s in &r.strands {
                let scale = &mut scales[s];
                let slots = [
                    &mut scale.stretch,
                    &mut scale.bend,
                    &mut scale.goal,
                    &mut scale.damping,
                    &mut scale.drag,
                ];
                for (slot, f) in slots.into_iter().zip(factors) {
                    if let Some(f) = f {
                        *slot = f;
                    }
                }
            }
        }
        for (scale, &f) in scales.iter_mut().zip(&self.stiffness_map) {
            scale.bend *= f;
        }
        Ok(scales)
    }

    /// The region named `name`.
    pub fn get_mut(&mut self, name: &str) -> Option<&mut BuiltRegion> {
        self.regions.iter_mut().find(|r| r.name == name)
    }
}

/// Checks a region's values: finite, ≥ 0 (stretch and mass > 0), and no component the scene
/// has off.
pub fn check_params(r: &RegionParams, params: &HairParams, what: &str) -> Result<(), RegionError> {
    factors(r, params, what)?;
    if let Some(m) = r.mass_scale {
        if !(m.is_finite() && m > 0.0) {
            return Err(RegionError::MassScale {
                region: what.to_string(),
                value: m,
            });
        }
    }
    if let Some(m) = r.radius_scale {
        if !(m.is_finite() && m >= 0.0) {
            return Err(RegionError::RadiusScale {
                region: what.to_string(),
                value: m,
            });
        }
    }
    Ok(())
}

/// The factors of `params` a region's values make (stretch, bend, goal, damping, drag; None
/// where the region keeps the scene's value).
fn factors(
    r: &RegionParams,
    params: &HairParams,
    what: &str,
) -> Result<[Option<f32>; 5], RegionError> {
    let mut out = [None; 5];
    for (slot, (key, value, scene)) in out.iter_mut().zip(r.solver_keys()) {
        let Some(value) = value else { continue };
        let scene = scene(params);
        let least = if key == "stretch_stiffness" {
            "> 0"
        } else {
            "≥ 0"
        };
        let valid = value.is_finite() && (value > 0.0 || (value == 0.0 && least == "≥ 0"));
        if !valid {
            return Err(RegionError::Parameter {
                region: what.to_string(),
                key,
                value,
                least,
            });
        }
        *slot = Some(if scene > 0.0 {
            value / scene
        } else if value == 0.0 {
            1.0
        } else {
            return Err(RegionError::SwitchedOff {
                region: what.to_string(),
                key,
                value,
            });
        });
    }
    Ok(out)
}

/// The strands `s` selects; errors name `what`, the bad index and the fix, or say the selection
/// names no hair.
fn select(
    s: &HairSelection,
    what: &str,
    strands: &StrandSet,
    roots: &StrandRoots,
    maps: &ScalpMaps,
) -> Result<Vec<bool>, SelectionError> {
    let count = strands.len();
    let mut chosen = vec![false; count];
    let selection = || what.to_string();
    if let Some(list) = &s.guides {
        if roots.guide_count == 0 {
            return Err(SelectionError::NoGuides {
                selection: selection(),
            });
        }
        for &g in list {
            if g >= roots.guide_count {
                return Err(SelectionError::Guide {
                    selection: selection(),
                    guide: g,
                    count: roots.guide_count,
                });
            }
        }
        for (c, nearest) in chosen.iter_mut().zip(roots.nearest_guide) {
            *c |= nearest.is_some_and(|n| list.contains(&n));
        }
    }
    if let Some(list) = &s.strands {
        for &i in list {
            *chosen.get_mut(i).ok_or_else(|| SelectionError::Strand {
                selection: selection(),
                strand: i,
                count,
            })? = true;
        }
    }
    let surface = |s: usize| match strands.anchors()[s] {
        Anchor::Surface(sample) => Some(sample),
        Anchor::Body(_) => None,
    };
    if let Some(r) = &s.region {
        let mesh = roots
            .mesh
            .ok_or_else(|| SelectionError::RegionWithoutScalp {
                selection: selection(),
            })?;
        let (axis, cos) = r.cone(what)?;
        for (i, c) in chosen.iter_mut().enumerate() {
            if let Some(sample) = surface(i) {
                let normal = mesh.evaluate(&sample).rotation * Vector3::z();
                *c |= normal.dot(&axis) >= cos;
            }
        }
    }
    if let Some(m) = &s.map {
        let map = maps.selected(m, what)?;
        let mesh = roots.mesh.ok_or_else(|| SelectionError::MapWithoutScalp {
            selection: selection(),
        })?;
        for (i, c) in chosen.iter_mut().enumerate() {
            if let Some(sample) = surface(i) {
                *c |= m.contains(
                    map.at(mesh, &sample, &format!("strand {i}"))
                        .map_err(MapsError::Map)?,
                );
            }
        }
    }
    if !chosen.iter().any(|&c| c) {
        return Err(SelectionError::NoHair {
            selection: selection(),
            hairs: "strand",
        });
    }
    Ok(chosen)
}

/// Why `[[regions]]` (or a host's region parameters) are refused. `region` names the region
/// as the message shows it (`[[regions]] #i "name"`, `region "name"`).
#[derive(Debug, thiserror::Error)]
pub enum RegionError {
    /// A region without a name.
    #[error(
        "[[regions]] #{index} has no name; give name = \"fringe\" (errors and the library name \
         regions)"
    )]
    Unnamed {
        /// The region's index in `[[regions]]`.
        index: usize,
    },
    /// Two regions with one name.
    #[error("{region}: another region has this name; give each region its own")]
    SameName {
        /// The second region.
        region: String,
    },
    /// The region's selection of hair is refused.
    #[error("{0}")]
    Selection(Box<SelectionError>),
    /// A solver parameter that is not finite or below its least value.
    #[error("{region} {key} = {value}: give a finite value {least} in [physics]'s units")]
    Parameter {
        /// The region.
        region: String,
        /// The key (`bend_stiffness`, …).
        key: &'static str,
        /// The value given.
        value: f32,
        /// The allowed range: `"> 0"` or `"≥ 0"`.
        least: &'static str,
    },
    /// A parameter the scene switches off (0 in `[physics]`), which a region cannot scale.
    #[error(
        "{region} {key} = {value}, but [physics] {key} = 0 switches it off for all hair: a region \
         scales the scene's material, so set [physics] {key} > 0 (and give the other hair its \
         own region, or 0 here) or remove the key"
    )]
    SwitchedOff {
        /// The region.
        region: String,
        /// The key.
        key: &'static str,
        /// The value given.
        value: f32,
    },
    /// `mass_scale` not a finite factor > 0.
    #[error("{region} mass_scale = {value}: give a finite factor > 0 of the hair's masses")]
    MassScale {
        /// The region.
        region: String,
        /// The value given.
        value: f32,
    },
    /// `radius_scale` not a finite factor ≥ 0.
    #[error("{region} radius_scale = {value}: give a finite factor ≥ 0 of the hair's radii")]
    RadiusScale {
        /// The region.
        region: String,
        /// The value given.
        value: f32,
    },
    /// A strand's masses or radii cannot be scaled.
    #[error("[[regions]] {0}")]
    Material(#[source] hair_core::HairError),
    /// `[maps.stiffness]` cannot be applied.
    #[error("{0}")]
    Maps(Box<MapsError>),
}

boxed_from!(RegionError, Selection, SelectionError);
boxed_from!(RegionError, Maps, MapsError);
