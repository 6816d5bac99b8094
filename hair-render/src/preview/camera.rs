//! The preview camera: a pinhole with a vertical field of view, placed explicitly
//! ([`Camera::look_at`]) or by a preset [`View`] framed to a box ([`Camera::framed`]).
//!
//! Presets are named for the built-in head (`hair_groom::builtin_head`), whose face looks down −Y
//! (Blender's front view), Z up: [`View::Front`] looks at the face from −Y, [`View::Back`] from
//! +Y, [`View::Side`] from +X (the head's left side) and [`View::ThreeQuarter`] from halfway
//! between front and side, each from a little above. Framing fits the eight corners of the box
//! into the image with a margin, so a run framed to one box (the union of all its frames) keeps
//! one camera for every frame.
//!
//! Camera space: `right`, `up`, `forward` (the view direction) form a right-handed-on-screen
//! basis; a point's depth is its distance along `forward`; pixels grow right and down.

use nalgebra::Vector3;

use super::error::{parameter, PreviewError, Result};
use super::scene::Bounds;

/// A preset direction to look from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum View {
    /// From −Y (the built-in head's face), 10° above.
    Front,
    /// From +X (the built-in head's left side), 10° above.
    Side,
    /// From +Y (the back of the head), 10° above.
    Back,
    /// From between the front and the side (45°), 15° above.
    ThreeQuarter,
    /// From any direction: `azimuth_deg` turns from the front (0°) towards +X (90°, the side)
    /// about Z; `elevation_deg` looks from above (positive) or below, in (−90, 90).
    Orbit {
        /// Degrees about Z from the front (−Y) towards +X.
        azimuth_deg: f32,
        /// Degrees above the horizontal plane.
        elevation_deg: f32,
    },
}

impl View {
    /// Every named preset, for contact sheets of all sides.
    pub const PRESETS: [View; 4] = [View::Front, View::Side, View::Back, View::ThreeQuarter];

    /// Parses a preset name: `front`, `side`, `back`, `three-quarter` (or `3/4`).
    pub fn parse(name: &str) -> Result<View> {
        match name {
            "front" => Ok(View::Front),
            "side" => Ok(View::Side),
            "back" => Ok(View::Back),
            "three-quarter" | "3/4" => Ok(View::ThreeQuarter),
            _ => Err(parameter(
                "view",
                name,
                "use front, side, back or three-quarter",
            )),
        }
    }

    /// Azimuth and elevation, degrees.
    fn angles(self) -> (f32, f32) {
        match self {
            View::Front => (0.0, 10.0),
            View::Side => (90.0, 10.0),
            View::Back => (180.0, 10.0),
            View::ThreeQuarter => (45.0, 15.0),
            View::Orbit {
                azimuth_deg,
                elevation_deg,
            } => (azimuth_deg, elevation_deg),
        }
    }

    /// Unit direction from the looked-at point towards the eye.
    fn towards_eye(self) -> Result<Vector3<f32>> {
        let (az, el) = self.angles();
        if !az.is_finite() {
            return Err(parameter("view.azimuth_deg", az, "give a finite angle"));
        }
        if !(el.is_finite() && el.abs() < 89.0) {
            return Err(parameter(
                "view.elevation_deg",
                el,
                "give an angle strictly between −89° and 89° (straight down or up has no \
                 horizon to keep Z up on screen)",
            ));
        }
        let (az, el) = (az.to_radians(), el.to_radians());
        Ok(Vector3::new(
            az.sin() * el.cos(),
            -az.cos() * el.cos(),
            el.sin(),
        ))
    }
}

impl std::fmt::Display for View {
    /// The preset's name as [`View::parse`] reads it, or `orbit A° E°`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            View::Front => f.write_str("front"),
            View::Side => f.write_str("side"),
            View::Back => f.write_str("back"),
            View::ThreeQuarter => f.write_str("three-quarter"),
            View::Orbit {
                azimuth_deg,
                elevation_deg,
            } => write!(f, "orbit {azimuth_deg}° {elevation_deg}°"),
        }
    }
}

/// A pinhole camera, meters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub eye: Vector3<f32>,
    /// A point on the view axis (the image centre).
    pub target: Vector3<f32>,
    /// Which way is up on screen (projected; Z for hairsys).
    pub up: Vector3<f32>,
    /// Vertical field of view, degrees, in [1, 150].
    pub fov_y_deg: f32,
}

/// Default vertical field of view, degrees: a 50 mm lens on a 24 mm-tall sensor is 27°; a bit
/// wider keeps the perspective visible without distorting a head.
pub const DEFAULT_FOV_Y_DEG: f32 = 30.0;

