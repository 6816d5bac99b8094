"""Writes a groom as Pixar's USD writes it, for hairsys's USD reader tests, and the positions
Pixar's USD says its points have in the world.

usage: usd_groom_fixture.py OUT.usd[a|c] EXPECTED.txt

The stage is Y up and in centimetres (metersPerUnit 0.01); the curves sit under a transformed
Xform parent (translate, rotateXYZ, uniform scale) with their own translate, and carry `widths`
(vertex), `primvars:st` (uniform) and a time-sampled parent translate (frames 1 and 11).
Besides the curves it holds a Mesh and a second BasisCurves prim elsewhere, so prim selection
matters. EXPECTED.txt holds (one `name value value …` line each) for the prim /Character/Body/hair at times 1 and 6, the points
taken through `ComputeLocalToWorldTransform` (stage units, Y up), the widths scaled by that
transform's uniform scale, and the st values.

Exit codes: 0 written, 3 pxr is missing.
"""

import sys

try:
    from pxr import Gf, Sdf, Usd, UsdGeom, Vt
except ImportError as e:  # pragma: no cover
    print(f"cannot import pxr ({e}): pip install usd-core", file=sys.stderr)
    sys.exit(3)

out, expected_path = sys.argv[1], sys.argv[2]
stage = Usd.Stage.CreateNew(out)
UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
UsdGeom.SetStageMetersPerUnit(stage, 0.01)
stage.SetStartTimeCode(1)
stage.SetEndTimeCode(11)
stage.SetTimeCodesPerSecond(24)

root = UsdGeom.Xform.Define(stage, "/Character")
stage.SetDefaultPrim(root.GetPrim())
body = UsdGeom.Xform.Define(stage, "/Character/Body")
t = body.AddTranslateOp()
t.Set(Gf.Vec3d(10.0, 150.0, -5.0), 1)
t.Set(Gf.Vec3d(20.0, 150.0, -5.0), 11)
body.AddRotateXYZOp().Set(Gf.Vec3f(30.0, 45.0, 10.0))
body.AddScaleOp().Set(Gf.Vec3f(2.0, 2.0, 2.0))

hair = UsdGeom.BasisCurves.Define(stage, "/Character/Body/hair")
hair.AddTranslateOp().Set(Gf.Vec3d(0.0, 5.0, 0.0))
hair.CreateTypeAttr(UsdGeom.Tokens.linear)
counts = [3, 4]
points = [(0, 0, 0), (0, 1, 0.5), (0, 2, 1.5), (1, 0, 0), (1.2, 1, 0), (1.5, 2, 0.2), (2, 3, 0.1)]
hair.CreateCurveVertexCountsAttr(Vt.IntArray(counts))
hair.CreatePointsAttr(Vt.Vec3fArray([Gf.Vec3f(*p) for p in points]))
widths = [0.1, 0.08, 0.05, 0.12, 0.1, 0.07, 0.02]
hair.CreateWidthsAttr(Vt.FloatArray(widths))
hair.SetWidthsInterpolation(UsdGeom.Tokens.vertex)
st = UsdGeom.PrimvarsAPI(hair).CreatePrimvar(
    "st", Sdf.ValueTypeNames.TexCoord2fArray, UsdGeom.Tokens.uniform)
st.Set(Vt.Vec2fArray([Gf.Vec2f(0.25, 0.5), Gf.Vec2f(0.75, 0.125)]))

other = UsdGeom.BasisCurves.Define(stage, "/Character/Props/rope")
other.CreateCurveVertexCountsAttr(Vt.IntArray([2]))
other.CreatePointsAttr(Vt.Vec3fArray([Gf.Vec3f(0, 0, 0), Gf.Vec3f(0, 100, 0)]))
mesh = UsdGeom.Mesh.Define(stage, "/Character/Body/skin")
mesh.CreatePointsAttr(Vt.Vec3fArray([Gf.Vec3f(0, 0, 0), Gf.Vec3f(1, 0, 0), Gf.Vec3f(0, 1, 0)]))
mesh.CreateFaceVertexCountsAttr(Vt.IntArray([3]))
mesh.CreateFaceVertexIndicesAttr(Vt.IntArray([0, 1, 2]))
stage.GetRootLayer().Save()

lines = ["counts " + " ".join(map(str, counts)), "st 0.25 0.5 0.75 0.125"]
for time in (1, 6):
    m = hair.ComputeLocalToWorldTransform(Usd.TimeCode(time))
    world = [m.Transform(Gf.Vec3d(*p)) for p in points]
    scale = abs(m.ExtractRotationMatrix().GetDeterminant()) ** (1.0 / 3.0)
    lines.append(f"points@{time} " + " ".join(repr(c) for p in world for c in p))
    lines.append(f"widths@{time} " + " ".join(repr(w * scale) for w in widths))
with open(expected_path, "w") as f:
    f.write("\n".join(lines) + "\n")
