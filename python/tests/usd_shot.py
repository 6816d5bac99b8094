"""Helpers of the whole-run USD export tests (test_usd_export.py, and Blender's
blender/tests/test_usd_shot_import.py): a small cached run of the default scene made with the
`hairsys` command, and the cache's frames decoded independently of hairsys (the `mcap`
package and the layout spec)."""

import subprocess

from hairsys_testing import hairsys_binary, read_mcap_frames

# The default scene (its head turn keyed on the scalp) with 120 strands over frames 1-24: a
# few seconds to simulate, and the scalp moves, so /scalp must be animated.
STRANDS = 120
FRAMES = (1, 24)


def hairsys(*args, cwd):
    """Runs the hairsys command in `cwd`; its stdout, or a test failure with its stderr."""
    out = subprocess.run([hairsys_binary(), *map(str, args)], cwd=cwd, capture_output=True,
                         text=True)
    assert out.returncode == 0, f"hairsys {' '.join(map(str, args))}: {out.stderr}"
    return out.stdout


def small_run(directory):
    """Simulates the small default-scene run into `directory`/c.mcap; returns its path and
    its frames {frame: (positions (P,3), velocities (P,3))} as the cache stores them."""
    scene = hairsys("scene", "init", cwd=directory)
    lines = []
    for line in scene.splitlines():
        if line.startswith("count = 4000 "):
            line = f"count = {STRANDS}"
        elif line.startswith("frames = [1, 48]"):
            line = f"frames = [{FRAMES[0]}, {FRAMES[1]}]"
        lines.append(line)
    (directory / "small.toml").write_text("\n".join(lines) + "\n")
    hairsys("simulate", "small.toml", "--cache", "c.mcap", "--quiet", cwd=directory)
    frames, _ = read_mcap_frames(directory / "c.mcap")
    assert sorted(frames) == list(range(FRAMES[0], FRAMES[1] + 1))
    assert len(frames[FRAMES[0]][0]) == STRANDS * 17
    return directory / "c.mcap", frames
