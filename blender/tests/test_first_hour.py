"""An artist's first hour with the extension, headless: install it as docs/blender.md says, bake,
edit the groom and bake again, bake an unsaved file, bake a still head with the defaults, put
the hair on the wrong mesh, render widths, and script a bake as the docs show."""

import os
import pathlib
import re
import shlex
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from test_addon import build_scene, read_mcap

REPO = pathlib.Path(__file__).resolve().parents[2]
DOCS = REPO / "docs" / "blender.md"


def still(scene, frames):
    """Stops the rig of `build_scene` (a still body) and bakes `frames` frames."""
    import bpy

    rig = bpy.data.objects["rig"]
    rig.animation_data_clear()
    rig.pose.bones["upper"].rotation_euler = (0, 0, 0)
    scene.frame_end = frames


def positions(hair):
    flat = np.empty(len(hair.data.points) * 3, dtype=np.float32)
    hair.data.attributes["position"].data.foreach_get("vector", flat)
    return flat.reshape(-1, 3)


def set_positions(hair, pts):
    hair.data.attributes["position"].data.foreach_set(
        "vector", np.asarray(pts, dtype=np.float32).ravel())
    hair.data.update_tag()


def the_wheel():
    """The hairsys wheel the tests run on (scripts/test.sh builds it into target/wheels)."""
    wheel = os.environ.get("HAIRSYS_WHEEL")
    if wheel:
        return pathlib.Path(wheel)
    found = sorted((REPO / "target" / "wheels").glob("hairsys-*-abi3-*.whl"))
    if not found:
        pytest.skip("no hairsys wheel in target/wheels (scripts/test.sh builds one)")
    return found[-1]


def run_blender(code, env):
    """Runs `code` in a new headless Blender session (this Python, bpy), returns stdout."""
    done = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], env=env,
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


def test_installing_as_the_readme_says_gives_the_panel_in_a_new_session(tmp_path):
    """README's build and install commands (docs/blender.md gives the same), run as given: the
    `blender --command extension …` arguments go to the handler Blender's `--command extension`
    calls, in headless Blender with its user resources in a temporary folder. A new Blender
    session then has the add-on enabled, its operators and its Physics panel."""
    line = r"^blender --command extension (install-file .*)$"
    install = re.search(line, (REPO / "README.md").read_text(), re.M)
    assert install, "README.md gives no `blender --command extension install-file` line"
    assert install.group(0) in DOCS.read_text(), "docs/blender.md installs otherwise"
    args = shlex.split(install.group(1))
    assert "-e" in args or "--enable" in args, "the install command does not enable the add-on"
    out = tmp_path / "zip"
    env = dict(os.environ, HAIRSYS_WHEEL=str(the_wheel()),
               BLENDER_USER_RESOURCES=str(tmp_path / "blender"))
    built = subprocess.run(["bash", str(REPO / "blender" / "build.sh"), str(out)], env=env,
                           capture_output=True, text=True, timeout=600)
    assert built.returncode == 0, built.stderr
    zips = list(out.glob("hairsys-*.zip"))
    assert len(zips) == 1
    args = [str(zips[0]) if a.endswith(".zip") else a for a in args]
    # A clean environment: the add-on's wheel comes from the extension, not from this venv.
    env["PYTHONNOUSERSITE"] = "1"
    run_blender(f"""
        import sys
        import bpy
        from bl_pkg import bl_extension_cli
        code = bl_extension_cli.cli_extension_handler({args!r})
        assert code == 0, code
        """, env)
    # The `blender` program reads the saved preferences when it starts; the bpy module starts
    # from the factory ones, so the new session reads them first.
    shown = run_blender("""
        import bpy
        import addon_utils
        bpy.ops.wm.read_userpref()
        print("enabled", addon_utils.check("bl_ext.user_default.hairsys")[1])
        print("bake", hasattr(bpy.ops.hairsys, "bake") and bpy.ops.hairsys.bake.idname())
        print("panel", bpy.types.HAIRSYS_PT_panel.bl_context)
        """, env)
    assert "enabled True" in shown, shown
    assert "bake HAIRSYS_OT_bake" in shown, shown
    assert "panel physics" in shown, shown
    # Blender installed the bundled wheel for the extension.
    assert list((tmp_path / "blender").rglob("site-packages/hairsys/__init__.py")), \
        "the extension's hairsys wheel was not installed"


