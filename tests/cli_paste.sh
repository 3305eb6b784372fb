#!/bin/sh
# cli_paste.sh — a front member pasted by name (issue 40 item 2): FILE.csv:NAME
# is a form wherever eval, ops, codegen, stability, time, gpucost, render and
# fit (its start) take one (one reader, analysis/cli/member.c), with the member's
# parameters baked in and, for codegen, its provenance (source, fitted domain
# and error) from the front.csv; a split-sum member is FILE.csv:NAME:A or :B.
# Each check has a negative control that shows it can fail.
# usage: sh tests/cli_paste.sh path/to/brdfkit   (from the repository root)
set -u
BK=${1:?usage: sh tests/cli_paste.sh path/to/brdfkit}
T=$(mktemp -d /tmp/bk_cli_paste_XXXXXX)
trap 'rm -rf "$T"' EXIT
CSVGET=${CSVGET:-build/csvget}
EXRCMP=${EXRCMP:-build/exrcmp}
. tests/lib.sh
pass=0 fail=0

ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }

VF=results/search/vf2d/front.csv
ENV=results/search/env/front.csv

# inputs FORM: NAME=VALUE for each input FORM reads (a = r*r where both are read).
inputs() {
	for _w in NoV:0.6 LoH:0.7 r:0.5 a:0.25 f0:0.04; do
		if echo "$1" | grep -q "\(^\|[^A-Za-z0-9_]\)${_w%:*}\([^A-Za-z0-9_(]\|$\)"; then printf ' %s=%s' "${_w%:*}" "${_w#*:}"; fi
	done
}

# body FILE: the generated function after the provenance comment.
body() { sed -n '/^ \*\//,$p' "$1" | tail -n +2; }

# same_code MEMBER FORM PARAMS: the member's C (its front's one signature,
# its constants named) and FORM's with PARAMS ("p0=X;p1=Y"; the inputs FORM
# reads, literals) compute the same float, bit for bit, at 64 points: the
# named constants hold the same values and the expression is the same.
args_of() { sed -n "s/^static inline float $1(\(.*\))\$/\1/p" "$2" | sed 's/float //g'; }
same_code() {
	# shellcheck disable=SC2046 # PARAMS are words pN=VALUE
	"$BK" codegen --lang c --name mfun "$1" >"$T/m.c" &&
		"$BK" codegen --lang c --name ffun "$2" $(echo "$3" | tr ';' ' ') >"$T/f.c" || return 1
	cat >"$T/same.c" <<-EOC
	#include <stdio.h>
	#include "m.c"
	#include "f.c"
	int main(void)
	{
		for (int i = 0; i < 64; i++) {
			float NoV = 0.01f + 0.0155f * (float)i, NoL = 0.9f - 0.013f * (float)i, NoH = 0.5f + 0.007f * (float)i;
			float LoH = 0.32f + 0.0106f * (float)i, VoH = LoH, r = 0.03f + 0.015f * (float)i, a = r * r, f0 = 0.04f;
			(void)NoV, (void)NoL, (void)NoH, (void)LoH, (void)VoH, (void)r, (void)a, (void)f0;
			printf("%a %a\\n", (double)mfun($(args_of mfun "$T/m.c")), (double)ffun($(args_of ffun "$T/f.c")));
		}
		return 0;
	}
	EOC
	cc -std=c11 -O1 -ffp-contract=off -o "$T/same" "$T/same.c" -lm 2>"$T/cc.err" && "$T/same" >"$T/same.txt" &&
		[ "$(wc -l <"$T/same.txt")" -eq 64 ] && awk '$1 != $2 { exit 1 }' "$T/same.txt"
}

