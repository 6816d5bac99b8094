//! Deforming mesh colliders and a deforming scalp (see `hair_core::contacts::deforming`).
//!
//! References: an independent parry check of every free hair point against the mesh as the host
//! gave it at each frame's end (an oriented parry `TriMesh`, pseudo-normal inside test); the
//! same motion done by a rigid pose; the barycentric root invariant (a root is its mesh sample
//! evaluated on the frame's mesh); bit-identity of a resumed run.

mod common;

use common::bits;
use hair_core::{
    Anchor, Collider, ColliderId, Colliders, HairError, HairParams, MassSpringSolver, MeshSample,
    RodParams, RodSolver, RootFrame, Scalp, SolverSettings, StrandInput, StrandSet, TriMesh,
};
use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use parry3d::math::Vector;
use parry3d::query::PointQuery;
use parry3d::shape::{TriMesh as ParryMesh, TriMeshFlags};

const FPS: f32 = 24.0;
const HAIR_RADIUS: f32 = 1e-3;

fn params() -> HairParams {
    HairParams {
        gravity: [0.0, 0.0, -9.81],
        stretch_stiffness: 40.0,
        bend_stiffness: 0.02,
        goal_stiffness: 0.0,
        stretch_damping: 200.0,
        air_drag: 1.0,
    }
}

fn settings() -> SolverSettings {
    SolverSettings {
        fps: FPS,
        ..SolverSettings::default()
    }
}

/// A straight strand of `segments` segments of `length` m along root-local z.
fn strand(anchor: Anchor, segments: usize, length: f32) -> StrandInput {
    let rest = (0..=segments)
        .map(|i| Vector3::z() * (length * i as f32 / segments as f32))
        .collect();
    StrandInput::uniform(anchor, rest, 1e-3, HAIR_RADIUS, 0.0, 0.0)
}

/// A root frame at `origin` whose local z points along `dir`.
fn along(origin: Vector3<f32>, dir: Vector3<f32>) -> Anchor {
    let rotation = UnitQuaternion::rotation_between(&Vector3::z(), &dir.normalize())
        .unwrap_or_else(UnitQuaternion::identity);
    Anchor::Body(RootFrame { origin, rotation })
}

/// Signed distance (m, negative inside) of every free point of `strands` to `mesh` (world),
/// by parry's oriented point projection: the smallest, and how many are inside.
fn gap_to(mesh: &TriMesh, strands: &StrandSet) -> (f32, usize) {
    let vertices = mesh
        .positions()
        .iter()
        .map(|p| Vector::new(p.x, p.y, p.z))
        .collect();
    let parry = ParryMesh::with_flags(vertices, mesh.triangles().to_vec(), TriMeshFlags::ORIENTED)
        .expect("closed mesh");
    let mut smallest = f32::INFINITY;
    let mut inside = 0;
    for (i, x) in strands.positions.iter().enumerate() {
        if strands.inverse_masses()[i] == 0.0 {
            continue;
        }
        let p = Vector::new(x.x, x.y, x.z);
        let proj = parry.project_local_point(p, false);
        let d = (proj.point - p).length();
        let signed = if proj.is_inside { -d } else { d };
        smallest = smallest.min(signed);
        inside += usize::from(proj.is_inside);
    }
    (smallest, inside)
}

/// The free points of `strands`.
fn free(strands: &StrandSet) -> impl Iterator<Item = (usize, &Vector3<f32>)> {
    strands
        .positions
        .iter()
        .enumerate()
        .filter(|(i, _)| strands.inverse_masses()[*i] > 0.0)
}

// ---------------------------------------------------------------------------------------------
// An inflating and deflating sphere.

const BALL: f32 = 0.1;

/// Radius (m) of the breathing sphere at frame `f`: 0.1 m growing to 0.13 m and back over 24
/// frames.
fn breathing_radius(f: u32) -> f32 {
    let phase = std::f32::consts::TAU * f as f32 / 24.0;
    BALL * (1.0 + 0.15 * (1.0 - phase.cos()))
}

