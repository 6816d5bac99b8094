//! The plain structs and constants the C API passes by pointer. Units are SI (m, s, kg); point
//! arrays are `float` xyz interleaved (`x0 y0 z0 x1 y1 z1 …`), counted in points.

use std::ffi::c_char;

/// A rigid transform (body to world): a translation in m and a unit rotation quaternion
/// `(x, y, z, w)`; the identity is `{{0, 0, 0}, {0, 0, 0, 1}}`. A rotation whose length is off
/// 1 by more than 1e-4 is refused (`HAIRSYS_STATUS_BAD_ARGUMENT`), never renormalised.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HairsysTransform {
    /// Translation, m.
    pub translation: [f32; 3],
    /// Rotation quaternion `(x, y, z, w)`, unit.
    pub rotation: [f32; 4],
}

/// A sphere collider: `radius` (m) around its pose's origin.
pub const HAIRSYS_SHAPE_SPHERE: u32 = 0;
/// A capsule collider along its body Z axis: `half_height` and `radius` (m).
pub const HAIRSYS_SHAPE_CAPSULE: u32 = 1;
/// A triangle-mesh collider: `vertices` (body space, m) and `triangles`.
pub const HAIRSYS_SHAPE_MESH: u32 = 2;

/// One collider of a groom session. Its id in the session is its index in
/// [`HairsysGroomOptions::colliders`].
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct HairsysCollider {
    /// `HAIRSYS_SHAPE_SPHERE`, `HAIRSYS_SHAPE_CAPSULE` or `HAIRSYS_SHAPE_MESH`.
    pub shape: u32,
    /// Sphere and capsule radius, m.
    pub radius: f32,
    /// Capsule half height (of its segment, along body Z), m.
    pub half_height: f32,
    /// Contact thickness added to the surface, m.
    pub thickness: f32,
    /// Coulomb friction coefficient (≥ 0).
    pub friction: f32,
    /// Mesh vertices, xyz interleaved, body space, m (`vertex_count` points); NULL otherwise.
    pub vertices: *const f32,
    /// Number of mesh vertices.
    pub vertex_count: usize,
    /// Mesh triangles, three vertex indices each (`triangle_count` triangles); NULL otherwise.
    pub triangles: *const u32,
    /// Number of mesh triangles.
    pub triangle_count: usize,
    /// Pose at the first frame.
    pub pose: HairsysTransform,
}

/// Per-curve factors of the material (1 = the session's value).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HairsysStrandScales {
    /// Factor of the stretch stiffness.
    pub stretch: f32,
    /// Factor of the bend stiffness.
    pub bend: f32,
    /// Factor of the goal stiffness.
    pub goal: f32,
    /// Factor of the stretch damping.
    pub damping: f32,
    /// Factor of the air drag.
    pub drag: f32,
}

/// A groom and its scalp as the host's arrays, world space at the first frame, m, Z up. The
/// library copies what it needs during the create call; the host keeps ownership.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct HairsysGroomArrays {
    /// Scalp vertices, xyz interleaved, m (`scalp_vertex_count` points).
    pub scalp_vertices: *const f32,
    /// Number of scalp vertices.
    pub scalp_vertex_count: usize,
    /// Scalp triangles, three vertex indices each (`scalp_triangle_count` triangles).
    pub scalp_triangles: *const u32,
    /// Number of scalp triangles.
    pub scalp_triangle_count: usize,
    /// Scalp UVs, uv interleaved, one per scalp vertex (children's root UVs); NULL for none.
    pub scalp_uvs: *const f32,
    /// Every curve's points, root first, curve after curve, xyz interleaved, m.
    pub curve_points: *const f32,
    /// Number of curve points (the sum of `curve_counts`).
    pub curve_point_count: usize,
    /// Points per curve (each ≥ 2).
    pub curve_counts: *const u32,
    /// Number of curves.
    pub curve_count: usize,
    /// Goal weight in [0, 1] per curve point (`curve_point_count` values); NULL: linear from
    /// `goal_root` to `goal_tip`.
    pub goal_weights: *const f32,
    /// Per curve point, 1 = pinned (held on its rest shape in the root frame), 0 = free
    /// (`curve_point_count` bytes); NULL: only the roots. Only with `sim_hairs` = 0.
    pub pinned: *const u8,
    /// Per-curve material factors (`curve_count` entries); NULL: all 1.
    pub strand_scales: *const HairsysStrandScales,
}

