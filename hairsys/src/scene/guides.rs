//! The `[guides]` and `[sim_hairs]` scene sections (seed 001, "Hair Levels"): a few guide hairs,
//! imported from a groom file and snapped onto the scalp or generated on it, define the rest
//! shapes; many more simulation hairs get theirs by interpolation from the nearest guides.

use std::path::{Path, PathBuf};

use hair_core::{Anchor, StrandInput, TriMesh};
use hair_groom::{
    Curl, Distance, GrowDirection, Guide, GuideOptions, ImportOptions, InterpolateOptions, Region,
    SnapOptions, UpAxis,
};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::rig::animated_guides::GuideAnimation;
use crate::scene::guide_anim::GuideAnimError;
use crate::scene::guide_anim::{
    self, AnimationKeys, HairSelection, PinSection, PoseSection, SimWeightSection,
};
use crate::scene::maps::{MapsError, ScalpMaps};
use crate::scene::motion::Interpolation;
use crate::scene::RegionSection;

/// `[guides]`: import `file`, or generate `count` guides.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GuidesSection {
    /// Groom file (.hair, .tfx, .obj polylines, .usd/.usda/.usdc/.usdz), relative to the scene
    /// file.
    #[serde(default)]
    pub file: Option<PathBuf>,
    /// USD files: the prim whose `BasisCurves` are read (`"/Sintel/hair"`: the prim itself or
    /// the curves below it); absent, every `BasisCurves` of the stage.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub prim: Option<String>,
    /// Meters per file unit (absent: 1, or for USD the stage's `metersPerUnit`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<f32>,
    /// The file's up axis, `"z"` or `"y"` (absent: Z, or for USD the stage's `upAxis`). For USD,
    /// giving `scale` or `up_axis` replaces both of the stage's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub up_axis: Option<UpAxis>,
    /// Largest distance a root may be moved onto the scalp, m; farther roots are refused.
    #[serde(default = "default_snap")]
    pub max_snap_distance: f32,
    /// Generated guides: how many.
    #[serde(default)]
    pub count: Option<usize>,
    /// Generated guides: length, m.
    #[serde(default)]
    pub length: Option<f32>,
    /// Generated guides: segments.
    #[serde(default)]
    pub segments: Option<u32>,
    /// Generated guides: seed of the roots.
    #[serde(default)]
    pub seed: u64,
    /// Generated guides: where they grow.
    #[serde(default)]
    pub region: Option<RegionSection>,
    /// Generated guides: comb towards this world direction (absent: along the normal).
    #[serde(default)]
    pub comb_direction: Option<[f32; 3]>,
    /// Generated guides: angle from the normal when combed, degrees.
    #[serde(default)]
    pub comb_angle_deg: f32,
    /// Generated guides: curl radius, m (0 = straight).
    #[serde(default)]
    pub curl_radius: f32,
    /// Generated guides: curl turns per meter.
    #[serde(default)]
    pub curl_turns_per_meter: f32,
    /// Generated guides: laid over the scalp like `[hair.style]` (combed, lifted, curving with
    /// the head) instead of straight.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub style: Option<crate::scene::style::StyleSection>,
    /// Indices of guides switched off (the sim hairs interpolate from the others).
    #[serde(default)]
    pub disabled: Vec<usize>,
    /// `[[guides.pose]]`: keyed guide poses (animated guides; see [`guide_anim`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pose: Vec<PoseSection>,
    /// Interpolation between pose keys, `"ease"` (default) or `"linear"`.
    #[serde(default)]
    pub pose_interpolation: Interpolation,
    /// Height above the scalp, m, that posed sim hairs (keyed poses, between keys, or set by a
    /// host) are lifted to where they would dip into the scalp (absent: as posed). A sweep
    /// that turns hair towards the head then lays it over the head instead. The sim hairs'
    /// radius plus the scalp collider's thickness puts posed hair just touching.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pose_clearance: Option<f32>,
    /// `[guides.sim_weight]`: the curve handing sim hairs between simulation (0) and the
    /// animated guides (1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sim_weight: Option<SimWeightSection>,
    /// `[[guides.pin]]`: sim-hair points held on the animated guides.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pin: Vec<PinSection>,
    /// `[guides.hold_out]`: sim hairs that follow the animated guides exactly, out of the
    /// simulation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hold_out: Option<HairSelection>,
}

