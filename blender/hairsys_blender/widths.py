"""Render widths: the hair Curves' `radius` point attribute, which Cycles and EEVEE render.

A point's radius is half the hair's width at its place along the curve: the width runs linearly
from Root Width at the root to Tip Width at the tip over the curve's arc length (the groom's,
so it stays put while the curve moves), the taper hairsys's children have
(`hair_render::shape::Taper`, shape 1). Written after each bake and whenever either width
changes.
"""

import numpy as np

from .bake import REST_ATTRIBUTE


def tapered_radius(points, counts, root_width, tip_width):
    """Radius (m) at each point, (P,) float32: half the width at its arc-length fraction along
    its curve, from `root_width` to `tip_width` (diameters, m). `points` (P, 3), `counts` (C,)
    points per curve."""
    points = np.asarray(points, dtype=np.float64)
    counts = np.asarray(counts, dtype=np.int64)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
    along = np.concatenate([[0.0], np.cumsum(seg)])
    # Arc length from each point's own root: subtract the root's running total.
    from_root = along - np.repeat(along[starts], counts)
    total = np.repeat(along[starts + counts - 1] - along[starts], counts)
    s = np.divide(from_root, total, out=np.zeros_like(from_root), where=total > 0)
    return (0.5 * (root_width + (tip_width - root_width) * s)).astype(np.float32)


def update(obj):
    """Writes `obj`'s `radius` point attribute from its Root Width and Tip Width."""
    curves = obj.data
    n = len(curves.points)
    if n == 0:
        return
    source = curves.attributes.get(REST_ATTRIBUTE) or curves.attributes["position"]
    flat = np.empty(n * 3, dtype=np.float32)
    source.data.foreach_get("vector", flat)
    offsets = np.empty(len(curves.curves) + 1, dtype=np.int32)
    curves.curve_offset_data.foreach_get("value", offsets)
    s = obj.hairsys
    radius = tapered_radius(flat.reshape(-1, 3), np.diff(offsets), s.root_width, s.tip_width)
    attr = curves.attributes.get("radius")
    if attr is None or attr.domain != "POINT" or attr.data_type != "FLOAT":
        if attr is not None:
            curves.attributes.remove(attr)
        attr = curves.attributes.new("radius", "FLOAT", "POINT")
    attr.data.foreach_set("value", radius)
    curves.update_tag()
