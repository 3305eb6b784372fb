#!/bin/sh
# render.sh — brdfkit render on Mesa's lavapipe against the same scene
# rendered from the IR on the CPU (--device cpu), a planted fp16 artefact
# where brdfkit stability says it will be, and bad input. Small images (64x32,
# four roughness columns): lavapipe's pipeline creation and the CPU's
# prefilter dominate.
#
# (a) The exact shading in f32 on lavapipe agrees with the IR in double at
#     the same float inputs within REL = 2^-16 relative (+ 2^-24 absolute):
#     a pixel is about 40 f32 operations (D, V, F, the split sum, the
#     shading), each within 3 ulp of the exact result of its operands
#     (Vulkan: add and mul correctly rounded, division 2.5 ulp, sqrt and
#     inversesqrt within 3), 2^-23 relative per ulp, in forms that add
#     positive terms (condition about 1; 1 - LoH is exact): 120 ulp < 2^7 ulp
#     = 2^-16. The f16 images agree with the IR's BK_F16 within 2^-9 relative
#     (two half ulps; the operations run in the same order). Negative
#     controls: the CPU render at another roughness (1 -> 0.99), and D with a
#     constant 1.0001 times, fail it.
# (b) A V·F candidate with an intermediate 1/a^3 (1e6 at r = 0.1, past half's
#     65504): its f16 image has non-finite pixels beyond the exact f16
#     image's in the spheres whose r is below the roughness brdfkit
#     stability finds safe (r_min), none extra in the others, and none in f32.
# (c) Bad input: one line, exit 2 (1 for a missing driver, naming the package).
# usage: sh tests/render.sh build/brdfkit   (needs build/csvget, build/exrcmp)
set -u
B=${1:?usage: render.sh build/brdfkit}
T=$(mktemp -d /tmp/bk_render_XXXXXX)
trap 'rm -rf "$T"' EXIT
CSVGET=${CSVGET:-build/csvget}
EXRCMP=${EXRCMP:-build/exrcmp}
. tests/lib.sh
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
S="--size 64 --roughness 0.1,0.4,0.7,1"
REL=0.0000152587890625 # 2^-16
ABS=0.000000059604644775390625 # 2^-24
REL16=0.001953125 # 2^-9

# run NAME ARGS...: brdfkit render into $T/NAME, its stdout in $T/NAME.log
run() {
	n=$1; shift
	# shellcheck disable=SC2086
	"$B" render "$@" --out "$T/$n" >"$T/$n.log" 2>&1 || bad "render $n: $(cat "$T/$n.log")"
}
# cmp_ok WHAT A B REL ABS; cmp_fails WHAT A B REL ABS
cmp_ok() { "$EXRCMP" "$2" "$3" "$4" "$5" >"$T/cmp" 2>&1 && ok || bad "$1: $(cat "$T/cmp")"; }
cmp_fails() {
	"$EXRCMP" "$2" "$3" "$4" "$5" >"$T/cmp" 2>&1
	[ $? -eq 1 ] && ok || bad "control '$1' passed: $(cat "$T/cmp")"
}

# ---- (a) lavapipe against the IR ---------------------------------------------------
# shellcheck disable=SC2086
run gpu --form vf_talk_r $S
# shellcheck disable=SC2086
run cpu --form vf_talk_r $S --device cpu
for f in exact.exr candidate_f32.exr exact.png candidate_f16.exr diff_f32.png diff_f16.png spheres.csv \
	section.html shader_f32.comp shader_f16.comp; do
	[ -s "$T/gpu/$f" ] && ok || bad "no $f"
done
grep -q 'float16_t' "$T/gpu/shader_f16.comp" && grep -q 'bk_cand(' "$T/gpu/shader_f32.comp" && ok ||
	bad "the shaders do not call the candidate or the f16 one has no float16_t"
cmp_ok "exact f32, lavapipe vs the IR" "$T/cpu/exact.exr" "$T/gpu/exact.exr" $REL $ABS
cmp_ok "candidate f32, lavapipe vs the IR" "$T/cpu/candidate_f32.exr" "$T/gpu/candidate_f32.exr" $REL $ABS
cmp_ok "exact f16, lavapipe vs the IR" "$T/cpu/exact_f16.exr" "$T/gpu/exact_f16.exr" $REL16 $ABS
cmp_ok "candidate f16, lavapipe vs the IR" "$T/cpu/candidate_f16.exr" "$T/gpu/candidate_f16.exr" $REL16 $ABS
# the comparison is not vacuous: the candidate differs from the exact image
cmp_fails "candidate vs exact" "$T/gpu/exact.exr" "$T/gpu/candidate_f32.exr" $REL $ABS
# negative controls: another roughness, a perturbed constant
# shellcheck disable=SC2086
run wrong_r --form vf_talk_r --size 64 --roughness 0.1,0.4,0.7,0.99 --device cpu --precision single
cmp_fails "roughness 0.99 for 1" "$T/wrong_r/exact.exr" "$T/gpu/exact.exr" $REL $ABS
# shellcheck disable=SC2086
run perturbed --form 'D_ggx(NoH, a)*1.0001' --term d $S --device cpu --precision single
cmp_fails "D x 1.0001" "$T/perturbed/candidate_f32.exr" "$T/gpu/exact.exr" $REL $ABS
# determinism: the same command writes the same bytes
mv "$T/gpu" "$T/gpu1"
# shellcheck disable=SC2086
run gpu --form vf_talk_r $S
same=1
for f in "$T"/gpu1/* "$T/gpu1/.brdfkit-output"; do cmp -s "$f" "$T/gpu/${f##*/}" || { same=0; echo "differs: ${f##*/}"; }; done
[ "$same" -eq 1 ] && ok || bad "a second run wrote other bytes"
# the EXR and PNG state their conventions and provenance
grep -q 'brdfkit:conventions' "$T/gpu/exact.exr" && grep -q 'Reinhard' "$T/gpu/diff_f32.png" &&
	grep -q 'Command' "$T/gpu/exact.png" && ok || bad "conventions missing from the EXR or PNG headers"

# ---- (b) a planted fp16 overflow where stability says ------------------------------
P='f0/(4*LoH*LoH*(r + 0.5))*(1 + (1/(a*a*a))*1e-7)'
"$B" stability "$P" --out "$T/stab" >/dev/null 2>&1 || bad "stability on the planted form failed"
rmin=$(csv_col "$T/stab/stability.csv" r_min)
case $rmin in
'' | *[!0-9.e-]*) bad "stability gives no r_min for the planted form: '$rmin'"; rmin=0 ;;
esac
# shellcheck disable=SC2086
run planted --form "$P" --term vf $S
csv_cols "$T/planted/spheres.csv" r nonfinite_exact_f16 nonfinite_candidate_f16 nonfinite_candidate_f32 \
	>"$T/sph" || bad "spheres.csv: columns"
