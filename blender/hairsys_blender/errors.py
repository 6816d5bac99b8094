"""hairsys's errors in Blender's words: which object, which panel, what to change.

The Python module's messages name its own arguments (`max_snap_distance`, `curve_points`, …)
and the ways a host could fix them (export transforms, import options), which an artist in
Blender never sees. `explain` looks at the groom itself first: roots off the surface are the
common case (the Curves' Surface is another mesh than the one the hair was grown on, or the
hair object was moved away from it), and it says so with the object names and the panels where
they are fixed. Other messages have their argument names replaced by the panel's labels.
"""

import numpy as np

#: `Session.from_groom` argument → where the artist sets it.
SETTINGS = {
    "stretch_stiffness": "Stretch Stiffness",
    "bend_stiffness": "Bend Stiffness",
    "goal_stiffness": "Goal Stiffness",
    "air_drag": "Air Drag",
    "mass_per_length": "Mass per Length",
    "radius": "Radius",
    "substeps": "Substeps",
    "threads": "Threads",
    "max_snap_distance": "Max Snap Distance",
    "goal_weights": "Goal Weights",
    "pinned": "Pin",
    "strand_scales": "the Stiffness, Stretch, Damping and Drag maps",
    "sag_free": "Sag-Free Rest",
    "scalp_thickness": "Surface Thickness",
    "scalp_friction": "Surface Friction",
    "scalp_collider": "Surface Collision",
    "colliders": "Colliders",
    "fps": "the scene's Frame Rate (Properties › Output › Format)",
    "gravity": "the scene's Gravity (Properties › Scene › Gravity)",
}
#: Arguments the add-on fills from the objects themselves, not from a setting.
GEOMETRY = {
    "scalp_vertices": "the surface mesh",
    "scalp_triangles": "the surface mesh's faces",
    "curve_points": "the curves' points",
    "curve_counts": "the curves (each needs at least 2 points)",
}
PANEL = "Properties › Physics › hairsys"


def root_distances(points, counts, verts, tris):
    """Distance (m) of each curve's root (world space) from the surface triangles."""
    from mathutils import Vector
    from mathutils.bvhtree import BVHTree

    bvh = BVHTree.FromPolygons([Vector(v) for v in verts], [tuple(map(int, t)) for t in tris])
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(int)
    out = np.empty(len(starts))
    for i, root in enumerate(points[starts]):
        hit = bvh.find_nearest(Vector(root))
        out[i] = hit[3] if hit[0] is not None else np.inf
    return out


def length(metres):
    """A length as Blender shows it in the panel (mm below 1 m)."""
    return f"{metres * 1e3:.3g} mm" if metres < 1.0 else f"{metres:.3g} m"


def explain(error, hair_obj, points, counts, verts, tris):
    """The message of `error` (raised by `Session.from_groom` for `hair_obj`) in the panel's
    words."""
    s = hair_obj.hairsys
    surface = hair_obj.data.surface
    if len(tris) and len(counts):
        far = root_distances(points, counts, verts, tris)
        off = far > s.max_snap_distance
        if off.any():
            return (
                f"{off.sum()} of {len(far)} curve roots of {hair_obj.name!r} are farther than "
                f"Max Snap Distance ({length(s.max_snap_distance)}) from its surface "
                f"{surface.name!r}, the farthest {length(float(far.max()))} away: the hair does "
                f"not grow on {surface.name!r}. Pick the mesh it was grown on as Surface "
                "(Properties › Object Data › Surface), or put the hair back on this one "
                f"(move {hair_obj.name!r} back, or Curves Sculpt Mode › Curves › Snap to "
                "Nearest Surface); roots only slightly off need a larger Max Snap Distance "
                f"({PANEL})")
    message = str(error)
    name, _, rest = message.partition(":")
    name = name.strip()
    if name in SETTINGS:
        where = SETTINGS[name]
        if not where.startswith("the "):
            where = f"{where} ({PANEL})"
        return f"{hair_obj.name!r}: {where}: {rest.strip()}"
    if name in GEOMETRY:
        return f"{hair_obj.name!r}: {GEOMETRY[name]}: {rest.strip()}"
    return f"{hair_obj.name!r} ({PANEL}): {message}"
