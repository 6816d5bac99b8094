"""The hairsys Python module: shapes, zero copy, GIL release, errors, snapshots, caches, and
bit-identity with the `hairsys simulate` command."""

import pathlib
import subprocess
import threading
import time

import numpy as np
import pytest

import hairsys
from hairsys_testing import REPO, hairsys_binary, read_mcap_frames, sphere_groom, uv_sphere

SMALL_SCENE = """
[scene]
name = "small"
fps = 24.0
frames = [1, 12]
[scalp.mesh]
kind = "builtin-head"
[scalp.motion]
keys = [
    { frame = 1, translation = [0.0, 0.0, 0.0], rotation_deg = [0.0, 0.0, 0.0] },
    { frame = 12, translation = [0.0, 0.05, 0.0], rotation_deg = [0.0, 0.0, 60.0] },
]
[scalp.collider]
thickness = 0.002
friction = 0.3
[hair]
count = 150
length = 0.2
segments = 8
seed = 3
region = { direction = [0.0, 0.3, 1.0], max_angle_deg = 90.0 }
"""


@pytest.fixture
def small_scene(tmp_path):
    p = tmp_path / "small.toml"
    p.write_text(SMALL_SCENE)
    return p


def rotation_z(deg, t=(0.0, 0.0, 0.0)):
    a = np.radians(deg)
    m = np.eye(4)
    m[:2, :2] = [[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]]
    m[:3, 3] = t
    return m


def test_shapes_and_layout(groom):
    v, t, pts, counts = groom
    s = hairsys.Session.from_groom(v, t, pts, counts)
    assert s.positions.shape == (len(pts), 3) and s.positions.dtype == np.float32
    assert s.velocities.shape == (len(pts), 3)
    off = s.strand_offsets
    assert off.dtype == np.uint32 and off[0] == 0 and off[-1] == len(pts)
    assert np.array_equal(np.diff(off), counts)
    assert (s.strand_count, s.point_count, s.frame, s.fps) == (len(counts), len(pts), 1, 24.0)
    # At rest the strands are the curves (roots were on the scalp already).
    np.testing.assert_allclose(s.positions, pts, atol=1e-5)


def test_positions_are_views_of_the_session_without_copies(groom):
    s = hairsys.Session.from_groom(*groom)
    a, b = s.positions, s.positions
    assert np.shares_memory(a, b)
    assert a.base is s and not a.flags.writeable and not a.flags.owndata
    with pytest.raises(ValueError):
        a[0, 0] = 1.0
    address = a.__array_interface__["data"][0]
    snap = s.snapshot()
    before = np.array(a)
    s.step(scalp_matrix=rotation_z(20))
    # The same memory shows the new frame: never reallocated by step or restore.
    assert s.positions.__array_interface__["data"][0] == address
    assert not np.array_equal(a, before)
    s.restore(snap)
    assert s.positions.__array_interface__["data"][0] == address
    assert np.array_equal(a, before)
    # The view keeps the session alive.
    del s
    assert np.array_equal(a, before)


def test_step_releases_the_gil():
    s = hairsys.Session.from_scene(None)  # default scene: 4000 strands, ~ 100 ms a frame
    ticks = []
    done = threading.Event()

    def step():
        for _ in range(3):
            s.step()
        done.set()

    th = threading.Thread(target=step)
    th.start()
    while not done.is_set():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    th.join()
    # Python ran in this thread while the other stepped: many ticks, no long gaps.
    assert len(ticks) > 20, f"only {len(ticks)} ticks while stepping"
    gaps = np.diff(ticks)
    assert gaps.max() < 0.05, f"the main thread was blocked {gaps.max():.3f} s"
    assert s.frame == 4


def test_other_calls_on_a_stepping_session_raise_instead_of_reading_a_torn_frame():
    s = hairsys.Session.from_scene(None)
    errors = []
    th = threading.Thread(target=lambda: [s.step() for _ in range(2)])
    th.start()
    while th.is_alive():
        try:
            s.positions
        except RuntimeError as e:
            errors.append(e)
    th.join()
    assert errors, "positions was read while a step was computing"
    assert "borrow" in str(errors[0])


