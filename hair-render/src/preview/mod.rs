//! A CPU preview renderer: one frame of hair with its scalp and colliders to an RGBA image and a
//! PNG, with no GPU and no display (`hairsys preview`, tests, quick looks at a run).
//!
//! # Use
//!
//! ```
//! use hair_render::preview::{render_view, Mesh, RenderSettings, Scene, Strands, View};
//! use nalgebra::Vector3;
//!
//! let head = hair_groom::builtin_head();
//! // One strand hanging in front of the face (the face looks down −Y).
//! let hair: Vec<_> = (0..5).map(|i| Vector3::new(0.0, -0.12, 0.2 - 0.03 * i as f32)).collect();
//! let scene = Scene {
//!     strands: Some(Strands::new(&hair, &[0, 5]).unwrap()),
//!     meshes: vec![Mesh::from_trimesh(0, &head, [0.6, 0.45, 0.35]).unwrap()],
//!     ..Default::default()
//! };
//! let settings = RenderSettings { width: 64, height: 64, ..Default::default() };
//! let image = render_view(&scene, View::Front, None, &settings).unwrap();
//! assert_eq!((image.width(), image.height()), (64, 64));
//! // image.write_png(Path::new("front.png"))?;
//! ```
//!
//! - [`Scene`]: [`Strands`] (flat positions + offsets, optional per-point radii and colors; render
//!   children through [`StrandBuffers::from_children`]),
//!   [`Mesh`]es (vertices + triangles + a color) and a [`Highlight`] (points inside colliders,
//!   over-stretched segments, drawn in red on top);
//! - [`Camera`]: explicit ([`Camera::look_at`]) or a preset [`View`] (front, side, back,
//!   three-quarter) framed to a [`Bounds`] ([`Camera::framed`]): pass one box (e.g. the union of
//!   every frame's [`Scene::bounds`]) to keep one framing for a whole run;
//! - [`render`] / [`render_view`] → [`PreviewImage`] (8-bit sRGB RGBA) →
//!   [`PreviewImage::write_png`]; [`contact_sheet`] puts frames in a labelled grid.
//!
//! # How a frame is drawn
//!
//! 0. A depth map along the key light gives hair self-shadowing and hair shadows on the meshes
//!    (a one-layer deep opacity map; `HairLook::shadow_depth`).
//! 1. Meshes are projected, clipped at the near plane and filled with a z-buffer, lit by
//!    two-sided Lambert plus ambient.
//! 2. Strand segments are projected, shaded with Kajiya–Kay (Kajiya & Kay 1989) from their
//!    tangents, sorted far to near and drawn as anti-aliased thick lines whose width is the
//!    projected strand diameter; each fragment is depth-tested against the meshes and blended
//!    with "over", so hair behind the head is hidden and near hair covers far hair.
//! 3. Highlights are drawn last without depth test, so a point buried in a collider still shows.
//!
//! The image is split into bands of rows drawn in parallel (rayon, the caller's pool); the result
//! does not depend on the thread count. Colors are linear RGB throughout and become sRGB at the
//! end.
//!
//! # Limits
//!
//! Shadows assume hair of even density behind the nearest hair to the light (no deep layers);
//! mesh edges are not anti-aliased; and hair–hair order is by segment mid depth, which is wrong only
//! where two segments cross in depth within one pixel.

mod camera;
mod canvas;
mod error;
mod image;
mod mesh_raster;
mod scene;
mod shading;
mod shadow;
mod sheet;
mod strand_raster;

pub use camera::{Camera, View, DEFAULT_FOV_Y_DEG, FRAME_MARGIN};
pub use error::{Nothing, PngWriteError, PreviewError, PreviewInputError, Result};
pub use image::{PreviewImage, MAX_SIDE};
pub use scene::{Bounds, Highlight, Mesh, Rgb, Scene, StrandBuffers, Strands};
pub use shading::{HairLook, Light, RenderSettings};
pub use sheet::{contact_sheet, Tile, FONT, GAP, LABEL_HEIGHT};

use camera::Projection;
use canvas::{bin_by_band, Canvas};
use shading::WorldLight;

