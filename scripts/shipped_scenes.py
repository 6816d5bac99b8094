#!/usr/bin/env python3
"""The shipped scenes' cost and look, as BENCHMARKS.md's "Shipped scenes" tables.

Runs `hairsys simulate SCENE --json` for every shipped scene (or those named) with one binary,
or with two binaries alternated run by run (`--against OLD`), and prints Markdown tables:

- cost: integrator and why, substeps per collision step and collision steps per frame (counted,
  from the summary), ms per frame split into strand phase and contacts, microseconds per
  point-frame and that figure relative to the default scene's in the same run (the machine's
  speed moves between hours; the ratio does not);
- look (the run's quality report): deepest point inside a collider, point-frames inside
  (beyond the 0.1 mm tolerance), p99 and largest stretch, hairpins (points turning > 90°), p99
  velocity–position mismatch;
- with `--against`, each scene's ms per frame under both binaries and their ratio (best of the
  runs of each, taken alternately).

Usage:
    scripts/shipped_scenes.py [--bin target/release/hairsys] [--against OLD_BINARY]
                              [--runs 2] [--frames A-B] [SCENE ...]
"""

import argparse
import datetime
import json
import os
import platform
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = [
    "default",
    "wind_demo",
    "collision_demo",
    "gust",
    "character",
    "sintel",
    "parity_collide",
]


def run(binary, scene, frames, cache):
    """One `simulate --json` run; returns its summary."""
    cmd = [binary, "simulate", scene, "--json", "--force", "--cache", cache]
    if frames:
        cmd += ["--frames", frames]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    for line in reversed(out.splitlines()):
        event = json.loads(line)
        if event.get("event") == "done":
            return event["summary"]
    raise RuntimeError(f"{scene}: no summary in the output of {' '.join(cmd)}")


def cpu():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--bin", default=os.path.join(ROOT, "target/release/hairsys"))
    p.add_argument("--against", help="an older binary, alternated with --bin run by run")
    p.add_argument("--runs", type=int, default=2, help="runs per binary and scene (best kept)")
    p.add_argument("--frames", help="frame range FIRST-LAST instead of each scene's")
    p.add_argument("scenes", nargs="*", help=f"scene names (default: {' '.join(SCENES)})")
    args = p.parse_args()
    names = args.scenes or SCENES
    binaries = [args.bin] + ([args.against] if args.against else [])
    best = {}
    with tempfile.TemporaryDirectory(dir="/dev/shm" if os.path.isdir("/dev/shm") else None) as tmp:
        cache = os.path.join(tmp, "run.mcap")
        for name in names:
            scene = os.path.join(ROOT, "scenes", f"{name}.toml")
            for r in range(args.runs):
                # Alternate the binaries run by run, starting with a different one each round.
                order = binaries if r % 2 == 0 else list(reversed(binaries))
                for binary in order:
                    s = run(binary, scene, args.frames, cache)
                    print(f"{name} [{os.path.basename(binary)}] run {r + 1}: "
                          f"{s['ms_per_frame']:.1f} ms/frame", file=sys.stderr)
                    key = (name, binary)
                    if key not in best or s["ms_per_frame"] < best[key]["ms_per_frame"]:
                        best[key] = s

    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    cmd = "scripts/shipped_scenes.py " + " ".join(sys.argv[1:])
    print(f"`{cmd.strip()}`, {now}, {cpu()}, {os.cpu_count()} CPUs, best of {args.runs} runs.\n")
    base = best.get(("default", args.bin))
    base_us = base["ms_per_frame"] * 1e3 / base["points"] if base else None
    print("| scene | points | integrator | substeps/step × steps/frame | ms/frame | strands | "
          "contacts | µs per point-frame | ÷ default |")
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|")
    for name in names:
        s = best[(name, args.bin)]
        us = s["ms_per_frame"] * 1e3 / s["points"]
        rel = f"{us / base_us:.2f}" if base_us else "—"
        print(f"| {name} | {s['points']:,} | {s['integrator']} | {s['substeps']} × "
              f"{s['max_collision_steps']} | {s['ms_per_frame']:.1f} | "
              f"{s['strands_ms_per_frame']:.1f} | {s['contacts_ms_per_frame']:.1f} | {us:.2f} | "
              f"{rel} |")
    print()
    print("| scene | deepest inside (mm) | point-frames inside | p99 stretch | max stretch | "
          "hairpins | p99 velocity mismatch (m/s) |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name in names:
        q = best[(name, args.bin)]["quality"]["run"]
        pen, st = q["penetration"], q["strain"]["stretch"]
        print(f"| {name} | {pen['deepest'] * 1e3:.3f} | {pen['inside']} | "
              f"{st['p99'] * 100:.2f} % | {st['max'] * 100:.2f} % | {q['hairpins']['count']} | "
              f"{q['velocity_mismatch']['p99']:.3f} |")
    if args.against:
        print()
        print(f"| scene | {os.path.basename(args.against)} ms/frame (integrator, substeps) | "
              f"{os.path.basename(args.bin)} ms/frame (integrator, substeps) | speed-up |")
        print("|---|---|---|---:|")
        for name in names:
            old, new = best[(name, args.against)], best[(name, args.bin)]
            print(f"| {name} | {old['ms_per_frame']:.1f} ({old['integrator']}, "
                  f"{old['substeps']}) | {new['ms_per_frame']:.1f} ({new['integrator']}, "
                  f"{new['substeps']}) | {old['ms_per_frame'] / new['ms_per_frame']:.1f}× |")


if __name__ == "__main__":
    main()
