"""Side by side with Blender 5.2's own Hair Dynamics: the same hair Curves on the same
armature-animated character, simulated by Blender's Hair Dynamics node modifier (Physics mode,
Surface Collision and Deforming on) and baked by this extension; the same figures measured on
both, for any settings of either.

    target/pyenv313/bin/python blender/compare_hair_dynamics.py [--frames 48] [--curves 1500]
        [--length 0.1] [--still] [--hd SOCKET=VALUE ...] [--hd-sweep SOCKET=V1,V2,...]
        [--ours SETTING=VALUE ...] [--ours-sweep SETTING=V1,V2,...] [--rounds 1]

`--hd` sets an input of the Hair Dynamics node group by its socket name as the modifier panel
shows it (`--hd Substeps=100 --hd Bendiness=1`; the names are read from the node group, and an
unknown name lists them); `--ours` sets a setting of this extension by its Python name
(`--ours bend_stiffness=100`, the `hair.hairsys` property group: see docs/blender.md). A
`--hd-sweep` or `--ours-sweep` runs that contender once per value (`--hd-sweep
Substeps=10,20,50,100`). The contenders run alternately (Hair Dynamics, this extension, Hair
Dynamics, …), `--rounds` times over; each one's time per frame is the median of its rounds.
Then the script names the cheapest Hair Dynamics setting whose p99 stretch is at most 1 %, the
cheapest setting of this extension whose max stretch is at most 1 % with no point inside, and
the ratio of their times per frame.

Needs Blender 5.2 (bpy 5.2.3, CPython 3.13: the `target/pyenv313` of scripts/test.sh) with the
hairsys wheel installed. The character is a closed cylinder (radius 0.1 m, 1 m) skinned to a
two-bone armature whose upper bone swings 60° and back; hair of 12 points, `--length` long
(default 0.1 m), grows on the upper part at random places, out along the surface normal and
tilted down. Blender's hair object is made by Add › Curves › Empty Hair
(`bpy.ops.object.curves_empty_hair_add` on the body: the Curves parented to it with its
`surface` and `surface_uv_map`, the surface's `add_rest_position_attribute`, and the Hair
Dynamics modifier, which moves the roots with the deforming surface itself), then given the
groom's points and per-curve `surface_uv_coordinate`; the modifier's inputs are set through
`modifier.properties.inputs.<socket identifier>.value`.

Figures, over every frame: time per frame after the first (Blender: `frame_set` evaluating the
simulation and reading the evaluated points; hairsys: `Baker.step`, which sets the frame, reads
the evaluated surface and steps the session), stretch of every segment against its groomed
length (p99 and max of |length / rest − 1|: a shortened segment counts as a lengthened one), the
points inside the evaluated body (deeper than 0.1 mm; worst frame, and how deep), and tip motion
against the head (each tip in the upper bone's space, its largest distance from where it
started). For this extension also the integrator and substeps per frame it took and the
library's share of the frame by phase.
Prints Markdown tables.
"""

import argparse
import math
import pathlib
import statistics
import sys
import tempfile
import time

import numpy as np

REPO = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "blender"))

POINTS = 12
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


def groom(body, count, length, seed=3):
    """`count` curves of `length` (m) on the upper part (z 0.65–0.95): out along the normal,
    tilted down."""
    rng = np.random.default_rng(seed)
    a = rng.uniform(0, 2 * math.pi, count)
    z = rng.uniform(0.65, 0.95, count)
    normal = np.stack([np.cos(a), np.sin(a), np.zeros(count)], 1)
    roots = normal * 0.1 + np.stack([np.zeros(count), np.zeros(count), z], 1)
    direction = normal * math.cos(math.radians(40)) + np.array([0, 0, -math.sin(math.radians(40))])
    steps = np.arange(POINTS) / (POINTS - 1) * length
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


def empty_hair(name, body, pts, counts):
    """A hair object made as Blender 5.2's Add › Curves › Empty Hair makes it on `body` (the
    Curves parented to it, its `surface` and `surface_uv_map` set, the Hair Dynamics modifier in
    its Animation mode), then given the groom: `pts` (world space; the object's matrix is the
    identity) with per-curve `surface_uv_coordinate`."""
    import bpy

    from hairsys_blender.children import root_uvs

    with bpy.context.temp_override(active_object=body, object=body, selected_objects=[body]):
        bpy.ops.object.curves_empty_hair_add()
    obj = bpy.context.active_object
    obj.name = name
    curves = obj.data
    curves.add_curves([int(c) for c in counts])
    curves.attributes["position"].data.foreach_set("vector", pts.ravel())
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    uv = root_uvs(body, bpy.context.evaluated_depsgraph_get(), pts[starts])
    attr = curves.attributes.new("surface_uv_coordinate", "FLOAT2", "CURVE")
    attr.data.foreach_set("vector", uv.ravel())
    return obj


