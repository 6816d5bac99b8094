#!/usr/bin/env python3
"""Times two or more `hairsys` binaries on one scene, alternating them run by run.

This VM's speed drifts by 10-15 % over minutes and by up to 2x over an hour (BENCHMARKS.md,
sessions 25-26), so a before/after comparison must not run one binary and then the other.

- By default the binaries take turns, run by run, each with every core.
- With `--together` they run at the same time, one process per binary, the cores shared out
  between them (`--threads`, at least one each), so every pair of runs meets the same host.
  This compares per-thread speed, not the all-core figure the scenes' targets are stated in,
  and the processes compete for the memory bus as well as for the host: use it to tell
  whether a change helps when turns disagree, and the default mode for the figure itself.

Each run is `hairsys simulate --json --force` into a scratch cache; the medians of
`ms_per_frame`, `strands_ms_per_frame` and `contacts_ms_per_frame` are printed per binary.

    scripts/ab_timing.py --runs 5 --scene scenes/parity_collide.toml /tmp/before /tmp/after
    scripts/ab_timing.py --together --runs 5 --scene scenes/default.toml /tmp/before /tmp/after
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path


def command(binary: str, scene: str, cache: Path, threads: int | None) -> list[str]:
    """The `simulate --json` command line of one run."""
    cmd = [binary, "simulate", "--json", "--force", "--cache", str(cache)]
    if threads is not None:
        cmd += ["--threads", str(threads)]
    return cmd + [scene]


def summary(binary: str, scene: str, done: subprocess.CompletedProcess) -> dict:
    """The summary of a finished run (exits with the run's stderr on failure)."""
    if done.returncode != 0:
        sys.exit(f"{binary} failed on {scene} (exit {done.returncode}):\n{done.stderr}")
    return json.loads(done.stdout.strip().splitlines()[-1])["summary"]


def run_turns(binaries: list[str], scene: str, scratch: Path) -> list[dict]:
    """One run of each binary in turn, every core each."""
    cache = scratch / "ab.mcap"
    results = []
    for b in binaries:
        done = subprocess.run(command(b, scene, cache, None), capture_output=True, text=True)
        results.append(summary(b, scene, done))
    return results


def run_together(binaries: list[str], scene: str, scratch: Path) -> list[dict]:
    """One run of every binary at the same time, the cores shared out between them."""
    threads = max(1, (os.cpu_count() or 1) // len(binaries))
    running = [
        subprocess.Popen(
            command(b, scene, scratch / f"ab{k}.mcap", threads),
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for k, b in enumerate(binaries)
    ]
    # Every run finishes before any is judged, so a failure leaves no process writing into the
    # scratch directory that is about to go.
    outputs = [p.communicate() for p in running]
    done = [
        subprocess.CompletedProcess(p.args, p.returncode, out, err)
        for p, (out, err) in zip(running, outputs)
    ]
    return [summary(b, scene, d) for b, d in zip(binaries, done)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("binaries", nargs="+", help="hairsys binaries to compare")
    parser.add_argument("--scene", required=True, help="scene file (TOML)")
    parser.add_argument("--runs", type=int, default=5, help="runs per binary (default 5)")
    parser.add_argument(
        "--together",
        action="store_true",
        help="run the binaries at the same time, sharing the cores (see the module docs)",
    )
    args = parser.parse_args()
    times = {b: [] for b in args.binaries}
    run = run_together if args.together else run_turns
    with tempfile.TemporaryDirectory() as scratch:
        for _ in range(args.runs):
            for binary, s in zip(args.binaries, run(args.binaries, args.scene, Path(scratch))):
                times[binary].append(
                    (s["ms_per_frame"], s["strands_ms_per_frame"], s["contacts_ms_per_frame"])
                )
    for binary, runs in times.items():
        total = statistics.median(r[0] for r in runs)
        strands = statistics.median(r[1] for r in runs)
        contacts = statistics.median(r[2] for r in runs)
        each = " ".join(f"{r[0]:.1f}" for r in runs)
        print(
            f"{binary}: median {total:.2f} ms/frame, strand phase {strands:.2f}, "
            f"contacts {contacts:.2f} ({each})"
        )


if __name__ == "__main__":
    main()
