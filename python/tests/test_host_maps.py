"""Painted values a host hands `Session.from_groom` per point and per strand (issue 20): pinned
points keep the groom's shape, per-curve stiffness factors change only their strand's motion,
and USD primvars reach a scene's maps: a scalp authored with Pixar's usd-core, its primvars
sampled at each root under every USD interpolation, read back through the hair's lengths."""

import numpy as np
import pytest

import hairsys
from hairsys_testing import sphere_groom

FRAMES = 6


def run(session, frames=FRAMES):
    for _ in range(frames):
        session.step()
    return np.array(session.positions)


def free_and(groom, **options):
    """Positions after FRAMES frames without and with `options` (fixed substeps, so that
    factors on some strands cannot change the others' step)."""
    v, t, pts, counts = groom
    base = dict(substeps=300, bend_stiffness=1.0)
    free = run(hairsys.Session.from_groom(v, t, pts, counts, **base))
    mapped = run(hairsys.Session.from_groom(v, t, pts, counts, **base, **options))
    return free, mapped


def test_pinned_points_keep_the_groom_shape_and_leave_the_other_strands_alone(groom):
    v, t, pts, counts = groom
    strand = np.repeat(np.arange(len(counts)), counts)
    chosen = strand % 3 == 0
    free, pinned = free_and(groom, pinned=chosen)
    np.testing.assert_allclose(pinned[chosen], pts[chosen], atol=1e-6)
    assert np.array_equal(pinned[~chosen], free[~chosen])
    moved = np.linalg.norm(free - pts, axis=1)
    assert moved[chosen].max() > 1e-3, "the free strands must move for the test to test pins"


def test_a_strand_scale_changes_only_its_strands_motion(groom):
    v, t, pts, counts = groom
    softer = np.arange(len(counts)) % 2 == 1
    bend = np.where(softer, 0.0, 1.0)
    free, scaled = free_and(groom, strand_scales={"bend": bend})
    point_softer = np.repeat(softer, counts)
    assert np.array_equal(scaled[~point_softer], free[~point_softer])
    tips = np.cumsum(counts) - 1
    drop = lambda pos: pts[tips, 2] - pos[tips, 2]
    assert np.mean(drop(scaled)[softer]) > np.mean(drop(free)[softer]) + 1e-3


def test_strand_scales_blend_over_interpolated_hairs(groom):
    """Interpolated hairs take their guides' factors blended by their weights: a bend factor 0
    on every curve gives every hair no bending stiffness, as bend_stiffness = 0 does."""
    v, t, pts, counts = groom
    opts = dict(sim_hairs=60, substeps=300)
    stiff = run(hairsys.Session.from_groom(v, t, pts, counts, bend_stiffness=1.0, **opts), 3)
    limp = run(hairsys.Session.from_groom(v, t, pts, counts, bend_stiffness=0.0, **opts), 3)
    zero = np.zeros(len(counts))
    scaled = run(hairsys.Session.from_groom(
        v, t, pts, counts, bend_stiffness=1.0, strand_scales={"bend": zero}, **opts), 3)
    np.testing.assert_allclose(scaled, limp, atol=1e-6)
    assert np.abs(stiff - limp).max() > 1e-3, "bending must matter for the test to test it"


@pytest.mark.parametrize("kwargs, match", [
    (dict(pinned=np.zeros(3, dtype=bool)), "pinned.*one flag per point"),
    (dict(pinned=np.zeros(1, dtype=np.float32)), "pinned.*expected bool"),
    (dict(strand_scales={"bendy": np.ones(2)}), "not a factor; the keys are stretch"),
    (dict(strand_scales={"bend": np.ones(2)}), "strand_scales.*2 entries for"),
    (dict(strand_scales={"stretch": None}), "strand_scales"),
    (dict(strand_scales=[1.0]), "give a dict"),
])
def test_bad_painted_values_are_refused_naming_the_argument(groom, kwargs, match):
    v, t, pts, counts = groom
    if "pinned" in kwargs and kwargs["pinned"].dtype == np.float32:
        kwargs = dict(pinned=np.zeros(len(pts), dtype=np.float32))
    with pytest.raises(hairsys.ArgumentError, match=match):
        hairsys.Session.from_groom(v, t, pts, counts, **kwargs)


def test_a_negative_factor_and_pins_on_guides_are_refused(groom):
    v, t, pts, counts = groom
    bad = -np.ones(len(counts))
    with pytest.raises(hairsys.ArgumentError, match="strand_scales.*bend"):
        hairsys.Session.from_groom(v, t, pts, counts, strand_scales={"bend": bad})
    with pytest.raises(hairsys.ArgumentError, match="pinned.*sim_hairs"):
        hairsys.Session.from_groom(v, t, pts, counts, sim_hairs=10,
                                   pinned=np.zeros(len(pts), dtype=bool))


# USD primvars as map sources, through a scene: a flat grid scalp authored with usd-core,
# straight hair grown on it whose lengths a [maps.length] primvar trims.