def test_deforming_scalp_moves_the_roots_onto_the_surface(groom):
    v, t, pts, counts = groom
    s = hairsys.Session.from_groom(v, t, pts, counts)
    off = s.strand_offsets[:-1]
    for f in range(1, 6):
        deformed = v * np.array([1.0 + 0.05 * f, 1.0, 1.0 - 0.04 * f]) + [0.0, 0.01 * f, 0.0]
        s.step(scalp_vertices=deformed.astype(np.float32))
    roots = s.positions[off]
    # The roots were at vertices: they follow those vertices exactly.
    idx = [int(np.argmin(np.linalg.norm(v - p, axis=1))) for p in pts[off]]
    np.testing.assert_allclose(roots, deformed[idx], atol=1e-6)


def test_rigid_matrix_and_body_space_vertices_agree(groom):
    v, t, pts, counts = groom
    a = hairsys.Session.from_groom(v, t, pts, counts)
    b = hairsys.Session.from_groom(v, t, pts, counts)
    m = rotation_z(30, (0.0, 0.02, 0.0))
    a.step(scalp_matrix=m)
    b.step(scalp_matrix=m, scalp_vertices=v)
    np.testing.assert_allclose(a.positions, b.positions, atol=1e-6)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(scalp_vertices=np.zeros((5, 3))), r"scalp_vertices: 5 vertices given, the scalp mesh has \d+"),
        (dict(scalp_vertices=np.zeros((10, 2))), r"scalp_vertices: has shape \[10, 2\], expected \(\d+, 3\)"),
        (dict(scalp_vertices=np.zeros((10, 3), dtype=np.int32)), r"scalp_vertices: has dtype kind 'i'"),
        (dict(scalp_vertices="nope"), r"scalp_vertices"),
        (dict(scalp_matrix=np.diag([2.0, 2.0, 2.0, 1.0])), r"scalp_matrix: is not rigid .* identity matrix"),
        (dict(scalp_matrix=np.eye(3)), r"scalp_matrix: has shape \[3, 3\], expected \(4, 4\)"),
    ],
)
def test_bad_step_arguments_raise_argument_error(groom, kwargs, match):
    s = hairsys.Session.from_groom(*groom)
    with pytest.raises(hairsys.ArgumentError, match=match):
        s.step(**kwargs)
    assert s.frame == 1


def test_nan_vertices_are_refused(groom):
    v, t, pts, counts = groom
    s = hairsys.Session.from_groom(v, t, pts, counts)
    bad = v.copy()
    bad[7, 1] = np.nan
    with pytest.raises(hairsys.ArgumentError, match="scalp_vertices: vertex 7 is not finite"):
        s.step(scalp_vertices=bad)
    with pytest.raises(hairsys.ArgumentError, match="scalp_vertices"):
        hairsys.Session.from_groom(bad, t, pts, counts)


def test_bad_groom_arrays_raise_argument_error(groom):
    v, t, pts, counts = groom
    with pytest.raises(hairsys.ArgumentError, match="curve_counts: add up to"):
        hairsys.Session.from_groom(v, t, pts, counts[:-1])
    with pytest.raises(hairsys.ArgumentError, match=r"scalp_triangles: has shape \[\d+, 4\]"):
        hairsys.Session.from_groom(v, np.zeros((4, 4), dtype=int), pts, counts)
    with pytest.raises(hairsys.ArgumentError, match="scalp_triangles: has dtype kind 'f'"):
        hairsys.Session.from_groom(v, t.astype(float), pts, counts)
    with pytest.raises(hairsys.ArgumentError, match="scalp_triangles: entry .* is -1"):
        hairsys.Session.from_groom(v, t * 0 - 1, pts, counts)
    with pytest.raises(hairsys.ArgumentError, match="goal_weights: .* shape"):
        hairsys.Session.from_groom(v, t, pts, counts, goal_weights=np.ones(3))
    with pytest.raises(hairsys.ArgumentError, match="bogus: is not an option"):
        hairsys.Session.from_groom(v, t, pts, counts, bogus=1)
    with pytest.raises(hairsys.ArgumentError, match="curve_points: .*max_snap_distance"):
        hairsys.Session.from_groom(v, t, pts + [0.0, 0.0, 1.0], counts)
    assert issubclass(hairsys.ArgumentError, ValueError)


