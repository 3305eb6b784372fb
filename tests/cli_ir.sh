#!/bin/sh
# cli_ir.sh — the formula IR's commands (eval, ops, codegen, time, gpucost,
# stability) give no silent wrong answer (issue 21): code that spells out what
# the IR evaluates, no "safe" verdict for a form that is not finite or right
# only by luck, no form without a value emitted or measured, no option value
# without an effect, no generated name that does not compile, brdfkit(1)'s
# nesting limit, warnings for constants the precision cannot hold. Each check
# has a negative control that shows it can fail.
# usage: sh tests/cli_ir.sh path/to/brdfkit   (from the repository root)
set -u
BK=${1:?usage: sh tests/cli_ir.sh path/to/brdfkit}
T=$(mktemp -d /tmp/bk_cli_ir_XXXXXX)
trap 'rm -rf "$T"' EXIT
CSVGET=${CSVGET:-build/csvget}
. tests/lib.sh
pass=0 fail=0

ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }

# refused NAME STATUS TOKEN CMD...: exit STATUS, nothing on stdout, one line on
# stderr holding TOKEN.
refused() {
	name=$1 status=$2 token=$3; shift 3
	"$@" >"$T/out" 2>"$T/err"
	rc=$?
	if [ "$rc" -eq "$status" ] && [ ! -s "$T/out" ] && [ "$(wc -l <"$T/err")" -eq 1 ] &&
		grep -qF -- "$token" "$T/err"; then ok
	else bad "$name: exit $rc, stdout $(wc -c <"$T/out") bytes, stderr '$(cat "$T/err")'"; fi
}

# accepted NAME CMD...: exit 0 and nothing on stderr.
accepted() {
	name=$1; shift
	"$@" >"$T/out" 2>"$T/err" && [ ! -s "$T/err" ] && ok || bad "$name: stderr '$(cat "$T/err")'"
}

# ---- mix: the code spells out x + (y - x) t, what the IR evaluates --------------
# (GLSL mix() and HLSL lerp() are x(1 - t) + y t, and a compiler picks either)
for l in glsl hlsl c; do
	for p in single half; do
		prec="--precision $p" # C is float only: once, without --precision
		[ $l = c ] && { [ $p = half ] && continue; prec=; }
		$BK codegen --lang $l $prec 'mix(NoV, NoL, LoH)' >"$T/mix" 2>"$T/err" || bad "mix $l $p: $(cat "$T/err")"
		sed '1,/\*\//d' "$T/mix" >"$T/mixbody" # the code after the provenance comment
		grep -qE 'mix\(|lerp\(' "$T/mixbody" && bad "mix $l $p: mix()/lerp() called" || ok
		grep -qF '= NoV + (NoL - NoV) * LoH;' "$T/mixbody" && ok || bad "mix $l $p: $(cat "$T/mixbody")"
	done
done
# negative control: the same check on a mix() call fails
printf 'float t = mix(NoV, NoL, LoH);\n' | grep -qE 'mix\(|lerp\(' && ok || bad "mix control"

# ---- stability: never "safe" when not finite, or right only by luck (H3) ------
for f in 'sqrt(NoV-2)' '1/0' 'log2(NoV-1)'; do
	refused "stability $f" 2 "NaN or infinite at every one of the" $BK stability "$f"
done
# (300 NoV)^2 overflows half for the grid's cosines 0.9, 0.999, 0.99999, 1 and
# rounds to 0 below 2^-25 (cosines 0, 1e-7: 0/0); min(1, NaN) hides both as 1.
# 13 roughness values: the f16 row's wrong column counts them all.
want=$(echo 0 1e-7 1e-4 1e-3 0.01 0.1 0.5 0.9 0.999 0.99999 1 | awk '{ for (i = 1; i <= NF; i++) {
	x = 300 * $i; n += (x * x > 65504 || x * x < 2^-25) } print 13 * n }')
