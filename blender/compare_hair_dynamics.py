"""Side by side with Blender 5.2's own Hair Dynamics: the same hair Curves on the same
armature-animated character, simulated once by Blender's Hair Dynamics node modifier (Physics
mode, Surface Collision and Deforming on, every other input at its default) and once baked by
this extension (its defaults); the same figures measured on both.

    target/pyenv313/bin/python blender/compare_hair_dynamics.py [--frames 48] [--curves 300]
        [--still]

Needs Blender 5.2 (bpy 5.2.3, CPython 3.13: the `target/pyenv313` of scripts/test.sh) with the
hairsys wheel installed. The character is a closed cylinder (radius 0.1 m, 1 m) skinned to a
two-bone armature whose upper bone swings 60° and back; hair of 12 points, 0.15 m, grows on the
upper part at random places, out along the surface normal and tilted down. Blender's hair object
is set up as Add › Curves › Empty Hair does (a Deform Curves on Surface modifier first, so the
roots follow the surface; the Curves' `surface`, `surface_uv_map` and per-curve
`surface_uv_coordinate`; the surface's rest positions, `add_rest_position_attribute`), then
the Hair Dynamics modifier, its inputs set through `modifier.properties.inputs.<socket>.value`.

Figures, over every frame: time per frame (Blender: `frame_set` evaluating the simulation;
hairsys: `Baker.step`), stretch of every segment against its groomed length (p99 and max of
|length / rest − 1|), the fraction of points inside the evaluated body (deeper than 0.1 mm),
and tip motion against the head (each tip in the upper bone's space, its largest distance from
where it started).
Prints a Markdown table.
"""

import argparse
import math
import pathlib
import sys
import tempfile
import time

import numpy as np

REPO = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "blender"))

POINTS, LENGTH = 12, 0.15
#: A point counts as inside the body deeper than this, m (roots lie on the faces, ±rounding).
DEEP = 1e-4


def cylinder(radius=0.1, height=1.0, segments=24, rings=21):
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


