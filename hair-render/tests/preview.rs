//! The CPU preview renderer, checked by geometric facts rather than pixel snapshots: where a
//! strand projects, what hides what, which side a preset sees, how much a line covers, and the
//! errors for bad cameras and empty frames.

use hair_render::preview::{
    contact_sheet, render, render_view, Camera, HairLook, Highlight, Light, Mesh, PreviewError,
    PreviewImage, RenderSettings, Scene, Strands, Tile, View, GAP, LABEL_HEIGHT,
};
use nalgebra::Vector3;

const W: u32 = 101;
const H: u32 = 101;

/// Flat lighting (ambient 1, no key light, no specular), black background, white hair 1 px wide
/// at 1 m: a pixel's linear value is exactly its hair coverage.
fn flat(width: u32, height: u32) -> RenderSettings {
    RenderSettings {
        width,
        height,
        background: [0.0; 3],
        light: Light {
            intensity: 0.0,
            ambient: 1.0,
            ..Default::default()
        },
        hair: HairLook {
            root_color: [1.0; 3],
            tip_color: [1.0; 3],
            specular: 0.0,
            default_radius: 0.5 / focal(),
            ..Default::default()
        },
    }
}

/// Camera 1 m in front of the origin on −Y, looking at it, Z up, 30° field of view.
fn camera() -> Camera {
    Camera::look_at(
        Vector3::new(0.0, -1.0, 0.0),
        Vector3::zeros(),
        Vector3::z(),
        30.0,
    )
    .unwrap()
}

/// Focal length of [`camera`] in pixels for an image `H` tall.
fn focal() -> f32 {
    0.5 * H as f32 / 15f32.to_radians().tan()
}

/// `n` points evenly from `a` to `b`.
fn line(a: Vector3<f32>, b: Vector3<f32>, n: usize) -> Vec<Vector3<f32>> {
    (0..n)
        .map(|i| a + (b - a) * (i as f32 / (n - 1) as f32))
        .collect()
}

/// A square of side `2 h` in the plane y = `y`, facing −Y.
fn wall(y: f32, h: f32) -> (Vec<Vector3<f32>>, Vec<[u32; 3]>) {
    let p = vec![
        Vector3::new(-h, y, -h),
        Vector3::new(h, y, -h),
        Vector3::new(h, y, h),
        Vector3::new(-h, y, h),
    ];
    (p, vec![[0, 1, 2], [0, 2, 3]])
}

