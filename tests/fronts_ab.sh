#!/bin/sh
# fronts_ab.sh — analysis/bench/fronts_ab.py runs each of make results' seven
# double fronts as make results makes it (issue 38: the four-step pipeline,
# first search, half search, merged front), not the last step alone. From
# its --dry-run: every front has a step that writes it; every --start-front
# a step reads is a front an earlier step wrote (no step reads what the
# pipeline did not make, none runs before what it reads; --start-forms
# likewise: vf's reads vf2d's front); every step has the
# seed and one thread, and no --gpu or --link-prefix; and each front's last
# step is, its paths aside, the command the committed
# results/search/NAME/front.csv says made it (the Makefile and the results
# agree). Controls: the same checks catch a pipeline with its half search
# left out, one with vf's step (it reads vf2d's front) run first, and one with
# a step's argument changed.
# usage: sh tests/fronts_ab.sh path/to/brdfkit   (from the repository root)
set -u
BK=${1:?usage: fronts_ab.sh path/to/brdfkit}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
cd "$ROOT" || exit 1
T=$(mktemp -d /tmp/bk_fronts_ab_XXXXXX)
trap 'rm -rf "$T"' EXIT
python3 analysis/bench/fronts_ab.py "$BK" "$BK" --seeds 3 --dry-run --out "$T/ab" >"$T/steps.txt" 2>"$T/err.txt" || {
	echo "FAIL: fronts_ab.py --dry-run: $(head -3 "$T/err.txt")"
	exit 1
}
python3 - "$T/steps.txt" "$T/ab" <<'EOF'
import os, shlex, sys
sys.path.insert(0, "analysis/bench")
from fronts_moved import SEARCHES

def pipelines(path):
    """{directory: [argv, ...]} from the dry run's listing."""
    out, cur = {}, None
    for line in open(path):
        if line.startswith("# "):
            cur = line.split()[1]
            out[cur] = []
        elif line.strip():
            out[cur].append(shlex.split(line))
    return out

def opt(argv, name):
    return [argv[i + 1] for i, a in enumerate(argv) if a == name and i + 1 < len(argv)]

def committed(name):
    for line in open("results/search/%s/front.csv" % name):
        if line.startswith("# command: "):
            return shlex.split(line[len("# command: "):])
    return None

def bare(argv):
    """The arguments less paths, seed, threads, --gpu and --link-prefix."""
    out, skip = [], 0
    for a in argv[1:]:
        if skip:
            skip = 0
            continue
        if a in ("--out", "--start-front", "--start-forms", "--gpu", "--link-prefix", "--seed", "--threads"):
            skip = 1
            continue
        out.append(a)
    return out

def faults(d, steps):
    f = []
    made = set()
    for argv in steps:
        for sf in opt(argv, "--start-front") + opt(argv, "--start-forms"):
            if os.path.dirname(sf) not in made:
                f.append("a step reads %s before any step made it" % sf)
            if not sf.startswith(d + "/"):
                f.append("a step reads %s, outside its pipeline" % sf)
        if opt(argv, "--seed") != ["3"] or opt(argv, "--threads") != ["1"]:
            f.append("a step without --seed 3 --threads 1")
        if "--gpu" in argv or "--link-prefix" in argv:
            f.append("a step kept --gpu or --link-prefix")
        made.update(opt(argv, "--out"))
    for n in SEARCHES:
        mine = [a for a in steps if opt(a, "--out") == [os.path.join(d, "results", n)]]
        if len(mine) != 1:
            f.append("%s: %d steps write its front" % (n, len(mine)))
            continue
        want = committed(n)
        if want is None or bare(mine[0]) != bare(want):
            f.append("%s: the last step is not the committed front's command" % n)
        for o in ("--start-front", "--start-forms"):
            if len(opt(mine[0], o)) != len(opt(want or [], o)):
                f.append("%s: it reads %d fronts by %s, the committed run %d" % (n, len(opt(mine[0], o)), o,
                                                                                len(opt(want or [], o))))
    return f

p = pipelines(sys.argv[1])
ok = bad = 0
for side in ("old", "new"):
    d = os.path.join(sys.argv[2], side, "seed3")
    if d not in p:
        print("FAIL: no pipeline for %s" % d); bad += 1; continue
    f = faults(d, p[d])
    if f:
        print("FAIL: %s: %s" % (d, "; ".join(f[:4]))); bad += 1
    else:
        ok += 1
    # controls: the half searches left out; one step's budget changed
    steps = p[d]
    no_half = [a for a in steps if "--precision" not in a or opt(a, "--out")[0].find("/results/") >= 0]
    if len(no_half) < len(steps) and faults(d, no_half):
        ok += 1
    else:
        print("FAIL: control: a pipeline without its half searches passes"); bad += 1
    # and vf's step, which reads vf2d's front by --start-forms, run first
    vf = [a for a in steps if opt(a, "--out") == [os.path.join(d, "results", "vf")]]
    early = vf + [a for a in steps if a not in vf]
    sf = opt(vf[0], "--start-forms") if vf else []
    if sf and any(sf[0] in x for x in faults(d, early)):
        ok += 1
    else:
        print("FAIL: control: a step reading --start-forms before its front is made passes"); bad += 1
    changed = [list(a) for a in steps]
    last = [a for a in changed if opt(a, "--out") == [os.path.join(d, "results", "f_gold")]][0]
    last[last.index("--evals") + 1] = "7"
    if faults(d, changed):
        ok += 1
    else:
        print("FAIL: control: a changed budget passes"); bad += 1
print("fronts_ab: %d passed, %d failed" % (ok, bad))
sys.exit(1 if bad else 0)
EOF
rc=$?
# --old-tree: the old side's commands are its own checkout's make results (a
# binary from before a change of options runs the pipeline it was made
# with), the new side's this tree's. A stand-in checkout whose one recipe
# asks for 17 fits; the control is the same run without --old-tree.
mkdir -p "$T/tree"
printf 'results-search-vf2d:\n\t$(TOOL) search --target vf2d --evals 17 --out results/search/vf2d\n' >"$T/tree/Makefile"
dry() { python3 analysis/bench/fronts_ab.py "$BK" "$BK" --seeds 3 --fronts vf2d --dry-run --out "$T/ab2" "$@"; }
side() { awk -v d="# $T/ab2/$1/seed3 " 'index($0, "# ") == 1 { on = index($0, d) == 1; next } on' "$2"; }
dry --old-tree "$T/tree" >"$T/both.txt"
dry >"$T/ctl.txt"
old=$(side old "$T/both.txt")
new=$(side new "$T/both.txt")
ctl=$(side old "$T/ctl.txt")
BKA=$(cd "$(dirname "$BK")" && pwd)/$(basename "$BK")
want="$BKA search --target vf2d --evals 17 --out $T/ab2/old/seed3/results/vf2d --seed 3 --threads 1"
if [ "$old" = "$want" ] && [ -n "$new" ] && [ "$new" = "${new#*--evals 17 }" ] && [ "$ctl" != "$want" ]; then
	echo "fronts_ab: --old-tree: the old side ran its own checkout's recipe (1 passed)"
else
	echo "FAIL: --old-tree: old side [$old], new side [$(echo "$new" | head -1)], without it [$(echo "$ctl" | head -1)]"
	rc=1
fi
exit $rc