below=0 above=0
while IFS="$(printf '\t')" read -r r ex c16 c32; do
	[ "$c32" -eq 0 ] || bad "planted: $c32 non-finite f32 pixels at r = $r"
	if awk -v r="$r" -v m="$rmin" 'BEGIN { exit !(r < m) }'; then
		below=$((below + 1))
		[ "$c16" -gt "$ex" ] && ok || bad "planted: r = $r < r_min $rmin: f16 non-finite $c16, exact f16 $ex"
	else
		above=$((above + 1))
		[ "$c16" -eq "$ex" ] && ok || bad "planted: r = $r >= r_min $rmin: f16 non-finite $c16, exact f16 $ex"
	fi
done <"$T/sph"
[ "$below" -eq 2 ] && [ "$above" -eq 6 ] && ok || bad "planted: $below spheres below r_min $rmin, $above above (want 2, 6)"
# the control: vf_talk_r itself adds nothing non-finite to the exact f16 image
csv_cols "$T/gpu/spheres.csv" nonfinite_exact_f16 nonfinite_candidate_f16 >"$T/sph0" || bad "spheres.csv"
awk -F '\t' '$1 != $2 { bad = 1 } END { exit bad }' "$T/sph0" && ok || bad "vf_talk_r shows non-finite f16 pixels of its own"

# ---- (c) bad input: one line --------------------------------------------------------
# expect RC PATTERN ARGS...
expect() {
	want=$1 pat=$2; shift 2
	"$B" render "$@" >"$T/out" 2>"$T/err"
	rc=$?
	if [ "$rc" -eq "$want" ] && [ "$(wc -l <"$T/err")" -eq 1 ] && grep -q -- "$pat" "$T/err"; then ok
	else bad "render $*: exit $rc (want $want), stderr '$(cat "$T/err")' (want '$pat')"; fi
}
expect 2 "column" --form 'D_ggx(NoH' --term d --out "$T/x"
expect 2 "needs --term" --form 'NoH*2' --out "$T/x"
expect 2 "expected vf2d" --form vf_talk_r --term q --out "$T/x"
expect 2 "p0" --form 'p0*NoH' --term d --out "$T/x"
expect 2 "parameters" --form vf_talk_r --params 'p0=abc' --out "$T/x"
expect 2 "only for --term env" --form 'NoH' --form-b 'NoV' --term d --out "$T/x"
expect 2 "one of --form and --batch" --out "$T/x"
printf 'name,term,form\n../evil,vf,vf_talk_r\n' >"$T/b.csv"
expect 2 "name '../evil'" --batch "$T/b.csv" --out "$T/x"
printf 'name,form\nx,vf_talk_r\n' >"$T/b2.csv"
expect 2 "no column 'term'" --batch "$T/b2.csv" --out "$T/x"
# shellcheck disable=SC2086
VK_ICD_FILENAMES=/nonexistent/lvp_icd.json expect 1 "mesa-vulkan-drivers" --form vf_talk_r $S --out "$T/x"
[ ! -e "$T/x" ] && ok || bad "a failed render left --out behind"

# a batch: one directory per row and one section for all
printf 'name,term,form,form_b,parameters\ntalk,,vf_talk_r,,\nkaris,,env_karis2014_split,,\nmine,env,p0,p1,p0=1;p1=0.1\n' >"$T/b3.csv"
# shellcheck disable=SC2086
run batch --batch "$T/b3.csv" $S --precision half --link-prefix 'r/<x>/'
for n in talk karis mine; do [ -s "$T/batch/$n/candidate_f16.png" ] && ok || bad "batch: no $n/candidate_f16.png"; done
[ "$(grep -c '<tr><th colspan' "$T/batch/section.html")" -eq 3 ] && grep -q 'r/%3Cx%3E/karis/candidate_f16.png' "$T/batch/section.html" && grep -q 'r/%3Cx%3E/exact_f16.png' "$T/batch/section.html" && [ -s "$T/batch/exact_f16.exr" ] && [ ! -e "$T/batch/talk/exact_f16.exr" ] &&
	! grep -q '<x>' "$T/batch/section.html" && ok || bad "batch section: rows or escaping"

echo "render: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