def test_collider_ids_and_poses_are_checked(groom):
    v, t, pts, counts = groom
    s = hairsys.Session.from_groom(
        v, t, pts, counts,
        colliders=[{"shape": "sphere", "radius": 0.03, "matrix": rotation_z(0, (0.3, 0, 0))}],
        scalp_collider=True, scalp_thickness=0.001,
    )
    assert s.collider_count == 2
    s.set_collider_pose(0, rotation_z(10, (0.25, 0, 0)))
    with pytest.raises(hairsys.ArgumentError, match="collider 5: does not exist: this session has 2"):
        s.set_collider_pose(5, np.eye(4))
    with pytest.raises(hairsys.ArgumentError, match="collider -1: does not exist"):
        s.set_collider_pose(-1, np.eye(4))
    with pytest.raises(hairsys.ArgumentError, match="collider 1: is the scalp collider"):
        s.set_collider_pose(1, np.eye(4))
    with pytest.raises(hairsys.ArgumentError, match="matrix: is not rigid"):
        s.set_collider_pose(0, np.diag([1.0, 1.0, 3.0, 1.0]))
    with pytest.raises(hairsys.ArgumentError, match=r'colliders\[0\]: shape "cube"'):
        hairsys.Session.from_groom(v, t, pts, counts, colliders=[{"shape": "cube"}])
    s.step()


def test_a_sphere_collider_pushes_hair_out(groom):
    v, t, pts, counts = groom
    # A sphere that sweeps through the hair from the side.
    s = hairsys.Session.from_groom(
        v, t, pts, counts, gravity=(0.0, 0.0, 0.0),
        colliders=[{"shape": "sphere", "radius": 0.04, "matrix": rotation_z(0, (0.3, 0, 0.12))}],
    )
    for f in range(24):
        x = 0.3 - 0.3 * (f + 1) / 24
        s.step()
        s.set_collider_pose(0, rotation_z(0, (x, 0, 0.12)))
    s.step()
    d = np.linalg.norm(s.positions - [0.0, 0.0, 0.12], axis=1)
    assert d.min() > 0.04 - 0.002, f"a point is {0.04 - d.min():.4f} m inside the sphere"


def test_stepping_after_a_failure_raises_until_restore(groom):
    s = hairsys.Session.from_groom(*groom)
    snap = s.snapshot()
    s.goal_stiffness = -1.0
    with pytest.raises(hairsys.SolverError, match="goal_stiffness"):
        s.step()
    with pytest.raises(hairsys.SessionFailedError, match="restore a snapshot"):
        s.step()
    s.restore(snap)  # the snapshot holds the solver, parameters included
    assert s.frame == 1 and s.goal_stiffness == 0.0
    s.step()
    assert s.frame == 2


def test_parameters_are_read_and_written(groom):
    s = hairsys.Session.from_groom(*groom)
    s.gravity = (0.0, 0.0, -1.0)
    assert list(s.gravity) == [0.0, 0.0, -1.0]
    s.goal_stiffness = 3.0
    s.air_drag = 1.5
    assert (s.goal_stiffness, s.air_drag) == (3.0, 1.5)
    assert s.hair_hair_friction is None
    with pytest.raises(hairsys.ArgumentError, match="hair–hair is off"):
        s.hair_hair_friction = 0.5
    with pytest.raises(hairsys.ArgumentError, match="field 0 does not exist"):
        s.set_field_strength(0, 1.0)
    h = hairsys.Session.from_groom(*groom, hair_hair_friction=0.2)
    assert abs(h.hair_hair_friction - 0.2) < 1e-7
    h.hair_hair_friction = 0.6
    assert abs(h.hair_hair_friction - 0.6) < 1e-7
    h.step()


def test_gravity_setter_changes_the_motion(groom):
    a = hairsys.Session.from_groom(*groom)
    b = hairsys.Session.from_groom(*groom)
    b.gravity = (0.0, 0.0, 0.0)
    for _ in range(5):
        a.step()
        b.step()
    tips = a.strand_offsets[1:] - 1
    assert a.positions[tips, 2].mean() < b.positions[tips, 2].mean() - 1e-3


def test_goal_weights_hold_strands_to_their_rest_shape(groom):
    v, t, pts, counts = groom
    free = hairsys.Session.from_groom(v, t, pts, counts, goal_stiffness=2.0)
    held = hairsys.Session.from_groom(v, t, pts, counts, goal_stiffness=2.0, goal_weights=np.ones(len(pts)))
    for _ in range(12):
        free.step()
        held.step()
    dev = lambda s: np.linalg.norm(s.positions - pts, axis=1).max()
    assert dev(held) < 0.5 * dev(free)


