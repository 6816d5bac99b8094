"""Headless Blender (the `bpy` package) with the hairsys extension registered from the source
folder; the `hairsys` wheel must be installed in the same Python (see the notes' test commands)."""

import pathlib
import sys

import pytest

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # blender/ holds the hairsys_blender package


@pytest.fixture(scope="session")
def addon():
    import bpy  # noqa: F401  (bpy first: it sets up Blender's Python)
    import hairsys_blender

    hairsys_blender.register()
    yield hairsys_blender
    hairsys_blender.unregister()
