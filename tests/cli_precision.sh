#!/bin/sh
# cli_precision.sh — where the precision cannot hold the result (issue 39,
# item 2): codegen and fit warn about a result out of the emitted precision's
# range at every sample (M3); lut --specular refuses a scale whose texels or
# shader constant are not normal float32s, and its EXR agrees with its CSV
# (H3); render's f16 summary does not read better for its non-finite pixels
# (L7). Each check has its negative control.
# usage: sh tests/cli_precision.sh path/to/brdfkit
set -u
BK=${1:?usage: cli_precision.sh path/to/brdfkit}
case $BK in /*) ;; *) BK=$(pwd)/$BK ;; esac
ROOT=$(pwd)
CSVGET=${CSVGET:-$ROOT/build/csvget}
T=$(mktemp -d /tmp/bk_precision_XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$ROOT/tests/lib.sh"
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
cd "$T" || exit 1

# warns NAME TOKEN CMD...: exit 0, output written, exactly one stderr line
# holding TOKEN. quiet NAME CMD...: exit 0 and nothing on stderr.
warns() {
	name=$1 token=$2; shift 2
	"$@" >out 2>err; rc=$?
	[ $rc -eq 0 ] && [ "$(wc -l <err)" -eq 1 ] && grep -qF -- "$token" err && ok \
		|| bad "$name: exit $rc, stderr '$(cat err)'"
}
quiet() {
	name=$1; shift
	"$@" >out 2>err; rc=$?
	[ $rc -eq 0 ] && [ ! -s err ] && ok || bad "$name: exit $rc, stderr '$(cat err)'"
}
# refused NAME RC TOKEN CMD...: exit RC, one stderr line holding TOKEN.
refused() {
	name=$1 want=$2 token=$3; shift 3
	"$@" >out 2>err; rc=$?
	[ $rc -eq "$want" ] && [ "$(wc -l <err)" -eq 1 ] && grep -qF -- "$token" err && ok \
		|| bad "$name: exit $rc (want $want), stderr '$(cat err)'"
}

# ---- M3: a result the emitted precision cannot hold at any sample ---------------
LOST="the result is out of"
warns "f32 overflow" "out of single precision's range at every one of the 5 samples" \
	"$BK" codegen --lang c '(NoV+1e38)*(NoV+1e38)'
grep -qF "(NoV = 0: 1e+76 is +inf in single precision)" err && ok || bad "f32 overflow: $(cat err)"
warns "f16 overflow" "out of half precision's range at every one of the 5 samples" \
	"$BK" codegen --lang glsl --precision half '(NoV+300)*(NoV+300)'
grep -qF "(NoV = 0: 90000 is +inf in half precision)" err && ok || bad "f16 overflow: $(cat err)"
warns "hlsl half overflow" "$LOST half" "$BK" codegen --lang hlsl --precision half '(NoV+300)*(NoV+300)'
warns "f32 underflow" "1e-40 is subnormal in single precision" \
	"$BK" codegen --lang c '((NoV+1)*1e-20)*((NoV+1)*1e-20)'
warns "f16 underflow" "is subnormal in half precision" \
	"$BK" codegen --lang glsl --precision half '((NoV+1)*0.001)*((NoV+1)*0.001)'
# a sample where double is 0 (and the precision too) does not count: lost at the other 4
warns "zero at NoV = 0" "at every one of the 4 samples" "$BK" codegen --lang c '(NoV*1e30)*(NoV*1e30)'
# negative controls: overflow at some samples only; in range; the same form in
# single precision; a catalog form
quiet "f16 overflow at NoV = 1 only" "$BK" codegen --lang glsl --precision half '(NoV*300)*(NoV*300)'
quiet "f32 in range" "$BK" codegen --lang c '(NoV+1e19)*(NoV+1e19)'
quiet "300 in single" "$BK" codegen --lang glsl '(NoV+300)*(NoV+300)'
quiet "catalog form in half" "$BK" codegen --lang glsl --precision half vf_talk_r
# the rule's other half stays a refusal: NaN or infinite everywhere in double
refused "nowhere finite" 2 "NaN or infinite everywhere" "$BK" codegen --lang c 'sqrt(NoV-2)'
# a fit's shaders get the same warning (the fitted form underflows in float;
# the fit itself cannot move it: exit 3, did not converge, results written)
"$BK" fit --target f --form '(LoH+p0)*1e-25*(LoH+p0)*1e-25' p0=1 --out fq >out 2>err; rc=$?
[ $rc -eq 3 ] && [ "$(wc -l <err)" -eq 1 ] && grep -qF "brdfkit fit: warning: brdfkit_fit: $LOST single" err && ok \
	|| bad "fit shaders: exit $rc, stderr '$(cat err)'"
[ -s fq/shader.c ] && ok || bad "fit: no shader.c"
# gpucost compiles the form in the precision asked: the same warning, the same control
warns "gpucost half" "brdfkit gpucost: warning: form1: $LOST half" \
	"$BK" gpucost --quiet --precision half '(NoV+300)*(NoV+300)'
quiet "gpucost single" "$BK" gpucost --quiet '(NoV+300)*(NoV+300)'
warns "time" "brdfkit time: warning: form1: $LOST single" "$BK" time --quiet --reps 1 '(NoV+1e38)*(NoV+1e38)'
quiet "fit in range" "$BK" fit --target f --form 'p0 + (1-p0)*pow(1-LoH, 5)' p0=0.04 --out fr

# ---- H3: lut --specular --scale where a texel or the constant is not a normal float
refused "scale 1e-300" 2 "--scale 1e-300: 4096 of 4096 texels are +inf in float32" \
	"$BK" lut --specular --scale 1e-300 --out ls1
refused "scale 1e-38" 2 "--scale 1e-38: 39 of 4096 texels are +inf in float32" \
	"$BK" lut --specular --scale 1e-38 --out ls2
refused "scale 1e-45" 2 "--scale 1e-45: 4043 of 4096 texels" "$BK" lut --specular --scale 1e-45 --out ls3
refused "sweep at 1e-300" 2 "--scale 1e-300" "$BK" lut --specular --sweep --scale 1e-300 --out ls4
for d in ls1 ls2 ls3 ls4; do [ ! -e $d ] && ok || bad "$d written"; done
# the bound the message states is the data's: at it the LUT is written, below it not
lo=$(sed -n 's/.*scale in \[\([^,]*\),.*/\1/p' err)
[ -n "$lo" ] && ok || bad "no bound in '$(cat err)'"
quiet "scale at the bound $lo" "$BK" lut --specular --scale "$lo" --out ls5
below=$(awk -v l="$lo" 'BEGIN { printf "%.3g", l/1.02 }')
refused "scale below the bound ($below)" 2 "texels are +inf" "$BK" lut --specular --scale "$below" --out ls6
# negative control: the default scale, every float finite and equal to the CSV's
quiet "default scale" "$BK" lut --specular --out ls7
[ "$(csv_col ls5/spec.csv float | grep -civ '^[0-9.e+-]*$')" -eq 0 ] && ok || bad "ls5 csv: a float not a number"

