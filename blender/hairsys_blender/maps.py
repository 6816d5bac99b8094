"""Painted maps: a surface vertex group or a curve attribute, chosen per purpose in the panel,
turned into the per-strand and per-point values `hairsys.Session.from_groom` takes.

| purpose   | panel settings                      | handed to hairsys                          |
|-----------|-------------------------------------|--------------------------------------------|
| goal      | `weight_source`, `weight_name`      | `goal_weights` (P,): value clipped to 0-1  |
| stiffness | `stiffness_source`, `stiffness_name`| `strand_scales={"bend": (C,)}`: the value  |
|           |                                     | multiplies Bend Stiffness (≥ 0)            |
| stretch   | `stretch_source`, `stretch_name`    | `strand_scales={"stretch": (C,)}`: × the   |
|           |                                     | Stretch Stiffness (≥ 0)                    |
| damping   | `damping_source`, `damping_name`    | `strand_scales={"damping": (C,)}`: × the   |
|           |                                     | stretch damping (≥ 0)                      |
| drag      | `drag_source`, `drag_name`          | `strand_scales={"drag": (C,)}`: × Air Drag |
|           |                                     | (≥ 0)                                      |
| pin       | `pin_source`, `pin_name`            | `pinned` (P,): points whose value ≥ 0.5    |

The four factors are per strand (a point attribute gives its root point's value) and go into one
`strand_scales` dict; a strand without a painted factor keeps 1 (the panel's setting). Blender
keeps vertex group weights in 0-1, so a factor above 1 (stiffer, more drag) needs a curve
attribute.

Sources:
- ATTRIBUTE: a float attribute of the curves. On the point domain it gives each point its own
  value (a per-strand purpose, stiffness, takes the root point's); on the curve domain every
  point of a curve takes the curve's.
- VERTEX_GROUP: a vertex group of the surface mesh, at each curve's root: the root's closest
  point on the evaluated surface (world space, the triangles hairsys snaps the root onto) lies
  in one triangle, and the value is the blend of that triangle's three vertex weights by the
  point's barycentric coordinates (a vertex outside the group weighs 0). Every point of the
  curve takes it (a pinned root pins the whole strand: it follows the surface rigidly, the
  hold-out of a scene). Before, the add-on took the weight of the nearest surface vertex, which
  on a coarse mesh hands a root in the middle of a face the value of whichever corner is
  closest; the blend is continuous over the surface and matches `[maps.NAME]` of a scene.

Vertex groups are read on the surface's original mesh, so the evaluated mesh must keep its
vertex count (armatures and shape keys do; a subdivision modifier does not and is refused).
"""

import numpy as np

#: Purpose, its (source, name) settings and its label in the panel.
PURPOSES = (
    ("goal", "weight_source", "weight_name", "Goal Weights"),
    ("stiffness", "stiffness_source", "stiffness_name", "Stiffness"),
    ("stretch", "stretch_source", "stretch_name", "Stretch"),
    ("damping", "damping_source", "damping_name", "Damping"),
    ("drag", "drag_source", "drag_name", "Drag"),
    ("pin", "pin_source", "pin_name", "Pin"),
)

#: Per-strand factor purposes: the `strand_scales` key each fills and the panel setting it
#: multiplies (named in errors).
FACTORS = {
    "stiffness": ("bend", "Bend Stiffness"),
    "stretch": ("stretch", "Stretch Stiffness"),
    "damping": ("damping", "stretch damping"),
    "drag": ("drag", "Air Drag"),
}


def root_triangles(verts, tris, roots):
    """Per root (C, 3): the index of the surface triangle it is closest to and the barycentric
    weights (C, 3) of its closest point on that triangle, which sum to 1."""
    from mathutils.bvhtree import BVHTree

    bvh = BVHTree.FromPolygons(verts.tolist(), tris.tolist())
    index = np.empty(len(roots), dtype=np.int64)
    closest = np.empty((len(roots), 3))
    for i, r in enumerate(roots):
        co, _, tri, _ = bvh.find_nearest(r.tolist())
        if tri is None:
            raise ValueError("the surface mesh has no faces to root the curves on")
        index[i], closest[i] = tri, co
    a, b, c = (verts[tris[index, k]] for k in range(3))
    e0, e1, d = b - a, c - a, closest - a
    d00, d01, d11 = (e0 * e0).sum(1), (e0 * e1).sum(1), (e1 * e1).sum(1)
    d20, d21 = (d * e0).sum(1), (d * e1).sum(1)
    denom = d00 * d11 - d01 * d01
    ok = denom > 0  # a degenerate (zero-area) triangle: its first corner
    safe = np.where(ok, denom, 1.0)
    v = np.where(ok, (d11 * d20 - d01 * d21) / safe, 0.0)
    w = np.where(ok, (d00 * d21 - d01 * d20) / safe, 0.0)
    weights = np.clip(np.stack([1.0 - v - w, v, w], axis=1), 0.0, 1.0)
    return index, weights / weights.sum(1, keepdims=True)


