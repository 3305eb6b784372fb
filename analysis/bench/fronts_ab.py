#!/usr/bin/env python3
"""fronts_ab.py: is a change to the search better on make results' fronts, over seeds?

  python3 analysis/bench/fronts_ab.py OLD_BRDFKIT NEW_BRDFKIT [--seeds 1,2,3] [--jobs 2]
                                      [--max-cost 16] [--out DIR] [--csv FILE] [--dry-run]
                                      [--fronts vf2d,env_mix,...] [--old-tree DIR] [--new-tree DIR]

A search at a fixed budget is one draw: a change to generation, starts or
screening reorders what it tries, and one seed's front moves both ways
(results/search/moved). So a change is judged here on the seven double fronts
of make results at several seeds, old and new binaries side by side.

A front of make results is the last step of a pipeline (the Makefile's "Fronts
that hold"): a first double search, the half search seeded with its front, the
double front seeded with both (and, for env_mix and env_f0, with each other's
runs). The commands are the Makefile's own, one source of truth: `make -n` of
the seven fronts' targets with TOOL set to the binary prints every step once,
in order; here each step's paths (build/evolved/, build/half/,
results/search/) move under the run's directory, --gpu and --link-prefix are
dropped, and every search gets --seed S --threads 1 (the same bytes as any
thread count). One pipeline per binary and seed, its steps one after the
other; --jobs pipelines at a time. A pipeline already in DIR (default
/tmp/fronts_ab) is not rerun when its stamp (the SHA-256 of the binary and its
commands) matches, so a second call with more seeds or another NEW binary
reuses the old side; one whose stamp does not match is made again, and one
with no stamp stops the script (remove it or give another --out). --dry-run
prints the commands and runs nothing; --old-tree and --new-tree name the
checkout whose Makefile gives that side's commands, and in which its steps
run (default: the current directory for both), so that a binary from before
a change of options is judged on its own make results (a worktree of its
commit) rather than refusing the new commands; --fronts judges some of the seven
(their pipelines only, and what those read: env_mix's takes env_f0's first
searches) in a shorter run.

Printed, per front and seed: of the costs <= --max-cost at which either front
has a member, those where the new front's best error at cost <= c is better
(< 0.999x the old), worse (> 1.001x) or the same, and the geometric mean of
new/old over them; then the totals per front and overall. Read by column name
(name, cost, error) as fronts_moved.py reads them; the catalog's rows are left out.
Timings of each pipeline (wall and CPU seconds) are printed with it. --csv writes
the same tallies (search, seed, better, worse, same, gmean_new_over_old; seed "all"
for a front's seeds together) for fronts_moved.py --seeds.
"""
import argparse
import csv
import hashlib
import math
import os
import shlex
import shutil
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fronts_moved import SEARCHES, front, rows, upto, verdict  # noqa: E402


MOVED = (("build/evolved/", "evolved/"), ("build/half/", "half/"), ("results/search/", "results/"))


def pipeline(binary, tree, d, seed, fronts):
    """The steps of the fronts' pipelines, as make -n in tree prints them for
    this binary, their paths under d; each an argv list."""
    targets = ["results-search-%s" % n for n in fronts]
    text = subprocess.run(["make", "--no-print-directory", "-C", tree, "-n", "TOOL=" + binary] + targets,
                          capture_output=True, text=True, check=True).stdout
    steps = []
    for line in text.replace("\\\n", " ").splitlines():
        argv = shlex.split(line)
        if not argv or argv[0] != binary:
            continue  # mkdir -p and make's own lines: the directories are made below
        out, skip = [binary], 0
        for a in argv[1:]:
            if skip:
                skip = 0
                continue
            if a in ("--gpu", "--link-prefix", "--seed", "--threads"):
                skip = 1
                continue
            if a == ">/dev/null":
                continue
            for old, new in MOVED:
                if a.startswith(old):
                    a = os.path.join(d, new + a[len(old):])
            out.append(a)
        steps.append(out + ["--seed", str(seed), "--threads", "1"])
    if not steps:
        sys.exit("fronts_ab: make -n printed no search for %s" % binary)
    return steps


