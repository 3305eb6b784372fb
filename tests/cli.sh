#!/bin/sh
# cli.sh — the command-line contract of brdfkit: help, exact values where a
# closed form exists, one-line errors naming the bad input with a non-zero exit,
# nothing left on disk after a failure, and the same bytes for the same command.
# usage: sh tests/cli.sh path/to/brdfkit
set -u
BK=${1:?usage: cli.sh path/to/brdfkit}
T=$(mktemp -d /tmp/bk_cli_XXXXXX)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0

ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }

# expect_out NAME EXPECTED CMD...: stdout equals EXPECTED, exit 0.
expect_out() {
	name=$1 want=$2; shift 2
	got=$("$@" 2>"$T/err") && [ "$got" = "$want" ] && ok || bad "$name: got '$got' $(cat "$T/err")"
}

# expect_error NAME TOKEN CMD...: non-zero exit, one line on stderr naming TOKEN.
expect_error() {
	name=$1 token=$2; shift 2
	if "$@" >"$T/out" 2>"$T/err"; then bad "$name: exit 0"; return; fi
	lines=$(wc -l <"$T/err")
	if [ "$lines" -eq 1 ] && grep -qF -- "$token" "$T/err"; then ok; else bad "$name: stderr '$(cat "$T/err")'"; fi
}

# help on every command
for c in "" terms dfg lut albedo; do
	if $BK $c --help >"$T/out" 2>&1 && grep -q '^usage: brdfkit' "$T/out"; then ok; else bad "help $c"; fi
done

# closed forms: r = 0 is the mirror, A = 1 - (1 - NoV)^5 = 0.96875 at NoV = 0.5
expect_out "dfg smooth limit" "nov,roughness,A,B
0.5,0,0.96875,0.03125" $BK dfg --nov 0.5 --roughness 0
# albedo at r = 0 with implicit V (1/4) and F = 1: V F NoL 4 VoH / NoH = NoV^2
expect_out "albedo smooth limit" "D,V,F,nov,roughness,f0,f90,eta,k,albedo
D_ggx,V_implicit,F_schlick,0.5,0,1,1,inf,0,0.25" \
	$BK albedo --d ggx --v implicit --f schlick --nov 0.5 --roughness 0 --f0 1
# glass: --ior 1.5 gives f0 = ((1.5 - 1)/(1.5 + 1))^2 = 0.04
$BK albedo --d ggx --v implicit --f dielectric --nov 1 --roughness 0 --ior 1.5 >"$T/out" 2>&1
grep -q '^D_ggx,V_implicit,F_dielectric,1,0,0.04,1,1.5,0,0.04$' "$T/out" && ok || bad "ior 1.5: $(cat "$T/out")"

# terms: every role present, 24 terms
n=$($BK terms --csv | tail -n +2 | wc -l)
[ "$n" -eq 24 ] && ok || bad "terms --csv: $n rows"
for r in D V F Fd; do $BK terms --role $r | grep -q "\[$r\]" && ok || bad "terms --role $r"; done

# bad input: one line naming it, non-zero exit
expect_error "nov text" "'abc'" $BK dfg --nov abc --roughness 0.5
expect_error "nov nan" "'nan'" $BK dfg --nov nan --roughness 0.5
expect_error "nov range" "1.5" $BK dfg --nov 1.5 --roughness 0.5
expect_error "nov zero" "--nov" $BK dfg --nov 0 --roughness 0.5
expect_error "roughness inf" "'inf'" $BK dfg --nov 0.5 --roughness inf
expect_error "smith" "'foo'" $BK dfg --nov 0.5 --roughness 0.5 --smith foo
expect_error "missing" "--roughness" $BK dfg --nov 0.5
expect_error "unknown option" "'--bogus'" $BK dfg --nov 0.5 --roughness 0.5 --bogus 1
expect_error "unknown command" "'frobnicate'" $BK frobnicate
expect_error "unknown D" "'nope'" $BK albedo --d nope --v implicit --f schlick --nov 0.5 --roughness 0.5 --f0 0.04
expect_error "role mismatch" "'F_schlick'" $BK albedo --d ggx --v F_schlick --f schlick --nov 0.5 --roughness 0.5 --f0 0.04
expect_error "f0 and ior" "--ior" $BK albedo --d ggx --v implicit --f schlick --nov 0.5 --roughness 0.5 --f0 0.04 --ior 1.5
expect_error "lut size" "--size" $BK lut --size 0 --out "$T/a.exr"
expect_error "lut suffix" "'$T/a.png'" $BK lut --size 4 --out "$T/a.png"
expect_error "lut origin" "'left'" $BK lut --size 4 --origin left --out "$T/a.exr"
expect_error "lut unwritable" "$T/no/dir/a" $BK lut --size 4 --out "$T/no/dir/a.exr"
expect_error "albedo unwritable" "$T/no/x.csv" $BK albedo --d ggx --v implicit --f schlick --nov 0.5 --roughness 0.5 --f0 0.04 --out "$T/no/x.csv"
# nothing half-written: the failed commands above left no file or temporary
[ -z "$(ls -A "$T" | grep -v '^out$\|^err$')" ] && ok || bad "left behind: $(ls -A "$T")"

