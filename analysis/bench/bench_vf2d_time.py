#!/usr/bin/env python3
"""bench_vf2d_time.py — make bench: how long `brdfkit search --target vf2d
--objective max` takes from a cold start until its front holds a form of cost
<= 8 with max abs error <= 0.01 (issue 22), median over seeds; with a second
tool (the old build), both side by side, interleaved seed by seed.

Per seed: a run of the first tool at --evals 100000 (make results' budget)
finds E, the first fit (found_at in candidates.csv, the screening error) of
cost <= 8 and error <= 0.01; then, for each tool, cold runs of --evals E,
E*1.25, ... (the same seed gives the same first E fits, whatever the budget;
old and new give the same candidates) until the refitted front.csv has such a
row; that run's CPU time (user + sys of the tool, what the cores spend) and
wall time are the figures. A seed that never gets there within 100000 fits
counts as infinite (the median says so if most do).

usage: bench_vf2d_time.py TOOL [OLD_TOOL] [--seeds K] [--threads T]
"""
import csv
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

BUDGET = 100000 # make results' budget for vf2d (SEARCH_EVALS)
COST, ERR = 8.0, 0.01


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def run(tool, seed, evals, threads, out):
    cmd = [tool, "search", "--target", "vf2d", "--objective", "max", "--evals", str(evals),
           "--seed", str(seed), "--threads", str(threads), "--out", out]
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.monotonic() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    return cpu, wall


def first_fit(out):
    best = None
    for r in rows(os.path.join(out, "candidates.csv")):
        try:
            if float(r["cost"]) <= COST and float(r["error"]) <= ERR:
                k = int(r["found_at"])
                best = k if best is None else min(best, k)
        except (ValueError, KeyError):
            pass
    return best


def front_has(out):
    for r in rows(os.path.join(out, "front.csv")):
        if float(r["cost"]) <= COST and float(r["max_abs"]) <= ERR:
            return True
    return False


def probe(tool, seed, threads, scratch):
    out = os.path.join(scratch, "probe")
    run(tool, seed, BUDGET, threads, out)
    return first_fit(out)


def time_to_target(tool, seed, e, threads, scratch):
    out = os.path.join(scratch, "run")
    if e is None:
        return float("inf"), float("inf"), None
    while True:
        cpu, wall = run(tool, seed, e, threads, out)
        if front_has(out):
            return cpu, wall, e
        if e >= BUDGET:
            return float("inf"), float("inf"), None
        e = min(BUDGET, int(e * 1.25) + 1)


def main():
    args = sys.argv[1:]
    seeds, threads = 5, 2
    if "--seeds" in args:
        i = args.index("--seeds")
        seeds = int(args[i + 1])
        del args[i:i + 2]
    if "--threads" in args:
        i = args.index("--threads")
        threads = int(args[i + 1])
        del args[i:i + 2]
    tools = args[:2]
    names = ["new", "old"][:len(tools)]
    scratch = tempfile.mkdtemp(prefix="bench_vf2d_time.")
    res = {n: [] for n in names}
    try:
        for s in range(1, seeds + 1):
            e0 = probe(tools[0], s, threads, scratch)
            for n, t in zip(names, tools):
                cpu, wall, e = time_to_target(t, s, e0, threads, scratch)
                res[n].append((cpu, wall, e))
                print(f"  seed {s} {n}: {'never' if e is None else f'{e} fits'}, "
                      f"{cpu:.1f} CPU s, {wall:.1f} s wall", flush=True)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    print(f"bench_vf2d_time: vf2d --objective max, front max abs <= {ERR} at cost <= {COST}, cold start, "
          f"{threads} threads, median of {seeds} seeds")
    med = {}
    for n in names:
        cpu = statistics.median(r[0] for r in res[n])
        wall = statistics.median(r[1] for r in res[n])
        fits = [r[2] for r in res[n] if r[2] is not None]
        med[n] = cpu
        print(f"  {n}: {cpu:.1f} CPU s, {wall:.1f} s wall"
              f" (fits to get there: median {statistics.median(fits) if fits else 'never'})")
    if "old" in med:
        ratio = med["old"] / med["new"] if med["new"] > 0 else float("inf")
        print(f"  old/new CPU time: {ratio:.2f}x (target: >= 2x)")


if __name__ == "__main__":
    main()