/// How a groom session is simulated. Fill it with `hairsys_groom_options_default` (the default
/// scene's material on a still scalp), then change fields.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct HairsysGroomOptions {
    /// 0: one strand per curve, in the host's order. N > 0: N hairs rooted area-weighted on the
    /// scalp, each blended from its `interpolate_k` nearest curves (as guides).
    pub sim_hairs: u32,
    /// Guides blended per interpolated hair (≥ 1).
    pub interpolate_k: u32,
    /// Points per interpolated hair (≥ 2); 0: the first curve's count.
    pub interpolate_points: u32,
    /// Seed of the interpolated hairs' roots.
    pub seed: u64,
    /// Frames per second (a step advances 1/fps s).
    pub fps: f32,
    /// Collision steps per frame (≥ 1).
    pub steps: u32,
    /// Force substeps per collision step; 0: `"auto"` (from the stability bound).
    pub substeps: u32,
    /// Damping iterations per substep.
    pub damping_iterations: u32,
    /// Frame number of the rest state.
    pub first_frame: u32,
    /// `"auto"` (NULL means the same) or an integrator's name (`"semi-implicit-euler"`,
    /// `"implicit-euler"`, `"bdf2"`, `"xpbd"`, `"explicit-euler"`), NUL-terminated.
    pub integrator: *const c_char,
    /// 1: solve rest shapes so the groom holds its shape under gravity at the first frame.
    pub sag_free: u32,
    /// Fastest speed of any collider surface point over the shot, m/s, for `"auto"`; negative:
    /// not said (any speed).
    pub collider_speed: f64,
    /// Gravity, m/s².
    pub gravity: [f32; 3],
    /// Stretch spring stiffness between neighbouring points, N/m.
    pub stretch_stiffness: f32,
    /// Bending stiffness `k_b`, N/m (bending rigidity `EI = k_b l³` with `l` the mean rest
    /// segment length).
    pub bend_stiffness: f32,
    /// Goal spring stiffness towards the rest shape, N/m (times each point's goal weight).
    pub goal_stiffness: f32,
    /// Viscous damping of each segment's stretching speed, 1/s.
    pub stretch_damping: f32,
    /// Air drag, 1/s: a free point's velocity decays as exp(−rate·t) in still air.
    pub air_drag: f32,
    /// Linear density, kg/m.
    pub mass_per_length: f32,
    /// Strand radius, m (collision sphere and render width).
    pub radius: f32,
    /// Goal weight at the root without per-point weights, 0–1.
    pub goal_root: f32,
    /// Goal weight at the tip without per-point weights, 0–1.
    pub goal_tip: f32,
    /// Largest distance a root may be moved onto the scalp, m.
    pub max_snap_distance: f32,
    /// 1: the scalp collides with its own hair.
    pub scalp_collider: u32,
    /// Scalp collider thickness, m.
    pub scalp_thickness: f32,
    /// Scalp collider Coulomb friction coefficient (≥ 0).
    pub scalp_friction: f32,
    /// Further colliders (`collider_count`), ids 0, 1, … in order; NULL when none.
    pub colliders: *const HairsysCollider,
    /// Number of colliders.
    pub collider_count: usize,
    /// 1: voxel hair–hair friction and repulsion.
    pub hair_hair: u32,
    /// Hair–hair friction: the fraction of the way each free point's velocity moves towards
    /// the grid's per collision step, 0–1.
    pub hair_hair_friction: f32,
    /// Hair–hair grid cell size, m.
    pub hair_hair_cell_size: f32,
    /// Worker threads of the session's own pool (at most `HAIRSYS_MAX_THREADS`); 0: the
    /// library's shared pool (one thread per core).
    pub threads: u32,
}

/// What a step did.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct HairsysFrameReport {
    /// The frame computed.
    pub frame: u32,
    /// Force substeps per collision step.
    pub substeps: u32,
    /// Collision steps run.
    pub steps: u32,
    /// Points × substeps advanced.
    pub point_substeps: u64,
    /// Point contacts found over the frame.
    pub contact_points: u64,
    /// Points put back on a collider's surface by the frame-end check.
    pub escaped_points: u64,
    /// Largest relative segment elongation at the end of the frame.
    pub max_stretch: f32,
}

/// The sizes of a session.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct HairsysSessionInfo {
    /// Frame number of the current state.
    pub frame: u32,
    /// Frames per second.
    pub fps: f32,
    /// Strands.
    pub strand_count: usize,
    /// Points of all strands.
    pub point_count: usize,
    /// Colliders (the scalp collider, if any, is the last and is not posed by the host).
    pub collider_count: usize,
    /// Vertices of the scalp mesh (0 without one): the length `set_scalp_vertices` takes.
    pub scalp_vertex_count: usize,
}

