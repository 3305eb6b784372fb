#!/bin/sh
# cli_fitstab.sh — brdfkit's command-line contract (the common start:
# tests/lib_cli.sh): fit, compare and report: every output file and the
# published row; fit and stability: no silent wrong answers (issue 9).
# usage: sh tests/cli_fitstab.sh path/to/brdfkit
NAME=cli_fitstab
. "$(dirname "$0")/lib_cli.sh"

# fit: the talk's constant refitted on its own plane; every output file, the
# published row, and the exit status
if $BK fit --target vf2d --form vf_talk_r --nx 32 --nr 32 --out "$T/fit" >"$T/out" 2>"$T/err"; then ok; else bad "fit vf2d: $(cat "$T/err")"; fi
for f in heatmap.exr heatmap.png shader.c shader.glsl shader.hlsl; do
	[ -s "$T/fit/$f" ] && ok || bad "fit: missing $f"
done
grep -qx 'constants,cost,rmse,weighted_rmse,max_abs,max_rel,albedo_max_abs' "$T/fit/metrics.csv" && ok || bad "metrics header"
# a row each, with a number for rmse (not a header alone)
csv_min "$T/fit/metrics.csv" rmse >/dev/null && csv_where "$T/fit/metrics.csv" constants published rmse >/dev/null &&
	csv_where "$T/fit/metrics.csv" constants fitted rmse >/dev/null && ok || bad "metrics rows"
grep -q '^form,parameter,value,standard_error$' "$T/fit/coefficients.csv" && ok || bad "coefficients header"
[ "$(csv_where "$T/fit/coefficients.csv" parameter p0 form)" = vf_talk_r ] && ok || bad "coefficients: no p0 row"
# the heatmap: one row per cell of the 32 x 32 grid
[ "$(csv_col "$T/fit/heatmap.csv" error | wc -l)" -eq 1024 ] && ok || bad "heatmap.csv: not 32 x 32 rows"
cp "$T/fit/coefficients.csv" "$T/c1.csv"; cp "$T/fit/heatmap.png" "$T/h1.png"
$BK fit --target vf2d --form vf_talk_r --nx 32 --nr 32 --out "$T/fit" >/dev/null 2>&1
cmp -s "$T/c1.csv" "$T/fit/coefficients.csv" && cmp -s "$T/h1.png" "$T/fit/heatmap.png" && ok || bad "fit not deterministic"
rm -rf "$T/fit" "$T/c1.csv" "$T/h1.png"
expect_error "fit nonfinite" "NaN or infinite at 16 of 32 samples" $BK fit --target f --nx 32 --form 'log(LoH - 0.5) + p0' p0=0 --out "$T/bad"
[ ! -e "$T/bad" ] && ok || bad "failed fit left $T/bad"
expect_error "fit input" "reads NoV, which target vf2d does not provide" $BK fit --target vf2d --form 'NoV*p0' p0=1 --out "$T/bad"
expect_error "fit target" "'nope'" $BK fit --target nope --form 'p0' --out "$T/bad"
expect_error "fit start" "p0=VALUE" $BK fit --target f --form 'p0*LoH' --out "$T/bad"

# compare and report: the tables, plots and page section, whole
if $BK compare --target vf2d --nx 8 --nr 8 --no-time --out "$T/cmp" >/dev/null 2>"$T/err"; then ok; else bad "compare: $(cat "$T/err")"; fi
for f in compare.csv pareto_cost.svg section.html heatmaps/vf_talk_r.png shaders/vf_talk_r_refit.glsl; do
	[ -s "$T/cmp/$f" ] && ok || bad "compare: missing $f"
done
# --no-time measured nothing: no timing table, no plot against ns
for f in timing.csv pareto_ns.svg; do [ ! -e "$T/cmp/$f" ] && ok || bad "compare --no-time wrote $f"; done
grep -v '^#' "$T/cmp/compare.csv" | head -1 | grep -q '^name,kind,source,form,form_b,parameters,rmse,' && ok ||
	bad "compare.csv header"