[ "$want" = 78 ] && ok || bad "expected count $want"
$BK stability 'min(1, sq(NoV*300)/sq(NoV*300))' >"$T/st" 2>/dev/null || bad "stability min: exit $?"
[ "$(awk '$1 == "f16" { print $3 }' "$T/st")" = "$want" ] && ok || bad "stability min: f16 $(grep '^f16' "$T/st")"
grep -q '^safe in half as is$' "$T/st" && bad "stability min called safe" || ok
grep -q '^guards: .*(still fails)$' "$T/st" && ok || bad "stability min: guards"
# negative control: 201^2 = 40401 stays in half's range
$BK stability 'min(1, sq(NoV*200 + 1)/sq(NoV*200 + 1))' 2>/dev/null | grep -q '^safe in half as is$' && ok ||
	bad "stability min control not safe"
# a pole somewhere (0/0 at NoV = 0, 13 samples of 143) is never safe as is
$BK stability 'NoV/NoV' >"$T/st" 2>/dev/null
grep -q '^the form itself is NaN or infinite at 13 of 143 samples (first at NoV = 0: NaN)' "$T/st" && ok ||
	bad "stability NoV/NoV: no pole line"
grep -q '^safe in half as is$' "$T/st" && bad "stability NoV/NoV called safe" || ok
$BK stability 'NoV/(NoV + 1)' 2>/dev/null | grep -q '^safe in half as is$' && ok || bad "stability pole control"

# ---- a form with no value is neither emitted nor measured (M6) ----------------
for f in 'NoV/0' '1/(NoV-NoV)' '1/0' 'sqrt(0-1)'; do
	case $f in NoV/0) token="not finite: a division by the constant 0" ;;
	           *NoV*) token="NaN or infinite everywhere on its inputs' domain" ;;
	           *) token="the code would compute a constant that is not finite" ;; esac
	refused "codegen c $f" 2 "$token" $BK codegen --lang c "$f"
	refused "codegen glsl $f" 2 "$token" $BK codegen --lang glsl "$f"
	refused "ops $f" 2 "$token" $BK ops "$f"
	refused "gpucost $f" 2 "$token" $BK gpucost "$f" --chips navi21
	refused "time $f" 2 "$token" $BK time "$f"
done
# negative control: a pole at one point (NoL = 0) is a form with values
accepted "codegen NoV/NoL" $BK codegen --lang c 'NoV/NoL'
accepted "ops NoV/NoL" $BK ops 'NoV/NoL'

# ---- pow of a negative base means what a GPU computes: no value (H1) --------------
# the audit's commands: eval said f64 -0.001953125, stability 'f32 wrong 0',
# codegen emitted pow(t2, 9.0) silently (NaN on every GPU)
refused "eval (NoV-1)^9" 1 "value not finite at NoV=0.5: f64 nan" $BK eval '(NoV-1)^9' NoV=0.5
refused "eval pow(NoV-1, NoH) at 0^0" 1 "f64 nan" $BK eval 'pow(NoV-1, NoH)' NoV=1 NoH=0
$BK stability '(NoV-1)^9' 2>/dev/null | grep -q '^the form itself is NaN or infinite at 130 of 143 samples' && ok ||
	bad "stability (NoV-1)^9: not NaN below NoV = 1"
# controls: an integral power up to 8 is multiplies, a number below 0 too
$BK eval '(NoV-1)^3' NoV=0.5 2>&1 | grep -q '^f64 -0.125$' && ok || bad "eval (NoV-1)^3 is not -0.125"
$BK codegen --lang c 'NoV^2.5' | grep -qF 'exp2f(2.5f * log2f(NoV))' && ok ||
	bad "codegen C: pow is not spelled exp2f(y * log2f(x))"

