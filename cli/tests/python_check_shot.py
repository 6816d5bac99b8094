"""Checks a `hairsys cache export` file with Pixar's USD (usd-core) against the cache as
`hairsys cache sample` decodes it.

usage: python_check_shot.py SHOT.usd[a|c] FPS FIRST LAST SAMPLE.json...
  (one `hairsys cache sample --time FRAME/FPS` JSON per frame to compare, named *_FRAME.json)

Checks: the stage opens; Z up, meters, timeCodesPerSecond = FPS, start/end time codes =
FIRST/LAST; /hair is a BasisCurves with LAST-FIRST+1 time samples of points, velocities and
extent; widths have vertex interpolation and one value per point; curve counts match the
cache's strand offsets; points at each sampled frame equal the cache's positions (f32 exact);
the extent at that frame bounds them; /scalp is a Mesh.
Exit codes: 0 ok, 1 mismatch (stderr), 3 pxr missing.
"""

import json
import re
import sys

try:
    from pxr import Usd, UsdGeom
except ImportError as e:  # pragma: no cover
    print(f"cannot import pxr ({e}): pip install usd-core", file=sys.stderr)
    sys.exit(3)


def fail(msg):
    print(msg, file=sys.stderr)
    sys.exit(1)


shot, fps, first, last = sys.argv[1], float(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
stage = Usd.Stage.Open(shot)
if stage is None:
    fail(f"usd-core cannot open {shot}")
if UsdGeom.GetStageUpAxis(stage) != UsdGeom.Tokens.z or UsdGeom.GetStageMetersPerUnit(stage) != 1.0:
    fail("stage is not Z up, meters")
if stage.GetTimeCodesPerSecond() != fps:
    fail(f"timeCodesPerSecond {stage.GetTimeCodesPerSecond()} != {fps}")
if (stage.GetStartTimeCode(), stage.GetEndTimeCode()) != (first, last):
    fail(f"time range {stage.GetStartTimeCode()}-{stage.GetEndTimeCode()} != {first}-{last}")
curves = UsdGeom.BasisCurves(stage.GetPrimAtPath("/hair"))
if not curves:
    fail("no BasisCurves /hair")
n = last - first + 1
for attr in (curves.GetPointsAttr(), curves.GetVelocitiesAttr(), curves.GetExtentAttr()):
    if attr.GetNumTimeSamples() != n:
        fail(f"{attr.GetName()}: {attr.GetNumTimeSamples()} time samples, expected {n}")
if curves.GetWidthsInterpolation() != UsdGeom.Tokens.vertex:
    fail(f"widths interpolation {curves.GetWidthsInterpolation()}")
counts = list(curves.GetCurveVertexCountsAttr().Get())
widths = curves.GetWidthsAttr().Get()
if len(widths) != sum(counts) or min(widths) <= 0:
    fail(f"{len(widths)} widths for {sum(counts)} points")
if not UsdGeom.Mesh(stage.GetPrimAtPath("/scalp")):
    fail("no Mesh /scalp")
for path in sys.argv[5:]:
    frame = int(re.search(r"_(\d+)\.json$", path).group(1))
    with open(path) as f:
        cache = json.load(f)
    offsets = cache["strand_offsets"]
    if counts != [b - a for a, b in zip(offsets, offsets[1:])]:
        fail("curveVertexCounts differ from the cache's strand offsets")
    pts = curves.GetPointsAttr().Get(frame)
    want = cache["positions"]
    if len(pts) != len(want):
        fail(f"frame {frame}: {len(pts)} points, cache has {len(want)}")
    for i, (p, q) in enumerate(zip(pts, want)):
        if any(abs(p[k] - q[k]) > 1e-6 for k in range(3)):
            fail(f"frame {frame} point {i}: {tuple(p)} != cache {q}")
    lo, hi = curves.GetExtentAttr().Get(frame)
    for p in pts:
        if any(p[k] < lo[k] or p[k] > hi[k] for k in range(3)):
            fail(f"frame {frame}: point {tuple(p)} outside extent {lo}-{hi}")
print(f"ok: {len(counts)} curves, {n} frames, {len(sys.argv) - 5} frames compared")