# the formula IR: 1/(0.5^2 (0.5 + 0.5)) = 4 exactly in every precision
expect_out "eval exact" "f64 4
f32 4
f16 4" $BK eval '1/(LoH*LoH*(r+p0))' LoH=0.5 r=0.5 p0=0.5
# 1/(0.003^2 * 0.6) = 185185 > 65504: only half precision overflows
$BK eval '1/(LoH*LoH*(r+p0))' LoH=0.003 r=0.1 p0=0.5 >"$T/out" 2>&1
grep -q '^f16 inf$' "$T/out" && grep -q '^f32 185185' "$T/out" && ok || bad "eval overflow: $(cat "$T/out")"
# the talk's claims from the counter: one division, no other complex op ...
$BK ops 'r^4 / (4*3.14159265*sq(NoH*NoH*(r^4 - 1) + 1) * LoH*LoH*(r + 0.5))' --csv >"$T/out"
grep -q '^div,1$' "$T/out" && grep -q '^complex,1$' "$T/out" && ok || bad "ops talk specular: $(tr '\n' ' ' <"$T/out")"
# ... none in its environment BRDF; Karis's EnvBRDFApprox has one exp2
$BK ops env_talk_r:B --csv | grep -q '^complex,0$' && ok || bad "ops env_talk_r:B"
$BK ops env_karis2014 --csv >"$T/out"
grep -q '^exp2,1$' "$T/out" && grep -q '^complex,1$' "$T/out" && ok || bad "ops env_karis2014"
n=$($BK catalog | tail -n +2 | wc -l)
[ "$n" -ge 15 ] && ok || bad "catalog: $n entries"
$BK catalog | head -1 | grep -q '^name,target,form,parameters,source' && ok || bad "catalog header"
$BK codegen --lang glsl --precision mediump vf_talk_r >"$T/a.glsl" && $BK codegen --lang glsl --precision mediump vf_talk_r >"$T/b.glsl"
cmp -s "$T/a.glsl" "$T/b.glsl" && grep -q 'DO NOT EDIT' "$T/a.glsl" && grep -q 'mediump float vf_talk_r' "$T/a.glsl" && ok || bad "codegen glsl"
rm -f "$T/a.glsl" "$T/b.glsl"
expect_error "eval parse" "form:1:18: expected ')' at end of form" $BK eval '1/(LoH*LoH*(r+p0)' LoH=0.5
expect_error "eval missing input" "NoH" $BK eval 'D_ggx(NoH, a)' r=0.5
expect_error "eval missing param" "p0" $BK eval 'NoV + p0' NoV=0.5
expect_error "eval bad value" "'x'" $BK eval 'NoV' NoV=x
expect_error "codegen lang" "'fortran'" $BK codegen --lang fortran NoV
expect_error "codegen env needs part" "env_talk_r:A" $BK codegen --lang c env_talk_r
expect_error "ops unknown function" "near 'foo'" $BK ops 'foo(NoV)'

# fit: the talk's constant refitted on its own plane; every output file, the
# published row, and the exit status
if $BK fit --target vf2d --form vf_talk_r --nx 32 --nr 32 --out "$T/fit" >"$T/out" 2>"$T/err"; then ok; else bad "fit vf2d: $(cat "$T/err")"; fi
for f in coefficients.csv metrics.csv heatmap.exr heatmap.png heatmap.csv shader.c shader.glsl shader.hlsl; do
	[ -s "$T/fit/$f" ] && ok || bad "fit: missing $f"
done
grep -qx 'constants,cost,rmse,weighted_rmse,max_abs,max_rel,albedo_max_abs' "$T/fit/metrics.csv" && ok || bad "metrics header"
grep -q '^published,' "$T/fit/metrics.csv" && grep -q '^fitted,' "$T/fit/metrics.csv" && ok || bad "metrics rows"
grep -q '^form,parameter,value,standard_error$' "$T/fit/coefficients.csv" && ok || bad "coefficients header"
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
for f in compare.csv timing.csv pareto_cost.svg pareto_ns.svg section.html heatmaps/vf_talk_r.png shaders/vf_talk_r_refit.glsl; do
	[ -s "$T/cmp/$f" ] && ok || bad "compare: missing $f"
