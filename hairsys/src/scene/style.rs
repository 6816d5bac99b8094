//! The `[hair.style]` scene section: generated hair laid over the scalp — combed, optionally
//! parted, lifted off the scalp and falling under gravity past it — instead of standing straight
//! out along the normals (see [`hair_groom::style`] for how a strand is laid).

use hair_groom::{Part, StyleOptions};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// `[hair.style]`: how generated hair is laid over the scalp. Lengths in m, angles in degrees.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StyleSection {
    /// World direction hair is combed towards (Z up; the built-in head faces −Y, so `[0, 1, 0]`
    /// combs it back).
    pub comb: [f32; 3],
    /// Weight of the comb against gravity: 0 lets hair fall straight down the scalp.
    #[serde(default = "one")]
    pub comb_weight: f32,
    /// Angle at which hair leaves the scalp, from its tangent plane, degrees in (0, 90].
    #[serde(default = "default_lift")]
    pub lift_deg: f32,
    /// Least height of hair above the scalp, m: at least the strand radius plus the scalp
    /// collider's thickness, so the groom starts clear of the collider.
    pub clearance: f32,
    /// Depth of the hair layer above `clearance`, m: strand heights spread over it.
    #[serde(default)]
    pub layer: f32,
    /// Largest curvature of a laid strand, 1/m (1 / the tightest bend radius).
    #[serde(default = "default_curvature")]
    pub max_curvature: f32,
    /// A part: hair on each side of the plane is combed away from it.
    #[serde(default)]
    pub part: Option<PartSection>,
}

/// `[hair.style.part]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartSection {
    /// Normal of the part plane (world; `[1, 0, 0]` parts the built-in head in the middle).
    pub normal: [f32; 3],
    /// A point of the plane, m.
    #[serde(default)]
    pub point: [f32; 3],
    /// How strongly hair is combed away from the part, relative to the comb.
    #[serde(default = "one")]
    pub weight: f32,
}

fn one() -> f32 {
    1.0
}
fn default_lift() -> f32 {
    30.0
}
fn default_curvature() -> f32 {
    30.0
}

impl StyleSection {
    /// The groom options, with gravity `gravity` (m/s², its direction is "down"; straight down −Z
    /// when gravity is zero) and the hair's `seed`.
    pub fn options(&self, gravity: &Vector3<f32>, seed: u64) -> StyleOptions {
        let down = if gravity.norm() > 0.0 {
            *gravity
        } else {
            -Vector3::z()
        };
        StyleOptions {
            comb: Vector3::from(self.comb),
            comb_weight: self.comb_weight,
            part: self.part.map(|p| Part {
                normal: Vector3::from(p.normal),
                point: Vector3::from(p.point),
                weight: p.weight,
            }),
            lift_deg: self.lift_deg,
            clearance: self.clearance,
            layer: self.layer,
            max_curvature: self.max_curvature,
            down,
            seed,
        }
    }
}
