"""Render children: many hairs generated around the simulated (or groomed) guide curves, into a
second Curves object that Cycles and EEVEE render, regenerated at every frame change (viewport
playback and every frame of a render).

hairsys makes the children (`Session.children` with `positions` and `scalp_vertices`): the
guides are the hair object's curves as they are now (playback has put the cached frame there),
rooted on the surface as evaluated now. A child session is made once per hair object from the
groom at the frame it is first asked for (it snaps the roots onto the surface: mesh samples
that hold on the deformed surface at any frame) and kept until the guides' or the surface's
topology changes. The children object holds:

- `position`, `radius` (half of the tapered width, Root Width to Tip Width),
- `surface_uv_coordinate` (curve domain): the surface UV at each child's root, from the
  surface's active UV map, blended over the corners of the triangle the root lies in (found
  once per child session, the roots keep their place on the surface),
- `surface`, `surface_uv_map`: the hair object's, so Blender's own hair nodes can use them.

The viewport shows `Display Amount` children per guide with the guides' own points (hairsys's
display level of detail: a prefix of each guide's render children, so the same hairs); a render
shows `Render Amount` per guide with the render subdivisions. `render_pre` switches to the
render level, `render_post` back.
"""

import numpy as np

import hairsys

#: Set between render_pre and render_post: children are made at the render level.
rendering = False
#: Per hair object name: (key, child session, {lod key: root UVs}).
_sessions = {}


def child_object(hair_obj, create=True):
    """The Curves object holding `hair_obj`'s children (made in its collections on request)."""
    import bpy

    s = hair_obj.hairsys
    obj = s.children_object
    if obj is None and create:
        data = bpy.data.hair_curves.new(f"{hair_obj.name} Children")
        obj = bpy.data.objects.new(f"{hair_obj.name} Children", data)
        for coll in hair_obj.users_collection:
            coll.objects.link(obj)
        for mat in hair_obj.data.materials:
            data.materials.append(mat)
        s.children_object = obj
    return obj


def settings_args(s, render):
    """`Session.children` keyword arguments of the panel's settings at a level."""
    per_parent = s.child_render_amount
    args = dict(
        per_parent=per_parent, interpolated=s.children_type == "INTERPOLATED",
        spread=s.child_radius, clump=s.child_clump, curl_radius=s.child_curl_radius,
        curl_frequency=s.child_curl_frequency, roughness=s.child_roughness,
        roughness_endpoint=s.child_roughness_endpoint,
        length_variation=s.child_length_variation, root_width=s.root_width,
        tip_width=s.tip_width, subdivisions=s.child_subdivisions, seed=s.child_seed)
    if not render:
        args.update(display=True,
                    display_fraction=min(1.0, s.child_display_amount / max(1, per_parent)))
    return args


def child_session(hair_obj, guides, counts, verts, tris):
    """The child session of `hair_obj`, made from these guides on this surface when there is
    none for this topology."""
    key = (len(guides), len(counts), len(verts), len(tris), hair_obj.data.surface.name)
    entry = _sessions.get(hair_obj.name)
    if entry is None or entry[0] != key:
        session = hairsys.Session.from_groom(
            verts, tris, guides, counts, gravity=(0.0, 0.0, 0.0),
            max_snap_distance=hair_obj.hairsys.max_snap_distance)
        entry = (key, session, {})
        _sessions[hair_obj.name] = entry
    return entry


def forget(hair_obj=None):
    """Drops the child sessions (of one object, or all)."""
    if hair_obj is None:
        _sessions.clear()
    else:
        _sessions.pop(hair_obj.name, None)


