//! The `[strips]` scene section: seed 000's hair-strip model (`[solver] model = "strips"`). Strips
//! are grown on scalp triangles inside an optional cone `region` (every `every`-th triangle, at
//! most `max_strips`); each strip's two edge strands are the simulated strands of the scene, so
//! the cache holds them like any other strands (strip `k` = strands `2k`, `2k + 1`).

use hair_core::model::strips::{RootAngleLimit, StripGrowth, StripSet, StripSettings};
use hair_core::TriMesh;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::scene::RegionSection;

/// `[strips]`.
///
/// Not a pair of `hair_core::model::strips` types, on purpose: the section is one flat table where
/// the library splits growth ([`StripGrowth`]) from stepping ([`StripSettings`]), gives the root
/// angle in degrees where [`RootAngleLimit`] holds radians, and adds scene-only choices of which
/// triangles grow strips (`every`, `max_strips`, `region`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct StripsSection {
    /// Edge strand length, m.
    pub length: f32,
    /// Segments per edge strand.
    pub segments: u32,
    /// Hairs one strip stands for.
    pub hairs_per_strip: u32,
    /// Where the right edge sits between the triangle's centre (0) and its corner (1).
    pub width_fraction: f32,
    /// Linear density of an edge strand, kg/m.
    pub mass_per_length: f32,
    /// Collision radius of edge points, m.
    pub radius: f32,
    /// Provot's strain limit (dimensionless, ≥ 0).
    pub max_strain: f32,
    /// Root angle limit, degrees in (0, 180); absent = off.
    pub root_angle_deg: Option<f32>,
    /// Gap kept between edge points and the head, m (with `[scalp.collider]`).
    pub clearance: f32,
    /// Use every n-th scalp triangle inside the region (≥ 1).
    pub every: u32,
    /// At most this many strips (absent = no limit).
    pub max_strips: Option<u32>,
    /// Triangles whose normal lies within this cone; absent = the whole scalp.
    pub region: Option<RegionSection>,
    /// Lay both edge strands of every strip over the scalp (see [`crate::scene::style`]) so the
    /// cards lie on the head instead of standing out along the normals. `layer` should be 0 (both
    /// edges at one height) and the lift within `root_angle_deg` of the normal.
    #[serde(default)]
    pub style: Option<crate::scene::style::StyleSection>,
}

impl Default for StripsSection {
    fn default() -> Self {
        let g = StripGrowth::default();
        let s = StripSettings::default();
        Self {
            length: g.length,
            segments: g.segments,
            hairs_per_strip: g.hairs_per_strip,
            width_fraction: g.width_fraction,
            mass_per_length: g.mass_per_length,
            radius: g.radius,
            max_strain: s.max_strain,
            root_angle_deg: Some(60.0),
            clearance: s.clearance,
            every: 1,
            max_strips: None,
            region: None,
            style: None,
        }
    }
}

impl StripsSection {
    /// The strip-model settings of the section.
    pub fn settings(&self) -> Result<StripSettings, StripsError> {
        let root_angle = self
            .root_angle_deg
            .map(|deg| RootAngleLimit::new(deg.to_radians()))
            .transpose()
            .map_err(StripsError::Invalid)?;
        let s = StripSettings {
            max_strain: self.max_strain,
            root_angle,
            clearance: self.clearance,
        };
        s.validate().map_err(StripsError::Invalid)?;
        Ok(s)
    }

    /// Grows the strips on `mesh` (the scalp at rest, m).
    pub fn build(&self, mesh: &TriMesh) -> Result<StripSet, StripsError> {
        if self.every == 0 {
            return Err(StripsError::EveryZero);
        }
        let cone = match &self.region {
            Some(r) => {
                let axis = Vector3::from(r.direction);
                let Some(axis) = axis.try_normalize(1e-12) else {
                    return Err(StripsError::NoDirection {
                        direction: r.direction,
                    });
                };
                Some((axis, r.max_angle_deg.to_radians().cos()))
            }
            None => None,
        };
        let normals = mesh.vertex_normals();
        let triangles: Vec<u32> = (0..mesh.triangles().len())
            .filter(|&t| match cone {
                None => true,
                Some((axis, cos)) => {
                    let n: Vector3<f32> = mesh.triangles()[t]
                        .iter()
                        .map(|&i| normals[i as usize])
                        .sum();
                    n.try_normalize(1e-12).is_some_and(|n| n.dot(&axis) >= cos)
                }
            })
            .step_by(self.every as usize)
            .take(self.max_strips.map_or(usize::MAX, |m| m as usize))
            .map(|t| t as u32)
            .collect();
        let growth = StripGrowth {
            length: self.length,
            segments: self.segments,
            hairs_per_strip: self.hairs_per_strip,
            width_fraction: self.width_fraction,
            mass_per_length: self.mass_per_length,
            radius: self.radius,
        };
        StripSet::from_triangles(mesh, &triangles, &growth).map_err(StripsError::Invalid)
    }
}

