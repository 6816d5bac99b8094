"""Builds hairsys's character test asset with headless Blender (the `bpy` 5.0.1 package).

A head-and-shoulders mesh (one closed surface of revolution, elliptical below the neck)
skinned to an armature that turns the head and shrugs the shoulders over 24 frames, plus a
small groom of hair curves on the head, exported as one `.usdc`:

- `/root/rig/body/body`: the Mesh, `points` time-sampled at frames 6-24 (frames 1-5 are still and
  hold frame 6's value; the armature is applied, not exported as UsdSkel), Z up, meters;
- `/root/groom/groom`: the groom as curves, at rest (frame 1).

Run (any Python with `pip install bpy==5.0.1 usd-core`):

    python scripts/make_character.py data/character/character.usdc

The asset is CC0 (made by the hairsys project with this script). The script checks what it
wrote with Pixar's usd-core: 24 time samples of the points, the head turned and the shoulders
raised where the animation says.
"""

import math
import sys

import bpy
import mathutils

FRAMES = (1, 24)
SEGMENTS = 32  # vertices around each ring
HEAD_CENTRE_Z = 1.685  # m
HEAD_RADIUS = (0.085, 0.1, 0.1)  # m along x (ear to ear), y (front-back), z
GUIDES = 64
GUIDE_POINTS = 12
GUIDE_LENGTH = 0.14  # m


def smoothstep(a, b, x):
    t = min(1.0, max(0.0, (x - a) / (b - a)))
    return t * t * (3.0 - 2.0 * t)


def rings():
    """(z, radius along x, radius along y) from the crown down to the chest."""
    out = []
    # The head: an ellipsoid from near the crown to under the chin.
    for i in range(1, 14):
        theta = math.radians(180.0 * i / 16.0)
        out.append(
            (
                HEAD_CENTRE_Z + HEAD_RADIUS[2] * math.cos(theta),
                HEAD_RADIUS[0] * math.sin(theta),
                HEAD_RADIUS[1] * math.sin(theta),
            )
        )
    # Neck, shoulders, chest (x wide, y narrow).
    out += [
        (1.56, 0.052, 0.055),
        (1.52, 0.055, 0.058),
        (1.49, 0.085, 0.075),
        (1.465, 0.17, 0.095),
        (1.44, 0.205, 0.105),
        (1.40, 0.215, 0.11),
        (1.33, 0.205, 0.11),
        (1.26, 0.18, 0.10),
    ]
    return out


def build_mesh():
    verts = [(0.0, 0.0, HEAD_CENTRE_Z + HEAD_RADIUS[2])]
    ring_list = rings()
    for z, rx, ry in ring_list:
        for k in range(SEGMENTS):
            a = 2.0 * math.pi * k / SEGMENTS
            verts.append((rx * math.cos(a), ry * math.sin(a), z))
    verts.append((0.0, 0.0, ring_list[-1][0]))
    bottom = len(verts) - 1
    faces = []
    ring = lambda r, k: 1 + r * SEGMENTS + (k % SEGMENTS)  # noqa: E731
    for k in range(SEGMENTS):
        faces.append((0, ring(0, k), ring(0, k + 1)))
    for r in range(len(ring_list) - 1):
        for k in range(SEGMENTS):
            # Counter-clockwise seen from outside: normals point out.
            faces.append((ring(r, k), ring(r + 1, k), ring(r + 1, k + 1), ring(r, k + 1)))
    last = len(ring_list) - 1
    for k in range(SEGMENTS):
        faces.append((bottom, ring(last, k + 1), ring(last, k)))
    mesh = bpy.data.meshes.new("body")
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    mesh.validate()
    obj = bpy.data.objects.new("body", mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def build_armature(body):
    arm_data = bpy.data.armatures.new("rig")
    rig = bpy.data.objects.new("rig", arm_data)
    bpy.context.scene.collection.objects.link(rig)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode="EDIT")
    bones = arm_data.edit_bones
    spine = bones.new("spine")
    spine.head, spine.tail = (0, 0, 1.26), (0, 0, 1.50)
    head = bones.new("head")
    head.head, head.tail = (0, 0, 1.52), (0, 0, 1.78)
    head.parent = spine
    for side, sign in (("L", 1.0), ("R", -1.0)):
        b = bones.new("shoulder." + side)
        b.head, b.tail = (0.04 * sign, 0, 1.47), (0.2 * sign, 0, 1.45)
        b.parent = spine
    bpy.ops.object.mode_set(mode="OBJECT")

    groups = {name: body.vertex_groups.new(name=name) for name in ("spine", "head", "shoulder.L", "shoulder.R")}
    for v in body.data.vertices:
        x, _, z = v.co
        w_head = smoothstep(1.53, 1.6, z)
        w_shoulder = smoothstep(0.06, 0.15, abs(x)) * (1.0 - smoothstep(1.44, 1.52, z)) * (1.0 - w_head)
        side = "shoulder.L" if x > 0 else "shoulder.R"
        for name, w in (("head", w_head), (side, w_shoulder), ("spine", 1.0 - w_head - w_shoulder)):
            if w > 0.0:
                groups[name].add([v.index], w, "REPLACE")
    mod = body.modifiers.new("rig", "ARMATURE")
    mod.object = rig
    body.parent = rig
    return rig


