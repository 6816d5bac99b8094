//! The `[hair_hair]` and `[[fields]]` scene sections: voxel hair–hair interaction (seed 001,
//! "Hair-Hair collision"; see `hair_core::volume`) and force fields (Blender's effectors; see
//! `hair_core::fields`).
//!
//! `[hair_hair]` is `hair_core::HairHairSettings` itself, and a field's `strength` and `falloff`
//! are `hair_core::Strength` and `hair_core::Falloff` (their `serde` feature); the `[[fields]]`
//! table around them is this module's [`FieldSection`] (see there why).
//!
//! ```toml
//! [hair_hair]
//! cell_size = 0.01        # m, edge of a grid cell
//! friction = 0.3          # 0–1: velocity moved this far towards the grid velocity per step
//! repulsion = 0.3         # m²/s², push out of cells denser than the target (0 = off)
//! target_density = 0.3    # hair volume fraction (0–1) above which repulsion acts
//!
//! [[fields]]
//! type = "wind"           # "wind", "vortex", "turbulence", "drag" or "force"
//! strength = 2.0          # or keys: [[1, 0.0], [24, 2.0]] as [frame, value]
//! direction = [1, 0, 0]   # wind flow; vortex and tube axis
//! center = [0, 0, 0]      # m: vortex axis, point force, falloff origin
//! noise = 0.3             # wind only: relative variation of the speed
//! seed = 1                # wind noise, turbulence
//! falloff = { shape = "sphere", power = 2, min_distance = 0.1, max_distance = 1.0 }
//! ```
//!
//! Strength units by type: air speed in m/s for wind, vortex and turbulence (they push hair
//! through `[physics] air_drag`), a rate in 1/s for drag, m/s² for a point force (negative
//! attracts). Turbulence also takes `size` (m, feature size) and `flow` (feature sizes per
//! second the pattern drifts).

use hair_core::{Falloff, FieldKind, ForceField, HairError, MassSpringSolver, Strength};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::build::Simulation;

/// Field types of `[[fields]] type`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FieldType {
    /// Air flowing along `direction` (strength: air speed, m/s).
    Wind,
    /// Air turning around the axis (strength: air speed, m/s).
    Vortex,
    /// Air in a smooth seeded noise field (strength: air speed, m/s).
    Turbulence,
    /// Extra drag (strength: rate, 1/s).
    Drag,
    /// Point force from `center` (strength: m/s², negative attracts).
    Force,
}

/// `[[fields]]`: one force field.
///
/// Not `hair_core::ForceField` itself, on purpose: the file spells a field flat (`type = "wind"`
/// beside `noise`, `seed`, `size`, `flow`) where the library nests the per-type values in
/// [`FieldKind`] variants, and the section refuses a key that does not apply to its type
/// (`noise` on a vortex) by name. `strength` and `falloff` are the library's own
/// [`Strength`] and [`Falloff`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FieldSection {
    /// Name shown in errors (optional).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub name: String,
    /// What the field does.
    #[serde(rename = "type")]
    pub kind: FieldType,
    /// Strength (units by type, see the module doc): a number, or `[[frame, value], …]` keys.
    pub strength: Strength,
    /// Center, m.
    #[serde(default)]
    pub center: [f32; 3],
    /// Direction (wind flow, vortex and tube axis); normalised.
    #[serde(default = "up")]
    pub direction: [f32; 3],
    /// Wind only: relative amplitude of the speed's variation.
    #[serde(default)]
    pub noise: Option<f32>,
    /// Seed of the wind's noise or of the turbulence.
    #[serde(default)]
    pub seed: u64,
    /// Turbulence only: feature size, m.
    #[serde(default)]
    pub size: Option<f32>,
    /// Turbulence only: drift of the pattern, feature sizes per second.
    #[serde(default)]
    pub flow: Option<f32>,
    /// Distance falloff (absent: none): `{ shape, power, min_distance, max_distance }`.
    #[serde(default)]
    pub falloff: Option<Falloff>,
}

fn up() -> [f32; 3] {
    [0.0, 0.0, 1.0]
}

impl FieldSection {
    /// The library field, validated; errors name `[[fields]] #index`, the key and the fix.
    pub fn field(&self, index: usize) -> Result<ForceField, FieldError> {
        let only = |key: &'static str, kind: &'static str| {
            Err(FieldError::OtherType {
                index,
                name: self.name.clone(),
                key,
                kind,
            })
        };
        if self.noise.is_some() && self.kind != FieldType::Wind {
            return only("noise", "wind");
        }
        if self.kind != FieldType::Turbulence {
            if self.size.is_some() {
                return only("size", "turbulence");
            }
            if self.flow.is_some() {
                return only("flow", "turbulence");
            }
        }
        let kind = match self.kind {
            FieldType::Wind => FieldKind::Wind {
                noise: self.noise.unwrap_or(0.0),
                seed: self.seed,
            },
            FieldType::Vortex => FieldKind::Vortex,
            FieldType::Turbulence => FieldKind::Turbulence {
                size: self.size.ok_or_else(|| FieldError::TurbulenceSize {
                    index,
                    name: self.name.clone(),
                })?,
                flow: self.flow.unwrap_or(0.0),
                seed: self.seed,
            },
            FieldType::Drag => FieldKind::Drag,
            FieldType::Force => FieldKind::Force,
        };
        let mut field = ForceField {
            kind,
            center: Vector3::from(self.center),
            direction: Vector3::from(self.direction),
            strength: self.strength.clone(),
            falloff: self.falloff.unwrap_or_default(),
        };
        field
            .validate(index)
            .map_err(|source| FieldError::Invalid {
                index,
                name: self.name.clone(),
                source,
            })?;
        Ok(field)
    }
}

