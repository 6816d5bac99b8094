"""Per-frame cost of the add-on's render children: 1,000 guide curves of 17 points on a UV-sphere
head (radius 0.1 m) swaying frame by frame, 100 simple children per guide at 1 render step
(100,000 children × 17 points), regenerated into the children Curves object every frame as a
render does (`children.update(..., render=True)`: hairsys makes them from the guides and the
evaluated head, the add-on writes position, radius and, once, the root UVs).

    target/pyenv/bin/python blender/bench_children.py [--frames 12] [--guides 1000]

Prints the first frame (child session, root UVs) apart from the steady frames (mean, max) and
the steady frames' split between hairsys (`Session.children`, timed again alone) and the rest
(reading the guides and the evaluated head, writing into Blender).
"""

import argparse
import math
import pathlib
import sys
import time

import numpy as np

REPO = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "blender"))

POINTS, LENGTH, PER_GUIDE = 17, 0.25, 100


def build(guides):
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.1, segments=32, ring_count=16)
    head = bpy.context.active_object
    head.name = "head"
    rng = np.random.default_rng(1)
    z = rng.uniform(0.0, 1.0, guides)  # upper hemisphere, uniform in area
    a = rng.uniform(0.0, 2 * math.pi, guides)
    normals = np.stack([np.sqrt(1 - z * z) * np.cos(a), np.sqrt(1 - z * z) * np.sin(a), z], 1)
    steps = np.arange(POINTS) / (POINTS - 1)
    pts = (normals[:, None, :] * (0.1 + LENGTH * steps[None, :, None])).reshape(-1, 3)
    curves = bpy.data.hair_curves.new("hair")
    curves.add_curves([POINTS] * guides)
    curves.attributes["position"].data.foreach_set("vector", pts.astype(np.float32).ravel())
    curves.surface = head
    hair = bpy.data.objects.new("hair", curves)
    bpy.context.scene.collection.objects.link(hair)
    s = hair.hairsys
    s.playback = False
    s.child_render_amount, s.child_subdivisions = PER_GUIDE, 1
    return hair, pts


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frames", type=int, default=12)
    parser.add_argument("--guides", type=int, default=1000)
    args = parser.parse_args()

    import bpy

    import hairsys_blender
    from hairsys_blender import children
    from hairsys_blender.bake import evaluated_mesh

    hairsys_blender.register()
    hair, rest = build(args.guides)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    s = hair.hairsys
    s.children_type = "SIMPLE"  # the update callback makes the viewport's children once
    made_in = []
    times = []
    steps = np.arange(POINTS) / (POINTS - 1)
    for f in range(args.frames):
        # Sway: each guide's points bend sideways along x, more towards the tip.
        sway = 0.03 * math.sin(f / 3.0) * (steps ** 2)
        pts = rest.reshape(-1, POINTS, 3).copy()
        pts[:, :, 0] += sway[None, :]
        hair.data.attributes["position"].data.foreach_set(
            "vector", pts.astype(np.float32).ravel())
        hair.data.update_tag()
        t0 = time.perf_counter()
        kids = children.update(hair, depsgraph, render=True)
        times.append(time.perf_counter() - t0)
        # hairsys's share: the same call again, alone.
        _, session, _ = children._sessions[hair.name]
        guides, _ = children.guide_arrays(hair)
        verts, _ = evaluated_mesh(hair.data.surface, depsgraph)
        t0 = time.perf_counter()
        session.children(positions=guides, scalp_vertices=verts,
                         **children.settings_args(s, render=True))
        made_in.append(time.perf_counter() - t0)
    count = len(kids.data.curves)
    points = len(kids.data.points)
    steady = np.array(times[1:])
    made = np.array(made_in[1:])
    print(f"{count:,} children, {points:,} points ({points // count} per child), "
          f"{args.guides:,} guides × {POINTS} points, {args.frames} frames")
    print(f"first frame (child session, root UVs): {times[0]:.3f} s")
    print(f"per frame after it: mean {steady.mean():.3f} s, max {steady.max():.3f} s "
          f"(hairsys {made.mean():.3f} s, the rest {steady.mean() - made.mean():.3f} s)")
    hairsys_blender.unregister()


if __name__ == "__main__":
    main()