# same_eval MEMBER FORM ARGS...: eval of the member and of FORM with ARGS
# (pN=VALUE, inputs) print the same three lines at the inputs FORM reads.
same_eval() {
	_m=$1 _f=$2; shift 2
	# shellcheck disable=SC2046 # inputs are words NAME=VALUE
	"$BK" eval "$_m" $(inputs "$_f") >"$T/m.txt" && "$BK" eval "$_f" "$@" $(inputs "$_f") >"$T/f.txt" || return 1
	[ "$(wc -l <"$T/m.txt")" -eq 3 ] && cmp -s "$T/m.txt" "$T/f.txt"
}

# provenance FILE ERROR OBJECTIVE PRECISION TARGET: FILE's comment states the
# fitted error (OBJECTIVE ERROR in PRECISION precision) and the target as the
# fitted domain.
provenance() {
	grep -qF " * fitted error: $3 $2 in $4 precision" "$1" &&
		grep -qF " * fitted domain: $5" "$1" && grep -q '^ \* source: member ' "$1"
}

# subst FORM PARAMS: FORM with each pN replaced by its value in parentheses.
subst() {
	_s=$1
	for _p in $(echo "$2" | tr ';' ' '); do
		_s=$(echo "$_s" | sed "s/\([^A-Za-z0-9_]\|^\)${_p%%=*}\([^A-Za-z0-9_]\|$\)/\1(${_p#*=})\2/g")
	done
	echo "$_s"
}

# ---- one form: codegen and eval match the form with its parameters -----------
m=$(csv_col "$VF" name | tail -1)
form=$(csv_where "$VF" name "$m" form)
pars=$(csv_where "$VF" name "$m" parameters)
err=$(csv_where "$VF" name "$m" error)
[ -n "$m" ] && [ -n "$form" ] && [ -n "$pars" ] && ok || bad "$VF: no member read"
same_code "$VF:$m" "$form" "$pars" && ok || bad "codegen $VF:$m: not the values of '$form' with $pars: $(cat "$T/cc.err")"
bumped=$(echo "$pars" | awk -F';' -v OFS=';' '{ split($1, a, "="); $1 = "p0=" a[2] * 1.5 + 0.25; print }')
expect_fail "code with p0 changed" same_code "$VF:$m" "$form" "$bumped"
# shellcheck disable=SC2046 # parameters are words pN=VALUE
same_eval "$VF:$m" "$form" $(echo "$pars" | tr ';' ' ') && ok || bad "eval $VF:$m differs from '$form' with $pars"
# shellcheck disable=SC2046
expect_fail "eval with p0 changed" same_eval "$VF:$m" "$form" $(echo "$bumped" | tr ';' ' ')

# ---- its provenance: the front's error, objective, precision and target ----------
obj=$(sed -n 's/^# cost: .*; error: \([a-z_]*\) in \([a-z0-9]*\) precision.*/\1/p' "$VF")
prec=$(sed -n 's/^# cost: .*; error: \([a-z_]*\) in \([a-z0-9]*\) precision.*/\2/p' "$VF")
target=$(sed -n 's/^# target: //p' "$VF")
"$BK" codegen --lang c "$VF:$m" >"$T/m.c" 2>"$T/err" || bad "codegen $VF:$m: $(cat "$T/err")"
provenance "$T/m.c" "$err" "$obj" "$prec" "$target" && ok ||
	bad "codegen $VF:$m: no provenance '$obj $err in $prec precision', '$target'"
grep -q "^static inline float $m(" "$T/m.c" && ok || bad "codegen $VF:$m: not named $m"
# shellcheck disable=SC2046
"$BK" codegen --lang c "$form" $(echo "$pars" | tr ';' ' ') >"$T/f.c"
expect_fail "provenance of the typed form" provenance "$T/f.c" "$err" "$obj" "$prec" "$target"
# ops: the member counts as its form does
"$BK" ops --csv "$VF:$m" >"$T/m.ops" && "$BK" ops --csv "$form" >"$T/f.ops" && cmp -s "$T/m.ops" "$T/f.ops" && ok ||
	bad "ops $VF:$m differs from ops '$form'"

