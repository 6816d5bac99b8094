"""The Blender add-on, headless: hair Curves on a mesh bent by an armature, baked over 24 frames
through the add-on's operator, read back and played back."""

import math
import struct

import numpy as np
import pytest

FRAMES = 24


def cylinder(radius=0.1, height=1.0, segments=16, rings=11):
    """A closed cylinder from z = 0 to `height`: vertices, faces (quads and two caps)."""
    verts, faces = [], []
    for r in range(rings):
        z = height * r / (rings - 1)
        for s in range(segments):
            a = 2 * math.pi * s / segments
            verts.append((radius * math.cos(a), radius * math.sin(a), z))
    for r in range(rings - 1):
        for s in range(segments):
            a, b = r * segments + s, r * segments + (s + 1) % segments
            faces.append((a, b, b + segments, a + segments))
    faces.append(tuple(reversed(range(segments))))
    faces.append(tuple((rings - 1) * segments + s for s in range(segments)))
    return verts, faces


def build_scene(tmp_path):
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, FRAMES
    scene.render.fps = 24

    # The surface: a cylinder skinned to a two-bone armature.
    verts, faces = cylinder()
    mesh = bpy.data.meshes.new("body")
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    body = bpy.data.objects.new("body", mesh)
    scene.collection.objects.link(body)

    arm = bpy.data.armatures.new("rig")
    rig = bpy.data.objects.new("rig", arm)
    scene.collection.objects.link(rig)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode="EDIT")
    lower = arm.edit_bones.new("lower")
    lower.head, lower.tail = (0, 0, 0), (0, 0, 0.5)
    upper = arm.edit_bones.new("upper")
    upper.head, upper.tail = (0, 0, 0.5), (0, 0, 1.0)
    upper.parent, upper.use_connect = lower, True
    bpy.ops.object.mode_set(mode="OBJECT")
    g_lower, g_upper = body.vertex_groups.new(name="lower"), body.vertex_groups.new(name="upper")
    for i, (_, _, z) in enumerate(verts):
        w = min(1.0, max(0.0, (z - 0.4) / 0.2))  # blend around the joint at z = 0.5
        g_upper.add([i], w, "REPLACE")
        g_lower.add([i], 1.0 - w, "REPLACE")
    mod = body.modifiers.new("rig", "ARMATURE")
    mod.object = rig
    bone = rig.pose.bones["upper"]
    bone.rotation_mode = "XYZ"
    bone.rotation_euler = (0, 0, 0)
    bone.keyframe_insert("rotation_euler", frame=1)
    bone.rotation_euler = (math.radians(60), 0, 0)
    bone.keyframe_insert("rotation_euler", frame=FRAMES)

    # Hair: straight curves along the outward normal at the side vertices of the upper part.
    roots = [np.array(v) for v in verts if 0.6 <= v[2] <= 0.9]
    n_points, length = 6, 0.12
    curves = bpy.data.hair_curves.new("hair")
    curves.add_curves([n_points] * len(roots))
    pts = []
    for r in roots:
        normal = np.array([r[0], r[1], 0.0]) / np.hypot(r[0], r[1])
        pts.extend(r + normal * length * j / (n_points - 1) for j in range(n_points))
    pts = np.array(pts, dtype=np.float32)
    curves.attributes["position"].data.foreach_set("vector", pts.ravel())
    curves.surface = body
    hair = bpy.data.objects.new("hair", curves)
    scene.collection.objects.link(hair)
    bpy.context.view_layer.objects.active = hair
    hair.hairsys.cache_path = str(tmp_path / "hair.mcap")
    # The surface deforms; the library's surface collider follows rigid motion only (deforming
    # colliders are pending), so collision with it is off and the hair's stiffness keeps it out.
    hair.hairsys.surface_collision = False
    return scene, body, hair, pts, np.full(len(roots), n_points)


