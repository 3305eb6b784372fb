#!/bin/sh
# cli_results_render.sh — make results' rendered comparisons show, of each
# search front, the most accurate member at cost <= 16 (the Makefile's
# RENDER_MAX_COST), whatever the row order (a half front's rows are not in
# cost order: the last row at cost <= 16 was once a cost-5 member of
# env_f0_half, rmse 0.073, beside a 0.026 one). Reads results/render's
# directories (DIR-NAME) and results/search/DIR/front.csv by column name.
# usage: sh tests/cli_results_render.sh build/brdfkit   (the tool is not run)
set -u
T=$(mktemp -d /tmp/bk_results_render_XXXXXX)
trap 'rm -rf "$T"' EXIT
CSVGET=${CSVGET:-build/csvget}
. tests/lib.sh
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }

# best FRONT: the name of the least error at cost <= 16
best() {
	csv_cols "$1" name cost error | awk -F '\t' '$2 <= 16 && (n == "" || $3 < e) { n = $1; e = $3 } END { print n }'
}
# worst FRONT: the greatest error at cost <= 16 (the negative control)
worst() {
	csv_cols "$1" name cost error | awk -F '\t' '$2 <= 16 && (n == "" || $3 > e) { n = $1; e = $3 } END { print n }'
}

n=0
for d in results/render/*-*/; do
	d=${d%/}; b=${d##*/}; dir=${b%%-*}; name=${b#*-}
	f=results/search/$dir/front.csv
	[ -f "$f" ] || continue
	n=$((n + 1))
	want=$(best "$f")
	[ -n "$want" ] && [ "$name" = "$want" ] && ok || bad "$b: rendered $name, the best at cost <= 16 of $f is '$want'"
	# the control: the check tells a wrong member from the right one
	w=$(worst "$f")
	[ "$w" != "$want" ] && [ "$w" != "$name" ] && ok || bad "$b: control: the worst member '$w' is not told apart"
done
[ "$n" -ge 8 ] && ok || bad "only $n rendered front members in results/render (want the Makefile's 8)"

echo "cli_results_render: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
