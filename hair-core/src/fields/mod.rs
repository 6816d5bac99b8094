//! Force fields acting on hair (Blender's effectors; seed 001, "Force Fields Influence" and
//! "Effectors Optimization").
//!
//! A [`ForceField`] has a kind, a center and a direction (m, world space), a strength (constant
//! or keyframed over frames, [`Strength`]) and a distance [`Falloff`]. The fields are evaluated
//! **in batch**: once per collision step, over all points at once ([`evaluate`]), field by field
//! over contiguous point arrays, in parallel over fixed chunks of points. The result is an
//! acceleration per point (m/s²) that the solver holds constant over the step's substeps. Each
//! point sums the fields in their order, so the result does not depend on the thread count.
//!
//! Air-moving fields define the **air velocity** (m/s) and push hair through the scene's air
//! drag, `a = air_drag · w`: with the kernel's `−air_drag · v` this is drag towards the moving
//! air, `air_drag · (w − v)`, so hair at rest in a wind of speed `w` feels `air_drag · w` per unit
//! mass and a point moving with the air feels nothing.
//!
//! | kind | strength | acceleration |
//! |---|---|---|
//! | [`FieldKind::Wind`] | air speed along `direction`, m/s | `air_drag · S · (1 + noise · n(x, t)) · direction` |
//! | [`FieldKind::Vortex`] | air speed around the axis (`center`, `direction`), m/s | `air_drag · S · (direction × r̂)` |
//! | [`FieldKind::Turbulence`] | air speed, m/s | `air_drag · S · N(x/size + t·flow)` (3 noise channels) |
//! | [`FieldKind::Drag`] | extra drag rate, 1/s | removes the fraction `1 − exp(−S·T)` of the velocity over a step `T` |
//! | [`FieldKind::Force`] | m/s², along `x − center` (negative attracts) | `S · (x − c)/‖x − c‖` |
//!
//! Every strength is multiplied by the falloff factor at the point.

mod noise;

use hair_par::prelude::*;
use nalgebra::Vector3;
#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::error::{HairError, Result};

pub use noise::{noise, noise3};

/// Points per parallel work item of [`evaluate`].
const CHUNK: usize = 4096;

/// A field's strength over time. With the `serde` feature it reads a number (constant) or a list
/// of `[frame, value]` pairs (keys), as the scene's `strength` key.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(untagged))]
pub enum Strength {
    /// The same at every frame.
    Constant(f32),
    /// `(frame, value)` keys in increasing frame order, linear in between, held outside.
    Keys(Vec<(f32, f32)>),
}

impl Strength {
    /// The strength at (possibly fractional) `frame`.
    pub fn at(&self, frame: f32) -> f32 {
        match self {
            Strength::Constant(s) => *s,
            Strength::Keys(keys) => {
                let Some(&(f0, v0)) = keys.first() else {
                    return 0.0;
                };
                if frame <= f0 {
                    return v0;
                }
                for w in keys.windows(2) {
                    let ((fa, va), (fb, vb)) = (w[0], w[1]);
                    if frame <= fb {
                        return va + (vb - va) * (frame - fa) / (fb - fa);
                    }
                }
                keys[keys.len() - 1].1
            }
        }
    }
}

/// How a field's strength falls off with distance (`"none"`, `"sphere"`, `"tube"` with the
/// `serde` feature).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum FalloffShape {
    /// Full strength everywhere.
    #[default]
    None,
    /// By distance from the field's center.
    Sphere,
    /// By distance from the field's axis (through `center` along `direction`).
    Tube,
}

/// Distance falloff, as Blender's: factor `(1 + d − min_distance)^−power` for
/// `min_distance ≤ d ≤ max_distance`, 1 closer than `min_distance`, 0 beyond `max_distance`.
///
/// With the `serde` feature every key is optional (the default is no falloff) and unknown keys
/// are refused.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields, default))]
pub struct Falloff {
    /// What the distance is measured from.
    pub shape: FalloffShape,
    /// Exponent of the falloff (0 = constant up to `max_distance`).
    pub power: f32,
    /// Distance within which the field has full strength, m.
    pub min_distance: f32,
    /// Distance beyond which the field has no effect, m (`None` = unbounded).
    pub max_distance: Option<f32>,
}

