"""Python overhead per frame: the default scene stepped from Python (with its cache written, as
`hairsys simulate` does) against `hairsys simulate`'s own loop, alternating runs.

    target/pyenv/bin/python python/bench/overhead.py [--runs 3] [--bin target/release/hairsys]

Prints ms/frame of both per run and the overhead of the medians.
"""

import argparse
import json
import pathlib
import subprocess
import tempfile
import time

import hairsys

REPO = pathlib.Path(__file__).resolve().parents[2]


def python_run(out):
    s = hairsys.Session.from_scene(REPO / "scenes/default.toml")
    s.write_cache(out)
    t = time.perf_counter()
    n = 0
    while s.frame < 48:
        s.step()
        _ = s.positions  # what a host reads every frame (a view: no copy)
        n += 1
    elapsed = time.perf_counter() - t
    s.finish_cache()
    return 1e3 * elapsed / n


def cli_run(binary, out):
    p = subprocess.run([binary, "simulate", str(REPO / "scenes/default.toml"), "--cache", str(out),
                        "--json"], check=True, capture_output=True, text=True)
    summary = json.loads(p.stdout.strip().splitlines()[-1])
    # The run's solver time plus its cache-writing time per frame: the loop the Python run times.
    return summary["ms_per_frame"] + summary["cache_ms_per_frame"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--bin", default=str(REPO / "target/release/hairsys"))
    a = ap.parse_args()
    py, cli = [], []
    with tempfile.TemporaryDirectory() as d:
        for i in range(a.runs):
            cli.append(cli_run(a.bin, pathlib.Path(d) / f"cli{i}.mcap"))
            py.append(python_run(pathlib.Path(d) / f"py{i}.mcap"))
            print(f"run {i}: hairsys simulate {cli[-1]:.2f} ms/frame, Python {py[-1]:.2f} ms/frame")
    mc, mp = sorted(cli)[len(cli) // 2], sorted(py)[len(py) // 2]
    print(f"median: simulate {mc:.2f} ms/frame, Python {mp:.2f} ms/frame, "
          f"overhead {100 * (mp - mc) / mc:+.1f} %")


if __name__ == "__main__":
    main()