/// Fraction of the image left empty on each side by [`Camera::framed`].
pub const FRAME_MARGIN: f32 = 0.06;

impl Camera {
    /// A camera at `eye` looking at `target` with `up` upwards on screen; checked (finite,
    /// `eye ≠ target`, `up` not along the view, field of view in [1°, 150°]).
    pub fn look_at(
        eye: Vector3<f32>,
        target: Vector3<f32>,
        up: Vector3<f32>,
        fov_y_deg: f32,
    ) -> Result<Camera> {
        let camera = Camera {
            eye,
            target,
            up,
            fov_y_deg,
        };
        camera.basis()?;
        Ok(camera)
    }

    /// A camera looking from `view` at `bounds`, at the distance where all eight corners of the
    /// box fit in a `width` × `height` image with [`FRAME_MARGIN`] to spare, aimed at the box's
    /// centre. Fails on an empty or non-finite box.
    pub fn framed(
        view: View,
        bounds: &Bounds,
        width: u32,
        height: u32,
        fov_y_deg: f32,
    ) -> Result<Camera> {
        if !(bounds.min.iter().chain(bounds.max.iter())).all(|c| c.is_finite()) {
            return Err(PreviewError::Camera {
                problem: format!("framing box {bounds:?} is not finite"),
                fix: "frame finite geometry (a blown-up simulation has non-finite points)",
            });
        }
        let size = (bounds.max - bounds.min).norm();
        if size <= 1e-9
            || !bounds
                .min
                .iter()
                .zip(bounds.max.iter())
                .all(|(a, b)| a <= b)
        {
            return Err(PreviewError::Camera {
                problem: format!("framing box {:?}–{:?} has no size", bounds.min, bounds.max),
                fix: "frame a box that contains more than one point",
            });
        }
        check_fov(fov_y_deg)?;
        if width == 0 || height == 0 {
            return Err(parameter(
                "settings.width × height",
                format!("{width} × {height}"),
                "give an image at least 1 pixel wide and tall",
            ));
        }
        let corners = bounds.corners();
        Camera::fit(
            view,
            &[&corners],
            bounds.centre(),
            size,
            width,
            height,
            fov_y_deg,
        )
    }

    /// A camera looking from `view` at every point of `groups` (meters), as close as lets them
    /// all project inside a `width` × `height` image with [`FRAME_MARGIN`] to spare, the image
    /// centred on their projection. `bounds` must hold the points (its size sets the nearest
    /// distance allowed).
    pub(crate) fn framed_to_points(
        view: View,
        groups: &[&[Vector3<f32>]],
        bounds: &Bounds,
        width: u32,
        height: u32,
        fov_y_deg: f32,
    ) -> Result<Camera> {
        // Check the box as `framed` does, then fit the points themselves.
        Camera::framed(view, bounds, width, height, fov_y_deg)?;
        let size = (bounds.max - bounds.min).norm();
        Camera::fit(
            view,
            groups,
            bounds.centre(),
            size,
            width,
            height,
            fov_y_deg,
        )
    }

    /// Fits `groups` of points, already checked finite, around `centre` (see
    /// [`Camera::framed_to_points`]).
    fn fit(
        view: View,
        groups: &[&[Vector3<f32>]],
        centre: Vector3<f32>,
        size: f32,
        width: u32,
        height: u32,
        fov_y_deg: f32,
    ) -> Result<Camera> {
        let towards_eye = view.towards_eye()?;
        let forward = -towards_eye;
        let right = forward.cross(&Vector3::z()).normalize();
        let up = right.cross(&forward);
        let tan_y = (0.5 * fov_y_deg.to_radians()).tan() * (1.0 - 2.0 * FRAME_MARGIN);
        let tan_x = tan_y * width as f32 / height as f32;
        let points = || groups.iter().flat_map(|g| g.iter());
        // Distance d back from `c` along the view such that every point (x, y at depth d + z)
        // projects inside the image: d ≥ |x| / tan − z, and every point in front of the eye.
        let distance = |c: Vector3<f32>| {
            points().fold(0.0f32, |d, p| {
                let o = p - c;
                let (x, y, z) = (o.dot(&right), o.dot(&up), o.dot(&forward));
                d.max(x.abs() / tan_x - z)
                    .max(y.abs() / tan_y - z)
                    .max(-z + 0.01 * size)
            })
        };
        // Centre the projection: shift the view axis sideways by the middle of the points'
        // angular extent, then fit again from there (the second fit keeps every point inside).
        let d = distance(centre);
        let (mut lo, mut hi) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
        for p in points() {
            let o = p - centre;
            let depth = d + o.dot(&forward);
            let a = [o.dot(&right) / depth, o.dot(&up) / depth];
            for k in 0..2 {
                lo[k] = lo[k].min(a[k]);
                hi[k] = hi[k].max(a[k]);
            }
        }
        let target = centre + (right * (lo[0] + hi[0]) + up * (lo[1] + hi[1])) * (0.5 * d);
        let d = distance(target);
        Camera::look_at(target + towards_eye * d, target, Vector3::z(), fov_y_deg)
    }

