#!/bin/sh
# cli_formtarget.sh — brdfkit's command-line contract (the common start:
# tests/lib_cli.sh): fit --target form, and the TinySolver fast path (issue 10).
# usage: sh tests/cli_formtarget.sh path/to/brdfkit
NAME=cli_formtarget
. "$(dirname "$0")/lib_cli.sh"

# ---- issue 10 (form target) ----
# a target given by a formula: a planted form is recovered to every printed
# digit (its standard errors are ~1e-16, so the digits rule keeps 0.3, 0.7)
FT="0.3/(LoH*LoH + 0.7*r*r)"
$BK fit --target form --target-form "$FT" --domain LoH=0.3162:1,r=0:1 --form 'p0/(LoH*LoH + p1*r*r)' p0=1 p1=1 \
	--out "$T/ft" >"$T/out" 2>"$T/err"
st=$?
[ $st -eq 0 ] && [ "$(csv_where "$T/ft/coefficients.csv" parameter p0 value)" = 0.3 ] &&
	[ "$(csv_where "$T/ft/coefficients.csv" parameter p1 value)" = 0.7 ] && ok ||
	bad "form target: exit $st: $(cat "$T/err") $(cat "$T/ft/coefficients.csv")"
grep -qxF "# target form: $FT" "$T/ft/metrics.csv" && grep -qxF "# domain: LoH=0.3162:1,r=0:1 (cell centres, 64 per axis)" \
	"$T/ft/metrics.csv" && grep -q '^ \* fitted domain: form: 0.3/(LoH\*LoH + 0.7\*r\*r) evaluated in double on LoH in \[0.3162, 1\] x r in \[0, 1\]' \
	"$T/ft/shader.c" && ok || bad "form target: provenance: $(head -6 "$T/ft/metrics.csv")"
[ "$(csv_col "$T/ft/heatmap.csv" error | wc -l)" -eq $((64 * 64)) ] && ok || bad "form target: heatmap is not 64x64"
# three inputs: no plane, no heatmap, said on stdout
$BK fit --target form --target-form 'exp2(-5.5*LoH)*0.9*f0 + NoV' --domain LoH=0:1,f0=0:1,NoV=0:1 \
	--form 'p0*f0*exp2(p1*LoH) + NoV' p0=1 p1=-1 --out "$T/ft3" >"$T/out" 2>"$T/err" \
	&& grep -qx 'no heatmap: target form has 3 inputs; a heatmap needs 1 or 2' "$T/out" && [ ! -e "$T/ft3/heatmap.csv" ] \
	&& [ "$(csv_where "$T/ft3/coefficients.csv" parameter p1 value)" = -5.5 ] && ok || bad "form target, 3 inputs: $(cat "$T/out" "$T/err")"
# a target read from a file over two lines keeps the headers one line each
printf '0.3/(LoH*LoH +\n 0.7*r*r)\n' >"$T/ft.txt"
$BK fit --target form --target-form @"$T/ft.txt" --domain LoH=0.3162:1,r=0:1 --form 'p0/(LoH*LoH + p1*r*r)' p0=1 p1=1 \
	--out "$T/ft" >/dev/null 2>&1 && grep -qxF '# target form: 0.3/(LoH*LoH +  0.7*r*r)' "$T/ft/metrics.csv" \
	&& [ "$(csv_col "$T/ft/coefficients.csv" form | sort -u)" = 'p0/(LoH*LoH + p1*r*r)' ] \
	&& [ "$(grep -c '^form,\|^#\|^p0/' "$T/ft/coefficients.csv")" -eq "$(wc -l <"$T/ft/coefficients.csv")" ] && ok \
	|| bad "form target from a file: $(head -5 "$T/ft/coefficients.csv")"
rm -rf "$T/ft" "$T/ft3"
rm -f "$T/ft.txt"
FF="$BK fit --target form --form p0*LoH p0=1 --out $T/fe"
expect_error "form target: missing input" \
	"brdfkit fit: --target-form: the target form reads 'r', which the domain does not give (add r=LO:HI) (see brdfkit fit --help)" \
	$FF --target-form "$FT" --domain LoH=0.3162:1
expect_error "form target: unread input" \
	"brdfkit fit: --target-form: the domain gives 'NoV', which the target form does not read (see brdfkit fit --help)" \
	$FF --target-form "$FT" --domain LoH=0.3162:1,r=0:1,NoV=0:1
expect_error "form target: syntax" \
	"brdfkit fit: --domain: expected NAME=LO:HI, got 'LoH=0.3162' (see brdfkit fit --help)" \
	$FF --target-form "$FT" --domain LoH=0.3162,r=0:1
