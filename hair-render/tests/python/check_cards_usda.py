"""Checks a hairsys hair-cards .usda with Pixar's USD (`pip install usd-core`, module `pxr`).

Usage: check_cards_usda.py STAGE.usda EXPECTED.json

EXPECTED.json holds what the Rust test generated: prim path, fps, face vertex counts and indices,
points (flat x y z), st (flat u v) and time samples ({time code: flat points}).
Exit 0 when the stage matches and validates, 1 with the mismatch on stderr, 3 when pxr is missing.
"""

import json
import sys

try:
    from pxr import Usd, UsdGeom
except ImportError as e:  # pragma: no cover - the Rust test turns this into its message
    print(f"cannot import pxr ({e}): pip install usd-core", file=sys.stderr)
    sys.exit(3)


def fail(msg):
    print(msg, file=sys.stderr)
    sys.exit(1)


def close(a, b, what):
    if len(a) != len(b):
        fail(f"{what}: {len(a)} values, expected {len(b)}")
    for i, (x, y) in enumerate(zip(a, b)):
        if abs(x - y) > 1e-6 * max(1.0, abs(y)):
            fail(f"{what}[{i}] = {x}, expected {y}")


def flat(vecs):
    return [c for v in vecs for c in v]


def main():
    stage_path, expected_path = sys.argv[1], sys.argv[2]
    with open(expected_path) as f:
        exp = json.load(f)
    stage = Usd.Stage.Open(stage_path)
    if stage is None:
        fail(f"Usd.Stage.Open could not open {stage_path}")
    if UsdGeom.GetStageUpAxis(stage) != UsdGeom.Tokens.z:
        fail(f"upAxis is {UsdGeom.GetStageUpAxis(stage)}, expected Z")
    if UsdGeom.GetStageMetersPerUnit(stage) != 1.0:
        fail(f"metersPerUnit is {UsdGeom.GetStageMetersPerUnit(stage)}, expected 1")
    if stage.GetTimeCodesPerSecond() != exp["fps"]:
        fail(f"timeCodesPerSecond {stage.GetTimeCodesPerSecond()}, expected {exp['fps']}")
    prim = stage.GetPrimAtPath(exp["prim"])
    if not prim or not prim.IsA(UsdGeom.Mesh):
        fail(f"no Mesh prim at {exp['prim']}")
    if stage.GetDefaultPrim() != prim:
        fail("defaultPrim is not the cards prim")
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
