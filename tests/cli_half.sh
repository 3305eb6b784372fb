#!/bin/sh
# cli_half.sh — brdfkit search --precision half (issue 23): a planted member
# not safe in half (exp2(40 f0): past half's 65504 at f0 = 1, where
# (1 - f0) = 0 makes 0 * inf a NaN; stability "no") is left off a half
# front but kept on a double one (the negative control); it stays a catalog
# row with its verdict; --start-front seeds the search with a planted
# front's members (found at the seeds' fits, not catalog rows), and what
# they reach 300 fits alone do not; vs_double.csv's best-at-cost and ratio
# recomputed here from the two front.csv; bad --start-front and --vs-front
# files exit non-zero naming FILE:LINE. Tiny searches on target f (32 cells).
# usage: sh tests/cli_half.sh path/to/brdfkit
set -u
BK=${1:?usage: cli_half.sh path/to/brdfkit}
T=$(mktemp -d /tmp/bk_cli_half_XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/lib.sh"
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }

S1='f0 + (1 - f0) * sq(sq(1 - LoH)) * (1 - LoH)'
S2='f0 + (1 - f0) * p0 * sq(sq(1 - LoH)) * (1 - LoH) * exp2(40 * f0) + p1 * LoH * sq(1 - LoH)'
run() { "$BK" search --target f --nx 32 --threads 1 "$@" >"$T/out" 2>"$T/err" || { bad "search $*: $(tail -c 300 "$T/err")"; return 1; }; }

# the two starts alone (2 fits): in double both are on the front, the planted one "no" in half
run --enum-size 0 --evals 2 --start "$S1" --start "$S2" --out "$T/d"
run --enum-size 0 --evals 2 --start "$S1" --start "$S2" --precision half --out "$T/h"
on_front() { csv_col "$1/front.csv" name | grep -qx "$2"; }
on_front "$T/d" seed_start_2 && ok || bad "double: the planted member is not on the front"
[ "$(csv_where "$T/d/front.csv" name seed_start_2 stability_half)" = no ] && ok ||
	bad "double: the planted member is not 'no' in half"
on_front "$T/h" seed_start_1 && ok || bad "half: the safe member is not on the front"
off_front() { ! on_front "$1" "$2"; }
off_front "$T/h" seed_start_2 && ok || bad "half: the member not safe in half is on the front"
expect_fail "off_front on the double front" off_front "$T/d" seed_start_2
[ "$(csv_where "$T/h/catalog.csv" name 'start 2 (refit)' stability_half)" = no ] && ok ||
	bad "half: the catalog row of the planted form lost its verdict"
grep -q '1 refitted member not safe in half was left off' "$T/h/section.html" && ok ||
	bad "half: section.html does not say what was left off"

# a half front's code is half (issue 40): GLSL mediump and float16_t, HLSL
# min16float and half, MSL half, and its "fitted error" the front's error in
# f16; a double front's stays float, in f64
g="$T/h/front/seed_start_1/shader"
grep -q '^mediump float seed_start_1(' "$g.glsl" && grep -q '^min16float seed_start_1(' "$g.hlsl" &&
	grep -q '^float16_t seed_start_1(' "${g}_f16.glsl" && grep -q '^half seed_start_1(' "${g}_f16.hlsl" &&
	grep -q '^half seed_start_1(' "$g.metal" && ok ||
	bad "half: the member's shaders are not half"
for f in "$g.glsl" "${g}_f16.glsl" "$g.hlsl" "${g}_f16.hlsl" "$g.metal" "$g.c"; do
	grep -q '^ \* precision: .* with binary16 constants\|^ \* precision: C11 float with the half code' "$f" && ok ||
		bad "half: $f does not state its precision and half constants: $(grep 'precision:' "$f")"
done
[ ! -e "$T/d/front/seed_start_1/shader_f16.glsl" ] && grep -q '^float seed_start_1(' "$T/d/front/seed_start_1/shader.metal" && ok ||
	bad "double: the member has float16 files, or its Metal is not float"
