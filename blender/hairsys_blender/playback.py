"""Playback: on every frame change, hair objects with a baked cache take its positions.

Caches are opened once and kept by path (`hairsys.Cache`); a frame outside the cache leaves the
curves as they are. Positions are stored in world space and written back in the hair object's
local space (the inverse of its `matrix_world`); the digest of what playback writes is kept
(`bake.PLAYED_KEY`) so that a bake tells a played frame from an edited groom.

`cache_file` says where an object's cache is: its Cache path, `//` being the .blend file's
folder; a .blend file that was never saved has no folder, so `//name` goes to Blender's
temporary directory (Preferences › File Paths › Temporary Files, else the system's) under
`hairsys/`, and the bake reports where.
"""

import os
import tempfile

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


def cache_file(obj):
    """(absolute path of `obj`'s cache, a note for the artist or None). Raises ValueError when
    the Cache path is empty."""
    raw = obj.hairsys.cache_path.strip()
    if not raw:
        raise ValueError(f"{obj.name!r} has no Cache path: set one in Properties › Physics › "
                         "hairsys (e.g. //hair.mcap, next to the .blend file)")
    if raw.startswith("//") and not bpy.data.filepath:
        folder = bpy.context.preferences.filepaths.temporary_directory or tempfile.gettempdir()
        path = os.path.join(bpy.path.abspath(folder), "hairsys", raw[2:])
        note = (f"the .blend file is not saved yet, so the cache {raw} of {obj.name!r} is "
                f"written to {path}; save the .blend file to keep caches beside it")
        return os.path.normpath(path), note
    return os.path.normpath(bpy.path.abspath(raw)), None


def apply_frame(obj, frame):
    """Sets `obj`'s curve points from its cache at `frame`; False when the cache lacks it."""
    path, _ = cache_file(obj)
    if not os.path.exists(path):
        return False
    cache = cache_for(path)
    if frame not in cache.frames:
        return False
    positions, _ = cache.frame(frame)
    curves = obj.data
    if len(curves.points) != len(positions):
        return False
    from .bake import PLAYED_KEY, digest, rest_positions

    rest_positions(obj)  # keep the groom (or its edit) before overwriting it
    m = np.linalg.inv(np.array(obj.matrix_world, dtype=np.float64))
    local = (positions @ m[:3, :3].T + m[:3, 3]).astype(np.float32)
    curves.attributes["position"].data.foreach_set("vector", local.ravel())
    curves[PLAYED_KEY] = digest(local)
    curves.update_tag()
    return True


@persistent
def on_frame_change(scene, depsgraph=None):
    """Plays the caches back, then regenerates the children of hair objects that have them."""
    if baking:
        return
    from . import children

    for obj in scene.objects:
        if obj.type != "CURVES":
            continue
        s = obj.hairsys
        if s.playback and s.cache_path:
            try:
                apply_frame(obj, scene.frame_current)
            except (OSError, ValueError) as e:
                print(f"hairsys: cannot play back {obj.name}: {e}")
        if s.children_type != "NONE":
            try:
                children.update(obj, depsgraph or bpy.context.evaluated_depsgraph_get())
            except (OSError, ValueError) as e:
                print(f"hairsys: cannot make the children of {obj.name}: {e}")


@persistent
def on_render_init(scene, _=None):
    """A render job starts: children at the render level from now on."""
    from . import children

    children.rendering = True


@persistent
def on_render_pre(scene, _=None):
    """A frame is about to render: its children at the render level (a still render changes
    no frame, so they are made here)."""
    from . import children

    children.rendering = True
    on_frame_change(scene, bpy.context.evaluated_depsgraph_get())


@persistent
def on_render_end(scene, _=None):
    """The render job ended (or was cancelled): the viewport's children again at the next
    frame change."""
    from . import children

    children.rendering = False
