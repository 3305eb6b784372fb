#!/bin/sh
# cli_basics.sh — brdfkit's command-line contract (the common start:
# tests/lib_cli.sh): help on every command; the closed forms of dfg and albedo;
# terms; bad input; a LUT laid out for a scene; eval, ops, catalog and codegen;
# the same bytes for the same lut and albedo.
# usage: sh tests/cli_basics.sh path/to/brdfkit
NAME=cli_basics
. "$(dirname "$0")/lib_cli.sh"

# help on every command
for c in "" terms dfg lut albedo search scene; do
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
$BK albedo --d ggx --v implicit --f dielectric --nov 1 --roughness 0 --ior 1.5 >"$T/alb.csv" 2>"$T/err"
[ "$(csv_cols "$T/alb.csv" F eta f0 albedo)" = "$(printf 'F_dielectric\t1.5\t0.04\t0.04')" ] && ok ||
	bad "ior 1.5: $(cat "$T/alb.csv" "$T/err")"

# terms: every role present, 26 terms (D_charlie and D_ashikhmin since issue 41)
$BK terms --csv >"$T/terms.csv" 2>"$T/err" && n=$(csv_col "$T/terms.csv" name | wc -l) && [ "$n" -eq 26 ] && ok ||
	bad "terms --csv: ${n:-no} rows $(cat "$T/err")"
for r in D V F Fd; do
	$BK terms --role $r >"$T/out" 2>&1 && [ "$(grep -o '\[[A-Za-z]*\]$' "$T/out" | sort -u)" = "[$r]" ] && ok || bad "terms --role $r"
done

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
expect_error "lut origin" "'left'" $BK lut --size 4 --origin left --out "$T/a.exr"
expect_error "lut unwritable" "$T/no/dir/a" $BK lut --size 4 --out "$T/no/dir/a.exr"
expect_error "lut r-range" "'0.5:0.4'" $BK lut --size 4 --r-range 0.5:0.4 --out "$T/lr"
expect_error "lut r-range text" "'0.2'" $BK lut --size 4 --r-range 0.2 --out "$T/lr"
expect_error "lut warp" "'cube'" $BK lut --size 4 --warp cube --out "$T/lr"
expect_error "lut f0" "--f0" $BK lut --size 4 --f0 1.5 --out "$T/lr"
[ ! -e "$T/lr" ] && ok || bad "a refused lut left --out behind"
# a LUT laid out for a scene: one channel f0 A + B, rows over r in [0.4, 1],
# x at u = sqrt(NoV): the first texel is NoV = (0.5/4)^2 = 0.015625 at
# r = 0.4 + 0.6 (0.5/4) = 0.475, and holds 0.04 A + B there, as dfg gives it
# lut_first_texel DFG.CSV DFG_OUT.CSV: the LUT's first row is at NoV 0.015625,
# r 0.475 and its env is 0.04 A + B of dfg's A and B there (to 1e-7)
lut_first_texel() {
	[ "$(csv_cols "$1" nov roughness | head -1)" = "$(printf '0.015625\t0.475')" ] || return 1
	env=$(csv_col "$1" env | head -1) && a=$(csv_col "$2" A) && b=$(csv_col "$2" B) || return 1
	awk -v e="$env" -v a="$a" -v b="$b" 'BEGIN { d = e - (0.04 * a + b); exit !(e != "" && d * d < 1e-14) }'
}
$BK lut --size 4 --f0 0.04 --r-range 0.4:1 --warp sqrt --tol 1e-8 --out "$T/lf" 2>/dev/null
$BK dfg --nov 0.015625 --roughness 0.475 >"$T/dfg1.csv"
lut_first_texel "$T/lf/dfg.csv" "$T/dfg1.csv" && [ "$(grep -v '^#' "$T/lf/dfg.csv" | head -1)" = nov,roughness,env ] && ok ||
	bad "lut laid out: $(grep -v '^#' "$T/lf/dfg.csv" | head -2 | tr '\n' ' '), dfg $(tail -1 "$T/dfg1.csv")"
# control: dfg's B off by 1e-6 (a texel 1e-6 wrong) must fail
b=$(csv_col "$T/dfg1.csv" B) && csv_set "$T/dfg1.csv" B nov 0.015625 "$(awk -v b="$b" 'BEGIN { printf "%.9g", b + 1e-6 }')" >"$T/dfg1x.csv" &&
	expect_fail "lut laid out" lut_first_texel "$T/lf/dfg.csv" "$T/dfg1x.csv" || bad "lut laid out: no control"
