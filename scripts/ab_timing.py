#!/usr/bin/env python3
"""Times two or more `hairsys` binaries on one scene, alternating them run by run.

This VM's speed drifts by 10-15 % over minutes (BENCHMARKS.md, session 25), so a before/after
comparison must interleave the binaries rather than run one and then the other. Each run is
`hairsys simulate --json --force` into a scratch cache; the medians of `ms_per_frame` and
`strands_ms_per_frame` are printed per binary.

    scripts/ab_timing.py --runs 5 --scene scenes/parity_collide.toml /tmp/before /tmp/after
"""

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path


def run_once(binary: str, scene: str, cache: Path) -> dict:
    """One `simulate --json` run; returns its summary (exits with the run's stderr on failure)."""
    done = subprocess.run(
        [binary, "simulate", "--json", "--force", "--cache", str(cache), scene],
        capture_output=True,
        text=True,
    )
    if done.returncode != 0:
        sys.exit(f"{binary} failed on {scene} (exit {done.returncode}):\n{done.stderr}")
    return json.loads(done.stdout.strip().splitlines()[-1])["summary"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("binaries", nargs="+", help="hairsys binaries to compare")
    parser.add_argument("--scene", required=True, help="scene file (TOML)")
    parser.add_argument("--runs", type=int, default=5, help="runs per binary (default 5)")
    args = parser.parse_args()
    times = {b: [] for b in args.binaries}
    with tempfile.TemporaryDirectory() as scratch:
        cache = Path(scratch) / "ab.mcap"
        for _ in range(args.runs):
            for binary in args.binaries:
                s = run_once(binary, args.scene, cache)
                times[binary].append((s["ms_per_frame"], s["strands_ms_per_frame"]))
    for binary, runs in times.items():
        total = statistics.median(r[0] for r in runs)
        strands = statistics.median(r[1] for r in runs)
        each = " ".join(f"{r[0]:.1f}" for r in runs)
        print(f"{binary}: median {total:.2f} ms/frame, strand phase {strands:.2f} ({each})")


if __name__ == "__main__":
    main()