/// `[sim_hairs]`: simulation hairs interpolated from the guides.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimHairsSection {
    /// Number of hairs, roots area-weighted (or give `min_distance`).
    #[serde(default)]
    pub count: Option<usize>,
    /// Poisson-disk roots at least this far apart, m (instead of `count`).
    #[serde(default)]
    pub min_distance: Option<f32>,
    /// Seed of the roots.
    #[serde(default)]
    pub seed: u64,
    /// Where sim hairs grow.
    #[serde(default)]
    pub region: Option<RegionSection>,
    /// Sim hairs grow only within this distance (m, straight line) of an enabled guide's root:
    /// where the groom grows hair, not on the rest of the scalp mesh (a bust's neck and
    /// shoulders). Absent: the whole region.
    #[serde(default)]
    pub max_guide_distance: Option<f32>,
    /// Lift interpolated hair out of the scalp to at least this height, m (absent: as
    /// interpolated). Hair blended between guides on a curved head, or guides made on a finer
    /// mesh than this scalp, can dip into it; a scalp collider would then start with hair
    /// inside. The hair radius plus the collider's thickness starts it touching. Sim hairs whose
    /// lifted shape still passes through the scalp (blended between guides either side of a
    /// thin flap such as an ear) are left out: contacts act on points, so a flap between two
    /// points of a strand stays caught. So are sim hairs the lift cannot clear, which start in a
    /// gap of the scalp narrower than twice the clearance (between an ear and the head): a
    /// collider would hold them inside. And so are sim hairs whose root normal turns sharply,
    /// more than 60° from their guides' over less than a 3 cm radius of curvature (rooted on an
    /// ear's rim beside guides on the scalp): blending turns the guides' shapes by that angle,
    /// out into the air. `scene check` says how many of each.
    #[serde(default)]
    pub clearance: Option<f32>,
    /// Guides blended per hair.
    #[serde(default = "default_k")]
    pub k: usize,
    /// Points per hair (default: the guides' point count).
    #[serde(default)]
    pub points: Option<usize>,
    /// `"surface"` (default) or `"euclidean"` root distances.
    #[serde(default)]
    pub distance: Distance,
    /// Linear density, kg/m.
    #[serde(default = "default_density")]
    pub mass_per_length: f32,
    /// Radius, m.
    #[serde(default = "default_radius")]
    pub radius: f32,
    /// Goal weight at the root.
    #[serde(default)]
    pub goal_root: f32,
    /// Goal weight at the tip.
    #[serde(default)]
    pub goal_tip: f32,
}

impl GuidesSection {
    /// The animation keys (poses, sim weight, pins, hold-out) of this section.
    pub fn animation_keys(&self) -> AnimationKeys<'_> {
        AnimationKeys {
            poses: &self.pose,
            interpolation: self.pose_interpolation,
            clearance: self.pose_clearance,
            sim_weight: self.sim_weight.as_ref(),
            pins: &self.pin,
            hold_out: self.hold_out.as_ref(),
        }
    }
}

fn default_snap() -> f32 {
    0.025
}
fn default_k() -> usize {
    4
}
fn default_density() -> f32 {
    1e-3
}
fn default_radius() -> f32 {
    1e-3
}

fn region(r: &Option<RegionSection>) -> Region {
    match r {
        None => Region::All,
        Some(r) => Region::Cone {
            direction: Vector3::from(r.direction),
            max_angle_deg: r.max_angle_deg,
        },
    }
}

/// The guides and their sim hairs, with a report of what was done.
pub struct GuidedHair {
    /// Guides on the scalp (rest shapes in root frames).
    pub guides: Vec<Guide>,
    /// The simulation hairs to add to the strand set.
    pub inputs: Vec<StrandInput>,
    /// One line on the guides (source, snap distances) and the sim hairs.
    pub report: String,
    /// The guides' animation (poses, sim weight, pins, hold-outs), when the scene keys any.
    pub animation: Option<GuideAnimation>,
    /// Each sim hair's nearest guide (the first of its blend sources), for selections.
    pub nearest_guide: Vec<Option<usize>>,
}

