"""Compares an assembled farm shot with single-machine exports, with Pixar's USD (usd-core).

usage: python_check_farm.py SHOT.usda PRIM=WHOLE.usdc:WHOLE_PRIM...
  e.g. /alice/hair=whole_alice.usdc:/hair /alice/scalp=whole_alice.usdc:/scalp

For every pair: the stitched prim (read through SHOT.usda, its references and value clips) and
the whole-range export's prim have the same type and the same authored attributes; each
attribute has the same time samples (the same list of time codes) and, at every one, the same
value bit for bit (float arrays compared as bytes); an attribute without time samples has the
same default value. The shot stage's time range and frame rate are the whole export's.
Exit codes: 0 same, 1 different (stderr says where), 3 pxr or numpy missing.
"""

import sys

try:
    import numpy as np
    from pxr import Usd
except ImportError as e:  # pragma: no cover
    print(f"cannot import pxr/numpy ({e}): pip install usd-core numpy", file=sys.stderr)
    sys.exit(3)


def fail(msg):
    print(msg, file=sys.stderr)
    sys.exit(1)


def as_bytes(value):
    """A value's bits: arrays as their bytes (with dtype and shape), anything else as repr."""
    if value is None:
        return None
    try:
        a = np.array(value)
    except Exception:  # noqa: BLE001 - tokens, strings, dictionaries
        return repr(value)
    if a.dtype.kind in "fiub":
        return (a.dtype.str, a.shape, a.tobytes())
    return repr(value)


shot_path = sys.argv[1]
shot = Usd.Stage.Open(shot_path)
if shot is None:
    fail(f"usd-core cannot open {shot_path}")
checked = 0
for pair in sys.argv[2:]:
    prim_path, whole = pair.split("=", 1)
    whole_file, whole_prim = whole.rsplit(":", 1)
    stage = Usd.Stage.Open(whole_file)
    if stage is None:
        fail(f"usd-core cannot open {whole_file}")
    if (shot.GetStartTimeCode(), shot.GetEndTimeCode()) != (
        stage.GetStartTimeCode(),
        stage.GetEndTimeCode(),
    ):
        fail(
            f"{shot_path}: time codes {shot.GetStartTimeCode()}-{shot.GetEndTimeCode()}, "
            f"{whole_file}: {stage.GetStartTimeCode()}-{stage.GetEndTimeCode()}"
        )
    if shot.GetTimeCodesPerSecond() != stage.GetTimeCodesPerSecond():
        fail(f"timeCodesPerSecond {shot.GetTimeCodesPerSecond()} != {stage.GetTimeCodesPerSecond()}")
    a, b = shot.GetPrimAtPath(prim_path), stage.GetPrimAtPath(whole_prim)
    if not a or not b:
        fail(f"missing prim: {prim_path} in {shot_path} ({bool(a)}) or {whole_prim} in {whole_file} ({bool(b)})")
    if a.GetTypeName() != b.GetTypeName():
        fail(f"{prim_path} is a {a.GetTypeName()}, {whole_prim} a {b.GetTypeName()}")
    names_a = sorted(x.GetName() for x in a.GetAttributes() if x.HasAuthoredValue())
    names_b = sorted(x.GetName() for x in b.GetAttributes() if x.HasAuthoredValue())
    if names_a != names_b:
        fail(f"{prim_path} attributes {names_a} != {whole_prim} attributes {names_b}")
    for name in names_b:
        x, y = a.GetAttribute(name), b.GetAttribute(name)
        times_x, times_y = list(x.GetTimeSamples()), list(y.GetTimeSamples())
        if times_x != times_y:
            fail(
                f"{prim_path}.{name}: time samples differ: {len(times_x)} vs {len(times_y)}; "
                f"first difference at "
                f"{next((s for s, t in zip(times_x, times_y) if s != t), None)}"
            )
        if not times_y:
            if as_bytes(x.Get()) != as_bytes(y.Get()):
                fail(f"{prim_path}.{name}: default values differ")
            checked += 1
            continue
        for t in times_y:
            if as_bytes(x.Get(Usd.TimeCode(t))) != as_bytes(y.Get(Usd.TimeCode(t))):
                fail(f"{prim_path}.{name} at time code {t}: values differ")
            checked += 1
print(f"{checked} values identical")
