"""Writes a hair groom with headless Blender (bpy 5.0.1) as Blender's own USD exporter writes it,
for hairsys's USD reader tests, and where Blender says its points are in the world.

usage: python blender_groom_fixture.py OUT.usdc EXPECTED.txt

A Curves (hair) object of two curves has a non-identity object transform (location, rotation,
scale 2). It is exported Y up in centimetres (`convert_orientation`, `convert_scene_units`:
metersPerUnit 0.01), so Blender writes Catmull-Rom "pinned" curves under Xforms that carry the
unit and axis conversion. EXPECTED.txt: one line of the points' world positions in meters, Z up
(Blender's `matrix_world @ p`: its exporter takes one Blender unit as one meter, whatever the
scene's unit scale, checked with bpy 5.0.1).

Exit codes: 0 written, 3 bpy is missing.
"""

import sys

try:
    import bpy
    from mathutils import Euler, Vector
except ImportError as e:  # pragma: no cover
    print(f"cannot import bpy ({e}): pip install bpy==5.0.1", file=sys.stderr)
    sys.exit(3)

out, expected_path = sys.argv[1], sys.argv[2]
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
curves = bpy.data.hair_curves.new("groom")
curves.add_curves([4, 3])
points = [(0, 0, 0), (0, 0.1, 1), (0, 0.2, 2), (0.1, 0.3, 3), (1, 0, 0), (1.2, 0, 1), (1.3, 0.1, 2)]
for i, p in enumerate(points):
    curves.attributes["position"].data[i].vector = p
ob = bpy.data.objects.new("hair", curves)
scene.collection.objects.link(ob)
ob.location = (0.3, -0.2, 1.5)
ob.rotation_euler = Euler((0.3, 0.2, 0.9))
ob.scale = (2, 2, 2)
bpy.context.view_layer.update()
bpy.ops.wm.usd_export(
    filepath=out,
    export_hair=True,
    convert_orientation=True,
    export_global_forward_selection="NEGATIVE_Z",
    export_global_up_selection="Y",
    convert_scene_units="CENTIMETERS",
)
world = [ob.matrix_world @ Vector(p) for p in points]
with open(expected_path, "w") as f:
    f.write(" ".join(repr(c) for p in world for c in p) + "\n")