def digest(binary):
    h = hashlib.sha256()
    with open(binary, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def run(binary, tree, key, seed, d, dry, fronts):
    """key: the binary's digest; the stamp is it with the pipeline's steps."""
    steps = pipeline(binary, tree, d, seed, fronts)
    if dry:
        return seed, d, steps, None
    stamp = key + "\n" + "".join(" ".join(shlex.quote(x) for x in s[1:]) + "\n" for s in steps)
    stamp_path = d + ".stamp"
    done = all(os.path.exists(os.path.join(d, "results", n, "front.csv")) for n in fronts)
    have = None
    if os.path.exists(stamp_path):
        with open(stamp_path) as f:
            have = f.read()
    if os.path.exists(d):
        if have is None:
            sys.exit("fronts_ab: %s holds a run with no stamp (%s): which binary made it is unknown; "
                     "remove it or give another --out" % (d, stamp_path))
        if have == stamp and done:
            return seed, d, steps, None
        shutil.rmtree(d)  # a run this script made, by another binary or with other steps
    if have is not None:
        os.remove(stamp_path)
    for sub in ("evolved", "half", "results"):
        os.makedirs(os.path.join(d, sub), exist_ok=True)
    t0, cpu = time.time(), 0.0
    with open(d + ".log", "w") as log:
        for argv in steps:
            log.write("$ %s\n" % " ".join(shlex.quote(x) for x in argv))
            log.flush()
            p = subprocess.Popen(argv, stdout=log, stderr=log, cwd=tree)
            _, status, ru = os.wait4(p.pid, 0)  # this step's own CPU (os.times would add the other jobs')
            p.returncode = os.waitstatus_to_exitcode(status)
            cpu += ru.ru_utime + ru.ru_stime
            if p.returncode != 0:
                sys.exit("fronts_ab: %s failed (exit %d), see %s.log" % (" ".join(argv), p.returncode, d))
    with open(stamp_path, "w") as f:
        f.write(stamp)
    return seed, d, steps, (time.time() - t0, cpu)


def compare(old, new, max_cost):
    fo, fn = front(rows(open(old).read())), front(rows(open(new).read()))
    tally = {"better": 0, "worse": 0, "same": 0}
    logs = []
    for c in sorted(set(fo) | set(fn)):
        if c > max_cost:
            continue
        x, y = upto(fo, c), upto(fn, c)
        if x is None or y is None:
            continue
        tally[verdict(x, y)] += 1
        if x > 0 and y > 0:
            logs.append(math.log(y / x))
    return tally["better"], tally["worse"], tally["same"], logs


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--max-cost", type=float, default=16)
    ap.add_argument("--out", default="/tmp/fronts_ab")
    ap.add_argument("--csv")
    ap.add_argument("--dry-run", action="store_true")
    ap.add_argument("--fronts", default=",".join(SEARCHES))
    ap.add_argument("--old-tree", default=".")
    ap.add_argument("--new-tree", default=".")
    a = ap.parse_args()
    fronts = a.fronts.split(",")
    for n in fronts:
        if n not in SEARCHES:
            sys.exit("fronts_ab: --fronts: unknown front '%s' (known: %s)" % (n, ", ".join(SEARCHES)))
    seeds = [int(x) for x in a.seeds.split(",")]
    jobs = []
    trees = {"old": os.path.abspath(a.old_tree), "new": os.path.abspath(a.new_tree)}
    for side, binary in (("old", a.old), ("new", a.new)):
        binary, tree = os.path.abspath(binary), trees[side]
        key = digest(binary)
        for sd in seeds:
            d = os.path.join(os.path.abspath(a.out), side, "seed%d" % sd)
            os.makedirs(os.path.dirname(d), exist_ok=True)
            jobs.append((binary, tree, key, sd, d, a.dry_run, fronts))
    with ThreadPoolExecutor(max_workers=a.jobs) as ex:
        for sd, d, steps, t in ex.map(lambda j: run(*j), jobs):
            if a.dry_run:
                print("# %s (seed %d): %d steps" % (d, sd, len(steps)))
                for s in steps:
                    print(" ".join(shlex.quote(x) for x in s))
            elif t:
                print("ran %s (seed %d, %d steps): %.0f s wall, %.0f CPU-s" % (d, sd, len(steps), t[0], t[1]),
                      flush=True)
    if a.dry_run:
        return
    tb = tw = ts = 0
    alllogs = []
    table = []
    for n in fronts:
        line, nb, nw, ns, nl = "%-8s" % n, 0, 0, 0, []
        for sd in seeds:
            p = [os.path.join(a.out, side, "seed%d" % sd, "results", n, "front.csv") for side in ("old", "new")]
            b, w, s, logs = compare(p[0], p[1], a.max_cost)
            gm = math.exp(sum(logs) / len(logs)) if logs else float("nan")
            line += "  seed %d: +%d -%d =%d x%.3f" % (sd, b, w, s, gm)
            table.append((n, sd, b, w, s, gm))
            nb, nw, ns, nl = nb + b, nw + w, ns + s, nl + logs
        gm = math.exp(sum(nl) / len(nl)) if nl else float("nan")
        print("%s  | all: +%d -%d =%d x%.3f" % (line, nb, nw, ns, gm))
        table.append((n, "all", nb, nw, ns, gm))
        tb, tw, ts, alllogs = tb + nb, tw + nw, ts + ns, alllogs + nl
    gm = math.exp(sum(alllogs) / len(alllogs)) if alllogs else float("nan")
    print("total (costs <= %g, seeds %s): better %d, worse %d, same %d; geometric mean new/old x%.3f"
          % (a.max_cost, a.seeds, tb, tw, ts, gm))
    table.append(("all", "all", tb, tw, ts, gm))
    if a.csv:
        with open(a.csv, "w", newline="") as f:
            own = trees["old"] != trees["new"]
            f.write("# fronts_ab.py: make results' double fronts %s (each its whole pipeline%s), old %s against new %s, "
                    "seeds %s, cost levels <= %g; better/worse: the new front's best error at cost <= c below 0.999x / "
                    "above 1.001x the old's; gmean: of new/old over those levels\n"
                    % (" ".join(fronts), ", each side's as its own checkout's Makefile gives it" if own else "",
                       os.path.basename(a.old), os.path.basename(a.new), a.seeds, a.max_cost))
            w = csv.writer(f)
            w.writerow(["search", "seed", "better", "worse", "same", "gmean_new_over_old"])
            for r in table:
                w.writerow(list(r[:5]) + ["%.4f" % r[5]])


if __name__ == "__main__":
    main()
