#!/usr/bin/env python3
"""How far the points of one or more runs are from a reference run, over the shot.

    scripts/cache_distance.py REFERENCE.mcap RUN.mcap [RUN.mcap ...] [--every 2]
        [--hairsys target/release/hairsys] [--points-per-strand N]

For every Nth cached frame (`--every`, from the caches' second frame), reads the positions of
every run and of the reference through `hairsys cache sample` and measures each point's
distance to the reference's same point. Prints per run: the RMS per frame (mean and worst
frame), the 99th and 99.9th percentiles and the largest distance over all point-frames (with
the frame, strand and point where it is, given --points-per-strand), and how many point-frames
are more than 5 mm and 10 mm off.

An RMS over all points hides a few strands that go their own way: on Sintel, BDF2 at 7
substeps per frame was 0.55 mm RMS from a converged run while 599 point-frames were more than
1 cm off (BENCHMARKS.md, session 27). The tail is what a viewer sees.

The caches must hold the same strands (same scene, same sim-hair count). Needs numpy.
"""

import argparse
import json
import subprocess
import sys

import numpy as np


def positions(hairsys, cache, frame, fps):
    """The cached positions at `frame` (an (n, 3) array, m)."""
    out = subprocess.run(
        [hairsys, "cache", "sample", cache, "--time", repr(frame / fps)],
        capture_output=True,
        check=True,
    ).stdout
    return np.asarray(json.loads(out)["positions"], dtype=np.float64)


def cache_frames(hairsys, cache):
    """First and last frame and fps of a cache (`hairsys cache info --json`)."""
    out = subprocess.run(
        [hairsys, "cache", "info", cache, "--json"], capture_output=True, check=True
    ).stdout
    info = json.loads(out)
    return info["first_frame"], info["last_frame"], info["fps"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("reference")
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--every", type=int, default=2, help="every Nth frame [2]")
    parser.add_argument("--hairsys", default="target/release/hairsys")
    parser.add_argument(
        "--points-per-strand", type=int, default=0, help="to name the strand of the worst point"
    )
    args = parser.parse_args()
    first, last, fps = cache_frames(args.hairsys, args.reference)
    frames = list(range(first + 1, last + 1, args.every))
    reference = {f: positions(args.hairsys, args.reference, f, fps) for f in frames}
    for run in args.runs:
        d = np.stack(
            [
                np.linalg.norm(positions(args.hairsys, run, f, fps) - reference[f], axis=1)
                for f in frames
            ]
        )
        rms = np.sqrt((d**2).mean(axis=1))
        k, i = np.unravel_index(np.argmax(d), d.shape)
        where = f"frame {frames[k]}, point {i}"
        if args.points_per_strand:
            per = args.points_per_strand
            where += f" (strand {i // per}, point {i % per})"
        print(
            f"{run}: RMS mean {1e3 * rms.mean():.2f} mm, worst frame {1e3 * rms.max():.2f} mm; "
            f"p99 {1e3 * np.quantile(d, 0.99):.2f} mm, p99.9 {1e3 * np.quantile(d, 0.999):.2f} mm, "
            f"max {1e3 * d.max():.1f} mm at {where}; "
            f"> 5 mm: {(d > 0.005).sum()}, > 10 mm: {(d > 0.01).sum()} of {d.size} point-frames"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