done
head -1 "$T/cmp/compare.csv" | grep -q '^name,kind,source,form,form_b,parameters,rmse,' && ok || bad "compare.csv header"
grep -q '<svg' "$T/cmp/section.html" && ok || bad "section without its plot"
$BK report --out "$T/page.html" "$T/cmp/section.html" && grep -q '<h2>Target <code>vf2d</code></h2>' "$T/page.html" && ok || bad "report"
rm -rf "$T/cmp" "$T/page.html"
expect_error "compare target" "'nope'" $BK compare --target nope --out "$T/x"
expect_error "time parse" "form:1:" $BK time 'NoV +'

# ---- issue 9 (input side: numbers, forms, limits, names) ----
# numbers: decimal and scientific only, every item present; subnormals are numbers
expect_error "hex option" "'0x10'" $BK dfg --nov 0x10 --roughness 0.5
expect_error "list empty item" "empty item in the list '0.5,,0.6'" $BK dfg --nov 0.5,,0.6 --roughness 0.5
expect_error "list leading comma" "empty item in the list ',0.5'" $BK dfg --nov ,0.5 --roughness 0.5
expect_error "list trailing comma" "empty item in the list '0.5,'" $BK dfg --nov 0.5, --roughness 0.5
expect_error "option overflow" "'1e999'" $BK dfg --nov 0.5 --roughness 1e999
expect_error "option underflow to zero" "'1e-400'" $BK dfg --nov 1e-400 --roughness 0.5
expect_error "option leading space" "' 0.5'" $BK dfg --nov ' 0.5' --roughness 0.5
expect_error "eval hex input" "NoV: expected a finite number, got '0x1'" $BK eval NoV NoV=0x1
expect_error "eval inf input" "NoV: expected a finite number, got 'inf'" $BK eval NoV NoV=inf
expect_error "time hex param" "p0: expected a finite number, got '0x1'" $BK time 'p0*NoV' p0=0x1
expect_error "fit hex start" "'p0=0x1'" $BK fit --target f --form 'p0*LoH' p0=0x1 --out "$T/fit"
expect_error "fit hex range" "'0x0:1'" $BK fit --target f --form 'p0*LoH' p0=1 --r-range 0x0:1 --out "$T/fit"
# 1e-320 is subnormal (below 2^-1022 ~ 2.2e-308) and finite: accepted
$BK dfg --nov 1e-320 --roughness 0.5 >"$T/out" 2>"$T/err" && ok || bad "subnormal option: $(cat "$T/err")"
$BK eval NoV NoV=1e-320 >"$T/out" 2>"$T/err" && grep -q '^f64 9.99' "$T/out" && ok || bad "subnormal input: $(cat "$T/err")"
# literals that are not the number typed; a value that is not finite
expect_error "literal overflow" "form:1:7: number too large (overflows double) near '1e999'" $BK eval 'NoV * 1e999' NoV=1
expect_error "eval nan" "value not finite: f64 nan" $BK eval '0/0'
expect_error "eval pole" "value not finite at NoV=1 NoL=0: f64 inf" $BK eval 'NoV/NoL' NoV=1 NoL=0
expect_error "codegen 1/0" "1 / 0 is +inf in single precision" $BK codegen --lang c '1/0'
expect_error "codegen sqrt(-1)" "sqrt(-1) is NaN in single precision" $BK codegen --lang glsl 'sqrt(-1.0)*NoV'
expect_error "codegen past FLT_MAX" "the constant 1e+39 is +inf" $BK codegen --lang hlsl 'NoV*1e39'
expect_error "compare nan form" "form '0/0': not finite at any of the" \
	$BK compare --target f --no-refit --no-time --out "$T/cmpnan" '0/0'
[ ! -e "$T/cmpnan" ] && ok || bad "compare nan form left $T/cmpnan"
# names the target language refuses; a near one compiles
expect_error "codegen name int" "'int' is reserved in c" $BK codegen --lang c --name int NoV
expect_error "codegen name vec3" "'vec3' is reserved in glsl" $BK codegen --lang glsl --name vec3 NoV
expect_error "codegen name half" "'half' is reserved in hlsl" $BK codegen --lang hlsl --name half NoV
if $BK codegen --lang c --name int_ 'NoV*NoL' >"$T/int_.c" 2>"$T/err" && cc -std=c11 -Wall -Werror -c "$T/int_.c" -o "$T/int_.o" 2>>"$T/err"; then
	ok; else bad "codegen --name int_: $(cat "$T/err")"; fi
