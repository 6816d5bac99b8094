"""Whole-run USD export (`hairsys cache export`, `render-children export`) read back with
Pixar's USD (usd-core, module `pxr`): every file opens; time samples per frame (and per shutter
sample) with the cache's own positions, velocities and cubic Hermite sub-frames; extents that
bound every sample; `vertex` widths and `uniform` primvars of the right length; the keyed scalp
animated; `.usda` and `.usdc` the same; two `--frames` halves stitched by value clips into one
shot (the README's recipe)."""

import numpy as np
import pytest

from usd_shot import FRAMES, STRANDS, hairsys, small_run

pxr = pytest.importorskip("pxr", reason="pip install usd-core (scripts/test-requirements.txt)")
from pxr import Usd, UsdGeom  # noqa: E402


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """(directory, cache path, cache frames) of the small default-scene run."""
    d = tmp_path_factory.mktemp("usd_export")
    cache, frames = small_run(d)
    return d, cache, frames


def points(attr, t):
    return np.array(attr.Get(Usd.TimeCode(t)), dtype=np.float32).reshape(-1, 3)


def check_extent(prim, t):
    """The authored extent at `t` bounds the points, and contains USD's own computed extent."""
    b = UsdGeom.Boundable(prim)
    lo, hi = (np.array(v) for v in b.GetExtentAttr().Get(Usd.TimeCode(t)))
    p = points(UsdGeom.PointBased(prim).GetPointsAttr(), t)
    assert (p >= lo).all() and (p <= hi).all(), f"{prim.GetPath()} at {t}"
    clo, chi = (np.array(v) for v in UsdGeom.Boundable.ComputeExtentFromPlugins(b, Usd.TimeCode(t)))
    assert (clo >= lo - 1e-6).all() and (chi <= hi + 1e-6).all(), f"{prim.GetPath()} at {t}"


def check_primvars(prim, curves, names):
    api = UsdGeom.PrimvarsAPI(prim)
    for name, type_name in names.items():
        pv = api.GetPrimvar(name)
        assert pv.HasValue(), f"primvars:{name} missing"
        assert pv.GetInterpolation() == UsdGeom.Tokens.uniform, name
        assert str(pv.GetTypeName()) == type_name, (name, pv.GetTypeName())
        assert len(pv.Get()) == curves, name


def hermite(frames, fps, t):
    """The cache's cubic Hermite positions at time code `t`, computed here in float64 from the
    two cached frames around it and their velocities (hair-cache/src/sample.rs's definition)."""
    a, b = int(np.floor(t)), int(np.floor(t)) + 1
    (p0, v0), (p1, v1) = frames[a], frames[b]
    h = 1.0 / fps
    s = t - a
    h00, h10 = 2 * s**3 - 3 * s**2 + 1, (s**3 - 2 * s**2 + s) * h
    h01, h11 = -2 * s**3 + 3 * s**2, (s**3 - s**2) * h
    f = lambda x: x.astype(np.float64)  # noqa: E731
    return f(p0) * h00 + f(v0) * h10 + f(p1) * h01 + f(v1) * h11


@pytest.mark.parametrize("ext", ["usdc", "usda"])
def test_whole_run_is_one_animated_stage_with_the_caches_frames(run, ext):
    d, _, frames = run
    hairsys("cache", "export", "c.mcap", "-o", f"shot.{ext}", cwd=d)
    stage = Usd.Stage.Open(str(d / f"shot.{ext}"))
    assert stage, f"usd-core cannot open shot.{ext}"
    assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.z
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0
    assert stage.GetTimeCodesPerSecond() == 24.0
    assert (stage.GetStartTimeCode(), stage.GetEndTimeCode()) == FRAMES
    prim = stage.GetPrimAtPath("/hair")
    curves = UsdGeom.BasisCurves(prim)
    assert curves and curves.GetTypeAttr().Get() == "linear"
    times = [float(f) for f in range(FRAMES[0], FRAMES[1] + 1)]
    for attr in (curves.GetPointsAttr(), curves.GetVelocitiesAttr(), curves.GetExtentAttr()):
        assert attr.GetTimeSamples() == times, attr.GetName()
    counts = list(curves.GetCurveVertexCountsAttr().Get())
    assert len(counts) == STRANDS
    widths = np.array(curves.GetWidthsAttr().Get())
    assert curves.GetWidthsInterpolation() == UsdGeom.Tokens.vertex
    assert len(widths) == sum(counts) and (widths > 0).all()
    for f in range(FRAMES[0], FRAMES[1] + 1):
        pos, vel = frames[f]
        assert np.array_equal(points(curves.GetPointsAttr(), f), pos), f"points at {f}"
        assert np.array_equal(points(curves.GetVelocitiesAttr(), f), vel), f"velocities at {f}"
        check_extent(prim, f)
    check_primvars(prim, STRANDS, {"id": "int[]", "surface_uv_coordinate": "float2[]",
                                   "st": "texCoord2f[]"})
    assert list(UsdGeom.PrimvarsAPI(prim).GetPrimvar("id").Get()) == list(range(STRANDS))
    uv = np.array(UsdGeom.PrimvarsAPI(prim).GetPrimvar("surface_uv_coordinate").Get())
    assert ((uv >= 0) & (uv <= 1)).all(), "root UVs inside the scalp's UV square"
    # The default scene's head turns (keyed scalp motion): /scalp is animated with it.
    scalp = stage.GetPrimAtPath("/scalp")
    mesh = UsdGeom.Mesh(scalp)
    assert mesh.GetPointsAttr().GetTimeSamples() == times
    assert not np.array_equal(points(mesh.GetPointsAttr(), 1), points(mesh.GetPointsAttr(), 12))
    for f in (1, 12, 24):
        check_extent(scalp, f)


