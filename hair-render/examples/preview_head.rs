//! Renders hair on the built-in head to PNG with the CPU preview renderer: the groomed rest state
//! from the four preset views, then the same hair after one second of simulation under gravity
//! with the head as a collider, as a contact sheet.
//!
//! Run: `cargo run --release -p hair-render --example preview_head -- [OUT_DIR]`
//! (default `target/preview_head/`): writes `rest_front.png`, `settled_three_quarter.png`,
//! `children_three_quarter.png` (12 render children per strand) and `sheet.png` (rest and
//! settled from the four presets, one framing).

use std::path::PathBuf;

use hair_core::{
    Anchor, Collider, Colliders, HairParams, MassSpringSolver, MeshSample, Scalp, SolverSettings,
    StrandSet, TriMesh,
};
use hair_groom::{builtin_head, generate_guides, GrowDirection, GuideOptions, Region};
use hair_render::preview::{
    contact_sheet, render, render_view, Bounds, Camera, Mesh, PreviewError, RenderSettings, Scene,
    StrandBuffers, Strands, Tile, View, DEFAULT_FOV_Y_DEG,
};
use hair_render::{generate, ChildCount, ChildSettings, Clump, Lod, Parents, ScalpRoots, Shape};
use nalgebra::{Isometry3, Vector3};

/// Skin tone of the head, linear RGB.
const SKIN: [f32; 3] = [0.62, 0.42, 0.32];
/// Strand radius drawn, m: a simulated strand stands for many hairs, so it is drawn thicker
/// than one hair (0.4 mm).
const RADIUS: f32 = 4e-4;

/// The head and the strands at `positions`.
fn scene<'a>(
    positions: &'a [Vector3<f32>],
    offsets: &'a [u32],
    radii: &'a [f32],
    head: &'a TriMesh,
) -> Result<Scene<'a>, PreviewError> {
    Ok(Scene {
        strands: Some(Strands::new(positions, offsets)?.with_radii(radii)?),
        meshes: vec![Mesh::from_trimesh(0, head, SKIN)?],
        ..Default::default()
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .map_or_else(|| PathBuf::from("target/preview_head"), PathBuf::from);
    std::fs::create_dir_all(&out)?;
    let head = builtin_head();

    // 1,500 guides of 17 points on the top and back of the head (not the face), combed back and
    // down.
    let guides = generate_guides(
        &head,
        &GuideOptions {
            count: 1500,
            length: 0.22,
            segments: 16,
            seed: 3,
            region: Region::Cone {
                direction: Vector3::new(0.0, 0.6, 1.0),
                max_angle_deg: 66.0,
            },
            direction: GrowDirection::Combed {
                direction: Vector3::new(0.0, 0.5, -1.0),
                angle_deg: 75.0,
            },
            curl: None,
        },
    )?;
    let mut strands = StrandSet::new();
    for g in &guides {
        strands.push(g.to_strand_input(2e-4, RADIUS, 0.3, 0.0))?;
    }
    let scalp = Scalp {
        mesh: Some(head.clone()),
        body: Isometry3::identity(),
    };
    strands.reset_to_rest(&scalp);
    let rest = strands.positions.clone();

    // One second at 24 fps under gravity, the head a collider.
    let mut colliders = Colliders::new();
    colliders.insert(Collider::mesh(head.clone()), Isometry3::identity())?;
    let mut solver = MassSpringSolver::new(
        SolverSettings::default(),
        HairParams {
            air_drag: 1.0,
            ..HairParams::default()
        },
        &strands,
        &scalp,
        1,
    )?;
    for _ in 2..=24 {
        solver.step_frame_with_colliders(&mut strands, &scalp, &mut colliders)?;
    }

    let settings = RenderSettings::default();
    let radii = strands.radii();
    let offsets = strands.offsets();
    let (at_rest, settled) = (
        scene(&rest, offsets, radii, &head)?,
        scene(&strands.positions, offsets, radii, &head)?,
    );
    // One framing for both states, so the sheet compares like with like.
    let bounds: Bounds = at_rest
        .bounds()
        .zip(settled.bounds())
        .map(|(a, b)| a.union(&b))
        .expect("both scenes have hair");
    let camera = |view| {
        Camera::framed(
            view,
            &bounds,
            settings.width,
            settings.height,
            DEFAULT_FOV_Y_DEG,
        )
    };

    let start = std::time::Instant::now();
    let front = render(&at_rest, &camera(View::Front)?, &settings)?;
    println!(
        "rest, front: {} strands × 17 points, {}×{} in {:.0} ms",
        strands.len(),
        settings.width,
        settings.height,
        start.elapsed().as_secs_f64() * 1e3
    );
    front.write_png(&out.join("rest_front.png"))?;
    // The settled hair framed to itself.
    render_view(&settled, View::ThreeQuarter, None, &settings)?
        .write_png(&out.join("settled_three_quarter.png"))?;

    // Render children of the settled hair, as `hairsys preview` draws exported children.
    let samples: Vec<Option<MeshSample>> = strands
        .anchors()
        .iter()
        .map(|a| match a {
            Anchor::Surface(s) => Some(*s),
            Anchor::Body(_) => None,
        })
        .collect();
    let parents = Parents::new(&strands.positions, offsets)?.with_scalp(ScalpRoots {
        mesh: &head,
        samples: &samples,
        colors: None,
    })?;
    let children = generate(
        &parents,
        &ChildSettings {
            count: ChildCount::PerParent(12),
            spread: 0.006,
            subdivisions: 2,
            shape: Shape {
                clump: Clump {
                    factor: 0.5,
                    shape: 0.8,
                },
                ..Default::default()
            },
            ..Default::default()
        },
        Lod::Render,
    )?;
    let child_strands = StrandBuffers::from_children(&children)?;
    let child_scene = Scene {
        strands: Some(child_strands.strands()?),
        meshes: vec![Mesh::from_trimesh(0, &head, SKIN)?],
        ..Default::default()
    };
    let start = std::time::Instant::now();
    let image = render_view(&child_scene, View::ThreeQuarter, None, &settings)?;
    println!(
        "children, three-quarter: {} curves, {} points in {:.0} ms",
        children.curve_count(),
        children.point_count(),
        start.elapsed().as_secs_f64() * 1e3
    );
    image.write_png(&out.join("children_three_quarter.png"))?;

    let mut images = Vec::new();
    for (name, scene) in [("rest", &at_rest), ("1 s", &settled)] {
        for view in View::PRESETS {
            images.push((
                format!("{name}, {view}"),
                render(scene, &camera(view)?, &settings)?,
            ));
        }
    }
    let tiles: Vec<Tile> = images
        .iter()
        .map(|(label, image)| Tile { image, label })
        .collect();
    contact_sheet(&tiles, 4)?.write_png(&out.join("sheet.png"))?;
    println!("wrote {}", out.display());
    Ok(())
}