@pytest.mark.parametrize("restore", [False, True])
def test_an_edit_after_a_bake_is_what_the_next_bake_simulates(addon, tmp_path, restore):
    """Bake, look at the frames (playback writes the cache's positions), then either go back to
    the first frame or Restore Groom, bend one curve sideways and bake again: the new bake starts
    from the edited curve (its first frame is the edit) and the untouched curves from the groom,
    instead of from the positions stored by the first bake."""
    import bpy

    scene, body, hair, rest, counts = build_scene(tmp_path)
    scene.frame_end = 4  # the body bends: the frames differ from the groom
    assert bpy.ops.hairsys.bake() == {"FINISHED"}
    scene.frame_set(3)
    assert not np.allclose(positions(hair), rest, atol=1e-6), "playback did not show frame 3"
    if restore:
        assert bpy.ops.hairsys.restore_groom() == {"FINISHED"}
        np.testing.assert_array_equal(positions(hair), rest)
        hair.hairsys.playback = True
    else:
        scene.frame_set(1)  # the first frame, as played back from the cache
        assert "hairsys_played" in hair.data
    edited = positions(hair).copy()
    n = int(counts[0])
    edited[1:n, 1] += 0.02 * np.arange(1, n) / (n - 1)  # the first curve bent 2 cm sideways
    set_positions(hair, edited)
    assert bpy.ops.hairsys.bake() == {"FINISHED"}
    first = read_mcap(hair.hairsys.cache_path)[1]
    np.testing.assert_allclose(first, edited, atol=1e-5)
    if restore:
        # The untouched curves are the groom, not the frame shown before Restore Groom.
        np.testing.assert_allclose(first[n:], rest[n:], atol=1e-5)


def test_an_unsaved_file_bakes_into_the_temporary_directory_and_says_where(
        addon, tmp_path, capfd):
    """A .blend never saved has no folder for `//hair.mcap`: the cache goes to Blender's
    temporary directory under hairsys/, the bake reports that path, and playback reads it."""
    import bpy

    scene, body, hair, rest, counts = build_scene(tmp_path)
    still(scene, 3)
    assert bpy.data.filepath == ""
    prefs = bpy.context.preferences.filepaths
    before = prefs.temporary_directory
    prefs.temporary_directory = str(tmp_path / "temp")
    try:
        hair.hairsys.cache_path = "//hair.mcap"
        capfd.readouterr()
        assert bpy.ops.hairsys.bake() == {"FINISHED"}
        expected = tmp_path / "temp" / "hairsys" / "hair.mcap"
        assert sorted(read_mcap(expected)) == [1, 2, 3]
        said = " ".join(capfd.readouterr())
        assert str(expected) in said and "not saved" in said, said
        scene.frame_set(3)
        np.testing.assert_allclose(positions(hair), read_mcap(expected)[3], atol=1e-6)
    finally:
        prefs.temporary_directory = before


def test_a_missing_cache_folder_is_created(addon, tmp_path):
    import bpy

    scene, body, hair, rest, counts = build_scene(tmp_path)
    still(scene, 2)
    hair.hairsys.cache_path = str(tmp_path / "shots" / "010" / "hair.mcap")
    assert bpy.ops.hairsys.bake() == {"FINISHED"}
    assert sorted(read_mcap(hair.hairsys.cache_path)) == [1, 2]


