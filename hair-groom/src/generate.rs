//! Generated straight hair: strands rooted at area-weighted random points of a mesh, each
//! growing straight along its root's surface normal.
//!
//! Each strand's rest shape is in root-local coordinates (local +z is the smooth surface
//! normal, see [`hair_core::RootFrame`]): `segments` equal segments from the origin up the z
//! axis. Its anchor is the mesh sample, so the strand turns with the deforming scalp.

use hair_core::{Anchor, StrandInput, TriMesh};
use nalgebra::Vector3;

use crate::error::{parameter, GroomError};
use crate::rng::{self, Purpose};
#[cfg(doc)]
use crate::sampling::sample_area_weighted;
use crate::sampling::{sample_roots, Region, RootDensity};

/// What to grow. The field names are the scene-file keys under `[hair]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GenerateOptions {
    /// Number of strands, ≥ 1.
    pub count: usize,
    /// Strand length before variation, m; finite and > 0.
    pub length: f32,
    /// Equal segments per strand (points = segments + 1), ≥ 1.
    pub segments: u32,
    /// Seed of every random choice (roots, lengths): the same seed gives the same hair.
    pub seed: u64,
    /// Strand radius (collision sphere and render width), m; finite and ≥ 0.
    pub radius: f32,
    /// Linear mass density, kg/m, lumped onto the points; finite and > 0.
    pub mass_per_length: f32,
    /// Goal weight at the root, in [0, 1]; interpolated linearly to the tip.
    pub goal_root: f32,
    /// Goal weight at the tip, in [0, 1].
    pub goal_tip: f32,
    /// The part of the mesh that grows hair.
    pub region: Region,
    /// Random shortening, in [0, 1): each strand's length is `length · (1 − length_variation · r)`
    /// with `r` uniform in [0, 1).
    pub length_variation: f32,
}

impl GenerateOptions {
    /// Checks every option's range, naming the first one at fault.
    fn validate(&self) -> Result<(), GroomError> {
        if self.count < 1 {
            return Err(parameter(
                "count",
                self.count,
                "must be ≥ 1 (number of strands)",
            ));
        }
        if !(self.length.is_finite() && self.length > 0.0) {
            return Err(parameter(
                "length",
                self.length,
                "must be a finite number > 0 m (strand length)",
            ));
        }
        if self.segments < 1 {
            return Err(parameter(
                "segments",
                self.segments,
                "must be ≥ 1 (segments per strand)",
            ));
        }
        let points = self.count as u128 * (u128::from(self.segments) + 1);
        if points > u128::from(u32::MAX) {
            return Err(parameter(
                "count",
                self.count,
                "count · (segments + 1) points must fit in 32-bit offsets: grow fewer strands or \
                 use fewer segments",
            ));
        }
        if !(self.radius.is_finite() && self.radius >= 0.0) {
            return Err(parameter(
                "radius",
                self.radius,
                "must be a finite number ≥ 0 m (strand radius)",
            ));
        }
        if !(self.mass_per_length.is_finite() && self.mass_per_length > 0.0) {
            return Err(parameter(
                "mass_per_length",
                self.mass_per_length,
                "must be a finite number > 0 kg/m (linear density of a strand)",
            ));
        }
        for (name, w) in [("goal_root", self.goal_root), ("goal_tip", self.goal_tip)] {
            if !(0.0..=1.0).contains(&w) {
                return Err(parameter(
                    name,
                    w,
                    "must lie in [0, 1] (goal spring weight)",
                ));
            }
        }
        if !(0.0..1.0).contains(&self.length_variation) {
            return Err(parameter(
                "length_variation",
                self.length_variation,
                "must lie in [0, 1) (0 = all strands full length; 0.3 = up to 30 % shorter)",
            ));
        }
        Ok(())
    }
}

/// Grows `opts.count` straight strands on `mesh`, ready for [`hair_core::StrandSet::push`].
///
/// Roots come from [`sample_area_weighted`] with `opts.seed` and `opts.region`; lengths vary
/// from an independent stream of the same seed, so changing `length_variation` never moves a
/// root. Masses, radii and goal weights follow [`StrandInput::uniform`].
pub fn generate(mesh: &TriMesh, opts: &GenerateOptions) -> Result<Vec<StrandInput>, GroomError> {
    generate_with_density(mesh, opts, None)
}

