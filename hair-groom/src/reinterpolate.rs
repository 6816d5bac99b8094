//! Animated guides (seed 001, "Hair Levels": *animated* guide hairs define the rest positions):
//! simulation hairs re-interpolated from new guide shapes every frame with the weights
//! [`crate::interpolate()`] chose once.
//!
//! **Why the weights stay fixed.** Choosing a hair's guides and weights needs root distances
//! (along the surface: a Dijkstra run per guide) and a nearest-guide search, O(hairs · guides).
//! Neither changes when guides move: roots stay where they grow. [`GuideBlend`] keeps, per
//! simulation hair, its sources (guide, weight) and for each the rotation that carries the
//! guide's root-local shape into the hair's root frame (the guide frame, the smallest turn of
//! its normal onto the hair's, the hair frame inverted: the same transport as `interpolate`).
//! Re-interpolating is then one rotation and one multiply–add per source per point, plus the
//! length correction, O(points · k) per frame (counted by [`GuideBlend::apply`]).
//!
//! **Same rule as the build.** Each guide is resampled to the hair's point count by point index;
//! a hair rooted exactly at a guide copies it; otherwise the weighted blend is scaled about the
//! root so its length is the weighted mean of the guides' lengths. So guides at their groom
//! shape give back the interpolated rest shapes (to f32 rounding; the build rotates in two steps
//! where this rotates in one).

use hair_core::TriMesh;
use hair_par::prelude::*;
use nalgebra::{UnitQuaternion, Vector3};
use thiserror::Error;

use crate::error::{parameter, GroomError};
use crate::groom::polyline_length;
use crate::interpolate::{resample, SimHair};
use crate::snap::Guide;
use crate::trim::trim_polyline;

/// One guide's share in a hair, with its transport into the hair's root frame.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Source {
    guide: u32,
    weight: f64,
    /// Guide root-local → hair root-local rotation.
    turn: UnitQuaternion<f32>,
}

/// One simulation hair's recipe.
#[derive(Debug, Clone, PartialEq)]
struct Recipe {
    /// Sources with weight > 0.
    sources: Vec<Source>,
    /// A hair rooted at a guide's own sample: its shape is that guide's, resampled, untouched.
    exact_copy: bool,
}

/// Fixed interpolation weights of simulation hairs over their guides, to re-interpolate rest
/// shapes from animated guides (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct GuideBlend {
    recipes: Vec<Recipe>,
    /// Point count of each guide (an animated pose must keep it).
    guide_points: Vec<usize>,
    /// Points per simulation hair.
    points: usize,
    /// Per hair: the fraction (0, 1] of its blended length it is trimmed to (`None`: untrimmed).
    fractions: Option<Vec<f32>>,
}

impl GuideBlend {
    /// The recipe of every hair of `hairs` (from [`crate::interpolate()`] over `guides` on
    /// `mesh`, with `points` points per hair).
    ///
    /// Errors: a hair whose point count is not `points`, a source naming no guide, a root or
    /// guide sample not on `mesh`.
    pub fn new(
        mesh: &TriMesh,
        guides: &[Guide],
        hairs: &[SimHair],
        points: usize,
    ) -> Result<Self, GroomError> {
        let mut frames = Vec::with_capacity(guides.len());
        for guide in guides {
            guide.root.validate(mesh)?;
            frames.push(mesh.evaluate(&guide.root));
        }
        let mut recipes = Vec::with_capacity(hairs.len());
        for (h, hair) in hairs.iter().enumerate() {
            if hair.rest.len() != points {
                return Err(parameter(
                    "points",
                    hair.rest.len(),
                    &format!("sim hair {h} must have {points} points like the others"),
                ));
            }
            hair.root.validate(mesh)?;
            let frame = mesh.evaluate(&hair.root);
            let normal = frame.rotation * Vector3::z();
            let inv = frame.rotation.inverse();
            let mut sources = Vec::with_capacity(hair.sources.len());
            for s in hair.sources.iter().filter(|s| s.weight > 0.0) {
                let Some(gf) = frames.get(s.guide) else {
                    return Err(parameter(
                        "sources",
                        s.guide,
                        &format!("sim hair {h} names a guide beyond the {}", guides.len()),
                    ));
                };
                let g_normal = gf.rotation * Vector3::z();
                let to_normal = UnitQuaternion::rotation_between(&g_normal, &normal)
                    .unwrap_or_else(UnitQuaternion::identity);
                sources.push(Source {
                    guide: s.guide as u32,
                    weight: f64::from(s.weight),
                    turn: inv * to_normal * gf.rotation,
                });
            }
            let exact_copy =
                sources.len() == 1 && guides[sources[0].guide as usize].root == hair.root;
            recipes.push(Recipe {
                sources,
                exact_copy,
            });
        }
        Ok(Self {
            recipes,
            guide_points: guides.iter().map(|g| g.rest.len()).collect(),
            points,
            fractions: None,
        })
    }

