"""Playback: on every frame change, hair objects with a baked cache take its positions.

Caches are opened once and kept by path (`hairsys.Cache`); a frame outside the cache leaves the
curves as they are. Positions are stored in world space and written back in the hair object's
local space (the inverse of its `matrix_world`).
"""

import os

import bpy
import numpy as np
from bpy.app.handlers import persistent

import hairsys

_caches = {}
#: Set while a bake runs: its frame changes must not play the (partial) cache back.
baking = False


def cache_for(path):
    """The open cache at `path` (reopened when the file changed)."""
    stamp = os.path.getmtime(path)
    entry = _caches.get(path)
    if entry is None or entry[0] != stamp:
        entry = (stamp, hairsys.Cache(path))
        _caches[path] = entry
    return entry[1]


def forget(path):
    _caches.pop(path, None)


def apply_frame(obj, frame):
    """Sets `obj`'s curve points from its cache at `frame`; False when the cache lacks it."""
    path = bpy.path.abspath(obj.hairsys.cache_path)
    if not os.path.exists(path):
        return False
    cache = cache_for(path)
    if frame not in cache.frames:
        return False
    positions, _ = cache.frame(frame)
    curves = obj.data
    if len(curves.points) != len(positions):
        return False
    from .bake import rest_positions

    rest_positions(obj)  # keep the groom before the first overwrite
    m = np.linalg.inv(np.array(obj.matrix_world, dtype=np.float64))
    local = positions @ m[:3, :3].T + m[:3, 3]
    curves.attributes["position"].data.foreach_set("vector", local.astype(np.float32).ravel())
    curves.update_tag()
    return True


@persistent
def on_frame_change(scene, depsgraph=None):
    if baking:
        return
    for obj in scene.objects:
        if obj.type == "CURVES" and obj.hairsys.playback and obj.hairsys.cache_path:
            try:
                apply_frame(obj, scene.frame_current)
            except (OSError, ValueError) as e:
                print(f"hairsys: cannot play back {obj.name}: {e}")
