//! The **drape** case: a case that needs collision.
//!
//! One physical hair ([`crate::physical`]) 25 cm long, its root held 1 mm above the top of a
//! fixed sphere of radius 5 cm (a `[[colliders]]` sphere, thickness 0, **frictionless**: the
//! rod's contacts are, so every method meets the same contact law), released horizontally under
//! gravity with air drag 10/s, for 2 s. It falls onto the sphere, wraps over it along a
//! meridian and hangs from its side: at the end the hair lies on the sphere from the root to
//! near the equator and hangs straight down below it. (A single hair's bending length
//! `(EI/μg)^{1/3}` is 4.9 cm, so a shorter hair over a smaller sphere stands off it as a bent
//! beam instead of draping.) The truth is the converged rod with the same sphere
//! ([`crate::truth`]).
//!
//! Beside the position and tip errors the case measures **penetration** ([`Ball`]): the
//! deepest point centre inside the analytic sphere at any frame end (as the head case measures
//! the scalp's solid). The chords between nodes resting on the sphere dip into it by their
//! sagitta `l²/8R` less the hair radius (0.5 mm at 16 segments), but a renderer draws a smooth
//! curve through the points, which bulges outwards on a convex surface, so the points are what
//! is measured.
//!
//! At any segment count ([`drape_at`]) the strand is the same straight hair cut into equal
//! segments.

use crate::cases::CaseError;
use nalgebra::Vector3;

use crate::cases::{one_hair, Case, OneHair, Resegment};
use crate::physical::RADIUS;

/// The case's name (the report shows penetration for it).
pub const NAME: &str = "drape";
/// Length of the hair, m.
pub const LENGTH: f64 = 0.25;
/// Radius of the sphere, m (centred at the origin).
pub const SPHERE_RADIUS: f64 = 0.05;
/// Height of the root above the sphere's top, m.
pub const ROOT_GAP: f64 = 0.001;
/// Segments of the case as charted.
pub const SEGMENTS: usize = 16;

/// A fixed sphere, to measure how deep a strand's polyline goes into it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ball {
    /// Centre, m.
    pub centre: Vector3<f32>,
    /// Radius, m.
    pub radius: f32,
}

impl Ball {
    /// Deepest point centre of `positions` inside the sphere, m (0 if none is inside): the
    /// measure of the head case's solid, on an analytic surface.
    pub fn max_depth(&self, positions: &[Vector3<f32>]) -> f32 {
        let c = self.centre.cast::<f64>();
        positions
            .iter()
            .map(|p| self.radius as f64 - (p.cast::<f64>() - c).norm())
            .fold(0.0, f64::max) as f32
    }
}

/// The drape of [`drape`] at its charted segment count.
pub fn drape() -> Result<Case, CaseError> {
    drape_at(SEGMENTS)
}

/// The drape (module docs) with `n` segments.
pub fn drape_at(n: usize) -> Result<Case, CaseError> {
    let top = SPHERE_RADIUS + ROOT_GAP;
    let points: Vec<[f64; 3]> = (0..=n)
        .map(|i| [LENGTH * i as f64 / n as f64, 0.0, top])
        .collect();
    let mut case = one_hair(
        OneHair {
            name: NAME,
            title: "drape: a 25 cm hair in 16 segments, root held 1 mm above a 5 cm sphere, \
                    released horizontally, falls and drapes over it (frictionless), 2 s; truth: \
                    the converged rod with the same sphere",
            air_drag: 10.0,
            radius: Some(RADIUS),
            extra: format!(
                "[[colliders]]\nname = \"ball\"\nshape = {{ kind = \"sphere\", radius = \
                 {SPHERE_RADIUS} }}\nthickness = 0.0\nfriction = 0.0\n"
            ),
        },
        &points,
        Resegment {
            segments: SEGMENTS,
            build: drape_at,
        },
    )?;
    case.ball = Some(Ball {
        centre: Vector3::zeros(),
        radius: SPHERE_RADIUS as f32,
    });
    Ok(case)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ball_depth_is_the_deepest_point_inside() {
        let ball = Ball {
            centre: Vector3::new(0.0, 0.0, 1.0),
            radius: 1.0,
        };
        let p = [
            Vector3::new(0.0, 0.0, 2.5),
            Vector3::new(0.0, 0.0, 1.7),
            Vector3::new(0.0, 0.9, 1.0),
        ];
        assert!((ball.max_depth(&p) - 0.3).abs() < 1e-6);
        assert_eq!(ball.max_depth(&p[..1]), 0.0);
    }
}