# provenance FILE WHAT COMMAND [TARGET]: FILE opens with brdfkit's provenance
# lines (analysis/prov.h): "# brdfkit VERSION WHAT...", "# command: COMMAND",
# then "# target: TARGET..." where given; the version is --version's
provenance() {
	_v=$($BK --version | awk '{ print $2 }')
	case "$(sed -n 1p "$1")" in "# brdfkit $_v $2"*) ;; *) return 1 ;; esac
	[ "$(sed -n 2p "$1")" = "# command: $3" ] || return 1
	[ -z "${4:-}" ] && return 0
	case "$(sed -n 3p "$1")" in "# target: $4"*) return 0 ;; esac
	return 1
}
provenance "$T/cmp/compare.csv" "compare: " "brdfkit compare --target vf2d --nx 8 --nr 8 --no-time --out $T/cmp" "vf2d: " &&
	ok || bad "compare.csv provenance: $(head -3 "$T/cmp/compare.csv")"
# negative control: the table without its '#' lines fails the same check
grep -v '^#' "$T/cmp/compare.csv" >"$T/bare.csv"
expect_fail "provenance of a headerless compare.csv" \
	provenance "$T/bare.csv" "compare: " "brdfkit compare --target vf2d --nx 8 --nr 8 --no-time --out $T/cmp" "vf2d: "