fn srgb_to_linear(v: u8) -> f32 {
    let s = v as f32 / 255.0;
    if s <= 0.04045 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

fn red(px: [u8; 4]) -> bool {
    px[0] > 100 && (px[0] as u32) > 3 * px[1] as u32 && (px[0] as u32) > 3 * px[2] as u32
}

#[test]
fn horizontal_strand_lights_its_projected_line_and_nothing_far_from_it() {
    let pts = line(Vector3::new(-0.1, 0.0, 0.0), Vector3::new(0.1, 0.0, 0.0), 5);
    let scene = Scene {
        strands: Some(Strands::new(&pts, &[0, 5]).unwrap()),
        ..Default::default()
    };
    let img = render(&scene, &camera(), &flat(W, H)).unwrap();
    // The strand projects to row 50 (centre 50.5), x = 50.5 ± 0.1 · focal.
    let half = 0.1 * focal();
    let (x0, x1) = (50.5 - half, 50.5 + half);
    for x in (x0.ceil() as u32 + 1)..(x1.floor() as u32 - 1) {
        let column: f32 = (48..=52)
            .map(|y| srgb_to_linear(img.pixel(x, y).unwrap()[0]))
            .sum();
        assert!(
            (column - 1.0).abs() < 0.05,
            "column {x} covers {column}, a 1 px line covers 1"
        );
    }
    for y in 0..H {
        for x in 0..W {
            let far = (y as f32 + 0.5 - 50.5).abs() > 2.0
                || (x as f32 + 0.5) < x0 - 2.0
                || (x as f32 + 0.5) > x1 + 2.0;
            if far {
                assert_eq!(
                    img.pixel(x, y).unwrap(),
                    [0, 0, 0, 255],
                    "pixel {x},{y} lit"
                );
            }
        }
    }
}

#[test]
fn line_coverage_matches_projected_width() {
    // A vertical strand 1 m away; radius r projects to 2 r · focal pixels.
    for width_px in [0.3f32, 1.0, 4.0] {
        let r = 0.5 * width_px / focal();
        let pts = line(Vector3::new(0.0, 0.0, -0.1), Vector3::new(0.0, 0.0, 0.1), 3);
        let radii = vec![r; 3];
        let scene = Scene {
            strands: Some(
                Strands::new(&pts, &[0, 3])
                    .unwrap()
                    .with_radii(&radii)
                    .unwrap(),
            ),
            ..Default::default()
        };
        let img = render(&scene, &camera(), &flat(W, H)).unwrap();
        for y in [40, 45, 50, 55, 60] {
            let row: f32 = (0..W)
                .map(|x| srgb_to_linear(img.pixel(x, y).unwrap()[0]))
                .sum();
            assert!(
                (row - width_px).abs() < 0.05 * width_px.max(1.0),
                "{width_px} px line covers {row} px in row {y}"
            );
        }
    }
}

#[test]
fn collinear_points_leave_no_beads_at_the_joints() {
    let settings = flat(W, H);
    let draw = |n| {
        let pts = line(
            Vector3::new(-0.1, 0.0, -0.08),
            Vector3::new(0.1, 0.0, 0.07),
            n,
        );
        let radii = vec![2.0 / focal(); n];
        let offsets = [0, n as u32];
        let scene = Scene {
            strands: Some(
                Strands::new(&pts, &offsets)
                    .unwrap()
                    .with_radii(&radii)
                    .unwrap(),
            ),
            ..Default::default()
        };
        render(&scene, &camera(), &settings).unwrap()
    };
    let (two, nine) = (draw(2), draw(9));
    for (a, b) in two.pixels().iter().zip(nine.pixels()) {
        assert!(
            a.abs_diff(*b) <= 2,
            "a joint changed a pixel from {a} to {b}"
        );
    }
}

#[test]
fn strand_behind_an_opaque_mesh_is_hidden_and_in_front_is_visible() {
    let (wp, wt) = wall(0.0, 0.2);
    let settings = RenderSettings {
        width: W,
        height: H,
        ..flat(W, H)
    };
    let mesh = Mesh::new(0, &wp, &wt, [0.2, 0.2, 0.6]).unwrap();
    let only_wall = render(
        &Scene {
            meshes: vec![mesh],
            ..Default::default()
        },
        &camera(),
        &settings,
    )
    .unwrap();
    let with_strand = |y: f32| {
        let pts = line(Vector3::new(0.0, y, -0.1), Vector3::new(0.0, y, 0.1), 4);
        let radii = vec![2.0 / focal(); 4];
        let scene = Scene {
            strands: Some(
                Strands::new(&pts, &[0, 4])
                    .unwrap()
                    .with_radii(&radii)
                    .unwrap(),
            ),
            meshes: vec![mesh],
            ..Default::default()
        };
        render(&scene, &camera(), &settings).unwrap()
    };
    assert_eq!(
        with_strand(0.1),
        only_wall,
        "a strand behind the wall shows"
    );
    let front = with_strand(-0.1);
    let centre = front.pixel(50, 50).unwrap();
    assert_ne!(centre, only_wall.pixel(50, 50).unwrap());
    assert!(
        centre[..3].iter().all(|&c| c > 250),
        "{centre:?} is not the white hair"
    );
}

#[test]
fn near_hair_covers_far_hair_whatever_the_input_order() {
    let near = line(
        Vector3::new(-0.1, -0.1, 0.0),
        Vector3::new(0.1, -0.1, 0.0),
        3,
    );
    let far = line(Vector3::new(0.0, 0.1, -0.1), Vector3::new(0.0, 0.1, 0.1), 3);
    let radii = vec![2.0 / focal(); 6];
    for near_first in [true, false] {
        let (mut pts, mut colors) = (Vec::new(), Vec::new());
        for (p, c) in if near_first {
            [(&near, [1.0, 0.0, 0.0]), (&far, [0.0, 0.0, 1.0])]
        } else {
            [(&far, [0.0, 0.0, 1.0]), (&near, [1.0, 0.0, 0.0])]
        } {
            pts.extend_from_slice(p);
            colors.extend([c; 3]);
        }
        let strands = Strands::new(&pts, &[0, 3, 6])
            .unwrap()
            .with_radii(&radii)
            .unwrap()
            .with_colors(&colors)
            .unwrap();
        let scene = Scene {
            strands: Some(strands),
            ..Default::default()
        };
        let img = render(&scene, &camera(), &flat(W, H)).unwrap();
        assert!(red(img.pixel(50, 50).unwrap()), "near_first = {near_first}");
    }
}

/// The built-in head with a red marker square on the side `side` (unit axis) just off its
/// surface, facing out.
fn marked_head(side: Vector3<f32>) -> (hair_core::TriMesh, Vec<Vector3<f32>>, Vec<[u32; 3]>) {
    let head = hair_groom::builtin_head();
    let centre = Vector3::new(0.0, 0.0, 0.11);
    // Farthest vertex along `side`, then a 4 cm square 2 mm outside it.
    let tip = head
        .positions()
        .iter()
        .max_by(|a, b| {
            (*a - centre)
                .dot(&side)
                .total_cmp(&(*b - centre).dot(&side))
        })
        .copied()
        .unwrap();
    let o = tip + side * 0.002;
    let u = side.cross(&Vector3::z()).normalize() * 0.02;
    let v = Vector3::z() * 0.02;
    let p = vec![o - u - v, o + u - v, o + u + v, o - u + v];
    (head, p, vec![[0, 1, 2], [0, 2, 3]])
}

fn red_pixels(img: &PreviewImage) -> usize {
    (0..img.height())
        .flat_map(|y| (0..img.width()).map(move |x| (x, y)))
        .filter(|&(x, y)| red(img.pixel(x, y).unwrap()))
        .count()
}

#[test]
fn front_view_sees_the_face_and_back_view_does_not() {
    let settings = RenderSettings {
        width: 120,
        height: 120,
        ..Default::default()
    };
    for (side, sees, hidden) in [
        (-Vector3::y(), View::Front, View::Back),
        (Vector3::y(), View::Back, View::Front),
        (
            Vector3::x(),
            View::Side,
            View::Orbit {
                azimuth_deg: -90.0,
                elevation_deg: 10.0,
            },
        ),
    ] {
        let (head, mp, mt) = marked_head(side);
        let scene = Scene {
            meshes: vec![
                Mesh::from_trimesh(0, &head, [0.6, 0.45, 0.35]).unwrap(),
                Mesh::new(1, &mp, &mt, [1.0, 0.0, 0.0]).unwrap(),
            ],
            ..Default::default()
        };
        let seen = red_pixels(&render_view(&scene, sees, None, &settings).unwrap());
        let unseen = red_pixels(&render_view(&scene, hidden, None, &settings).unwrap());
        assert!(
            seen > 100,
            "{sees:?} sees {seen} marker pixels on side {side:?}"
        );
        assert_eq!(unseen, 0, "{hidden:?} sees the marker on side {side:?}");
    }
}

#[test]
fn highlights_show_through_the_mesh() {
    let (wp, wt) = wall(0.0, 0.2);
    let pts = line(Vector3::new(-0.1, 0.1, 0.0), Vector3::new(0.1, 0.1, 0.0), 3);
    let mut scene = Scene {
        strands: Some(Strands::new(&pts, &[0, 3]).unwrap()),
        meshes: vec![Mesh::new(0, &wp, &wt, [0.3, 0.3, 0.3]).unwrap()],
        ..Default::default()
    };
    let settings = flat(W, H);
    assert_eq!(
        red_pixels(&render(&scene, &camera(), &settings).unwrap()),
        0
    );
    // Point 2 (x = 0.1) inside a collider: a red dot at its projection only.
    let points = [false, false, true];
    scene.highlight = Highlight {
        points: Some(&points),
        segments: None,
    };
    let img = render(&scene, &camera(), &settings).unwrap();
    let x = (50.5 + 0.1 * focal() * 1.0 / 1.1) as u32;
    assert!(red(img.pixel(x, 50).unwrap()));
    assert!(!red(img.pixel(50, 50).unwrap()));
    // Segment 0 (x from −0.1 to 0) over-stretched: red along its left half.
    let segments = [true, false];
    scene.highlight = Highlight {
        points: None,
        segments: Some(&segments),
    };
    let img = render(&scene, &camera(), &settings).unwrap();
    assert!(red(img.pixel(40, 50).unwrap()) && !red(img.pixel(60, 50).unwrap()));
    let wrong = [true];
    scene.highlight.segments = Some(&wrong);
    let e = render(&scene, &camera(), &settings)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("1 highlight segment flags for 2 segments"),
        "{e}"
    );
}