def vertex_group_values(surface, name, vertex_count):
    """Weights (V,) of the vertex group `name` of the mesh object `surface` (0 outside it)."""
    group = surface.vertex_groups.get(name)
    if group is None:
        raise ValueError(f"the surface {surface.name!r} has no vertex group {name!r}")
    mesh = surface.data
    if len(mesh.vertices) != vertex_count:
        raise ValueError(
            f"the surface {surface.name!r} has {len(mesh.vertices)} vertices but its evaluated "
            f"mesh has {vertex_count}: vertex groups are read on the original mesh, so its "
            "modifiers must keep the vertex count (apply or disable the one that changes it)")
    values = np.zeros(vertex_count, dtype=np.float64)
    for v in mesh.vertices:
        for g in v.groups:
            if g.group == group.index:
                values[v.index] = g.weight
    return values


def curve_attribute(hair_obj, name, counts):
    """The float attribute `name` of the curves: (values, domain) with one value per point
    ("POINT") or per curve ("CURVE")."""
    attr = hair_obj.data.attributes.get(name)
    if attr is None or attr.data_type != "FLOAT" or attr.domain not in {"POINT", "CURVE"}:
        raise ValueError(
            f"the hair has no float attribute {name!r} on points or curves; add one or choose "
            "another source")
    values = np.empty(len(attr.data), dtype=np.float32)
    attr.data.foreach_get("value", values)
    return values.astype(np.float64), attr.domain


class Sampler:
    """Values of the chosen sources for one groom: `points` (P, 3) world-space rest points,
    `counts` (C,) points per curve, on the evaluated surface `verts` (V, 3) and `tris` (T, 3).
    The roots' triangles are found once, when a vertex group first asks for them."""

    def __init__(self, hair_obj, verts, tris, points, counts):
        self.hair = hair_obj
        self.verts, self.tris = verts, tris
        self.counts = np.asarray(counts)
        self.starts = np.concatenate([[0], np.cumsum(self.counts)[:-1]]).astype(np.int64)
        self.roots = points[self.starts]
        self._at_roots = None

    def at_roots(self, per_vertex):
        """`per_vertex` (V,) blended at every root (C,)."""
        if self._at_roots is None:
            self._at_roots = root_triangles(self.verts, self.tris, self.roots)
        index, weights = self._at_roots
        return (per_vertex[self.tris[index]] * weights).sum(1)

    def per_curve(self, source, name):
        """One value per curve from `source` (root values of a point attribute)."""
        if source == "VERTEX_GROUP":
            surface = self.hair.data.surface
            return self.at_roots(vertex_group_values(surface, name, len(self.verts)))
        values, domain = curve_attribute(self.hair, name, self.counts)
        return values if domain == "CURVE" else values[self.starts]

    def per_point(self, source, name):
        """One value per point from `source` (a curve's value on all its points)."""
        if source == "ATTRIBUTE":
            values, domain = curve_attribute(self.hair, name, self.counts)
            if domain == "POINT":
                return values
            return np.repeat(values, self.counts)
        return np.repeat(self.per_curve(source, name), self.counts)


def strand_maps(hair_obj, settings, verts, tris, points, counts):
    """The keyword arguments of `Session.from_groom` the panel's map sources give (empty when
    every source is None): goal_weights, strand_scales and pinned (see the module docs)."""
    sampler = Sampler(hair_obj, verts, tris, points, counts)
    out = {}
    for purpose, source_key, name_key, label in PURPOSES:
        source = getattr(settings, source_key)
        if source == "NONE":
            continue
        name = getattr(settings, name_key)
        try:
            if purpose == "goal":
                out["goal_weights"] = np.clip(sampler.per_point(source, name), 0.0, 1.0)
            elif purpose in FACTORS:
                key, setting = FACTORS[purpose]
                factor = sampler.per_curve(source, name)
                if not np.all(np.isfinite(factor)) or factor.min() < 0.0:
                    raise ValueError(f"{name!r} has a value below 0 or not finite; a "
                                     f"{label.lower()} factor is ≥ 0 (1 = the panel's "
                                     f"{setting}, 0 = none)")
                out.setdefault("strand_scales", {})[key] = factor
            else:
                out["pinned"] = sampler.per_point(source, name) >= 0.5
        except ValueError as e:
            raise ValueError(f"{label}: {e}") from None
    return out
