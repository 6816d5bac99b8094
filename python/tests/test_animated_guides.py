"""Animated guides from Python: a host poses the guides and hands the hair to them with the sim
weight; bad poses and weights raise ArgumentError naming the argument."""

import numpy as np
import pytest

import hairsys

GUIDED_SCENE = """
[scene]
name = "guided"
fps = 24.0
frames = [1, 12]
[solver]
max_strain = 0.01
[scalp.mesh]
kind = "builtin-head"
[guides]
count = 30
length = 0.2
segments = 8
seed = 2
region = { direction = [0.0, 0.4, 1.0], max_angle_deg = 80.0 }
comb_direction = [0.0, 1.0, -0.6]
comb_angle_deg = 50.0
[sim_hairs]
count = 120
seed = 3
distance = "euclidean"
clearance = 0.003
"""


@pytest.fixture
def session(tmp_path):
    p = tmp_path / "guided.toml"
    p.write_text(GUIDED_SCENE)
    return hairsys.Session.from_scene(str(p))


def test_weight_one_puts_the_hair_on_the_posed_guides(session):
    counts = session.guide_point_counts
    assert len(counts) == 30 and all(c == 9 for c in counts)
    start, end = session.guided_strands
    assert end - start == 120
    # Every guide a straight line 0.2 m along +X (the roots are taken from the points, so only
    # the shape matters): a pose far from the combed groom. No `[guides.sim_weight]` in the
    # scene, so the host's weight alone hands the hair over.
    points = np.zeros((sum(counts), 3), np.float32)
    points[:, 0] = np.tile(np.linspace(0.0, 0.2, 9), 30)
    session.set_guide_pose(points)
    session.set_sim_weight(1.0)
    session.step()
    off = session.strand_offsets
    pos = np.array(session.positions)
    chords = np.array([pos[off[s + 1] - 1] - pos[off[s]] for s in range(start, end)])
    # Straight guides of one length blend to straight hair of that length: the chord is the
    # whole hair.
    assert np.all(np.linalg.norm(chords, axis=1) > 0.199), chords
    # Each guide's shape reaches a sim hair turned by the smallest rotation between the two
    # roots' normals (the groom's transport), so hairs point along +X up to that turn: on
    # average, clearly +X (the combed groom points back, along +Y).
    mean = chords.mean(axis=0)
    assert mean[0] / np.linalg.norm(mean) > 0.9, mean


def test_the_groom_as_a_pose_at_weight_one_is_the_rest_state(session):
    before = np.array(session.positions)
    groom = session.guide_groom_points
    assert groom.shape == (sum(session.guide_point_counts), 3)
    session.set_guide_pose(groom)
    session.set_sim_weight(1.0)
    session.step()
    # The head does not move, so the hair on its guides' own groom is where it started: at rest.
    start, end = session.guided_strands
    off = session.strand_offsets
    sim = slice(off[start], off[end])
    after = np.array(session.positions)
    np.testing.assert_allclose(after[sim], before[sim], atol=2e-6)


def test_bad_poses_and_weights_raise(session):
    total = sum(session.guide_point_counts)
    with pytest.raises(hairsys.ArgumentError, match="points"):
        session.set_guide_pose(np.zeros((total - 1, 3), np.float32))
    bad = np.zeros((total, 3), np.float32)
    bad[5, 1] = np.nan
    with pytest.raises(hairsys.ArgumentError, match="guide 0 point 5 is not finite"):
        session.set_guide_pose(bad)
    with pytest.raises(hairsys.ArgumentError, match=r"sim_weight.*\[0, 1\]"):
        session.set_sim_weight(1.5)
    with pytest.raises(hairsys.ArgumentError, match="one per sim hair"):
        session.set_strand_sim_weights(np.ones(3, np.float32))
    with pytest.raises(hairsys.ArgumentError, match=r"weights\[0\]"):
        session.set_strand_sim_weights(np.full(120, -0.5, np.float32))