#[test]
fn image_does_not_depend_on_thread_count() {
    let head = hair_groom::builtin_head();
    let pts: Vec<_> = (0..200)
        .flat_map(|s| {
            let a = s as f32 * 0.1;
            let root = Vector3::new(0.07 * a.cos(), 0.09 * a.sin(), 0.16);
            line(root, root + Vector3::new(0.05 * a.cos(), 0.05, -0.15), 9)
        })
        .collect();
    let offsets: Vec<u32> = (0..=200).map(|s| 9 * s).collect();
    let scene = Scene {
        strands: Some(Strands::new(&pts, &offsets).unwrap()),
        meshes: vec![Mesh::from_trimesh(0, &head, [0.6, 0.45, 0.35]).unwrap()],
        ..Default::default()
    };
    let settings = RenderSettings {
        width: 160,
        height: 120,
        ..Default::default()
    };
    let draw = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| render_view(&scene, View::ThreeQuarter, None, &settings).unwrap())
    };
    assert_eq!(draw(1), draw(2));
}

#[test]
fn camera_inside_the_head_is_refused() {
    let head = hair_groom::builtin_head();
    let scene = Scene {
        meshes: vec![Mesh::from_trimesh(0, &head, [0.6, 0.45, 0.35]).unwrap()],
        ..Default::default()
    };
    let inside = Camera::look_at(
        Vector3::new(0.0, 0.0, 0.1),
        Vector3::new(0.0, -1.0, 0.1),
        Vector3::z(),
        30.0,
    )
    .unwrap();
    let e = render(&scene, &inside, &RenderSettings::default()).unwrap_err();
    assert!(matches!(e, PreviewError::Camera { .. }), "{e}");
    assert!(e.to_string().contains("inside the bounds of mesh 0"), "{e}");
}