# each half file compiles: GLSL mediump as ES 3.00, float16_t under its
# extension, HLSL min16float and half (glslang's HLSL front end takes both)
{ printf '#version 300 es\nprecision highp float;\n'; cat "$g.glsl"
  printf 'uniform highp float u;\nout vec4 o;\nvoid main() { o = vec4(seed_start_1(u, u)); }\n'; } >"$T/m.frag"
glslangValidator "$T/m.frag" >"$T/glsl.log" 2>&1 && ok || bad "half: shader.glsl does not compile: $(tail -3 "$T/glsl.log")"
{ printf '#version 450\n#extension GL_EXT_shader_explicit_arithmetic_types_float16 : require\n'; cat "${g}_f16.glsl"
  printf 'layout(location = 0) in vec4 u;\nlayout(location = 0) out vec4 o;\n'
  printf 'void main() { o = vec4(seed_start_1(float16_t(u.x), float16_t(u.y))); }\n'; } >"$T/m16.frag"
glslangValidator -V -o "$T/m16.spv" "$T/m16.frag" >"$T/glsl.log" 2>&1 && ok ||
	bad "half: shader_f16.glsl does not compile: $(tail -3 "$T/glsl.log")"
for h in "$g.hlsl" "${g}_f16.hlsl"; do
	{ cat "$h"; printf 'float4 main(float4 u : TEXCOORD0) : SV_Target { return float4(seed_start_1(u.x, u.y), 0, 0, 1); }\n'; } >"$T/m.hlsl"
	glslangValidator -V -D -S frag -e main -o "$T/m.spv" "$T/m.hlsl" >"$T/hlsl.log" 2>&1 && ok ||
		bad "half: $h does not compile: $(tail -3 "$T/hlsl.log")"
done
# the half files' constants are binary16 values (tests/tools/halflit.c)
cc -std=c11 -Wall -Wextra -Werror -Ibrdf tests/tools/halflit.c -lm -o "$T/halflit" &&
	"$T/halflit" "$g.glsl" "${g}_f16.glsl" "$g.hlsl" "${g}_f16.hlsl" "$g.metal" "$g.c" >"$T/hl" && ok ||
	bad "half: a constant of the half files is no binary16 value: $(cat "$T/hl")"
e=$(csv_where "$T/h/front.csv" name seed_start_1 error)
grep -q "fitted error: rmse $(printf '%.3g' "$e") in f16" "$g.glsl" && ok ||
	bad "half: the shader's fitted error is not the front's f16 error $e: $(grep 'fitted error' "$g.glsl")"
d="$T/d/front/seed_start_1/shader"
grep -q '^highp float seed_start_1(' "$d.glsl" && grep -q 'fitted error: in f64' "$d.glsl" && ok ||
	bad "double: the member's shader is not highp, in f64"

# --start-front: a planted front (search_f_6 of a double search: rmse 2.3e-4 at
# cost 6, found there after 31,664 fits); its member, named, is fitted among
# the seeds (found_at at most the seeds' count) and is no catalog row
# (its '#' lines state what a front of these searches states: read and checked)
HEAD='# brdfkit 0.1.0 search front (refitted on the full samples)
# target: f: exact unpolarised Fresnel of index 1.5 + 0i (f0 = 0.04, the input f0 of forms) on LoH in [0, 1] (32 cell centres)
# cost: simple*1 + complex*4 after folding, sharing and multiply-add fusion (brdfkit ops); error: rmse in f64 precision on the samples'
{ echo "$HEAD"; cat <<'EOF'
name,cost,error,form,form_b,parameters
planted_f6,6,0.000234584,p0 * (p1 + (p2 + sq(sq(p3 + LoH))) * (4 + sq(p2 + sq(sq(p3 + LoH))))),,p0=0.032058;p1=-4.7171;p2=1.12995;p3=-1.15279
planted_one,0,0.3,p0,,p0=0.3
EOF
} >"$T/planted.csv"
run --evals 300 --enum-max 100 --precision half --start-front "$T/planted.csv" --vs-front "$T/planted.csv" --out "$T/s"
run --evals 300 --enum-max 100 --precision half --out "$T/s0"
nseeds=$(csv_col "$T/s/candidates.csv" seed | grep -c .)
at=$(csv_where "$T/s/candidates.csv" seed planted_f6 found_at)
[ -n "$at" ] && [ "$at" -le "$nseeds" ] && ok || bad "--start-front: planted_f6 found at '$at' (seeds: $nseeds)"
! csv_col "$T/s/catalog.csv" name | grep -q planted && ok || bad "--start-front: a front's member became a catalog row"
# reached: a front member of cost <= 6 within 2e-3 in half; 300 fits alone do not reach it
reached() { csv_cols "$1/front.csv" cost error | awk -F'\t' '$1 <= 6 && $2 <= 2e-3 { f = 1 } END { exit !f }'; }
reached "$T/s" && ok || bad "--start-front: no member of cost <= 6 within 2e-3"
expect_fail "reached without --start-front" reached "$T/s0"

