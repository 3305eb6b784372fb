#!/bin/sh
# cli_prune.sh — dead branches removed after the front's refit (issue 40
# item 4, analysis/search_front.c's prune_member, fit/search/prune.h): a
# search of the planted target max(1.5, 2 LoH) on LoH in [0.3, 1], seeded
# with max(p0, max(1.5, p1*LoH)), screens forms whose outer max(p, ...) never
# takes p at the fitted constants; its front holds no such max, and the member
# that had one is there without it, as accurate (a rmse below 1e-12: the
# target itself). The control: catalog.csv's rows are not pruned (a published
# form is shown as published), so the seed's refit row still holds the dead
# max the front's check looks for: the check can see one.
# The logic itself is tested on planted samples in tests/test_prune.c.
# usage: sh tests/cli_prune.sh path/to/brdfkit   (from the repository root)
set -u
BK=${1:?usage: sh tests/cli_prune.sh path/to/brdfkit}
T=$(mktemp -d /tmp/bk_cli_prune_XXXXXX)
trap 'rm -rf "$T"' EXIT
CSVGET=${CSVGET:-build/csvget}
. tests/lib.sh
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }

if ! "$BK" search --target form --target-form 'max(1.5, 2*LoH)' --domain LoH=0.3:1 \
	--start 'max(p0, max(1.5, p1*LoH))' --evals 30 --enum-max 10 --threads 1 --quiet --out "$T/s" >"$T/log" 2>&1; then
	bad "the planted search failed: $(tail -3 "$T/log")"
	echo "cli_prune: $pass passed, $fail failed"
	exit 1
fi

# dead FILE: the forms of FILE with an outer max over a parameter and a max
# holding the literal 1.5, which the inner max exceeds everywhere
dead() { csv_col "$1" form | grep -E 'max\(p[0-9]+, .*max\(1\.5'; }

if dead "$T/s/front.csv" >"$T/d"; then bad "front.csv keeps a dead max: $(cat "$T/d")"; else ok; fi
if dead "$T/s/catalog.csv" >/dev/null; then ok; else bad "control: catalog.csv's seed rows should keep their dead max"; fi
# the pruned member: the target's own max, exact, at cost 3 (one max, one mad, one mul)
csv_cols "$T/s/front.csv" form cost rmse >"$T/rows" || bad "front.csv: columns form, cost, rmse"
if awk -F'\t' '$1 ~ /^p0 \* max\(1\.5, / && $2 == 3 && $3 + 0 < 1e-12 { found = 1 } END { exit !found }' "$T/rows"; then
	ok
else
	bad "no exact member p0 * max(1.5, ...) at cost 3 on the front: $(cat "$T/rows")"
fi
# determinism: the same front with 2 threads (the line naming the command aside)
"$BK" search --target form --target-form 'max(1.5, 2*LoH)' --domain LoH=0.3:1 \
	--start 'max(p0, max(1.5, p1*LoH))' --evals 30 --enum-max 10 --threads 2 --quiet --out "$T/s2" >/dev/null 2>&1
grep -v '^# command:' "$T/s/front.csv" >"$T/a"
grep -v '^# command:' "$T/s2/front.csv" >"$T/b" 2>/dev/null
if [ -s "$T/a" ] && cmp -s "$T/a" "$T/b"; then ok; else bad "front.csv differs between 1 and 2 threads (but its command line)"; fi

echo "cli_prune: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
