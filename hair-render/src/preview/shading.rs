//! Light and materials of the preview: Lambert for meshes, Kajiya–Kay for hair.
//!
//! One key light fixed relative to the camera (from the upper left, in front), so every preset
//! view is lit the same way, plus a constant ambient term. Colors are linear RGB; the image is
//! converted to sRGB at the end.
//!
//! Kajiya & Kay, "Rendering fur with three dimensional textures", SIGGRAPH 1989, §4: a hair is a
//! thin cylinder with tangent `T`; its diffuse term is `sin(T, L) = √(1 − (T·L)²)` and its
//! specular term peaks on the cone of mirror directions around `T`:
//! `(sin(T, L) sin(T, E) − (T·L)(T·E))^p` with `L` towards the light and `E` towards the eye
//! (the cosine of the angle between `E` and the nearest mirror direction, clamped at 0).

use nalgebra::Vector3;

use super::error::{parameter, Result};
use super::scene::Rgb;

/// The key light and ambient term.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    /// Direction towards the light in camera space (right, up, towards the viewer); normalised
    /// when used. The default, (−0.5, 0.7, 0.6), lights from the upper left, in front.
    pub direction: [f32; 3],
    /// Key light intensity (1 = full).
    pub intensity: f32,
    /// Ambient intensity added everywhere.
    pub ambient: f32,
}

impl Default for Light {
    fn default() -> Self {
        Self {
            direction: [-0.5, 0.7, 0.6],
            intensity: 0.9,
            ambient: 0.22,
        }
    }
}

/// How hair is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HairLook {
    /// Color at the root, linear RGB (the gradient's start; per-point colors replace it).
    pub root_color: Rgb,
    /// Color at the tip, linear RGB.
    pub tip_color: Rgb,
    /// Radius of strands without per-point radii, meters.
    pub default_radius: f32,
    /// Factor on every radius before projection (e.g. < 1 to draw thick simulation strands
    /// thinner), finite and > 0.
    pub radius_scale: f32,
    /// Narrowest drawn line, pixels, ≥ 0.5: thinner strands are drawn this wide with their
    /// coverage lowered in proportion, so a 0.2 px hair is a faint 1 px line.
    pub min_width_px: f32,
    /// Opacity of a fully covered pixel, in (0, 1].
    pub opacity: f32,
    /// Strength of the Kajiya–Kay specular highlight, ≥ 0.
    pub specular: f32,
    /// Kajiya–Kay specular exponent, ≥ 1 (larger = tighter highlight).
    pub shininess: f32,
    /// Self-shadowing: meters of hair between a point and the key light that dim the light by a
    /// factor e (see [`super`]'s shadow notes); 0 turns hair and mesh shadows off.
    pub shadow_depth: f32,
}

impl Default for HairLook {
    fn default() -> Self {
        Self {
            root_color: [0.045, 0.024, 0.012],
            tip_color: [0.23, 0.13, 0.06],
            default_radius: 5e-5,
            radius_scale: 1.0,
            min_width_px: 1.0,
            opacity: 1.0,
            specular: 0.35,
            shininess: 40.0,
            shadow_depth: 0.008,
        }
    }
}

/// Everything [`super::render`] needs besides the scene and the camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    /// Image width, pixels (1–16384).
    pub width: u32,
    /// Image height, pixels (1–16384).
    pub height: u32,
    /// Background, linear RGB.
    pub background: Rgb,
    /// Key and ambient light.
    pub light: Light,
    /// Hair material and widths.
    pub hair: HairLook,
}

impl Default for RenderSettings {
    /// 800 × 800, light grey background, default light and hair.
    fn default() -> Self {
        Self {
            width: 800,
            height: 800,
            background: [0.52, 0.55, 0.6],
            light: Light::default(),
            hair: HairLook::default(),
        }
    }
}