def test_snapshot_restore_gives_identical_frames(small_scene):
    s = hairsys.Session.from_scene(small_scene)
    for _ in range(3):
        s.step()
    snap = s.snapshot()
    assert snap.frame == 4
    first = []
    for _ in range(4):
        s.step()
        first.append(np.array(s.positions))
    s.restore(snap)
    assert s.frame == 4
    for f in first:
        s.step()
        assert np.array_equal(s.positions, f)


def test_cache_is_readable_by_mcap_and_by_hairsys_cache(tmp_path, small_scene):
    s = hairsys.Session.from_scene(small_scene)
    path = tmp_path / "out.mcap"
    s.write_cache(path)
    kept = {1: np.array(s.positions)}
    for _ in range(5):
        s.step()
        kept[s.frame] = np.array(s.positions)
    summary = s.finish_cache()
    assert summary["frames"] == 6 and summary["first_frame"] == 1 and path.exists()
    frames, meta = read_mcap_frames(path)
    assert sorted(frames) == list(range(1, 7))
    assert meta["fps"] == "24" and "small" in meta["scene_toml"]
    for f, p in kept.items():
        assert np.array_equal(frames[f][0], p)
    c = hairsys.Cache(path)
    assert c.frames == list(range(1, 7)) and len(c) == 6 and c.point_count == s.point_count
    pos, vel = c.frame(4)
    assert pos.flags.owndata or pos.base is not None
    assert np.array_equal(pos, kept[4]) and vel.shape == pos.shape
    with pytest.raises(hairsys.CacheError, match="frame 40"):
        c.frame(40)
    with pytest.raises(hairsys.CacheError):
        hairsys.Cache(tmp_path / "missing.mcap")
    assert issubclass(hairsys.CacheError, OSError)


def test_restore_is_refused_while_recording(tmp_path, groom):
    s = hairsys.Session.from_groom(*groom)
    snap = s.snapshot()
    s.write_cache(tmp_path / "c.mcap")
    with pytest.raises(hairsys.ArgumentError, match="finish the cache first"):
        s.restore(snap)
    s.finish_cache()


