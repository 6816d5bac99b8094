#!/usr/bin/env python3
"""Times a shot's farm job on this machine and prints BENCHMARKS.md's "A shot on a farm" tables.

1. **Export step.** One character of 1,000 strands × 9 points over 240 frames, exported as
   100,000 render children of 9 points per frame (`usd = "children"`, `subdivisions = 1`, no
   shutter; the whole export holds 5.2 GB of samples in memory, the default 4 subdivisions
   would take 19 GB): one `hairsys cache export
   --children` of the whole range, against the job's Export tasks (`hairsys farm export`, one
   process per chunk, run one after another) for chunks of 10, 30 and 120 frames. The
   contenders take turns round by round, in a rotated order, so a drift of the host's speed
   falls on all of them.
2. **Simulate-task overhead.** `hairsys farm simulate` of the same character over one frame
   (process start, shot and scene loading, the scene's build, the rest frame written), against
   the whole 240-frame task, a bare process start (`hairsys --version`), and the one-frame task
   of a larger scene (`--overhead-scene`, the shipped default scene: 4,000 strands on the
   built-in head).

Every chunked export is checked to write as many time samples as the whole export. Nothing is
asserted about speed; the figures go to stdout as Markdown, with the command, the host and the
date in the heading.

    cargo build --release -p hairsys-cli
    scripts/farm_bench.py --binary target/release/hairsys --rounds 3 > /tmp/farm_bench.md
"""

import argparse
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from datetime import datetime, timezone
from pathlib import Path

SCENE = """version = 1
[scene]
name = "farm bench"
frames = [1, {frames}]

[scalp.mesh]
kind = "uv-sphere"
radius = 0.1
segments = 32
rings = 16

[scalp.motion]
keys = [
    {{ frame = 1, rotation_deg = [0.0, 0.0, 0.0] }},
    {{ frame = {frames}, translation = [0.2, 0.0, 0.0], rotation_deg = [0.0, 0.0, 90.0] }},
]

[hair]
count = {strands}
length = 0.2
segments = 8
seed = 5

[children]
count = {children}
subdivisions = 1
"""

SHOT = """version = 1
[shot]
name = "farm_bench"
frames = [1, {last}]

[output]
usd = "children"

[[characters]]
name = "bench"
scene = "bench.toml"
"""


def run(cmd: list[str], cwd: Path) -> float:
    """Runs `cmd` in `cwd`; returns its wall time in seconds (exits on failure)."""
    return run_out(cmd, cwd)[0]


PEAK: list[int] = []


def run_out(cmd: list[str], cwd: Path) -> tuple[float, str]:
    """Runs `cmd` in `cwd` under `/usr/bin/time` (its peak resident memory, KiB, goes to
    `PEAK`); returns its wall time in seconds and its stdout (exits on failure)."""
    peak = cwd / "peak.txt"
    start = time.perf_counter()
    done = subprocess.run(["/usr/bin/time", "-f", "%M", "-o", str(peak)] + cmd, cwd=cwd,
                          capture_output=True, text=True)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed (exit {done.returncode}):\n{done.stderr}")
    PEAK.append(int(peak.read_text().split()[-1]))
    return seconds, done.stdout