# ---- M5: the sweep's ranking tells a LUT of zeros from the best ----------------
# --scale 1e6 makes every 8-bit code 0 (the largest intensity is about 20): the
# given LUT outputs 0. It must score 1 on the ranking column and clearly worse
# (by a fifth or more) than the best.
clearly_worse() { # FILE COLUMN: the given row's COLUMN >= 1.2 x the best row's
	g=$(csv_where "$1" role given "$2") && b=$(csv_where "$1" role best "$2") &&
		awk -v g="$g" -v b="$b" 'BEGIN { exit !(g + 0 >= 1.2 * b && b + 0 > 0) }'
}
for fr in none schlick; do
	"$BK" lut --specular --sweep --fresnel $fr --scale 1e6 --quiet --out z_$fr >out 2>err && ok || bad "sweep $fr: $(cat err)"
	[ "$(csv_where z_$fr/sweep.csv role given albedo_rel_rms)" = 1 ] && ok \
		|| bad "zeros ($fr): albedo_rel_rms $(csv_where z_$fr/sweep.csv role given albedo_rel_rms), not 1"
	clearly_worse z_$fr/sweep.csv albedo_rel_rms && ok || bad "zeros ($fr) not clearly worse than the best"
	# negative control: the absolute rms (the old ranking) has them within 10 %
	expect_fail "absolute rms ($fr)" clearly_worse z_$fr/sweep.csv albedo_rms
