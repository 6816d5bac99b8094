//! One physical hair, and every model's parameters derived from it.
//!
//! The bench's hair cases (the chain, the cantilever, the head) are made of **one** material so
//! that their errors compare models, not parameter choices. A human scalp hair is a keratin
//! fibre of Young's modulus `E = 3.89 GPa` (Robbins, *Chemical and Physical Behavior of Human
//! Hair*, Springer, appendix: `E = 3.89 × 10¹⁰ dyn/cm²`, the value `[rod]` already defaults
//! to), density `ρ = 1320 kg/m³` (Robbins: 1.32 g/cm³) and radius `r = 40 µm` (diameter 80 µm;
//! human hair is about 60–100 µm across, Yang et al., "On the strength of hair across species",
//! *Matter* 2, 2019, doi:10.1016/j.matt.2019.09.019). A round section is taken.
//!
//! From these, per unit length and per segment of rest length `l` (m):
//!
//! | quantity | formula | one hair |
//! |---|---|---|
//! | linear density `μ` (kg/m) | `ρ π r²` | 6.6 × 10⁻⁶ |
//! | stretch rigidity `EA` (N) | `E π r²` | 19.6 |
//! | bending rigidity `EI` (N m²) | `E π r⁴ / 4` | 7.8 × 10⁻⁹ |
//! | point mass (kg) | `μ l` (half at the tip), [`hair_core::StrandInput::uniform`] | |
//! | mass-spring stretch stiffness (N/m) | `EA / l` | 1,960 at `l` = 1 cm |
//! | mass-spring bend stiffness (N/m) | `EI / l³` ([`hair_core::HairParams::bend_stiffness`]: `EI = k_b l̄³`) | 7.8 × 10⁻³ at 1 cm |
//! | rod material (`[rod]`) | `E`, semi-axes `r` × `r` (round) | |
//!
//! A simulated strand that stands for a **wisp** of `n` hairs (the head case) carries `n` times
//! the mass, stretch and bending rigidity of one hair (hairs side by side, not glued: bending
//! rigidities add); for the rod this is a round section of radius `r n^{1/4}` of the same `E`.
//!
//! Physical stretch stiffness is far beyond what an explicit step can carry at frame-rate
//! substeps (`EA/l` on a 6.6 × 10⁻⁸ kg point at 1 cm bounds the step to 6 µs), which is why the
//! mass-spring model is run in three ways: with **soft** springs (the stiffness a scene sets for
//! an affordable step, the default scene's 40 N/m; their stretch is then an error against the
//! inextensible truth), with the **physical** `EA/l` under implicit Euler (stable at any step),
//! or **inextensible** (the projection, no springs).

use hair_core::RodParams;

/// Young's modulus of hair, Pa (Robbins).
pub const YOUNGS_MODULUS: f64 = 3.89e9;
/// Shear modulus of hair, Pa (the `[rod]` default; twist is not compared by any case).
pub const SHEAR_MODULUS: f64 = 1.5e9;
/// Density of hair, kg/m³ (Robbins).
pub const DENSITY: f64 = 1320.0;
/// Radius of one hair, m.
pub const RADIUS: f64 = 40e-6;

/// The default scene's stretch stiffness (40 N/m) as a fraction of its strands' physical
/// `EA/l` (a 1 g/m wisp is 151 hairs; 16 segments over 0.25 m): about 2.1 × 10⁻⁴. The cases'
/// **soft** springs are this fraction of their own physical stiffness, so that they stretch
/// under their own weight as much as the default scene's hair does.
pub fn soft_fraction() -> f64 {
    let wisp = Hair {
        hairs: 1e-3 / Hair::ONE.mass_per_length(),
    };
    40.0 / wisp.stretch_stiffness(0.25 / 16.0)
}

/// A strand of `hairs` physical hairs side by side (1 for a single hair).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hair {
    /// Hairs the strand stands for (≥ 1).
    pub hairs: f64,
}

impl Hair {
    /// One hair.
    pub const ONE: Self = Self { hairs: 1.0 };

    /// Cross-section area of one hair, m².
    fn area() -> f64 {
        std::f64::consts::PI * RADIUS * RADIUS
    }

    /// Linear density `n ρ π r²`, kg/m.
    pub fn mass_per_length(&self) -> f64 {
        self.hairs * DENSITY * Self::area()
    }

    /// Stretch rigidity `n E π r²`, N.
    pub fn stretch_rigidity(&self) -> f64 {
        self.hairs * YOUNGS_MODULUS * Self::area()
    }

    /// Bending rigidity `n E π r⁴ / 4`, N m².
    pub fn bending_rigidity(&self) -> f64 {
        self.hairs * YOUNGS_MODULUS * std::f64::consts::PI * RADIUS.powi(4) / 4.0
    }

    /// Mass-spring stretch stiffness of a segment of rest length `l` (m): `EA / l`, N/m.
    pub fn stretch_stiffness(&self, l: f64) -> f64 {
        self.stretch_rigidity() / l
    }

    /// Mass-spring bend stiffness for segments of rest length `l` (m): `EI / l³`, N/m.
    pub fn bend_stiffness(&self, l: f64) -> f64 {
        self.bending_rigidity() / l.powi(3)
    }

    /// The rod's material: `E`, and a round section whose `E π a⁴ / 4` is the strand's `EI`
    /// (`a = r n^{1/4}`). The projection settings are `base`'s.
    pub fn rod(&self, base: RodParams) -> RodParams {
        RodParams {
            youngs_modulus: YOUNGS_MODULUS as f32,
            shear_modulus: SHEAR_MODULUS as f32,
            semi_major_axis: (RADIUS * self.hairs.powf(0.25)) as f32,
            axis_ratio: 1.0,
            ..base
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hair_core::model::rod::Stiffness;

    #[test]
    fn one_hair_has_the_documented_rigidities() {
        let h = Hair::ONE;
        assert!((h.mass_per_length() - 6.63e-6).abs() < 0.01e-6);
        assert!((h.stretch_rigidity() - 19.55).abs() < 0.01);
        assert!((h.bending_rigidity() - 7.82e-9).abs() < 0.01e-9);
        assert!((h.stretch_stiffness(0.01) - 1955.0).abs() < 1.0);
    }

    #[test]
    fn soft_springs_are_the_default_scenes_fraction_of_the_physical_stiffness() {
        let f = soft_fraction();
        assert!((f - 2.12e-4).abs() < 0.01e-4, "{f}");
    }

    #[test]
    fn rod_section_of_a_wisp_has_the_wisps_bending_rigidity() {
        let wisp = Hair { hairs: 150.0 };
        let s = Stiffness::of(&wisp.rod(RodParams::default()));
        let want = wisp.bending_rigidity();
        assert!((s.major - want).abs() < 1e-5 * want, "{} {want}", s.major);
        assert!((s.minor - want).abs() < 1e-5 * want, "{} {want}", s.minor);
    }
}