rm -f "$T/int_.c" "$T/int_.o"
# options and inputs that would do nothing, or be silently replaced
expect_error "dfg tol and samples" "--tol and --samples" $BK dfg --nov 0.5 --roughness 0.5 --tol 1e-6 --samples 64
expect_error "eval input twice" "NoV given twice" $BK eval NoV NoV=0.5 NoV=0.6
expect_error "eval VoH != LoH" "VoH=0.5 and LoH=0.6 differ" $BK eval VoH VoH=0.5 LoH=0.6
expect_out "eval VoH = LoH" "f64 0.5
f32 0.5
f16 0.5" $BK eval VoH VoH=0.5 LoH=0.5
# report: a section that is not text
expect_error "report binary section" "$BK: not text (a NUL byte at offset" $BK report --out "$T/bin.html" "$BK"
printf '<p>\377</p>\n' >"$T/latin1.html"
expect_error "report invalid utf-8" "latin1.html: not text (invalid UTF-8 at offset 3)" $BK report --out "$T/bin.html" "$T/latin1.html"
[ ! -e "$T/bin.html" ] && ok || bad "report left $T/bin.html"
rm -f "$T/latin1.html"
# forms: -- ends the options, @FILE and - read a form, limits named
expect_out "form after --" "f64 -0.5
f32 -0.5
f16 -0.5" $BK eval -- -NoV NoV=0.5
expect_out "form --NoV after --" "f64 0.5
f32 0.5
f16 0.5" $BK eval -- --NoV NoV=0.5
printf 'NoV*2\n' >"$T/form.txt"
expect_out "eval @FILE" "f64 1
f32 1
f16 1" $BK eval "@$T/form.txt" NoV=0.5
expect_out "eval stdin" "f64 1.5
f32 1.5
f16 1.5" sh -c "echo 'NoV*3' | $BK eval - NoV=0.5"
expect_out "ops @FILE" "mul        1" sh -c "$BK ops '@$T/form.txt' | grep '^mul'"
$BK codegen --lang c "@$T/form.txt" | grep -q '= NoV \* 2.0f;' && ok || bad "codegen @FILE"
printf 'NoV +\n' >"$T/bad.txt"
for c in eval ops time stability; do
	expect_error "$c @FILE" "brdfkit $c: form:1:6: expected a number" $BK $c "@$T/bad.txt"
done
expect_error "compare @FILE" "brdfkit compare: form:1:6:" $BK compare --target f --no-refit --no-time --out "$T/c" "@$T/bad.txt"
expect_error "fit --form @FILE" "brdfkit fit: form:1:6:" $BK fit --target f --form "@$T/bad.txt" --out "$T/fit"
expect_error "fit --weight @FILE" "brdfkit fit: weight:1:6:" $BK fit --target vf2d --form 'p0*NoV' --weight "@$T/bad.txt" --out "$T/fit" p0=1
expect_error "form file missing" "@$T/none.txt: cannot read: No such file or directory" $BK eval "@$T/none.txt"
printf 'NoV\000' >"$T/nul.txt"
expect_error "form file not text" "@$T/nul.txt: not text (a NUL byte at offset 3)" $BK eval "@$T/nul.txt"
awk 'BEGIN { s = "r"; for (i = 1; i <= 16384; i++) s = s " "; print s }' >"$T/long.txt"
expect_error "form too long" "form:1:16385: form longer than 16384 characters" $BK eval "@$T/long.txt"
awk 'BEGIN { s = "r"; for (i = 1; i < 4097; i++) s = s "+r"; print s }' >"$T/many.txt"
expect_error "form too many instructions" "form too large (more than 4096 instructions)" $BK eval "@$T/many.txt" r=1
awk 'BEGIN { for (i = 0; i < 300; i++) printf "("; printf "NoV"; for (i = 0; i < 300; i++) printf ")"; print "" }' >"$T/deep.txt"
expect_error "form too deep" "form:1:201: expression nested too deeply (more than 200 levels)" $BK eval "@$T/deep.txt" NoV=1
rm -f "$T/form.txt" "$T/bad.txt" "$T/nul.txt" "$T/long.txt" "$T/many.txt" "$T/deep.txt"

# determinism: the same command gives the same bytes
# (the command line is recorded in the files, so both runs use one path)
for k in 1 2; do
	$BK lut --size 8 --half --out "$T/d.exr" 2>/dev/null && cp "$T/d.exr" "$T/d$k.exr" && cp "$T/d.csv" "$T/d$k.csv"
	$BK albedo --d all --v hammon --f schlick --nov 0.3 --roughness 0.6 --f0 0.04 --out "$T/alb.csv" 2>/dev/null && cp "$T/alb.csv" "$T/alb$k.csv"
done
cmp -s "$T/d1.exr" "$T/d2.exr" && ok || bad "lut exr differs between runs"
cmp -s "$T/d1.csv" "$T/d2.csv" && ok || bad "lut csv differs between runs"
cmp -s "$T/alb1.csv" "$T/alb2.csv" && ok || bad "albedo csv differs between runs"

echo "cli: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