#[test]
fn empty_frames_are_refused() {
    let e = render_view(
        &Scene::default(),
        View::Front,
        None,
        &RenderSettings::default(),
    )
    .unwrap_err();
    assert!(matches!(e, PreviewError::Empty(_)), "{e}");
    let e = Strands::new(&[], &[0]).unwrap_err();
    assert!(matches!(e, PreviewError::Empty(_)), "{e}");
    let one = [Vector3::zeros()];
    let e = Strands::new(&one, &[0, 1]).unwrap_err().to_string();
    assert!(e.contains("strand 0") && e.contains("at least 2"), "{e}");
    let nan = [Vector3::zeros(), Vector3::new(0.0, f32::NAN, 0.0)];
    let e = Strands::new(&nan, &[0, 2]).unwrap_err().to_string();
    assert!(e.contains("non-finite"), "{e}");
}

#[test]
fn bad_settings_and_meshes_are_named() {
    let pts = line(Vector3::zeros(), Vector3::z(), 2);
    let scene = Scene {
        strands: Some(Strands::new(&pts, &[0, 2]).unwrap()),
        ..Default::default()
    };
    let big = RenderSettings {
        width: 100_000,
        ..Default::default()
    };
    let e = render(&scene, &camera(), &big).unwrap_err().to_string();
    assert!(e.contains("settings.width"), "{e}");
    let (wp, _) = wall(0.0, 1.0);
    let e = Mesh::new(3, &wp, &[[0, 1, 9]], [0.5; 3])
        .unwrap_err()
        .to_string();
    assert!(e.contains("mesh 3") && e.contains("triangle 0"), "{e}");
}