def surface_bvh(body):
    """BVH of the body's evaluated mesh at the current frame (world = local here)."""
    import bpy
    from mathutils.bvhtree import BVHTree

    depsgraph = bpy.context.evaluated_depsgraph_get()
    return BVHTree.FromObject(body, depsgraph)


def read_mcap(path):
    from mcap.reader import make_reader

    frames = {}
    with open(path, "rb") as f:
        for _, channel, message in make_reader(f).iter_messages(topics=["/hairsys/frames"]):
            data = message.data
            _, frame = struct.unpack_from("<II", data, 0)
            (p,) = struct.unpack_from("<I", data, 16)
            frames[frame] = np.frombuffer(data, "<f4", 3 * p, 20).reshape(p, 3)
    return frames


def test_bake_follows_the_bending_surface_and_plays_back(addon, tmp_path):
    import bpy

    scene, body, hair, rest, counts = build_scene(tmp_path)
    result = bpy.ops.hairsys.bake()
    assert result == {"FINISHED"}

    frames = read_mcap(hair.hairsys.cache_path)
    assert sorted(frames) == list(range(1, FRAMES + 1))
    np.testing.assert_allclose(frames[1], rest, atol=1e-5)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])

    for f in (1, 12, FRAMES):
        scene.frame_set(f)
        bvh = surface_bvh(body)
        pos = frames[f]
        # Roots sit on the deformed surface.
        for r in pos[starts]:
            loc, _, _, dist = bvh.find_nearest(r)
            assert dist < 1e-4, f"frame {f}: a root is {dist} m off the surface"
        # No point is inside the mesh (behind the nearest face).
        for p in pos:
            loc, normal, _, dist = bvh.find_nearest(p)
            depth = -np.dot(np.array(p) - np.array(loc), np.array(normal))
            assert depth < 1e-3, f"frame {f}: a point is {depth} m inside the surface"
        # Playback set the curves to the cache's frame.
        shown = np.empty(len(rest) * 3, dtype=np.float32)
        hair.data.attributes["position"].data.foreach_get("vector", shown)
        np.testing.assert_allclose(shown.reshape(-1, 3), pos, atol=1e-6)

    # The roots moved with the bend: the top ring swings by about 0.4 m × sin 60°.
    moved = np.linalg.norm(frames[FRAMES][starts] - frames[1][starts], axis=1)
    assert moved.max() > 0.2, f"the roots moved at most {moved.max()} m"


def test_goal_weights_from_a_curve_attribute_hold_the_hair(addon, tmp_path):
    import bpy

    scene, body, hair, rest, counts = build_scene(tmp_path)
    rig = bpy.data.objects["rig"]
    rig.animation_data_clear()  # a still, straight surface: only gravity moves the hair
    rig.pose.bones["upper"].rotation_euler = (0, 0, 0)
    attr = hair.data.attributes.new("goal", "FLOAT", "CURVE")
    attr.data.foreach_set("value", np.ones(len(counts), dtype=np.float32))
    s = hair.hairsys
    s.weight_source, s.weight_name, s.goal_stiffness = "ATTRIBUTE", "goal", 5.0
    scene.frame_end = 8
    assert bpy.ops.hairsys.bake() == {"FINISHED"}
    held = read_mcap(s.cache_path)[8]
    s.weight_source = "NONE"
    s.cache_path = str(tmp_path / "free.mcap")
    assert bpy.ops.hairsys.bake() == {"FINISHED"}
    free = read_mcap(s.cache_path)[8]
    sag = lambda pos: (rest[:, 2] - pos[:, 2]).max()
    assert sag(held) < 0.5 * sag(free)


def test_errors_reach_the_operator_report(addon, tmp_path):
    import bpy

    scene, body, hair, rest, counts = build_scene(tmp_path)
    hair.hairsys.weight_source = "VERTEX_GROUP"
    hair.hairsys.weight_name = "missing"
    with pytest.raises(RuntimeError, match="no vertex group 'missing'"):
        bpy.ops.hairsys.bake()