@pytest.mark.parametrize("groom", ["sticking-out", "combed-down"])
def test_the_defaults_hold_a_groom_on_a_still_head(addon, tmp_path, groom):
    """A still body, every setting at its default, one second: no tip moves more than 1 mm from
    the groom. Hair sticking straight out sideways is the hardest case for gravity (every
    segment is a lever); hair combed down rests 4 mm off the surface. (Measured: 0.1 µm and
    0.2 µm; with Sag-Free Rest off the same bakes move tips 83 mm and 1.0 mm.)"""
    import bpy

    from test_addon import comb_down

    scene, body, hair, rest, counts = build_scene(tmp_path)
    if groom == "combed-down":
        rest, counts = comb_down(hair, body)
    still(scene, 24)
    assert hair.hairsys.sag_free
    assert bpy.ops.hairsys.bake() == {"FINISHED"}
    tips = np.cumsum(counts) - 1
    motion = max(np.linalg.norm(pos[tips] - rest[tips], axis=1).max()
                 for pos in read_mcap(hair.hairsys.cache_path).values())
    assert motion <= 1e-3, f"a tip moved {motion * 1e3:.2f} mm on a still head"


def test_goal_stiffness_without_goal_weights_is_pointed_out(addon, tmp_path, capfd):
    import bpy

    scene, body, hair, rest, counts = build_scene(tmp_path)
    still(scene, 2)
    hair.hairsys.goal_stiffness = 5.0
    capfd.readouterr()
    assert bpy.ops.hairsys.bake() == {"FINISHED"}
    said = " ".join(capfd.readouterr())
    assert "Goal Stiffness" in said and "Goal Weights" in said, said


def test_hair_on_the_wrong_mesh_is_told_in_blenders_words(addon, tmp_path):
    """The Curves' Surface set to another mesh (a chair across the room): the message names the
    hair and the mesh, the panel where each is set and what to change, in the panel's words, not
    the Python module's argument names or export and import options."""
    import bpy

    scene, body, hair, rest, counts = build_scene(tmp_path)
    still(scene, 2)
    chair_mesh = bpy.data.meshes.new("chair")
    chair_mesh.from_pydata([(2, 0, 0), (3, 0, 0), (3, 1, 0), (2, 1, 0)], [], [(0, 1, 2, 3)])
    chair = bpy.data.objects.new("chair", chair_mesh)
    scene.collection.objects.link(chair)
    hair.data.surface = chair
    with pytest.raises(RuntimeError) as caught:
        bpy.ops.hairsys.bake()
    message = str(caught.value)
    for words in ("'hair'", "'chair'", "Surface", "Properties › Object Data",
                  "Max Snap Distance", "Properties › Physics › hairsys"):
        assert words in message, f"{words!r} missing from: {message}"
    python_words = re.findall(r"\b[a-z]+_[a-z_]+\b|\w+=|\bup_axis\b|\bscale\b", message)
    assert not python_words, f"Python API words {python_words} in: {message}"
    assert len(message) < 700, message


def test_renders_get_a_radius_tapered_from_root_to_tip(addon, tmp_path):
    """After a bake the curves carry a `radius` point attribute: half the Root Width at each
    root, half the Tip Width at each tip, linear in arc length between; changing a width
    rewrites it."""
    import bpy

    scene, body, hair, rest, counts = build_scene(tmp_path)
    still(scene, 2)
    s = hair.hairsys
    assert bpy.ops.hairsys.bake() == {"FINISHED"}

    def radius():
        attr = hair.data.attributes["radius"]
        assert attr.domain == "POINT"
        out = np.empty(len(attr.data), dtype=np.float32)
        attr.data.foreach_get("value", out)
        return out

    r = radius()
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    tips = np.cumsum(counts) - 1
    np.testing.assert_allclose(r[starts], s.root_width / 2, rtol=1e-6)
    np.testing.assert_allclose(r[tips], s.tip_width / 2, rtol=1e-6)
    # The straight curves of build_scene have evenly spaced points: the radius falls evenly.
    n = int(counts[0])
    expected = (s.root_width + (s.tip_width - s.root_width) * np.arange(n) / (n - 1)) / 2
    np.testing.assert_allclose(r[:n], expected, rtol=1e-5)
    s.tip_width = 0.0
    np.testing.assert_allclose(radius()[tips], 0.0, atol=1e-9)