#[test]
fn contact_sheet_has_the_grid_size_and_the_tiles_in_place() {
    let tiles: Vec<PreviewImage> = (0..5u8)
        .map(|i| PreviewImage::filled(30, 20, [40 * i, 200, 10, 255]).unwrap())
        .collect();
    let labels: Vec<String> = (0..5).map(|i| format!("frame {i}")).collect();
    let t: Vec<Tile> = tiles
        .iter()
        .zip(&labels)
        .map(|(image, label)| Tile { image, label })
        .collect();
    let sheet = contact_sheet(&t, 3).unwrap();
    assert_eq!(sheet.width(), 3 * 30 + 4 * GAP);
    assert_eq!(sheet.height(), 2 * (20 + LABEL_HEIGHT) + 3 * GAP);
    // Tile 4 is row 1, column 1; its pixels are copied unchanged.
    let (x, y) = (
        GAP + 30 + GAP + 5,
        GAP + 20 + LABEL_HEIGHT + GAP + LABEL_HEIGHT + 5,
    );
    assert_eq!(sheet.pixel(x, y).unwrap(), [160, 200, 10, 255]);
    // Labels put light pixels in the strip above each tile.
    let strip_light = (0..LABEL_HEIGHT)
        .flat_map(|dy| (0..30).map(move |dx| (GAP + dx, GAP + dy)))
        .filter(|&(x, y)| sheet.pixel(x, y).unwrap()[0] > 150)
        .count();
    assert!(
        strip_light > 10,
        "no label text ({strip_light} light pixels)"
    );
    // Fewer tiles than columns: the sheet is as wide as the tiles.
    assert_eq!(contact_sheet(&t[..2], 8).unwrap().width(), 2 * 30 + 3 * GAP);
    let odd = PreviewImage::filled(31, 20, [0; 4]).unwrap();
    let mut mixed = t.clone();
    mixed.push(Tile {
        image: &odd,
        label: "odd",
    });
    let e = contact_sheet(&mixed, 3).unwrap_err().to_string();
    assert!(e.contains("tile 5 is 31 × 20"), "{e}");
    assert!(matches!(contact_sheet(&[], 3), Err(PreviewError::Empty(_))));
}

