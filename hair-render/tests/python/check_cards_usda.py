"""Checks a hairsys hair-cards .usda with Pixar's USD (`pip install usd-core`, module `pxr`).

Usage: check_cards_usda.py STAGE.usda EXPECTED.json

EXPECTED.json holds what the Rust test generated: prim path, fps, face vertex counts and indices,
points (flat x y z), st (flat u v) and time samples ({time code: flat points}).
Exit 0 when the stage matches and validates, 1 with the mismatch on stderr, 3 when pxr is missing.
"""

import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from usd_stage import close, fail, flat, open_stage  # noqa: E402

try:
    from pxr import Usd, UsdGeom
except ImportError:  # pragma: no cover - usd_stage has already exited with 3
    sys.exit(3)


def main():
    stage_path, expected_path = sys.argv[1], sys.argv[2]
    with open(expected_path) as f:
        exp = json.load(f)
    stage, prim = open_stage(stage_path, exp, UsdGeom.Mesh, "cards")
    mesh = UsdGeom.Mesh(prim)
    counts = list(mesh.GetFaceVertexCountsAttr().Get())
    indices = list(mesh.GetFaceVertexIndicesAttr().Get())
    if counts != exp["counts"]:
        fail(f"faceVertexCounts {counts[:8]}..., expected {exp['counts'][:8]}...")
    if indices != exp["indices"]:
        fail("faceVertexIndices differ from the expected ones")
    points = mesh.GetPointsAttr()
    n_points = len(points.Get())
    ok, why = UsdGeom.Mesh.ValidateTopology(indices, counts, n_points)
    if not ok:
        fail(f"invalid mesh topology: {why}")
    close(flat(points.Get()), exp["points"], "points")
    if mesh.GetSubdivisionSchemeAttr().Get() != "none":
        fail("subdivisionScheme is not none")
    st = UsdGeom.PrimvarsAPI(prim).GetPrimvar("st")
    if not st or st.GetTypeName() != "texCoord2f[]":
        fail("no texCoord2f[] primvars:st")
    if st.GetInterpolation() != UsdGeom.Tokens.vertex:
        fail(f"st interpolation {st.GetInterpolation()}, expected vertex")
    close(flat(st.Get()), exp["st"], "st")
    for code, expected in exp["time_samples"].items():
        close(flat(points.Get(float(code))), expected, f"points at {code}")
    samples = points.GetTimeSamples()
    if len(samples) != len(exp["time_samples"]):
        fail(f"{len(samples)} time samples, expected {len(exp['time_samples'])}")
    extent = mesh.GetExtentAttr().Get()
    for code in list(samples) + [Usd.TimeCode.Default()]:
        pts = points.Get(code)
        for p in pts:
            for k in range(3):
                if not (extent[0][k] - 1e-6 <= p[k] <= extent[1][k] + 1e-6):
                    fail(f"point {p} outside the extent {extent}")
    print(f"pxr: {len(counts)} quads, {n_points} points, {len(samples)} time samples: ok")


main()