    /// The same blend with every hair trimmed to its painted fraction of its length (one per
    /// hair, each in (0, 1]; see the module docs). Errors: a count that is not the hairs', a
    /// fraction outside (0, 1] (naming the hair).
    pub fn with_length_fractions(mut self, fractions: Vec<f32>) -> Result<Self, GroomError> {
        if fractions.len() != self.recipes.len() {
            return Err(parameter(
                "fractions",
                fractions.len(),
                &format!(
                    "give one length fraction per sim hair ({})",
                    self.recipes.len()
                ),
            ));
        }
        if let Err((h, f)) = crate::trim::check_length_fractions(&fractions) {
            return Err(parameter(
                "fractions",
                f,
                &format!("sim hair {h}'s length fraction must be in (0, 1]"),
            ));
        }
        self.fractions = Some(fractions);
        Ok(self)
    }

    /// Per hair: the fraction of its length it is trimmed to (`None`: untrimmed).
    pub fn length_fractions(&self) -> Option<&[f32]> {
        self.fractions.as_deref()
    }

    /// Number of simulation hairs.
    pub fn hairs(&self) -> usize {
        self.recipes.len()
    }

    /// Points per simulation hair.
    pub fn points(&self) -> usize {
        self.points
    }

    /// Point count of each guide, in guide order: an animated pose must give each guide exactly
    /// this many points.
    pub fn guide_points(&self) -> &[usize] {
        &self.guide_points
    }