# ---- pN= the form does not use; --chips duplicates and empty items (M10) -------
refused "eval p1 unused" 2 "p1=VALUE has no effect: the form uses p0 only" $BK eval 'NoV*p0' p0=1 p1=2 NoV=0.5
refused "codegen p1 unused" 2 "p1=VALUE has no effect" $BK codegen --lang c 'NoV*p0' p0=1 p1=2
refused "gpucost p1 unused" 2 "p1=VALUE has no effect" $BK gpucost 'NoV*p0' p0=1 p1=2 --chips navi21
refused "time p1 unused" 2 "p1=VALUE has no effect" $BK time 'NoV*p0' p0=1 p1=2
refused "eval catalog p1 unused" 2 "p1=VALUE has no effect: vf_talk_r uses p0 only" $BK eval vf_talk_r p1=2 LoH=1 r=1
refused "eval p0 on no parameter" 2 "uses no parameter" $BK eval 'NoV' p0=1 NoV=0.5
refused "eval p0 missing" 2 "uses p0 but no value was given" $BK eval 'NoV*p0' NoV=0.5
[ "$($BK eval 'NoV*p0' p0=2 NoV=0.25 2>&1 | head -1)" = "f64 0.5" ] && ok || bad "eval p0 control"
for c in navi21,navi21 navi21,NAVI21 navi21, ,navi21 navi21,,vega10; do
	case $c in *,,*|*,|,*) token="an empty item" ;; *) token="named twice" ;; esac
	refused "gpucost --chips $c" 2 "$token" $BK gpucost NoV --chips "$c"
done
$BK gpucost NoV --chips navi21,vega10 --out "$T/chips.csv" 2>/dev/null && ok || bad "gpucost two chips"
[ "$(csv_col "$T/chips.csv" chip | tr '\n' ' ')" = "navi21 vega10 " ] && ok || bad "gpucost two chips: rows"

# ---- fp16 calibration on a chip without shaderFloat16 (M7) ---------------------
refused "calibrate fp16 polaris10" 2 "polaris10 has no shaderFloat16" \
	$BK gpucost --precision half --calibrate --chips polaris10
# negative control: navi21 has it, and its counts are counts (not all zero)
$BK gpucost --precision half --calibrate --chips navi21 --out "$T/cal.csv" 2>/dev/null && ok || bad "calibrate fp16 navi21"
[ "$(csv_col "$T/cal.csv" instructions | awk '$1 > 0' | wc -l)" -gt 20 ] && ok || bad "calibrate fp16 navi21: counts"

# ---- a driver path elsewhere is named, not a package to install (L4) -----------
refused "VK_ICD_FILENAMES elsewhere" 1 "VK_ICD_FILENAMES=/nonexistent does not name RADV's" \
	env VK_ICD_FILENAMES=/nonexistent $BK gpucost NoV
grep -q apt-get "$T/err" && bad "VK_ICD_FILENAMES elsewhere: install line" || ok

# ---- 200 levels deep, as brdfkit(1) says ---------------------------------
for n in 200 201; do
	awk -v n=$n 'BEGIN { for (i = 0; i < n; i++) printf "("; printf "NoV"; for (i = 0; i < n; i++) printf ")"; print "" }' >"$T/d$n"
done
[ "$($BK eval @"$T/d200" NoV=0.5 2>&1 | head -1)" = "f64 0.5" ] && ok || bad "200 levels: $($BK eval @"$T/d200" NoV=0.5 2>&1)"
refused "201 levels" 2 "nested too deeply (more than 200 levels)" $BK eval @"$T/d201" NoV=0.5

# ---- constants the precision cannot hold; clamp bounds out of order (L13) ------
# warn_once NAME TOKEN CMD...: exit 0, code on stdout, exactly one stderr line with TOKEN
warn_once() {
	name=$1 token=$2; shift 2
	"$@" >"$T/out" 2>"$T/err" && [ -s "$T/out" ] && [ "$(wc -l <"$T/err")" -eq 1 ] && grep -qF -- "$token" "$T/err" &&
		ok || bad "$name: stderr '$(cat "$T/err")'"
}
warn_once "exp2 in half" "warning: form: exp2(128) is +inf in half precision" \
	$BK codegen --lang glsl --precision half 'exp2(127.99)*NoV'
warn_once "1e-46 in float" "warning: form: the constant 1e-46 is 0 in single precision" $BK codegen --lang c '1e-46*NoV'
warn_once "clamp reversed" "warning: clamp(x, 1, 0) has its lower bound above its upper" \
	$BK codegen --lang glsl 'clamp(NoV, 1, 0)'