/// 24 strands hanging from roots 4 cm above the largest sphere, combed down its sides.
fn hair_over_ball() -> StrandSet {
    let mut set = StrandSet::new();
    for k in 0..24 {
        let phi = std::f32::consts::TAU * k as f32 / 24.0;
        let out = Vector3::new(phi.cos(), phi.sin(), 0.0);
        let root = Vector3::new(0.0, 0.0, 1.3 * BALL + 0.04) + out * 0.01;
        set.push(strand(along(root, out + Vector3::z() * 0.2), 20, 0.3))
            .unwrap();
    }
    set.reset_to_rest(&Scalp::fixed());
    set
}

/// Hair settles on the sphere for 12 frames, then the sphere breathes for 24; calls `each`
/// after every frame with the frame's mesh.
fn breathe(mut each: impl FnMut(u32, &TriMesh, &StrandSet, &hair_core::FrameReport)) {
    let rest = TriMesh::uv_sphere(BALL, 48, 24).unwrap();
    let mut strands = hair_over_ball();
    let scalp = Scalp::fixed();
    let mut solver = MassSpringSolver::new(settings(), params(), &strands, &scalp, 0).unwrap();
    let mut colliders = Colliders::new();
    let ball = colliders
        .insert(
            Collider::mesh(rest.clone()).with_friction(0.3),
            Isometry3::identity(),
        )
        .unwrap();
    for f in 1..=36u32 {
        let scale = breathing_radius(f.saturating_sub(12)) / BALL;
        let vertices: Vec<_> = rest.positions().iter().map(|p| p * scale).collect();
        colliders.set_vertices(ball, &vertices).unwrap();
        let report = solver
            .step_frame_with_colliders(&mut strands, &scalp, &mut colliders)
            .unwrap();
        let mut mesh = rest.clone();
        mesh.set_positions(&vertices).unwrap();
        each(f, &mesh, &strands, &report);
    }
}

#[test]
fn breathing_sphere_pushes_hair_out_and_no_point_ends_inside() {
    let mut worst = f32::INFINITY;
    let mut inside = 0;
    let mut pushed_out = 0usize;
    let mut resting: Vec<usize> = Vec::new();
    let mut max_steps = 0;
    breathe(|f, mesh, strands, report| {
        let (gap, n) = gap_to(mesh, strands);
        worst = worst.min(gap);
        inside += n;
        max_steps = max_steps.max(report.steps);
        // Points resting on the sphere while it is small must be outside it once it has grown:
        // the growing surface swept through where they were.
        if f == 12 {
            resting = free(strands)
                .filter(|(_, x)| x.norm() < BALL + 3.0 * HAIR_RADIUS)
                .map(|(i, _)| i)
                .collect();
        }
        if f == 24 {
            // The sphere is 0.13 m now: every point that rested on it at 0.1 m was swept.
            pushed_out = resting
                .iter()
                .filter(|&&i| strands.positions[i].norm() > breathing_radius(12) - 1e-3)
                .count();
        }
    });
    println!(
        "breathing sphere 0.10–0.13 m over 24 frames: smallest gap {:.3} mm, {inside} point-frames \
         inside, {} points resting on it at 0.10 m, {pushed_out} of them beyond 0.129 m at its \
         largest, up to {max_steps} steps per frame",
        worst * 1e3,
        resting.len()
    );
    assert_eq!(inside, 0, "smallest gap {worst} m");
    assert!(resting.len() > 50, "hair should rest on the sphere");
    assert_eq!(pushed_out, resting.len(), "resting hair must be pushed out");
}

#[test]
fn rod_hair_on_a_breathing_sphere_stays_outside() {
    // The rod model projects its nodes onto the shape in every substep and sees a deforming
    // mesh at the frame's end for the whole frame; its distance memory must not outlive a
    // reshape (a stale bound would skip a node the surface grew into).
    let rest = TriMesh::uv_sphere(BALL, 48, 24).unwrap();
    let mut strands = hair_over_ball();
    let scalp = Scalp::fixed();
    let mut solver = RodSolver::new(
        settings(),
        params(),
        RodParams::default(),
        &strands,
        &scalp,
        0,
    )
    .unwrap();
    let mut colliders = Colliders::new();
    let ball = colliders
        .insert(Collider::mesh(rest.clone()), Isometry3::identity())
        .unwrap();
    let mut worst = f32::INFINITY;
    for f in 1..=36u32 {
        let scale = breathing_radius(f.saturating_sub(12)) / BALL;
        let vertices: Vec<_> = rest.positions().iter().map(|p| p * scale).collect();
        colliders.set_vertices(ball, &vertices).unwrap();
        solver
            .step_frame_with_colliders(&mut strands, &scalp, &mut colliders)
            .unwrap();
        let mut mesh = rest.clone();
        mesh.set_positions(&vertices).unwrap();
        let (gap, inside) = gap_to(&mesh, &strands);
        worst = worst.min(gap);
        assert_eq!(
            inside, 0,
            "frame {f}: a rod node ended inside (gap {gap} m)"
        );
    }
    println!(
        "rod model on the breathing sphere: smallest gap {:.3} mm",
        worst * 1e3
    );
}

