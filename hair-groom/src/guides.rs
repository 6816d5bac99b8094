//! Generated guide hairs: roots at seeded area-weighted points of a scalp region, each guide
//! growing along its surface normal or combed towards a world direction, straight or curled.
//!
//! Shapes are built in the root frame (local +z = the surface normal). A combed guide leaves the
//! scalp at `angle_deg` from the normal, towards the comb direction projected onto the tangent
//! plane (a comb direction along the normal leaves it on the normal). A curl winds the guide as
//! a helix of `radius` around that axis, `turns_per_meter` turns per meter along the axis, starting
//! at the root; the axis is shortened so the length along the hair stays `length`. Points are
//! equally spaced along the hair, so every segment has the same rest length.

use std::f32::consts::TAU;

use hair_core::mesh::any_perpendicular;
use hair_core::TriMesh;
use nalgebra::Vector3;

use crate::error::{parameter, GroomError};
use crate::sampling::{sample_area_weighted, Region};
use crate::snap::Guide;

/// Which way guides grow from the scalp.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GrowDirection {
    /// Along the surface normal.
    Normal,
    /// Tilted from the normal by `angle_deg` towards `direction`.
    Combed {
        /// World direction to comb towards (any non-zero length; Z up).
        direction: Vector3<f32>,
        /// Angle between the hair and the surface normal, degrees in [0, 90].
        angle_deg: f32,
    },
}

/// A helical curl.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Curl {
    /// Helix radius, m; finite and ≥ 0.
    pub radius: f32,
    /// Turns per meter along the helix axis; finite and ≥ 0.
    pub turns_per_meter: f32,
}

/// What guides to grow. The field names are the proposed scene-file keys under `[guides]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GuideOptions {
    /// Number of guides, ≥ 1.
    pub count: usize,
    /// Length along each guide, m; finite and > 0.
    pub length: f32,
    /// Equal segments per guide (points = segments + 1), ≥ 1.
    pub segments: u32,
    /// Seed of the root positions.
    pub seed: u64,
    /// The part of the mesh that grows guides.
    pub region: Region,
    /// Which way they grow.
    pub direction: GrowDirection,
    /// A curl, if any.
    pub curl: Option<Curl>,
}

impl GuideOptions {
    /// Checks every option's range, naming the first one at fault.
    fn validate(&self) -> Result<(), GroomError> {
        if self.count < 1 {
            return Err(parameter(
                "count",
                self.count,
                "must be ≥ 1 (number of guides)",
            ));
        }
        if !(self.length.is_finite() && self.length > 0.0) {
            return Err(parameter(
                "length",
                self.length,
                "must be a finite length > 0 m",
            ));
        }
        if self.segments < 1 {
            return Err(parameter(
                "segments",
                self.segments,
                "must be ≥ 1 (segments per guide)",
            ));
        }
        if let GrowDirection::Combed {
            direction,
            angle_deg,
        } = self.direction
        {
            let n = direction.norm();
            if !(n.is_finite() && n > 0.0) {
                return Err(parameter(
                    "comb_direction",
                    format!("({}, {}, {})", direction.x, direction.y, direction.z),
                    "must be a finite, non-zero vector (world space, Z up)",
                ));
            }
            if !(0.0..=90.0).contains(&angle_deg) {
                return Err(parameter(
                    "comb_angle_deg",
                    angle_deg,
                    "must lie in [0, 90] degrees from the surface normal",
                ));
            }
        }
        if let Some(curl) = self.curl {
            if !(curl.radius.is_finite() && curl.radius >= 0.0) {
                return Err(parameter(
                    "curl_radius",
                    curl.radius,
                    "must be a finite radius ≥ 0 m",
                ));
            }
            if !(curl.turns_per_meter.is_finite() && curl.turns_per_meter >= 0.0) {
                return Err(parameter(
                    "curl_turns_per_meter",
                    curl.turns_per_meter,
                    "must be a finite number ≥ 0 (turns per meter along the hair's axis)",
                ));
            }
        }
        Ok(())
    }
}

/// Grows `opts.count` guides on `mesh` (see the module docs). The same options give the same
/// guides; the roots are those of [`sample_area_weighted`] with `opts.seed` and `opts.region`.
pub fn generate_guides(mesh: &TriMesh, opts: &GuideOptions) -> Result<Vec<Guide>, GroomError> {
    opts.validate()?;
    let roots = sample_area_weighted(mesh, opts.count, opts.seed, &opts.region)?;
    Ok(roots
        .into_iter()
        .map(|root| {
            let frame = mesh.evaluate(&root);
            let axis = match opts.direction {
                GrowDirection::Normal => Vector3::z(),
                GrowDirection::Combed {
                    direction,
                    angle_deg,
                } => {
                    let local = frame.rotation.inverse() * direction.normalize();
                    let tangent = Vector3::new(local.x, local.y, 0.0);
                    let n = tangent.norm();
                    if n < 1e-6 {
                        Vector3::z()
                    } else {
                        let a = angle_deg.to_radians();
                        Vector3::z() * a.cos() + tangent / n * a.sin()
                    }
                }
            };
            Guide {
                root,
                rest: shape(&axis, opts.length, opts.segments, opts.curl),
            }
        })
        .collect())
}

