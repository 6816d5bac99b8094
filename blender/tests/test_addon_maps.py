"""The add-on's painted maps, headless: a surface vertex group is sampled at each root by the
barycentric weights of its surface triangle (not the nearest vertex), and a painted vertex group
or curve attribute changes exactly the painted strands' behaviour (pin, bend and stretch
stiffness, stretch damping, air drag), leaving the others bit for bit as without the map."""

import numpy as np
import pytest

from test_addon import read_mcap

FRAMES = 8
N_POINTS = 6


def field(x, y):
    """The linear field painted on the coarse quad's corners."""
    return 0.1 + 0.5 * x + 0.3 * y


def mesh_object(name, verts, faces):
    import bpy

    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def hair_object(surface, points, counts, tmp_path):
    import bpy

    curves = bpy.data.hair_curves.new("hair")
    curves.add_curves([int(c) for c in counts])
    curves.attributes["position"].data.foreach_set(
        "vector", np.asarray(points, dtype=np.float32).ravel())
    curves.surface = surface
    hair = bpy.data.objects.new("hair", curves)
    bpy.context.scene.collection.objects.link(hair)
    bpy.context.view_layer.objects.active = hair
    hair.hairsys.cache_path = str(tmp_path / "hair.mcap")
    # The maps are measured against hair sagging under gravity (and Sag-Free Rest is one
    # material only), so the groom is not made sag-free here.
    hair.hairsys.sag_free = False
    return hair


def test_a_vertex_group_at_a_root_is_the_blend_over_its_triangle_not_the_nearest_vertex(
        addon, tmp_path):
    """One quad (two triangles, 1 m wide) painted with a linear field at its corners: the goal
    weight at a root anywhere inside is the field there (barycentric blending of a linear field
    is exact). The nearest-vertex value the add-on used before is off by up to 0.4 at these
    roots, so the test tells the two apart."""
    import bpy

    from hairsys_blender.bake import evaluated_mesh
    from hairsys_blender.maps import strand_maps

    bpy.ops.wm.read_factory_settings(use_empty=True)
    corners = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
    quad = mesh_object("quad", corners, [(0, 1, 2, 3)])
    group = quad.vertex_groups.new(name="goal")
    for i, (x, y, _) in enumerate(corners):
        group.add([i], field(x, y), "REPLACE")
    rng = np.random.default_rng(3)
    roots = np.column_stack([rng.uniform(0.05, 0.95, (40, 2)), np.zeros(40)])
    points = np.concatenate([[r, r + (0, 0, 0.05)] for r in roots])
    counts = np.full(len(roots), 2)
    hair = hair_object(quad, points, counts, tmp_path)
    s = hair.hairsys
    s.weight_source, s.weight_name = "VERTEX_GROUP", "goal"
    verts, tris = evaluated_mesh(quad, bpy.context.evaluated_depsgraph_get(), triangles=True)
    maps = strand_maps(hair, s, verts, tris, points, counts)
    assert set(maps) == {"goal_weights"}
    want = np.repeat(field(roots[:, 0], roots[:, 1]), 2)
    np.testing.assert_allclose(maps["goal_weights"], want, atol=1e-6)
    nearest = np.array([field(*np.round(r[:2])) for r in roots])
    assert np.abs(nearest - want[::2]).max() > 0.2


def wall(tmp_path, cells=4, side=0.4, length=0.12):
    """A vertical wall (plane x = 0, `cells` × `cells` quads over y, z in [-side/2, side/2] and
    [1 - side/2, 1 + side/2]) with straight horizontal curves along +x rooted at points inside
    the cells of the rows y ∈ [-0.2, -0.1], [-0.1, 0] and [0.1, 0.2]: the cells of the row
    [0, 0.1] are left bare, so every root's cell has corners of one weight under `paint`.
    Returns the hair object, the wall, its rest points, the curve counts and each curve's root
    y."""
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, FRAMES
    step = side / cells
    verts = [(0.0, -side / 2 + i * step, 1 - side / 2 + j * step)
             for j in range(cells + 1) for i in range(cells + 1)]
    n = cells + 1
    faces = [(j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i)
             for j in range(cells) for i in range(cells)]
    body = mesh_object("wall", verts, faces)
    roots = []
    for yc in (-0.15, -0.05, 0.15):
        for zc in 1 - side / 2 + step * (np.arange(cells) + 0.5):
            for dy, dz in ((-0.02, -0.03), (0.03, 0.01)):
                roots.append((0.0, yc + dy, zc + dz))
    roots = np.array(roots)
    steps = np.linspace(0.0, length, N_POINTS)
    points = (roots[:, None, :] + steps[None, :, None] * np.array([1.0, 0, 0])).reshape(-1, 3)
    counts = np.full(len(roots), N_POINTS)
    hair = hair_object(body, points, counts, tmp_path)
    s = hair.hairsys
    s.surface_collision = False
    s.substeps = 200  # fixed: a map's stiffer strands must not change the others' substeps
    return hair, body, points, counts, roots[:, 1]


