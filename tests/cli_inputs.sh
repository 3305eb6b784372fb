#!/bin/sh
# cli_inputs.sh — what brdfkit takes from a user's files and options (issue
# 39, items 4 and 5): forms that read an input the target does not sample
# are refused everywhere a form meets a target (M1); a front or catalog read
# for comparison or seeding must state the target, objective and precision
# the run needs (H2); numbers in a user's CSV are decimal (L8); links in
# every section are relative, percent-encoded and checked where the option
# is parsed and where report reads them (H4, L2, L3).
# usage: sh tests/cli_inputs.sh path/to/brdfkit
set -u
BK=${1:?usage: cli_inputs.sh path/to/brdfkit}
BK=$(cd "$(dirname "$BK")" && pwd)/$(basename "$BK")
REPO=$(pwd)
T=$(mktemp -d /tmp/bk_cli_inputs_XXXXXX)
trap 'rm -rf "$T"' EXIT
CSVGET=$REPO/build/csvget
. "$REPO/tests/lib.sh"
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
cd "$T" || exit 1

# refused RC NAME TOKEN CMD...: exit RC, one line on stderr holding TOKEN
refused() {
	want=$1 name=$2 token=$3; shift 3
	"$@" >out 2>err; rc=$?
	if [ "$rc" -eq "$want" ] && [ "$(wc -l <err)" -eq 1 ] && grep -qF -- "$token" err; then ok
	else bad "$name: exit $rc, stderr '$(head -c 400 err)'"; fi
}
# runs NAME CMD...: exit 0 (the matching case, the control of each refusal)
runs() {
	name=$1; shift
	if "$@" >out 2>err; then ok; else bad "$name: exit $?, stderr '$(head -c 400 err)'"; fi
}
S="search --evals 10 --threads 1 --quiet"

# ---- M1: an input the target does not sample ------------------------------------------
# f is Fresnel of LoH alone (it had r = 0.5 and a = 0.25 as constants), d is
# GGX D of NoH and r (it had f0): a form reading them fitted a constant.
refused 2 "f --start r" "--start 'r' reads an input target f does not provide" $BK $S --target f --start r --out m1
refused 2 "f --start a" "reads an input target f does not provide" $BK $S --target f --start 'a*LoH' --out m2
refused 2 "d --start f0" "--start 'f0*NoH' reads an input target d does not provide" $BK $S --target d --start 'f0*NoH' --out m3
refused 1 "fit f a" "the form reads a, which target f does not provide" $BK fit --target f --form 'p0*LoH + a' p0=1 --out m4
refused 1 "fit d f0" "the form reads f0, which target d does not provide" $BK fit --target d --form 'p0*NoH*f0' p0=1 --out m5
refused 2 "f --inputs r" "--inputs: the target does not provide r" $BK $S --target f --inputs LoH,r --out m6
refused 2 "compare f r" "'r*LoH' reads r, which target f does not provide" $BK compare --target f --no-time --no-refit --quiet --out m7 'r*LoH'
refused 2 "compare d f0" "'f0*NoH' reads f0, which target d does not provide" $BK compare --target d --no-time --no-refit --quiet --out m8 'f0*NoH'
# controls: what each target samples is still taken
runs "f --start f0" $BK $S --target f --start 'f0 + (1 - f0)*(1 - LoH)' --out m9
runs "d --start r" $BK $S --target d --start 'r*NoH' --out m10
runs "fit f f0" $BK fit --target f --nx 16 --form 'f0 + p0*(1 - LoH)' p0=1 --out m11
# the grammar a search on f enumerates: LoH and f0, no r or a
grep -q '^# certificate: .*; inputs LoH f0;' m9/front.csv && ok || bad "f's grammar: $(grep '^# certificate' m9/front.csv)"
# a --start-front member reading r, on f
printf 'name,form,form_b,parameters\nx,r*LoH,,\n' >rfront.csv
refused 1 "f --start-front r" "rfront.csv:2: x: the form reads an input the target does not provide" $BK $S --target f --start-front rfront.csv --out m12

echo "cli_inputs: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
