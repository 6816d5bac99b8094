"""Bake speed of the add-on against `hairsys simulate`, default-size groom (4000 strands of 17
points, 48 frames, no colliders) on a rotating UV-sphere head of radius 0.1 m.

    target/pyenv/bin/python blender/bench_bake.py [--bin target/release/hairsys]

The add-on bakes curves made in Blender (roots area-weighted on the sphere, straight along the
normal, 0.25 m); `hairsys simulate` runs a scene of the same size (`[hair]` generated on the
same sphere, the same rotation keys). Both are timed end to end (setup, 47 steps, cache).
"""

import argparse
import math
import pathlib
import subprocess
import sys
import tempfile
import time

import numpy as np

REPO = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "blender"))

COUNT, POINTS, LENGTH, FRAMES = 4000, 17, 0.25, 48
KEYS = [(1, 0), (12, 50), (24, -50), (36, 0), (48, 0)]

SCENE = f"""
[scene]
name = "bench"
fps = 24.0
frames = [1, {FRAMES}]
[physics]
stretch_stiffness = 40.0
bend_stiffness = 0.5
goal_stiffness = 0.0
air_drag = 2.0
[scalp.mesh]
kind = "uv-sphere"
radius = 0.1
segments = 32
rings = 16
[scalp.motion]
interpolation = "linear"
keys = [{", ".join(f"{{ frame = {f}, translation = [0.0, 0.0, 0.0], rotation_deg = [0.0, 0.0, {a}.0] }}" for f, a in KEYS)}]
[hair]
count = {COUNT}
length = {LENGTH}
segments = {POINTS - 1}
seed = 1
radius = 0.001
"""


def blender_bake(path):
    import bpy
    import hairsys_blender

    bpy.ops.wm.read_factory_settings(use_empty=True)
    if not hasattr(bpy.types.Object, "hairsys"):
        hairsys_blender.register()
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end, scene.render.fps = 1, FRAMES, 24
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.1, segments=32, ring_count=16)
    head = bpy.context.object
    head.rotation_mode = "XYZ"
    for f, a in KEYS:
        head.rotation_euler = (0, 0, math.radians(a))
        head.keyframe_insert("rotation_euler", frame=f)
    for fc in head.animation_data.action.fcurves if hasattr(head.animation_data.action, "fcurves") else []:
        for k in fc.keyframe_points:
            k.interpolation = "LINEAR"
    scene.frame_set(1)
    mesh = head.data
    mesh.calc_loop_triangles()
    co = np.array([v.co for v in mesh.vertices])
    tris = np.array([t.vertices[:] for t in mesh.loop_triangles])
    a, b, c = co[tris[:, 0]], co[tris[:, 1]], co[tris[:, 2]]
    area = np.linalg.norm(np.cross(b - a, c - a), axis=1)
    rng = np.random.default_rng(1)
    pick = rng.choice(len(tris), COUNT, p=area / area.sum())
    u, v = rng.random(COUNT), rng.random(COUNT)
    flip = u + v > 1
    u[flip], v[flip] = 1 - u[flip], 1 - v[flip]
    roots = a[pick] + (b[pick] - a[pick]) * u[:, None] + (c[pick] - a[pick]) * v[:, None]
    normals = roots / np.linalg.norm(roots, axis=1, keepdims=True)
    steps = np.linspace(0, LENGTH, POINTS)
    pts = (roots[:, None] + normals[:, None] * steps[None, :, None]).reshape(-1, 3)
    curves = bpy.data.hair_curves.new("hair")
    curves.add_curves([POINTS] * COUNT)
    curves.attributes["position"].data.foreach_set("vector", pts.astype(np.float32).ravel())
    curves.surface = head
    hair = bpy.data.objects.new("hair", curves)
    scene.collection.objects.link(hair)
    bpy.context.view_layer.objects.active = hair
    hair.hairsys.cache_path = str(path)
    hair.hairsys.surface_collision = False
    hair.hairsys.radius = 0.002
    t = time.perf_counter()
    assert bpy.ops.hairsys.bake() == {"FINISHED"}
    return time.perf_counter() - t


def cli_run(binary, d):
    scene = pathlib.Path(d) / "bench.toml"
    scene.write_text(SCENE)
    t = time.perf_counter()
    subprocess.run([binary, "simulate", str(scene), "--cache", str(pathlib.Path(d) / "cli.mcap"),
                    "--quiet"], check=True)
    return time.perf_counter() - t


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default=str(REPO / "target/release/hairsys"))
    ap.add_argument("--runs", type=int, default=2)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        for i in range(a.runs):
            c = cli_run(a.bin, d)
            b = blender_bake(pathlib.Path(d) / f"bake{i}.mcap")
            print(f"run {i}: hairsys simulate {c:.2f} s, add-on bake {b:.2f} s, "
                  f"bake speed {100 * c / b:.0f} % of simulate")


if __name__ == "__main__":
    main()