    /// Checks that `shapes` gives one root-local shape per guide with the guide's point count.
    /// `what` names the pose in the message (a file, a scene key).
    pub fn check_pose(&self, shapes: &[Vec<Vector3<f32>>], what: &str) -> Result<(), PoseError> {
        if shapes.len() != self.guide_points.len() {
            return Err(PoseError::GuideCount {
                pose: what.to_string(),
                found: shapes.len(),
                expected: self.guide_points.len(),
            });
        }
        for (guide, (shape, &n)) in shapes.iter().zip(&self.guide_points).enumerate() {
            if shape.len() != n {
                return Err(PoseError::PointCount {
                    pose: what.to_string(),
                    guide,
                    found: shape.len(),
                    expected: n,
                });
            }
            if let Some(point) = shape.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
                return Err(PoseError::NonFinite {
                    pose: what.to_string(),
                    guide,
                    point,
                });
            }
        }
        Ok(())
    }

    /// Re-interpolates every hair from the guide shapes `shapes` (root-local, one per guide,
    /// checked by [`GuideBlend::check_pose`]) into `out` (`hairs · points` root-local points,
    /// hair after hair), each trimmed to its painted fraction when the blend has them
    /// ([`GuideBlend::with_length_fractions`]). Returns the work done: the number of
    /// source-point blends (hair points times sources, plus the guides' resampled points, plus
    /// the points of every trimmed hair), which is linear in the points.
    ///
    /// # Panics
    /// If `out` does not hold `hairs · points` points or `shapes` was not checked.
    pub fn apply(&self, shapes: &[Vec<Vector3<f32>>], out: &mut [Vector3<f32>]) -> u64 {
        assert_eq!(out.len(), self.recipes.len() * self.points, "output size");
        let n = self.points;
        let mut work = 0u64;
        // Each guide resampled once to the hairs' point count, with its length.
        let resampled: Vec<(Vec<Vector3<f32>>, f64)> = shapes
            .iter()
            .map(|s| {
                let r = resample(s, n);
                let len = polyline_length(&r);
                (r, len)
            })
            .collect();
        work += (shapes.len() * n) as u64;
        // Hairs are independent: blended in parallel, each with its own scratch (the same bits
        // whatever the thread count).
        let fractions = self.fractions.as_deref();
        let scratch = || {
            let trimmed = if fractions.is_some() { n } else { 0 };
            (
                vec![Vector3::<f64>::zeros(); n],
                vec![Vector3::zeros(); trimmed],
            )
        };
        work += self
            .recipes
            .par_iter()
            .zip(out.par_chunks_exact_mut(n))
            .enumerate()
            .map_init(scratch, |(acc, untrimmed), (h, (recipe, hair))| {
                let mut work = blend_one(recipe, &resampled, acc, hair);
                if let Some(f) = fractions.map(|f| f[h]).filter(|&f| f < 1.0) {
                    untrimmed.copy_from_slice(hair);
                    trim_polyline(untrimmed, f, hair);
                    work += n as u64;
                }
                work
            })
            .sum::<u64>();
        work
    }
}

/// Blends one hair from the `resampled` guides (shape and length) into `hair` by `recipe`
/// (`acc`: scratch of the hair's point count); returns the source-point blends done.
fn blend_one(
    recipe: &Recipe,
    resampled: &[(Vec<Vector3<f32>>, f64)],
    acc: &mut [Vector3<f64>],
    hair: &mut [Vector3<f32>],
) -> u64 {
    let n = hair.len() as u64;
    let first = recipe.sources[0];
    let (shape, _) = &resampled[first.guide as usize];
    if recipe.exact_copy {
        hair.copy_from_slice(shape);
        return n;
    }
    if recipe.sources.len() == 1 {
        for (o, p) in hair.iter_mut().zip(shape) {
            *o = first.turn * p;
        }
        return n;
    }
    acc.iter_mut().for_each(|a| *a = Vector3::zeros());
    let mut target = 0.0f64;
    for s in &recipe.sources {
        let (shape, len) = &resampled[s.guide as usize];
        for (a, p) in acc.iter_mut().zip(shape) {
            *a += (s.turn * p).cast::<f64>() * s.weight;
        }
        target += s.weight * len;
    }
    for (o, a) in hair.iter_mut().zip(acc.iter()) {
        *o = a.cast::<f32>();
    }
    let length = polyline_length(hair);
    let scale = if length > 0.0 {
        (target / length) as f32
    } else {
        1.0
    };
    hair.iter_mut().for_each(|p| *p *= scale);
    n * recipe.sources.len() as u64
}