/// Points of a hair of `length` (m) along the unit `axis`, in `segments` equal segments, curled
/// by `curl`.
fn shape(axis: &Vector3<f32>, length: f32, segments: u32, curl: Option<Curl>) -> Vec<Vector3<f32>> {
    let (r, f) = curl.map_or((0.0, 0.0), |c| (c.radius, c.turns_per_meter));
    // A helix rises `1/sqrt(1 + (2π f r)²)` m along its axis per meter along the hair.
    let rise = 1.0 / (1.0 + (TAU * f * r).powi(2)).sqrt();
    let u = any_perpendicular(axis);
    let v = axis.cross(&u);
    (0..=segments)
        .map(|i| {
            let s = length * rise * i as f32 / segments as f32;
            let phase = TAU * f * s;
            axis * s + (u * (phase.cos() - 1.0) + v * phase.sin()) * r
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::uv_sphere;

    fn options() -> GuideOptions {
        GuideOptions {
            count: 30,
            length: 0.2,
            segments: 16,
            seed: 3,
            region: Region::All,
            direction: GrowDirection::Normal,
            curl: None,
        }
    }

    fn segment_lengths(rest: &[Vector3<f32>]) -> Vec<f32> {
        rest.windows(2).map(|w| (w[1] - w[0]).norm()).collect()
    }

    #[test]
    fn normal_combed_and_curled_guides() {
        let mesh = uv_sphere(0.1, 24, 12).unwrap();
        let straight = generate_guides(&mesh, &options()).unwrap();
        assert_eq!(straight.len(), 30);
        assert!((straight[0].rest[16] - Vector3::new(0.0, 0.0, 0.2)).norm() < 1e-6);

        let combed = GuideOptions {
            direction: GrowDirection::Combed {
                direction: -Vector3::z(),
                angle_deg: 60.0,
            },
            ..options()
        };
        for g in generate_guides(&mesh, &combed).unwrap() {
            let d = (g.rest[1] - g.rest[0]).normalize();
            // 60° from the normal; in world space, heading down unless the root is at a pole.
            assert!((d.z - 0.5).abs() < 1e-5, "{d:?}");
            let frame = mesh.evaluate(&g.root);
            let world = frame.rotation * d;
            let normal = frame.rotation * Vector3::z();
            assert!(
                world.z <= normal.z * 0.5 + 1e-5,
                "{world:?} vs normal {normal:?}"
            );
        }

        let curled = GuideOptions {
            curl: Some(Curl {
                radius: 0.01,
                turns_per_meter: 20.0,
            }),
            ..options()
        };
        let g = &generate_guides(&mesh, &curled).unwrap()[0];
        let lengths = segment_lengths(&g.rest);
        let total: f32 = lengths.iter().sum();
        assert!(
            lengths.iter().all(|l| (l - lengths[0]).abs() < 1e-6),
            "{lengths:?}"
        );
        // Equal chords of a helix are a bit shorter than its arcs.
        assert!(total < 0.2 && total > 0.19, "{total}");
        let off_axis = g.rest.iter().map(|p| p.xy().norm()).fold(0.0f32, f32::max);
        assert!(off_axis > 0.015 && off_axis <= 0.02 + 1e-6, "{off_axis}");
        assert_eq!(generate_guides(&mesh, &curled).unwrap()[0], *g);
    }

    #[test]
    fn bad_options_are_named() {
        let mesh = uv_sphere(0.1, 8, 4).unwrap();
        type Spoil = fn(&mut GuideOptions);
        let cases: [(&str, Spoil); 7] = [
            ("count", |o| o.count = 0),
            ("length", |o| o.length = -1.0),
            ("segments", |o| o.segments = 0),
            ("comb_direction", |o| {
                o.direction = GrowDirection::Combed {
                    direction: Vector3::zeros(),
                    angle_deg: 10.0,
                }
            }),
            ("comb_angle_deg", |o| {
                o.direction = GrowDirection::Combed {
                    direction: Vector3::x(),
                    angle_deg: 100.0,
                }
            }),
            ("curl_radius", |o| {
                o.curl = Some(Curl {
                    radius: f32::NAN,
                    turns_per_meter: 1.0,
                })
            }),
            ("curl_turns_per_meter", |o| {
                o.curl = Some(Curl {
                    radius: 0.01,
                    turns_per_meter: -1.0,
                })
            }),
        ];
        for (name, spoil) in cases {
            let mut opts = options();
            spoil(&mut opts);
            let err = generate_guides(&mesh, &opts).unwrap_err().to_string();
            assert!(err.contains(&format!("`{name}`")), "{name}: {err}");
        }
    }
}
