#!/usr/bin/python3
"""Timing of 1000 accurate R_d spectra with colours (151 wavelengths, 400-700 nm) from Python
(spectral_skin, one array call) and from `skin batch` (one process), against 1000 single calls.
Best of --repeat runs: wall time, and the CPU time of all threads (user + system; for `skin
batch` the child process's), which a machine shared with other jobs inflates less than the wall
time. Usage (from a build tree):

    PYTHONPATH=build/python bench/python_timing.py --skin build/bin/skin
"""
import argparse
import os
import subprocess
import time

import numpy as np

import spectral_skin as ss


def cpu_seconds():
    """CPU time of this process's threads and of its finished children."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def best(f, repeat):
    """(wall, cpu) of the fastest of `repeat` runs."""
    runs = []
    for _ in range(repeat):
        w, c = time.perf_counter(), cpu_seconds()
        f()
        runs.append((time.perf_counter() - w, cpu_seconds() - c))
    return min(runs)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--skin", help="the skin executable (times `skin batch` too)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--solver", default="accurate")
    args = ap.parse_args()
    # 50 melanin x 20 hemoglobin values: pale to dark skin.
    melanin = np.linspace(0, 0.5, 50)[:, None]
    hemoglobin = np.linspace(0.001, 0.1, 20)[None, :]
    n = melanin.size * hemoglobin.size
    rows = []
    for threads in (1, 2):
        t = best(lambda: ss.spectrum(melanin=melanin, hemoglobin=hemoglobin, solver=args.solver,
                                     threads=threads), args.repeat)
        rows.append((f"Python spectrum(), arrays of {n} sets, {threads} thread(s)", t))
    flat_m = np.broadcast_to(melanin, (50, 20)).ravel()
    flat_h = np.broadcast_to(hemoglobin, (50, 20)).ravel()
    t = best(lambda: [ss.spectrum(melanin=m, hemoglobin=h, solver=args.solver, threads=1)
                      for m, h in zip(flat_m, flat_h)], 1)
    rows.append((f"Python spectrum(), {n} single calls, 1 thread", t))
    if args.skin:
        for threads in (1, 2):
            cmd = [args.skin, "batch", "--sweep", "melanin=0:0.5:50", "--sweep", "hemoglobin=0.001:0.1:20",
                   "--solver", args.solver, "--threads", str(threads), "-o", "/dev/null"]
            t = best(lambda: subprocess.run(cmd, check=True), args.repeat)
            rows.append((f"skin batch, {n} sets, {threads} thread(s) (whole process)", t))
    width = max(len(r[0]) for r in rows)
    print(f"{'':<{width}}  {'wall':>7}    {'CPU':>7}    {'CPU/set':>7}")
    for what, (wall, cpu) in rows:
        print(f"{what:<{width}}  {wall:7.3f} s  {cpu:7.3f} s  {1e3 * cpu / n:7.3f} ms")
    print("load average", " ".join(f"{x:.2f}" for x in os.getloadavg()), "cores", os.cpu_count())


if __name__ == "__main__":
    main()
