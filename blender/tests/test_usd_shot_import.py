"""A whole run exported by `hairsys cache export` imports into Blender (bpy 5.0.1, headless)
as an animated Curves object whose evaluated positions at frames 1, 12 and 24 are the cache's,
bit for bit, with the scalp as a mesh beside it."""

import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "python" / "tests"))

from usd_shot import hairsys, small_run  # noqa: E402


def test_exported_shot_imports_as_animated_curves_at_the_caches_positions(tmp_path):
    import bpy

    _, frames = small_run(tmp_path)
    hairsys("cache", "export", "c.mcap", "-o", "shot.usdc", cwd=tmp_path)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    assert bpy.ops.wm.usd_import(filepath=str(tmp_path / "shot.usdc")) == {"FINISHED"}
    hair = bpy.data.objects["hair"]
    assert hair.type == "CURVES"
    assert bpy.data.objects["scalp"].type == "MESH"
    assert len(hair.data.curves) == len(frames[1][0]) // 17
    scene = bpy.context.scene
    assert (scene.frame_start, scene.frame_end, scene.render.fps) == (1, 24, 24)
    for f in (1, 12, 24):
        scene.frame_set(f)
        evaluated = hair.evaluated_get(bpy.context.evaluated_depsgraph_get())
        position = evaluated.data.attributes["position"]
        got = np.empty(3 * len(position.data), dtype=np.float32)
        position.data.foreach_get("vector", got)
        assert np.array_equal(got.reshape(-1, 3), frames[f][0]), f"frame {f}"