// ---------------------------------------------------------------------------------------------
// Fast-motion stepping.

/// Collision steps of the first frame of a sphere mesh (radius 0.1 m) grown by `grow` m within
/// it, with hair resting on it.
fn steps_for_growth(grow: f32) -> u32 {
    let rest = TriMesh::uv_sphere(BALL, 48, 24).unwrap();
    let mut strands = hair_over_ball();
    let scalp = Scalp::fixed();
    let mut solver = MassSpringSolver::new(settings(), params(), &strands, &scalp, 0).unwrap();
    let mut colliders = Colliders::new();
    let ball = colliders
        .insert(Collider::mesh(rest.clone()), Isometry3::identity())
        .unwrap();
    let scale = (BALL + grow) / BALL;
    let vertices: Vec<_> = rest.positions().iter().map(|p| p * scale).collect();
    colliders.set_vertices(ball, &vertices).unwrap();
    solver
        .step_frame_with_colliders(&mut strands, &scalp, &mut colliders)
        .unwrap()
        .steps
}

#[test]
fn fast_deformation_splits_the_frame_into_more_steps() {
    // Growing from R = 0.1 m to R + δ changes the bending 1/R by Δκ = δ/(R(R + δ)); the model
    // errs by Δκ δ²/2 in one step, against the default tolerance of half the hair radius
    // (0.5 mm). δ = 5 mm: 0.006 mm, one step. δ = 5 cm: 4.2 mm, so ⌈√8.3⌉ = 3 steps; the
    // bending measured on the 48 × 24 mesh's hinges scatters by about 10 % above 1/R near its
    // poles, which may make it 4.
    let slow = steps_for_growth(0.005);
    let fast = steps_for_growth(0.05);
    println!("sphere growing 5 mm per frame: {slow} step(s); 5 cm per frame: {fast} steps");
    assert_eq!(slow, 1);
    assert!(
        (3..=4).contains(&fast),
        "a fast deformation must split the frame, got {fast}"
    );
}

// ---------------------------------------------------------------------------------------------
// Friction against a surface sliding by deformation.

/// A closed box (m): x in ±1, y in ±0.3, z in [−0.05, 0], triangles wound outwards.
fn slab() -> TriMesh {
    let (x, y, z0, z1) = (1.0, 0.3, -0.05, 0.0);
    let p: Vec<Vector3<f32>> = (0..8)
        .map(|i| {
            Vector3::new(
                if i & 1 == 0 { -x } else { x },
                if i & 2 == 0 { -y } else { y },
                if i & 4 == 0 { z0 } else { z1 },
            )
        })
        .collect();
    let quads = [
        [0, 2, 3, 1], // bottom (−z)
        [4, 5, 7, 6], // top (+z)
        [0, 1, 5, 4], // −y
        [2, 6, 7, 3], // +y
        [0, 4, 6, 2], // −x
        [1, 3, 7, 5], // +x
    ];
    let t = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    TriMesh::new(p, t).unwrap()
}

const SLIDE_SPEED: f32 = 0.2;