done
# the given LUT really is zeros: every code of its PNG's CSV column is 0
[ "$(csv_col z_none/spec.csv unorm8 | sort -u)" = 0 ] && ok || bad "scale 1e6: codes not all 0"

# ---- L7: render's summary does not read better for non-finite pixels ------------
# exp2(1000*(r-0.5)) overflows half at r = 0.6 (450 f16 pixels +inf): f16's
# difference there is the whole display range, 1, not the 1e-4 of the few
# finite pixels; at r = 0.1 (all finite) it stays what it was.
"$BK" render --form 'exp2(1000*(r-0.5))' --term vf --size 40 --roughness 0.1,0.6 --out rg >out 2>err && ok \
	|| bad "render: $(cat err)"
grep -qF "f16 450 (exact f16 0)" out && ok || bad "render: not 450 non-finite: $(cat out)"
grep -qF "f16 display difference max 1 " out && ok || bad "render: f16 summary $(cat out)"
# per sphere: not finite somewhere -> max 1 and mean >= f32's; the rule's
# negative control: all finite -> below 1
sphere_rule() { # FILE: every sphere with non-finite f16 pixels has max_diff_f16 1, mean_diff_f16 >= mean_diff_f32
	csv_cols "$1" nonfinite_candidate_f16 max_diff_f16 mean_diff_f16 mean_diff_f32 |
		awk -F '\t' '$1 > 0 { n++; if ($2 != 1 || $3 < $4) bad = 1 } END { exit !(n > 0 && !bad) }'
}
sphere_rule rg/spheres.csv && ok || bad "spheres.csv: $(cat rg/spheres.csv | tail -4)"
csv_cols rg/spheres.csv nonfinite_candidate_f16 max_diff_f16 |
	awk -F '\t' '$1 == 0 { n++; if ($2 >= 1) bad = 1 } END { exit !(n > 0 && !bad) }' && ok \
	|| bad "finite spheres read 1"
# the check refuses the old summary (non-finite pixels left out: max 9.8e-5)
csv_set rg/spheres.csv max_diff_f16 col 1 9.8091e-05 >old.csv && ok || bad "csv_set spheres.csv"
expect_fail "summary without the non-finite pixels" sphere_rule old.csv

# the same rule in stability's largest relative error: the same form is +inf
# in half and single at r = 0.7 and 1, so max_rel is inf there, not the 0 of
# the finite samples; double (finite everywhere) keeps its number
"$BK" stability 'exp2(1000*(r-0.5))' --quiet --out st >out 2>err && ok || bad "stability: $(cat err)"
maxrel_inf() { # FILE PREC: PREC's max_rel is inf where its inf column is not 0
	i=$(csv_where "$1" precision "$2" inf) && m=$(csv_where "$1" precision "$2" max_rel) &&
		[ "$i" -gt 0 ] && [ "$m" = inf ]
}
for p in f16 f32; do maxrel_inf st/details.csv $p && ok || bad "details.csv $p: $(grep "^form,.*,$p," st/details.csv)"; done
m=$(csv_where st/details.csv precision f64 max_rel)
awk -v m="$m" 'BEGIN { exit !(m + 0 > 0 && m + 0 < 1e-12) }' && ok || bad "f64 max_rel '$m'"
[ "$(csv_col st/stability.csv f16_max_rel)" = inf ] && ok || bad "stability.csv f16_max_rel $(csv_col st/stability.csv f16_max_rel)"
csv_set st/details.csv max_rel precision f16 0 >old2.csv && ok || bad "csv_set details.csv"
expect_fail "max_rel without the non-finite samples" maxrel_inf old2.csv f16

echo "cli_precision: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