def test_shutter_samples_are_the_caches_hermite_sub_frames(run):
    d, _, frames = run
    hairsys("cache", "export", "c.mcap", "-o", "blur.usdc", "--frames", "11-13",
            "--shutter", "-0.25,0.25", cwd=d)
    stage = Usd.Stage.Open(str(d / "blur.usdc"))
    curves = UsdGeom.BasisCurves(stage.GetPrimAtPath("/hair"))
    times = [10.75, 11.0, 11.25, 11.75, 12.0, 12.25, 12.75, 13.0, 13.25]
    assert curves.GetPointsAttr().GetTimeSamples() == times
    assert curves.GetExtentAttr().GetTimeSamples() == times
    assert (stage.GetStartTimeCode(), stage.GetEndTimeCode()) == (10.75, 13.25)
    for t in times:
        want = hermite(frames, 24.0, t)
        got = points(curves.GetPointsAttr(), t)
        assert np.abs(got - want).max() < 1e-6, f"points at {t}"
        check_extent(stage.GetPrimAtPath("/hair"), t)


def test_children_at_every_time_code_are_render_childrens_own(run):
    d, _, _ = run
    hairsys("cache", "export", "c.mcap", "-o", "kids.usdc", "--frames", "1-3", "--children",
            "--count", "600", "--shutter", "-0.25,0.25", cwd=d)
    hairsys("render-children", "export", "--cache", "c.mcap", "--frame", "2", "--count", "600",
            "-o", "two.usda", cwd=d)
    stage = Usd.Stage.Open(str(d / "kids.usdc"))
    prim = stage.GetPrimAtPath("/children")
    curves = UsdGeom.BasisCurves(prim)
    # 0.75 lies before the first cached frame and is left out.
    times = [1.0, 1.25, 1.75, 2.0, 2.25, 2.75, 3.0, 3.25]
    for attr in (curves.GetPointsAttr(), curves.GetVelocitiesAttr(), curves.GetExtentAttr()):
        assert attr.GetTimeSamples() == times, attr.GetName()
    counts = curves.GetCurveVertexCountsAttr().Get()
    assert len(counts) == 600
    assert curves.GetWidthsInterpolation() == UsdGeom.Tokens.vertex
    assert len(curves.GetWidthsAttr().Get()) == sum(counts)
    check_primvars(prim, 600, {"id": "int[]", "parent": "int[]", "random": "float[]",
                               "surface_uv_coordinate": "float2[]", "st": "texCoord2f[]"})
    for t in times:
        check_extent(prim, t)
    two = Usd.Stage.Open(str(d / "two.usda"))  # the stage must outlive its prims
    one = UsdGeom.BasisCurves(two.GetPrimAtPath("/children"))
    assert np.array_equal(points(curves.GetPointsAttr(), 2), points(one.GetPointsAttr(), 2))
    # Velocities: central differences of the neighbouring samples (1.75 and 2.25), m/s.
    want = (points(curves.GetPointsAttr(), 2.25) - points(curves.GetPointsAttr(), 1.75)) / (0.5 / 24)
    assert np.abs(points(curves.GetVelocitiesAttr(), 2) - want).max() < 1e-3