def chunks(first: int, last: int, size: int) -> list[tuple[int, int]]:
    """Contiguous chunks of `size` frames (the last may be shorter)."""
    out, a = [], first
    while a <= last:
        b = min(a + size - 1, last)
        out.append((a, b))
        a = b + 1
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", default="target/release/hairsys")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--frames", type=int, default=240)
    ap.add_argument("--strands", type=int, default=1000)
    ap.add_argument("--children", type=int, default=100_000)
    ap.add_argument("--chunk-sizes", default="10,30,120")
    ap.add_argument("--overhead-scene", default=str(Path(__file__).resolve().parent.parent
                                                    / "scenes" / "default.toml"),
                    help="a second scene whose 1-frame Simulate task is timed (a larger build)")
    ap.add_argument("--keep", action="store_true", help="keep the scratch folder")
    args = ap.parse_args()
    binary = str(Path(args.binary).resolve())
    sizes = [int(s) for s in args.chunk_sizes.split(",")]
    scratch = Path(tempfile.mkdtemp(prefix="hairsys-farm-bench-"))
    last = args.frames
    (scratch / "bench.toml").write_text(
        SCENE.format(frames=last, strands=args.strands, children=args.children)
    )
    (scratch / "shot.toml").write_text(SHOT.format(last=last))
    (scratch / "one.toml").write_text(SHOT.format(last=1))
    other = Path(args.overhead_scene).resolve()
    (scratch / "other.toml").write_text(
        SHOT.format(last=1).replace('"bench.toml"', json.dumps(str(other))))

    # The character's cache, once: the Simulate task of the job.
    sim_full = run([binary, "farm", "simulate", "shot.toml", "--character", "bench",
                    "--out-dir", "out", "--quiet"], scratch)
    cache = scratch / "out" / "bench" / "bench.mcap"

    # Export step: contenders in turns.
    names = ["whole"] + [f"chunks of {n}" for n in sizes]
    times: dict[str, list[float]] = {n: [] for n in names}
    task_times: dict[str, list[float]] = {n: [] for n in names}
    peaks: dict[str, int] = {n: 0 for n in names}
    samples: dict[str, int] = {}
    for r in range(args.rounds):
        order = names[r % len(names):] + names[: r % len(names)]
        for name in order:
            if name == "whole":
                out = scratch / "whole.usdc"
                t, text = run_out([binary, "cache", "export", str(cache), "-o", str(out),
                                   "--children", "--json"], scratch)
                samples["whole"] = json.loads(text)["time_samples"]
                peaks[name] = max(peaks[name], PEAK[-1])
                out.unlink()
                times[name].append(t)
                task_times[name].append(t)
                continue
            size = int(name.split()[-1])
            total, written = 0.0, 0
            for a, b in chunks(1, last, size):
                t, text = run_out([binary, "farm", "export", "shot.toml", "--character", "bench",
                                   "--frames", f"{a}-{b}", "--out-dir", "out", "--json"], scratch)
                written += json.loads(text)["summary"]["time_samples"]
                total += t
                task_times[name].append(t)
                peaks[name] = max(peaks[name], PEAK[-1])
            samples[name] = written
            shutil.rmtree(scratch / "out" / "bench" / "chunks")
            times[name].append(total)
        print(f"round {r + 1}/{args.rounds} done", file=sys.stderr)

    if len(set(samples.values())) != 1:
        sys.exit(f"the contenders wrote different numbers of time samples: {samples}")

    # Simulate-task overhead.
    start_only, one_frame, other_frame = [], [], []
    for _ in range(max(3, args.rounds)):
        start_only.append(run([binary, "--version"], scratch))
        shutil.rmtree(scratch / "out1", ignore_errors=True)
        one_frame.append(run([binary, "farm", "simulate", "one.toml", "--character", "bench",
                              "--out-dir", "out1", "--quiet"], scratch))
        shutil.rmtree(scratch / "out2", ignore_errors=True)
        other_frame.append(run([binary, "farm", "simulate", "other.toml", "--character",
                                "bench", "--out-dir", "out2", "--quiet"], scratch))

    host = platform.node()
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo")
                if l.startswith("model name")), platform.processor())
    load = os.getloadavg()[0]
    when = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    cmd = (f"scripts/farm_bench.py --binary {args.binary} --rounds {args.rounds} "
           f"--frames {args.frames} --strands {args.strands} --children {args.children} "
           f"--chunk-sizes {args.chunk_sizes}")
    med = statistics.median
    whole = med(times["whole"])
    print(f"`{cmd}`, {when}, {cpu} ({os.cpu_count()} vCPU, host {host}), load average "
          f"{load:.1f} at the end; {args.rounds} rounds, contenders in turns, medians:\n")
    print(f"| Export step, {last} frames × {args.children:,} children | tasks | "
          "all tasks, one after another | against one whole export | one task (median) | "
          "longest task | peak memory of a task |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name in names:
        n_tasks = 1 if name == "whole" else len(chunks(1, last, int(name.split()[-1])))
        label = "one `cache export --children` of the whole range" if name == "whole" \
            else f"`farm export` tasks, {name} frames"
        print(f"| {label} | {n_tasks} | {med(times[name]):.2f} s | "
              f"{med(times[name]) / whole:.2f}× | {med(task_times[name]):.2f} s | "
              f"{max(task_times[name]):.2f} s | {peaks[name] / 2**20:.2f} GiB |")
    print()
    print("| Simulate task | wall time (median) |")
    print("|---|---:|")
    print(f"| process start alone (`hairsys --version`) | {med(start_only) * 1e3:.0f} ms |")
    print(f"| `farm simulate`, 1 frame (start, shot and scene load, build, rest frame) | "
          f"{med(one_frame) * 1e3:.0f} ms |")
    print(f"| `farm simulate`, {last} frames (once) | {sim_full:.2f} s |")
    print(f"| `farm simulate`, 1 frame of `{other.name}` ({other.parent.name}/) | "
          f"{med(other_frame) * 1e3:.0f} ms |")
    if not args.keep:
        shutil.rmtree(scratch)
    else:
        print(f"\nscratch kept in {scratch}", file=sys.stderr)


if __name__ == "__main__":
    main()
