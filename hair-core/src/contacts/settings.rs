//! Settings of hair–object collision: how finely fast colliders are stepped and the speed at which
//! deep penetrations are removed.

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::error::{check_positive, HairError, Result};

/// How contacts are stepped (scene section `[contacts]`).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields, default))]
pub struct ContactSettings {
    /// Largest error (m) the contact model may make within one collision step because its
    /// collider moved; a frame whose colliders move farther than that allows is split into more
    /// steps (see [`super::collider_set`]). `None` (the default): half the smallest hair radius,
    /// at least 0.1 mm — the gap the response keeps is the hair radius, so a point centre stays
    /// outside the collider.
    pub tolerance: Option<f32>,
    /// Most collision steps a frame may be split into, in all (≥ 1). A frame that would need
    /// more runs with this many, and its contacts are then less accurate than `tolerance`.
    pub max_steps: u32,
    /// Largest speed (m/s) at which a point found inside a collider at detection is moved out
    /// (> 0). A point found inside by `d` is moved out by at most `max_push_speed·dt` of it per
    /// substep, as a position correction that leaves no velocity behind: penetrations of a few
    /// millimetres (a missed detection, the strain limiter) go within a substep or two, while
    /// hair found deep inside (it started there, the collider was teleported) is eased out over
    /// a few frames instead of being torn apart and flung. Penetration the step itself makes
    /// after detection (a large implicit substep overshooting into the surface) is removed at
    /// once.
    pub max_push_speed: f32,
}

impl Default for ContactSettings {
    fn default() -> Self {
        Self {
            tolerance: None,
            max_steps: 64,
            max_push_speed: 1.0,
        }
    }
}

impl ContactSettings {
    /// Checks `tolerance` (if given) and `max_push_speed` are finite and > 0 and `max_steps` ≥ 1.
    pub fn validate(&self) -> Result<()> {
        if let Some(t) = self.tolerance {
            check_positive("tolerance", t)?;
        }
        check_positive("max_push_speed", self.max_push_speed)?;
        if self.max_steps == 0 {
            return Err(HairError::Parameter {
                name: "max_steps".into(),
                value: "0".into(),
                fix: "use at least 1 collision step per frame".into(),
            });
        }
        Ok(())
    }
}