/// Builds the guides and the sim hairs interpolated from them. Errors name the section and key.
pub fn build(
    guides: &GuidesSection,
    sim: Option<&SimHairsSection>,
    mesh: &TriMesh,
    base_dir: &Path,
    gravity: &Vector3<f32>,
    maps: &ScalpMaps,
) -> Result<GuidedHair, GuidesError> {
    if guides.file.is_some() && guides.style.is_some() {
        return Err(GuidesError::StyleOfFile);
    }
    let (guides_list, source) = match &guides.file {
        Some(file) => {
            let groom = read_guides(guides, file, base_dir, None).map_err(GuidesError::File)?;
            let snapped = hair_groom::snap_to_scalp(
                &groom,
                mesh,
                &SnapOptions {
                    max_distance: guides.max_snap_distance,
                },
            )
            .map_err(GuidesError::Guides)?;
            let [lo, median, hi] = snapped.distance_summary();
            let source = format!(
                "{} guides from {}, roots snapped {:.2} / {:.2} / {:.2} mm (min / median / max)",
                snapped.guides.len(),
                file.display(),
                lo * 1e3,
                median * 1e3,
                hi * 1e3
            );
            (snapped.guides, source)
        }
        None => {
            let need = |key: &'static str| GuidesError::Missing { key };
            let opts = GuideOptions {
                count: guides.count.ok_or_else(|| need("count"))?,
                length: guides.length.ok_or_else(|| need("length"))?,
                segments: guides.segments.ok_or_else(|| need("segments"))?,
                seed: guides.seed,
                region: region(&guides.region),
                direction: match guides.comb_direction {
                    Some(d) => GrowDirection::Combed {
                        direction: Vector3::from(d),
                        angle_deg: guides.comb_angle_deg,
                    },
                    None => GrowDirection::Normal,
                },
                curl: (guides.curl_radius > 0.0).then_some(Curl {
                    radius: guides.curl_radius,
                    turns_per_meter: guides.curl_turns_per_meter,
                }),
            };
            let mut list = hair_groom::generate_guides(mesh, &opts).map_err(GuidesError::Guides)?;
            if let Some(style) = &guides.style {
                // The styling works on strands: lay the guides as strands, keep their shapes.
                let mut strands: Vec<StrandInput> = list
                    .iter()
                    .map(|g| {
                        StrandInput::uniform(
                            Anchor::Surface(g.root),
                            g.rest.clone(),
                            1e-3,
                            1e-3,
                            0.0,
                            0.0,
                        )
                    })
                    .collect();
                hair_groom::lay_over_scalp(
                    &mut strands,
                    mesh,
                    &style.options(gravity, guides.seed),
                )
                .map_err(GuidesError::Style)?;
                for (g, s) in list.iter_mut().zip(strands) {
                    g.rest = s.rest;
                }
            }
            let source = format!("{} generated guides", list.len());
            (list, source)
        }
    };
    let mut enabled = vec![true; guides_list.len()];
    for &i in &guides.disabled {
        let slot = enabled.get_mut(i).ok_or(GuidesError::Disabled {
            guide: i,
            count: guides_list.len(),
        })?;
        *slot = false;
    }
    let Some(sim) = sim else {
        return Err(GuidesError::NoSimHairs);
    };
    let density = maps.density(mesh).map_err(MapsError::Map)?;
    let density = density.as_ref().map(|d| d as &dyn hair_groom::RootDensity);
    let roots = match (sim.count, sim.min_distance, sim.max_guide_distance) {
        (Some(count), None, Some(d)) => {
            near_guides(mesh, &guides_list, &enabled, count, d, sim, density)?
        }
        (Some(count), None, None) => {
            hair_groom::sample_roots(mesh, count, sim.seed, &region(&sim.region), density)
                .map_err(GuidesError::SimHairs)?
        }
        (None, Some(spacing), near) => {
            let roots = hair_groom::sample_poisson_disk(
                mesh,
                spacing,
                sim.seed,
                &region(&sim.region),
                density,
            )
            .map_err(GuidesError::SimHairs)?;
            match near {
                None => roots,
                Some(d) => {
                    let near = guide_roots(mesh, &guides_list, &enabled, d)?;
                    let grid = PointGrid::new(&near, d);
                    roots
                        .into_iter()
                        .filter(|r| grid.any_within(&mesh.evaluate(r).origin))
                        .collect()
                }
            }
        }
        _ => return Err(GuidesError::RootCount),
    };
    let points = sim
        .points
        .unwrap_or_else(|| guides_list.first().map_or(2, |g| g.rest.len()));
    let opts = InterpolateOptions {
        k: sim.k,
        points,
        distance: sim.distance,
    };
    let mut hairs = hair_groom::interpolate(mesh, &guides_list, &enabled, &roots, &opts)
        .map_err(GuidesError::SimHairs)?;
    let mut inputs = hairs
        .iter()
        .map(|h| {
            StrandInput::uniform(
                Anchor::Surface(h.root),
                h.rest.clone(),
                sim.mass_per_length,
                sim.radius,
                sim.goal_root,
                sim.goal_tip,
            )
        })
        .collect::<Vec<_>>();
    let mut left_out = String::new();
    if let Some(clearance) = sim.clearance {
        // One search tree of the scalp for the lift and both checks after it.
        let lift = hair_groom::ScalpLift::new(mesh, clearance).map_err(GuidesError::SimHairs)?;
        lift.lift_all(&mut inputs);
        let through = lift.strands_through(&inputs);
        // Hair the lift left lower than the quality report's contact tolerance below the
        // clearance would start inside a scalp collider of that reach.
        let tolerance = hair_core::QualityOptions::default().contact_tolerance;
        let low = lift
            .strands_below(&inputs, tolerance)
            .map_err(GuidesError::SimHairs)?;
        // A blend turning its guides' shapes (the angle between root normals) by more than
        // 60° over roots closer than a 3 cm radius of curvature needs — sharper than any skull,
        // as at an ear's rim — turns them out into the air: see
        // `hair_groom::hairs_turned_off_their_guides`.
        let turned =
            hair_groom::hairs_turned_off_their_guides(&hairs, &guides_list, mesh, 60.0, 0.03)
                .map_err(GuidesError::SimHairs)?;
        let mut reasons = Vec::new();
        if !through.is_empty() {
            reasons.push(format!(
                "{} left out: their blended shape passes through the scalp, e.g. between \
                 guides either side of an ear",
                through.len()
            ));
        }
        let low: Vec<usize> = low.into_iter().filter(|i| !through.contains(i)).collect();
        if !low.is_empty() {
            reasons.push(format!(
                "{} left out: they start in a gap of the scalp narrower than twice the \
                 clearance, e.g. between ear and head, which no lift clears",
                low.len()
            ));
        }
        let turned: Vec<usize> = turned
            .into_iter()
            .filter(|i| !through.contains(i) && !low.contains(i))
            .collect();
        if !turned.is_empty() {
            reasons.push(format!(
                "{} left out: rooted where the scalp turns sharply, more than 60° from their \
                 guides' roots nearby (e.g. on an ear's rim), their blended shape would stand \
                 off the head",
                turned.len()
            ));
        }
        if !reasons.is_empty() {
            left_out = format!(" ({})", reasons.join("; "));
            // The hairs and their strand inputs stay in step: animated guides blend the
            // hairs kept, one per strand.
            let mut keep = vec![true; inputs.len()];
            through
                .iter()
                .chain(&low)
                .chain(&turned)
                .for_each(|&i| keep[i] = false);
            let mut kept = keep.iter();
            inputs.retain(|_| kept.next() == Some(&true));
            let mut kept = keep.iter();
            hairs.retain(|_| kept.next() == Some(&true));
        }
    }
    // `[maps.length]`: each sim hair cut to its painted fraction, as built here and as every
    // pose re-blends it (the blend trims by the same fractions).
    let fractions = maps.length_fractions(mesh, hairs.iter().map(|h| &h.root), "sim hair")?;
    if let Some(fractions) = &fractions {
        for (input, &f) in inputs.iter_mut().zip(fractions) {
            crate::scene::maps::trim_input(input, f);
        }
    }
    let keys = guides.animation_keys();
    // Built for every guided scene (cheap: the weights are kept, nothing runs per frame without
    // keys), so a host can pose the guides of any guided scene.
    let animation = {
        let read =
            |file: &Path, time: Option<f64>| -> Result<Vec<Vec<Vector3<f32>>>, ReadGuidesError> {
                read_guides(guides, file, base_dir, time).map(|g| g.curves().to_vec())
            };
        Some(guide_anim::build(
            &keys,
            mesh,
            &guides_list,
            &hairs,
            &mut inputs,
            points,
            fractions,
            guides.max_snap_distance,
            maps,
            &read,
        )?)
    };
    let report = format!(
        "{source}; {} enabled; {} sim hairs of {points} points from the {} nearest{left_out}",
        enabled.iter().filter(|&&e| e).count(),
        inputs.len(),
        sim.k
    );
    Ok(GuidedHair {
        guides: guides_list,
        nearest_guide: hairs
            .iter()
            .map(|h| h.sources.first().map(|s| s.guide))
            .collect(),
        inputs,
        report,
        animation,
    })
}

