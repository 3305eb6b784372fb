#!/bin/sh
# cli_longfits.sh — brdfkit's command-line contract (the common start:
# tests/lib_cli.sh): long env fits state their work up front, refuse an
# unwritable --out before it and log progress; a fit that took no step is not
# converged (issue 9, numerics; split from cli_numerics.sh).
# usage: sh tests/cli_longfits.sh path/to/brdfkit
NAME=cli_longfits
. "$(dirname "$0")/lib_cli.sh"

# within_5s T0: at most 5 s have passed since T0 (date +%s)
within_5s() { [ $(($(date +%s) - $1)) -le 5 ]; }
# long env fits: the work is stated up front, an unwritable --out is refused
# before it (at once, not after hours; a path under a regular file fails for
# root too), and logs (stderr not a terminal) see progress while it runs
: >"$T/file"
for cmd in "fit --target env --form env_karis2014_split" "compare --target env --no-time"; do
	t0=$(date +%s)
	expect_error "$cmd unwritable out" "--out $T/file/sub: cannot create: not a directory" \
		timeout 20 $BK $cmd --nx 1024 --nr 1024 --out "$T/file/sub"
	within_5s "$t0" && ok || bad "$cmd: unwritable --out refused only after the work"
done
# control: the same clock check after 6 s must fail
t0=$(date +%s); sleep 6; expect_fail "refused at once" within_5s "$t0"
until_lines 1 3 "$T/err" $BK fit --target env --form env_karis2014_split --nx 4096 --nr 4096 --out "$T/big"
grep -q '^fit: env target 4096x4096 = 16.8M integrals, about [0-9.]* \(s\|min\|h\) on this machine$' "$T/err" && ok \
	|| bad "no work estimate: $(cat "$T/err")"
# (without the suites' table cache: integrals read from it need no progress)
env -u BRDFKIT_TABLE_CACHE timeout 20 $BK fit --target env --form env_karis2014_split --nx 256 --nr 64 --out "$T/mid" \
	>/dev/null 2>"$T/err"
grep -q '^reference: [1-5]\?[0-9]/64 ([0-9]* %, [0-9]* s)$' "$T/err" && ok || bad "no progress lines in a log: $(cat "$T/err")"
rm -rf "$T/file" "$T/big" "$T/mid"

# a fit that took no step from a point that is not a minimum is not converged
# (exit 3, the reason said): a Huber scale that flattens every residual, and a
# start where the form is flat (the derivative of 1/(r + p0) underflows)
for how in "--loss huber --loss-scale 1e-300" "p0=1e308"; do
	$BK fit --target vf2d --form vf_talk_r $how --out "$T/nostep" >"$T/out" 2>&1
	st=$?
	[ $st -eq 3 ] && grep -q '^warning: did not converge (no step taken from a point that is not a minimum: ' "$T/out" && ok \
		|| bad "fit $how: exit $st: $(tail -1 "$T/out")"
done
rm -rf "$T/nostep"

cli_done