/// Hair lying on a slab that slides along +x at 0.2 m/s for 1 s, moved by deformation
/// (`by_vertices`) or by its pose. Returns the free points' positions.
fn slide(by_vertices: bool, friction: f32) -> Vec<Vector3<f32>> {
    let rest = slab();
    let mut set = StrandSet::new();
    for k in 0..8 {
        let root = Vector3::new(0.01 * k as f32 - 0.035, -0.1, 0.004);
        let rest_shape = (0..=16)
            .map(|i| Vector3::z() * (0.0125 * i as f32))
            .collect();
        set.push(StrandInput::uniform(
            along(root, Vector3::y()),
            rest_shape,
            1e-3,
            HAIR_RADIUS,
            0.0,
            0.0,
        ))
        .unwrap();
    }
    let scalp = Scalp::fixed();
    set.reset_to_rest(&scalp);
    let mut solver = MassSpringSolver::new(settings(), params(), &set, &scalp, 0).unwrap();
    let mut colliders = Colliders::new();
    let id = colliders
        .insert(
            Collider::mesh(rest.clone()).with_friction(friction),
            Isometry3::identity(),
        )
        .unwrap();
    for f in 1..=FPS as u32 {
        let dx = SLIDE_SPEED * f as f32 / FPS;
        if by_vertices {
            let moved: Vec<_> = rest
                .positions()
                .iter()
                .map(|p| p + Vector3::x() * dx)
                .collect();
            colliders.set_vertices(id, &moved).unwrap();
        } else {
            colliders
                .set_pose(id, Isometry3::translation(dx, 0.0, 0.0))
                .unwrap();
        }
        let report = solver
            .step_frame_with_colliders(&mut set, &scalp, &mut colliders)
            .unwrap();
        // A flat surface slides exactly: no extra steps, however fast.
        assert_eq!(report.steps, 1);
    }
    free(&set).map(|(_, x)| *x).collect()
}

#[test]
fn surface_sliding_by_deformation_drags_hair_like_the_same_rigid_motion() {
    let deformed = slide(true, 0.5);
    let rigid = slide(false, 0.5);
    let frictionless = slide(true, 0.0);
    let mean_x = |xs: &[Vector3<f32>]| xs.iter().map(|x| x.x).sum::<f32>() / xs.len() as f32;
    let differ = deformed
        .iter()
        .zip(&rigid)
        .map(|(a, b)| (a - b).norm())
        .fold(0.0f32, f32::max);
    println!(
        "slab sliding 0.2 m/s for 1 s: mean x of the hair {:.4} m by deformation, {:.4} m by \
         pose, {:.2e} m without friction; largest difference deformation vs pose {differ:.2e} m",
        mean_x(&deformed),
        mean_x(&rigid),
        mean_x(&frictionless)
    );
    // Friction drags the hair along +x (its roots hold it back); without friction nothing does.
    // The strands start centred on x = 0.
    assert!(mean_x(&deformed) > 0.01, "friction must drag the hair");
    assert!(mean_x(&frictionless).abs() < 1e-4);
    // Both describe the same surface motion; they differ by f32 rounding (the slab's vertices are
    // moved in body space, the pose moves them in world space), a few ulps of 1 m ≈ 1e-7 m per
    // frame, which the damped, frictional dynamics do not amplify. 0.1 mm is 10 % of the hair
    // radius.
    assert!(differ < 1e-4, "deformation and pose differ by {differ} m");
}

// ---------------------------------------------------------------------------------------------
// Bad input.

#[test]
fn wrong_vertex_count_and_non_finite_vertices_are_refused_by_name() {
    let rest = TriMesh::uv_sphere(BALL, 8, 4).unwrap();
    let n = rest.positions().len();
    let mut colliders = Colliders::new();
    let ball = colliders
        .insert(Collider::sphere(0.1), Isometry3::identity())
        .unwrap();
    let mesh = colliders
        .insert(Collider::mesh(rest.clone()), Isometry3::identity())
        .unwrap();

    let err = colliders
        .set_vertices(mesh, &rest.positions()[..n - 2])
        .unwrap_err();
    let text = err.to_string();
    assert!(
        matches!(err, HairError::Collider { collider: 1, .. }),
        "{text}"
    );
    assert!(text.contains(&format!("has {} vertices", n - 2)), "{text}");
    assert!(text.contains(&format!("has {n}")), "{text}");

    let mut bad = rest.positions().to_vec();
    bad[7].y = f32::NAN;
    let text = colliders.set_vertices(mesh, &bad).unwrap_err().to_string();
    assert!(text.contains("vertex 7"), "{text}");
    let text = colliders
        .place_vertices(mesh, &bad)
        .unwrap_err()
        .to_string();
    assert!(text.contains("vertex 7"), "{text}");

    let text = colliders
        .set_vertices(ball, rest.positions())
        .unwrap_err()
        .to_string();
    assert!(
        text.contains("collider 0") && text.contains("only mesh"),
        "{text}"
    );
    let text = colliders
        .set_vertices(ColliderId(9), rest.positions())
        .unwrap_err()
        .to_string();
    assert!(text.contains("no such collider"), "{text}");

    // Saying a collider will deform: a mesh (the scalp's too) yes, a sphere or no collider no.
    colliders.will_deform(mesh).unwrap();
    for id in [ball, ColliderId(9)] {
        let text = colliders.will_deform(id).unwrap_err().to_string();
        assert!(text.contains("no mesh collider"), "{text}");
    }
}