def root_uvs(surface, depsgraph, roots):
    """UV (C, 2) float32 of the active UV map at `roots` (world space) on `surface` as evaluated
    now: the corners' UVs of the nearest loop triangle blended by the root's barycentric
    coordinates. None when the surface has no UV map."""
    from mathutils import Vector
    from mathutils.bvhtree import BVHTree
    from mathutils.geometry import barycentric_transform

    ev = surface.evaluated_get(depsgraph)
    mesh = ev.to_mesh()
    try:
        uv_layer = mesh.uv_layers.active
        if uv_layer is None:
            return None
        mesh.calc_loop_triangles()
        m = ev.matrix_world
        co = [m @ v.co for v in mesh.vertices]
        tris = [tuple(t.vertices) for t in mesh.loop_triangles]
        loops = [tuple(t.loops) for t in mesh.loop_triangles]
        uv = [Vector((d.uv[0], d.uv[1], 0.0)) for d in uv_layer.data]
        bvh = BVHTree.FromPolygons(co, tris)
        out = np.zeros((len(roots), 2), dtype=np.float32)
        for i, r in enumerate(roots):
            loc, _, t, _ = bvh.find_nearest(Vector(r))
            if t is None:
                continue
            a, b, c = (co[j] for j in tris[t])
            la, lb, lc = (uv[j] for j in loops[t])
            p = barycentric_transform(loc, a, b, c, la, lb, lc)
            out[i] = (p[0], p[1])
        return out
    finally:
        ev.to_mesh_clear()


def guide_arrays(hair_obj):
    """The hair object's curves now: world-space points (P, 3) float64 and counts (C,)."""
    from .bake import world_points

    curves = hair_obj.data
    flat = np.empty(len(curves.points) * 3, dtype=np.float32)
    curves.attributes["position"].data.foreach_get("vector", flat)
    offsets = np.empty(len(curves.curves) + 1, dtype=np.int32)
    curves.curve_offset_data.foreach_get("value", offsets)
    return (world_points(hair_obj.matrix_world, flat.reshape(-1, 3).astype(np.float64)),
            np.diff(offsets))


def update(hair_obj, depsgraph, render=None):
    """Regenerates `hair_obj`'s children from its curves and surface as they are now, at the
    render level when rendering (or `render`), else at the display level. Returns the
    children object."""
    from .bake import evaluated_mesh

    if render is None:
        render = rendering
    surface = hair_obj.data.surface
    if surface is None or surface.type != "MESH":
        raise ValueError(f"{hair_obj.name!r} has no surface mesh for its children: pick one as "
                         "Surface in Properties › Object Data › Surface")
    guides, counts = guide_arrays(hair_obj)
    verts, tris = evaluated_mesh(surface, depsgraph, triangles=True)
    _, session, uv_cache = child_session(hair_obj, guides, counts, verts, tris)
    args = settings_args(hair_obj.hairsys, render)
    made = session.children(positions=guides, scalp_vertices=verts, **args)
    counts_c = np.asarray(made.vertex_counts)
    points = np.asarray(made.points)
    widths = np.asarray(made.widths)
    obj = child_object(hair_obj)
    data = obj.data
    if len(data.curves) != len(counts_c) or len(data.points) != len(points) or not np.array_equal(
            _offsets(data)[1:] - _offsets(data)[:-1], counts_c):
        data = _new_data(obj, hair_obj, counts_c)
    data.attributes["position"].data.foreach_set("vector", points.ravel())
    radius = data.attributes.get("radius") or data.attributes.new("radius", "FLOAT", "POINT")
    radius.data.foreach_set("value", (0.5 * widths).astype(np.float32))
    lod_key = tuple(sorted(args.items()))
    uv = uv_cache.get(lod_key)
    if uv is None:
        starts = np.concatenate([[0], np.cumsum(counts_c)[:-1]]).astype(np.int64)
        uv = root_uvs(surface, depsgraph, points[starts])
        uv_cache.clear()
        uv_cache[lod_key] = uv
    if uv is not None:
        attr = (data.attributes.get("surface_uv_coordinate")
                or data.attributes.new("surface_uv_coordinate", "FLOAT2", "CURVE"))
        attr.data.foreach_set("vector", uv.ravel())
    data.update_tag()
    return obj


def _offsets(data):
    offsets = np.empty(len(data.curves) + 1, dtype=np.int32)
    data.curve_offset_data.foreach_get("value", offsets)
    return offsets


def _new_data(obj, hair_obj, counts):
    """New Curves data for `obj` with curves of `counts` points (the old data is removed when
    nothing else uses it)."""
    import bpy

    old = obj.data
    data = bpy.data.hair_curves.new(old.name)
    data.add_curves([int(c) for c in counts])
    for mat in old.materials:
        data.materials.append(mat)
    data.surface = hair_obj.data.surface
    data.surface_uv_map = hair_obj.data.surface_uv_map
    obj.data = data
    if old.users == 0:
        bpy.data.hair_curves.remove(old)
    return data