def paint(body, name, weight_of_y):
    """A vertex group `name` on every wall vertex, weighted by its y."""
    group = body.vertex_groups.new(name=name)
    for v in body.data.vertices:
        group.add([v.index], weight_of_y(v.co.y), "REPLACE")


def bake(hair, path):
    import bpy

    hair.hairsys.cache_path = str(path)
    assert bpy.ops.hairsys.bake() == {"FINISHED"}
    return read_mcap(path)[FRAMES]


@pytest.mark.parametrize("source", ["VERTEX_GROUP", "ATTRIBUTE"])
def test_a_painted_pin_holds_exactly_the_painted_strands(addon, tmp_path, source):
    """Strands rooted where the pin is painted (y > 0) keep their groom shape to the bit, as the
    roots do on the still wall; the others sag under gravity exactly as without the map."""
    hair, body, rest, counts, root_y = wall(tmp_path)
    painted = root_y > 0
    if source == "VERTEX_GROUP":
        paint(body, "pin", lambda y: 1.0 if y > 0.05 else 0.0)
    else:
        attr = hair.data.attributes.new("pin", "FLOAT", "CURVE")
        attr.data.foreach_set("value", painted.astype(np.float32))
    free = bake(hair, tmp_path / "free.mcap")
    hair.hairsys.pin_source, hair.hairsys.pin_name = source, "pin"
    pinned = bake(hair, tmp_path / "pinned.mcap")
    point_painted = np.repeat(painted, counts)
    np.testing.assert_allclose(pinned[point_painted], rest[point_painted], atol=1e-6)
    assert np.array_equal(pinned[~point_painted], free[~point_painted])
    sag = rest[:, 2] - free[:, 2]
    assert sag[point_painted].max() > 0.005, "free strands must sag for the test to test pins"


def test_a_painted_stiffness_group_softens_exactly_the_painted_strands(addon, tmp_path):
    """Bend stiffness × the group's weight: strands where it is 1 (y > 0) move exactly as without
    the map; where it is 0.1 they bend more under gravity."""
    hair, body, rest, counts, root_y = wall(tmp_path)
    full = root_y > 0
    paint(body, "stiffness", lambda y: 1.0 if y > 0.05 else 0.1)
    hair.hairsys.bend_stiffness = 2.0
    plain = bake(hair, tmp_path / "plain.mcap")
    hair.hairsys.stiffness_source = "VERTEX_GROUP"
    mapped = bake(hair, tmp_path / "mapped.mcap")
    point_full = np.repeat(full, counts)
    assert np.array_equal(mapped[point_full], plain[point_full])
    tips = np.cumsum(counts) - 1
    drop = lambda pos: rest[tips, 2] - pos[tips, 2]
    soft = ~full
    assert np.all(drop(mapped)[soft] > 1.5 * drop(plain)[soft]), (
        f"softened tips dropped {drop(mapped)[soft]} m, with the panel's stiffness "
        f"{drop(plain)[soft]} m")


def test_a_negative_stiffness_attribute_is_refused_naming_the_purpose(addon, tmp_path):
    import bpy

    hair, body, rest, counts, root_y = wall(tmp_path)
    attr = hair.data.attributes.new("stiffness", "FLOAT", "CURVE")
    attr.data.foreach_set("value", np.full(len(counts), -1.0, dtype=np.float32))
    hair.hairsys.stiffness_source = "ATTRIBUTE"
    with pytest.raises(RuntimeError, match="Stiffness: 'stiffness' has a value below 0"):
        bpy.ops.hairsys.bake()


def test_a_vertex_group_exported_to_usd_is_a_scene_map_source(addon, tmp_path):
    """Blender's own USD export writes a vertex group as `float[] primvars:NAME` (vertex): a
    scene on the exported scalp reads it with `[maps.length] primvar = NAME`, and each hair's
    length is the group's weight blended at its root (a linear field: exact)."""
    import bpy
    from pxr import Usd, UsdGeom

    import hairsys

    bpy.ops.wm.read_factory_settings(use_empty=True)
    cells, side, length = 4, 0.2, 0.05
    weight = lambda x, y: 0.3 + 1.5 * x + 1.5 * y
    n = cells + 1
    verts = [(side * i / cells, side * j / cells, 0.0) for j in range(n) for i in range(n)]
    faces = [(j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i)
             for j in range(cells) for i in range(cells)]
    scalp = mesh_object("scalp", verts, faces)
    group = scalp.vertex_groups.new(name="trim")
    for i, (x, y, _) in enumerate(verts):
        group.add([i], weight(x, y), "REPLACE")
    usd = tmp_path / "scalp.usda"
    assert bpy.ops.wm.usd_export(filepath=str(usd)) == {"FINISHED"}
    stage = Usd.Stage.Open(str(usd))
    (prim,) = [p for p in stage.Traverse() if p.IsA(UsdGeom.Mesh)]
    assert prim.GetAttribute("primvars:trim").GetMetadata("interpolation") == "vertex"
    scene = tmp_path / "scene.toml"
    scene.write_text(f"""
[scene]
frames = [1, 2]
[scalp.mesh]
kind = "usd"
path = "scalp.usda"
prim = "{prim.GetPath()}"
[hair]
count = 150
length = {length}
segments = 4
seed = 2
[maps.length]
primvar = "trim"
""")
    s = hairsys.Session.from_scene(scene)
    pos, off = np.array(s.positions), s.strand_offsets
    roots = pos[off[:-1]]
    lengths = np.array([np.linalg.norm(np.diff(pos[a:b], axis=0), axis=1).sum()
                        for a, b in zip(off[:-1], off[1:])])
    np.testing.assert_allclose(lengths, length * weight(roots[:, 0], roots[:, 1]), rtol=1e-4)