#[test]
fn a_triangle_collapsing_while_deforming_is_stepped_through() {
    // A host's deformation may pinch a triangle to a line; the collider keeps working (the
    // shortcut skips it, parry's search and the smooth normals handle it).
    let rest = TriMesh::uv_sphere(BALL, 16, 8).unwrap();
    let mut strands = hair_over_ball();
    let scalp = Scalp::fixed();
    let mut solver = MassSpringSolver::new(settings(), params(), &strands, &scalp, 0).unwrap();
    let mut colliders = Colliders::new();
    let ball = colliders
        .insert(Collider::mesh(rest.clone()), Isometry3::identity())
        .unwrap();
    let [a, b, _] = rest.triangles()[0];
    let mut pinched: Vec<_> = rest.positions().iter().map(|p| p * 1.5).collect();
    pinched[b as usize] = pinched[a as usize];
    let mut contacts = 0;
    for _ in 0..12 {
        colliders.set_vertices(ball, &pinched).unwrap();
        let report = solver
            .step_frame_with_colliders(&mut strands, &scalp, &mut colliders)
            .unwrap();
        contacts += report.contact_points;
    }
    assert!(contacts > 0, "the hair must reach the pinched sphere");
    assert!(strands
        .positions
        .iter()
        .all(|x| x.iter().all(|c| c.is_finite())));
}

#[test]
fn a_scalp_whose_topology_changes_is_refused_when_stepped() {
    let mesh = TriMesh::uv_sphere(BALL, 12, 6).unwrap();
    let scalp = Scalp {
        mesh: Some(mesh.clone()),
        body: Isometry3::identity(),
    };
    let mut colliders = Colliders::new();
    let head = colliders.insert_scalp(&scalp, 0.0, 0.3).unwrap();
    let text = colliders
        .set_vertices(head, mesh.positions())
        .unwrap_err()
        .to_string();
    assert!(text.contains("follows the scalp"), "{text}");

    let mut strands = StrandSet::new();
    strands
        .push(strand(
            Anchor::Surface(MeshSample {
                triangle: 0,
                weights: [1.0 / 3.0; 3],
            }),
            4,
            0.05,
        ))
        .unwrap();
    strands.reset_to_rest(&scalp);
    let mut solver = MassSpringSolver::new(settings(), params(), &strands, &scalp, 0).unwrap();
    let finer = Scalp {
        mesh: Some(TriMesh::uv_sphere(BALL, 12, 7).unwrap()),
        body: Isometry3::identity(),
    };
    let text = solver
        .step_frame_with_colliders(&mut strands, &finer, &mut colliders)
        .unwrap_err()
        .to_string();
    assert!(
        text.contains("collider 0") && text.contains("vertices"),
        "{text}"
    );
}

// ---------------------------------------------------------------------------------------------
// A deforming scalp: a UV-sphere head with hair on its upper half.

/// The head mesh (a 0.1 m UV sphere, 64 × 32: facets 1 cm wide, whose sagitta of 0.12 mm the
/// 1 mm hair radius covers) with every vertex moved by `deform`.
fn head(deform: impl Fn(Vector3<f64>) -> Vector3<f64>) -> TriMesh {
    TriMesh::lat_long(64, 32, |theta, phi| {
        let r = f64::from(BALL);
        deform(Vector3::new(
            r * theta.sin() * phi.cos(),
            r * theta.sin() * phi.sin(),
            r * theta.cos(),
        ))
    })
    .unwrap()
}

