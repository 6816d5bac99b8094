"""Fixtures of the hairsys Python tests (helpers in hairsys_testing.py)."""

import pytest

from hairsys_testing import sphere_groom


@pytest.fixture
def groom():
    """A UV sphere scalp and straight curves on it: (vertices, triangles, points, counts)."""
    return sphere_groom()
