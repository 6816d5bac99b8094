"""What both .usda checkers share: failing with a message, f32 comparisons, and opening a stage
whose metadata hairsys always writes (Z up, meters, the frame rate, the default prim).

Exit codes of the checkers: 0 the stage matches, 1 a mismatch (on stderr), 3 pxr is missing.
"""

import sys

try:
    from pxr import Usd, UsdGeom
except ImportError as e:  # pragma: no cover - the Rust tests turn this into their message
    print(f"cannot import pxr ({e}): pip install usd-core", file=sys.stderr)
    sys.exit(3)


def fail(msg):
    print(msg, file=sys.stderr)
    sys.exit(1)


def close(a, b, what):
    """Element-wise comparison of two flat float lists at f32 precision."""
    if len(a) != len(b):
        fail(f"{what}: {len(a)} values, expected {len(b)}")
    for i, (x, y) in enumerate(zip(a, b)):
        if abs(x - y) > 1e-6 * max(1.0, abs(y)):
            fail(f"{what}[{i}] = {x}, expected {y}")


def flat(vecs):
    return [c for v in vecs for c in v]


def open_stage(stage_path, exp, schema, what):
    """Opens `stage_path`, checks upAxis Z, metersPerUnit 1, timeCodesPerSecond = exp["fps"] and
    that exp["prim"] is the default prim and a `schema` (e.g. UsdGeom.Mesh); returns
    (stage, prim)."""
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
    if not prim or not prim.IsA(schema):
        fail(f"no {schema.__name__} prim at {exp['prim']}")
    if stage.GetDefaultPrim() != prim:
        fail(f"defaultPrim is not the {what} prim")
    return stage, prim