def hair_dynamics_group():
    """Blender's Hair Dynamics node group, appended from its bundled asset file."""
    import bpy

    group = bpy.data.node_groups.get("Hair Dynamics")
    if group is not None:
        return group
    path = (bpy.utils.system_resource("DATAFILES")
            + "/assets/nodes/geometry_nodes_dynamics_assets.blend")
    with bpy.data.libraries.load(path) as (_, dst):
        dst.node_groups = ["Hair Dynamics"]
    return dst.node_groups[0]


def hair_dynamics_inputs(group):
    """The node group's inputs as {name: (identifier, socket type)}; of two inputs with one name
    (the Gravity toggle and the Gravity vector) the first is kept as `name`, the second as
    `name (2)`."""
    inputs = {}
    for item in group.interface.items_tree:
        if item.item_type != "SOCKET" or item.in_out != "INPUT":
            continue
        name = item.name if item.name not in inputs else f"{item.name} (2)"
        inputs[name] = (item.identifier, item.socket_type)
    return inputs


def hair_dynamics(obj, settings):
    """Sets the Hair Dynamics modifier Empty Hair gave `obj` to Physics mode with Surface
    Collision and Deforming on, then `settings` ({socket name: value}) on top."""
    mod = next(m for m in obj.modifiers
               if m.type == "NODES" and m.node_group and m.node_group.name == "Hair Dynamics")
    ids = hair_dynamics_inputs(mod.node_group)
    inputs = mod.properties.inputs
    mode = getattr(inputs, ids["Mode"][0])
    choices = [e.identifier for e in mode.bl_rna.properties["value"].enum_items]
    mode.value = next(c for c in choices if c.startswith("Physics"))
    getattr(inputs, ids["Surface Collision"][0]).value = True
    getattr(inputs, ids["Deforming"][0]).value = True
    for name, value in settings.items():
        getattr(inputs, ids[name][0]).value = value
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
    """Stretch, points inside and tip motion of per-frame world positions."""
    from mathutils import Vector

    ends = np.cumsum(counts)
    seg_mask = np.ones(len(rest) - 1, dtype=bool)
    seg_mask[ends[:-1] - 1] = False  # no segment from one curve's tip to the next root
    rest_len = np.linalg.norm(np.diff(rest, axis=0), axis=1)[seg_mask]
    stretch, inside, depth, tip_local = [], [], 0.0, []
    tips = ends - 1
    for pos, (bvh, bone) in zip(frames, states):
        length = np.linalg.norm(np.diff(pos, axis=0), axis=1)[seg_mask]
        stretch.append(np.abs(length / rest_len - 1.0))
        count = 0
        for p in pos:
            loc, normal, _, _ = bvh.find_nearest(Vector(p))
            if loc is None:
                continue
            d = float(np.dot(np.array(loc) - np.array(p), np.array(normal)))
            if d > DEEP:
                count += 1
                depth = max(depth, d)
        inside.append(count)
        inv = np.linalg.inv(bone)
        tip_local.append(pos[tips] @ inv[:3, :3].T + inv[:3, 3])
    stretch = np.concatenate(stretch)
    motion = np.linalg.norm(np.array(tip_local) - tip_local[0], axis=2)
    return dict(p99=np.percentile(stretch, 99), max=stretch.max(), inside=max(inside),
                depth=depth, tip=motion.max(), tip_mean=motion.mean())


def run_blender(scene, body, rig, pts, counts, settings):
    """Hair Dynamics with `settings` over the frame range: (figures, seconds per frame, notes)."""
    import bpy

    obj = empty_hair("hair_dynamics", body, pts, counts)
    hair_dynamics(obj, settings)
    frames, states, times = [], [], []
    scene.frame_set(scene.frame_start)
    for f in range(scene.frame_start, scene.frame_end + 1):
        t0 = time.perf_counter()
        scene.frame_set(f)
        pos = evaluated_points(obj)
        times.append(time.perf_counter() - t0)
        frames.append(pos)
        states.append(body_state(body, rig))
    bpy.data.objects.remove(obj)
    return figures(frames, states, pts, counts), per_frame(times), ""