/// Reads the groom `file` (relative to `base_dir`) with `[guides]`'s `prim`, `scale` and
/// `up_axis`; USD files at time code `time` (absent: the earliest sample or the default).
fn read_guides(
    guides: &GuidesSection,
    file: &Path,
    base_dir: &Path,
    time: Option<f64>,
) -> Result<hair_groom::Groom, ReadGuidesError> {
    let path = base_dir.join(file);
    let units = ImportOptions {
        scale: guides.scale.unwrap_or(1.0),
        up_axis: guides.up_axis.unwrap_or_default(),
    };
    match hair_groom::GroomFormat::of(&path) {
        #[cfg(not(feature = "usd"))]
        Ok(hair_groom::GroomFormat::Usd) => Err(hair_groom::GroomError::usd_not_built(&path)),
        #[cfg(feature = "usd")]
        Ok(hair_groom::GroomFormat::Usd) => hair_groom::read_usd(
            &path,
            &hair_groom::UsdReadOptions {
                prim: guides.prim.clone(),
                time,
                units: (guides.scale.is_some() || guides.up_axis.is_some()).then_some(units),
            },
        )
        .map(|c| c.groom),
        _ if guides.prim.is_some() => {
            return Err(ReadGuidesError::PrimOfNotUsd {
                prim: guides.prim.clone().unwrap_or_default(),
                file: file.to_path_buf(),
            })
        }
        _ if time.is_some() => {
            return Err(ReadGuidesError::TimeOfNotUsd {
                file: file.to_path_buf(),
            })
        }
        _ => hair_groom::read_groom(&path, &units),
    }
    .map_err(ReadGuidesError::Read)
}

