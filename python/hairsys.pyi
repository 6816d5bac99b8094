"""hairsys: hair simulation for Python hosts (Blender, Houdini, Maya, scripts).

A `Session` is driven frame by frame: set the scalp (a rigid 4x4 matrix, or deformed vertices),
pose colliders, change parameters, `step()`, read `positions` / `velocities` as read-only numpy
views (no copy). Units: meters, seconds, kilograms; Z up.

Views and lifetime: `positions` and `velocities` view the session's own buffers; their numpy
`base` is the Session, so the memory lives as long as the array. The buffers are never
reallocated, so an array shows the current frame after every `step` / `restore`; copy it
(`np.array(s.positions)`) to keep a frame. While one thread steps a session, calls on the same
session from other threads raise RuntimeError ("already borrowed"), and arrays taken before must
not be read from another thread until the step returns.

Errors: `SceneError`, `ArgumentError` (both ValueError), `SolverError`, `SessionFailedError`
(a SolverError), `CacheError` (OSError), `InternalError` (a caught Rust panic: a bug). A Rust
panic never crosses into the host.
"""

from os import PathLike
from typing import Literal, Sequence, TypedDict

import numpy as np
import numpy.typing as npt

__version__: str

_Floats = npt.ArrayLike
"""A float32 or float64 array (or anything numpy.asarray takes)."""

class SceneError(ValueError):
    """A scene file cannot be used; names the file, the key and the fix."""

class ArgumentError(ValueError):
    """An argument has the wrong shape, dtype, size or value; names it and what is expected."""

class SolverError(RuntimeError):
    """The solver refused the setup or blew up (frame, strand, stability bound)."""

class SessionFailedError(SolverError):
    """The session's last step failed: restore a snapshot or build a new session."""

class CacheError(OSError):
    """A cache cannot be written or read."""

class InternalError(RuntimeError):
    """A bug in hairsys: a Rust panic caught at the module boundary."""

class FrameReport(TypedDict):
    frame: int
    substeps: int
    steps: int
    point_substeps: int
    contact_points: int
    max_stretch: float
    phase_ms: PhaseTimes
    """Wall time of the step's phases, ms."""
    step_ms: float
    """Wall time of the library's step (GIL released), ms."""

class PhaseTimes(TypedDict):
    roots: float
    """Root frames evaluated on the scalp."""
    strands: float
    """Force substeps of every strand, the contact response included."""
    contacts: float
    """Contact detection."""
    volume: float
    """Hair–hair grid."""
    fields: float
    """Force fields."""

class CacheSummary(TypedDict):
    path: str
    frames: int
    first_frame: int | None
    last_frame: int | None
    fps: float
    strands: int
    points: int
    bytes: int

class ColliderSpec(TypedDict, total=False):
    """One collider of `Session.from_groom(colliders=[...])`.

    shape: "sphere" (radius), "capsule" (half_height, radius; along body z) or "mesh"
    (vertices (V, 3) m, triangles (T, 3); closed = solid, open = two-sided shell).
    thickness: m kept between hair and surface. friction: Coulomb coefficient (≥ 0).
    matrix: (4, 4) rigid pose at the first frame (identity when absent).
    """

    shape: Literal["sphere", "capsule", "mesh"]
    radius: float
    half_height: float
    vertices: _Floats
    triangles: npt.ArrayLike
    thickness: float
    friction: float
    matrix: _Floats

class Snapshot:
    """A copy of a session's state at one frame (`Session.snapshot()`)."""

    @property
    def frame(self) -> int: ...

class Children:
    """Render children of a frame as flat arrays (owned, no copy)."""

    @property
    def vertex_counts(self) -> npt.NDArray[np.uint32]:
        """Points per child curve, (C,)."""
    @property
    def points(self) -> npt.NDArray[np.float32]:
        """Every child's points, root first, curve after curve, (N, 3), m."""
    @property
    def widths(self) -> npt.NDArray[np.float32]:
        """Width at every point, (N,), m."""
    @property
    def parent(self) -> npt.NDArray[np.uint32]:
        """The strand each child follows, (C,)."""
    @property
    def root_uv(self) -> npt.NDArray[np.float32] | None:
        """Scalp UV at each root, (C, 2), or None."""
    def __len__(self) -> int: ...

