"""Checks a hairsys children .usda with Pixar's USD (`pip install usd-core`, module `pxr`).

Usage: check_usda.py STAGE.usda EXPECTED.json

EXPECTED.json holds what the Rust test generated: prim path, curve vertex counts, points (flat
x y z), widths, st (flat u v or null), time samples ({time code: flat points}) or velocities.
Exit 0 when the stage matches, 1 with the mismatch on stderr, 3 when pxr is not installed.
"""

import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from usd_stage import close, fail, flat, open_stage  # noqa: E402

try:
    from pxr import Gf, Usd, UsdGeom
except ImportError:  # pragma: no cover - usd_stage has already exited with 3
    sys.exit(3)


def main():
    stage_path, expected_path = sys.argv[1], sys.argv[2]
    with open(expected_path) as f:
        exp = json.load(f)
    stage, prim = open_stage(stage_path, exp, UsdGeom.BasisCurves, "curves")
    curves = UsdGeom.BasisCurves(prim)
    if curves.GetTypeAttr().Get() != "linear":
        fail(f"type {curves.GetTypeAttr().Get()}, expected linear")
    counts = list(curves.GetCurveVertexCountsAttr().Get())
    if counts != exp["counts"]:
        fail(f"curveVertexCounts {counts[:10]}..., expected {exp['counts'][:10]}...")
    npoints = sum(counts)
    points_attr = curves.GetPointsAttr()
    close(flat(points_attr.Get(Usd.TimeCode.Default())), exp["points"], "points")
    widths = curves.GetWidthsAttr().Get()
    close(list(widths), exp["widths"], "widths")
    if curves.GetWidthsInterpolation() != UsdGeom.Tokens.vertex:
        fail(f"widths interpolation {curves.GetWidthsInterpolation()}, expected vertex")
    if len(widths) != npoints:
        fail(f"{len(widths)} widths for {npoints} points")
    api = UsdGeom.PrimvarsAPI(prim)
    st = api.GetPrimvar("st")
    if exp["st"] is None:
        if st.HasValue():
            fail("primvars:st present but the scalp has no UVs")
    else:
        if st.GetInterpolation() != UsdGeom.Tokens.uniform:
            fail(f"st interpolation {st.GetInterpolation()}, expected uniform")
        if str(st.GetTypeName()) != "texCoord2f[]":
            fail(f"st type {st.GetTypeName()}, expected texCoord2f[]")
        close(flat(st.Get()), exp["st"], "primvars:st")
    for name in ("random", "parent"):
        pv = api.GetPrimvar(name)
        if pv.GetInterpolation() != UsdGeom.Tokens.uniform or len(pv.Get()) != len(counts):
            fail(f"primvars:{name} must have one uniform value per curve")
    # Every point of every sample inside the authored extent; the extent USD computes agrees.
    extent = curves.GetExtentAttr().Get()
    lo, hi = Gf.Vec3f(extent[0]), Gf.Vec3f(extent[1])
    samples = exp.get("time_samples") or {}
    times = sorted(float(t) for t in samples)
    if [float(t) for t in points_attr.GetTimeSamples()] != times:
        fail(f"points time samples {points_attr.GetTimeSamples()}, expected {times}")
    for t in times:
        got = flat(points_attr.Get(Usd.TimeCode(t)))
        close(got, samples[repr(t) if repr(t) in samples else str(t)], f"points at time {t}")
    for t in [Usd.TimeCode.Default()] + [Usd.TimeCode(t) for t in times]:
        for p in points_attr.Get(t):
            if any(p[k] < lo[k] or p[k] > hi[k] for k in range(3)):
                fail(f"point {p} outside the extent {extent} at {t}")
        computed = UsdGeom.Boundable.ComputeExtentFromPlugins(curves, t)
        if not times:  # with motion samples the authored extent spans them all
            close(flat(computed), flat(extent), "extent (USD's own ComputeExtent of the frame)")
        for k in range(3):
            if computed[0][k] < lo[k] - 1e-6 or computed[1][k] > hi[k] + 1e-6:
                fail(f"USD's computed extent {computed} exceeds the authored {extent} at {t}")
    if times:
        if stage.GetStartTimeCode() != times[0] or stage.GetEndTimeCode() != times[-1]:
            fail("startTimeCode/endTimeCode do not span the motion samples")
    if exp.get("velocities") is not None:
        close(flat(curves.GetVelocitiesAttr().Get()), exp["velocities"], "velocities")
    print(f"ok: {len(counts)} curves, {npoints} points, time samples {times}")


main()