# --start-front twice (issue 38's merged fronts): the members of both files
# are seeds, a form on both is seeded once, and a front's member is written
# under the run's own name (search_f_K: two fronts may both hold a
# search_f_3); a merge of the seeds alone (--enum-size 0 --evals 1) keeps
# each file's best at its cost: planted_f6's 2.3e-4 at cost 6, which is on
# the second file only. Control: the first file alone does not reach it.
{ echo "$HEAD"; printf 'name,cost,error,form,form_b,parameters\nplanted_one,0,0.3,p0,,p0=0.3\n'; } >"$T/fa.csv"
{ echo "$HEAD"; printf 'name,cost,error,form,form_b,parameters\nplanted_one,0,0.3,p0,,p0=0.2\n'
  grep '^planted_f6,' "$T/planted.csv"; } >"$T/fb.csv"
run --enum-size 0 --evals 1 --start-front "$T/fa.csv" --start-front "$T/fb.csv" --out "$T/m2"
run --enum-size 0 --evals 1 --start-front "$T/fa.csv" --out "$T/m1"
merged() { csv_cols "$1/front.csv" cost error | awk -F'\t' '$1 <= 6 && $2 <= 2.35e-4 { f = 1 } END { exit !f }'; }
merged "$T/m2" && ok || bad "--start-front twice: the second file's cost-6 member is not on the merged front"
expect_fail "merged from the first file alone" merged "$T/m1"
[ "$(csv_col "$T/m2/candidates.csv" seed | grep -c '^planted')" -eq 2 ] && ok ||
	bad "--start-front twice: 'p0' on both files not seeded once: $(csv_col "$T/m2/candidates.csv" seed | grep planted | tr '\n' ' ')"
csv_col "$T/m2/front.csv" name | grep -q '^search_f_[0-9]*$' && ! csv_col "$T/m2/front.csv" name | grep -q planted && ok ||
	bad "--start-front twice: a front's member kept its old name: $(csv_col "$T/m2/front.csv" name | tr '\n' ' ')"

# vs_double.csv recomputed: at each cost <= 16 of either front, the least
# error of each front at that cost or below, the ratio and the pass
check_vs() { # DOUBLE_FRONT HALF_DIR
	csv_cols "$1" cost error >"$T/dd" && csv_cols "$2/front.csv" cost error >"$T/hh" &&
		csv_cols "$2/vs_double.csv" cost double_error half_error ratio pass >"$T/vv" || return 1
	awk -F'\t' 'FILENAME == ARGV[1] { dc[++nd] = $1; de[nd] = $2; next }
	     FILENAME == ARGV[2] { hc[++nh] = $1; he[nh] = $2; next }
	     { c = $1; bd = -1; bh = -1
	       for (i = 1; i <= nd; i++) if (dc[i] <= c && (bd < 0 || de[i] < bd)) bd = de[i]
	       for (i = 1; i <= nh; i++) if (hc[i] <= c && (bh < 0 || he[i] < bh)) bh = he[i]
	       if (bd < 0 || bh < 0 || $2 != bd || $3 != bh) { bad = 1; exit }
	       r = bh / bd; if ($4 - r > 1e-5 * r || r - $4 > 1e-5 * r) { bad = 1; exit }
	       if ($5 != (r <= 1.25)) { bad = 1; exit }
	       n++ }
	     END { exit bad || !(n > 0) }' "$T/dd" "$T/hh" "$T/vv"
}
check_vs "$T/planted.csv" "$T/s" && ok || bad "vs_double.csv does not match the two fronts"
# the negative control: the same check against another double front
csv_set "$T/planted.csv" error name planted_f6 0.0001 >"$T/planted2.csv" || bad "csv_set"
expect_fail "check_vs on a changed double front" check_vs "$T/planted2.csv" "$T/s"
# at cost 6 the half front cannot be within 1.25x of 2.3e-4 (half's rounding alone): a failing row
[ "$(csv_where "$T/s/vs_double.csv" cost 6 pass)" = 0 ] && ok || bad "vs_double.csv: cost 6 passes"
grep -q 'costs &le; 16 the half front' "$T/s/section.html" && ok || bad "section.html: no side-by-side table"

