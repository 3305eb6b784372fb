#!/bin/sh
# cli_paste.sh — a front member pasted by name (issue 40 item 2): FILE.csv:NAME
# is a form wherever eval, ops and codegen take one, with the member's
# parameters baked in and, for codegen, its provenance (source, fitted domain
# and error) from the front.csv; a split-sum member is FILE.csv:NAME:A or :B.
# Each check has a negative control that shows it can fail.
# usage: sh tests/cli_paste.sh path/to/brdfkit   (from the repository root)
set -u
BK=${1:?usage: sh tests/cli_paste.sh path/to/brdfkit}
T=$(mktemp -d /tmp/bk_cli_paste_XXXXXX)
trap 'rm -rf "$T"' EXIT
CSVGET=${CSVGET:-build/csvget}
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

# same_body MEMBER FORM PARAMS: codegen of the member and of FORM with PARAMS
# ("p0=X;p1=Y") as pN=VALUE write the same function.
same_body() {
	# shellcheck disable=SC2046 # PARAMS are words pN=VALUE
	"$BK" codegen --lang glsl --name f "$1" >"$T/m.glsl" &&
		"$BK" codegen --lang glsl --name f "$2" $(echo "$3" | tr ';' ' ') >"$T/f.glsl" || return 1
	[ -s "$T/m.glsl" ] && [ "$(body "$T/m.glsl")" = "$(body "$T/f.glsl")" ]
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
same_body "$VF:$m" "$form" "$pars" && ok || bad "codegen $VF:$m: not the body of '$form' with $pars"
bumped=$(echo "$pars" | awk -F';' -v OFS=';' '{ split($1, a, "="); $1 = "p0=" a[2] * 1.5 + 0.25; print }')
expect_fail "body with p0 changed" same_body "$VF:$m" "$form" "$bumped"
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

echo "cli_paste: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