/// The enabled guides' roots (m), with `max_distance` (the sim hairs' largest distance from
/// one, m) checked: finite and > 0.
fn guide_roots(
    mesh: &TriMesh,
    guides: &[Guide],
    enabled: &[bool],
    max_distance: f32,
) -> Result<Vec<Vector3<f32>>, GuidesError> {
    if !(max_distance.is_finite() && max_distance > 0.0) {
        return Err(GuidesError::MaxGuideDistance {
            value: max_distance,
        });
    }
    Ok(guides
        .iter()
        .zip(enabled)
        .filter(|(_, &e)| e)
        .map(|(g, _)| mesh.evaluate(&g.root).origin)
        .collect())
}

/// `count` roots within `max_distance` (m) of an enabled guide root: the area-weighted sequence
/// (thinned by `density`), drawn until `count` are near the guides.
fn near_guides(
    mesh: &TriMesh,
    guides: &[Guide],
    enabled: &[bool],
    count: usize,
    max_distance: f32,
    sim: &SimHairsSection,
    density: Option<&dyn hair_groom::RootDensity>,
) -> Result<Vec<hair_core::MeshSample>, GuidesError> {
    let guide_roots = guide_roots(mesh, guides, enabled, max_distance)?;
    let grid = PointGrid::new(&guide_roots, max_distance);
    let mut sampler = hair_groom::RootSampler::new(mesh, sim.seed, &region(&sim.region), density)
        .map_err(GuidesError::SimHairs)?;
    // A groom covering a thousandth of the region is still filled; a smaller one is refused.
    let max_draws = count.saturating_mul(hair_groom::sampling::MAX_DRAWS_PER_ROOT);
    let kept = sampler
        .fill(count, max_draws, |r| {
            grid.any_within(&mesh.evaluate(r).origin)
        })
        .map_err(GuidesError::SimHairs)?;
    if kept.len() < count {
        return Err(GuidesError::FewNearGuides {
            max_distance,
            found: kept.len(),
            count,
            draws: sampler.drawn(),
            density: density.is_some(),
        });
    }
    Ok(kept)
}

/// Points hashed into cubic cells of one search radius, to ask "is any within the radius?" by
/// looking at the 27 cells around a query.
struct PointGrid<'a> {
    points: &'a [Vector3<f32>],
    radius: f32,
    cells: std::collections::HashMap<[i64; 3], Vec<usize>>,
}

impl<'a> PointGrid<'a> {
    fn cell(p: &Vector3<f32>, radius: f32) -> [i64; 3] {
        [p.x, p.y, p.z].map(|c| (c / radius).floor() as i64)
    }

    fn new(points: &'a [Vector3<f32>], radius: f32) -> Self {
        let mut cells: std::collections::HashMap<[i64; 3], Vec<usize>> = Default::default();
        for (i, p) in points.iter().enumerate() {
            cells.entry(Self::cell(p, radius)).or_default().push(i);
        }
        Self {
            points,
            radius,
            cells,
        }
    }