grep -qF 'min(max(NoV, 1.0), 0.0)' "$T/out" && ok || bad "clamp reversed: not spelled min(max())"
# negative controls: in range and in order, no word
accepted "exp2 in float" $BK codegen --lang glsl 'exp2(127.99)*NoV'
accepted "exp2(15) in half" $BK codegen --lang glsl --precision half 'exp2(15)*NoV'
accepted "clamp in order" $BK codegen --lang glsl 'clamp(NoV, 0.1, 1)'
grep -qF 'clamp(NoV, 0.1, 1.0)' "$T/out" && ok || bad "clamp in order: $(cat "$T/out")"

# ---- names: reserved ones refused, tricky accepted ones compile (M11) ----------
long64=$(awk 'BEGIN { for (i = 0; i < 64; i++) printf "x"; print "" }')
long63=$(awk 'BEGIN { for (i = 0; i < 63; i++) printf "y"; print "" }')
long5000=$(awk 'BEGIN { for (i = 0; i < 5000; i++) printf "z"; print "" }')
for n in pow sqrt exp2 sqrtf powf fabs M_PI M_PIf y0 j1 gamma fadd f32addf64 roundevenf lgammaf_r INFINITY isnan \
	HUGE_VALF FP_NAN main linux unix _x __y _Bool; do
	refused "c --name $n" 2 "'$n' is reserved in c" $BK codegen --lang c --name "$n" 'NoV*NoL'
done
for n in main texture textureLod texture2D mix smoothstep fract inversesqrt dFdx fma inverse gl_x a__b vec3 \
	f16vec2 dmat3x2 sampler2D isampler3D image2D iimage2D uimageCube texture2DArray subpassInput float16_t half input; do
	refused "glsl --name $n" 2 "'$n' is reserved in glsl" $BK codegen --lang glsl --name "$n" 'NoV*NoL'
done
for n in main lerp saturate tex2D frac mul rsqrt mad WaveActiveSum float4 half3x3 min16float uint64_t \
	Texture2D SamplerState _Foo a__b; do
	refused "hlsl --name $n" 2 "'$n' is reserved in hlsl" $BK codegen --lang hlsl --name "$n" 'NoV*NoL'
done
for l in c glsl hlsl; do
	refused "$l --name 64 characters" 2 "64 characters, more than 63" $BK codegen --lang $l --name "$long64" NoV
	refused "$l --name 5000 characters" 2 "5000 characters, more than 63" $BK codegen --lang $l --name "$long5000" NoV
done

# compile_c NAME FILE: gcc -c as C11 and as GNU C (whose math.h and
# predefined macros add names) with every warning an error
compile_c() {
	gcc -c -std=c11 -pedantic -Wall -Wextra -Werror -o "$T/o.o" "$2" >"$T/cc" 2>&1 &&
		gcc -c -std=gnu11 -Wall -Wextra -Werror -o "$T/o.o" "$2" >>"$T/cc" 2>&1
}
# glsl_shaders FILE NAME OUT: GLSL ES 3.00 and GLSL 4.50 fragment shaders
# calling it, OUT.es.frag and OUT.450.frag; compile_glsl FILE NAME compiles
# the two alone ($T/alone.*, messages in $T/cc)
glsl_shaders() {
	{ printf '#version 300 es\nprecision highp float;\n'; cat "$1"
	  printf 'uniform highp float u0, u1;\nout vec4 o;\nvoid main() { o = vec4(%s(u0, u1)); }\n' "$2"; } >"$3.es.frag"
	{ printf '#version 450\n'; cat "$1"
	  printf 'uniform float u0, u1;\nout vec4 o;\nvoid main() { o = vec4(%s(u0, u1)); }\n' "$2"; } >"$3.450.frag"
}
compile_glsl() {
	glsl_shaders "$1" "$2" "$T/alone"
	glslangValidator "$T/alone.es.frag" >"$T/cc" 2>&1 && glslangValidator "$T/alone.450.frag" >>"$T/cc" 2>&1
}
# compile_hlsl FILE NAME: a pixel shader calling it, through glslang's HLSL front end
compile_hlsl() {
	{ cat "$1"; printf 'float4 main(float4 u : TEXCOORD0) : SV_Target { return float4(%s(u.x, u.y), 0, 0, 1); }\n' "$2"; } >"$T/p.hlsl"
	glslangValidator -V -D -S frag -e main -o "$T/p.spv" "$T/p.hlsl" >"$T/cc" 2>&1
}
command -v gcc >/dev/null && command -v glslangValidator >/dev/null || bad "gcc and glslangValidator are needed"
for n in Float sq mix lerp texture saturate frac inversesqrt float4 vec3 Main x__y exp2_ powx D_ggx_fit "$long63"; do
	$BK codegen --lang c --name "$n" 'NoV*NoL' >"$T/f.c" 2>"$T/err" || bad "c --name $n refused: $(cat "$T/err")"
	compile_c "$n" "$T/f.c" && ok || bad "c --name $n does not compile: $(head -3 "$T/cc")"