/// [`generate()`] with the roots distributed by `density` ([`sample_roots`]: still
/// `opts.count` strands, denser where the density is higher; a density at its maximum
/// everywhere gives [`generate()`]'s strands bit for bit).
pub fn generate_with_density(
    mesh: &TriMesh,
    opts: &GenerateOptions,
    density: Option<&dyn RootDensity>,
) -> Result<Vec<StrandInput>, GroomError> {
    opts.validate()?;
    let roots = sample_roots(mesh, opts.count, opts.seed, &opts.region, density)?;
    let mut lengths = rng::stream(opts.seed, Purpose::Lengths);
    let strands = roots
        .into_iter()
        .map(|sample| {
            let shortening = opts.length_variation * rng::unit_f32(&mut lengths);
            let step = opts.length * (1.0 - shortening) / opts.segments as f32;
            let rest = (0..=opts.segments)
                .map(|i| Vector3::new(0.0, 0.0, step * i as f32))
                .collect();
            StrandInput::uniform(
                Anchor::Surface(sample),
                rest,
                opts.mass_per_length,
                opts.radius,
                opts.goal_root,
                opts.goal_tip,
            )
        })
        .collect();
    Ok(strands)
}

#[cfg(test)]
mod tests {
    use hair_core::{Scalp, StrandSet};

    use super::*;
    use crate::shapes::uv_sphere;

    fn options() -> GenerateOptions {
        GenerateOptions {
            count: 200,
            length: 0.2,
            segments: 10,
            seed: 5,
            radius: 0.001,
            mass_per_length: 2e-4,
            goal_root: 1.0,
            goal_tip: 0.2,
            region: Region::All,
            length_variation: 0.0,
        }
    }

    #[test]
    fn strands_grow_along_the_normal() {
        let mesh = uv_sphere(0.1, 16, 8).unwrap();
        let opts = options();
        let strands = generate(&mesh, &opts).unwrap();
        assert_eq!(strands.len(), 200);
        let mut set = StrandSet::new();
        for s in strands {
            assert_eq!(s.rest.len(), 11);
            assert_eq!(s.rest[0], Vector3::zeros());
            assert!((s.rest[10] - Vector3::new(0.0, 0.0, 0.2)).norm() < 1e-6);
            assert!(s.goal_weight[0] == 1.0 && (s.goal_weight[10] - 0.2).abs() < 1e-6);
            let total: f32 = s.mass.iter().sum();
            assert!((total - 0.2 * 2e-4).abs() < 1e-9);
            set.push(s).unwrap();
        }
        let scalp = Scalp {
            mesh: Some(mesh),
            ..Scalp::fixed()
        };
        set.validate_anchors(&scalp).unwrap();
        set.reset_to_rest(&scalp);
        // On a sphere the normal is radial: tips sit 0.2 m beyond the surface, outwards.
        for s in 0..set.len() {
            let p = set.points(s);
            let (root, tip) = (set.positions[p.start], set.positions[p.end - 1]);
            assert!((root.norm() - 0.1).abs() < 0.01, "root at {root:?}");
            assert!(
                (tip.norm() - root.norm() - 0.2).abs() < 0.01,
                "tip at {tip:?}"
            );
        }
    }

    #[test]
    fn length_variation_shortens_without_moving_roots() {
        let mesh = uv_sphere(0.1, 16, 8).unwrap();
        let plain = generate(&mesh, &options()).unwrap();
        let varied_opts = GenerateOptions {
            length_variation: 0.5,
            ..options()
        };
        let varied = generate(&mesh, &varied_opts).unwrap();
        let lengths: Vec<f32> = varied.iter().map(|s| s.rest[10].z).collect();
        assert!(lengths.iter().all(|&l| l > 0.1 - 1e-6 && l <= 0.2));
        assert!(lengths.iter().any(|&l| l < 0.15) && lengths.iter().any(|&l| l > 0.15));
        for (a, b) in plain.iter().zip(&varied) {
            assert_eq!(a.anchor, b.anchor);
        }
        assert_eq!(varied, generate(&mesh, &varied_opts).unwrap());
    }

    #[test]
    fn bad_options_are_named() {
        let mesh = uv_sphere(0.1, 8, 4).unwrap();
        type Spoil = fn(&mut GenerateOptions);
        let cases: [(&str, Spoil); 10] = [
            ("count", |o| o.count = 0),
            ("count", |o| o.count = 1 << 31),
            ("length", |o| o.length = 0.0),
            ("length", |o| o.length = f32::INFINITY),
            ("segments", |o| o.segments = 0),
            ("radius", |o| o.radius = -1e-3),
            ("mass_per_length", |o| o.mass_per_length = 0.0),
            ("goal_root", |o| o.goal_root = 1.5),
            ("goal_tip", |o| o.goal_tip = f32::NAN),
            ("length_variation", |o| o.length_variation = 1.0),
        ];
        for (name, spoil) in cases {
            let mut opts = options();
            spoil(&mut opts);
            let err = generate(&mesh, &opts).unwrap_err();
            assert!(
                err.to_string().contains(&format!("`{name}`")),
                "{name}: {err}"
            );
        }
    }
}
