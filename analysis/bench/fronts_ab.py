#!/usr/bin/env python3
"""fronts_ab.py: is a change to the search better on make results' fronts, over seeds?

  python3 analysis/bench/fronts_ab.py OLD_BRDFKIT NEW_BRDFKIT [--seeds 1,2,3] [--jobs 2]
                                      [--max-cost 16] [--out DIR] [--csv FILE]

A search at a fixed budget is one draw: a change to generation, starts or
screening reorders what it tries, and one seed's front moves both ways
(results/search/moved). So a change is judged here on the seven double searches
of make results at several seeds, old and new binaries side by side.

Each search's command is read from the "# command:" line of its committed
results/search/NAME/front.csv (one source of truth: the Makefile's budgets as
last run), less --gpu, --out and --link-prefix, plus --seed S --threads 1 and
an --out under DIR (default /tmp/fronts_ab); --jobs commands run at a time.
A run already in DIR (its front.csv there) is not rerun when its stamp (DIR's
NAME.stamp: the SHA-256 of the binary that made it and its arguments) matches,
so a second call with more seeds or another NEW binary reuses the old side; a
run whose stamp does not match (another binary at the same path: a rebuilt
build/brdfkit, or a DIR left by an earlier session) is made again, and a run
with no stamp at all stops the script (remove it or give another --out).

Printed, per search and seed: of the costs <= --max-cost at which either front
has a member, those where the new front's best error at cost <= c is better
(< 0.999x the old), worse (> 1.001x) or the same, and the geometric mean of
new/old over them; then the totals per search and overall. Read by column name
(name, cost, error) as fronts_moved.py reads them; the catalog's rows are left out.
Timings of each run (wall and CPU seconds) are printed with it. --csv writes the
same tallies (search, seed, better, worse, same, gmean_new_over_old; seed "all"
for a search's seeds together) for fronts_moved.py --seeds.
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


def command(name):
    with open("results/search/%s/front.csv" % name) as f:
        for line in f:
            if line.startswith("# command: "):
                argv = shlex.split(line[len("# command: "):])
                break
        else:
            sys.exit("fronts_ab: results/search/%s/front.csv: no '# command:' line" % name)
    out, skip = [], 0
    for a in argv[1:]:  # argv[0] is the binary's name
        if skip:
            skip = 0
            continue
        if a in ("--gpu", "--out", "--link-prefix", "--seed", "--threads"):
            skip = 1
            continue
        out.append(a)
    return out


def digest(binary):
    h = hashlib.sha256()
    with open(binary, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def run(binary, key, name, seed, d):
    """key: the binary's digest; the stamp is it with the arguments."""
    path = os.path.join(d, "front.csv")
    argv = [binary] + command(name) + ["--seed", str(seed), "--threads", "1", "--out", d]
    stamp = key + " " + " ".join(shlex.quote(x) for x in argv[1:]) + "\n"
    stamp_path = d + ".stamp"
    have = None
    if os.path.exists(stamp_path):
        with open(stamp_path) as f:
            have = f.read()
    if os.path.exists(d):
        if have is None:
            sys.exit("fronts_ab: %s holds a run with no stamp (%s): which binary made it is unknown; "
                     "remove it or give another --out" % (d, stamp_path))
        if have == stamp and os.path.exists(path):
            return name, seed, None
        shutil.rmtree(d)  # a run this script made, by another binary or with other arguments
    if have is not None:
        os.remove(stamp_path)
    t0, r0 = time.time(), os.times()
    with open(d + ".log", "w") as log:
        rc = subprocess.call(argv, stdout=log, stderr=log)
    r1 = os.times()
    if rc != 0:
        sys.exit("fronts_ab: %s failed (exit %d), see %s.log" % (" ".join(argv), rc, d))
    with open(stamp_path, "w") as f:
        f.write(stamp)
    return name, seed, (time.time() - t0, r1.children_user - r0.children_user)


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
    a = ap.parse_args()
    seeds = [int(x) for x in a.seeds.split(",")]
    jobs = []
    for side, binary in (("old", a.old), ("new", a.new)):
        key = digest(binary)
        for sd in seeds:
            for n in SEARCHES:
                d = os.path.join(a.out, side, "seed%d" % sd, n)
                os.makedirs(os.path.dirname(d), exist_ok=True)
                jobs.append((binary, key, n, sd, d))
    with ThreadPoolExecutor(max_workers=a.jobs) as ex:
        for n, sd, t in ex.map(lambda j: run(*j), jobs):
            if t:
                print("ran %-8s seed %d: %.0f s wall, %.0f CPU-s" % (n, sd, t[0], t[1]), flush=True)
    tb = tw = ts = 0
    alllogs = []
    table = []
    for n in SEARCHES:
        line, nb, nw, ns, nl = "%-8s" % n, 0, 0, 0, []
        for sd in seeds:
            p = [os.path.join(a.out, side, "seed%d" % sd, n, "front.csv") for side in ("old", "new")]
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
            f.write("# fronts_ab.py: make results' seven double searches, old %s against new %s, seeds %s, "
                    "cost levels <= %g; better/worse: the new front's best error at cost <= c below 0.999x / "
                    "above 1.001x the old's; gmean: of new/old over those levels\n"
                    % (os.path.basename(a.old), os.path.basename(a.new), a.seeds, a.max_cost))
            w = csv.writer(f)
            w.writerow(["search", "seed", "better", "worse", "same", "gmean_new_over_old"])
            for r in table:
                w.writerow(list(r[:5]) + ["%.4f" % r[5]])


if __name__ == "__main__":
    main()