#[test]
fn png_round_trip_keeps_size_and_pixels() {
    let pts = line(
        Vector3::new(-0.1, 0.0, -0.1),
        Vector3::new(0.1, 0.0, 0.1),
        4,
    );
    let scene = Scene {
        strands: Some(Strands::new(&pts, &[0, 4]).unwrap()),
        ..Default::default()
    };
    let img = render(
        &scene,
        &camera(),
        &RenderSettings {
            width: 64,
            height: 48,
            ..Default::default()
        },
    )
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("frame.png");
    img.write_png(&path).unwrap();
    assert!(!dir.path().join("frame.png.partial").exists());
    let decoder = png::Decoder::new(std::fs::File::open(&path).unwrap());
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (64, 48));
    assert_eq!(info.color_type, png::ColorType::Rgba);
    assert_eq!(&buf[..info.buffer_size()], img.pixels());
    let e = img
        .write_png(&dir.path().join("missing/dir/frame.png"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing/dir/frame.png"), "{e}");
}

#[test]
fn geometry_reaching_behind_the_camera_is_clipped_at_the_near_plane() {
    // A strand parallel to the view, 5 cm right of the axis, from 1 m behind the eye to the
    // origin: in front of the eye it projects to the ray from x = 50.5 + 0.05 · focal to the
    // right edge along row 50. Its radius keeps it under 1 px wide everywhere in view.
    let pts = line(
        Vector3::new(0.05, -2.0, 0.0),
        Vector3::new(0.05, 0.0, 0.0),
        9,
    );
    let radii = [2e-4; 9];
    let scene = Scene {
        strands: Some(
            Strands::new(&pts, &[0, 9])
                .unwrap()
                .with_radii(&radii)
                .unwrap(),
        ),
        ..Default::default()
    };
    let img = render(&scene, &camera(), &flat(W, H)).unwrap();
    let start = 50.5 + 0.05 * focal();
    for x in (start.ceil() as u32 + 1)..W {
        assert!(
            img.pixel(x, 50).unwrap()[0] > 0,
            "column {x} of the ray is dark"
        );
    }
    for y in 0..H {
        for x in 0..W {
            if (x as f32 + 0.5) < start - 2.0 || (y as f32 + 0.5 - 50.5).abs() > 2.0 {
                assert_eq!(img.pixel(x, y).unwrap()[0], 0, "pixel {x},{y} lit");
            }
        }
    }
    // A floor 20 cm below the eye running from behind it to far ahead fills the lower half of
    // the image up to its horizon (row 50) and nothing above.
    let floor = vec![
        Vector3::new(-5.0, -3.0, -0.2),
        Vector3::new(5.0, -3.0, -0.2),
        Vector3::new(5.0, 50.0, -0.2),
        Vector3::new(-5.0, 50.0, -0.2),
    ];
    let tris = [[0, 1, 2], [0, 2, 3]];
    let scene = Scene {
        meshes: vec![Mesh::new(0, &floor, &tris, [0.5, 0.5, 0.5]).unwrap()],
        ..Default::default()
    };
    let img = render(&scene, &camera(), &flat(W, H)).unwrap();
    assert!(
        (0..W).all(|x| img.pixel(x, H - 1).unwrap()[0] > 0),
        "floor missing"
    );
    assert!(
        (0..W).all(|x| img.pixel(x, 48).unwrap()[0] == 0),
        "floor above the horizon"
    );
}

#[test]
fn render_children_become_strands_with_half_their_width() {
    use hair_render::{generate, ChildBuffers, ChildCount, ChildSettings, Lod, Parents};
    let parents: Vec<_> = (0..2)
        .flat_map(|p| {
            line(
                Vector3::new(0.02 * p as f32, 0.0, 0.0),
                Vector3::new(0.0, 0.0, -0.1),
                5,
            )
        })
        .collect();
    let settings = ChildSettings {
        count: ChildCount::PerParent(3),
        ..Default::default()
    };
    let children = generate(
        &Parents::new(&parents, &[0, 5, 10]).unwrap(),
        &settings,
        Lod::Render,
    )
    .unwrap();
    let buffers = hair_render::preview::StrandBuffers::from_children(&children).unwrap();
    let strands = buffers.strands().unwrap();
    assert_eq!(strands.len(), 6);
    assert_eq!(strands.point_count(), children.point_count());
    assert_eq!(buffers.radii[0], 0.5 * children.widths[0]);
    assert_eq!(buffers.positions[7].x, children.points[21]);
    let broken = ChildBuffers {
        vertex_counts: vec![3],
        ..children.clone()
    };
    let e = hair_render::preview::StrandBuffers::from_children(&broken).unwrap_err();
    assert!(e.to_string().contains("add up to 3 points"), "{e}");
}