/// What a field does (see the module table).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FieldKind {
    /// Air flowing along `direction`; `noise` (0–1, relative) varies its speed smoothly over
    /// about 1 m and 1 s, seeded.
    Wind {
        /// Relative amplitude of the speed's variation (0 = steady).
        noise: f32,
        /// Seed of the variation.
        seed: u64,
    },
    /// Air turning around the axis through `center` along `direction`.
    Vortex,
    /// Air moving in a smooth seeded noise field.
    Turbulence {
        /// Size of the noise's features, m.
        size: f32,
        /// How fast the pattern drifts through space, in feature sizes per second.
        flow: f32,
        /// Seed of the field.
        seed: u64,
    },
    /// Extra velocity-proportional drag (strength in 1/s).
    Drag,
    /// A point force along `x − center` (strength in m/s²; negative attracts).
    Force,
}

/// One force field.
#[derive(Debug, Clone, PartialEq)]
pub struct ForceField {
    /// Kind and kind-specific parameters.
    pub kind: FieldKind,
    /// Center (m): the vortex axis, the point force, the falloff's origin.
    pub center: Vector3<f32>,
    /// Direction (unit after validation): the wind's flow, the vortex and tube axis.
    pub direction: Vector3<f32>,
    /// Strength over frames (units by kind, see the module table).
    pub strength: Strength,
    /// Distance falloff.
    pub falloff: Falloff,
}

impl ForceField {
    /// A field of `kind` at the origin, pointing along +z, of constant `strength`, no falloff.
    pub fn new(kind: FieldKind, strength: f32) -> Self {
        Self {
            kind,
            center: Vector3::zeros(),
            direction: Vector3::z(),
            strength: Strength::Constant(strength),
            falloff: Falloff::default(),
        }
    }

    /// Checks every parameter is finite and in range; `index` names the field in errors
    /// (`fields[index].parameter`). Normalises the direction.
    pub fn validate(&mut self, index: usize) -> Result<()> {
        let err = |param: &str, value: String, fix: &str| HairError::Parameter {
            name: format!("fields[{index}].{param}"),
            value,
            fix: fix.into(),
        };
        let finite3 = |v: &Vector3<f32>| v.iter().all(|c| c.is_finite());
        if !finite3(&self.center) {
            return Err(err(
                "center",
                format!("{:?}", self.center.as_slice()),
                "give three finite numbers, m",
            ));
        }
        let len = self.direction.norm();
        if !finite3(&self.direction) || len <= 1e-12 {
            return Err(err(
                "direction",
                format!("{:?}", self.direction.as_slice()),
                "give a finite, non-zero vector",
            ));
        }
        self.direction /= len;
        match &self.strength {
            Strength::Constant(s) if !s.is_finite() => {
                return Err(err("strength", s.to_string(), "use a finite number"))
            }
            Strength::Keys(keys) => {
                if keys.is_empty() {
                    return Err(err(
                        "strength",
                        "[]".into(),
                        "give at least one [frame, value] key, or a number",
                    ));
                }
                for (k, &(f, v)) in keys.iter().enumerate() {
                    if !(f.is_finite() && v.is_finite()) {
                        return Err(err(
                            "strength",
                            format!("key {k} = [{f}, {v}]"),
                            "use finite frames and values",
                        ));
                    }
                    if k > 0 && f <= keys[k - 1].0 {
                        return Err(err(
                            "strength",
                            format!("key {k} at frame {f}"),
                            "keys must be in increasing frame order",
                        ));
                    }
                }
            }
            Strength::Constant(_) => {}
        }
        let f = &self.falloff;
        if !(f.power.is_finite() && f.power >= 0.0) {
            return Err(err(
                "falloff.power",
                f.power.to_string(),
                "use a finite number ≥ 0",
            ));
        }
        if !(f.min_distance.is_finite() && f.min_distance >= 0.0) {
            return Err(err(
                "falloff.min_distance",
                f.min_distance.to_string(),
                "use a finite distance ≥ 0 m",
            ));
        }
        if let Some(max) = f.max_distance {
            if !(max.is_finite() && max >= f.min_distance) {
                return Err(err(
                    "falloff.max_distance",
                    max.to_string(),
                    "use a finite distance ≥ min_distance, m",
                ));
            }
        }
        match self.kind {
            FieldKind::Wind { noise, .. } if !(noise.is_finite() && noise >= 0.0) => Err(err(
                "noise",
                noise.to_string(),
                "use a finite number ≥ 0 (relative amplitude)",
            )),
            FieldKind::Turbulence { size, .. } if !(size.is_finite() && size > 0.0) => Err(err(
                "size",
                size.to_string(),
                "use a finite feature size > 0 m",
            )),
            FieldKind::Turbulence { flow, .. } if !flow.is_finite() => {
                Err(err("flow", flow.to_string(), "use a finite number, 1/s"))
            }
            _ => Ok(()),
        }
    }