CELLS, SIDE, LENGTH = 4, 0.2, 0.05


def field(x, y):
    """A linear field over the grid, within [0.3, 0.9]."""
    return 0.3 + 1.5 * x + 1.5 * y


def author_scalp(path):
    """A CELLS × CELLS grid of quads in z = 0 (m, Z up) with the primvars `vertex_lin`
    (vertex), `corner_lin` (faceVarying, indexed), `face` (uniform), `whole` (constant) and
    `color` (color3f, vertex; the field in green), written with Pixar's USD."""
    from pxr import Sdf, Usd, UsdGeom, Vt

    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    mesh = UsdGeom.Mesh.Define(stage, "/scalp")
    n = CELLS + 1
    step = SIDE / CELLS
    points = [(i * step, j * step, 0.0) for j in range(n) for i in range(n)]
    indices = []
    for j in range(CELLS):
        for i in range(CELLS):
            a = j * n + i
            indices += [a, a + 1, a + n + 1, a + n]
    mesh.CreatePointsAttr(points)
    mesh.CreateFaceVertexCountsAttr([4] * CELLS * CELLS)
    mesh.CreateFaceVertexIndicesAttr(indices)
    api = UsdGeom.PrimvarsAPI(mesh)
    lin = [field(p[0], p[1]) for p in points]
    api.CreatePrimvar("vertex_lin", Sdf.ValueTypeNames.FloatArray,
                      UsdGeom.Tokens.vertex).Set(lin)
    corner = api.CreatePrimvar("corner_lin", Sdf.ValueTypeNames.FloatArray,
                               UsdGeom.Tokens.faceVarying)
    corner.Set(lin)
    corner.SetIndices(Vt.IntArray(indices))
    api.CreatePrimvar("face", Sdf.ValueTypeNames.FloatArray, UsdGeom.Tokens.uniform).Set(
        [face_value(f) for f in range(CELLS * CELLS)])
    api.CreatePrimvar("whole", Sdf.ValueTypeNames.Float, UsdGeom.Tokens.constant).Set(0.4)
    api.CreatePrimvar("color", Sdf.ValueTypeNames.Color3fArray, UsdGeom.Tokens.vertex).Set(
        [(0.9, value, 0.1) for value in lin])
    api.CreatePrimvar("short", Sdf.ValueTypeNames.FloatArray, UsdGeom.Tokens.vertex).Set(
        [0.5, 0.5, 0.5])
    stage.GetRootLayer().Save()


def face_value(f):
    return 0.3 + 0.04 * f


def lengths_session(tmp_path, primvar, channel=None):
    author_scalp(tmp_path / "scalp.usda")
    extra = f'channel = "{channel}"\n' if channel else ""
    scene = tmp_path / "scene.toml"
    scene.write_text(f"""
[scene]
frames = [1, 2]
[scalp.mesh]
kind = "usd"
path = "scalp.usda"
prim = "/scalp"
[hair]
count = 200
length = {LENGTH}
segments = 4
seed = 11
[maps.length]
primvar = "{primvar}"
{extra}""")
    s = hairsys.Session.from_scene(scene)
    pos = np.array(s.positions)
    off = s.strand_offsets
    roots = pos[off[:-1]]
    lengths = np.array([np.linalg.norm(np.diff(pos[a:b], axis=0), axis=1).sum()
                        for a, b in zip(off[:-1], off[1:])])
    return roots, lengths


@pytest.mark.parametrize("primvar, channel", [
    ("vertex_lin", None), ("corner_lin", None), ("color", "g")])
def test_a_usd_primvar_trims_each_hair_to_the_painted_field_at_its_root(
        tmp_path, primvar, channel):
    roots, lengths = lengths_session(tmp_path, primvar, channel)
    assert len(roots) == 200
    np.testing.assert_allclose(lengths, LENGTH * field(roots[:, 0], roots[:, 1]), rtol=1e-4)


def test_uniform_and_constant_primvars_give_each_root_its_face_or_the_whole_value(tmp_path):
    roots, lengths = lengths_session(tmp_path, "face")
    cell = SIDE / CELLS
    fx, fy = roots[:, 0] / cell, roots[:, 1] / cell
    inner = (np.abs(fx - np.round(fx)) > 1e-3) & (np.abs(fy - np.round(fy)) > 1e-3)
    face = np.floor(fy).astype(int) * CELLS + np.floor(fx).astype(int)
    np.testing.assert_allclose(lengths[inner], LENGTH * face_value(face[inner]), rtol=1e-4)
    assert inner.sum() > 150
    _, lengths = lengths_session(tmp_path, "whole")
    np.testing.assert_allclose(lengths, LENGTH * 0.4, rtol=1e-4)


def test_a_primvar_count_that_does_not_fit_its_interpolation_is_a_scene_error(tmp_path):
    with pytest.raises(hairsys.SceneError, match=r"(?s)maps\.length.*scalp\.usda.*primvars:short"
                                                 r".*3 values.*25 points"):
        lengths_session(tmp_path, "short")