def test_scene_errors_name_the_file(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text("[scene]\nframes = [1, 10]\nbogus = 1\n")
    with pytest.raises(hairsys.SceneError, match="bad.toml"):
        hairsys.Session.from_scene(p)
    with pytest.raises(hairsys.SceneError, match="cannot read"):
        hairsys.Session.from_scene(tmp_path / "none.toml")


def test_children_are_numpy_arrays(groom):
    s = hairsys.Session.from_groom(*groom)
    s.step()
    c = s.children(per_parent=3)
    assert len(c) == 3 * s.strand_count
    assert c.points.shape == (int(c.vertex_counts.sum()), 3) and c.points.dtype == np.float32
    assert c.widths.shape == (len(c.points),)
    assert c.parent.max() == s.strand_count - 1
    starts = np.concatenate([[0], np.cumsum(c.vertex_counts)[:-1]]).astype(np.int64)
    roots = c.points[starts]
    parent_roots = s.positions[s.strand_offsets[c.parent]]
    assert np.linalg.norm(roots - parent_roots, axis=1).max() <= 0.005 * 1.01


def test_children_of_given_positions_are_the_children_of_that_frame(groom):
    """Children of a frame handed back as `positions` and `scalp_vertices` (what a host playing a
    cache does) are bit for bit the children the session makes when it stands at that frame,
    and making them leaves the session where it is."""
    v, t, pts, counts = groom
    moved = np.asarray(v, dtype=np.float64) + (0.01, 0.0, 0.02)
    live = hairsys.Session.from_groom(v, t, pts, counts)
    for _ in range(3):
        live.step(scalp_vertices=moved)
    frame = np.array(live.positions)
    expected = live.children(per_parent=4, clump=0.5, roughness=0.001, tip_width=0.0)

    other = hairsys.Session.from_groom(v, t, pts, counts)
    before = np.array(other.positions)
    made = other.children(per_parent=4, clump=0.5, roughness=0.001, tip_width=0.0,
                          positions=frame, scalp_vertices=moved)
    assert np.array_equal(made.points, expected.points)
    assert np.array_equal(made.vertex_counts, expected.vertex_counts)
    assert np.array_equal(made.widths, expected.widths)
    assert made.widths.min() == 0.0  # the tips, tip_width 0
    assert np.array_equal(other.positions, before) and other.frame == 1

    shown = other.children(per_parent=10, display=True, display_fraction=0.3, positions=frame,
                           scalp_vertices=moved)
    assert len(shown) == 3 * other.strand_count
    with pytest.raises(hairsys.ArgumentError, match="positions"):
        other.children(positions=frame[:-1])
    with pytest.raises(hairsys.ArgumentError, match="scalp_vertices"):
        other.children(positions=frame, scalp_vertices=moved[:-1])


def test_interpolated_sim_hairs(groom):
    v, t, pts, counts = groom
    s = hairsys.Session.from_groom(v, t, pts, counts, sim_hairs=200, k=3, points=7, seed=2)
    assert s.strand_count == 200 and s.point_count == 1400


def test_threads_option_gives_the_same_bits(small_scene):
    a = hairsys.Session.from_scene(small_scene, threads=1)
    b = hairsys.Session.from_scene(small_scene, threads=2)
    for _ in range(4):
        a.step()
        b.step()
    assert np.array_equal(a.positions, b.positions)
    with pytest.raises(hairsys.ArgumentError, match="threads"):
        hairsys.Session.from_scene(small_scene, threads=0)


def test_python_session_is_bit_identical_to_hairsys_simulate(tmp_path, small_scene):
    out = tmp_path / "cli.mcap"
    subprocess.run([hairsys_binary(), "simulate", str(small_scene), "--cache", str(out), "--quiet"],
                   check=True)
    frames, _ = read_mcap_frames(out)
    assert sorted(frames) == list(range(1, 13))
    s = hairsys.Session.from_scene(small_scene)
    assert np.array_equal(s.positions, frames[1][0])
    for f in range(2, 13):
        s.step()
        assert s.frame == f
        assert np.array_equal(s.positions, frames[f][0]), f"frame {f} differs"
        assert np.array_equal(s.velocities, frames[f][1]), f"frame {f} velocities differ"


WIND_SCENE = """version = 1
[scene]
frames = [1, 13]
[physics]
air_drag = 2.0
[[strands]]
points = [[0, 0, 0], [0, 0, -0.05], [0, 0, -0.1], [0, 0, -0.15], [0, 0, -0.2]]
[[fields]]
type = "wind"
strength = 3.0
direction = [1, 0, 0]
"""


def test_field_direction_and_center_setters_turn_the_wind(tmp_path):
    path = tmp_path / "wind.toml"
    path.write_text(WIND_SCENE)
    east = hairsys.Session.from_scene(str(path))
    west = hairsys.Session.from_scene(str(path))
    assert west.field_count == 1
    west.set_field_direction(0, (-2.0, 0.0, 0.0))  # any length: normalised
    west.set_field_center(0, (0.0, 0.0, 1.0))  # no falloff: the center changes nothing
    for _ in range(6):
        east.step()
        west.step()
    tip_east, tip_west = east.positions[-1], west.positions[-1]
    assert tip_east[0] > 0.01, tip_east
    np.testing.assert_allclose(tip_west, tip_east * [-1, 1, 1], atol=1e-6)
    with pytest.raises(hairsys.ArgumentError, match="direction"):
        west.set_field_direction(0, (0.0, 0.0, 0.0))
    with pytest.raises(hairsys.ArgumentError, match="center"):
        west.set_field_center(0, (float("nan"), 0.0, 0.0))
    with pytest.raises(hairsys.ArgumentError, match="field 3 does not exist"):
        west.set_field_direction(3, (1.0, 0.0, 0.0))


@pytest.mark.parametrize("word, substeps", [("implicit-euler", 16), ("bdf2", 7)])
def test_the_integrator_keyword_runs_an_implicit_integrator_at_its_accuracy_limit(
    groom, word, substeps
):
    """A stiff groom (2,000 N/m springs on 2 cm segments) asks semi-implicit Euler for hundreds of
    substeps a frame (737); implicit Euler takes its 16 (h = 1/384 s at 24 fps), BDF2 its 7
    (h = 1/168 s), and both keep the rest lengths under gravity."""
    stiff = dict(stretch_stiffness=2000.0, mass_per_length=0.001)
    explicit = hairsys.Session.from_groom(*groom, integrator="semi-implicit-euler", **stiff)
    implicit = hairsys.Session.from_groom(*groom, integrator=word, **stiff)
    e, i = explicit.step(), implicit.step()
    assert i["substeps"] == substeps and e["substeps"] > 48, (e["substeps"], i["substeps"])
    assert np.isfinite(implicit.positions).all()
    assert i["max_stretch"] < 0.01
    # Both settle into the same equilibrium (a statics answer, whatever the integrator): within
    # 0.5 mm after 10 s (implicit Euler measured 0.13 mm; 5 mm apart at 1 s, where the explicit
    # run still swings at 0.3 m/s and implicit Euler's damping has all but stopped it).
    for _ in range(239):
        explicit.step()
        implicit.step()
    assert np.abs(explicit.positions - implicit.positions).max() < 5e-4


def test_an_unknown_integrator_is_refused(groom):
    with pytest.raises(hairsys.ArgumentError, match=r'integrator: unknown integrator "rk4": use "auto"'):
        hairsys.Session.from_groom(*groom, integrator="rk4")


def test_auto_chooses_as_a_scene_file_does_from_the_motion_the_host_expects(groom):
    """The stiff groom asks semi-implicit Euler for hundreds of substeps: "auto" (the default)
    takes BDF2 at its 7, bit for bit a session that names it, also with a colliding scalp.
    A collider the host moves at a speed it does not give, or fast against its size (a 0.05 m
    ball at 24 m/s crosses 2.9 of its radius in a BDF2 substep), keeps semi-implicit Euler, as
    a scene file with such a collider does; at 1 m/s (0.12 of its radius) BDF2."""
    stiff = dict(stretch_stiffness=2000.0, mass_per_length=0.001)
    auto = hairsys.Session.from_groom(*groom, **stiff)
    named = hairsys.Session.from_groom(*groom, integrator="bdf2", **stiff)
    a, n = auto.step(), named.step()
    assert a["substeps"] == n["substeps"] == 7, (a["substeps"], n["substeps"])
    np.testing.assert_array_equal(auto.positions, named.positions)
    scalp = hairsys.Session.from_groom(*groom, scalp_collider=True, **stiff)
    assert scalp.step()["substeps"] == 7
    far = np.eye(4)
    far[:3, 3] = (0.0, 0.0, 5.0)
    ball = dict(shape="sphere", radius=0.05, matrix=far)
    for speed, bdf2 in [(None, False), (24.0, False), (1.0, True)]:
        s = hairsys.Session.from_groom(*groom, colliders=[ball], collider_speed=speed, **stiff)
        assert (s.step()["substeps"] == 7) == bdf2, speed


def segment_strain(positions, rest, offsets):
    """Largest len / rest − 1 over every segment of every strand."""
    worst = -1.0
    for a, b in zip(offsets[:-1], offsets[1:]):
        now = np.linalg.norm(np.diff(positions[a:b], axis=0), axis=1)
        was = np.linalg.norm(np.diff(rest[a:b], axis=0), axis=1)
        worst = max(worst, float((now / was - 1.0).max()))
    return worst


def test_max_strain_keeps_every_segment_within_the_limit(groom):
    v, t, pts, counts = groom
    # Heavy hair on soft springs: gravity alone stretches it far past 1 %.
    soft = dict(stretch_stiffness=1.0, mass_per_length=0.05)
    free = hairsys.Session.from_groom(v, t, pts, counts, **soft)
    held = hairsys.Session.from_groom(v, t, pts, counts, max_strain=0.01, **soft)
    for _ in range(12):
        free.step()
        report = held.step()
    offsets = held.strand_offsets
    assert segment_strain(free.positions, pts, offsets) > 0.03
    assert segment_strain(held.positions, pts, offsets) <= 0.01 + 1e-4
    assert report["max_stretch"] <= 0.01 + 1e-4
    with pytest.raises(hairsys.SolverError, match="max_strain"):
        hairsys.Session.from_groom(v, t, pts, counts, max_strain=-0.1)


def test_the_report_splits_the_step_by_phase_and_names_the_integrator(groom):
    v, t, pts, counts = groom
    s = hairsys.Session.from_groom(v, t, pts, counts, integrator="bdf2")
    assert s.integrator == "bdf2"
    assert hairsys.Session.from_groom(*groom, integrator="semi-implicit-euler").integrator == \
        "semi-implicit-euler"
    report = s.step()
    phases = report["phase_ms"]
    assert set(phases) == {"roots", "strands", "contacts", "volume", "fields"}
    assert all(ms >= 0.0 for ms in phases.values())
    assert sum(phases.values()) <= report["step_ms"]