def run_hairsys(context, scene, body, rig, pts, counts, settings, folder):
    """This extension with `settings` over the frame range: (figures, seconds per frame, notes
    on the integrator, substeps and the library's phases)."""
    import bpy
    import hairsys

    from hairsys_blender.bake import Baker

    obj = hair_object("hairsys", body, pts, counts)
    for name, value in settings.items():
        setattr(obj.hairsys, name, value)
    obj.hairsys.cache_path = str(pathlib.Path(folder) / "hair.mcap")
    obj.hairsys.playback = False
    context.view_layer.objects.active = obj
    baker = Baker(context, obj)
    times, reports = [], []
    while True:
        t0 = time.perf_counter()
        more = baker.step(context)
        if not more:
            break
        times.append(time.perf_counter() - t0)
        reports.append(baker.report)
    baker.finish()
    integrator = baker.session.integrator
    cache = hairsys.Cache(obj.hairsys.cache_path)
    frames, states = [], []
    for f in range(scene.frame_start, scene.frame_end + 1):
        scene.frame_set(f)
        frames.append(np.array(cache.frame(f)[0], dtype=np.float64))
        states.append(body_state(body, rig))
    bpy.data.objects.remove(obj)
    steady = reports[1:] or reports
    substeps = sorted({r["substeps"] * r["steps"] for r in steady})
    phases = {k: statistics.fmean(r["phase_ms"][k] for r in steady)
              for k in steady[0]["phase_ms"]}
    step_ms = statistics.fmean(r["step_ms"] for r in steady)
    frame_ms = per_frame(times) * 1e3
    note = (f"{integrator}, {'/'.join(map(str, substeps))} substeps per frame; of "
            f"{frame_ms:.1f} ms per frame the library's step {step_ms:.1f} ms ("
            + ", ".join(f"{k} {v:.1f}" for k, v in phases.items() if v >= 0.05)
            + f"), Blender and the add-on {frame_ms - step_ms:.1f} ms")
    return figures(frames, states, pts, counts), per_frame(times), note


def per_frame(times):
    """Mean seconds per frame, the first frame left out (it sets up caches on both sides)."""
    steady = times[1:] if len(times) > 1 else times
    return statistics.fmean(steady)


def parse_settings(pairs, kind, known):
    """[NAME=VALUE, …] as {name: value}; `known(name)` gives the value's type or raises
    SystemExit naming what there is."""
    out = {}
    for pair in pairs:
        name, sep, value = pair.partition("=")
        if not sep:
            sys.exit(f"{kind} {pair!r}: give NAME=VALUE")
        out[name] = known(name)(value)
    return out


def sweep(pair, kind, known):
    """NAME=V1,V2,… as [{name: v1}, {name: v2}, …]."""
    if pair is None:
        return [{}]
    name, _, values = pair.partition("=")
    kind_of = known(name)
    return [{name: kind_of(v)} for v in values.split(",") if v]


def hd_known(ids):
    types = {"NodeSocketInt": int, "NodeSocketFloat": float,
             "NodeSocketBool": lambda v: v.lower() in ("1", "true", "on", "yes")}

    def known(name):
        if name not in ids or ids[name][1] not in types:
            sys.exit(f"Hair Dynamics has no number or toggle input {name!r}; its inputs: "
                     + ", ".join(n for n, (_, t) in ids.items() if t in types))
        return types[ids[name][1]]
    return known


def ours_known(name):
    from hairsys_blender import HairsysSettings

    props = HairsysSettings.bl_rna.properties
    kinds = {"INT": int, "FLOAT": float,
             "BOOLEAN": lambda v: v.lower() in ("1", "true", "on", "yes")}
    if name not in props or props[name].type not in kinds:
        sys.exit(f"hairsys has no number or toggle setting {name!r}; its settings: "
                 + ", ".join(p.identifier for p in props if p.type in kinds))
    return kinds[props[name].type]


def label(settings):
    return ", ".join(f"{k} {v:g}" if not isinstance(v, bool) else f"{k} {'on' if v else 'off'}"
                     for k, v in settings.items()) or "defaults"