/// Renders `scene` seen by `camera`.
///
/// Fails on an empty scene, highlight arrays that do not fit the strands, bad settings, a
/// degenerate camera, or a camera inside the bounds of a mesh (it would see the mesh's inside).
pub fn render(scene: &Scene, camera: &Camera, settings: &RenderSettings) -> Result<PreviewImage> {
    scene.validate()?;
    settings.validate()?;
    let proj = Projection::new(camera, settings.width, settings.height)?;
    for (i, mesh) in scene.meshes.iter().enumerate() {
        let b = mesh.bounds();
        if b.contains(&camera.eye) {
            return Err(PreviewError::Camera {
                problem: format!(
                    "the eye {:?} is inside the bounds of mesh {i} ({:?} to {:?} m)",
                    camera.eye, b.min, b.max
                ),
                fix: "place the camera outside every mesh, or use a preset view, which frames \
                      the scene from outside",
            });
        }
    }
    let basis = proj.basis;
    let light = WorldLight::new(&settings.light, &basis.right, &basis.up, &basis.forward);
    let (w, h) = (settings.width as usize, settings.height as usize);
    let mut canvas = Canvas::new(w, h, settings.background);
    let bands = canvas.band_count();

    let shadows = (settings.hair.shadow_depth > 0.0).then(|| {
        let bounds = scene
            .bounds()
            .expect("a validated scene has strands or meshes");
        shadow::ShadowMap::build(
            scene.strands.as_ref(),
            &scene.meshes,
            &bounds,
            light.to_light,
            settings.hair.shadow_depth,
        )
    });
    let shadows = shadows.as_ref();
    let triangles = mesh_raster::project_meshes(&scene.meshes, &proj);
    let tri_bins = bin_by_band(triangles.iter().map(|t| t.rows()), h, bands);
    let (segments, marks) = match &scene.strands {
        Some(strands) => (
            strand_raster::project_strands(strands, &proj, &light, &settings.hair, shadows),
            strand_raster::project_marks(strands, &scene.highlight, &proj, &settings.hair),
        ),
        None => (Vec::new(), Vec::new()),
    };
    let seg_bins = bin_by_band(segments.iter().map(|s| s.rows()), h, bands);
    let mark_bins = bin_by_band(marks.iter().map(|s| s.rows()), h, bands);
    canvas.for_each_band(|band| {
        let b = band.y0 / canvas::BAND_ROWS;
        for &t in &tri_bins[b] {
            mesh_raster::fill(band, &triangles[t as usize], &light, &basis, shadows);
        }
        for &s in &seg_bins[b] {
            strand_raster::draw(band, &segments[s as usize]);
        }
        for &m in &mark_bins[b] {
            strand_raster::draw(band, &marks[m as usize]);
        }
    });
    PreviewImage::from_rgba(settings.width, settings.height, canvas.to_rgba8())
}

/// Renders `scene` from the preset `view` with [`DEFAULT_FOV_Y_DEG`], framed to `framing` (one
/// box for every frame of a run) or, without it, to the scene itself ([`frame`]).
pub fn render_view(
    scene: &Scene,
    view: View,
    framing: Option<&Bounds>,
    settings: &RenderSettings,
) -> Result<PreviewImage> {
    let camera = frame(scene, view, framing, settings)?;
    render(scene, &camera, settings)
}

/// The camera [`render_view`] uses: from the preset `view`, framed to the box `framing`, or
/// without it fitted to every strand point and mesh vertex of `scene` and centred on them.
pub fn frame(
    scene: &Scene,
    view: View,
    framing: Option<&Bounds>,
    settings: &RenderSettings,
) -> Result<Camera> {
    scene.validate()?;
    let (w, h) = (settings.width, settings.height);
    if let Some(b) = framing {
        return Camera::framed(view, b, w, h, DEFAULT_FOV_Y_DEG);
    }
    let bounds = scene
        .bounds()
        .expect("a validated scene has strands or meshes");
    let mut groups: Vec<&[nalgebra::Vector3<f32>]> =
        scene.meshes.iter().map(|m| m.positions()).collect();
    groups.extend(scene.strands.as_ref().map(|s| s.positions()));
    Camera::framed_to_points(view, &groups, &bounds, w, h, DEFAULT_FOV_Y_DEG)
}