def lengths(pos, counts):
    """Each curve's polyline length (C,)."""
    ends = np.cumsum(counts)
    return np.array([np.linalg.norm(np.diff(pos[a - n:a], axis=0), axis=1).sum()
                     for a, n in zip(ends, counts)])


@pytest.mark.parametrize("purpose,source,factor", [
    ("stretch", "VERTEX_GROUP", 0.02),
    ("damping", "VERTEX_GROUP", 0.0),
    ("drag", "ATTRIBUTE", 20.0),  # vertex group weights are 0-1: a factor above 1 is an attribute
])
def test_a_painted_factor_changes_exactly_the_painted_strands(addon, tmp_path, purpose, source,
                                                              factor):
    """Stretch stiffness, stretch damping and air drag × the painted value: strands painted 1
    (y > 0) move exactly as without the map; the others by the physics of their factor. Softer
    stretch springs (× 0.02) let the sagging strands stretch; 20× the air drag slows their fall;
    without stretch damping their springs ring, so they move otherwise than damped ones."""
    hair, body, rest, counts, root_y = wall(tmp_path)
    hair.hairsys.stretch_stiffness = 40.0
    hair.hairsys.max_stretch = 1.0  # the strain limit would hide the softer springs' stretch
    ones = root_y > 0
    bake(hair, tmp_path / "plain.mcap")
    plain_frames = read_mcap(tmp_path / "plain.mcap")
    plain = plain_frames[FRAMES]
    if source == "VERTEX_GROUP":
        paint(body, purpose, lambda y: 1.0 if y > 0.05 else factor)
    else:
        attr = hair.data.attributes.new(purpose, "FLOAT", "CURVE")
        attr.data.foreach_set("value", np.where(ones, 1.0, factor).astype(np.float32))
    setattr(hair.hairsys, f"{purpose}_source", source)
    bake(hair, tmp_path / "mapped.mcap")
    mapped_frames = read_mcap(tmp_path / "mapped.mcap")
    mapped = mapped_frames[FRAMES]
    point_ones = np.repeat(ones, counts)
    for frame in range(1, FRAMES + 1):
        assert np.array_equal(mapped_frames[frame][point_ones], plain_frames[frame][point_ones])
    painted = ~ones
    tips = np.cumsum(counts) - 1
    drop = lambda pos: rest[tips, 2] - pos[tips, 2]
    if purpose == "stretch":
        stretched = lengths(mapped, counts)[painted] / lengths(plain, counts)[painted]
        assert np.all(stretched > 1.01), f"softened strands' lengths × {stretched}"
    elif purpose == "drag":
        # One frame after release the tips still fall from rest: free fall would drop
        # g t²/2 = 8.5 mm, at 40/s of drag g/k (t - (1 - exp(-k t))/k) = 5.2 mm.
        early_plain, early_mapped = drop(plain_frames[2]), drop(mapped_frames[2])
        assert np.all(early_mapped[painted] < 0.8 * early_plain[painted]), (
            f"dragged tips dropped {early_mapped[painted]} m, freely {early_plain[painted]} m")
    else:
        moved = np.abs(mapped[np.repeat(painted, counts)] - plain[np.repeat(painted, counts)])
        assert moved.max() > 1e-6, "undamped strands moved as damped ones"


@pytest.mark.parametrize("purpose,label", [("stretch", "Stretch"), ("damping", "Damping"),
                                           ("drag", "Drag")])
def test_a_negative_factor_attribute_is_refused_naming_the_purpose(addon, tmp_path, purpose,
                                                                   label):
    import bpy

    hair, body, rest, counts, root_y = wall(tmp_path)
    attr = hair.data.attributes.new(purpose, "FLOAT", "CURVE")
    attr.data.foreach_set("value", np.full(len(counts), -1.0, dtype=np.float32))
    setattr(hair.hairsys, f"{purpose}_source", "ATTRIBUTE")
    with pytest.raises(RuntimeError, match=f"{label}: '{purpose}' has a value below 0"):
        bpy.ops.hairsys.bake()