# a typed form longer than compare's rows once held (1,023 characters) is
# written whole; the control: the same text cut at 1,023 characters is not
# what the table holds
long="0.25"
i=0
while [ $i -lt 160 ]; do long="$long + 0*r*r"; i=$((i + 1)); done
if $BK compare --target vf2d --nx 8 --nr 8 --no-refit --no-time --out "$T/cmpl" "$long" >/dev/null 2>"$T/err"; then
	[ ${#long} -gt 1100 ] && [ "$(csv_where "$T/cmpl/compare.csv" kind form form)" = "$long" ] && ok ||
		bad "compare: a long typed form is not written whole (${#long} characters)"
	expect_fail "a long form cut at 1,023 characters" test "$(csv_where "$T/cmpl/compare.csv" kind form form)" = \
		"$(printf '%.1023s' "$long")"
	# its shaders are named form_N (its text slugged is no identifier: it
	# starts with a digit), and they compile as C
	n=$(ls "$T/cmpl/shaders" | grep -c '^form_[0-9]*\.\(c\|glsl\|hlsl\)$')
	[ "$n" = 3 ] && ok || bad "compare: the typed form's shaders: $(ls "$T/cmpl/shaders" | grep -v '^[a-z]')"
	cc -std=c11 -Wall -Werror -c -o "$T/form.o" "$T/cmpl/shaders/"form_*.c 2>"$T/err" && ok ||
		bad "compare: the typed form's C does not compile: $(head -3 "$T/err")"
else
	bad "compare with a long typed form: $(cat "$T/err")"
fi
# timed, the same header on timing.csv, and the columns read by name under it
$BK compare --target f --nx 16 --no-refit --out "$T/cmpt" >/dev/null 2>"$T/err" || bad "compare f: $(cat "$T/err")"
provenance "$T/cmpt/timing.csv" "compare timing: " "brdfkit compare --target f --nx 16 --no-refit --out $T/cmpt" "f: " &&
	is_num "$(csv_where "$T/cmpt/timing.csv" name f_schlick_sg ns_per_eval)" && ok ||
	bad "timing.csv provenance: $(head -4 "$T/cmpt/timing.csv")"
# the talk's form and its refit are rows with an rmse
is_num "$(csv_where "$T/cmp/compare.csv" name vf_talk_r rmse)" &&
	is_num "$(csv_where "$T/cmp/compare.csv" name 'vf_talk_r (refit)' rmse)" && ok || bad "compare.csv: no vf_talk_r rows"
# the target is never a competitor (results/compare/vf2d/pareto_cost.png drew vf2d's own
# v_kelemen_talk_r x F_schlick at error 0): no row exact on every sample, and the
# page names what was left out; negative control: the committed compare.csv of
# before (it has the row at max_abs 0) fails the same check
csv_any_le "$T/cmp/compare.csv" max_abs 0 && bad "compare: a row at error 0 (the target itself)" || ok
grep -q 'Left out as the target itself (exact on every sample): v_kelemen_talk_r x F_schlick' "$T/cmp/section.html" &&
	ok || bad "compare: section.html does not name the target left out"
printf 'name,max_abs\nv_kelemen_talk_r x F_schlick,0\nvf_talk_r,0.26\n' >"$T/self.csv"
csv_any_le "$T/self.csv" max_abs 0 && ok || bad "negative control: a row at error 0 is not seen"
grep -q "<img src=\"pareto_cost.svg\"" "$T/cmp/section.html" && [ -s "$T/cmp/pareto_cost.pdf" ] && [ -s "$T/cmp/pareto_cost.png" ] && ok || bad "section without its plot"
$BK report --out "$T/page.html" "$T/cmp/section.html" && grep -q '<h2>Target <code>vf2d</code></h2>' "$T/page.html" && ok || bad "report"
rm -rf "$T/cmp" "$T/page.html"
expect_error "compare target" "'nope'" $BK compare --target nope --out "$T/x"
expect_error "time parse" "form:1:" $BK time 'NoV +'

# stability.csv: the provenance lines (no target: the stress grid is its own)
$BK stability NoV --out "$T/stab" >/dev/null 2>"$T/err" || bad "stability --out: $(cat "$T/err")"
provenance "$T/stab/stability.csv" "stability: " "brdfkit stability NoV --out $T/stab" &&
	[ "$(csv_col "$T/stab/stability.csv" form)" = NoV ] && ok || bad "stability.csv provenance: $(head -3 "$T/stab/stability.csv")"
provenance "$T/stab/details.csv" "stability details: " "brdfkit stability NoV --out $T/stab" &&
	[ "$(csv_where "$T/stab/details.csv" precision f16 form)" = NoV ] && ok ||
	bad "details.csv provenance: $(head -3 "$T/stab/details.csv")"

# ---- issue 9 (fit and stability: no silent wrong answers) ----
# stab_f16 ARGS...: "samples wrong" of the f16 line of brdfkit stability.
stab_f16() { $BK stability "$@" 2>/dev/null | awk '$1 == "f16" { print $2, $3 }'; }
# stability reads the whole form: 240 terms NoV*1e-9 (0 in half, a reference below
# half's smallest normal: never wrong) and a tail NoV*300*300 = 90000 NoV, past
# 65504 for NoV > 0.728: the grid's cosines 0.9, 0.999, 0.99999 and 1, at its 13
# roughness values, are Inf in half: 52 of 143. A copy cut at 2 KB ends in "+NoV"
# and is safe in half.
P="NoV*1e-10+"; i=0
while [ $i -lt 240 ]; do P="${P}NoV*1e-9+"; i=$((i + 1)); done
[ ${#P} -gt 2100 ] && ok || bad "long form: ${#P} characters"
[ "$(stab_f16 "${P}NoV*300*300")" = "143 52" ] && ok || bad "long form: f16 $(stab_f16 "${P}NoV*300*300")"
$BK stability "${P}NoV*300*300" >"$T/out" 2>/dev/null; grep -q '^f16 ' "$T/out" && lacks "$T/out" 'safe in half as is' && ok || bad "long form called safe"
$BK stability "${P}NoV" 2>/dev/null | grep -q '^safe in half as is$' && ok || bad "long form without its tail"
# 1e5 is Inf in half and 0*Inf is NaN, where long double gives 0: wrong at all
# 143 samples, and no clamp fixes it (min(NaN, 65504) is not 0); NoV/NoV is NaN
# at NoV = 0 in long double too (13 samples): not wrong
[ "$(stab_f16 '0*(1e5*NoV)')" = "143 143" ] && ok || bad "0*(1e5*NoV): f16 $(stab_f16 '0*(1e5*NoV)')"
$BK stability '0*(1e5*NoV)' 2>/dev/null | grep -q '^guards: .*(still fails)$' && ok || bad "0*(1e5*NoV) guarded"
[ "$(stab_f16 'NoV/NoV')" = "143 0" ] && ok || bad "NoV/NoV: f16 $(stab_f16 'NoV/NoV')"
# parameters: a value for each, from pN=VALUE or the catalog (overridable)
expect_usage_error "stability p0 unset" "form uses p0 but no value was given (p0=VALUE)" $BK stability 'p0*1e5*NoV'
[ "$(stab_f16 'p0*NoV' p0=1e5)" = "143 143" ] && ok || bad "p0=1e5: f16 $(stab_f16 'p0*NoV' p0=1e5)"
$BK stability 'p0*NoV' p0=2 2>/dev/null | grep -q '^safe in half as is$' && ok || bad "p0=2"
$BK stability vf_talk_r p0=1e5 2>/dev/null | grep -q '^constants a half shader cannot hold: 1e+05 (infinite in half)$' && ok || bad "vf_talk_r p0=1e5"
expect_usage_error "stability p1 unused" "p1=VALUE has no effect" $BK stability 'p0*NoV' p0=1 p1=2
expect_usage_error "stability --all with a form" "'NoV'" $BK stability --all --out "$T/st" NoV
expect_usage_error "stability --link-prefix" "--link-prefix has no effect without --out" $BK stability NoV --link-prefix x/
# fit: the published row is at the published constant (0.5) whatever the start;
# its rmse from the closed forms: V = 0.25/(LoH^2 (1 - r^2) + r^2), F Schlick at
# f0 = 0.04, form 0.04/(4 LoH^2 (r + 0.5)), 256 x 256 cell centres, LoH from sqrt(0.1)
want=$(awk 'BEGIN { n = 256; lo = sqrt(0.1); for (j = 0; j < n; j++) for (k = 0; k < n; k++) {
	r = (j + 0.5) / n; L = lo + (k + 0.5) * (1 - lo) / n; y = 0.25 / (L*L*(1 - r*r) + r*r) * (0.04 + 0.96 * (1 - L)^5)
	e = 0.04 / (4*L*L*(r + 0.5)) - y; se += e*e }; printf "%.5g", sqrt(se / (n*n)) }')
$BK fit --target vf2d --form vf_talk_r p0=5 --out "$T/f5" >/dev/null 2>&1 && ok || bad "fit p0=5"
$BK fit --target vf2d --form vf_talk_r --out "$T/f0" >/dev/null 2>&1 && ok || bad "fit"
# metrics_row FILE ROW: every column of metrics.csv's row ROW (fails without it)
metrics_row() {
	for c in constants cost rmse weighted_rmse max_abs max_rel albedo_max_abs; do
		csv_where "$1" constants "$2" "$c" || return 1
	done
}
r5=$(metrics_row "$T/f5/metrics.csv" published) && r0=$(metrics_row "$T/f0/metrics.csv" published) && [ "$r5" = "$r0" ] &&
	ok || bad "published row depends on p0="
same_but_command "$T/f5/heatmap_published.csv" "$T/f0/heatmap_published.csv" && ok ||
	bad "published heatmap depends on p0="
got=$(csv_where "$T/f5/metrics.csv" constants published rmse | awk '{ printf "%.5g", $1 }')
[ "$got" = "$want" ] && [ "$want" = "0.02861" ] && ok || bad "published rmse $got, closed form $want"
rm -rf "$T/f5" "$T/f0"
expect_usage_error "fit digits" "--digits: expected an integer in [1, 17] or half, got '-7xyz'" \
	$BK fit --target vf2d --form vf_talk_r --digits=-7xyz --out "$T/bad"
# fits that would do nothing: a zero weight, a form without parameters
expect_usage_error "fit weight 0" "--weight '0' is not positive at any of the 4096 samples" \
	$BK fit --target vf2d --form vf_talk_r --nx 64 --nr 64 --weight 0 --out "$T/bad"
[ ! -e "$T/bad" ] && ok || bad "refused fit left $T/bad"
$BK fit --target vf2d --form LoH --out "$T/loh" >"$T/out" 2>&1 && ok || bad "fit LoH: $(cat "$T/out")"
[ "$(head -1 "$T/out")" = "fit form on vf2d: no parameters: evaluated, not fitted" ] && ok || bad "fit LoH: $(head -1 "$T/out")"
lacks "$T/out" 'converged' && ok || bad "fit LoH says converged"
want=$(awk 'BEGIN { n = 256; lo = sqrt(0.1); for (j = 0; j < n; j++) for (k = 0; k < n; k++) {
	r = (j + 0.5) / n; L = lo + (k + 0.5) * (1 - lo) / n; y = 0.25 / (L*L*(1 - r*r) + r*r) * (0.04 + 0.96 * (1 - L)^5)
	e = L - y; se += e*e }; printf "%.5g", sqrt(se / (n*n)) }')
got=$(csv_where "$T/loh/metrics.csv" constants fitted rmse | awk '{ printf "%.5g", $1 }')
[ "$got" = "$want" ] && [ -s "$T/loh/shader.c" ] && ok || bad "fit LoH rmse $got, closed form $want"
rm -rf "$T/loh"
# a step too small to take from a non-optimal point is no convergence (exit 3)
$BK fit --target vf2d --form vf_talk_r --nx 32 --nr 32 --loss huber --loss-scale 1e-300 --out "$T/ns" >/dev/null 2>&1
[ $? -eq 3 ] && ok || bad "huber 1e-300 called converged" # needs the fitter's no-step rule (h-numdet)
$BK fit --target vf2d --form vf_talk_r --nx 32 --nr 32 p0=1e308 --out "$T/ns" >/dev/null 2>&1
[ $? -eq 3 ] && ok || bad "p0=1e308 called converged" # needs the fitter's no-step rule (h-numdet)
rm -rf "$T/ns"
# options that would change nothing are refused, naming the conflict
F="--target vf2d --form vf_talk_r --nx 8 --nr 8 --out $T/bad"
expect_usage_error "fit ior" "--ior has no effect on target vf2d (it sets the exact Fresnel of target f)" $BK fit $F --ior 1.4
expect_usage_error "fit nu" "--nu has no effect on target vf2d" $BK fit $F --nu 4
expect_usage_error "fit smith" "--smith has no effect on target vf2d" $BK fit $F --smith schlick
expect_usage_error "fit f0 list" "--f0: target vf2d uses one value, got 2" $BK fit $F --f0 0.1,0.2
expect_usage_error "fit weight dnol" "--weight dnol has no effect on target vf2d" $BK fit $F --weight dnol
expect_usage_error "fit loss-scale" "--loss-scale has no effect without --loss" $BK fit $F --loss-scale 2
expect_usage_error "fit p1" "'p1=2' has no effect: the form uses p0 only" $BK fit $F p1=2
expect_usage_error "fit talk" "--talk-roughness has no effect on target vf" \
	$BK fit --target vf --form vf_talk_r --talk-roughness a --out "$T/bad"
expect_usage_error "fit f0 on f" "--f0 has no effect on target f" $BK fit --target f --form 'p0*LoH' p0=1 --f0 0.5 --out "$T/bad"
expect_usage_error "fit starts, no parameters" "--starts has no effect: the form has no parameters" \
	$BK fit --target f --form LoH --starts 3 --out "$T/bad"
# --k applies with the default index 1.5 (it used to need --ior)
$BK fit --target f --nx 8 --form 'F_schlick(f0, 1, LoH)' --k 3 --out "$T/k" >/dev/null 2>&1 &&
	grep -q 'index 1.5 + 3i' "$T/k/metrics.csv" && ok || bad "fit --k without --ior"
rm -rf "$T/k"
# compare: the same rule, and typed forms it cannot score as written
expect_usage_error "compare no-lut" "--no-lut has no effect on target vf2d" $BK compare --target vf2d --no-lut --out "$T/bad"
expect_usage_error "compare reps" "--reps has no effect with --no-time" $BK compare --target vf2d --no-time --reps 3 --out "$T/bad"
expect_usage_error "compare p0" "'p0*LoH' uses p0" $BK compare --target vf2d --out "$T/bad" 'p0*LoH'
expect_usage_error "compare input" "'NoV' reads NoV, which target vf2d does not provide" \
	$BK compare --target vf2d --nx 8 --nr 8 --no-time --out "$T/bad" NoV
[ ! -e "$T/bad" ] && ok || bad "refused commands left $T/bad"

cli_done