    fn any_within(&self, q: &Vector3<f32>) -> bool {
        let [x, y, z] = Self::cell(q, self.radius);
        (-1..=1).any(|dx| {
            (-1..=1).any(|dy| {
                (-1..=1).any(|dz| {
                    self.cells
                        .get(&[x + dx, y + dy, z + dz])
                        .is_some_and(|list| {
                            list.iter()
                                .any(|&i| (self.points[i] - q).norm() <= self.radius)
                        })
                })
            })
        })
    }
}

/// Why a guide groom file (`[guides] file`, a `[[guides.pose]]` file) cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum ReadGuidesError {
    /// The file cannot be read as a groom.
    #[error("{0}")]
    Read(#[source] hair_groom::GroomError),
    /// `prim` is given for a file that is not USD.
    #[error(
        "[guides] prim = {prim:?} selects a prim of a USD stage, but {} is not a USD file; \
         remove `prim`",
        file.display()
    )]
    PrimOfNotUsd {
        /// The prim given.
        prim: String,
        /// The file, as the scene names it.
        file: PathBuf,
    },
    /// `time` is given for a file that is not USD.
    #[error(
        "`time` picks a USD time sample, but {} is not a USD file; remove `time`",
        file.display()
    )]
    TimeOfNotUsd {
        /// The file, as the scene names it.
        file: PathBuf,
    },
}

/// Why `[guides]` and `[sim_hairs]` cannot be built into simulation hairs.
#[derive(Debug, thiserror::Error)]
pub enum GuidesError {
    /// `[guides.style]` beside an imported groom.
    #[error(
        "[guides.style] lays generated guides over the scalp; an imported groom keeps its \
         shape: remove [guides.style] or `file`"
    )]
    StyleOfFile,
    /// `[guides] file` cannot be read.
    #[error("[guides] file: {0}")]
    File(#[source] ReadGuidesError),
    /// The guides cannot be snapped or generated on the scalp.
    #[error("[guides] {0}")]
    Guides(#[source] hair_groom::GroomError),
    /// A key generated guides need is missing.
    #[error("[guides] needs `file`, or `{key}` (with count, length, segments) to generate guides")]
    Missing {
        /// The key.
        key: &'static str,
    },
    /// `[guides.style]` cannot lay the guides.
    #[error("[guides.style] {0}")]
    Style(#[source] hair_groom::GroomError),
    /// `disabled` names a guide that does not exist.
    #[error(
        "[guides] disabled names guide {guide} but there are {count} guides (0–{})",
        .count.saturating_sub(1)
    )]
    Disabled {
        /// The guide named.
        guide: usize,
        /// The guides there are.
        count: usize,
    },
    /// `[guides]` without `[sim_hairs]`.
    #[error(
        "[guides] needs a [sim_hairs] section: how many simulation hairs to interpolate from \
         the guides"
    )]
    NoSimHairs,
    /// The sim hairs cannot be rooted, interpolated or lifted.
    #[error("[sim_hairs] {0}")]
    SimHairs(#[source] hair_groom::GroomError),
    /// Neither or both of `count` and `min_distance`.
    #[error(
        "[sim_hairs] give exactly one of `count` (area-weighted roots) or `min_distance` \
         (Poisson disk, m)"
    )]
    RootCount,
    /// `max_guide_distance` not a finite distance > 0.
    #[error("[sim_hairs] max_guide_distance = {value}: use a finite distance > 0 m, e.g. 0.01")]
    MaxGuideDistance {
        /// The value given, m.
        value: f32,
    },
    /// Too few roots near the guides.
    #[error(
        "[sim_hairs] max_guide_distance = {max_distance} m: only {found} of {count} roots found \
         near the guide roots in {draws} draws; raise max_guide_distance or check that the \
         guides were snapped onto this scalp{}",
        if *.density { " (and that [maps.density] is painted near them)" } else { "" }
    )]
    FewNearGuides {
        /// `max_guide_distance`, m.
        max_distance: f32,
        /// Roots found.
        found: usize,
        /// Roots asked for (`count`).
        count: usize,
        /// Candidates drawn.
        draws: usize,
        /// Whether a `[maps.density]` thinned the candidates.
        density: bool,
    },
    /// A map cannot be applied to the sim hairs.
    #[error("{0}")]
    Maps(Box<MapsError>),
    /// The animated guides' keys are refused.
    #[error("{0}")]
    Animation(Box<GuideAnimError>),
}

boxed_from!(GuidesError, Maps, MapsError);
boxed_from!(GuidesError, Animation, GuideAnimError);