    /// True for fields that move the air (they act through the air drag).
    pub fn moves_air(&self) -> bool {
        matches!(
            self.kind,
            FieldKind::Wind { .. } | FieldKind::Vortex | FieldKind::Turbulence { .. }
        )
    }

    /// Falloff factor at `x` (0–1).
    fn falloff_at(&self, x: &Vector3<f32>) -> f32 {
        let f = &self.falloff;
        let r = x - self.center;
        let d = match f.shape {
            FalloffShape::None => return 1.0,
            FalloffShape::Sphere => r.norm(),
            FalloffShape::Tube => (r - self.direction * r.dot(&self.direction)).norm(),
        };
        if f.max_distance.is_some_and(|m| d > m) {
            0.0
        } else if d <= f.min_distance || f.power == 0.0 {
            1.0
        } else {
            (1.0 + d - f.min_distance).powf(-f.power)
        }
    }
}

/// Inputs of one batch evaluation.
#[derive(Debug, Clone, Copy)]
pub struct FieldInput<'a> {
    /// Point positions, m.
    pub positions: &'a [Vector3<f32>],
    /// Point velocities, m/s.
    pub velocities: &'a [Vector3<f32>],
    /// Frame (possibly fractional) at which strengths are taken.
    pub frame: f32,
    /// Time in seconds (noise drift).
    pub time: f32,
    /// The scene's air drag, 1/s.
    pub air_drag: f32,
    /// Length of the collision step the accelerations hold for, s.
    pub step_dt: f32,
}

/// Adds the acceleration (m/s²) of every field at every point to `accel` (one per point).
/// Fields must have been validated ([`ForceField::validate`]).
pub fn evaluate(fields: &[ForceField], input: &FieldInput, accel: &mut [Vector3<f32>]) {
    let strengths: Vec<f32> = fields.iter().map(|f| f.strength.at(input.frame)).collect();
    accel
        .par_chunks_mut(CHUNK)
        .enumerate()
        .for_each(|(c, out)| {
            let start = c * CHUNK;
            let x = &input.positions[start..start + out.len()];
            let v = &input.velocities[start..start + out.len()];
            for (field, &s) in fields.iter().zip(&strengths) {
                if s != 0.0 {
                    add_field(field, s, input, x, v, out);
                }
            }
        });
}