def main():
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0],
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--frames", type=int, default=48)
    parser.add_argument("--curves", type=int, default=1500)
    parser.add_argument("--length", type=float, default=0.1, help="hair length, m")
    parser.add_argument("--still", action="store_true",
                        help="the body does not move: how each holds a still groom")
    parser.add_argument("--hd", action="append", default=[], metavar="SOCKET=VALUE",
                        help="a Hair Dynamics input by its socket name, for every run of it")
    parser.add_argument("--hd-sweep", metavar="SOCKET=V1,V2,...",
                        help="one Hair Dynamics run per value of this input")
    parser.add_argument("--ours", action="append", default=[], metavar="SETTING=VALUE",
                        help="a hairsys setting by its Python name, for every run of it")
    parser.add_argument("--ours-sweep", metavar="SETTING=V1,V2,...",
                        help="one hairsys run per value of this setting")
    parser.add_argument("--rounds", type=int, default=1,
                        help="times each contender runs (alternated); time = median")
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
    pts, counts = groom(body, args.curves, args.length)

    known = hd_known(hair_dynamics_inputs(hair_dynamics_group()))
    hd_base = parse_settings(args.hd, "--hd", known)
    ours_base = parse_settings(args.ours, "--ours", ours_known)
    hd_runs = [{**hd_base, **v} for v in sweep(args.hd_sweep, "--hd-sweep", known)]
    ours_runs = [{**ours_base, **v} for v in sweep(args.ours_sweep, "--ours-sweep", ours_known)]
    # Alternate: HD 1, ours 1, HD 2, ours 2, …, the longer list's rest at the end; per round.
    order = []
    for i in range(max(len(hd_runs), len(ours_runs))):
        if i < len(hd_runs):
            order.append(("hd", i))
        if i < len(ours_runs):
            order.append(("ours", i))
    results = {}
    with tempfile.TemporaryDirectory() as folder:
        for r in range(args.rounds):
            for kind, i in order:
                scene.frame_set(1)
                if kind == "hd":
                    out = run_blender(scene, body, rig, pts, counts, hd_runs[i])
                else:
                    out = run_hairsys(bpy.context, scene, body, rig, pts, counts, ours_runs[i],
                                      folder)
                fig, t, note = out
                entry = results.setdefault((kind, i), dict(fig=fig, times=[], note=note))
                entry["times"].append(t)
                print(f"round {r + 1}: {kind} {label((hd_runs if kind == 'hd' else ours_runs)[i])}"
                      f": {t * 1e3:.1f} ms per frame", file=sys.stderr, flush=True)

    print(f"{args.curves:,} curves × {POINTS} points, {args.length * 100:g} cm, "
          f"{args.frames} frames{', still body' if args.still else ''}, Blender "
          f"{bpy.app.version_string}, {args.rounds} round(s)\n")
    print("| | settings | time per frame | stretch p99 | stretch max "
          "| points inside, worst frame (deepest) | tip motion against the head, max (mean) |")
    print("|---|---|---:|---:|---:|---:|---:|")
    rows = []
    for kind, i in sorted(results, key=lambda k: (k[0] != "hd", k[1])):
        entry = results[(kind, i)]
        f, t = entry["fig"], statistics.median(entry["times"])
        settings = (hd_runs if kind == "hd" else ours_runs)[i]
        name = "Blender 5.2 Hair Dynamics" if kind == "hd" else "hairsys extension"
        rows.append((kind, settings, t, f))
        print(f"| {name} | {label(settings)} | {t * 1e3:.1f} ms | {f['p99']:.2%} | "
              f"{f['max']:.2%} | {f['inside']:,} ({f['depth'] * 1e3:.2f} mm) | "
              f"{f['tip'] * 1e3:.1f} mm ({f['tip_mean'] * 1e3:.1f} mm) |")
    print()
    for kind, i in sorted(results):
        if kind == "ours":
            print(f"hairsys, {label(ours_runs[i])}: {results[(kind, i)]['note']}")
    holds_hd = [r for r in rows if r[0] == "hd" and r[3]["p99"] <= 0.01]
    holds_ours = [r for r in rows if r[0] == "ours" and r[3]["max"] <= 0.01
                  and r[3]["inside"] == 0]
    best_hd = min(holds_hd, key=lambda r: r[2], default=None)
    best_ours = min(holds_ours, key=lambda r: r[2], default=None)
    print()
    print("Hair Dynamics' cheapest setting with p99 stretch ≤ 1 %: "
          + (f"{label(best_hd[1])}, {best_hd[2] * 1e3:.1f} ms" if best_hd else "none of these"))
    print("hairsys's cheapest setting with max stretch ≤ 1 % and no point inside: "
          + (f"{label(best_ours[1])}, {best_ours[2] * 1e3:.1f} ms" if best_ours
             else "none of these"))
    if best_hd and best_ours:
        print(f"Time per frame, Hair Dynamics / hairsys: {best_hd[2] / best_ours[2]:.1f}×")
    hairsys_blender.unregister()


if __name__ == "__main__":
    main()