/// Why a `[[fields]]` table is refused. Displays as `[[fields]] #i (name): what and the fix`.
#[derive(Debug, thiserror::Error)]
pub enum FieldError {
    /// A key that applies to another field type only.
    #[error("{}: `{key}` applies to type = \"{kind}\" only; remove it", label(*.index, .name))]
    OtherType {
        /// The field's index in `[[fields]]`.
        index: usize,
        /// Its `name` (may be empty).
        name: String,
        /// The key given.
        key: &'static str,
        /// The field type it applies to.
        kind: &'static str,
    },
    /// A turbulence field without `size`.
    #[error(
        "{}: turbulence needs `size`, its feature size in m (e.g. 0.1)",
        label(*.index, .name)
    )]
    TurbulenceSize {
        /// The field's index in `[[fields]]`.
        index: usize,
        /// Its `name` (may be empty).
        name: String,
    },
    /// A value of the field is out of range (the solver's check, in the scene's keys).
    #[error("{}: {}", label(*.index, .name), field_message(.source))]
    Invalid {
        /// The field's index in `[[fields]]`.
        index: usize,
        /// Its `name` (may be empty).
        name: String,
        /// The solver's error: the parameter, its value and the fix.
        source: HairError,
    },
}

/// `[[fields]] #i` or `[[fields]] #i (name)`.
fn label(index: usize, name: &str) -> String {
    if name.is_empty() {
        format!("[[fields]] #{index}")
    } else {
        format!("[[fields]] #{index} ({name})")
    }
}

/// A field's parameter error in the scene's words: `key = value: fix`.
fn field_message(e: &HairError) -> String {
    match e {
        HairError::Parameter { name, value, fix } => {
            let key = name.split_once('.').map_or(name.as_str(), |(_, k)| k);
            format!("{key} = {value}: {fix}")
        }
        other => other.to_string(),
    }
}

impl Simulation {
    /// `solver` with the scene's hair–hair interaction and force fields switched on.
    pub fn with_interactions(
        &self,
        mut solver: MassSpringSolver,
    ) -> Result<MassSpringSolver, HairError> {
        if let Some(h) = self.hair_hair {
            solver = solver.with_hair_hair(h, &self.strands)?;
        }
        if !self.fields.is_empty() {
            solver = solver.with_fields(self.fields.clone())?;
        }
        Ok(solver)
    }
}

#[cfg(test)]
mod tests {
    use crate::scene::{SceneFile, DEFAULT_SCENE};
    use hair_core::{Falloff, FalloffShape, HairHairSettings, Strength};
    use std::path::PathBuf;

    /// The default scene without its own `[hair_hair]`, then `extra`.
    fn parse(extra: &str) -> Result<SceneFile, String> {
        let start = DEFAULT_SCENE
            .find("\n[hair_hair]")
            .expect("the default has hair–hair");
        let end = start + 1 + DEFAULT_SCENE[start + 1..].find("\n\n").unwrap();
        let text = format!(
            "{}{}\n{extra}",
            &DEFAULT_SCENE[..start],
            &DEFAULT_SCENE[end..]
        );
        SceneFile::parse(&text, "f.toml", PathBuf::from(".")).map_err(|e| e.to_string())
    }

    #[test]
    fn hair_hair_and_field_keys_read_into_the_library_types() {
        let s = parse(
            "[hair_hair]\ncell_size = 0.02\nfriction = 0.3\n\n[[fields]]\ntype = \"wind\"\n\
             strength = [[1, 0.0], [24, 2.0]]\nfalloff = { shape = \"tube\", power = 2, \
             max_distance = 1.0 }\n",
        )
        .unwrap()
        .scene;
        assert_eq!(
            s.hair_hair,
            Some(HairHairSettings {
                cell_size: 0.02,
                friction: 0.3,
                ..HairHairSettings::default()
            })
        );
        let f = &s.fields[0];
        assert_eq!(f.strength, Strength::Keys(vec![(1.0, 0.0), (24.0, 2.0)]));
        assert_eq!(
            f.falloff,
            Some(Falloff {
                shape: FalloffShape::Tube,
                power: 2.0,
                min_distance: 0.0,
                max_distance: Some(1.0),
            })
        );
    }

    #[test]
    fn unknown_keys_in_library_types_are_refused_naming_the_file_and_the_key() {
        let e = parse("[hair_hair]\ncell_sise = 0.02\n").unwrap_err();
        assert!(
            e.starts_with("f.toml: ") && e.contains("unknown field `cell_sise`"),
            "{e}"
        );
        let e = parse("[[fields]]\ntype = \"drag\"\nstrength = 1.0\nfalloff = { reach = 2 }\n")
            .unwrap_err();
        assert!(e.contains("unknown field `reach`"), "{e}");
        let e = parse("[hair_hair]\nfriction = 2.0\n")
            .unwrap()
            .build()
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("[hair_hair] parameter `hair_hair.friction` = 2"),
            "{e}"
        );
    }
}
