"""Shared helpers of the hairsys Python tests (imported by conftest.py and the tests).

The module under test is the installed `hairsys` wheel (see python.notes / the test script:
`maturin build --release -m python/Cargo.toml -o target/wheels` then `pip install` it).
"""

import os
import pathlib
import struct

import numpy as np
import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


def uv_sphere(radius=0.1, segments=16, rings=8):
    """A closed UV sphere: vertices (V, 3) float64, triangles (T, 3) int64 (outward winding)."""
    verts = [(0.0, 0.0, radius)]
    for r in range(1, rings):
        theta = np.pi * r / rings
        for s in range(segments):
            phi = 2 * np.pi * s / segments
            verts.append((radius * np.sin(theta) * np.cos(phi),
                          radius * np.sin(theta) * np.sin(phi),
                          radius * np.cos(theta)))
    verts.append((0.0, 0.0, -radius))
    tris = []
    for s in range(segments):
        tris.append((0, 1 + s, 1 + (s + 1) % segments))
    for r in range(rings - 2):
        a = 1 + r * segments
        b = a + segments
        for s in range(segments):
            s1 = (s + 1) % segments
            tris.append((a + s, b + s, b + s1))
            tris.append((a + s, b + s1, a + s1))
    south = len(verts) - 1
    last = 1 + (rings - 2) * segments
    for s in range(segments):
        tris.append((last + s, south, last + (s + 1) % segments))
    return np.array(verts), np.array(tris, dtype=np.int64)


def sphere_groom(points=5, length=0.08):
    """Straight curves along the normal at every upper-half vertex of `uv_sphere()`."""
    v, t = uv_sphere()
    roots = v[(v[:, 2] > 0.02) & (v[:, 2] < 0.099)]
    n = roots / np.linalg.norm(roots, axis=1, keepdims=True)
    steps = np.linspace(0.0, length, points)
    curves = roots[:, None, :] + n[:, None, :] * steps[None, :, None]
    counts = np.full(len(roots), points, dtype=np.int32)
    return v, t, curves.reshape(-1, 3), counts


def hairsys_binary():
    """The `hairsys` command: $HAIRSYS_BIN, else target/release or target/debug of the repo."""
    env = os.environ.get("HAIRSYS_BIN")
    if env:
        return env
    for kind in ("release", "debug"):
        p = REPO / "target" / kind / "hairsys"
        if p.exists():
            return str(p)
    pytest.fail("no hairsys binary: run `cargo build --release -p hairsys-cli` or set HAIRSYS_BIN")


def read_mcap_frames(path):
    """Frames of a hairsys cache decoded with the `mcap` package from the layout spec
    (hair-cache/src/layout.rs): {frame: (positions (P,3), velocities (P,3))}, and the metadata."""
    from mcap.reader import make_reader

    frames = {}
    with open(path, "rb") as f:
        reader = make_reader(f)
        meta = {}
        for m in reader.iter_metadata():
            if m.name == "hairsys":
                meta = dict(m.metadata)
        for schema, channel, message in reader.iter_messages(topics=["/hairsys/frames"]):
            assert channel.message_encoding == "hairsys.frame.v1"
            data = message.data
            version, frame = struct.unpack_from("<II", data, 0)
            (time,) = struct.unpack_from("<d", data, 8)
            (p,) = struct.unpack_from("<I", data, 16)
            assert version == 1 and len(data) == 20 + 24 * p
            pos = np.frombuffer(data, dtype="<f4", count=3 * p, offset=20).reshape(p, 3)
            vel = np.frombuffer(data, dtype="<f4", count=3 * p, offset=20 + 12 * p).reshape(p, 3)
            assert message.sequence == frame
            frames[frame] = (pos, vel)
    return frames, meta