/// One field over a chunk of points.
fn add_field(
    f: &ForceField,
    s: f32,
    input: &FieldInput,
    x: &[Vector3<f32>],
    v: &[Vector3<f32>],
    out: &mut [Vector3<f32>],
) {
    let air = input.air_drag * s;
    let plain = f.falloff.shape == FalloffShape::None;
    let fall = |x: &Vector3<f32>| if plain { 1.0 } else { f.falloff_at(x) };
    match f.kind {
        FieldKind::Wind { noise: amp, seed } => {
            let drift = Vector3::new(0.31, 0.47, 0.83) * input.time;
            for (a, x) in out.iter_mut().zip(x) {
                let gust = if amp > 0.0 {
                    1.0 + amp * noise(&(x + drift), seed)
                } else {
                    1.0
                };
                *a += f.direction * (air * gust * fall(x));
            }
        }
        FieldKind::Vortex => {
            for (a, x) in out.iter_mut().zip(x) {
                let r = x - f.center;
                let around = f.direction.cross(&r);
                let len = around.norm();
                if len > 0.0 {
                    *a += around * (air * fall(x) / len);
                }
            }
        }
        FieldKind::Turbulence { size, flow, seed } => {
            let drift = Vector3::new(0.31, 0.47, 0.83) * (flow * input.time);
            let inv = 1.0 / size;
            for (a, x) in out.iter_mut().zip(x) {
                *a += noise3(&(x * inv + drift), seed) * (air * fall(x));
            }
        }
        FieldKind::Drag => {
            let t = input.step_dt;
            for ((a, x), v) in out.iter_mut().zip(x).zip(v) {
                let removed = 1.0 - (-s * fall(x) * t).exp();
                *a -= v * (removed / t);
            }
        }
        FieldKind::Force => {
            for (a, x) in out.iter_mut().zip(x) {
                let r = x - f.center;
                let len = r.norm();
                if len > 0.0 {
                    *a += r * (s * fall(x) / len);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keyframed_strength_is_linear_between_keys_and_held_outside() {
        let s = Strength::Keys(vec![(1.0, 0.0), (11.0, 10.0)]);
        assert_eq!(s.at(0.0), 0.0);
        assert_eq!(s.at(6.0), 5.0);
        assert_eq!(s.at(20.0), 10.0);
    }

    #[test]
    fn sphere_falloff_follows_blenders_formula() {
        let mut f = ForceField::new(FieldKind::Force, 1.0);
        f.falloff = Falloff {
            shape: FalloffShape::Sphere,
            power: 2.0,
            min_distance: 0.5,
            max_distance: Some(3.0),
        };
        assert_eq!(f.falloff_at(&Vector3::new(0.2, 0.0, 0.0)), 1.0);
        assert!((f.falloff_at(&Vector3::new(1.5, 0.0, 0.0)) - 0.25).abs() < 1e-6);
        assert_eq!(f.falloff_at(&Vector3::new(3.5, 0.0, 0.0)), 0.0);
    }

    fn one_point(field: ForceField, x: Vector3<f32>, v: Vector3<f32>) -> Vector3<f32> {
        let mut field = field;
        field.validate(0).unwrap();
        let mut a = [Vector3::zeros()];
        let input = FieldInput {
            positions: &[x],
            velocities: &[v],
            frame: 1.0,
            time: 0.0,
            air_drag: 2.0,
            step_dt: 0.1,
        };
        evaluate(&[field], &input, &mut a);
        a[0]
    }

    #[test]
    fn drag_removes_the_exponential_fraction_of_velocity_per_step() {
        let v = Vector3::new(1.0, -2.0, 0.5);
        let a = one_point(ForceField::new(FieldKind::Drag, 3.0), Vector3::zeros(), v);
        // Held over the step, the acceleration leaves v·exp(−rate·T).
        let after = v + a * 0.1;
        assert!((after - v * (-0.3f32).exp()).norm() < 1e-6);
    }

    #[test]
    fn vortex_turns_air_around_its_axis_at_its_speed() {
        let mut f = ForceField::new(FieldKind::Vortex, 1.5);
        f.center = Vector3::new(1.0, 0.0, 0.0);
        let a = one_point(f, Vector3::new(1.0, 2.0, 5.0), Vector3::zeros());
        // Air at 1.5 m/s along z × (0, 1, 0) = −x, through air drag 2/s.
        assert!((a - Vector3::new(-3.0, 0.0, 0.0)).norm() < 1e-6);
    }

    #[test]
    fn negative_point_force_attracts_with_its_strength() {
        let mut f = ForceField::new(FieldKind::Force, -4.0);
        f.center = Vector3::new(0.0, 0.0, 1.0);
        let a = one_point(f, Vector3::new(3.0, 0.0, 5.0), Vector3::zeros());
        assert!((a - Vector3::new(-0.6, 0.0, -0.8) * 4.0).norm() < 1e-6);
    }

    #[test]
    fn nan_parameter_is_refused_by_name() {
        let mut f = ForceField::new(
            FieldKind::Turbulence {
                size: f32::NAN,
                flow: 0.0,
                seed: 1,
            },
            1.0,
        );
        let e = f.validate(3).unwrap_err().to_string();
        assert!(e.contains("fields[3].size"), "{e}");
    }
}
