#!/bin/sh
# cli_msl.sh — brdfkit codegen --lang msl (issue 40): Metal made by
# SPIRV-Cross from the SPIR-V of the GLSL, and the half variants' constants.
#
# No Metal compiler runs here, but MSL is C++14: each emitted function is
# compiled with g++ against a small shim of <metal_stdlib> written below (half
# a float rounded to binary16 after every operation by an implementation of
# its own, not brdf/half.h; the math functions with the IR's meanings: pow =
# exp2(y log2 x)) and its values at sample points are compared with brdfkit
# eval's f32 and f16 of the same form, an independent evaluator (the IR's).
# Negative control: a constant perturbed in the MSL text is caught.
# Then every literal of the half files (GLSL mediump and float16_t, HLSL
# min16float and half, MSL half) is a binary16 value (tests/tools/halflit.c);
# control: the single-precision file of the same form is refused.
#
# usage: sh tests/cli_msl.sh path/to/brdfkit   (from the repository root)

BK=${1:?usage: cli_msl.sh path/to/brdfkit}
T=$(mktemp -d /tmp/bk_cli_msl_XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/lib.sh"
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
command -v g++ >/dev/null && command -v cc >/dev/null || { echo "FAIL: g++ and cc are needed"; exit 1; }

mkdir "$T/shim"
cat >"$T/shim/metal_stdlib" <<'SHIM'
// <metal_stdlib> for g++: only what brdfkit's MSL uses. No libm header is
// included, so that the global namespace has no pow or exp2 to compete with
// metal's: the functions come from GCC's builtins.
namespace metal {
// binary16 rounding, nearest even: 11 significant bits above 2^-14, the
// quantum 2^-24 below, infinite from 65520 (65504 + half its ulp) on
static inline float r16(double x)
{
	double ax = __builtin_fabs(x);
	if (x != x)
		return (float)x;
	if (!(ax < 65520.0))
		return (float)__builtin_copysign(__builtin_inf(), x);
	double q = 5.9604644775390625e-08; /* 2^-24 (C++14 has no hex floats) */
	if (ax >= 6.103515625e-05) { /* 2^-14 */
		int e;
		__builtin_frexp(ax, &e); /* ax in [2^(e-1), 2^e): ulp 2^(e-11) */
		q = __builtin_ldexp(1.0, e - 11);
	}
	return (float)__builtin_copysign(__builtin_rint(ax / q) * q, x);
}
struct half {
	float v;
	half() : v(0) {}
	half(double x) : v(r16(x)) {}
	explicit operator float() const { return v; }
};
static inline half operator+(half a, half b) { return half((double)(a.v + b.v)); }
static inline half operator-(half a, half b) { return half((double)(a.v - b.v)); }
static inline half operator*(half a, half b) { return half((double)(a.v * b.v)); }
static inline half operator/(half a, half b) { return half((double)(a.v / b.v)); }
static inline half operator-(half a) { return half(-(double)a.v); }
#define ONE(name, expr) \
	static inline float name(float x) { return expr; } \
	static inline half name(half h) { float x = h.v; return half((double)(expr)); }
ONE(exp2, __builtin_exp2f(x))
ONE(log2, __builtin_log2f(x))
ONE(exp, __builtin_expf(x))
ONE(log, __builtin_logf(x))
ONE(sqrt, __builtin_sqrtf(x))
ONE(rsqrt, 1.0f / __builtin_sqrtf(x))
ONE(abs, __builtin_fabsf(x))
#undef ONE
static inline float pow(float x, float y) { return __builtin_exp2f(y * __builtin_log2f(x)); }
static inline half pow(half x, half y) { return half((double)pow(x.v, y.v)); }
static inline float min(float a, float b) { return b < a ? b : a; }
static inline float max(float a, float b) { return a < b ? b : a; }
static inline half min(half a, half b) { return b.v < a.v ? b : a; }
static inline half max(half a, half b) { return a.v < b.v ? b : a; }
static inline float clamp(float x, float lo, float hi) { return min(max(x, lo), hi); }
static inline half clamp(half x, half lo, half hi) { return min(max(x, lo), hi); }
static inline float fma(float a, float b, float c) { return __builtin_fmaf(a, b, c); }
static inline half fma(half a, half b, half c) { return half((double)__builtin_fmaf(a.v, b.v, c.v)); }
// SPIRV-Cross spells float min/max/clamp fast:: (NaN handling left to the GPU)
namespace fast {
static inline float min(float a, float b) { return metal::min(a, b); }
static inline float max(float a, float b) { return metal::max(a, b); }
static inline float clamp(float x, float lo, float hi) { return metal::clamp(x, lo, hi); }
}
}
extern "C" int printf(const char *, ...);
SHIM

# msl_values FILE NAME TYPE POINTS...: the MSL function NAME of FILE (its type
# TYPE, float or half) at each point "NoV=..,r=.." (its inputs in its order),
# one value a line (%.9g)
msl_values() {
	_f=$1 _n=$2 _t=$3; shift 3
	ins=$(sed -n "s/^$_t $_n(\(.*\))\$/\1/p" "$_f" | sed "s/$_t //g; s/,/ /g")
	{ cat "$_f"; echo "int main() {"
	  for pt in "$@"; do
		args="" sep=""
		for v in $ins; do
			x=$(echo "$pt" | tr ',' '\n' | sed -n "s/^$v=//p")
			args="$args$sep$_t($x)" sep=", "
		done
		printf '\tprintf("%%.9g\\n", (double)static_cast<float>(%s(%s)));\n' "$_n" "$args"
	  done
	  echo "}"; } >"$T/m.cc"
	g++ -std=c++14 -O0 -Wall -Werror -I"$T/shim" "$T/m.cc" -lm -o "$T/m" 2>"$T/gxx.log" || { cat "$T/gxx.log" >&2; return 1; }
	"$T/m"
}

# eval_values PREC FORM PARAMS INPUTS POINTS...: brdfkit eval's value in PREC
# (f32 or f16) at each point, one a line (INPUTS: the names the form reads)
eval_values() {
	_p=$1 _form=$2 _pars=$3 _ins=$4; shift 4
	for pt in "$@"; do
		_a=""
		for v in $_ins; do _a="$_a $v=$(echo "$pt" | tr ',' '\n' | sed -n "s/^$v=//p")"; done
		# shellcheck disable=SC2086 # words NAME=VALUE
		"$BK" eval "$_form" $_pars $_a | sed -n "s/^$_p //p"
	done
}

# agree GOT WANT RTOL: the two lists agree line by line within RTOL relative
# (+ RTOL absolute near 0), and have the same length
agree() {
	printf '%s\n' "$1" >"$T/got"; printf '%s\n' "$2" >"$T/want"
	[ "$(wc -l <"$T/got")" = "$(wc -l <"$T/want")" ] || return 1
	paste "$T/got" "$T/want" | awk -v t="$3" '
		{ d = $1 - $2; if (d < 0) d = -d; w = $2 < 0 ? -$2 : $2
		  if ($1 !~ /^[-+0-9.eE]+$/ || !(d <= t * w + t)) bad = 1 }
		END { exit bad }'
}

# forms: every operation the IR has (pow, the reciprocals, the clamps, mix,
# a multiply-add) and catalog entries with their published constants
KITCHEN='pow(NoV, p0) + 1/sqrt(r) + rsqrt(a) + rcp(LoH) + exp(f0) + log(NoH+1) + log2(NoL+1) + min(NoV,0.5) + max(r,0.25) + clamp(LoH, 0.1, 0.9) + saturate(NoV*3) + mix(f0, 1, LoH) + abs(NoV-0.5) - NoV + NoV*r + f0 + clamp(NoV, p0, r)'
PTS="NoV=0.5,NoL=0.7,NoH=0.9,LoH=0.6,r=0.3,a=0.09,f0=0.04 NoV=0.05,NoL=0.2,NoH=0.99,LoH=0.3,r=0.8,a=0.64,f0=0.5 NoV=0.95,NoL=0.05,NoH=0.5,LoH=0.9,r=0.05,a=0.0025,f0=1"
i=0
for spec in "kitchen|$KITCHEN|p0=3.5" "vf_talk_r||" "f_schlick_sg||" "env_karis2014||"; do
	label=${spec%%|*} rest=${spec#*|} form=${rest%|*} pars=${rest#*|}
	[ -n "$form" ] || form=$label
	fform=$form
	[ "$label" = kitchen ] || fform=$("$BK" catalog | "$CSVGET" /dev/stdin form name "$label") || { bad "$label: not in the catalog"; continue; }
	[ "$label" = kitchen ] || pars=$("$BK" catalog | "$CSVGET" /dev/stdin parameters name "$label" | tr ';' ' ')
	for prec in single half; do
		i=$((i + 1)) f="$T/$label.$prec.metal"
		# shellcheck disable=SC2086 # parameters are words p0=X
		if ! "$BK" codegen --lang msl --precision "$prec" --name msl_fn "$fform" $pars >"$f" 2>"$T/err"; then
			bad "$label $prec: codegen --lang msl failed: $(cat "$T/err")"; continue
		fi
		grep -q '^ \* precision: MSL' "$f" && grep -q '^ \* op counts' "$f" && grep -q '^ \* form: ' "$f" && ok ||
			bad "$label $prec: the MSL lost brdfkit's header comment"
		T_=float E=f32 tol=2e-6
		[ $prec = half ] && T_=half E=f16 tol=2e-3
		# shellcheck disable=SC2086
		got=$(msl_values "$f" msl_fn $T_ $PTS) || { bad "$label $prec: the MSL does not compile as C++14"; continue; }
		# shellcheck disable=SC2086
		ins=$(sed -n "s/^$T_ msl_fn(\(.*\))\$/\1/p" "$f" | sed "s/$T_ //g; s/,/ /g")
		want=$(eval_values $E "$fform" "$pars" "$ins" $PTS)
		agree "$got" "$want" $tol && ok || bad "$label $prec: MSL gives $(echo $got), brdfkit eval $E $(echo $want)"
		# control, once per precision: p0 = 0.5 of vf_talk_r (f0/(4 LoH^2 (r + p0)))
		# written 0.515625 in the MSL, a 1-2% change of the value, is caught
		if [ "$label" = vf_talk_r ]; then
			sed 's/\([ (]\)0\.5\([;)]\)/\10.515625\2/g' "$f" >"$T/perturbed.metal"
			grep -q '0\.515625' "$T/perturbed.metal" || bad "control: no constant 0.5 to perturb in $f"
			# shellcheck disable=SC2086
			pgot=$(msl_values "$T/perturbed.metal" msl_fn $T_ $PTS)
			expect_fail "MSL $prec with a perturbed constant" agree "$pgot" "$want" $tol
		fi
	done
done
[ $i -eq 8 ] && ok || bad "ran $i of 8 MSL cases"

# the same function name and signature as the GLSL's
"$BK" codegen --lang glsl vf_talk_r | grep '^highp float' | sed 's/highp //g' >"$T/sig.glsl"
"$BK" codegen --lang msl vf_talk_r | grep '^float' >"$T/sig.msl"
cmp -s "$T/sig.glsl" "$T/sig.msl" && ok || bad "MSL signature $(cat "$T/sig.msl") is not the GLSL's $(cat "$T/sig.glsl")"

# ---- constants on the half grid, in every language's half files ------------------------
cc -std=c11 -Wall -Wextra -Werror -Ibrdf tests/tools/halflit.c -lm -o "$T/halflit" || bad "halflit does not build"
FORM='clamp(p0*exp2(p1*NoV), 0, 1) + 1/sqrt(r)/(LoH + 0.1) + saturate(NoV)'
for l in c glsl hlsl msl; do
	for prec in half float16; do
		[ $l = c ] && continue
		"$BK" codegen --lang $l --precision $prec "$FORM" p0=0.3 p1=-5.55473 >"$T/h.$prec.$l" || bad "codegen $l $prec"
	done
	"$BK" codegen --lang $l "$FORM" p0=0.3 p1=-5.55473 >"$T/s.$l" || bad "codegen $l single"
done
halflits() { "$T/halflit" "$@" >"$T/hl.out"; }
halflits "$T"/h.* && ok || bad "half files with constants half cannot hold: $(cat "$T/hl.out")"
grep -q '^4[0-9] literals$' "$T/hl.out" && ok || bad "halflit checked $(cat "$T/hl.out") (48 expected)"
for l in c glsl hlsl msl; do expect_fail "halflit on the $l single file (0.3, -5.55473, 0.1)" halflits "$T/s.$l"; done
# the same binary16 values in every language: 0.300048828125 (p0), -5.5546875 (p1), 0.0999755859375
for v in 0.300048828125 5.5546875 0.0999755859375; do
	[ "$(grep -l "$v" "$T"/h.* | wc -l)" -eq 6 ] && ok || bad "the half value $v is not in all six half files"
done
grep -q 'p0 = 0.3 (0.300048828 in half, as written below)' "$T/h.half.glsl" && ok ||
	bad "the header does not give p0's half value"
# -enable-16bit-types code: float16_t and half literals carry their suffix
grep -q '0\.300048828125hf' "$T/h.float16.glsl" && grep -q '0\.300048828125h\b' "$T/h.float16.hlsl" && ok ||
	bad "the float16 files' literals lack hf / h"
grep -q '^min16float brdfkit_form(' "$T/h.half.hlsl" && grep -q '^half brdfkit_form(' "$T/h.float16.hlsl" &&
	grep -q '^mediump float brdfkit_form(' "$T/h.half.glsl" && grep -q '^float16_t brdfkit_form(' "$T/h.float16.glsl" && ok ||
	bad "the half files' types are not mediump, float16_t, min16float, half"

# names Metal reserves and GLSL does not (a keyword, an address space, a vector
# type, a <metal_stdlib> function) are refused by name; SPIRV-Cross would keep
# them and the file would not compile. Control: a free name is taken.
for n in kernel device half4 float3x3 saturate; do
	"$BK" codegen --lang msl --name $n NoV >/dev/null 2>"$T/err" && bad "msl --name $n accepted" ||
		{ grep -q "'$n' is reserved in msl" "$T/err" && ok || bad "msl --name $n: $(cat "$T/err")"; }
done
"$BK" codegen --lang msl --name my_fn NoV | grep -q '^float my_fn(float NoV)$' && ok || bad "msl --name my_fn"

# usage: an unknown precision names itself
"$BK" codegen --lang msl --precision quarter NoV >/dev/null 2>"$T/err" && bad "--precision quarter accepted" ||
	{ grep -q "quarter" "$T/err" && ok || bad "--precision quarter: $(cat "$T/err")"; }

echo "cli_msl.sh: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
