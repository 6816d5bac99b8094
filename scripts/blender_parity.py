"""Times Blender's own hair dynamics on hairsys's parity scene (`scenes/parity.toml`).

Run with headless Blender (`pip install bpy==5.0.1 "numpy<2"`):

    python scripts/blender_parity.py [--collider] [--quality 5] [--frames 24]

The scene is `scenes/parity.toml` rebuilt in Blender: a UV sphere of radius 1 m (64 segments,
32 rings) emitting 20,000 hair particles of length 1.5 m with 16 segments each, hair dynamics
on at the given cloth quality (steps per frame), the sphere moving x 0 -> 1 -> 0 m and turning
0 -> 30 -> 0 degrees about z over frames 1, 12, 24 with Blender's default (eased) keyframes.
With `--collider` the sphere gets a Collision modifier ahead of the particle system, so the hair
collides with it, as in `scenes/parity_collide.toml`.

It prints, as one JSON line on stdout, the wall-clock seconds of every simulated frame (Blender
steps its hair dynamics when the frame is set, as when an animator plays the scene), their
median, and the largest segment stretch (|segment| / rest - 1) of the evaluated hair at a few
frames. Frames are stepped one by one in order, as hair dynamics needs (`bpy.ops.ptcache.bake_all`
in a background session returns at once without baking). Blender and hairsys do not solve the
same model; the figure is the time a Blender user waits for this scene on this machine.
"""

import argparse
import json
import statistics
import sys
import time

import bpy
import numpy as np


def build(quality, collider, frames):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.frame_start = 1
    scene.frame_end = frames
    scene.render.fps = 24
    bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32, radius=1.0)
    head = bpy.context.active_object
    if collider:
        head.modifiers.new("collision", "COLLISION")
    head.modifiers.new("hair", "PARTICLE_SYSTEM")
    psys = head.particle_systems[0]
    settings = psys.settings
    settings.type = "HAIR"
    settings.count = 20000
    settings.hair_length = 1.5
    settings.hair_step = 16
    settings.emit_from = "FACE"
    psys.seed = 1
    psys.use_hair_dynamics = True
    psys.cloth.settings.quality = quality
    psys.point_cache.frame_start = 1
    psys.point_cache.frame_end = frames
    for frame, x, turn in ((1, 0.0, 0.0), (12, 1.0, 30.0), (24, 0.0, 0.0)):
        head.location = (x, 0.0, 0.0)
        head.rotation_euler = (0.0, 0.0, np.radians(turn))
        head.keyframe_insert("location", frame=frame)
        head.keyframe_insert("rotation_euler", frame=frame)
    return scene, head


def strand_points(head):
    """Evaluated hair points in world space, one (segments + 1, 3) array per strand."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = head.evaluated_get(depsgraph)
    psys = evaluated.particle_systems[0]
    modifier = evaluated.modifiers["hair"]
    strands = []
    for particle in psys.particles:
        keys = particle.hair_keys
        strands.append(
            np.array([k.co_object(evaluated, modifier, particle) for k in keys], dtype=np.float64)
        )
    return strands


def max_stretch(strands, rest):
    worst = 0.0
    for now, then in zip(strands, rest):
        seg = np.linalg.norm(np.diff(now, axis=0), axis=1)
        rest_seg = np.linalg.norm(np.diff(then, axis=0), axis=1)
        worst = max(worst, float(np.max(seg / rest_seg - 1.0)))
    return worst


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--collider", action="store_true", help="the sphere collides with the hair")
    parser.add_argument("--quality", type=int, default=5, help="cloth steps per frame")
    parser.add_argument("--frames", type=int, default=24)
    parser.add_argument("--stretch-at", type=int, nargs="*", default=[12, 24],
                        help="frames whose largest stretch is measured (slow: Python per point)")
    args = parser.parse_args()
    scene, head = build(args.quality, args.collider, args.frames)
    scene.frame_set(1)
    rest = strand_points(head)
    seconds = []
    stretch = {}
    for frame in range(2, args.frames + 1):
        t0 = time.perf_counter()
        scene.frame_set(frame)
        seconds.append(time.perf_counter() - t0)
        if frame in args.stretch_at:
            stretch[frame] = max_stretch(strand_points(head), rest)
    json.dump(
        {
            "blender": bpy.app.version_string,
            "collider": args.collider,
            "quality": args.quality,
            "strands": len(rest),
            "points_per_strand": len(rest[0]) if rest else 0,
            "seconds_per_frame": seconds,
            "median_s": statistics.median(seconds),
            "max_stretch": stretch,
        },
        sys.stdout,
    )
    print()


if __name__ == "__main__":
    main()