def test_render_children_usda_and_usdc_hold_the_same_stage(run):
    d, _, _ = run
    for ext in ("usda", "usdc"):
        hairsys("render-children", "export", "--cache", "c.mcap", "--frame", "12",
                "--count", "300", "-o", f"one.{ext}", cwd=d)
        hairsys("render-children", "export", "--cache", "c.mcap", "--frames", "2-4",
                "--count", "300", "-o", f"range.{ext}", cwd=d)
    stages = [Usd.Stage.Open(str(d / f"one.{e}")) for e in ("usda", "usdc")]
    a, b = (UsdGeom.BasisCurves(s.GetPrimAtPath("/children")) for s in stages)
    assert np.array_equal(points(a.GetPointsAttr(), 12), points(b.GetPointsAttr(), 12))
    assert np.array_equal(np.array(a.GetWidthsAttr().Get()), np.array(b.GetWidthsAttr().Get()))
    assert a.GetWidthsInterpolation() == b.GetWidthsInterpolation() == UsdGeom.Tokens.vertex
    for ext in ("usda", "usdc"):
        stage = Usd.Stage.Open(str(d / f"range.{ext}"))
        c = UsdGeom.BasisCurves(stage.GetPrimAtPath("/children"))
        assert c.GetPointsAttr().GetTimeSamples() == [2.0, 3.0, 4.0], ext
        assert (stage.GetStartTimeCode(), stage.GetEndTimeCode()) == (2.0, 4.0)


# The README's stitching stage: each half is a value clip of /hair and /scalp (sub-layers would
# not do: USD takes an attribute's time samples from the strongest layer that has any).
STITCH = """#usda 1.0
(
    subLayers = [@a.usdc@]
    startTimeCode = 1
    endTimeCode = 24
    timeCodesPerSecond = 24
    upAxis = "Z"
    metersPerUnit = 1
)

over "hair" (
    clips = {
        dictionary default = {
            asset[] assetPaths = [@a.usdc@, @b.usdc@]
            string primPath = "/hair"
            double2[] active = [(1, 0), (13, 1)]
            double2[] times = [(1, 1), (24, 24)]
        }
    }
)
{
}

over "scalp" (
    clips = {
        dictionary default = {
            asset[] assetPaths = [@a.usdc@, @b.usdc@]
            string primPath = "/scalp"
            double2[] active = [(1, 0), (13, 1)]
            double2[] times = [(1, 1), (24, 24)]
        }
    }
)
{
}
"""


def test_two_halves_exported_apart_stitch_into_one_shot(run):
    d, _, frames = run
    hairsys("cache", "export", "c.mcap", "-o", "a.usdc", "--frames", "1-12", cwd=d)
    hairsys("cache", "export", "c.mcap", "-o", "b.usdc", "--frames", "13-24", cwd=d)
    hairsys("cache", "export", "c.mcap", "-o", "whole.usdc", cwd=d)
    (d / "stitch.usda").write_text(STITCH)
    stage = Usd.Stage.Open(str(d / "stitch.usda"))
    whole = Usd.Stage.Open(str(d / "whole.usdc"))
    curves = UsdGeom.BasisCurves(stage.GetPrimAtPath("/hair"))
    assert curves.GetPointsAttr().GetTimeSamples() == [float(f) for f in range(1, 25)]
    for f in (1, 5, 12, 13, 20, 24):
        assert np.array_equal(points(curves.GetPointsAttr(), f), frames[f][0]), f
    scalp, whole_scalp = (UsdGeom.Mesh(s.GetPrimAtPath("/scalp")).GetPointsAttr()
                          for s in (stage, whole))
    for f in (5, 20):
        assert np.array_equal(points(scalp, f), points(whole_scalp, f)), f
    # With shutter samples the clips switch halfway between the halves' frames (12.5): every
    # time code of the unsplit export reads the same from the stitched stage.
    # (New file names: USD keeps the layers opened above in its registry.)
    for name, frames_arg in (("sa.usdc", "1-12"), ("sb.usdc", "13-24"), ("sw.usdc", "1-24")):
        hairsys("cache", "export", "c.mcap", "-o", name, "--frames", frames_arg,
                "--shutter", "-0.25,0.25", cwd=d)
    (d / "blur.usda").write_text(STITCH.replace("(13, 1)", "(12.5, 1)")
                                 .replace("@a.usdc@", "@sa.usdc@").replace("@b.usdc@", "@sb.usdc@"))
    blur = Usd.Stage.Open(str(d / "blur.usda"))
    whole = Usd.Stage.Open(str(d / "sw.usdc"))
    stitched, unsplit = (UsdGeom.BasisCurves(s.GetPrimAtPath("/hair")).GetPointsAttr()
                         for s in (blur, whole))
    assert len(unsplit.GetTimeSamples()) == 24 * 3 - 2  # 0.75 and 24.25 lie outside the cache
    for t in unsplit.GetTimeSamples():
        assert np.array_equal(points(stitched, t), points(unsplit, t)), t
    # Sub-layering the two halves keeps only the stronger half's samples: why clips.
    (d / "sub.usda").write_text("#usda 1.0\n(\n    subLayers = [@a.usdc@, @b.usdc@]\n)\n")
    sub_stage = Usd.Stage.Open(str(d / "sub.usda"))
    sub = UsdGeom.BasisCurves(sub_stage.GetPrimAtPath("/hair"))
    assert sub.GetPointsAttr().GetTimeSamples() == [float(f) for f in range(1, 13)]


