"""Per-region physics from Python: a host reads a region's parameters and changes them between
frames; unknown regions and keys raise ArgumentError naming them."""

import numpy as np
import pytest

import hairsys

REGION_SCENE = """
[scene]
name = "regions"
fps = 24.0
frames = [1, 12]
[solver]
substeps = 240
[physics]
stretch_stiffness = 40.0
bend_stiffness = 2.0
stretch_damping = 200.0
air_drag = 2.0
[scalp.mesh]
kind = "builtin-head"
[hair]
count = 120
length = 0.12
segments = 8
seed = 3
[[regions]]
name = "fringe"
region = { direction = [0.0, -1.0, 0.0], max_angle_deg = 45.0 }
bend_stiffness = 2.0
"""


def session(tmp_path, text=REGION_SCENE):
    p = tmp_path / "regions.toml"
    p.write_text(text)
    return hairsys.Session.from_scene(str(p))


def test_region_parameters_read_back(tmp_path):
    s = session(tmp_path)
    assert s.region_names == ["fringe"]
    params = s.region_params("fringe")
    assert params["bend_stiffness"] == 2.0
    assert params["stretch_stiffness"] is None
    strands = s.region_strands("fringe")
    assert 0 < len(strands) < 120 and strands == sorted(strands)


def test_a_stiffer_region_set_between_frames_moves_only_its_strands(tmp_path):
    plain = session(tmp_path)
    stiff = session(tmp_path)
    stiff.set_region_params("fringe", {"bend_stiffness": 20.0})
    assert stiff.region_params("fringe")["bend_stiffness"] == 20.0
    for _ in range(11):
        plain.step()
        stiff.step()
    offsets = np.asarray(plain.strand_offsets)
    fringe = set(stiff.region_strands("fringe"))
    a, b = np.asarray(plain.positions), np.asarray(stiff.positions)
    for s in range(len(offsets) - 1):
        same = np.array_equal(a[offsets[s] : offsets[s + 1]], b[offsets[s] : offsets[s + 1]])
        assert same == (s not in fringe), s
    # The same as a scene that gave 20 N/m from the start.
    scene20 = session(
        tmp_path,
        REGION_SCENE.replace(
            "max_angle_deg = 45.0 }\nbend_stiffness = 2.0",
            "max_angle_deg = 45.0 }\nbend_stiffness = 20.0",
        ),
    )
    for _ in range(11):
        scene20.step()
    assert np.array_equal(np.asarray(scene20.positions), b)


def test_bad_region_arguments_raise_argument_error(tmp_path):
    s = session(tmp_path)
    with pytest.raises(hairsys.ArgumentError, match="back"):
        s.set_region_params("back", {"bend_stiffness": 1.0})
    with pytest.raises(hairsys.ArgumentError, match="stifness"):
        s.set_region_params("fringe", {"bend_stifness": 1.0})
    with pytest.raises(hairsys.ArgumentError, match="mass_scale"):
        s.set_region_params("fringe", {"mass_scale": 2.0})
    with pytest.raises(hairsys.ArgumentError, match="bend_stiffness"):
        s.set_region_params("fringe", {"bend_stiffness": -1.0})
    with pytest.raises(hairsys.ArgumentError, match="back"):
        s.region_params("back")