/// Skinning weight of the head's bone at height `z` (m): 0 at the bottom of the sphere (the
/// neck), rising smoothly to 1 at 0.3 R below the equator and above, where the hair is.
fn head_weight(z: f64) -> f64 {
    let s = ((z / f64::from(BALL) + 1.0) / 0.7).clamp(0.0, 1.0);
    s * s * (3.0 - 2.0 * s)
}

/// The head turned about z by `angle` rad by skinning: the upper part turns rigidly, the neck
/// below twists.
fn twisted(angle: f64) -> TriMesh {
    head(|p| {
        let a = angle * head_weight(p.z);
        let (s, c) = a.sin_cos();
        Vector3::new(c * p.x - s * p.y, s * p.x + c * p.y, p.z)
    })
}

/// The head with its +x side lifted by `lift` m (a shoulder shrug): smooth in x, most at the
/// side.
fn shrugged(lift: f64) -> TriMesh {
    head(|p| {
        let s = (p.x / f64::from(BALL)).clamp(0.0, 1.0);
        p + Vector3::z() * (lift * s * s)
    })
}

/// 120 strands rooted on the upper half of the head by mesh samples, 12 cm long, growing along
/// the normal; gravity lays them on it.
fn hair_on(mesh: &TriMesh, scalp: &Scalp) -> StrandSet {
    let mut set = StrandSet::new();
    let mut seed = 7u64;
    let mut uniform = || {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (seed >> 40) as f32 / (1u64 << 24) as f32
    };
    while set.len() < 120 {
        let t = (uniform() * mesh.triangles().len() as f32) as usize;
        let corners = mesh.corners(t);
        if corners.iter().any(|c| c.z < 0.3 * BALL) {
            continue;
        }
        let (u, v) = (uniform(), uniform());
        let (u, v) = if u + v > 1.0 {
            (1.0 - u, 1.0 - v)
        } else {
            (u, v)
        };
        let sample = MeshSample {
            triangle: t as u32,
            weights: [1.0 - u - v, u, v],
        };
        set.push(strand(Anchor::Surface(sample), 12, 0.12)).unwrap();
    }
    set.reset_to_rest(scalp);
    set
}

/// Steps hair on the deforming head through `meshes` (one per frame after the first, which is
/// the rest) and checks each frame: every root on its mesh sample, no free point inside the
/// mesh. Returns the smallest gap (m), the most steps of a frame and the largest root error (m).
fn run_on_head(meshes: &[TriMesh]) -> (f32, u32, f32) {
    let rest = &meshes[0];
    let at = |mesh: &TriMesh| Scalp {
        mesh: Some(mesh.clone()),
        body: Isometry3::identity(),
    };
    let scalp = at(rest);
    let mut strands = hair_on(rest, &scalp);
    let mut solver = MassSpringSolver::new(settings(), params(), &strands, &scalp, 0).unwrap();
    let mut colliders = Colliders::new();
    colliders.insert_scalp(&scalp, 0.0, 0.3).unwrap();
    let (mut worst, mut steps, mut root_error) = (f32::INFINITY, 0, 0.0f32);
    for mesh in &meshes[1..] {
        let scalp = at(mesh);
        let report = solver
            .step_frame_with_colliders(&mut strands, &scalp, &mut colliders)
            .unwrap();
        steps = steps.max(report.steps);
        for (s, anchor) in strands.anchors().iter().enumerate() {
            let Anchor::Surface(sample) = anchor else {
                unreachable!()
            };
            let expected = mesh.evaluate(sample).origin;
            let root = strands.positions[strands.points(s).start];
            root_error = root_error.max((root - expected).norm());
        }
        let (gap, inside) = gap_to(mesh, &strands);
        assert_eq!(inside, 0, "a point ended inside the head (gap {gap} m)");
        worst = worst.min(gap);
    }
    (worst, steps, root_error)
}