/// Why an animated pose does not fit a [`GuideBlend`]; `pose` names the pose (a file, a scene
/// key) as the caller gave it.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum PoseError {
    /// The pose has not one shape per guide.
    #[error(
        "{pose} has {found} guides, but the groom has {expected}: a pose must give every guide, \
         in the groom's order"
    )]
    GuideCount {
        /// The pose.
        pose: String,
        /// Number of guide shapes it gives.
        found: usize,
        /// Number of guides of the groom.
        expected: usize,
    },
    /// A guide's shape has another point count than the groom's guide.
    #[error(
        "{pose}: guide {guide} has {found} points, but the groom's guide {guide} has {expected}: \
         an animated guide keeps its point count (resample the pose to the groom's)"
    )]
    PointCount {
        /// The pose.
        pose: String,
        /// The guide.
        guide: usize,
        /// Number of points its shape gives.
        found: usize,
        /// Number of points of the groom's guide.
        expected: usize,
    },
    /// A guide's point is not finite.
    #[error("{pose}: guide {guide} point {point} has a non-finite coordinate")]
    NonFinite {
        /// The pose.
        pose: String,
        /// The guide.
        guide: usize,
        /// The first bad point.
        point: usize,
    },
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interpolate::{interpolate, Distance, InterpolateOptions};
    use crate::sampling::{sample_area_weighted, Region};
    use crate::shapes::uv_sphere;

    fn setup(hairs: usize) -> (TriMesh, Vec<Guide>, Vec<SimHair>) {
        let mesh = uv_sphere(0.1, 24, 12).unwrap();
        let roots = sample_area_weighted(&mesh, 30, 7, &Region::All).unwrap();
        let guides: Vec<Guide> = roots
            .into_iter()
            .enumerate()
            .map(|(g, root)| Guide {
                root,
                rest: (0..8)
                    .map(|i| {
                        let s = i as f32 / 7.0;
                        Vector3::new(
                            0.01 * (g % 4) as f32 * s * s,
                            0.0,
                            (0.05 + 0.001 * g as f32) * s,
                        )
                    })
                    .collect(),
            })
            .collect();
        let mut hair_roots = sample_area_weighted(&mesh, hairs, 11, &Region::All).unwrap();
        hair_roots[0] = guides[3].root; // one exact copy
        let opts = InterpolateOptions {
            k: 4,
            points: 8,
            distance: Distance::Euclidean,
        };
        let enabled = vec![true; guides.len()];
        let sim = interpolate(&mesh, &guides, &enabled, &hair_roots, &opts).unwrap();
        (mesh, guides, sim)
    }

    #[test]
    fn groom_pose_gives_back_the_interpolated_rest_shapes() {
        let (mesh, guides, hairs) = setup(200);
        let blend = GuideBlend::new(&mesh, &guides, &hairs, 8).unwrap();
        let shapes: Vec<_> = guides.iter().map(|g| g.rest.clone()).collect();
        let mut out = vec![Vector3::zeros(); 200 * 8];
        blend.apply(&shapes, &mut out);
        for (h, hair) in hairs.iter().enumerate() {
            for (a, b) in hair.rest.iter().zip(&out[h * 8..(h + 1) * 8]) {
                assert!((a - b).norm() < 1e-6, "hair {h}: {a:?} vs {b:?}");
            }
        }
        // The exact copy is bit-exact.
        assert_eq!(&out[..8], &hairs[0].rest[..]);
    }

    #[test]
    fn a_rotated_pose_rotates_every_hair_that_follows_only_it() {
        let (mesh, guides, hairs) = setup(50);
        let blend = GuideBlend::new(&mesh, &guides, &hairs, 8).unwrap();
        let turn = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.7);
        let shapes: Vec<_> = guides
            .iter()
            .map(|g| g.rest.iter().map(|p| turn * p).collect())
            .collect();
        let mut out = vec![Vector3::zeros(); 50 * 8];
        blend.apply(&shapes, &mut out);
        // Hair 0 copies guide 3: it is guide 3's posed shape.
        assert_eq!(&out[..8], &shapes[3][..]);
        // Lengths are the weighted guide lengths, unchanged by a rigid turn of every guide.
        for (h, hair) in hairs.iter().enumerate() {
            let a = polyline_length(&hair.rest);
            let b = polyline_length(&out[h * 8..(h + 1) * 8]);
            assert!((a - b).abs() < 1e-5 * a, "hair {h}: {a} vs {b}");
        }
    }

    #[test]
    fn work_is_linear_in_hairs_and_independent_of_the_guide_count() {
        let (mesh, guides, hairs) = setup(400);
        let small = GuideBlend::new(&mesh, &guides, &hairs[..100], 8).unwrap();
        let large = GuideBlend::new(&mesh, &guides, &hairs, 8).unwrap();
        let shapes: Vec<_> = guides.iter().map(|g| g.rest.clone()).collect();
        let mut out = vec![Vector3::zeros(); 400 * 8];
        let w_small = small.apply(&shapes, &mut out[..800]) - (guides.len() * 8) as u64;
        let w_large = large.apply(&shapes, &mut out) - (guides.len() * 8) as u64;
        // At most k = 4 sources per point: bounded by points · k, whatever the guide count.
        assert!(w_small <= 100 * 8 * 4 && w_large <= 400 * 8 * 4);
        let ratio = w_large as f64 / w_small as f64;
        assert!(
            (3.5..=4.5).contains(&ratio),
            "work ratio {ratio} for 4× the hairs"
        );
    }

    #[test]
    fn pose_with_a_changed_point_count_is_refused_by_guide() {
        let (mesh, guides, hairs) = setup(10);
        let blend = GuideBlend::new(&mesh, &guides, &hairs, 8).unwrap();
        let mut shapes: Vec<_> = guides.iter().map(|g| g.rest.clone()).collect();
        shapes[5].pop();
        let e = blend
            .check_pose(&shapes, "pose.obj")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("pose.obj") && e.contains("guide 5 has 7 points"),
            "{e}"
        );
        shapes.pop();
        let e = blend
            .check_pose(&shapes, "pose.obj")
            .unwrap_err()
            .to_string();
        assert!(e.contains("29 guides"), "{e}");
    }

    #[test]
    fn painted_fractions_trim_each_blended_hair_to_its_fraction() {
        let (mesh, guides, hairs) = setup(60);
        let fractions: Vec<f32> = (0..60).map(|h| 0.25 + 0.75 * h as f32 / 59.0).collect();
        let plain = GuideBlend::new(&mesh, &guides, &hairs, 8).unwrap();
        let trimmed = plain
            .clone()
            .with_length_fractions(fractions.clone())
            .unwrap();
        let shapes: Vec<_> = guides.iter().map(|g| g.rest.clone()).collect();
        let (mut a, mut b) = (
            vec![Vector3::zeros(); 60 * 8],
            vec![Vector3::zeros(); 60 * 8],
        );
        plain.apply(&shapes, &mut a);
        trimmed.apply(&shapes, &mut b);
        let mut want = [Vector3::zeros(); 8];
        for (h, &f) in fractions.iter().enumerate() {
            let at = h * 8..(h + 1) * 8;
            if f < 1.0 {
                trim_polyline(&a[at.clone()], f, &mut want);
            } else {
                // The full length: the blend as it is, not resampled.
                want.copy_from_slice(&a[at.clone()]);
            }
            assert_eq!(&b[at.clone()], &want[..], "hair {h}");
            // The guides here are gently curved: the chords lose well under 1 %.
            let ratio = polyline_length(&b[at.clone()]) / polyline_length(&a[at]);
            assert!(
                (f64::from(f) * 0.99..=f64::from(f) + 1e-6).contains(&ratio),
                "hair {h}: {ratio} for {f}"
            );
        }
    }

    #[test]
    fn fractions_of_the_wrong_count_or_outside_zero_to_one_are_refused() {
        let (mesh, guides, hairs) = setup(10);
        let blend = GuideBlend::new(&mesh, &guides, &hairs, 8).unwrap();
        let e = blend
            .clone()
            .with_length_fractions(vec![0.5; 9])
            .unwrap_err();
        assert!(
            e.to_string()
                .contains("one length fraction per sim hair (10)"),
            "{e}"
        );
        let mut f = vec![0.5; 10];
        f[4] = 0.0;
        let e = blend.with_length_fractions(f).unwrap_err();
        assert!(e.to_string().contains("sim hair 4"), "{e}");
    }
}