# ---- a split-sum member: :A and :B ----------------------------------------------
s=$(csv_cols "$ENV" name form_b | awk -F'\t' '$2 != "" { print $1; exit }')
sa=$(csv_where "$ENV" name "$s" form)
sb=$(csv_where "$ENV" name "$s" form_b)
sp=$(csv_where "$ENV" name "$s" parameters)
[ -n "$s" ] && [ -n "$sb" ] && ok || bad "$ENV: no split-sum member"
same_eval "$ENV:$s:A" "$(subst "$sa" "$sp")" && ok || bad "eval $ENV:$s:A differs from '$sa' with $sp"
same_eval "$ENV:$s:B" "$(subst "$sb" "$sp")" && ok || bad "eval $ENV:$s:B differs from '$sb' with $sp"
expect_fail "B evaluated as A" same_eval "$ENV:$s:B" "$(subst "$sa" "$sp")"
"$BK" codegen --lang hlsl "$ENV:$s:B" >"$T/b.hlsl" 2>"$T/err" && grep -q "${s}_B(" "$T/b.hlsl" &&
	grep -qF " * form: $sb" "$T/b.hlsl" && ok || bad "codegen $ENV:$s:B: $(cat "$T/err")"

# ---- one signature per front (issue 40 item 2) ----------------------------------
# Every member of a front is emitted with the same parameter list (the inputs
# any member reads, a as r), so members swap at one call site; a member of
# another target has another one (the control).
sig() { "$BK" codegen --lang glsl --name f "$1" 2>/dev/null | grep '^highp [a-z0-9]* f('; }
one_signature() {
	_f=$1; _first=""
	for _n in $(csv_col "$_f" name); do
		_s=$(sig "$_f:$_n") && [ -n "$_s" ] || return 1
		[ -z "$_first" ] && _first=$_s
		[ "$_s" = "$_first" ] || return 1
	done
	echo "$_first"
}
vsig=$(one_signature "$VF") && [ "$vsig" = "highp float f(highp float LoH, highp float r, highp float f0)" ] && ok ||
	bad "$VF: members' signatures differ, or not (LoH, r, f0): '$vsig'"
esig=$(one_signature "$ENV") && [ "$esig" = "highp vec2 f(highp float NoV, highp float r)" ] && ok ||
	bad "$ENV: pairs' wrappers differ, or not vec2 (NoV, r): '$esig'"
F0=results/search/env_f0/front.csv
[ "$(sig "$F0:$(csv_col "$F0" name | tail -1)")" != "$vsig" ] && ok || bad "control: an env_f0 member has vf2d's signature"
# the check on a vf2d front with an env_f0 member (NoV) mixed in fails
{ sed -n '1,/^name,/p' "$VF"; grep -v '^#' "$VF" | sed 1d | head -2; grep -v '^#' "$F0" | sed 1d | head -1; } >"$T/mixed.csv"
vf_signature() { [ "$(one_signature "$1")" = "$vsig" ]; }
expect_fail "a front with an env_f0 member mixed in" vf_signature "$T/mixed.csv"

# The search's own front files are the same code: each member's
# front/NAME/shader.{glsl,c} has the body codegen FILE.csv:NAME writes (the one
# signature, named constants, a pair's wrapper), and one signature line across
# the members. Control: a member's file compared with another member's code.
code_lines() { grep -v '^ \*\|^/\*' "$1"; } # FILE: without its provenance comments (a pair has two)
same_files() { # DIR LANG EXT: every member's file body = codegen's
	for _n in $(csv_col "$1/front.csv" name); do
		"$BK" codegen --lang "$2" "$1/front.csv:$_n" >"$T/cg" 2>/dev/null || return 1
		[ "$(code_lines "$T/cg")" = "$(code_lines "$1/front/$_n/shader.$3")" ] || { echo "$_n: shader.$3 differs"; return 1; }
	done
}
signature_lines() { # DIR EXT: the distinct signature lines of the members' files, names as f
	for _n in $(csv_col "$1/front.csv" name); do
		grep -h "^[a-z].* $_n(" "$1/front/$_n/shader.$2" | sed "s/ $_n(/ f(/"
	done | sort -u
}
"$BK" search --target vf2d --evals 3000 --quiet --out "$T/sv" >/dev/null 2>"$T/err" || bad "search vf2d: $(cat "$T/err")"
"$BK" search --target env --evals 2000 --quiet --out "$T/se" >/dev/null 2>"$T/err" || bad "search env: $(cat "$T/err")"
for _d in sv se; do
	for _l in glsl c; do
		_why=$(same_files "$T/$_d" $_l $_l) && ok || bad "search $_d: front files against codegen FILE.csv:MEMBER: $_why"
	done