rm -rf "$T/lf" "$T/dfg1.csv" "$T/dfg1x.csv"
expect_error "albedo unwritable" "$T/no/x.csv" $BK albedo --d ggx --v implicit --f schlick --nov 0.5 --roughness 0.5 --f0 0.04 --out "$T/no/x.csv"
# nothing half-written: the failed commands above left no file or temporary
# (the test's own files and lib.sh's .csv_* set aside first)
rm -f "$T/alb.csv" "$T/terms.csv" "$T"/.csv_*
[ -z "$(ls -A "$T" | grep -v '^out$\|^err$')" ] && ok || bad "left behind: $(ls -A "$T")"

# the formula IR: 1/(0.5^2 (0.5 + 0.5)) = 4 exactly in every precision
expect_out "eval exact" "f64 4
f32 4
f16 4" $BK eval '1/(LoH*LoH*(r+p0))' LoH=0.5 r=0.5 p0=0.5
# 1/(0.003^2 * 0.6) = 185185 > 65504: only half precision overflows
$BK eval '1/(LoH*LoH*(r+p0))' LoH=0.003 r=0.1 p0=0.5 >"$T/out" 2>&1
grep -q '^f16 inf$' "$T/out" && grep -q '^f32 185185' "$T/out" && ok || bad "eval overflow: $(cat "$T/out")"
# the talk's claims from the counter: one division, no other complex op ...
# ops_count CSV CLASS N: brdfkit ops --csv counts N of CLASS
ops_count() { [ "$(csv_where "$1" class "$2" count)" = "$3" ]; }
$BK ops 'r^4 / (4*3.14159265*sq(NoH*NoH*(r^4 - 1) + 1) * LoH*LoH*(r + 0.5))' --csv >"$T/ops.csv"
ops_count "$T/ops.csv" div 1 && ops_count "$T/ops.csv" complex 1 && ok || bad "ops talk specular: $(tr '\n' ' ' <"$T/ops.csv")"
expect_fail "ops count" ops_count "$T/ops.csv" div 2
# ... none in its environment BRDF; Karis's EnvBRDFApprox has one exp2
$BK ops env_talk_r:B --csv >"$T/ops.csv" && ops_count "$T/ops.csv" complex 0 && ok || bad "ops env_talk_r:B"
$BK ops env_karis2014 --csv >"$T/ops.csv"
ops_count "$T/ops.csv" exp2 1 && ops_count "$T/ops.csv" complex 1 && ok || bad "ops env_karis2014"
# the README's count (and brdfkit-catalog(1)): 39 published forms
$BK catalog >"$T/cat.csv" && n=$(csv_col "$T/cat.csv" name | wc -l) && [ "$n" -eq 39 ] && ok || bad "catalog: ${n:-no} entries, the README says 39"
head -1 "$T/cat.csv" | grep -q '^name,target,form,parameters,source' && ok || bad "catalog header"
$BK codegen --lang glsl --precision half vf_talk_r >"$T/a.glsl" && $BK codegen --lang glsl --precision half vf_talk_r >"$T/b.glsl"
cmp -s "$T/a.glsl" "$T/b.glsl" && grep -q 'DO NOT EDIT' "$T/a.glsl" && grep -q 'mediump float vf_talk_r' "$T/a.glsl" && ok || bad "codegen glsl"
rm -f "$T/a.glsl" "$T/b.glsl"
expect_error "eval parse" "form:1:18: expected ')' at end of form" $BK eval '1/(LoH*LoH*(r+p0)' LoH=0.5
expect_error "eval missing input" "NoH" $BK eval 'D_ggx(NoH, a)' r=0.5
expect_error "eval missing param" "p0" $BK eval 'NoV + p0' NoV=0.5
expect_error "eval bad value" "'x'" $BK eval 'NoV' NoV=x
expect_error "codegen lang" "'fortran'" $BK codegen --lang fortran NoV
expect_error "codegen env needs part" "env_talk_r:A" $BK codegen --lang c env_talk_r
expect_error "ops unknown function" "near 'foo'" $BK ops 'foo(NoV)'

# determinism: the same command gives the same bytes
# (the command line is recorded in the files, so both runs use one path)
for k in 1 2; do
	$BK lut --size 8 --precision half --out "$T/d" 2>/dev/null && cp "$T/d/dfg.exr" "$T/d$k.exr" && cp "$T/d/dfg.csv" "$T/d$k.csv"
	$BK albedo --d all --v hammon --f schlick --nov 0.3 --roughness 0.6 --f0 0.04 --out "$T/alb.csv" 2>/dev/null && cp "$T/alb.csv" "$T/alb$k.csv"
done
cmp -s "$T/d1.exr" "$T/d2.exr" && ok || bad "lut exr differs between runs"
cmp -s "$T/d1.csv" "$T/d2.csv" && ok || bad "lut csv differs between runs"
cmp -s "$T/alb1.csv" "$T/alb2.csv" && ok || bad "albedo csv differs between runs"

cli_done