# the half grid: f_glass's cost-6 member (constants that cancel: p1 = -4.7
# against a product near 4.7), refitted in a half search, holds constants a
# half shader can hold exactly (each x = m 2^e with |m| < 2048, checked here in
# awk, not by brdfkit), and its max error in half is below that of the double
# least-squares point rounded to half (the same metric, f16_max_abs, of the
# same form refitted in a double search). Controls: the double point is not on
# the grid; the comparison reversed fails.
F6='p0 * (p1 + (p2 + sq(sq(p3 + LoH))) * (4 + sq(p2 + sq(sq(p3 + LoH)))))'
"$BK" search --target f --start "$F6" --enum-size 0 --evals 1 --threads 1 --out "$T/g64" >/dev/null 2>&1
"$BK" search --target f --start "$F6" --enum-size 0 --evals 1 --threads 1 --precision half --out "$T/g16" >/dev/null 2>&1
on_half_grid() {
	csv_where "$1/front.csv" name seed_start_1 parameters | tr ';' '\n' | sed 's/^p[0-9]*=//' |
		awk '{ x = $1 < 0 ? -$1 : $1; if (x == 0) next; e = 0; while (x >= 2048) { x /= 2; e++ }
		       while (x < 1024 && e > -24) { x *= 2; e-- } if (x != int(x)) bad = 1; n++ }
		     END { exit bad || n != 4 }'
}
on_half_grid "$T/g16" && ok || bad "half grid: the half search's constants are not half values: $(csv_where "$T/g16/front.csv" name seed_start_1 parameters)"
expect_fail "on_half_grid of the double point" on_half_grid "$T/g64"
h16=$(csv_where "$T/g16/front.csv" name seed_start_1 f16_max_abs)
h64=$(csv_where "$T/g64/front.csv" name seed_start_1 f16_max_abs)
below() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a + 0 > 0 && a + 0 < b + 0) }'; }
below "$h16" "$h64" && ok || bad "half grid: max error in half $h16 is not below the double point's $h64"
expect_fail "the reversed comparison" below "$h64" "$h16"

# a checkpoint records the seeds: a resume with the same --start-front goes on,
# with another front (or none) it is refused
run --evals 300 --enum-max 100 --precision half --start-front "$T/planted.csv" --checkpoint "$T/ck" --out "$T/c1"
run --evals 600 --enum-max 100 --precision half --start-front "$T/planted.csv" --resume "$T/ck" --out "$T/c2" &&
	grep -q "resumed at" "$T/err" && ok || bad "resume with the same --start-front refused"
grep -v planted_f6 "$T/planted.csv" >"$T/planted3.csv"
for other in "--start-front $T/planted3.csv" ""; do
	# shellcheck disable=SC2086 # two words or none
	"$BK" search --target f --nx 32 --threads 1 --evals 600 --enum-max 100 --precision half $other --resume "$T/ck" \
		--out "$T/c3" >/dev/null 2>"$T/err"
	[ $? -eq 1 ] && grep -q "other options" "$T/err" && ok || bad "resume with '$other' accepted: $(cat "$T/err")"