done
[ "$(signature_lines "$T/sv" glsl)" = "highp float f(highp float LoH, highp float r, highp float f0)" ] && ok ||
	bad "search vf2d: front files' signatures: $(signature_lines "$T/sv" glsl)"
[ "$(signature_lines "$T/se" glsl)" = "highp vec2 f(highp float NoV, highp float r)" ] && ok ||
	bad "search env: front files' pair signatures: $(signature_lines "$T/se" glsl)"
_n1=$(csv_col "$T/sv/front.csv" name | head -1)
_n2=$(csv_col "$T/sv/front.csv" name | tail -1)
cp -r "$T/sv" "$T/sv_swapped" && cp "$T/sv/front/$_n2/shader.glsl" "$T/sv_swapped/front/$_n1/shader.glsl"
expect_fail "front files = codegen, one member's file another's" same_files "$T/sv_swapped" glsl glsl

# ---- a split-sum pair as engines call it: NAME(NoV, r) returning (A, B) -----------
# The C wrapper compiled and run gives A and B as eval gives them for :A and
# :B (f32 line, 2^-20 relative: C's float against the IR's BK_F32 rounding).
"$BK" codegen --lang c "$ENV:$s" >"$T/pair.c" 2>"$T/err" || bad "codegen $ENV:$s: $(cat "$T/err")"
cat >"$T/pair_main.c" <<EOC
#include <stdio.h>
#include "pair.c"
int main(void)
{
	float A, B;
	$s(0.6f, 0.5f, &A, &B);
	printf("%.9g %.9g\\n", (double)A, (double)B);
	return 0;
}
EOC
pair_ok() { # pair_ok A B: the wrapper's output within 2^-20 of A and B
	cc -std=c11 -O1 -ffp-contract=off -o "$T/pair" "$T/pair_main.c" -lm 2>"$T/cc.err" && "$T/pair" >"$T/pair.txt" &&
		awk -v a="$1" -v b="$2" 'function off(x, y) { d = x - y; if (d < 0) d = -d; return d > 9.5367431640625e-7 * (y < 0 ? -y : y) }
			{ exit off($1, a) || off($2, b) }' "$T/pair.txt"
}
# shellcheck disable=SC2046 # inputs are words NAME=VALUE: NoV 0.6, r 0.5, a 0.25 as the call's
ea=$("$BK" eval "$ENV:$s:A" $(inputs "$sa") 2>/dev/null | awk '$1 == "f32" { print $2 }')
# shellcheck disable=SC2046
eb=$("$BK" eval "$ENV:$s:B" $(inputs "$sb") 2>/dev/null | awk '$1 == "f32" { print $2 }')
pair_ok "$ea" "$eb" && ok || bad "$s(0.6, 0.5): $(cat "$T/pair.txt" "$T/cc.err"), eval A $ea B $eb"
expect_fail "wrapper against B, A swapped" pair_ok "$eb" "$ea"
grep -q "^static inline void $s(float NoV, float r, float \*A, float \*B)\$" "$T/pair.c" && ok ||
	bad "codegen $ENV:$s: no wrapper $s(NoV, r, *A, *B)"