impl RenderSettings {
    /// Checks every field's range, naming the first at fault.
    pub(crate) fn validate(&self) -> Result<()> {
        super::image::check_size("settings.width × height", self.width, self.height)?;
        let rgb = |name, c: Rgb| {
            if c.iter().all(|v| v.is_finite() && (0.0..=1.0).contains(v)) {
                Ok(())
            } else {
                Err(parameter(
                    name,
                    format!("{c:?}"),
                    "give linear RGB with each channel in [0, 1]",
                ))
            }
        };
        rgb("settings.background", self.background)?;
        rgb("settings.hair.root_color", self.hair.root_color)?;
        rgb("settings.hair.tip_color", self.hair.tip_color)?;
        let l = &self.light;
        let d = Vector3::from(l.direction);
        if !(d.iter().all(|c| c.is_finite()) && d.norm() > 1e-6) {
            return Err(parameter(
                "settings.light.direction",
                format!("{:?}", l.direction),
                "give a finite, non-zero direction (camera space: right, up, towards viewer)",
            ));
        }
        let check = |name, v: f32, ok: bool, fix| {
            if v.is_finite() && ok {
                Ok(())
            } else {
                Err(parameter(name, v, fix))
            }
        };
        check(
            "settings.light.intensity",
            l.intensity,
            l.intensity >= 0.0,
            "give an intensity ≥ 0",
        )?;
        check(
            "settings.light.ambient",
            l.ambient,
            l.ambient >= 0.0,
            "give an ambient intensity ≥ 0",
        )?;
        let h = &self.hair;
        check(
            "settings.hair.default_radius",
            h.default_radius,
            h.default_radius >= 0.0,
            "give a radius ≥ 0 m",
        )?;
        check(
            "settings.hair.radius_scale",
            h.radius_scale,
            h.radius_scale > 0.0,
            "give a factor > 0",
        )?;
        check(
            "settings.hair.min_width_px",
            h.min_width_px,
            (0.5..=64.0).contains(&h.min_width_px),
            "give a width in [0.5, 64] pixels",
        )?;
        check(
            "settings.hair.opacity",
            h.opacity,
            h.opacity > 0.0 && h.opacity <= 1.0,
            "give an opacity in (0, 1]",
        )?;
        check(
            "settings.hair.specular",
            h.specular,
            h.specular >= 0.0,
            "give a strength ≥ 0",
        )?;
        check(
            "settings.hair.shininess",
            h.shininess,
            (1.0..=10_000.0).contains(&h.shininess),
            "give an exponent in [1, 10000]",
        )?;
        check(
            "settings.hair.shadow_depth",
            h.shadow_depth,
            h.shadow_depth >= 0.0,
            "give a depth ≥ 0 m (0 turns shadows off; 0.008 suits a head of hair)",
        )
    }
}

/// The light in world space for one camera.
#[derive(Debug, Clone, Copy)]
pub(crate) struct WorldLight {
    /// Unit direction towards the light.
    pub to_light: Vector3<f32>,
    pub intensity: f32,
    pub ambient: f32,
}

impl WorldLight {
    pub fn new(light: &Light, right: &Vector3<f32>, up: &Vector3<f32>, fwd: &Vector3<f32>) -> Self {
        let [x, y, z] = light.direction;
        Self {
            to_light: (right * x + up * y - fwd * z).normalize(),
            intensity: light.intensity,
            ambient: light.ambient,
        }
    }

    /// Two-sided Lambert: `normal` (unit) is turned to face `to_eye` first, so open meshes are
    /// lit on whichever side is seen; `lit` (0–1) is the fraction of the key light that arrives.
    pub fn lambert(
        &self,
        color: Rgb,
        normal: &Vector3<f32>,
        to_eye: &Vector3<f32>,
        lit: f32,
    ) -> Rgb {
        let n = if normal.dot(to_eye) < 0.0 {
            -normal
        } else {
            *normal
        };
        let k = self.ambient + lit * self.intensity * n.dot(&self.to_light).max(0.0);
        color.map(|c| c * k)
    }

