#!/bin/sh
# cli_numbers.sh — brdfkit's command-line contract (the common start:
# tests/lib_cli.sh): the input side: numbers, forms, limits, names (issue 9).
# usage: sh tests/cli_numbers.sh path/to/brdfkit
NAME=cli_numbers
. "$(dirname "$0")/lib_cli.sh"

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
expect_error "fit hex start" "p0: expected a finite number, got '0x1'" $BK fit --target f --form 'p0*LoH' p0=0x1 --out "$T/fit"
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
expect_error "dfg tol and samples" "--tol has no effect with --samples" $BK dfg --nov 0.5 --roughness 0.5 --tol 1e-6 --samples 64
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
expect_error "form too deep" "form:1:202: expression nested too deeply (more than 200 levels)" $BK eval "@$T/deep.txt" NoV=1
rm -f "$T/form.txt" "$T/bad.txt" "$T/nul.txt" "$T/long.txt" "$T/many.txt" "$T/deep.txt"

# a start given twice is refused, not the last one silently taken
expect_error "fit p0 twice" "p0 given twice" $BK fit --target vf2d --form vf_talk_r p0=1 p0=2 --out "$T/fit2"
expect_error "fit p-0" "expected pN=VALUE" $BK fit --target vf2d --form vf_talk_r p-0=1 --out "$T/fit2"

cli_done