# the members' GLSL (a pair's wrapper, a one-form member in half) compiles
# with glslang in one fragment shader; the control drops a named constant
frag() {
	{ echo '#version 310 es'; echo 'precision highp float;'; cat "$1"
		echo 'layout(std140, binding = 0) uniform U { highp float u0, u1, u2; };'
		echo 'layout(location = 0) out vec4 o;'
		echo "void main() { o = vec4($s(u0, u1), $m(u0, u1, u2), 0.0); }"; } >"$T/t.frag"
	glslangValidator -V -o "$T/t.spv" "$T/t.frag" >"$T/gl.log" 2>&1
}
{ "$BK" codegen --lang glsl "$ENV:$s" && "$BK" codegen --lang glsl --precision half "$VF:$m"; } >"$T/members.glsl"
frag "$T/members.glsl" && ok || bad "the members' GLSL does not compile: $(tail -5 "$T/gl.log")"
grep -v "^	const .*${m}_p0 = " "$T/members.glsl" >"$T/broken.glsl"
expect_fail "GLSL without ${m}_p0" frag "$T/broken.glsl"

# every member's C pastes cleanly into code built with -Wall -Wextra -Werror
# (a pair's B reads p2..p4 of p0..p4: only those are named; an input the
# member does not read is (void)); the control adds an unused constant
c_clean() {
	printf '#include "%s"\nint main(void) { return 0; }\n' "$1" >"$T/clean_main.c"
	cc -std=c11 -Wall -Wextra -Werror -Wno-unused-function -c -o "$T/clean.o" "$T/clean_main.c" 2>"$T/cc.err"
}
all_clean() {
	for _n in $(csv_col "$1" name); do
		"$BK" codegen --lang c "$1:$_n" >"$T/clean.c" 2>/dev/null && c_clean "$T/clean.c" || return 1
	done
}
all_clean "$ENV" && all_clean "$VF" && ok || bad "a member's C does not build with -Wall -Wextra -Werror: $(head -3 "$T/cc.err")"
"$BK" codegen --lang c "$VF:$m" | sed 's/^{$/{\n\tconst float unused_k = 1.0f;/' >"$T/unclean.c"
expect_fail "C with an unused constant" c_clean "$T/unclean.c"

# ---- a path with ':' in it: the file part ends at the last ".csv:" -----------------
mkdir -p "$T/a:b" && cp "$VF" "$T/a:b/front.csv"
# shellcheck disable=SC2046
same_eval "$T/a:b/front.csv:$m" "$form" $(echo "$pars" | tr ';' ' ') && ok || bad "eval $T/a:b/front.csv:$m"

# ---- refusals: exit 2, one line naming the bad input ----------------------------------
# refused NAME TOKEN CMD...: exit 2, nothing on stdout, one line on stderr holding TOKEN.
refused() {
	_n=$1 _t=$2; shift 2
	"$@" >"$T/out" 2>"$T/err"
	_rc=$?
	[ "$_rc" -eq 2 ] && [ ! -s "$T/out" ] && [ "$(wc -l <"$T/err")" -eq 1 ] && grep -qF -- "$_t" "$T/err"
}
check_refused() {
	_n=$1; shift
	refused "$_n" "$@" && ok || bad "$_n: exit $_rc, stdout $(wc -c <"$T/out") bytes, stderr '$(cat "$T/err")'"
}
check_refused "missing file" "$T/none.csv: cannot be read" "$BK" codegen --lang c "$T/none.csv:$m"
first=$(csv_col "$VF" name | head -1)
check_refused "wrong member" "no member 'nope_$m'" "$BK" eval "$VF:nope_$m" LoH=0.5
check_refused "wrong member lists names" "$first" "$BK" ops "$VF:nope_$m"
expect_fail "right member refused as wrong" refused "right member" "no member" "$BK" ops "$VF:$m"
csv_drop "$VF" name "$first" | grep -v '^# brdfkit ' >"$T/plain.csv"
check_refused "not a front" "not a front.csv of brdfkit search" "$BK" ops "$T/plain.csv:$m"
expect_fail "a front refused as not one" refused "a front" "not a front.csv" "$BK" ops "$VF:$m"
printf 'name,form\nx,NoV\n' >"$T/other.csv"
check_refused "other csv" "not a front.csv of brdfkit search" "$BK" ops "$T/other.csv:x"
check_refused "split without part" "write $ENV:$s:A or $ENV:$s:B" "$BK" ops "$ENV:$s"
check_refused "split, part C" "unknown part 'C'" "$BK" ops "$ENV:$s:C"
check_refused "one form with a part" "unknown part 'A'" "$BK" ops "$VF:$m:A"
expect_fail "split with part refused" refused "split A" "unknown part" "$BK" ops "$ENV:$s:A"