def test_the_docs_scripting_example_bakes_every_frame_before_it_returns(addon, tmp_path):
    """The Scripting example of docs/blender.md, run as it is on an object named Hair with a
    `pin` vertex group: `bpy.ops.hairsys.bake()` (EXEC) returns with every frame baked, and
    frame_set then plays frame 12 back."""
    import bpy

    from hairsys_blender.playback import cache_file

    docs = DOCS.read_text()
    section = docs.split("## Scripting", 1)[1]
    example = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    assert "bpy.ops.hairsys.bake()" in example and "INVOKE_DEFAULT" not in example
    scene, body, hair, rest, counts = build_scene(tmp_path)
    still(scene, 12)
    hair.name = "Hair"
    body.vertex_groups.new(name="pin").add(list(range(len(body.data.vertices))), 1.0,
                                           "REPLACE")
    prefs = bpy.context.preferences.filepaths
    before = prefs.temporary_directory
    prefs.temporary_directory = str(tmp_path / "temp")
    try:
        exec(example, {})
        path, _ = cache_file(hair)
        frames = read_mcap(path)
        assert sorted(frames) == list(range(1, 13))
        np.testing.assert_allclose(positions(hair), frames[12], atol=1e-6)
    finally:
        prefs.temporary_directory = before


class Layout:
    """Stands in for a panel's layout headless: records what the panel draws."""

    def __init__(self):
        self.props, self.operators, self.labels = [], [], []

    def column(self, **_):
        return self

    row = column

    def separator(self, **_):
        pass

    def prop(self, data, name, **_):
        assert name in data.bl_rna.properties, f"the panel draws a missing setting {name!r}"
        self.props.append(name)

    def operator(self, idname, **_):
        module, name = idname.split(".")
        assert hasattr(getattr(__import__("bpy").types, f"{module.upper()}_OT_{name}"), "execute")
        self.operators.append(idname)

    def label(self, text="", **_):
        self.labels.append(text)


@pytest.mark.parametrize("children_type", ["NONE", "SIMPLE", "INTERPOLATED"])
def test_the_physics_panel_draws_existing_settings_and_the_goal_hint(
        addon, tmp_path, children_type):
    """The hairsys panel (Properties › Physics) draws only settings and operators that exist,
    shows the hint when Goal Stiffness has no Goal Weights, and the children settings when
    children are on."""
    import types

    import bpy

    scene, body, hair, rest, counts = build_scene(tmp_path)
    s = hair.hairsys
    s.children_type = children_type
    s.goal_stiffness = 5.0
    layout = Layout()
    panel = types.SimpleNamespace(layout=layout)
    context = types.SimpleNamespace(object=hair)
    bpy.types.HAIRSYS_PT_panel.draw(panel, context)
    assert {"cache_path", "sag_free", "root_width", "tip_width"} <= set(layout.props)
    assert any("Goal Weights" in t for t in layout.labels)
    assert ("child_render_amount" in layout.props) == (children_type != "NONE")
    assert ("hairsys.update_children" in layout.operators) == (children_type != "NONE")


def test_build_without_maturin_says_how_to_get_it(tmp_path):
    """blender/build.sh on a PATH without maturin stops before building and names the fix."""
    env = {k: v for k, v in os.environ.items() if k != "HAIRSYS_WHEEL"}
    env["PATH"] = "/usr/bin:/bin"
    done = subprocess.run(["bash", str(REPO / "blender" / "build.sh"), str(tmp_path)], env=env,
                          capture_output=True, text=True, timeout=60)
    assert done.returncode != 0
    assert "pip install maturin" in done.stderr, done.stderr
    assert not list(tmp_path.glob("*.zip"))