def test_cache_export_refuses_child_options_without_children(run):
    d, _, _ = run
    import subprocess
    from hairsys_testing import hairsys_binary
    out = subprocess.run([hairsys_binary(), "cache", "export", "c.mcap", "-o", "x.usdc",
                          "--count", "5"], cwd=d, capture_output=True, text=True)
    assert out.returncode == 2 and "--children" in out.stderr, out.stderr
    out = subprocess.run([hairsys_binary(), "cache", "export", "c.mcap", "-o", "x.usdc",
                          "--shutter", "0.5,-0.5"], cwd=d, capture_output=True, text=True)
    assert out.returncode == 2 and "--shutter" in out.stderr, out.stderr
    assert not (d / "x.usdc").exists()


@pytest.mark.parametrize("ext", ["usdc", "usda"])
def test_a_shot_starting_at_frame_1001_round_trips_with_a_time_offset(run, ext):
    """`--time-offset 1000`: cache frame f lands on time code 1000 + f (strands, scalp and
    the stage's range), and render children of one frame on 1000 + f with their shutter."""
    d, _, frames = run
    hairsys("cache", "export", "c.mcap", "-o", f"late.{ext}", "--time-offset", "1000", cwd=d)
    stage = Usd.Stage.Open(str(d / f"late.{ext}"))
    assert (stage.GetStartTimeCode(), stage.GetEndTimeCode()) == (1001.0, 1024.0)
    curves = UsdGeom.BasisCurves(stage.GetPrimAtPath("/hair"))
    times = [1000.0 + f for f in range(FRAMES[0], FRAMES[1] + 1)]
    assert curves.GetPointsAttr().GetTimeSamples() == times
    for f in (1, 12, 24):
        pos, vel = frames[f]
        assert np.array_equal(points(curves.GetPointsAttr(), 1000 + f), pos), f"points at {f}"
        assert np.array_equal(points(curves.GetVelocitiesAttr(), 1000 + f), vel), f
        check_extent(stage.GetPrimAtPath("/hair"), 1000 + f)
    scalp = UsdGeom.Mesh(stage.GetPrimAtPath("/scalp"))
    assert scalp.GetPointsAttr().GetTimeSamples() == times
    # The same frame without the offset: the same scalp, 1000 time codes earlier.
    hairsys("cache", "export", "c.mcap", "-o", f"early.{ext}", cwd=d)
    early = Usd.Stage.Open(str(d / f"early.{ext}"))
    early_scalp = UsdGeom.Mesh(early.GetPrimAtPath("/scalp"))
    assert np.array_equal(points(scalp.GetPointsAttr(), 1012),
                          points(early_scalp.GetPointsAttr(), 12))
    hairsys("render-children", "export", "--cache", "c.mcap", "--frame", "12", "--count", "300",
            "--shutter", "-0.25,0.25", "--time-offset", "1000", "-o", f"kids.{ext}", cwd=d)
    kids = Usd.Stage.Open(str(d / f"kids.{ext}"))
    assert (kids.GetStartTimeCode(), kids.GetEndTimeCode()) == (1011.75, 1012.25)
    pts = UsdGeom.BasisCurves(kids.GetPrimAtPath("/children")).GetPointsAttr()
    assert pts.GetTimeSamples() == [1011.75, 1012.0, 1012.25]