# ---- every command that takes a form takes a member (one reader, member.h) --------
# Each runs the member and the same form typed with the member's parameters
# and compares what it states of the form: the member reaches the command
# with its own parameters (a changed p0 is seen), its name and its target.
MP=$(echo "$pars" | tr ';' ' ')

# stability: the same report as the typed form with its parameters, but for the name
stab_same() {
	# shellcheck disable=SC2086 # parameters are words pN=VALUE
	"$BK" stability "$1" >"$T/sm" 2>/dev/null && "$BK" stability "$form" $2 >"$T/sf" 2>/dev/null || return 1
	[ -s "$T/sm" ] && [ "$(sed 1d "$T/sm")" = "$(sed 1d "$T/sf")" ] && head -1 "$T/sm" | grep -q "^$m:"
}
stab_same "$VF:$m" "$MP" && ok || bad "stability $VF:$m differs from '$form' $MP"
expect_fail "stability with p0 changed" stab_same "$VF:$m" "$(echo "$bumped" | tr ';' ' ')"

# time: the row names the member, its form and its op counts are the typed form's
time_same() {
	# shellcheck disable=SC2086
	"$BK" time --reps 1 "$1" "$form" $2 >"$T/tm" 2>/dev/null || return 1
	[ "$(csv_col "$T/tm" name | head -1)" = "$m" ] &&
		[ "$(csv_cols "$T/tm" form simple complex cost spirv | sort -u | wc -l)" -eq 1 ]
}
time_same "$VF:$m" "$MP" && ok || bad "time $VF:$m: not the row of '$form'"
expect_fail "time of another member" time_same "$VF:$first" "$MP"

# gpucost: the same ACO counts as the typed form with the member's parameters
if "$BK" gpucost --chips navi21 "$VF:$m" "$form" $MP >"$T/gm" 2>"$T/err"; then
	[ "$(csv_col "$T/gm" name | head -1)" = "$m" ] &&
		[ "$(csv_cols "$T/gm" instructions vgprs transcendental | sort -u | wc -l)" -eq 1 ] && ok ||
		bad "gpucost $VF:$m: not the counts of '$form': $(cat "$T/gm")"
	check_refused "gpucost: a member takes no pN=" "must follow a typed form" "$BK" gpucost "$VF:$m" p0=1
else
	echo "SKIP: gpucost (no RADV here): $(head -c 200 "$T/err")"
fi

# fit: the member's parameters start the fit; the generated files name it
"$BK" fit --target vf2d --form "$VF:$m" --out "$T/fit" >"$T/fit.txt" 2>"$T/err" &&
	grep -q "^fit $m on vf2d:" "$T/fit.txt" && grep -q "^ \* source: member $m of $VF " "$T/fit/shader.c" &&
	grep -q "^static inline float $m(" "$T/fit/shader.c" && ok || bad "fit --form $VF:$m: $(cat "$T/err" "$T/fit.txt")"