#[test]
fn hair_on_a_head_turned_by_skinning_at_ten_rad_per_s_stays_outside_and_on_its_roots() {
    // The top of the head turns by 1 rad · sin(10 t): up to 10 rad/s, 0.42 rad per frame.
    let meshes: Vec<TriMesh> = (0..=36)
        .map(|f| twisted((10.0 * f64::from(f) / f64::from(FPS)).sin()))
        .collect();
    let (gap, steps, root_error) = run_on_head(&meshes);
    println!(
        "head turned by skinning at up to 10 rad/s: smallest gap {:.3} mm, up to {steps} steps \
         per frame, largest root error {root_error:.2e} m",
        gap * 1e3
    );
    assert!(steps > 1, "a fast turn must split frames");
    // Roots are interpolated linearly within the frame; at its end they are their samples on
    // the frame's mesh up to f32 rounding of that interpolation.
    assert!(root_error < 1e-6, "root off its sample by {root_error} m");
}

#[test]
fn hair_on_a_fast_shrug_stays_outside_and_on_its_roots() {
    // The side of the head rises 5 cm in 2 frames (0.6 m/s), holds, and drops back.
    let lift = [
        0.0, 0.0, 0.0, 0.025, 0.05, 0.05, 0.05, 0.025, 0.0, 0.0, 0.0, 0.0,
    ];
    let meshes: Vec<TriMesh> = lift.iter().map(|&l| shrugged(l)).collect();
    let (gap, steps, root_error) = run_on_head(&meshes);
    println!(
        "shrug of 5 cm in 2 frames: smallest gap {:.3} mm, up to {steps} steps per frame, \
         largest root error {root_error:.2e} m",
        gap * 1e3
    );
    assert!(steps > 1, "a fast shrug must split frames");
    assert!(root_error < 1e-6, "root off its sample by {root_error} m");
}

// ---------------------------------------------------------------------------------------------
// Resuming.

#[test]
fn a_run_resumed_on_a_deforming_scalp_and_collider_is_bit_identical() {
    // The head twists while a breathing ball next to it deforms; a run resumed at frame 6 from
    // the strands of that frame, with colliders built from the rest meshes and placed at frame 6,
    // must match the uninterrupted run to the bit.
    let frames = 12u32;
    let meshes: Vec<TriMesh> = (0..=frames)
        .map(|f| twisted(0.6 * (8.0 * f64::from(f) / f64::from(FPS)).sin()))
        .collect();
    let ball_rest = TriMesh::uv_sphere(0.05, 24, 12).unwrap();
    let ball_at = |f: u32| -> Vec<Vector3<f32>> {
        let s = 1.0 + 0.3 * (f as f32 * 0.5).sin();
        ball_rest.positions().iter().map(|p| p * s).collect()
    };
    let ball_pose = Isometry3::translation(0.0, 0.0, 0.16);
    let scalp_at = |f: u32| Scalp {
        mesh: Some(meshes[f as usize].clone()),
        body: Isometry3::identity(),
    };
    let build = |f: u32| {
        let mut colliders = Colliders::new();
        colliders
            .insert_scalp_rest(meshes[0].clone(), Isometry3::identity(), 0.0, 0.3)
            .unwrap();
        let ball = colliders
            .insert(
                Collider::mesh(ball_rest.clone()).with_friction(0.3),
                ball_pose,
            )
            .unwrap();
        colliders.place_scalp(&scalp_at(f)).unwrap();
        colliders.place_vertices(ball, &ball_at(f)).unwrap();
        (colliders, ball)
    };
    let run = |strands: &mut StrandSet, from: u32, to: u32, snapshot: &mut Option<StrandSet>| {
        let mut solver =
            MassSpringSolver::new(settings(), params(), strands, &scalp_at(from), from).unwrap();
        let (mut colliders, ball) = build(from);
        let mut contacts = 0;
        for f in from + 1..=to {
            colliders.set_vertices(ball, &ball_at(f)).unwrap();
            let report = solver
                .step_frame_with_colliders(strands, &scalp_at(f), &mut colliders)
                .unwrap();
            contacts += report.contact_points;
            if f == 6 {
                *snapshot = Some(strands.clone());
            }
        }
        contacts
    };
    let mut whole = hair_on(&meshes[0], &scalp_at(0));
    let mut at_six = None;
    let contacts = run(&mut whole, 0, frames, &mut at_six);
    let mut resumed = at_six.expect("frame 6 was stepped");
    run(&mut resumed, 6, frames, &mut None);
    assert!(
        contacts > 100,
        "the scene must collide ({contacts} contacts)"
    );
    assert!(bits(&whole) == bits(&resumed), "the resumed run differs");
}
