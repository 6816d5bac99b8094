"""Render children in Blender, headless: the hair of the bending body baked, its children made at
the viewport's amount when the frame changes and at the render amount when Cycles renders a
frame, rooted on the deformed surface with the surface's UVs and following their guides."""

import math

import numpy as np

from test_addon import build_scene, surface_bvh

FRAMES = 8
DISPLAY, RENDER = 2, 12


def uv_body(body):
    """Gives the body a UV map: u = angle around the axis / 2π, v = height (rest z)."""
    mesh = body.data
    layer = mesh.uv_layers.new(name="UVMap")
    for loop in mesh.loops:
        x, y, z = mesh.vertices[loop.vertex_index].co
        layer.data[loop.index].uv = ((math.atan2(y, x) / (2 * math.pi)) % 1.0, z)


def curve_arrays(obj):
    data = obj.data
    pts = np.empty(len(data.points) * 3, dtype=np.float32)
    data.attributes["position"].data.foreach_get("vector", pts)
    offsets = np.empty(len(data.curves) + 1, dtype=np.int32)
    data.curve_offset_data.foreach_get("value", offsets)
    return pts.reshape(-1, 3), offsets


def camera(scene):
    import bpy

    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(cam)
    cam.location = (1.2, -1.2, 0.9)
    cam.rotation_euler = (math.radians(80), 0, math.radians(45))
    scene.camera = cam


def test_children_follow_the_baked_guides_in_the_viewport_and_in_a_cycles_render(
        addon, tmp_path):
    import bpy

    scene, body, hair, rest, counts = build_scene(tmp_path)
    scene.frame_end = FRAMES
    uv_body(body)
    hair.data.surface_uv_map = "UVMap"
    s = hair.hairsys
    s.child_display_amount, s.child_render_amount = DISPLAY, RENDER
    s.children_type = "SIMPLE"
    assert bpy.ops.hairsys.bake() == {"FINISHED"}

    # Viewport: a frame change plays the cache back and makes the display amount of children.
    scene.frame_set(FRAMES)
    kids = s.children_object
    assert kids is not None and kids.type == "CURVES"
    assert len(kids.data.curves) == DISPLAY * len(counts)

    # A Cycles render of the frame makes every render child before it renders.
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 1
    scene.render.resolution_x = scene.render.resolution_y = 16
    scene.render.filepath = str(tmp_path / "frame.png")
    camera(scene)
    rendered = {}

    def look(scene, _=None):  # what the render sees, before the viewport's children return
        data = s.children_object.data
        pts, offsets = curve_arrays(s.children_object)
        radius = np.empty(len(pts), dtype=np.float32)
        data.attributes["radius"].data.foreach_get("value", radius)
        uv_attr = data.attributes["surface_uv_coordinate"]
        uv = np.empty(len(data.curves) * 2, dtype=np.float32)
        uv_attr.data.foreach_get("vector", uv)
        rendered.update(pts=pts, offsets=offsets, radius=radius, uv=uv.reshape(-1, 2),
                        uv_domain=uv_attr.domain, surface=data.surface)

    bpy.app.handlers.render_post.append(look)
    try:
        bpy.ops.render.render(write_still=True)
    finally:
        bpy.app.handlers.render_post.remove(look)
    assert (tmp_path / "frame.png").exists()
    pts, offsets = rendered["pts"], rendered["offsets"]
    assert len(offsets) - 1 == RENDER * len(counts)
    starts, tips = offsets[:-1], offsets[1:] - 1
    # After the render the viewport shows its own amount again.
    assert len(s.children_object.data.curves) == DISPLAY * len(counts)

    # Roots on the surface as bent at this frame: on the tangent disc of radius r = child_radius
    # around their guide's root, whose plane is that of the smooth (interpolated) normal. The
    # 16 facets of the body tilt up to π/16 from it, and the disc leaves a cylinder of R = 0.1 m
    # by r²/2R: at most r·sin(π/16) + r²/2R = 1.1 mm off the faces.
    r = s.child_radius
    bound = r * math.sin(math.pi / 16) + r * r / (2 * 0.1)
    bvh = surface_bvh(body)
    off = np.array([bvh.find_nearest(p)[3] for p in pts[starts]])
    assert off.max() <= bound * 1.01, f"a child's root is {off.max() * 1e3:.3f} mm off the surface"
    assert np.median(off) < 0.5 * bound

    # Each child keeps its root offset (≤ child_radius) from its guide along the guide's path:
    # its tip is within that of its guide's tip at this frame (which the bend moved).
    guides, goffsets = curve_arrays(hair)
    guide_tips = guides[goffsets[1:] - 1]
    parent = np.repeat(np.arange(len(counts)), RENDER)
    gap = np.linalg.norm(pts[tips] - guide_tips[parent], axis=1)
    assert gap.max() <= 1.5 * s.child_radius, f"a child's tip is {gap.max():.4f} m from its guide's"
    moved = np.linalg.norm(guide_tips - rest[np.cumsum(counts) - 1], axis=1)
    assert moved.max() > 0.02, "the guides did not move: the test would not test following"

    # The radius tapers from the root width to the tip width; root UVs are the surface's.
    np.testing.assert_allclose(rendered["radius"][starts], s.root_width / 2, rtol=1e-4)
    assert rendered["uv_domain"] == "CURVE"
    v = rendered["uv"][:, 1]
    # Roots were grown between rest heights 0.6 and 0.9; v is the rest height.
    assert v.min() > 0.6 - 0.01 and v.max() < 0.9 + 0.01, (v.min(), v.max())
    assert rendered["surface"] == body


def test_interpolated_children_grow_on_the_surface_among_their_guides(addon, tmp_path):
    """Interpolated children are rooted on the surface between guides (mesh samples: on the
    faces) and blend their neighbouring guides, so each tip lies among the guides' tips: no
    farther from the nearest than the guides' spacing around the body (2π · 0.1 m / 16)."""
    import bpy

    from hairsys_blender import children

    scene, body, hair, rest, counts = build_scene(tmp_path)
    scene.frame_end = FRAMES
    s = hair.hairsys
    s.child_display_amount, s.child_render_amount = DISPLAY, RENDER
    s.children_type = "INTERPOLATED"
    assert bpy.ops.hairsys.bake() == {"FINISHED"}
    scene.frame_set(FRAMES)
    kids = children.update(hair, bpy.context.evaluated_depsgraph_get(), render=True)
    pts, offsets = curve_arrays(kids)
    assert len(offsets) - 1 == RENDER * len(counts)
    bvh = surface_bvh(body)
    off = max(bvh.find_nearest(p)[3] for p in pts[offsets[:-1]])
    assert off < 1e-5, f"a child's root is {off * 1e3:.3f} mm off the surface"
    guides, goffsets = curve_arrays(hair)
    guide_tips = guides[goffsets[1:] - 1]
    tips = pts[offsets[1:] - 1]
    nearest = np.linalg.norm(tips[:, None, :] - guide_tips[None, :, :], axis=2).min(axis=1)
    spacing = 2 * math.pi * 0.1 / 16
    assert nearest.max() <= spacing, f"a child's tip is {nearest.max():.4f} m from every guide's"