class Session:
    """A hair simulation driven frame by frame."""

    @staticmethod
    def from_scene(path: str | PathLike[str] | None = None, *, threads: int | None = None) -> Session:
        """A session of a scene file (TOML; the built-in default scene when None).

        The scene's keyframes move the scalp and colliders for frames the host does not set.
        `threads`: size of the session's own thread pool (None: a shared global pool).
        Raises SceneError.
        """
    @staticmethod
    def from_groom(
        scalp_vertices: _Floats,
        scalp_triangles: npt.ArrayLike,
        curve_points: _Floats,
        curve_counts: npt.ArrayLike,
        *,
        scalp_uvs: _Floats | None = None,
        goal_weights: _Floats | None = None,
        pinned: npt.ArrayLike | None = None,
        strand_scales: dict[Literal["stretch", "bend", "goal", "damping", "drag"], _Floats]
        | None = None,
        sim_hairs: int | None = None,
        k: int = 4,
        points: int | None = None,
        seed: int = 0,
        fps: float = 24.0,
        first_frame: int = 1,
        steps: int = 1,
        substeps: int | Literal["auto"] = "auto",
        integrator: Literal[
            "auto", "semi-implicit-euler", "implicit-euler", "bdf2", "xpbd", "explicit-euler"
        ] = "auto",
        sag_free: bool = False,
        collider_speed: float | None = None,
        damping_iterations: int = 10,
        max_strain: float | None = None,
        gravity: tuple[float, float, float] = (0.0, 0.0, -9.81),
        stretch_stiffness: float = ...,
        bend_stiffness: float = ...,
        goal_stiffness: float = ...,
        stretch_damping: float = ...,
        air_drag: float = ...,
        mass_per_length: float = 0.001,
        radius: float = 0.001,
        goal_root: float = 0.0,
        goal_tip: float = 0.0,
        max_snap_distance: float = 0.025,
        scalp_collider: bool = False,
        scalp_thickness: float = 0.0,
        scalp_friction: float = 0.0,
        colliders: Sequence[ColliderSpec] | None = None,
        hair_hair_friction: float | None = None,
        hair_hair_cell_size: float | None = None,
        threads: int | None = None,
    ) -> Session:
        """A session of a groom on a scalp given as arrays (m, Z up, world space at the first frame).

        scalp_vertices (V, 3) float, scalp_triangles (T, 3) int, curve_points (P, 3) float (every
        curve root first, curve after curve), curve_counts (C,) int (points per curve, ≥ 2,
        adding up to P). Roots are snapped onto the scalp (refused beyond max_snap_distance, m).
        sim_hairs None simulates the curves themselves, one strand per curve in order (write
        `positions` back onto them); an int interpolates that many hairs from the k nearest
        curves (as guides) with `points` points each. goal_weights (P,) in [0, 1]: per-point
        pull towards the animated rest shape (times goal_stiffness, N/m); without them goal
        weights run linearly from goal_root to goal_tip. pinned (P,) bool: points held on the
        rest shape in the root frame (kinematic, they follow the scalp rigidly; roots always
        are); only with sim_hairs None. strand_scales: per-curve factors of the material, a dict
        of (C,) arrays keyed stretch (> 0), bend, goal, damping, drag (≥ 0; a key left out is 1):
        curve c runs with bend_stiffness × bend[c] and so on (what a scene's [[regions]] and
        [maps.stiffness] give); interpolated hairs blend their guides' factors by their
        interpolation weights. Stiffnesses in N/m, stretch_damping and
        air_drag in 1/s, mass_per_length in kg/m, radius in m (wisp radius, collision and
        render width). scalp_collider makes the scalp collide with its hair (thickness m,
        friction). colliders: see ColliderSpec; their ids are 0, 1, … in order, the scalp
        collider after them. hair_hair_friction (0–1) switches voxel hair–hair friction on.
        integrator: "auto" (the default) chooses between semi-implicit Euler and BDF2 by the
        same rule as a scene file's [solver] integrator, from the curves' stiffness, their
        sharpest rest joint and how fast the host says its colliders will move: collider_speed
        (fastest speed of a collider's surface over the shot, rigid motion and deformation
        together, m/s; None, not said, is taken as any speed). A collider whose surface crosses
        more than half its size in one BDF2 substep keeps semi-implicit Euler; the scalp never
        counts, deforming or not. Or name the integrator. sag_free solves rest shapes so the groom is in equilibrium under
        gravity at the first frame (a scene's [solver] sag_free): hair keeps its groomed shape
        instead of sagging when the simulation starts; one material only (no strand_scales).
        Raises ArgumentError naming the bad argument.
        """
    def step(
        self, scalp_matrix: _Floats | None = None, scalp_vertices: _Floats | None = None
    ) -> FrameReport:
        """Advances one frame (1/fps s), releasing the GIL while it computes.

        scalp_matrix: (4, 4) rigid transform of the scalp (body to world) at the new frame; a
        scaled or sheared matrix is refused (pass world-space vertices with no matrix instead).
        scalp_vertices: (V, 3) float32/float64 deformed scalp, m, in its body space placed by
        scalp_matrix (world space without one); V is the scalp's vertex count, same order.
        Raises ArgumentError, SolverError, SessionFailedError (stepping after a failed step),
        CacheError.
        """
    @property
    def positions(self) -> npt.NDArray[np.float32]:
        """Positions of every point, m, (P, 3) float32, read-only view without a copy."""
    @property
    def velocities(self) -> npt.NDArray[np.float32]:
        """Velocities of every point, m/s, (P, 3) float32, read-only view without a copy."""
    @property
    def strand_offsets(self) -> npt.NDArray[np.uint32]:
        """Strand s is points offsets[s]:offsets[s+1]; (strands + 1,)."""
    @property
    def strand_count(self) -> int: ...
    @property
    def point_count(self) -> int: ...
    @property
    def frame(self) -> int:
        """Frame number of the current state."""
    @property
    def fps(self) -> float: ...
    @property
    def integrator(self) -> str:
        """The time integrator the session runs ("auto" resolved when it was made):
        "semi-implicit-euler", "bdf2", "implicit-euler", "xpbd" or "explicit-euler"; "rod" and
        "strips" for the models that keep their own schemes."""
    @property
    def collider_count(self) -> int: ...
    def set_collider_pose(self, id: int, matrix: _Floats) -> None:
        """Poses collider `id` (rigid (4, 4), body to world, m) at the end of the next frame.

        Raises ArgumentError for an id that does not exist, the scalp collider (set the scalp
        instead) or a matrix that is not rigid.
        """
    def set_collider_vertices(self, id: int, vertices: _Floats) -> None:
        """Deforms mesh collider `id`: (V, 3) vertices, m, its body space, at the end of the
        next frame (same count and order as the mesh it was made with).

        Raises ArgumentError for an id that does not exist, a sphere or capsule, a wrong vertex
        count or a non-finite vertex.
        """
    def set_guide_pose(self, points: _Floats) -> None:
        """Sets the guides' pose for the next frame (animated guides): (P, 3) points, m, every
        guide's points in the groom's order and point counts (`guide_point_counts`), in the
        scalp's body space at rest. The sim hairs' rest shapes are re-interpolated from it.

        Raises ArgumentError for a session without guides, a wrong point count or a non-finite
        point.
        """
    @property
    def region_names(self) -> list[str]:
        """Names of the scene's [[regions]], in file order (empty without regions)."""
        ...
    def region_strands(self, name: str) -> list[int]:
        """Strand indices of region `name`, increasing. Raises ArgumentError for an unknown name."""
        ...
    def region_params(self, name: str) -> dict[str, float | None]:
        """Region `name`'s parameters: stretch_stiffness, bend_stiffness, goal_stiffness (N/m),
        stretch_damping, air_drag (1/s), mass_scale, radius_scale; None = the scene's."""
        ...
    def set_region_params(self, name: str, params: dict[str, float | None]) -> None:
        """Changes region `name`'s springs, damping and drag from the next frame on (keys left
        out keep their value, None = the scene's [physics]). Raises ArgumentError for an unknown
        region or key, a bad value, or mass_scale / radius_scale (fixed at build)."""
        ...
    def set_sim_weight(self, weight: float) -> None:
        """Sets the sim weight for the next frame instead of the scene's curve: 0 = simulation,
        1 = exactly the animated guides, between a blend (times each hair's factor).

        Raises ArgumentError outside [0, 1] or for a session without guides.
        """
    def set_strand_sim_weights(self, weights: _Floats) -> None:
        """Sets each sim hair's factor of the sim weight, (H,) in [0, 1], kept until set again.

        Raises ArgumentError for a wrong count, a value outside [0, 1] or a session without
        guides.
        """
    @property
    def guide_point_counts(self) -> list[int]:
        """Point count of each guide, in the groom's order (empty without guides)."""
    @property
    def guide_groom_points(self) -> npt.NDArray[np.float32]:
        """(P, 3) the guides' groom points, m, in the scalp's body space at rest, every guide in
        order (`guide_point_counts` each): edit them and pass them to `set_guide_pose`. Empty
        without guides."""
    @property
    def guided_strands(self) -> tuple[int, int] | None:
        """Strand indices (start, end) of the sim hairs the guides drive (None without guides)."""
    gravity: tuple[float, float, float]
    """Gravity, m/s²."""
    goal_stiffness: float
    """Goal spring stiffness, N/m (times each point's goal weight)."""
    air_drag: float
    """Decay rate of velocity in still air, 1/s."""
    bend_stiffness: float
    """Bending spring stiffness, N/m."""
    hair_hair_friction: float | None
    """Hair–hair friction 0–1 (None when hair–hair is off; setting it then raises)."""
    @property
    def field_count(self) -> int: ...
    def field_strength(self, index: int) -> float:
        """Strength of force field `index` at the next frame."""
    def set_field_strength(self, index: int, value: float) -> None:
        """Sets force field `index`'s strength (constant from now on)."""
    def set_field_direction(self, index: int, direction: tuple[float, float, float]) -> None:
        """Sets force field `index`'s direction (normalised; not zero): wind flow, vortex axis."""
    def set_field_center(self, index: int, center: tuple[float, float, float]) -> None:
        """Sets force field `index`'s center, m: vortex axis point, point force, falloff origin."""
    def snapshot(self) -> Snapshot:
        """A copy of the state at the current frame."""
    def restore(self, snapshot: Snapshot) -> None:
        """Back to `snapshot`'s state (stepping on gives the same bits); clears a failed step."""
    def write_cache(
        self,
        path: str | PathLike[str],
        *,
        compression: Literal["none", "lz4", "zstd"] = "none",
        quantize: bool = False,
    ) -> None:
        """Starts an MCAP cache at `path` (written as path.partial until finish_cache): the
        current frame now, then every step."""
    def finish_cache(self) -> CacheSummary:
        """Finishes the cache (index, summary, rename to its final name)."""
    def children(
        self,
        *,
        per_parent: int = 10,
        total: int | None = None,
        interpolated: bool = False,
        neighbours: int = 4,
        spread: float = 0.005,
        clump: float = 0.0,
        curl_radius: float = 0.0,
        curl_frequency: float = 0.0,
        roughness: float = 0.0,
        roughness_endpoint: float = 0.0,
        length_variation: float = 0.0,
        root_width: float = 80e-6,
        tip_width: float = 20e-6,
        subdivisions: int = 4,
        seed: int = 0,
        display: bool = False,
        display_fraction: float = 0.1,
        positions: _Floats | None = None,
        scalp_vertices: _Floats | None = None,
    ) -> Children:
        """Render children of the current frame, or of `positions` (P, 3) (m, world space, the
        strands' points in order, e.g. a cached frame) rooted on the scalp at `scalp_vertices`
        (V, 3) (m, world space; None: the current scalp), without stepping. spread,
        curl_radius, roughness, roughness_endpoint, root_width, tip_width in m (widths are
        diameters); curl_frequency in turns/m; clump −1–1; length_variation 0–0.99;
        subdivisions 1–64 pieces per parent segment at render level; display: the display
        level of detail (display_fraction of each parent's children, the parents' own points).
        Raises ArgumentError naming the bad argument."""

class Cache:
    """A hairsys MCAP cache opened for reading."""

    def __init__(self, path: str | PathLike[str]) -> None: ...
    @property
    def frames(self) -> list[int]: ...
    @property
    def fps(self) -> float: ...
    @property
    def strand_offsets(self) -> npt.NDArray[np.uint32]: ...
    @property
    def point_count(self) -> int: ...
    @property
    def scene_toml(self) -> str: ...
    def frame(self, n: int) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]:
        """(positions m, velocities m/s) of frame n, each (P, 3) float32. Raises CacheError."""
    def sample(self, time: float) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]:
        """(positions, velocities) at `time` s, cubic Hermite between frames."""
    def __len__(self) -> int: ...