    /// The camera's orthonormal basis, or why it has none.
    pub(crate) fn basis(&self) -> Result<Basis> {
        let finite = |v: &Vector3<f32>| v.iter().all(|c| c.is_finite());
        if !(finite(&self.eye) && finite(&self.target) && finite(&self.up)) {
            return Err(PreviewError::Camera {
                problem: format!(
                    "eye {:?}, target {:?} or up {:?} is not finite",
                    self.eye, self.target, self.up
                ),
                fix: "give finite coordinates in meters",
            });
        }
        check_fov(self.fov_y_deg)?;
        let view = self.target - self.eye;
        if view.norm() <= 1e-6 {
            return Err(PreviewError::Camera {
                problem: format!("eye and target are both at {:?}", self.eye),
                fix: "put the target in front of the eye, or use a preset view",
            });
        }
        let forward = view.normalize();
        let side = forward.cross(&self.up);
        if side.norm() <= 1e-3 * self.up.norm() || self.up.norm() <= 1e-9 {
            return Err(PreviewError::Camera {
                problem: format!(
                    "up {:?} is zero or along the view direction {forward:?}, so the image has \
                     no up",
                    self.up
                ),
                fix: "give an up vector across the view (Z, unless looking straight down)",
            });
        }
        let right = side.normalize();
        Ok(Basis {
            eye: self.eye,
            right,
            up: right.cross(&forward),
            forward,
        })
    }
}

fn check_fov(fov_y_deg: f32) -> Result<()> {
    if fov_y_deg.is_finite() && (1.0..=150.0).contains(&fov_y_deg) {
        Ok(())
    } else {
        Err(parameter(
            "camera.fov_y_deg",
            fov_y_deg,
            "give a vertical field of view in [1°, 150°] (30° is a portrait lens)",
        ))
    }
}

/// Camera frame: eye and orthonormal right, up, forward.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Basis {
    pub eye: Vector3<f32>,
    pub right: Vector3<f32>,
    pub up: Vector3<f32>,
    pub forward: Vector3<f32>,
}

/// World → camera space → pixels for one image size.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Projection {
    pub basis: Basis,
    /// Focal length in pixels.
    pub focal_px: f32,
    /// Image centre, pixels.
    pub cx: f32,
    pub cy: f32,
    /// Nearest drawn depth, meters.
    pub near: f32,
}

/// Nearest drawn depth, meters: geometry closer to the eye than this is clipped.
pub(crate) const NEAR: f32 = 1e-3;

impl Projection {
    pub fn new(camera: &Camera, width: u32, height: u32) -> Result<Self> {
        let basis = camera.basis()?;
        Ok(Self {
            basis,
            focal_px: 0.5 * height as f32 / (0.5 * camera.fov_y_deg.to_radians()).tan(),
            cx: 0.5 * width as f32,
            cy: 0.5 * height as f32,
            near: NEAR,
        })
    }

    /// Camera-space coordinates (right, up, depth), meters.
    pub fn camera_space(&self, p: &Vector3<f32>) -> Vector3<f32> {
        let o = p - self.basis.eye;
        Vector3::new(
            o.dot(&self.basis.right),
            o.dot(&self.basis.up),
            o.dot(&self.basis.forward),
        )
    }