done

# bad files: one line naming FILE:LINE, non-zero exit, no --out
expect_error() { # NAME TOKEN ARGS...
	name=$1 token=$2; shift 2
	"$BK" search --target f --nx 32 --threads 1 --evals 10 --precision half "$@" --out "$T/bad" >/dev/null 2>"$T/err"
	st=$?
	if [ "$st" -ne 0 ] && [ "$(wc -l <"$T/err")" -eq 1 ] && grep -qF -- "$token" "$T/err" && [ ! -e "$T/bad" ]; then ok
	else bad "$name: exit $st, stderr: $(head -c 300 "$T/err")"; fi
}
printf '# x\nname,form,form_b\nx,LoH,\n' >"$T/nocol.csv"
printf 'name,form,form_b,parameters\nx,LoH,,\ny,LoH * (p0,,p0=1\n' >"$T/badform.csv"
{ echo "$HEAD"; printf 'name,form,form_b,parameters\nx,NoV * LoH,,\n'; } >"$T/input.csv"
printf 'name,cost,error\nx,1,oops\n' >"$T/vsbad.csv"
{ echo "$HEAD"; printf 'name,form,form_b,parameters\nx,LoH,,\nx,LoH * LoH,,\n'; } >"$T/twice.csv"
expect_error "missing column" "$T/nocol.csv:2: no column 'parameters'" --start-front "$T/nocol.csv"
expect_error "bad form" "$T/badform.csv:3: form: column" --start-front "$T/badform.csv"
expect_error "input not provided" "$T/input.csv:5: x: the form reads an input" --start-front "$T/input.csv"
expect_error "a name twice" "$T/twice.csv:6: the name 'x' is on line 5 already" --start-front "$T/twice.csv"
expect_error "missing file" "$T/none.csv: cannot be read" --start-front "$T/none.csv"
expect_error "bad --vs-front" "$T/vsbad.csv:2: error:" --vs-front "$T/vsbad.csv"
"$BK" search --target f --evals 10 --vs-front "$T/planted.csv" --out "$T/bad" >/dev/null 2>&1
[ $? -eq 2 ] && ok || bad "--vs-front without --precision half accepted"

# the committed fronts hold (issue 38, make results' merges): env_f0 and
# env_mix answer one question (env as one form in f0, rmse in f64), and each
# merged the other's runs, so at every cost <= 15 their staircases (the least
# error at that cost or below) are one, to the refit's last digits; the same
# of their half fronts (rmse in f16). Control: env (split pairs A, B: another
# question, searched alone) differs from env_f0 there.
R="$(dirname "$0")/../results/search"
same_below_15() { # FRONT_A FRONT_B
	csv_cols "$1" cost error >"$T/sa" && csv_cols "$2" cost error >"$T/sb" || return 1
	awk -F'\t' 'FILENAME == ARGV[1] { ac[++na] = $1; ae[na] = $2; next }
	     { bc[++nb] = $1; be[nb] = $2 }
	     function best(n, c, e, x,   i, b) { b = -1; for (i = 1; i <= n; i++) if (c[i] <= x && (b < 0 || e[i] < b)) b = e[i]; return b }
	     END { for (x = 0; x <= 15; x++) { a = best(na, ac, ae, x); b = best(nb, bc, be, x)
	             if ((a < 0) != (b < 0)) exit 1
	             if (a >= 0 && (a - b > 1e-4 * b || b - a > 1e-4 * a)) exit 1; n++ }
	           exit !(n == 16) }' "$T/sa" "$T/sb"
}
same_below_15 "$R/env_f0/front.csv" "$R/env_mix/front.csv" && ok || bad "committed env_f0 and env_mix differ at a cost <= 15"
same_below_15 "$R/env_f0_half/front.csv" "$R/env_mix_half/front.csv" && ok ||
	bad "committed env_f0_half and env_mix_half differ at a cost <= 15"
expect_fail "same_below_15 of env and env_f0" same_below_15 "$R/env/front.csv" "$R/env_f0/front.csv"

echo "cli_half: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