def animate(rig):
    head = rig.pose.bones["head"]
    head.rotation_mode = "XYZ"
    # Head turn about the (vertical) bone's own axis: still, 50° left, 20° right, back.
    for frame, deg in ((1, 0), (6, 0), (12, 50), (18, -20), (24, 0)):
        head.rotation_euler = (0.0, math.radians(deg), 0.0)
        head.keyframe_insert("rotation_euler", frame=frame)
    # Shrug: both shoulders rise about 4 cm and drop again (a positive turn about the bone's own
    # x axis lifts its tip: roll 0 leaves z up for a bone lying along ±x).
    for side in ("L", "R"):
        b = rig.pose.bones["shoulder." + side]
        b.rotation_mode = "XYZ"
        for frame, deg in ((1, 0), (8, 0), (12, 15), (16, 0), (24, 0)):
            b.rotation_euler = (math.radians(deg), 0.0, 0.0)
            b.keyframe_insert("rotation_euler", frame=frame)


def build_groom(body):
    """Hair curves on the top and back of the head, grown out along the normal and combed
    back and down; a deterministic spiral of roots (no randomness)."""
    curves = bpy.data.hair_curves.new("groom")
    curves.add_curves([GUIDE_POINTS] * GUIDES)
    golden = math.pi * (3.0 - math.sqrt(5.0))
    rx, ry, rz = HEAD_RADIUS
    comb = mathutils.Vector((0.0, 0.45, -1.0)).normalized()
    positions = []
    for i in range(GUIDES):
        # Roots on the cap above 25° of elevation, avoiding the face (−y).
        h = 0.3 + 0.7 * (i + 0.5) / GUIDES
        r = math.sqrt(1.0 - h * h)
        a = golden * i
        u = mathutils.Vector((r * math.cos(a), r * math.sin(a), h))
        if u.y < -0.45:
            u.y = -u.y * 0.5
            u.normalize()
        root = mathutils.Vector((rx * u.x, ry * u.y, HEAD_CENTRE_Z + rz * u.z))
        normal = mathutils.Vector((u.x / rx, u.y / ry, u.z / rz)).normalized()
        step = GUIDE_LENGTH / (GUIDE_POINTS - 1)
        p = root.copy()
        d = normal.copy()
        for k in range(GUIDE_POINTS):
            positions.append(p.copy())
            # Turn from the normal towards the comb, staying outside the head.
            d = (d + 0.35 * comb).normalized()
            radial = (p - mathutils.Vector((0, 0, HEAD_CENTRE_Z))).normalized()
            if d.dot(radial) < 0.15:
                d = (d + (0.15 - d.dot(radial)) * radial).normalized()
            p = p + step * d
    for i, p in enumerate(positions):
        curves.points[i].position = p
    obj = bpy.data.objects.new("groom", curves)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def main(out):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = FRAMES
    scene.render.fps = 24
    body = build_mesh()
    rig = build_armature(body)
    animate(rig)
    build_groom(body)
    scene.frame_set(FRAMES[0])
    bpy.ops.wm.usd_export(
        filepath=out,
        export_animation=True,
        export_armatures=False,  # bake the skinning into time-sampled points
        export_shapekeys=False,
        export_hair=True,
        export_uvmaps=False,
        export_normals=False,
        export_materials=False,
        export_mesh_colors=False,
        export_custom_properties=False,
        author_blender_name=False,
        export_lights=False,
        export_cameras=False,
    )
    check(out)


def check(out):
    from pxr import Usd, UsdGeom

    stage = Usd.Stage.Open(out)
    meshes = [p for p in stage.Traverse() if p.IsA(UsdGeom.Mesh)]
    curves = [p for p in stage.Traverse() if p.IsA(UsdGeom.BasisCurves) or p.GetTypeName() == "Curves"]
    assert len(meshes) == 1, [str(p.GetPath()) for p in stage.Traverse()]
    mesh = UsdGeom.Mesh(meshes[0])
    times = mesh.GetPointsAttr().GetTimeSamples()
    # Blender writes no sample for the still frames before the first change (frames 1-5 hold
    # the value of frame 6, which equals them), then one per frame.
    assert times[-1] == FRAMES[1] and len(times) >= FRAMES[1] - 6 + 1, times
    assert stage.GetStartTimeCode() == FRAMES[0] and stage.GetEndTimeCode() == FRAMES[1]
    p1 = mesh.GetPointsAttr().Get(1)
    p12 = mesh.GetPointsAttr().Get(12)
    crown = max(range(len(p1)), key=lambda i: p1[i][2])
    front = min(range(len(p1)), key=lambda i: p1[i][1] if p1[i][2] > 1.66 else 1.0)
    turn = math.degrees(math.atan2(p12[front][1], p12[front][0]) - math.atan2(p1[front][1], p1[front][0]))
    tip = max(range(len(p1)), key=lambda i: p1[i][0] if p1[i][2] < 1.47 else -1.0)
    rise = p12[tip][2] - p1[tip][2]
    print(
        f"{out}: mesh {meshes[0].GetPath()} {len(p1)} points, {len(times)} samples; curves "
        f"{[str(c.GetPath()) for c in curves]}; head turned {turn:.1f}° at frame 12, shoulder "
        f"tip raised {rise * 100:.1f} cm"
    )
    assert abs(p12[crown][2] - p1[crown][2]) < 1e-4
    assert 40.0 < abs(turn) < 60.0, turn
    assert 0.02 < rise < 0.08, rise
    assert curves, "no curves exported"


if __name__ == "__main__":
    main(sys.argv[-1] if len(sys.argv) > 1 and sys.argv[-1].endswith((".usdc", ".usd", ".usda")) else "character.usdc")
