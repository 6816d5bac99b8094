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
    wall, inside = 0.0, 0.0
    while s.frame < 48:
        t = time.perf_counter()
        report = s.step()
        _ = s.positions  # what a host reads every frame (a view: no copy)
        wall += time.perf_counter() - t
        inside += report["step_ms"] * 1e-3
    s.finish_cache()
    # Python's own cost per frame: the call, argument and result handling, the view.
    return 1e3 * wall / 47, 1e3 * (wall - inside) / 47


def cli_run(binary, out):
    p = subprocess.run([binary, "simulate", str(REPO / "scenes/default.toml"), "--cache", str(out),
                        "--json"], check=True, capture_output=True, text=True)
    summary = json.loads(p.stdout.strip().splitlines()[-1])["summary"]
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
            per_frame, own = python_run(pathlib.Path(d) / f"py{i}.mcap")
            py.append(per_frame)
            print(f"run {i}: hairsys simulate {cli[-1]:.2f} ms/frame, Python {per_frame:.2f} "
                  f"ms/frame of which outside the library step {own * 1e3:.1f} µs "
                  f"({100 * own / per_frame:.3f} %)")
    mc, mp = sorted(cli)[len(cli) // 2], sorted(py)[len(py) // 2]
    print(f"median: simulate {mc:.2f} ms/frame, Python {mp:.2f} ms/frame "
          f"({100 * (mp - mc) / mc:+.1f} %, between processes: load noise included)")


if __name__ == "__main__":
    main()