    /// Kajiya–Kay shading of a hair of unit `tangent` seen along unit `to_eye`; `lit` (0–1) is
    /// the fraction of the key light that arrives.
    pub fn kajiya_kay(
        &self,
        color: Rgb,
        tangent: &Vector3<f32>,
        to_eye: &Vector3<f32>,
        look: &HairLook,
        lit: f32,
    ) -> Rgb {
        let tl = tangent.dot(&self.to_light);
        let te = tangent.dot(to_eye);
        let sin_l = (1.0 - tl * tl).max(0.0).sqrt();
        let sin_e = (1.0 - te * te).max(0.0).sqrt();
        let key = lit * self.intensity;
        let diffuse = self.ambient + key * sin_l;
        let spec = key * look.specular * (sin_l * sin_e - tl * te).max(0.0).powf(look.shininess);
        color.map(|c| c * diffuse + spec)
    }
}

/// Linear [0, 1] → 8-bit sRGB (IEC 61966-2-1 transfer function), clamped.
pub(crate) fn srgb8(linear: f32) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    fn light_along(d: Vector3<f32>) -> WorldLight {
        WorldLight {
            to_light: d.normalize(),
            intensity: 1.0,
            ambient: 0.0,
        }
    }

    #[test]
    fn kajiya_kay_diffuse_is_sine_of_tangent_and_light() {
        let l = light_along(Vector3::z());
        let look = HairLook {
            specular: 0.0,
            ..Default::default()
        };
        let across = l.kajiya_kay([1.0; 3], &Vector3::x(), &Vector3::y(), &look, 1.0);
        let along = l.kajiya_kay([1.0; 3], &Vector3::z(), &Vector3::y(), &look, 1.0);
        let diag = l.kajiya_kay(
            [1.0; 3],
            &Vector3::new(1.0, 0.0, 1.0).normalize(),
            &Vector3::y(),
            &look,
            1.0,
        );
        assert!((across[0] - 1.0).abs() < 1e-6 && along[0].abs() < 1e-6);
        assert!((diag[0] - std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-6);
    }

    #[test]
    fn kajiya_kay_specular_peaks_on_the_mirror_cone() {
        let look = HairLook {
            specular: 1.0,
            shininess: 50.0,
            ..Default::default()
        };
        // Hair along x, light from (−1, 0, 1): the mirror cone holds (1, 0, 1) and (1, 1, 0)·…
        let l = light_along(Vector3::new(-1.0, 0.0, 1.0));
        let t = Vector3::x();
        let black = [0.0; 3];
        let mirror = l.kajiya_kay(
            black,
            &t,
            &Vector3::new(1.0, 0.0, 1.0).normalize(),
            &look,
            1.0,
        );
        let on_cone = l.kajiya_kay(
            black,
            &t,
            &Vector3::new(1.0, 1.0, 0.0).normalize(),
            &look,
            1.0,
        );
        let back = l.kajiya_kay(
            black,
            &t,
            &Vector3::new(-1.0, 0.0, 1.0).normalize(),
            &look,
            1.0,
        );
        assert!((mirror[0] - 1.0).abs() < 1e-5, "{mirror:?}");
        assert!((on_cone[0] - 1.0).abs() < 1e-5, "{on_cone:?}");
        assert!(back[0] < 1e-6, "{back:?}");
    }

    #[test]
    fn lambert_is_two_sided() {
        let l = light_along(Vector3::z());
        let n = Vector3::z();
        let front = l.lambert([1.0; 3], &n, &Vector3::z(), 1.0);
        let behind = l.lambert([1.0; 3], &-n, &Vector3::z(), 1.0);
        assert_eq!(front, behind);
        assert!((front[0] - 1.0).abs() < 1e-6);
    }

    #[test]
    fn srgb_end_points_and_mid_grey() {
        assert_eq!(srgb8(0.0), 0);
        assert_eq!(srgb8(1.0), 255);
        assert_eq!(srgb8(2.0), 255);
        // 18 % grey is about 118 in sRGB.
        assert!((srgb8(0.18) as i32 - 118).abs() <= 1);
    }
}