/// Adds the edge strands of `[strips]` to `strands` when `[solver] model = "strips"` and returns
/// the strip settings; checks that the model and the section come together, that the scalp has
/// a mesh and that no other hair source (`[hair]`, `[guides]`, `[[strands]]`) or mass-spring-only
/// component (`[hair_hair]`, `[[fields]]`) is given with it.
pub fn build_into(
    scene: &crate::scene::Scene,
    mesh: Option<&TriMesh>,
    strands: &mut hair_core::StrandSet,
) -> Result<Option<StripSettings>, StripsError> {
    let strips_model = scene.solver.model == hair_core::StrandModel::Strips;
    let section = match (&scene.strips, strips_model) {
        (None, false) => return Ok(None),
        (Some(_), false) => return Err(StripsError::WithoutModel),
        (None, true) => return Err(StripsError::MissingSection),
        (Some(section), true) => section,
    };
    if !strands.is_empty() || scene.guides.is_some() {
        return Err(StripsError::OtherHair);
    }
    if scene.hair_hair.is_some() || !scene.fields.is_empty() {
        return Err(StripsError::MassSpringOnly);
    }
    let Some(mesh) = mesh else {
        return Err(StripsError::NoScalp);
    };
    let settings = section.settings()?;
    let set = section.build(mesh)?;
    let mut inputs = Vec::with_capacity(set.strands.len());
    for s in 0..set.strands.len() {
        inputs.push(hair_core::StrandInput {
            anchor: set.strands.anchors()[s],
            rest: set.strands.rest_local()[set.strands.points(s)].to_vec(),
            mass: set.strands.masses()[set.strands.points(s)].to_vec(),
            radius: set.strands.radii()[set.strands.points(s)].to_vec(),
            goal_weight: set.strands.goal_weights()[set.strands.points(s)].to_vec(),
            pinned: set.strands.inverse_masses()[set.strands.points(s)]
                .iter()
                .map(|&w| w == 0.0)
                .collect(),
        });
    }
    if let Some(style) = &section.style {
        // One seed for every strip: with `layer = 0` both edges of a card lie at one height.
        let opts = style.options(&scene.physics.gravity(), 0);
        hair_groom::lay_over_scalp(&mut inputs, mesh, &opts).map_err(StripsError::Style)?;
    }
    for input in inputs {
        strands.push(input).map_err(StripsError::Invalid)?;
    }
    Ok(Some(settings))
}

/// Why the `[strips]` section (or the strips model) is refused.
#[derive(Debug, thiserror::Error)]
pub enum StripsError {
    /// A value of the section is out of range, or the strips cannot be grown (the solver's
    /// check).
    #[error("[strips] {0}")]
    Invalid(#[source] hair_core::HairError),
    /// `every = 0`.
    #[error("[strips] every = 0: use every n-th triangle with n ≥ 1")]
    EveryZero,
    /// The region's direction has no length.
    #[error("[strips] region.direction = {direction:?} has no length; give an axis")]
    NoDirection {
        /// The direction given.
        direction: [f32; 3],
    },
    /// `[strips]` without `[solver] model = "strips"`.
    #[error(
        "[strips] is given but [solver] model is not \"strips\"; set model = \"strips\" or \
         remove [strips]"
    )]
    WithoutModel,
    /// `[solver] model = "strips"` without `[strips]`.
    #[error(
        "[solver] model = \"strips\" needs a [strips] section (e.g. length = 0.2, segments = 8, \
         hairs_per_strip = 100)"
    )]
    MissingSection,
    /// Other hair (`[hair]`, `[guides]`, `[[strands]]`) beside the strips.
    #[error(
        "[solver] model = \"strips\" grows its own edge strands from [strips]; remove [hair], \
         [guides] and [[strands]]"
    )]
    OtherHair,
    /// `[hair_hair]` or `[[fields]]` with the strips model.
    #[error(
        "[hair_hair] and [[fields]] act on the mass-spring model only; remove them or set \
         [solver] model = \"mass-spring\""
    )]
    MassSpringOnly,
    /// No scalp mesh to grow strips on.
    #[error(
        "[strips] grows strips on scalp triangles, but [scalp.mesh] kind = \"none\"; choose a \
         scalp mesh"
    )]
    NoScalp,
    /// `[strips.style]` cannot lay the strips.
    #[error("[strips.style] {0}")]
    Style(#[source] hair_groom::GroomError),
}
