#!/bin/sh
# cli_tables.sh — the IR commands take no argument without an effect (issue
# 21): eval refuses an input the form does not read (r acts through a = r*r
# where the form reads a and a is not given), codegen --precision on C output
# (float only), ops weights next to --cost-model. The walk of every table is
# tests/cli_opts.sh; these pin the messages, each with a control that the
# accepted form still computes the hand-counted value.
# usage: sh tests/cli_tables.sh path/to/brdfkit
set -u
BK=${1:?usage: sh tests/cli_tables.sh path/to/brdfkit}
T=$(mktemp -d /tmp/bk_cli_tables_XXXXXX)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }

# refused NAME TOKEN CMD...: exit 2, nothing on stdout, one line on stderr holding TOKEN.
refused() {
	name=$1 token=$2; shift 2
	"$@" >"$T/out" 2>"$T/err"
	rc=$?
	if [ $rc -eq 2 ] && [ ! -s "$T/out" ] && [ "$(wc -l <"$T/err")" -eq 1 ] && grep -qF -- "$token" "$T/err"; then ok
	else bad "$name: rc $rc, stdout '$(head -c 200 "$T/out")', stderr '$(cat "$T/err")'"; fi
}
# first NAME WANT CMD...: the first line of stdout is WANT, nothing on stderr.
first() {
	name=$1 want=$2; shift 2
	got=$("$@" 2>"$T/err" | head -1)
	[ "$got" = "$want" ] && [ ! -s "$T/err" ] && ok || bad "$name: '$got' (want '$want'), stderr '$(cat "$T/err")'"
}

# ---- eval: inputs the form does not read -----------------------------------------
refused "eval NoL unread" "brdfkit eval: NoL=VALUE has no effect: the form does not read NoL" \
	$BK eval NoV NoV=0.5 NoL=0.3
refused "eval catalog NoV unread" "NoV=VALUE has no effect: vf_talk_r does not read NoV" \
	$BK eval vf_talk_r LoH=1 r=1 NoV=0.5
refused "eval r beside a" "r=VALUE has no effect: the form does not read r" $BK eval a r=0.5 a=0.25
refused "eval a beside r" "a=VALUE has no effect: the form does not read a" $BK eval r r=0.5 a=0.3
refused "eval VoH unread" "VoH=VALUE has no effect: the form does not read VoH" $BK eval NoV VoH=0.5 NoV=0.2
# controls: 0.5 * 0.25 (exact in binary); a = r^2 = 0.25 from r alone; VoH is LoH
first "eval NoV*NoL" "f64 0.125" $BK eval 'NoV*NoL' NoV=0.5 NoL=0.25
first "eval a from r" "f64 0.25" $BK eval a r=0.5
first "eval LoH from VoH" "f64 0.5" $BK eval LoH VoH=0.5

# ---- codegen --precision: C output is float only, LaTeX and SymPy have none ----
for p in single half; do
	refused "codegen c $p" "brdfkit codegen: --precision has no effect with --lang c (it picks a shader's float type: C is float only, LaTeX and SymPy have none)" \
		$BK codegen --lang c --precision $p NoV
done
refused "codegen latex half" "brdfkit codegen: --precision has no effect with --lang latex (it picks a shader's float type: C is float only, LaTeX and SymPy have none)" \
	$BK codegen --lang latex --precision half NoV
# controls: C without it; GLSL mediump declares it, HLSL's half precisions are min16float and half
$BK codegen --lang c NoV >"$T/c" 2>"$T/err" && grep -q '^static inline float brdfkit_form(' "$T/c" && ok ||
	bad "codegen c: $(cat "$T/err")"
$BK codegen --lang glsl --precision half NoV 2>"$T/err" | grep -q 'mediump float' && ok || bad "glsl mediump: $(cat "$T/err")"
$BK codegen --lang hlsl --precision half NoV 2>"$T/err" | grep -q '^min16float ' && ok || bad "hlsl min16float: $(cat "$T/err")"
$BK codegen --lang hlsl --precision float16 NoV 2>"$T/err" | grep -q '^half ' && ok || bad "hlsl half: $(cat "$T/err")"
$BK codegen --lang glsl --precision float16 NoV 2>"$T/err" | grep -q '^float16_t ' && ok || bad "glsl float16_t: $(cat "$T/err")"

# ---- ops: --cost-model sets both weights ------------------------------------------
refused "ops model and simple" "brdfkit ops: --simple-cost has no effect with --cost-model (it sets both weights)" \
	$BK ops --cost-model ir --simple-cost 2 'NoV + NoL'
# control: one add at simple cost 2 costs 2
[ "$($BK ops --csv --simple-cost 2 'NoV + NoL' | sed -n 's/^cost,//p')" = 2 ] && ok || bad "ops --simple-cost 2: one add"

echo "cli_tables: $pass passed, $fail failed"
[ $fail -eq 0 ]