expect_error "form target: not an input" \
	"brdfkit fit: --domain: 'XoH' is not an input (NoV, NoL, NoH, LoH, r, a, f0) (see brdfkit fit --help)" \
	$FF --target-form LoH --domain XoH=0:1
expect_error "form target: strict number" \
	"brdfkit fit: --domain: LoH: expected LO:HI (two numbers), got '0x1:1' (see brdfkit fit --help)" \
	$FF --target-form LoH --domain LoH=0x1:1
expect_error "form target: LO >= HI" \
	"brdfkit fit: --domain: r: expected LO < HI, got '1:1' (see brdfkit fit --help)" \
	$FF --target-form "$FT" --domain LoH=0.3162:1,r=1:1
expect_error "form target: pole" \
	"brdfkit fit: the target form is inf at LoH = 0.625 (sample 3 of 4): a target must be finite on its domain" \
	$FF --target-form '1/(LoH - 0.625)' --domain LoH=0:1 --nx 4
expect_error "form target: parameter" \
	"brdfkit fit: --target-form: the target form uses p0..p1: a target has no parameters (write its constants as numbers) (see brdfkit fit --help)" \
	$FF --target-form 'p0*LoH + p1' --domain LoH=0:1
expect_error "form target: r and a" \
	"brdfkit fit: --target-form: the domain gives both 'r' and 'a': with r, a is r^2 (give one) (see brdfkit fit --help)" \
	$FF --target-form 'a*LoH' --domain LoH=0:1,r=0:1,a=0:1
expect_error "form target: no domain" \
	"brdfkit fit: target form needs --target-form EXPR and --domain IN=LO:HI[,...] (see brdfkit fit --help)" \
	$FF --target-form LoH
expect_error "form target: --domain elsewhere" \
	"brdfkit fit: --domain has no effect on target vf2d (it gives the domain of target form) (see brdfkit fit --help)" \
	$BK fit --target vf2d --form vf_talk_r --domain LoH=0:1 --out "$T/fe"
expect_error "form target: --target-form elsewhere" \
	"brdfkit fit: --target-form has no effect on target d (it gives the expression of target form) (see brdfkit fit --help)" \
	$BK fit --target d --form 'p0*NoH' p0=1 --target-form LoH --out "$T/fe"
expect_error "form target: --x-range" \
	"brdfkit fit: --x-range has no effect on target form (--domain sets the inputs of target form) (see brdfkit fit --help)" \
	$FF --target-form LoH --domain LoH=0:1 --x-range 0:0.5
expect_error "form target: candidate reads what the domain lacks" \
	"brdfkit fit: the form reads NoV, which target form does not provide" \
	$BK fit --target form --target-form LoH --domain LoH=0:1 --form 'p0*NoV' p0=1 --out "$T/fe"
expect_error "form target: compare" \
	"brdfkit compare: --target form: compare scores the catalog; fit a form target with brdfkit fit" \
	$BK compare --target form --out "$T/fe"
$FF --target-form "$FT" --domain LoH=0.3162:1 >/dev/null 2>&1; [ $? -eq 2 ] && ok || bad "form target: usage error is not exit 2"
[ ! -e "$T/fe" ] && ok || bad "form target: a refused run wrote $T/fe"

# stability's pN= takes the same number syntax as every other command
expect_error "stability p0 hex" "p0: expected a finite number, got '0x1p3'" $BK stability 'p0*NoV' p0=0x1p3

# ---- issue 10 (tiny) ----
# fit takes the TinySolver fast path where it applies (no finite bound, no
# loss, Levenberg-Marquardt: fit/tiny.cc) and Ceres elsewhere: stopped by an
# iteration limit of 1, the warning names the solver that stopped.
$BK fit --target vf2d --form vf_talk_r --nx 32 --nr 32 --starts 1 --max-iterations 1 --out "$T/tiny" >"$T/out" 2>&1
if grep -qxF 'warning: did not converge (iteration limit reached (TinySolver): 1 iterations)' "$T/out"; then ok
else bad "fit fast path: $(cat "$T/out")"; fi
for extra in "--bound p0=0:10" "--loss huber" "--trust-region dogleg"; do
	$BK fit --target vf2d --form vf_talk_r --nx 32 --nr 32 --starts 1 --max-iterations 1 $extra --out "$T/tiny" \
		>"$T/out" 2>&1
	if grep -qxF 'warning: did not converge (Maximum number of iterations reached. Number of iterations: 1.)' "$T/out"
	then ok; else bad "fit $extra: Ceres path: $(cat "$T/out")"; fi
done

cli_done