# a start at the member's own optimum (max_abs front, rmse fit): the fit
# starts from the member's values, so its first cost is the member's rmse^2/2
# summed, not the cost at a typed p0=1 start
start_cost() { sed -n 's/.* cost \([0-9.e+-]*\) -> .*/\1/p' "$1"; }
# shellcheck disable=SC2086
"$BK" fit --target vf2d --form "$form" $MP --out "$T/fit2" >"$T/fit2.txt" 2>&1
[ -n "$(start_cost "$T/fit.txt")" ] && [ "$(start_cost "$T/fit.txt")" = "$(start_cost "$T/fit2.txt")" ] && ok ||
	bad "fit from $VF:$m does not start at its parameters: $(start_cost "$T/fit.txt") vs $(start_cost "$T/fit2.txt")"
# shellcheck disable=SC2046
"$BK" fit --target vf2d --form "$form" $(echo "$bumped" | tr ';' ' ') --out "$T/fit3" >"$T/fit3.txt" 2>&1
[ "$(start_cost "$T/fit.txt")" != "$(start_cost "$T/fit3.txt")" ] && ok ||
	bad "control: fit from p0 changed starts at the same cost $(start_cost "$T/fit3.txt")"

# render: the member, its front's target as the term, named after it; the
# same image as the typed form with --term and --params
render_same() {
	"$BK" render --device cpu --size 40 --precision single --form "$1" --out "$T/r1" >/dev/null 2>"$T/err" &&
		"$BK" render --device cpu --size 40 --precision single --form "$form" --term vf --params "$2" \
			--out "$T/r2" >/dev/null 2>>"$T/err" || return 1
	grep -qF -- "--form $1 " "$T/r1/spheres.csv" && "$EXRCMP" "$T/r1/candidate_f32.exr" "$T/r2/candidate_f32.exr" 0 0 >/dev/null
}
render_same "$VF:$m" "$pars" && ok || bad "render --form $VF:$m: not the image of '$form' with $pars: $(cat "$T/err")"
expect_fail "render with p0 changed" render_same "$VF:$m" "$bumped"
"$BK" render --device cpu --size 40 --precision single --form "$ENV:$s" --out "$T/r3" >"$T/r3.txt" 2>"$T/err" &&
	grep -q "^render: $s (replaces env)" "$T/r3.txt" && ok || bad "render --form $ENV:$s: $(cat "$T/err" "$T/r3.txt")"
# a batch's form column takes a member as --form does (the Makefile's
# results-render names the chosen members so): the same image as the typed row
printf 'name,term,form,form_b,parameters\nm,vf,%s,,\nt,vf,"%s",,"%s"\n' "$VF:$m" "$form" "$pars" >"$T/batch.csv"
"$BK" render --device cpu --size 40 --precision single --batch "$T/batch.csv" --out "$T/rb" >/dev/null 2>"$T/err" &&
	"$EXRCMP" "$T/rb/m/candidate_f32.exr" "$T/rb/t/candidate_f32.exr" 0 0 >/dev/null && ok ||
	bad "render --batch with $VF:$m: not the typed row's image: $(cat "$T/err")"
check_refused "render: member with --form-b" "a front member brings its own B" \
	"$BK" render --device cpu --form "$ENV:$s" --form-b 1 --out "$T/r4"

# the reader's refusals, in each command: unknown member, not a front, a
# front whose header lacks a column (form renamed)
sed '/^name,/s/,form,/,formula,/' "$VF" >"$T/cols.csv"
for c in "stability" "time --reps 1" "gpucost" "render --device cpu --out $T/r5 --form" "fit --target vf2d --out $T/f5 --form"; do
	# shellcheck disable=SC2086 # c is words
	check_refused "$c: unknown member" "no member 'nope_$m'" "$BK" $c "$VF:nope_$m"
	# shellcheck disable=SC2086
	check_refused "$c: not a front" "not a front.csv of brdfkit search" "$BK" $c "$T/plain.csv:$m"
	# shellcheck disable=SC2086
	check_refused "$c: wrong columns" "$T/cols.csv" "$BK" $c "$T/cols.csv:$m"
done
[ ! -e "$T/r5" ] && [ ! -e "$T/f5" ] && ok || bad "a refused member left --out behind"

echo "cli_paste: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