done
# The GLSL shaders are compiled by one glslangValidator (each file its own
# shader, none linked: 60 starts were 8 CPU s of this script); when it
# refuses, each pair is compiled again alone to name the one at fault.
k=0
: >"$T/glsl.list"
for n in Float sq lerp saturate frac rsqrt mad mul float4 Main _x pow_ texture_ gl "$long63"; do
	for p in single half; do
		k=$((k + 1))
		$BK codegen --lang glsl --precision $p --name "$n" 'NoV*NoL' >"$T/f$k.glsl" 2>"$T/err" || bad "glsl --name $n refused"
		glsl_shaders "$T/f$k.glsl" "$n" "$T/g$k"
		printf '%s %s %s\n' "$k" "$p" "$n" >>"$T/glsl.list"
	done
done
if glslangValidator "$T"/g*.frag >"$T/batch" 2>&1; then
	while read -r k p n; do ok; done <"$T/glsl.list"
else
	f0=$fail
	while read -r k p n; do
		compile_glsl "$T/f$k.glsl" "$n" && ok || bad "glsl $p --name $n does not compile: $(grep ERROR "$T/cc" | head -2)"
	done <"$T/glsl.list"
	[ "$fail" -gt "$f0" ] || bad "glslangValidator refused the shaders together, none alone: $(grep ERROR "$T/batch" | head -2)"
fi
for n in Float sq mix texture_ inversesqrt fract vec3 _x gl_x Main "$long63"; do
	for p in single half; do
		$BK codegen --lang hlsl --precision $p --name "$n" 'NoV*NoL' >"$T/f.hlsl" 2>"$T/err" || bad "hlsl --name $n refused"
		compile_hlsl "$T/f.hlsl" "$n" && ok || bad "hlsl $p --name $n does not compile: $(grep ERROR "$T/cc" | head -2)"
	done
done
# negative controls: the same compiles fail for a reserved name written in by hand
$BK codegen --lang c --name ctl 'NoV*NoL' | sed 's/ ctl(/ pow(/' >"$T/bad.c"
compile_c pow "$T/bad.c" && bad "c control: pow compiled" || ok
$BK codegen --lang c --name ctl 'NoV*NoL' | sed 's/ ctl(/ y0(/' >"$T/bad.c"
compile_c y0 "$T/bad.c" && bad "c control: y0 compiled as GNU C" || ok
$BK codegen --lang glsl --name ctl 'NoV*NoL' | sed 's/ ctl(/ texture(/' >"$T/bad.glsl"
compile_glsl "$T/bad.glsl" texture && bad "glsl control: texture compiled" || ok
$BK codegen --lang hlsl --name ctl 'NoV*NoL' | sed 's/ ctl(/ float4(/' >"$T/bad.hlsl"
compile_hlsl "$T/bad.hlsl" float4 && bad "hlsl control: float4 compiled" || ok

echo "cli_ir: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
