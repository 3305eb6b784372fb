#!/bin/sh
# cli_ms.sh — targets ms and sheen (issue 41) through fit, compare and search.
#
#   - fit --target ms of ms_pesce_iwanicki2015: the refit's rmse is below the
#     published constants' (metrics.csv, rows by name), and the published
#     one matches compare's row for the entry on the same grid (one target,
#     two commands); a form reading f0 is refused on ms and sheen (F = 1:
#     E has no f0), as is --f0 (no effect on ms);
#   - compare --target ms scores exactly the catalog's ms entries (the names
#     from `brdfkit catalog`, not a list here), compare --target sheen the
#     sheen ones; ms's LUT rows (E in one channel) and sheen's (the cloth
#     channel), each with a heatmap of its own, get more accurate with
#     size, as bilinear filtering must;
#   - a small search on ms: its front's best member at a cost no higher than
#     ms_pesce_iwanicki2015's is more accurate than it (the issue's "beats every
#     published form at equal or lower cost", at the search's budget); control:
#     the same check against a catalog.csv whose Pesce row claims rmse 1e-9
#     must fail.
# usage: sh tests/cli_ms.sh path/to/brdfkit
set -u
BK=${1:?usage: sh tests/cli_ms.sh path/to/brdfkit}
case $BK in /*) ;; *) BK=$(pwd)/$BK ;; esac
ROOT=$(cd "$(dirname "$0")/.." && pwd)
T=$(mktemp -d /tmp/bk_cli_ms_XXXXXX)
trap 'rm -rf "$T"' EXIT
CSVGET=$ROOT/build/csvget
. "$ROOT/tests/lib.sh"
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
cd "$T" || exit 1

# refused NAME TOKEN CMD...: exit 2, one line on stderr holding TOKEN.
refused() {
	name=$1 token=$2; shift 2
	"$@" >out 2>err
	rc=$?
	if [ $rc -eq 2 ] && [ "$(wc -l <err)" -eq 1 ] && grep -qF -- "$token" err; then ok
	else bad "$name: rc $rc, stderr '$(cat err)'"; fi
}

# ---- fit -----------------------------------------------------------------------
"$BK" fit --target ms --form ms_pesce_iwanicki2015 --nx 20 --nr 20 --out fp >out 2>err || bad "fit ms: $(cat err)"
fitted=$(csv_where fp/metrics.csv constants fitted rmse) published=$(csv_where fp/metrics.csv constants published rmse)
awk -v f="$fitted" -v p="$published" 'BEGIN { exit !(f > 0 && f < p) }' && ok ||
	bad "fit ms: fitted rmse '$fitted', published '$published'"
# reads_no_f0 TARGET: a form in f0 fails, naming f0 and the target
reads_no_f0() {
	"$BK" fit --target "$1" --form 'f0*NoV' --nx 4 --nr 4 --out x >out 2>err
	[ $? -ne 0 ] && [ ! -e x ] && grep -q "reads f0, which target $1 does not provide" err
}
reads_no_f0 ms && ok || bad "ms: a form reading f0: $(cat err)"
reads_no_f0 sheen && ok || bad "sheen: a form reading f0: $(cat err)"
refused "ms --f0" "--f0" "$BK" fit --target ms --form 'p0*NoV' p0=1 --f0 0.5 --out x

# ---- compare: the catalog's entries of each target, by name ------------------------
"$BK" catalog >cat.csv 2>err || bad "catalog: $(cat err)"
for t in ms sheen; do
	"$BK" compare --target $t --no-time --nx 20 --nr 20 --out c_$t >out 2>err || bad "compare $t: $(cat err)"
	csv_where cat.csv target $t name | sort >want_$t
	csv_where c_$t/compare.csv kind published name | sort >got_$t
	[ -s want_$t ] && cmp -s want_$t got_$t && ok || bad "compare $t: rows '$(cat got_$t)', catalog '$(cat want_$t)'"
done
# ms's LUT rows: E in one channel (the DFG folded at f0 = 1); bilinear filtering
# errs O(h^2), so in float each size is more accurate than the one below it
# (control: the errors in increasing order fail it); 20x20 samples: no cell
# centre is a texel centre of any size, where a LUT would be exact
for z in 16 32 64 128; do csv_where c_ms/compare.csv name "LUT ${z}x$z float f0 1" rmse || echo missing; done >lut_err
shrinks() { awk 'NR > 1 && !($1 + 0 < last + 0) { bad = 1 } { last = $1 } END { exit bad || NR != 4 }' "$1"; }
shrinks lut_err && ok || bad "ms LUT rows: float rmse by size $(tr '\n' ' ' <lut_err)"
sort -g lut_err >lut_rev
expect_fail "LUT sizes reversed" shrinks lut_rev
# sheen's LUT rows: the cloth channel (the sheen albedo) in one fetch, the same
# order by size
for z in 16 32 64 128; do csv_where c_sheen/compare.csv name "LUT ${z}x$z float" rmse || echo missing; done >cloth_err
shrinks cloth_err && ok || bad "sheen LUT rows: float rmse by size $(tr '\n' ' ' <cloth_err)"
# each LUT row's heatmap is its own: the 16² and the 128² differ everywhere
# (once, ms's were scored as the generic layout, refused, and all showed the
# same stale buffer); the control: a heatmap against itself
EXRCMP=$ROOT/build/exrcmp
for h in c_ms/heatmaps/lut_%s_float_f0_1.exr c_sheen/heatmaps/lut_%s_float.exr; do
	# shellcheck disable=SC2059 # h is the format
	a=$(printf "$h" 16x16) b=$(printf "$h" 128x128)
	"$EXRCMP" "$a" "$b" 0 1e-12 >/dev/null 2>&1
	[ $? -eq 1 ] && ok || bad "$a and $b: not two heatmaps of their own"
	"$EXRCMP" "$b" "$b" 0 1e-12 >/dev/null 2>&1 && ok || bad "$b against itself"
done
cmp_rmse=$(csv_where c_ms/compare.csv name ms_pesce_iwanicki2015 rmse)
awk -v a="$cmp_rmse" -v b="$published" 'BEGIN { d = a - b; exit !(d < 1e-9 && d > -1e-9) }' && ok ||
	bad "ms_pesce_iwanicki2015: compare rmse '$cmp_rmse', fit's published '$published'"

# ---- search: the front against Pesce & Iwanicki at no higher cost ------------------
"$BK" search --target ms --evals 3000 --quiet --out s >out 2>err || bad "search ms: $(cat err)"
# beats CAT: the front's best error at cost <= the Pesce row's cost is below its error
beats() {
	pc=$(csv_where "$1" name ms_pesce_iwanicki2015 cost) || return 1
	pe=$(csv_where "$1" name ms_pesce_iwanicki2015 error) || return 1
	csv_cols s/front.csv cost error >fe || return 1
	awk -v c="$pc" -v e="$pe" '$1 + 0 <= c + 0 && $2 + 0 < e + 0 { f = 1 } END { exit !f }' fe
}
beats s/catalog.csv && ok || bad "search ms: no front member beats ms_pesce_iwanicki2015 at its cost"
csv_set s/catalog.csv error name ms_pesce_iwanicki2015 1e-9 >cat_ctl.csv || bad "csv_set"
if beats cat_ctl.csv; then bad "control: a Pesce row of error 1e-9 was beaten"; else ok; fi

echo "cli_ms: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