def character(frames):
    """The body (UV-mapped, skinned) and its rig, the upper bone swinging 60° and back."""
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, frames
    scene.render.fps = 24
    verts, faces = cylinder()
    mesh = bpy.data.meshes.new("body")
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    # UVs without overlaps (Blender finds each root by its UV): the side unrolled over u in
    # [0, 1] (the seam's quad closes at u = 1), the caps as two discs beside it.
    uv = mesh.uv_layers.new(name="UVMap")
    for poly in mesh.polygons:
        co = [mesh.vertices[mesh.loops[i].vertex_index].co for i in poly.loop_indices]
        if len(co) > 4:  # a cap
            for i, (x, y, z) in zip(poly.loop_indices, co):
                uv.data[i].uv = (1.2 + x, (0.2 if z < 0.5 else 0.6) + y)
            continue
        u = [(math.atan2(y, x) / (2 * math.pi)) % 1.0 for x, y, _ in co]
        if max(u) - min(u) > 0.5:
            u = [a + 1.0 if a < 0.5 else a for a in u]
        for i, a, (_, _, z) in zip(poly.loop_indices, u, co):
            uv.data[i].uv = (a, z)
    body = bpy.data.objects.new("body", mesh)
    scene.collection.objects.link(body)
    body.add_rest_position_attribute = True
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
        w = min(1.0, max(0.0, (z - 0.4) / 0.2))
        g_upper.add([i], w, "REPLACE")
        g_lower.add([i], 1.0 - w, "REPLACE")
    body.modifiers.new("rig", "ARMATURE").object = rig
    bone = rig.pose.bones["upper"]
    bone.rotation_mode = "XYZ"
    for frame, angle in ((1, 0), (frames // 2, 60), (frames, 0)):
        bone.rotation_euler = (math.radians(angle), 0, 0)
        bone.keyframe_insert("rotation_euler", frame=frame)
    return scene, body, rig


def groom(body, count, seed=3):
    """`count` curves on the upper part (z 0.65–0.95): out along the normal, tilted down."""
    rng = np.random.default_rng(seed)
    a = rng.uniform(0, 2 * math.pi, count)
    z = rng.uniform(0.65, 0.95, count)
    normal = np.stack([np.cos(a), np.sin(a), np.zeros(count)], 1)
    roots = normal * 0.1 + np.stack([np.zeros(count), np.zeros(count), z], 1)
    direction = normal * math.cos(math.radians(40)) + np.array([0, 0, -math.sin(math.radians(40))])
    steps = np.arange(POINTS) / (POINTS - 1) * LENGTH
    pts = roots[:, None, :] + direction[:, None, :] * steps[None, :, None]
    # Roots exactly on the faceted surface: move each root onto its nearest face.
    from mathutils import Vector
    from mathutils.bvhtree import BVHTree

    bvh = BVHTree.FromObject(body, __import__("bpy").context.evaluated_depsgraph_get())
    for c in range(count):
        loc = bvh.find_nearest(Vector(pts[c, 0]))[0]
        pts[c] += np.array(loc) - pts[c, 0]
    return pts.reshape(-1, 3).astype(np.float32), np.full(count, POINTS)


def hair_object(name, body, pts, counts):
    import bpy

    from hairsys_blender.children import root_uvs

    curves = bpy.data.hair_curves.new(name)
    curves.add_curves([int(c) for c in counts])
    curves.attributes["position"].data.foreach_set("vector", pts.ravel())
    curves.surface = body
    curves.surface_uv_map = "UVMap"
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    uv = root_uvs(body, bpy.context.evaluated_depsgraph_get(), pts[starts])
    attr = curves.attributes.new("surface_uv_coordinate", "FLOAT2", "CURVE")
    attr.data.foreach_set("vector", uv.ravel())
    obj = bpy.data.objects.new(name, curves)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def surface_deform(obj):
    """Adds the modifier Blender's Add › Curves › Empty Hair gives a hair object: Deform Curves
    on Surface, so the roots follow the deforming surface (before Hair Dynamics)."""
    import bpy

    group = bpy.data.node_groups.new("Surface Deform", "GeometryNodeTree")
    group.is_modifier = True
    group.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    nodes = group.nodes
    given, out = nodes.new("NodeGroupInput"), nodes.new("NodeGroupOutput")
    deform = nodes.new("GeometryNodeDeformCurvesOnSurface")
    group.links.new(given.outputs[0], deform.inputs[0])
    group.links.new(deform.outputs[0], out.inputs[0])
    mod = obj.modifiers.new("Surface Deform", "NODES")
    mod.node_group = group
    return mod


def hair_dynamics(obj):
    """Adds Blender's Hair Dynamics modifier in Physics mode with Surface Collision and
    Deforming on."""
    import bpy

    path = (bpy.utils.system_resource("DATAFILES")
            + "/assets/nodes/geometry_nodes_dynamics_assets.blend")
    with bpy.data.libraries.load(path) as (_, dst):
        dst.node_groups = ["Hair Dynamics"]
    group = dst.node_groups[0]
    mod = obj.modifiers.new("Hair Dynamics", "NODES")
    mod.node_group = group
    ids = {item.name: item.identifier for item in group.interface.items_tree
           if item.item_type == "SOCKET" and item.in_out == "INPUT"}
    inputs = mod.properties.inputs
    mode = getattr(inputs, ids["Mode"])
    choices = [e.identifier for e in mode.bl_rna.properties["value"].enum_items]
    mode.value = next(c for c in choices if c.startswith("Physics"))
    getattr(inputs, ids["Surface Collision"]).value = True
    getattr(inputs, ids["Deforming"]).value = True
    return mod


def evaluated_points(obj):
    import bpy

    ev = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    data = ev.data
    flat = np.empty(len(data.points) * 3, dtype=np.float32)
    data.attributes["position"].data.foreach_get("vector", flat)
    m = np.array(ev.matrix_world)
    return flat.reshape(-1, 3) @ m[:3, :3].T + m[:3, 3]


def body_state(body, rig):
    """The evaluated body's BVH (world space) and the upper bone's world matrix now."""
    import bpy
    from mathutils.bvhtree import BVHTree

    depsgraph = bpy.context.evaluated_depsgraph_get()
    bvh = BVHTree.FromObject(body, depsgraph)
    bone = np.array(rig.matrix_world @ rig.pose.bones["upper"].matrix)
    return bvh, bone


def figures(frames, states, rest, counts):
    """Stretch, inside fraction and tip motion of per-frame world positions."""
    from mathutils import Vector

    ends = np.cumsum(counts)
    seg_mask = np.ones(len(rest) - 1, dtype=bool)
    seg_mask[ends[:-1] - 1] = False  # no segment from one curve's tip to the next root
    rest_len = np.linalg.norm(np.diff(rest, axis=0), axis=1)[seg_mask]
    stretch, inside, tip_local = [], [], []
    tips = ends - 1
    for pos, (bvh, bone) in zip(frames, states):
        length = np.linalg.norm(np.diff(pos, axis=0), axis=1)[seg_mask]
        stretch.append(np.abs(length / rest_len - 1.0))
        count = 0
        for p in pos:
            loc, normal, _, _ = bvh.find_nearest(Vector(p))
            if loc is not None and np.dot(np.array(loc) - np.array(p), np.array(normal)) > DEEP:
                count += 1
        inside.append(count / len(pos))
        inv = np.linalg.inv(bone)
        tip_local.append(pos[tips] @ inv[:3, :3].T + inv[:3, 3])
    stretch = np.concatenate(stretch)
    motion = np.linalg.norm(np.array(tip_local) - tip_local[0], axis=2)
    return dict(p99=np.percentile(stretch, 99), max=stretch.max(), inside=max(inside),
                tip=motion.max(), tip_mean=motion.mean())


def run_blender(scene, body, rig, pts, counts):
    obj = hair_object("hair_dynamics", body, pts, counts)
    surface_deform(obj)
    hair_dynamics(obj)
    frames, states, times = [], [], []
    for f in range(scene.frame_start, scene.frame_end + 1):
        t0 = time.perf_counter()
        scene.frame_set(f)
        obj.evaluated_get(__import__("bpy").context.evaluated_depsgraph_get())
        pos = evaluated_points(obj)
        times.append(time.perf_counter() - t0)
        frames.append(pos)
        states.append(body_state(body, rig))
    obj.hide_viewport = obj.hide_render = True
    obj.modifiers.clear()
    return frames, states, times


def run_hairsys(context, scene, body, rig, pts, counts, folder):
    import hairsys

    from hairsys_blender.bake import Baker

    obj = hair_object("hairsys", body, pts, counts)
    obj.hairsys.cache_path = str(pathlib.Path(folder) / "hair.mcap")
    obj.hairsys.playback = False
    context.view_layer.objects.active = obj
    baker = Baker(context, obj)
    times = []
    while True:
        t0 = time.perf_counter()
        more = baker.step(context)
        if not more:
            break
        times.append(time.perf_counter() - t0)
    baker.finish()
    cache = hairsys.Cache(obj.hairsys.cache_path)
    frames, states = [], []
    for f in range(scene.frame_start, scene.frame_end + 1):
        scene.frame_set(f)
        frames.append(np.array(cache.frame(f)[0], dtype=np.float64))
        states.append(body_state(body, rig))
    return frames, states, times


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frames", type=int, default=48)
    parser.add_argument("--curves", type=int, default=300)
    parser.add_argument("--still", action="store_true",
                        help="the body does not move: how each holds a still groom")
    args = parser.parse_args()

    import bpy

    import hairsys_blender

    if bpy.app.version < (5, 2, 0):
        sys.exit(f"Blender {bpy.app.version_string}: Hair Dynamics needs Blender 5.2 "
                 "(bpy 5.2.3, CPython 3.13)")
    hairsys_blender.register()
    scene, body, rig = character(args.frames)
    if args.still:
        rig.animation_data_clear()
        rig.pose.bones["upper"].rotation_euler = (0, 0, 0)
    scene.frame_set(1)
    pts, counts = groom(body, args.curves)
    blender = run_blender(scene, body, rig, pts, counts)
    scene.frame_set(1)
    with tempfile.TemporaryDirectory() as folder:
        ours = run_hairsys(bpy.context, scene, body, rig, pts, counts, folder)
    rows = []
    for name, (frames, states, times) in (("Blender 5.2 Hair Dynamics", blender),
                                          ("hairsys extension", ours)):
        fig = figures(frames, states, pts, counts)
        steady = np.array(times[1:] if len(times) > 1 else times)
        rows.append((name, steady.mean(), fig))
    print(f"{args.curves} curves × {POINTS} points, {args.frames} frames"
          f"{', still body' if args.still else ''}, Blender {bpy.app.version_string}\n")
    print("| | time per frame | stretch p99 | stretch max | points inside (worst frame) "
          "| tip motion against the head, max (mean) |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, t, f in rows:
        print(f"| {name} | {t * 1e3:.1f} ms | {f['p99']:.2%} | {f['max']:.2%} | "
              f"{f['inside']:.2%} | {f['tip'] * 1e3:.1f} mm ({f['tip_mean'] * 1e3:.1f} mm) |")
    ratio = rows[0][1] / rows[1][1]
    print(f"\nBlender's time per frame / hairsys's: {ratio:.2f}")
    hairsys_blender.unregister()


if __name__ == "__main__":
    main()
