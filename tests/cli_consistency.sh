#!/bin/sh
# cli_consistency.sh — one command line across the commands (issue 24): a
# mistyped command, option or value gets the nearest name ("did you mean"),
# and a far-off one none; the precision spellings commands used before (fp16,
# f16, mediump, fp32, f32, highp, lut --half, compare --tier) are refused with
# the one spelling; every command takes --quiet, which silences progress but
# not errors. The expected names are the hand-counted nearest ones (one edit:
# an insertion, a deletion, a swap), not what the tool prints elsewhere.
# usage: sh tests/cli_consistency.sh path/to/brdfkit
set -u
BK=${1:?usage: sh tests/cli_consistency.sh path/to/brdfkit}
case $BK in /*) ;; *) BK=$(pwd)/$BK ;; esac # the setups run in a scratch directory
T=$(mktemp -d /tmp/bk_cli_consistency_XXXXXX)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
set -f # forms hold '*'

# usage NAME LINE CMD...: exit 2, nothing on stdout, stderr exactly LINE (one line).
usage() {
	name=$1 want=$2; shift 2
	"$@" >"$T/out" 2>"$T/err"
	rc=$?
	if [ $rc -eq 2 ] && [ ! -s "$T/out" ] && [ "$(cat "$T/err")" = "$want" ]; then ok
	else bad "$name: rc $rc, stdout '$(head -c 200 "$T/out")', stderr '$(cat "$T/err")' (want '$want')"; fi
}
# nohint NAME TOKEN CMD...: exit 2, one line holding TOKEN and no "did you mean".
nohint() {
	name=$1 token=$2; shift 2
	"$@" >"$T/out" 2>"$T/err"
	rc=$?
	if [ $rc -eq 2 ] && [ "$(wc -l <"$T/err")" -eq 1 ] && grep -qF -- "$token" "$T/err" &&
	   ! grep -q "did you mean" "$T/err"; then ok
	else bad "$name: rc $rc, stderr '$(cat "$T/err")'"; fi
}

# ---- did you mean ---------------------------------------------------------------
# 'serch': one insertion from 'search'
usage "command serch" "brdfkit: unknown command 'serch'; did you mean 'search'? (see brdfkit --help)" $BK serch
# 'scnee': one swap from 'scene' (Damerau's edit: a plain edit distance counts 2)
usage "command scnee" "brdfkit: unknown command 'scnee'; did you mean 'scene'? (see brdfkit --help)" $BK scnee
nohint "command far off" "unknown command 'frobnicate'" $BK frobnicate
usage "option --evls" "brdfkit search: unknown option '--evls'; did you mean '--evals'? (see brdfkit search --help)" \
	$BK search --target f --evls 30 --out s
usage "option --evls=30" "brdfkit search: unknown option '--evls'; did you mean '--evals'? (see brdfkit search --help)" \
	$BK search --target f --evls=30 --out s
usage "option --qiuet" "brdfkit lut: unknown option '--qiuet'; did you mean '--quiet'? (see brdfkit lut --help)" \
	$BK lut --size 4 --qiuet --out l
nohint "option far off" "unknown option '--zzzzzz'" $BK search --target f --zzzzzz --out s
usage "value vf2" "brdfkit fit: --target: unknown value 'vf2'; did you mean 'vf2d'? (known: vf2d, vf, spec, env, d, f, form, ms, sheen, table, merl) (see brdfkit fit --help)" \
	$BK fit --target vf2 --form vf_talk_r --out f
usage "value mx" "brdfkit search: --objective: unknown value 'mx'; did you mean 'max'? (known: rmse, max, albedo) (see brdfkit search --help)" \
	$BK search --target f --objective mx --out s
usage "value glls" "brdfkit codegen: --lang: unknown value 'glls'; did you mean 'glsl'? (known: c, glsl, hlsl, msl, latex, sympy) (see brdfkit codegen --help)" \
	$BK codegen --lang glls NoV
nohint "value far off" "unknown value 'banana'" $BK compare --target banana --out c
# one letter is one edit from 'd' and 'f' alike: too short to mean either
nohint "value too short" "unknown value 'x'" $BK search --target x --out s

# ---- one precision spelling ----------------------------------------------------------
hint() { # hint NAME OLD NEW CMD...
	name=$1 old=$2 new=$3; shift 3
	"$@" >"$T/out" 2>"$T/err"
	rc=$?
	if [ $rc -eq 2 ] && [ "$(wc -l <"$T/err")" -eq 1 ] && grep -qF -- "'$old'; did you mean '$new'?" "$T/err"; then ok
	else bad "$name: rc $rc, stderr '$(cat "$T/err")'"; fi
}
hint "codegen mediump" mediump half $BK codegen --lang glsl --precision mediump NoV
hint "codegen highp" highp single $BK codegen --lang hlsl --precision highp NoV
hint "gpucost fp16" fp16 half $BK gpucost --precision fp16 NoV
hint "gpucost fp32" fp32 single $BK gpucost --precision fp32 NoV
hint "render f16" f16 half $BK render --form vf_talk_r --precision f16 --out r
hint "render f32" f32 single $BK render --form vf_talk_r --precision f32 --out r
hint "search fp16" fp16 half $BK search --target f --precision fp16 --out s
hint "lut --half" --half "--precision half" $BK lut --size 4 --half --out l
hint "compare --tier" --tier --fetch-cost $BK compare --target env --tier 32 --out c
# control: gpucost has no double, so fp64 is no slip for a value it takes
nohint "gpucost fp64" "unknown value 'fp64' (known: single, half)" $BK gpucost --precision fp64 NoV
# control: the new spellings are taken (the tables' own output, hand-checked words)
$BK codegen --lang glsl --precision half NoV 2>"$T/err" | grep -q 'mediump float' && ok || bad "codegen half: $(cat "$T/err")"
$BK codegen --lang hlsl --precision single NoV 2>"$T/err" | grep -q '^float ' && ok || bad "codegen single: $(cat "$T/err")"

# ---- --quiet ----------------------------------------------------------------------
# every command takes it: each setup of the applicability walk (tests/cli_opts.sh) with --quiet
tab=$(printf '\t')
$BK help --applicability | awk -F"$tab" '$1 == "setup" { print $2 "\t" $3 }' >"$T/setups"
[ "$(cut -f1 "$T/setups" | sort -u | wc -l)" -ge 15 ] && ok || bad "fewer than 15 commands with setups"
mkdir "$T/run"
while IFS="$tab" read -r cmd args; do
	(cd "$T/run" && $BK $cmd $args --quiet --check-options >"$T/out" 2>"$T/err")
	rc=$?
	[ $rc -eq 0 ] && grep -q "^context$tab$cmd" "$T/out" && ok || bad "$cmd $args --quiet: rc $rc, $(cat "$T/err")"
done <"$T/setups"
# commands without a table take it too
$BK terms --quiet >/dev/null 2>"$T/err" && [ ! -s "$T/err" ] && ok || bad "terms --quiet: $(cat "$T/err")"

# progress is silenced, the result is the same; the control shows the line is there without it
$BK lut --size 8 --out "$T/l1" >/dev/null 2>"$T/e1"
$BK lut --size 8 --quiet --out "$T/l2" >/dev/null 2>"$T/e2"
grep -q "lut rows: 8/8 done" "$T/e1" && ok || bad "lut: no progress line without --quiet: '$(cat "$T/e1")'"
[ ! -s "$T/e2" ] && ok || bad "lut --quiet printed '$(cat "$T/e2")'"
grep -v '^#' "$T/l1/dfg.csv" >"$T/c1"; grep -v '^#' "$T/l2/dfg.csv" >"$T/c2"
[ -s "$T/c1" ] && cmp -s "$T/c1" "$T/c2" && ok || bad "lut --quiet changed dfg.csv"
S="search --target f --evals 30 --enum-max 30 --threads 1"
$BK $S --out "$T/s1" >/dev/null 2>"$T/e1"
$BK $S --quiet --out "$T/s2" >/dev/null 2>"$T/e2"
grep -q "^search: 30 fits" "$T/e1" && ok || bad "search: no progress line without --quiet: '$(cat "$T/e1")'"
[ ! -s "$T/e2" ] && ok || bad "search --quiet printed '$(cat "$T/e2")'"
# errors still print under --quiet: a usage error and a run-time one
usage "quiet usage error" "brdfkit lut: unknown option '--sizee'; did you mean '--size'? (see brdfkit lut --help)" \
	$BK lut --quiet --sizee 8 --out "$T/l3"
$BK lut --quiet --size 8 --out "$T/no/such/dir" >/dev/null 2>"$T/err"
rc=$?
[ $rc -eq 1 ] && grep -q "^brdfkit lut: --out $T/no/such/dir: cannot create" "$T/err" && ok ||
	bad "lut --quiet, bad --out: rc $rc, '$(cat "$T/err")'"
# --help names it
$BK fit --help | grep -q -- "--quiet" && ok || bad "fit --help does not name --quiet"

echo "cli_consistency: $pass passed, $fail failed"
[ $fail -eq 0 ]