/// A read-only view of `count` points (xyz interleaved, `3 * count` floats) owned by the
/// library; valid until the next call that changes the object it came from.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct HairsysPointsView {
    /// The first float; never NULL (dangling but aligned when `count` is 0).
    pub xyz: *const f32,
    /// Number of points.
    pub count: usize,
}

/// A read-only view of `count` `uint32_t`s owned by the library, valid as
/// [`HairsysPointsView`].
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct HairsysIndexView {
    /// The first value; never NULL.
    pub data: *const u32,
    /// Number of values.
    pub count: usize,
}

/// The material a host may change between frames (mass-spring sessions); units as in
/// [`HairsysGroomOptions`].
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HairsysParams {
    /// Gravity, m/s².
    pub gravity: [f32; 3],
    /// Stretch spring stiffness, N/m.
    pub stretch_stiffness: f32,
    /// Bending stiffness, N/m.
    pub bend_stiffness: f32,
    /// Goal spring stiffness, N/m.
    pub goal_stiffness: f32,
    /// Stretch damping, 1/s.
    pub stretch_damping: f32,
    /// Air drag, 1/s.
    pub air_drag: f32,
}

/// Most worker threads a session's own pool may have.
pub const HAIRSYS_MAX_THREADS: u32 = 1024;

/// No compression of cache chunks.
pub const HAIRSYS_COMPRESSION_NONE: u32 = 0;
/// LZ4 compression of cache chunks.
pub const HAIRSYS_COMPRESSION_LZ4: u32 = 1;
/// Zstandard compression of cache chunks.
pub const HAIRSYS_COMPRESSION_ZSTD: u32 = 2;

/// What a finished cache holds.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct HairsysCacheSummary {
    /// Frames written.
    pub frames: usize,
    /// First frame number (0 when none).
    pub first_frame: u32,
    /// Last frame number (0 when none).
    pub last_frame: u32,
    /// Frames per second.
    pub fps: f64,
    /// Strands.
    pub strands: usize,
    /// Points per frame.
    pub points: usize,
    /// File size, bytes.
    pub bytes: u64,
}

/// How render children are made (`hairsys_child_settings_default` fills the library's
/// defaults).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HairsysChildSettings {
    /// Children around every strand (used when `total` is 0).
    pub per_parent: u32,
    /// Children in all, spread over the strands; 0: `per_parent` each.
    pub total: u64,
    /// 0: simple children (a disc of `spread` around each parent); 1: interpolated between
    /// `neighbours` parents.
    pub interpolated: u32,
    /// Parents blended per interpolated child.
    pub neighbours: u32,
    /// Root disc radius of simple children, m.
    pub spread: f32,
    /// Clump factor, 0–1.
    pub clump: f32,
    /// Curl radius, m.
    pub curl_radius: f32,
    /// Curl frequency, turns per m.
    pub curl_frequency: f32,
    /// Seed of the children's randomness.
    pub seed: u64,
    /// 0: render level of detail; 1: display (a fraction of the children, fewer points).
    pub display: u32,
}

/// Render children as flat arrays owned by their `HairsysChildren` handle (valid until it is
/// destroyed).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct HairsysChildrenView {
    /// Points per child curve (`curve_count` values).
    pub vertex_counts: *const u32,
    /// Number of child curves.
    pub curve_count: usize,
    /// Every child's points, root first, curve after curve, xyz interleaved, m.
    pub points: *const f32,
    /// Number of points.
    pub point_count: usize,
    /// Width at every point, m (`point_count` values).
    pub widths: *const f32,
    /// The strand each child follows (`curve_count` values).
    pub parent: *const u32,
    /// Scalp UV at each child's root, uv interleaved (`curve_count` pairs); NULL when the scalp
    /// has no UVs.
    pub root_uv: *const f32,
}

/// What a cache holds.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct HairsysCacheInfo {
    /// Frames per second.
    pub fps: f64,
    /// Frames stored.
    pub frame_count: usize,
    /// First stored frame number (0 when none).
    pub first_frame: u32,
    /// Last stored frame number (0 when none).
    pub last_frame: u32,
    /// Strands.
    pub strand_count: usize,
    /// Points per frame.
    pub point_count: usize,
}