    /// Pixel coordinates (x right, y down; pixel centres at +0.5) of a camera-space point in
    /// front of the near plane, and its depth.
    pub fn pixels(&self, c: &Vector3<f32>) -> [f32; 3] {
        let s = self.focal_px / c.z;
        [self.cx + c.x * s, self.cy - c.y * s, c.z]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box() -> Bounds {
        Bounds {
            min: Vector3::new(-0.1, -0.1, 0.0),
            max: Vector3::new(0.1, 0.1, 0.2),
        }
    }

    #[test]
    fn presets_look_from_the_named_side() {
        let b = unit_box();
        let eye = |v| Camera::framed(v, &b, 100, 100, 30.0).unwrap().eye - b.centre();
        assert!(eye(View::Front).y < -0.1 && eye(View::Front).x.abs() < 1e-6);
        assert!(eye(View::Back).y > 0.1);
        assert!(eye(View::Side).x > 0.1);
        let q = eye(View::ThreeQuarter);
        assert!(q.x > 0.05 && q.y < -0.05 && (q.x + q.y).abs() < 1e-5);
    }

    #[test]
    fn framed_box_corners_project_inside_the_margin() {
        let b = unit_box();
        for view in View::PRESETS {
            for (w, h) in [(100, 100), (200, 100), (100, 300)] {
                let cam = Camera::framed(view, &b, w, h, 30.0).unwrap();
                let proj = Projection::new(&cam, w, h).unwrap();
                let mut touches = false;
                for c in b.corners() {
                    let [x, y, _] = proj.pixels(&proj.camera_space(&c));
                    let (mx, my) = (FRAME_MARGIN * w as f32, FRAME_MARGIN * h as f32);
                    assert!(
                        x >= mx - 1e-2 && x <= w as f32 - mx + 1e-2,
                        "{view:?} x {x}"
                    );
                    assert!(
                        y >= my - 1e-2 && y <= h as f32 - my + 1e-2,
                        "{view:?} y {y}"
                    );
                    touches |= (x - mx).abs() < 0.05
                        || (y - my).abs() < 0.05
                        || (x - w as f32 + mx).abs() < 0.05
                        || (y - h as f32 + my).abs() < 0.05;
                }
                assert!(touches, "{view:?} {w}×{h}: framing is not tight");
            }
        }
    }

    #[test]
    fn fitted_points_fill_the_image_centred() {
        // An off-centre, lopsided cloud: a ring plus one far point.
        let mut pts: Vec<_> = (0..100)
            .map(|i| {
                let a = i as f32 * 0.0628;
                Vector3::new(0.3 + 0.1 * a.cos(), 0.05 * a.sin(), 0.2 + 0.1 * a.sin())
            })
            .collect();
        pts.push(Vector3::new(0.6, 0.1, 0.5));
        let bounds = Bounds::of_points(pts.iter().copied()).unwrap();
        for view in View::PRESETS {
            let (w, h) = (200u32, 100u32);
            let cam = Camera::framed_to_points(view, &[&pts], &bounds, w, h, 30.0).unwrap();
            let proj = Projection::new(&cam, w, h).unwrap();
            let (mut lo, mut hi) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
            for p in &pts {
                let [x, y, _] = proj.pixels(&proj.camera_space(p));
                lo = [lo[0].min(x), lo[1].min(y)];
                hi = [hi[0].max(x), hi[1].max(y)];
            }
            let (mx, my) = (FRAME_MARGIN * w as f32, FRAME_MARGIN * h as f32);
            assert!(
                lo[0] >= mx - 0.01 && hi[0] <= w as f32 - mx + 0.01,
                "{view:?} {lo:?} {hi:?}"
            );
            assert!(
                lo[1] >= my - 0.01 && hi[1] <= h as f32 - my + 0.01,
                "{view:?} {lo:?} {hi:?}"
            );
            // Tight on one axis, and centred on both within a few pixels.
            assert!(
                lo[0] - mx < 0.5
                    || lo[1] - my < 0.5
                    || w as f32 - mx - hi[0] < 0.5
                    || h as f32 - my - hi[1] < 0.5,
                "{view:?} not tight: {lo:?} {hi:?}"
            );
            assert!(
                ((lo[0] + hi[0]) * 0.5 - 100.0).abs() < 3.0,
                "{view:?} {lo:?} {hi:?}"
            );
            assert!(
                ((lo[1] + hi[1]) * 0.5 - 50.0).abs() < 3.0,
                "{view:?} {lo:?} {hi:?}"
            );
        }
    }

    #[test]
    fn degenerate_cameras_are_refused() {
        let z = Vector3::z();
        let e = Camera::look_at(z, z, Vector3::x(), 30.0).unwrap_err();
        assert!(e.to_string().contains("eye and target"), "{e}");
        let e = Camera::look_at(Vector3::zeros(), z, z, 30.0).unwrap_err();
        assert!(e.to_string().contains("along the view"), "{e}");
        let e = Camera::look_at(Vector3::zeros(), Vector3::x(), z, 0.0).unwrap_err();
        assert!(e.to_string().contains("fov_y_deg"), "{e}");
        let flat = Bounds {
            min: Vector3::zeros(),
            max: Vector3::zeros(),
        };
        let e = Camera::framed(View::Front, &flat, 10, 10, 30.0).unwrap_err();
        assert!(e.to_string().contains("no size"), "{e}");
        assert!(View::parse("top").is_err());
        for v in View::PRESETS {
            assert_eq!(View::parse(&v.to_string()).unwrap(), v);
        }
        assert_eq!(View::parse("3/4").unwrap(), View::ThreeQuarter);
    }
}
