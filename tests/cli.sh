#!/bin/sh
# cli.sh — the command-line contract of brdfkit: help, exact values where a
# closed form exists, one-line errors naming the bad input with a non-zero exit,
# nothing left on disk after a failure, and the same bytes for the same command.
# CSV is read by column name (tests/lib.sh); every threshold check is a named
# function, run once more on an input it must refuse (its negative control).
# usage: sh tests/cli.sh path/to/brdfkit
set -u
BK=${1:?usage: cli.sh path/to/brdfkit}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
: "${CSVGET:=$ROOT/build/csvget}"
T=$(mktemp -d /tmp/bk_cli_XXXXXX)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0

ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
. "$ROOT/tests/lib.sh"
[ -x "$CSVGET" ] || { bad "no $CSVGET (make build/csvget)"; echo "cli: $pass passed, $fail failed"; exit 1; }

# lacks FILE PATTERN: FILE was written (non-empty) and no line matches PATTERN
# (a bare "grep -q ... && bad || ok" passes when the file is missing)
lacks() { [ -s "$1" ] || return 1; grep -q -- "$2" "$1"; [ $? -eq 1 ]; }
# close_to GOT WANT RTOL: both numbers, |GOT - WANT| <= RTOL |WANT| + 1e-30
close_to() {
	awk -v g="$1" -v w="$2" -v t="$3" 'BEGIN { num = "^[-+]?([0-9]+[.]?[0-9]*|[.][0-9]+)([eE][-+]?[0-9]+)?$"
		if (g !~ num || w !~ num) exit 1
		d = g - w; if (d < 0) d = -d; m = w < 0 ? -w : w; exit !(d <= t * m + 1e-30) }'
}
# is_num TEXT: TEXT is one decimal or scientific number
is_num() { close_to "$1" "$1" 0; }
# has_rows FILE COLUMN: FILE is a CSV with COLUMN and at least one data row
has_rows() { csv_col "$1" "$2" >/dev/null; }

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

# fit: the talk's constant refitted on its own plane; every output file, the
# published row, and the exit status
if $BK fit --target vf2d --form vf_talk_r --nx 32 --nr 32 --out "$T/fit" >"$T/out" 2>"$T/err"; then ok; else bad "fit vf2d: $(cat "$T/err")"; fi
for f in heatmap.exr heatmap.png shader.c shader.glsl shader.hlsl; do
	[ -s "$T/fit/$f" ] && ok || bad "fit: missing $f"
done
grep -qx 'constants,cost,rmse,weighted_rmse,max_abs,max_rel,albedo_max_abs' "$T/fit/metrics.csv" && ok || bad "metrics header"
# a row each, with a number for rmse (not a header alone)
csv_min "$T/fit/metrics.csv" rmse >/dev/null && csv_where "$T/fit/metrics.csv" constants published rmse >/dev/null &&
	csv_where "$T/fit/metrics.csv" constants fitted rmse >/dev/null && ok || bad "metrics rows"
grep -q '^form,parameter,value,standard_error$' "$T/fit/coefficients.csv" && ok || bad "coefficients header"
[ "$(csv_where "$T/fit/coefficients.csv" parameter p0 form)" = vf_talk_r ] && ok || bad "coefficients: no p0 row"
# the heatmap: one row per cell of the 32 x 32 grid
[ "$(csv_col "$T/fit/heatmap.csv" error | wc -l)" -eq 1024 ] && ok || bad "heatmap.csv: not 32 x 32 rows"
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
for f in compare.csv pareto_cost.svg section.html heatmaps/vf_talk_r.png shaders/vf_talk_r_refit.glsl; do
	[ -s "$T/cmp/$f" ] && ok || bad "compare: missing $f"
done
# --no-time measured nothing: no timing table, no plot against ns
for f in timing.csv pareto_ns.svg; do [ ! -e "$T/cmp/$f" ] && ok || bad "compare --no-time wrote $f"; done
head -1 "$T/cmp/compare.csv" | grep -q '^name,kind,source,form,form_b,parameters,rmse,' && ok || bad "compare.csv header"
# the talk's form and its refit are rows with an rmse
is_num "$(csv_where "$T/cmp/compare.csv" name vf_talk_r rmse)" &&
	is_num "$(csv_where "$T/cmp/compare.csv" name 'vf_talk_r (refit)' rmse)" && ok || bad "compare.csv: no vf_talk_r rows"
# the target is never a competitor (results/compare/vf2d/pareto_cost.png drew vf2d's own
# v_kelemen_talk_r x F_schlick at error 0): no row exact on every sample, and the
# page names what was left out; negative control: the committed compare.csv of
# before (it has the row at max_abs 0) fails the same check
csv_any_le "$T/cmp/compare.csv" max_abs 0 && bad "compare: a row at error 0 (the target itself)" || ok
grep -q 'Left out as the target itself (exact on every sample): v_kelemen_talk_r x F_schlick' "$T/cmp/section.html" &&
	ok || bad "compare: section.html does not name the target left out"
printf 'name,max_abs\nv_kelemen_talk_r x F_schlick,0\nvf_talk_r,0.26\n' >"$T/self.csv"
csv_any_le "$T/self.csv" max_abs 0 && ok || bad "negative control: a row at error 0 is not seen"
grep -q "<img src=\"pareto_cost.svg\"" "$T/cmp/section.html" && [ -s "$T/cmp/pareto_cost.pdf" ] && [ -s "$T/cmp/pareto_cost.png" ] && ok || bad "section without its plot"
$BK report --out "$T/page.html" "$T/cmp/section.html" && grep -q '<h2>Target <code>vf2d</code></h2>' "$T/page.html" && ok || bad "report"
rm -rf "$T/cmp" "$T/page.html"
expect_error "compare target" "'nope'" $BK compare --target nope --out "$T/x"
expect_error "time parse" "form:1:" $BK time 'NoV +'

# ---- issue 9 (output directories: only brdfkit's replaced, whole) ----
# siblings OUT: what a run left beside OUT (temporaries, set-aside copies)
siblings() { ls -A "$(dirname "$1")" | grep -F "$(basename "$1")." ; }
in_dir() { (d=$1; shift; cd "$d" && exec "$@"); }
case $BK in /*) BKA=$BK ;; *) BKA=$PWD/$BK ;; esac
O="$T/own"; mkdir -p "$O/d/mydocs"; echo x >"$O/d/mydocs/thesis.tex"
# a user's directory is refused, before any work, and left as it was
expect_error "stability onto a user's dir" "--out d/mydocs" in_dir "$O" $BKA stability NoV --out d/mydocs
[ "$(cat "$T/err")" = "brdfkit stability: --out d/mydocs: exists and was not written by brdfkit; choose another path or remove it" ] \
	&& ok || bad "stability refusal text: $(cat "$T/err")"
for c in "compare --target vf2d --nx 8 --nr 8 --no-time" "fit --target vf2d --form vf_talk_r --nx 8 --nr 8" "lut --size 4"; do
	expect_error "${c%% *} onto a user's dir" "--out $O/d/mydocs: exists and was not written by brdfkit" $BK $c --out "$O/d/mydocs"
done
[ "$(ls -A "$O/d/mydocs")" = thesis.tex ] && [ "$(cat "$O/d/mydocs/thesis.tex")" = x ] && ok || bad "user's dir touched: $(ls -A "$O/d/mydocs")"
# fit no longer moves a user's files aside to DIR.oldXXXXXX
[ -z "$(siblings "$O/d/mydocs")" ] && ok || bad "beside the user's dir: $(siblings "$O/d/mydocs")"
echo x >"$O/file"
expect_error "stability onto a file" "--out $O/file: exists and was not written by brdfkit" $BK stability NoV --out "$O/file"
# the current directory and its parents are refused, whatever they hold (/ is in
# test_out.c: a broken build must not be let loose on it)
mkdir -p "$O/cwd/sub"; : >"$O/cwd/sub/keep"
for o in . .. ../.. ../sub ./; do
	expect_error "--out $o" "--out $o: is the current directory or one of its parents" in_dir "$O/cwd/sub" $BKA stability NoV --out "$o"
done
[ -e "$O/cwd/sub/keep" ] && [ -e "$O/d/mydocs/thesis.tex" ] && ok || bad "--out . emptied the current directory"
# an empty directory may be used; the result carries the marker with the command
mkdir "$O/empty"
$BK stability NoV --out "$O/empty" >/dev/null 2>&1 && [ "$(csv_col "$O/empty/stability.csv" form)" = NoV ] && ok || bad "empty dir not used"
grep -qx "brdfkit stability NoV --out $O/empty" "$O/empty/.brdfkit-output" && ok || bad "marker: $(cat "$O/empty/.brdfkit-output")"
# a brdfkit directory is replaced whole: nothing of the old run stays, nothing beside it
$BK stability D_ggx --out "$O/s" >/dev/null 2>&1 && [ -s "$O/s/maps/d_ggx.png" ] && ok || bad "stability D_ggx"
$BK stability NoV --out "$O/s" >/dev/null 2>&1 && [ -s "$O/s/maps/form.png" ] && [ ! -e "$O/s/maps/d_ggx.png" ] \
	&& ok || bad "not replaced whole: $(ls "$O/s/maps")"
[ -z "$(siblings "$O/s")" ] && ok || bad "left beside: $(siblings "$O/s")"
# a symlink inside a brdfkit directory was not written by its run: refused,
# nothing followed or removed (issue 21: only what the marker lists is deleted)
mkdir "$O/p"; echo keep >"$O/p/keep.txt"; ln -s ../p "$O/s/link"; ln -s ../p/keep.txt "$O/s/maps/file_link"
expect_error "replace with a symlink inside" "--out $O/s: holds 'link', which brdfkit did not write" $BK stability NoV --out "$O/s"
[ -L "$O/s/link" ] && [ "$(cat "$O/p/keep.txt" 2>/dev/null)" = keep ] && ok || bad "symlink followed: $(ls -A "$O/p")"
rm "$O/s/link" "$O/s/maps/file_link"
# a symlink at --out itself is not brdfkit's directory
ln -s s "$O/slink"
expect_error "--out a symlink" "--out $O/slink: is a symlink: give the directory itself" $BK stability NoV --out "$O/slink"
# look-alikes of a killed run's temporary, with a marker or without, whose
# names brdfkit never recorded, stay (issue 21, H4; a real killed run's
# temporary is removed: tests/fault.sh, tests/cli_out.sh)
mkdir "$O/s.tmpAbC123" "$O/s.tmpXyZ789"; : >"$O/s.tmpAbC123/.brdfkit-output"; : >"$O/s.tmpAbC123/stability.csv"
: >"$O/s.tmpXyZ789/mine.txt"
$BK stability NoV --out "$O/s" >/dev/null 2>&1 && [ -e "$O/s.tmpAbC123/stability.csv" ] && [ -e "$O/s.tmpXyZ789/mine.txt" ] \
	&& ok || bad "leftovers: $(siblings "$O/s")"
rm -rf "$O/s.tmpAbC123" "$O/s.tmpXyZ789"
# lut: the EXR and its CSV are one directory
$BK lut --size 4 --out "$O/lut" 2>/dev/null && [ "$(ls "$O/lut" | tr '\n' ' ')" = "dfg.csv dfg.exr " ] \
	&& ok || bad "lut dir: $(ls -A "$O/lut")"
$BK lut --size 2 --out "$O/lut" 2>/dev/null && grep -q '^# brdfkit .* 2x2' "$O/lut/dfg.csv" && [ -z "$(siblings "$O/lut")" ] \
	&& ok || bad "lut replaced: $(siblings "$O/lut")"
rm -rf "$O"

# ---- issue 9 (fit and stability: no silent wrong answers) ----
# expect_usage_error NAME TOKEN CMD...: exit 2 (bad usage), one line on stderr naming TOKEN.
expect_usage_error() {
	name=$1 token=$2; shift 2
	"$@" >"$T/out" 2>"$T/err"; rc=$?
	if [ "$rc" -eq 2 ] && [ "$(wc -l <"$T/err")" -eq 1 ] && grep -qF -- "$token" "$T/err"; then ok
	else bad "$name: exit $rc, stderr '$(cat "$T/err")'"; fi
}
# stab_f16 ARGS...: "samples wrong" of the f16 line of brdfkit stability.
stab_f16() { $BK stability "$@" 2>/dev/null | awk '$1 == "f16" { print $2, $3 }'; }
# stability reads the whole form: 240 terms NoV*1e-9 (0 in half, a reference below
# half's smallest normal: never wrong) and a tail NoV*300*300 = 90000 NoV, past
# 65504 for NoV > 0.728: the grid's cosines 0.9, 0.999, 0.99999 and 1, at its 13
# roughness values, are Inf in half: 52 of 143. A copy cut at 2 KB ends in "+NoV"
# and is safe in half.
P="NoV*1e-10+"; i=0
while [ $i -lt 240 ]; do P="${P}NoV*1e-9+"; i=$((i + 1)); done
[ ${#P} -gt 2100 ] && ok || bad "long form: ${#P} characters"
[ "$(stab_f16 "${P}NoV*300*300")" = "143 52" ] && ok || bad "long form: f16 $(stab_f16 "${P}NoV*300*300")"
$BK stability "${P}NoV*300*300" >"$T/out" 2>/dev/null; grep -q '^f16 ' "$T/out" && lacks "$T/out" 'safe in half as is' && ok || bad "long form called safe"
$BK stability "${P}NoV" 2>/dev/null | grep -q '^safe in half as is$' && ok || bad "long form without its tail"
# 1e5 is Inf in half and 0*Inf is NaN, where long double gives 0: wrong at all
# 143 samples, and no clamp fixes it (min(NaN, 65504) is not 0); NoV/NoV is NaN
# at NoV = 0 in long double too (13 samples): not wrong
[ "$(stab_f16 '0*(1e5*NoV)')" = "143 143" ] && ok || bad "0*(1e5*NoV): f16 $(stab_f16 '0*(1e5*NoV)')"
$BK stability '0*(1e5*NoV)' 2>/dev/null | grep -q '^guards: .*(still fails)$' && ok || bad "0*(1e5*NoV) guarded"
[ "$(stab_f16 'NoV/NoV')" = "143 0" ] && ok || bad "NoV/NoV: f16 $(stab_f16 'NoV/NoV')"
# parameters: a value for each, from pN=VALUE or the catalog (overridable)
expect_usage_error "stability p0 unset" "form uses p0 but no value was given (p0=VALUE)" $BK stability 'p0*1e5*NoV'
[ "$(stab_f16 'p0*NoV' p0=1e5)" = "143 143" ] && ok || bad "p0=1e5: f16 $(stab_f16 'p0*NoV' p0=1e5)"
$BK stability 'p0*NoV' p0=2 2>/dev/null | grep -q '^safe in half as is$' && ok || bad "p0=2"
$BK stability vf_talk_r p0=1e5 2>/dev/null | grep -q '^constants a half shader cannot hold: 1e+05 (infinite in half)$' && ok || bad "vf_talk_r p0=1e5"
expect_usage_error "stability p1 unused" "p1=VALUE has no effect" $BK stability 'p0*NoV' p0=1 p1=2
expect_usage_error "stability --all with a form" "'NoV'" $BK stability --all --out "$T/st" NoV
expect_usage_error "stability --link-prefix" "--link-prefix has no effect without --out" $BK stability NoV --link-prefix x/
# fit: the published row is at the published constant (0.5) whatever the start;
# its rmse from the closed forms: V = 0.25/(LoH^2 (1 - r^2) + r^2), F Schlick at
# f0 = 0.04, form 0.04/(4 LoH^2 (r + 0.5)), 256 x 256 cell centres, LoH from sqrt(0.1)
want=$(awk 'BEGIN { n = 256; lo = sqrt(0.1); for (j = 0; j < n; j++) for (k = 0; k < n; k++) {
	r = (j + 0.5) / n; L = lo + (k + 0.5) * (1 - lo) / n; y = 0.25 / (L*L*(1 - r*r) + r*r) * (0.04 + 0.96 * (1 - L)^5)
	e = 0.04 / (4*L*L*(r + 0.5)) - y; se += e*e }; printf "%.5g", sqrt(se / (n*n)) }')
$BK fit --target vf2d --form vf_talk_r p0=5 --out "$T/f5" >/dev/null 2>&1 && ok || bad "fit p0=5"
$BK fit --target vf2d --form vf_talk_r --out "$T/f0" >/dev/null 2>&1 && ok || bad "fit"
# metrics_row FILE ROW: every column of metrics.csv's row ROW (fails without it)
metrics_row() {
	for c in constants cost rmse weighted_rmse max_abs max_rel albedo_max_abs; do
		csv_where "$1" constants "$2" "$c" || return 1
	done
}
r5=$(metrics_row "$T/f5/metrics.csv" published) && r0=$(metrics_row "$T/f0/metrics.csv" published) && [ "$r5" = "$r0" ] &&
	ok || bad "published row depends on p0="
[ -s "$T/f5/heatmap_published.csv" ] && cmp -s "$T/f5/heatmap_published.csv" "$T/f0/heatmap_published.csv" && ok ||
	bad "published heatmap depends on p0="
got=$(csv_where "$T/f5/metrics.csv" constants published rmse | awk '{ printf "%.5g", $1 }')
[ "$got" = "$want" ] && [ "$want" = "0.02861" ] && ok || bad "published rmse $got, closed form $want"
rm -rf "$T/f5" "$T/f0"
expect_usage_error "fit digits" "--digits: expected an integer in [1, 17] or half, got '-7xyz'" \
	$BK fit --target vf2d --form vf_talk_r --digits=-7xyz --out "$T/bad"
# fits that would do nothing: a zero weight, a form without parameters
expect_usage_error "fit weight 0" "--weight '0' is not positive at any of the 4096 samples" \
	$BK fit --target vf2d --form vf_talk_r --nx 64 --nr 64 --weight 0 --out "$T/bad"
[ ! -e "$T/bad" ] && ok || bad "refused fit left $T/bad"
$BK fit --target vf2d --form LoH --out "$T/loh" >"$T/out" 2>&1 && ok || bad "fit LoH: $(cat "$T/out")"
[ "$(head -1 "$T/out")" = "fit form on vf2d: no parameters: evaluated, not fitted" ] && ok || bad "fit LoH: $(head -1 "$T/out")"
lacks "$T/out" 'converged' && ok || bad "fit LoH says converged"
want=$(awk 'BEGIN { n = 256; lo = sqrt(0.1); for (j = 0; j < n; j++) for (k = 0; k < n; k++) {
	r = (j + 0.5) / n; L = lo + (k + 0.5) * (1 - lo) / n; y = 0.25 / (L*L*(1 - r*r) + r*r) * (0.04 + 0.96 * (1 - L)^5)
	e = L - y; se += e*e }; printf "%.5g", sqrt(se / (n*n)) }')
got=$(csv_where "$T/loh/metrics.csv" constants fitted rmse | awk '{ printf "%.5g", $1 }')
[ "$got" = "$want" ] && [ -s "$T/loh/shader.c" ] && ok || bad "fit LoH rmse $got, closed form $want"
rm -rf "$T/loh"
# a step too small to take from a non-optimal point is no convergence (exit 3)
$BK fit --target vf2d --form vf_talk_r --nx 32 --nr 32 --loss huber --loss-scale 1e-300 --out "$T/ns" >/dev/null 2>&1
[ $? -eq 3 ] && ok || bad "huber 1e-300 called converged" # needs the fitter's no-step rule (h-numdet)
$BK fit --target vf2d --form vf_talk_r --nx 32 --nr 32 p0=1e308 --out "$T/ns" >/dev/null 2>&1
[ $? -eq 3 ] && ok || bad "p0=1e308 called converged" # needs the fitter's no-step rule (h-numdet)
rm -rf "$T/ns"
# options that would change nothing are refused, naming the conflict
F="--target vf2d --form vf_talk_r --nx 8 --nr 8 --out $T/bad"
expect_usage_error "fit ior" "--ior has no effect on target vf2d (it sets the exact Fresnel of target f)" $BK fit $F --ior 1.4
expect_usage_error "fit nu" "--nu has no effect on target vf2d" $BK fit $F --nu 4
expect_usage_error "fit smith" "--smith has no effect on target vf2d" $BK fit $F --smith schlick
expect_usage_error "fit f0 list" "--f0: target vf2d uses one value, got 2" $BK fit $F --f0 0.1,0.2
expect_usage_error "fit weight dnol" "--weight dnol has no effect on target vf2d" $BK fit $F --weight dnol
expect_usage_error "fit loss-scale" "--loss-scale has no effect without --loss" $BK fit $F --loss-scale 2
expect_usage_error "fit p1" "'p1=2' has no effect: the form uses p0 only" $BK fit $F p1=2
expect_usage_error "fit talk" "--talk-roughness has no effect on target vf" \
	$BK fit --target vf --form vf_talk_r --talk-roughness a --out "$T/bad"
expect_usage_error "fit f0 on f" "--f0 has no effect on target f" $BK fit --target f --form 'p0*LoH' p0=1 --f0 0.5 --out "$T/bad"
expect_usage_error "fit starts, no parameters" "--starts has no effect: the form has no parameters" \
	$BK fit --target f --form LoH --starts 3 --out "$T/bad"
# --k applies with the default index 1.5 (it used to need --ior)
$BK fit --target f --nx 8 --form 'F_schlick(f0, 1, LoH)' --k 3 --out "$T/k" >/dev/null 2>&1 &&
	grep -q 'index 1.5 + 3i' "$T/k/metrics.csv" && ok || bad "fit --k without --ior"
rm -rf "$T/k"
# compare: the same rule, and typed forms it cannot score as written
expect_usage_error "compare no-lut" "--no-lut has no effect on target vf2d" $BK compare --target vf2d --no-lut --out "$T/bad"
expect_usage_error "compare reps" "--reps has no effect with --no-time" $BK compare --target vf2d --no-time --reps 3 --out "$T/bad"
expect_usage_error "compare p0" "'p0*LoH' uses p0" $BK compare --target vf2d --out "$T/bad" 'p0*LoH'
expect_usage_error "compare input" "'NoV' reads NoV, which target vf2d does not provide" \
	$BK compare --target vf2d --nx 8 --nr 8 --no-time --out "$T/bad" NoV
[ ! -e "$T/bad" ] && ok || bad "refused commands left $T/bad"

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

# ---- issue 9 (numerics: tiny roughness, long fits, CPU-independent fits) ----
# r too small to resolve (a = r^2 underflows below r ~ 1e-162; 1e-160 gives a
# subnormal a) is the smooth limit, A = 1 - (1 - NoV)^5 = 0.96875 at NoV = 0.5,
# and returns (it once looped for ever, or failed at r = 1e-100)
for r in 1e-300 1e-200 1e-160 1e-100 1e-20 1e-08; do
	expect_out "dfg tiny r $r" "nov,roughness,A,B
0.5,$r,0.96875,0.03125" timeout 20 $BK dfg --nov 0.5 --roughness $r
	expect_out "albedo tiny r $r" "D,V,F,nov,roughness,f0,f90,eta,k,albedo
D_ggx,V_implicit,F_schlick,0.5,$r,1,1,inf,0,0.25" \
		timeout 20 $BK albedo --d ggx --v implicit --f schlick --nov 0.5 --roughness $r --f0 1
done

# the same fit gives the same bytes whichever exp/log/pow glibc picks (FMA or
# not, chosen at run time from the CPU): env_karis2014's constants that the
# data do not pin once moved in their first digit between the two
for k in 1 2; do
	[ $k = 2 ] && tun=glibc.cpu.hwcaps=-AVX2,-FMA || tun=
	GLIBC_TUNABLES=$tun $BK fit --target env --form env_karis2014_split --hold p8,p9,p10 --nx 16 --nr 16 \
		--out "$T/fma" >/dev/null 2>&1 && cp "$T/fma/coefficients.csv" "$T/fma$k.csv"
done
cmp -s "$T/fma1.csv" "$T/fma2.csv" && ok || bad "env fit depends on the libm path: $(diff "$T/fma1.csv" "$T/fma2.csv" | head -4)"
grep -q '^# not identifiable, held at the start value: p1, p5$' "$T/fma1.csv" && ok || bad "held parameters not named"
rm -rf "$T/fma" "$T/fma1.csv" "$T/fma2.csv"
# ... and so do the reference integrals under it: cos, sin, acos and pow of
# glibc also differ by an ulp between the two, which walked a refit whose
# optimum sits on a saturate/min kink (env_narkowicz2014_lazarov_g1mr) to
# another point; the integrators now use brdf/dmath.c
for k in 1 2; do
	[ $k = 2 ] && tun=glibc.cpu.hwcaps=-AVX2,-FMA || tun=
	GLIBC_TUNABLES=$tun $BK compare --target env --no-time --no-lut --out "$T/fmac" >/dev/null 2>&1 &&
		cp "$T/fmac/compare.csv" "$T/fmac$k.csv"
done
cmp -s "$T/fmac1.csv" "$T/fmac2.csv" && ok || bad "compare env depends on the libm path: $(diff "$T/fmac1.csv" "$T/fmac2.csv" | cut -c1-60 | head -4)"
rm -rf "$T/fmac" "$T/fmac1.csv" "$T/fmac2.csv"
# ... and so do the IR's exp2, log2, pow, exp and log, now brdf/dmath.c's:
# glibc's own differ between the two at these points (found by a sweep; its
# log2 gave -7.5327805285534151 under the tunable, -7.532780528553416 without),
# and a search, whose default grammar has log2, moved with them: with libm's
# log2 the candidate 16,238 of this f search fitted to 0.000917661935 under
# the tunable, 0.000917663798 without
for k in 1 2; do
	[ $k = 2 ] && tun=glibc.cpu.hwcaps=-AVX2,-FMA || tun=
	for fx in 'log2(NoV)|0.005400166' 'pow(NoV, 1.7)|0.0010567180000000001' 'exp(-NoV)|0.002714966' \
		'log(NoV)|0.010078442' 'exp2(-3*NoV)|1.1' 'log2(NoV*NoV + 0.3)|0.37'; do
		GLIBC_TUNABLES=$tun $BK eval "${fx%|*}" NoV="${fx#*|}"
	done >"$T/fmae$k.txt" 2>&1
	GLIBC_TUNABLES=$tun $BK search --target f --ior 0.27 --k 2.78 --evals 17000 --threads 2 --quiet \
		--out "$T/fmas" >/dev/null 2>&1 && grep -v '^# command' "$T/fmas/candidates.csv" >"$T/fmas$k.csv" &&
		cp "$T/fmas/pareto.svg" "$T/fmas$k.svg" # its log axis: brdfkit's log10 (glibc's has a variant too)
done
[ "$(grep -c '^f64 ' "$T/fmae1.txt")" = 6 ] && cmp -s "$T/fmae1.txt" "$T/fmae2.txt" && ok ||
	bad "eval depends on the libm path: $(diff "$T/fmae1.txt" "$T/fmae2.txt" | head -4)"
[ -s "$T/fmas1.csv" ] && cmp -s "$T/fmas1.csv" "$T/fmas2.csv" && ok ||
	bad "search depends on the libm path: $(diff "$T/fmas1.csv" "$T/fmas2.csv" | cut -c1-90 | head -4)"
[ -s "$T/fmas1.svg" ] && cmp -s "$T/fmas1.svg" "$T/fmas2.svg" && ok || bad "search plot depends on the libm path"
rm -rf "$T/fmas" "$T"/fmae?.txt "$T"/fmas?.csv "$T"/fmas?.svg

# within_5s T0: at most 5 s have passed since T0 (date +%s)
within_5s() { [ $(($(date +%s) - $1)) -le 5 ]; }
# long env fits: the work is stated up front, an unwritable --out is refused
# before it (at once, not after hours; a path under a regular file fails for
# root too), and logs (stderr not a terminal) see progress while it runs
: >"$T/file"
for cmd in "fit --target env --form env_karis2014_split" "compare --target env --no-time"; do
	t0=$(date +%s)
	expect_error "$cmd unwritable out" "--out $T/file/sub: cannot create: not a directory" \
		timeout 20 $BK $cmd --nx 1024 --nr 1024 --out "$T/file/sub"
	within_5s "$t0" && ok || bad "$cmd: unwritable --out refused only after the work"
done
# control: the same clock check after 6 s must fail
t0=$(date +%s); sleep 6; expect_fail "refused at once" within_5s "$t0"
timeout 3 $BK fit --target env --form env_karis2014_split --nx 4096 --nr 4096 --out "$T/big" >/dev/null 2>"$T/err"
grep -q '^fit: env target 4096x4096 = 16.8M integrals, about [0-9.]* \(s\|min\|h\) on this machine$' "$T/err" && ok \
	|| bad "no work estimate: $(cat "$T/err")"
timeout 20 $BK fit --target env --form env_karis2014_split --nx 256 --nr 64 --out "$T/mid" >/dev/null 2>"$T/err"
grep -q '^reference: [1-5]\?[0-9]/64 ([0-9]* %, [0-9]* s)$' "$T/err" && ok || bad "no progress lines in a log: $(cat "$T/err")"
rm -rf "$T/file" "$T/big" "$T/mid"

# a fit that took no step from a point that is not a minimum is not converged
# (exit 3, the reason said): a Huber scale that flattens every residual, and a
# start where the form is flat (the derivative of 1/(r + p0) underflows)
for how in "--loss huber --loss-scale 1e-300" "p0=1e308"; do
	$BK fit --target vf2d --form vf_talk_r $how --out "$T/nostep" >"$T/out" 2>&1
	st=$?
	[ $st -eq 3 ] && grep -q '^warning: did not converge (no step taken from a point that is not a minimum: ' "$T/out" && ok \
		|| bad "fit $how: exit $st: $(tail -1 "$T/out")"
done
rm -rf "$T/nostep"

# ---- issue 10 (form target) ----
# a target given by a formula: a planted form is recovered to every printed
# digit (its standard errors are ~1e-16, so the digits rule keeps 0.3, 0.7)
FT="0.3/(LoH*LoH + 0.7*r*r)"
$BK fit --target form --target-form "$FT" --domain LoH=0.3162:1,r=0:1 --form 'p0/(LoH*LoH + p1*r*r)' p0=1 p1=1 \
	--out "$T/ft" >"$T/out" 2>"$T/err"
st=$?
[ $st -eq 0 ] && [ "$(csv_where "$T/ft/coefficients.csv" parameter p0 value)" = 0.3 ] &&
	[ "$(csv_where "$T/ft/coefficients.csv" parameter p1 value)" = 0.7 ] && ok ||
	bad "form target: exit $st: $(cat "$T/err") $(cat "$T/ft/coefficients.csv")"
grep -qxF "# target form: $FT" "$T/ft/metrics.csv" && grep -qxF "# domain: LoH=0.3162:1,r=0:1 (cell centres, 64 per axis)" \
	"$T/ft/metrics.csv" && grep -q '^ \* fitted domain: form: 0.3/(LoH\*LoH + 0.7\*r\*r) evaluated in double on LoH in \[0.3162, 1\] x r in \[0, 1\]' \
	"$T/ft/shader.c" && ok || bad "form target: provenance: $(head -6 "$T/ft/metrics.csv")"
[ "$(csv_col "$T/ft/heatmap.csv" error | wc -l)" -eq $((64 * 64)) ] && ok || bad "form target: heatmap is not 64x64"
# three inputs: no plane, no heatmap, said on stdout
$BK fit --target form --target-form 'exp2(-5.5*LoH)*0.9*f0 + NoV' --domain LoH=0:1,f0=0:1,NoV=0:1 \
	--form 'p0*f0*exp2(p1*LoH) + NoV' p0=1 p1=-1 --out "$T/ft3" >"$T/out" 2>"$T/err" \
	&& grep -qx 'no heatmap: target form has 3 inputs; a heatmap needs 1 or 2' "$T/out" && [ ! -e "$T/ft3/heatmap.csv" ] \
	&& [ "$(csv_where "$T/ft3/coefficients.csv" parameter p1 value)" = -5.5 ] && ok || bad "form target, 3 inputs: $(cat "$T/out" "$T/err")"
# a target read from a file over two lines keeps the headers one line each
printf '0.3/(LoH*LoH +\n 0.7*r*r)\n' >"$T/ft.txt"
$BK fit --target form --target-form @"$T/ft.txt" --domain LoH=0.3162:1,r=0:1 --form 'p0/(LoH*LoH + p1*r*r)' p0=1 p1=1 \
	--out "$T/ft" >/dev/null 2>&1 && grep -qxF '# target form: 0.3/(LoH*LoH +  0.7*r*r)' "$T/ft/metrics.csv" \
	&& [ "$(csv_col "$T/ft/coefficients.csv" form | sort -u)" = 'p0/(LoH*LoH + p1*r*r)' ] \
	&& [ "$(grep -c '^form,\|^#\|^p0/' "$T/ft/coefficients.csv")" -eq "$(wc -l <"$T/ft/coefficients.csv")" ] && ok \
	|| bad "form target from a file: $(head -5 "$T/ft/coefficients.csv")"
rm -rf "$T/ft" "$T/ft3"
rm -f "$T/ft.txt"
FF="$BK fit --target form --form p0*LoH p0=1 --out $T/fe"
expect_error "form target: missing input" \
	"brdfkit fit: --target-form: the target form reads 'r', which the domain does not give (add r=LO:HI) (see brdfkit fit --help)" \
	$FF --target-form "$FT" --domain LoH=0.3162:1
expect_error "form target: unread input" \
	"brdfkit fit: --target-form: the domain gives 'NoV', which the target form does not read (see brdfkit fit --help)" \
	$FF --target-form "$FT" --domain LoH=0.3162:1,r=0:1,NoV=0:1
expect_error "form target: syntax" \
	"brdfkit fit: --domain: expected NAME=LO:HI, got 'LoH=0.3162' (see brdfkit fit --help)" \
	$FF --target-form "$FT" --domain LoH=0.3162,r=0:1
expect_error "form target: not an input" \
	"brdfkit fit: --domain: 'XoH' is not an input (NoV, NoL, NoH, LoH, r, a, f0) (see brdfkit fit --help)" \
	$FF --target-form LoH --domain XoH=0:1
expect_error "form target: strict number" \
	"brdfkit fit: --domain: LoH: expected LO:HI (two numbers), got '0x1:1' (see brdfkit fit --help)" \
	$FF --target-form LoH --domain LoH=0x1:1
expect_error "form target: LO >= HI" \
	"brdfkit fit: --domain: r: expected LO < HI, got '1:1' (see brdfkit fit --help)" \
	$FF --target-form "$FT" --domain LoH=0.3162:1,r=1:1
expect_error "form target: pole" \
	"brdfkit fit: the target form is inf at LoH = 0.625 (sample 3 of 4): a target must be finite on its domain" \
	$FF --target-form '1/(LoH - 0.625)' --domain LoH=0:1 --nx 4
expect_error "form target: parameter" \
	"brdfkit fit: --target-form: the target form uses p0..p1: a target has no parameters (write its constants as numbers) (see brdfkit fit --help)" \
	$FF --target-form 'p0*LoH + p1' --domain LoH=0:1
expect_error "form target: r and a" \
	"brdfkit fit: --target-form: the domain gives both 'r' and 'a': with r, a is r^2 (give one) (see brdfkit fit --help)" \
	$FF --target-form 'a*LoH' --domain LoH=0:1,r=0:1,a=0:1
expect_error "form target: no domain" \
	"brdfkit fit: target form needs --target-form EXPR and --domain IN=LO:HI[,...] (see brdfkit fit --help)" \
	$FF --target-form LoH
expect_error "form target: --domain elsewhere" \
	"brdfkit fit: --domain has no effect on target vf2d (it gives the domain of target form) (see brdfkit fit --help)" \
	$BK fit --target vf2d --form vf_talk_r --domain LoH=0:1 --out "$T/fe"
expect_error "form target: --target-form elsewhere" \
	"brdfkit fit: --target-form has no effect on target d (it gives the expression of target form) (see brdfkit fit --help)" \
	$BK fit --target d --form 'p0*NoH' p0=1 --target-form LoH --out "$T/fe"
expect_error "form target: --x-range" \
	"brdfkit fit: --x-range has no effect on target form (--domain sets the inputs of target form) (see brdfkit fit --help)" \
	$FF --target-form LoH --domain LoH=0:1 --x-range 0:0.5
expect_error "form target: candidate reads what the domain lacks" \
	"brdfkit fit: the form reads NoV, which target form does not provide" \
	$BK fit --target form --target-form LoH --domain LoH=0:1 --form 'p0*NoV' p0=1 --out "$T/fe"
expect_error "form target: compare" \
	"brdfkit compare: --target form: compare scores the catalog; fit a form target with brdfkit fit" \
	$BK compare --target form --out "$T/fe"
$FF --target-form "$FT" --domain LoH=0.3162:1 >/dev/null 2>&1; [ $? -eq 2 ] && ok || bad "form target: usage error is not exit 2"
[ ! -e "$T/fe" ] && ok || bad "form target: a refused run wrote $T/fe"

# stability's pN= takes the same number syntax as every other command
expect_error "stability p0 hex" "p0: expected a finite number, got '0x1p3'" $BK stability 'p0*NoV' p0=0x1p3

# ---- issue 10 (tiny) ----
# fit takes the TinySolver fast path where it applies (no finite bound, no
# loss, Levenberg-Marquardt: fit/tiny.cc) and Ceres elsewhere: stopped by an
# iteration limit of 1, the warning names the solver that stopped.
$BK fit --target vf2d --form vf_talk_r --nx 32 --nr 32 --starts 1 --max-iterations 1 --out "$T/tiny" >"$T/out" 2>&1
if grep -qxF 'warning: did not converge (iteration limit reached (TinySolver): 1 iterations)' "$T/out"; then ok
else bad "fit fast path: $(cat "$T/out")"; fi
for extra in "--bound p0=0:10" "--loss huber" "--trust-region dogleg"; do
	$BK fit --target vf2d --form vf_talk_r --nx 32 --nr 32 --starts 1 --max-iterations 1 $extra --out "$T/tiny" \
		>"$T/out" 2>&1
	if grep -qxF 'warning: did not converge (Maximum number of iterations reached. Number of iterations: 1.)' "$T/out"
	then ok; else bad "fit $extra: Ceres path: $(cat "$T/out")"; fi
done

# ---- issue 10 (search) ----
# A planted form: the target is 0.3/(LoH^2 + 0.7 r^2), a seed one mutation
# away (an r^2 term missing) starts the search. Since issue 22 (the
# neighbours of each level's best by one free constant, fit/expr.h) both
# the 3000- and the 8000-fit runs of brdfkit-search(1) (seed 1) hold the answer.
# Each member the front calls exact is re-evaluated outside the search
# (brdfkit eval against the target computed here in awk, 1e-12).
PLANT='0.3/(LoH*LoH + 0.7*r*r)'
PLANT_AWK='0.3/(x*x + 0.7*r*r)'
PLANT_POINTS="0.3162,0 0.5,0.5 0.7,0.2 1,1 0.4,0.9 0.9,0.05"
# planted_recovered FRONT: some member is the planted form (rmse <= 1e-9, confirmed)
planted_recovered() { front_answers "$BK" "$1" "$PLANT_AWK" $PLANT_POINTS; }
# best_below FRONT BOUND: the front's smallest rmse is a number below BOUND
best_below() { m=$(csv_min "$1" rmse) && awk -v m="$m" -v b="$2" 'BEGIN { exit !(m + 0 < b + 0) }'; }
search_plant() { # search_plant OUT EVALS [options]: the planted search, as brdfkit-search(1) runs it
	o=$1 e=$2; shift 2
	$BK search --target form --target-form "$PLANT" --domain LoH=0.3162:1,r=0:1 --start 'p0/(LoH*LoH + p1)' \
		--ops '+,*,/,sq' --max-params 2 --evals "$e" --out "$o" "$@"
}
# 3000 fits (issue 22): recovered, confirmed outside the search; the best is
# below 0.01 too, and a copy with every member below it edited up to 0.0123
# must fail that check; the front without the recovered members must fail the
# first
if search_plant "$T/plant" 3000 --threads 2 >"$T/out" 2>"$T/err" && hit3=$(planted_recovered "$T/plant/front.csv"); then ok
else bad "planted form not recovered in 3000 fits: $(csv_cols "$T/plant/front.csv" rmse form | sort -g | head -3) $(tail -3 "$T/err")"; fi
cp "$T/plant/front.csv" "$T/without3.csv"
for h in ${hit3:-}; do csv_drop "$T/without3.csv" name "$h" >"$T/w.csv" && mv "$T/w.csv" "$T/without3.csv"; done
expect_fail "planted form absent (3000 fits)" planted_recovered "$T/without3.csv"
if best_below "$T/plant/front.csv" 0.01; then ok
else bad "planted search, 3000 fits: best rmse $(csv_min "$T/plant/front.csv" rmse) not below 0.01"; fi
cp "$T/plant/front.csv" "$T/worse.csv"
for b in $(csv_cols "$T/plant/front.csv" rmse name | awk -F'\t' '$1 + 0 < 0.01 { print $2 }'); do
	csv_set "$T/worse.csv" rmse name "$b" 0.0123 >"$T/w.csv" && mv "$T/w.csv" "$T/worse.csv"
done
expect_fail "planted best below 0.01" best_below "$T/worse.csv" 0.01
# 8000 fits: recovered, and the member really is the planted form; controls:
# the front without it, and with the constant p0 of every member that answers
# edited to 0.3000001 (their rmse still claiming 1e-15: the re-evaluation must
# catch it; a front may hold more than one such member, e.g. a longer twin
# with LoH * (1 / LoH) in it)
if search_plant "$T/plant8" 8000 --threads 2 >"$T/out" 2>"$T/err" && hit=$(planted_recovered "$T/plant8/front.csv"); then ok
else bad "planted form not recovered in 8000 fits: $(csv_cols "$T/plant8/front.csv" rmse form | sort -g | head -3) $(tail -3 "$T/err")"; fi
cp "$T/plant8/front.csv" "$T/without.csv"
for h in ${hit:-}; do csv_drop "$T/without.csv" name "$h" >"$T/w.csv" && mv "$T/w.csv" "$T/without.csv"; done
expect_fail "planted form absent" planted_recovered "$T/without.csv"
cp "$T/plant8/front.csv" "$T/edited.csv"
edited=0
for h in ${hit:-}; do
	pars=$(csv_where "$T/edited.csv" name "$h" parameters | sed 's/^p0=[^;]*/p0=0.3000001/') &&
		csv_set "$T/edited.csv" parameters name "$h" "$pars" >"$T/w.csv" && mv "$T/w.csv" "$T/edited.csv" &&
		edited=$((edited + 1))
done
[ "$edited" -gt 0 ] && expect_fail "planted form, constant edited" planted_recovered "$T/edited.csv" ||
	bad "planted form: no control"
# registry terms as operations (--ops F_schlick): a planted Schlick Fresnel
# scaled by 0.25 is F_schlick(0.01, 0.25, LoH) (Schlick is linear in f0 and
# f90), in the grammar only through the term: the front must reach rmse 1e-9
# with a member that calls it, and that member is 0.25 (0.04 + 0.96 (1 - x)^5)
SCHLICK_AWK='0.25*(0.04 + 0.96*(1 - x)^5)'
SCHLICK_POINTS="0,0 0.1,0 0.37,0 0.5,0 0.93,0 1,0"
# schlick_recovered FRONT: a member calling F_schlick is the planted term (confirmed)
schlick_recovered() {
	front_answers "$BK" "$1" "$SCHLICK_AWK" $SCHLICK_POINTS >"$T/hits" || return 1
	for h in $(cat "$T/hits"); do csv_where "$1" name "$h" form | grep -q 'F_schlick(' && return 0; done
	return 1
}
if $BK search --target form --target-form '0.25*F_schlick(0.04, 1, LoH)' --domain LoH=0:1 --ops '+,*,F_schlick' \
	--evals 300 --threads 2 --out "$T/plantf" >"$T/out" 2>"$T/err" && schlick_recovered "$T/plantf/front.csv"; then ok
else bad "planted term not recovered: $(csv_cols "$T/plantf/front.csv" rmse form | sort -g | head -3) $(tail -3 "$T/err")"; fi
cp "$T/plantf/front.csv" "$T/without.csv"
for h in $(cat "$T/hits"); do csv_drop "$T/without.csv" name "$h" >"$T/w.csv" && mv "$T/w.csv" "$T/without.csv"; done
expect_fail "planted term absent" schlick_recovered "$T/without.csv"
expect_error "search term of 4 arguments" "V_cook_torrance takes 4 arguments" $BK search --target vf2d --ops '+,V_cook_torrance' --out "$T/sx"
# the same run on one thread: the same bytes (threads merge in candidate order)
$BK search --target form --target-form "$PLANT" --domain LoH=0.3162:1,r=0:1 --start 'p0/(LoH*LoH + p1)' \
	--ops '+,*,/,sq' --max-params 2 --evals 3000 --threads 1 --out "$T/plant1" >/dev/null 2>&1
for f in front.csv candidates.csv catalog.csv front/search_form_2/coefficients.csv; do
	grep -v '^# command' "$T/plant/$f" >"$T/a.csv"; grep -v '^# command' "$T/plant1/$f" >"$T/b.csv"
	[ -s "$T/a.csv" ] && cmp -s "$T/a.csv" "$T/b.csv" && ok || bad "search --threads 1 and 2 differ in $f"
done
# checkpoint and resume: 1200 fits, then on to 3000, equals 3000 at once
$BK search --target form --target-form "$PLANT" --domain LoH=0.3162:1,r=0:1 --start 'p0/(LoH*LoH + p1)' \
	--ops '+,*,/,sq' --max-params 2 --evals 1200 --threads 2 --checkpoint "$T/ck" --every 500 --out "$T/part" >/dev/null 2>&1
$BK search --target form --target-form "$PLANT" --domain LoH=0.3162:1,r=0:1 --start 'p0/(LoH*LoH + p1)' \
	--ops '+,*,/,sq' --max-params 2 --evals 3000 --threads 2 --resume "$T/ck" --out "$T/resumed" >/dev/null 2>"$T/err"
for f in front.csv candidates.csv; do
	grep -v '^# command' "$T/plant/$f" >"$T/a.csv"; grep -v '^# command' "$T/resumed/$f" >"$T/b.csv"
	has_rows "$T/a.csv" cost && cmp -s "$T/a.csv" "$T/b.csv" && ok || bad "resumed search differs in $f: $(cat "$T/err")"
done
# a resume with other options is refused, naming the file
expect_error "resume other options" "$T/ck" $BK search --target form --target-form "$PLANT" --domain LoH=0.3162:1,r=0:1 \
	--ops '+,*' --max-params 2 --evals 3000 --resume "$T/ck" --out "$T/x"
[ ! -e "$T/x" ] && ok || bad "a refused resume left --out behind"
# the screening front in candidates.csv is the Pareto front of the ok rows:
# no ok row is at most as costly and at most as wrong, one strictly, than a
# front member; every ok row off the front is dominated by one on it
# pareto_ok CANDIDATES: that holds, with at least one front member
pareto_ok() {
	csv_cols "$1" cost error status front >"$T/cand" || return 1
	awk -F'\t' '$3 == "ok" { n++; c[n] = $1 + 0; e[n] = $2 + 0; f[n] = $4; nf += ($4 == 1) }
	END { bad = (nf == 0)
	      for (i = 1; i <= n; i++) if (f[i] == 1) for (j = 1; j <= n; j++)
	        if (j != i && c[j] <= c[i] && e[j] <= e[i] && (c[j] < c[i] || e[j] < e[i])) bad++
	      for (i = 1; i <= n; i++) if (f[i] != 1) { dom = 0
	        for (j = 1; j <= n; j++) if (f[j] == 1 && c[j] <= c[i] && e[j] <= e[i]) dom = 1
	        if (!dom) bad++ }
	      exit bad != 0 }' "$T/cand"
}
pareto_ok "$T/plant/candidates.csv" && ok || bad "candidates.csv front is not the Pareto front"
# controls: a front member taken off the front, a dominated row put on it
fa=$(csv_where "$T/plant/candidates.csv" front 1 found_at | head -1)
csv_set "$T/plant/candidates.csv" front found_at "$fa" 0 >"$T/c1.csv" && expect_fail "pareto, member dropped" pareto_ok "$T/c1.csv" ||
	bad "pareto: no control"
fa=$(csv_cols "$T/plant/candidates.csv" found_at status front | awk -F'\t' '$2 == "ok" && $3 == 0 { print $1; exit }')
csv_set "$T/plant/candidates.csv" front found_at "$fa" 1 >"$T/c2.csv" && expect_fail "pareto, dominated row added" pareto_ok "$T/c2.csv" ||
	bad "pareto: no control"
# every front member's GLSL and HLSL compile (glslangValidator, wrapped in a
# fragment shader), and its C agrees with the IR's single precision at a point
# c_matches_ir GOT WANT: the C's value is the IR's f32 to 1e-6 relative
c_matches_ir() { close_to "$1" "$2" 1e-6; }
csv_col "$T/plant/front.csv" name >"$T/names" || : >"$T/names"
n=0
for name in $(cat "$T/names"); do
	d="$T/plant/front/$name"; n=$((n + 1))
	[ -d "$d" ] || { bad "front $name: no directory front/$name"; continue; }
	# the inputs in order, e.g. "LoH a"; a value for each: cosines 0.5, r 0.5, a 0.25
	ins=$(sed -n 's/^highp float [A-Za-z0-9_]*(\(.*\))$/\1/p' "$d/shader.glsl" | sed 's/highp float //g; s/,/ /g')
	glsl_call="" hlsl_call="" c_call="" points="" k=0
	for v in $ins; do
		case $v in a) x=0.25 ;; *) x=0.5 ;; esac
		lane=$(echo "u.x u.y u.z u.w v.x v.y v.z" | cut -d' ' -f$((k + 1)))
		sep=${glsl_call:+, }
		glsl_call="$glsl_call${sep}u_$v" hlsl_call="$hlsl_call$sep$lane" c_call="$c_call$sep${x}f" points="$points $v=$x"
		k=$((k + 1))
	done
	{ printf '#version 300 es\nprecision highp float;\n'; cat "$d/shader.glsl"
	  for v in $ins; do printf 'uniform highp float u_%s;\n' "$v"; done
	  printf 'out vec4 o;\nvoid main() { o = vec4(%s(%s)); }\n' "$name" "$glsl_call"
	} >"$T/m.frag"
	glslangValidator "$T/m.frag" >"$T/glsl.log" 2>&1 && ok || bad "front $name: GLSL does not compile: $(tail -3 "$T/glsl.log")"
	{ cat "$d/shader.hlsl"; printf 'float4 main(float4 u : TEXCOORD0, float4 v : TEXCOORD1) : SV_Target { return float4(%s(%s), 0, 0, 1); }\n' "$name" "$hlsl_call"; } >"$T/m.hlsl"
	glslangValidator -V -D -S frag -e main -o "$T/m.spv" "$T/m.hlsl" >"$T/hlsl.log" 2>&1 && ok || bad "front $name: HLSL does not compile: $(tail -3 "$T/hlsl.log")"
	# the C against brdfkit eval's f32 of the same form and constants
	form=$(csv_where "$T/plant/front.csv" name "$name" form)
	pars=$(csv_where "$T/plant/front.csv" name "$name" parameters | tr ';' ' ')
	{ cat "$d/shader.c"; printf '#include <stdio.h>\nint main(void) { printf("%%.9g\\n", (double)%s(%s)); return 0; }\n' "$name" "$c_call"; } >"$T/m.c"
	want=$($BK eval "$form" $pars $points | sed -n 's/^f32 //p')
	got=""
	if cc -std=c11 -O2 "$T/m.c" -lm -o "$T/m" 2>"$T/cc.log" && got=$("$T/m") && c_matches_ir "$got" "$want"; then ok
	else bad "front $name: C gives $got, the IR's f32 $want ($form $pars $points) $(cat "$T/cc.log")"; fi
	# control, once: the same comparison against a value 1e-5 off must fail
	[ $n -eq 1 ] && expect_fail "C against the IR" c_matches_ir "$got" "$(awk -v w="$want" 'BEGIN { printf "%.9g", w * (1 + 1e-5) }')"
done
[ "$n" -ge 3 ] && ok || bad "the planted search's front has $n members"
# usage errors: one line naming the bad input, nothing written
expect_error "search objective" "'worst'" $BK search --target vf2d --objective worst --out "$T/s1"
expect_error "search albedo on vf2d" "albedo" $BK search --target vf2d --objective albedo --out "$T/s1"
expect_error "search precision" "'quad'" $BK search --target vf2d --precision quad --out "$T/s1"
expect_error "search ops" "'cos'" $BK search --target vf2d --ops '+,cos' --out "$T/s1"
expect_error "search inputs" "'NoX'" $BK search --target vf2d --inputs LoH,NoX --out "$T/s1"
expect_error "search inputs provided" "NoV" $BK search --target vf2d --inputs NoV --out "$T/s1"
expect_error "search evals" "--evals" $BK search --target vf2d --evals 0 --out "$T/s1"
expect_error "search every" "--every" $BK search --target vf2d --every 10 --out "$T/s1"
expect_error "search f0 on env pairs" "--f0 has no effect on env split pairs" $BK search --target env --f0 1 --out "$T/s1"
expect_error "search f0 list" "--f0: one value, got 2" $BK search --target vf2d --f0 0.1,0.2 --out "$T/s1"
expect_error "search start target" "vf_talk_r" $BK search --target env --start vf_talk_r --out "$T/s1"
expect_error "search r-range names search" "brdfkit search: --r-range" $BK search --target vf2d --r-range 1:0 --out "$T/s1"
expect_error "search weights" "--cost-weights" $BK search --target vf2d --cost-weights simple=-1 --out "$T/s1"
[ ! -e "$T/s1" ] && ok || bad "a refused search left --out behind"
# --fetch-cost puts compare's LUT rows on the search's axis: cost K + 1 (the fetch
# and the mad of f0 A + B); refused where there is no LUT
expect_error "search fetch-cost on vf2d" "--fetch-cost" $BK search --target vf2d --fetch-cost 16 --out "$T/s3"
if $BK search --target env --evals 300 --fetch-cost 16 --out "$T/lut" >/dev/null 2>"$T/err" &&
	[ "$(csv_cols "$T/lut/catalog.csv" name cost | grep -c '^LUT [0-9]*x[0-9]* [a-z0-9]*	17$')" = 12 ]; then ok
else bad "search --fetch-cost: $(grep LUT "$T/lut/catalog.csv" | head -3) $(tail -2 "$T/err")"; fi
# --env-form f0: one form in f0 scored on f0 A + B (compare's quantity): the
# catalog's forms in f0 seed it, each split pair as f0*(A) + (B); no form_b
expect_error "search env-form" "'triple'" $BK search --target env --env-form triple --out "$T/s4"
expect_error "search env-form split start" "write it as 'f0*(A) + (B)'" $BK search --target env --env-form f0 \
	--start env_karis2014_split --out "$T/s4"
if $BK search --target env --env-form f0 --evals 400 --out "$T/ef0" >/dev/null 2>"$T/err"; then ok
else bad "search --env-form f0: $(tail -2 "$T/err")"; fi
grep -q '^# target: env: .*one form in f0 fitted to f0 A + B over the f0 list' "$T/ef0/front.csv" && ok ||
	bad "search --env-form f0: the target line: $(grep '^# target' "$T/ef0/front.csv")"
csv_col "$T/ef0/catalog.csv" name | grep -qx env_pesce_iwanicki2015 && ok || bad "search --env-form f0: Pesce-Iwanicki not a seed"
csv_where "$T/ef0/catalog.csv" name env_karis2014_split form | grep -q '^f0\*((p9\*' && ok ||
	bad "search --env-form f0: the split pair not as f0*(A) + (B)"
# every row: name, form (quoted or not), an empty form_b
csv_col "$T/ef0/front.csv" form_b >"$T/fb" && [ "$(grep -c . "$T/fb")" = 0 ] && ok ||
	bad "search --env-form f0: a front member with form_b"
# --env-form mix: f0 A + B is exactly mix(B, S, f0) (S = A + B, linear in
# f0), so searches of S (f0 = 1) and of B (f0 = 0) run first, a quarter of the
# budget each, and their fronts' compositions seed the search of forms in f0
expect_error "search mix checkpoint" "--checkpoint has no effect with --env-form mix" $BK search --target env --env-form mix \
	--checkpoint "$T/mx.ck" --out "$T/s5"
expect_error "search mix budget" "too few to share among three searches" $BK search --target env --env-form mix \
	--evals 500 --out "$T/s5"
expect_error "search mix max-cost" "leaves nothing to the halves" $BK search --target env --env-form mix --max-cost 3 \
	--out "$T/s5"
if $BK search --target env --env-form mix --evals 4000 --max-cost 15 --threads 2 --out "$T/mix" >/dev/null 2>"$T/err" &&
	grep -q '^search: S = A + B half: [0-9]* fits in' "$T/err" && grep -q '^search: B half: [0-9]* fits in' "$T/err" &&
	grep -q '^search: [0-9]* compositions mix(B, S, f0) seed the search' "$T/err"; then ok
else bad "search --env-form mix: $(tail -3 "$T/err")"; fi
# the compositions compete on the front (named after their seeding), and none
# is listed as a catalog row (those are the published forms)
csv_cols "$T/mix/front.csv" name form | grep -q '^seed_halves_[0-9]*	mix(' && ok || bad "search --env-form mix: no composition on the front"
csv_col "$T/mix/catalog.csv" name >"$T/names" && lacks "$T/names" '^halves\|^seed_halves' && ok || bad "search --env-form mix: a composition in catalog.csv"
# three searches in turn, still the same bytes on one thread
$BK search --target env --env-form mix --evals 4000 --max-cost 15 --threads 1 --out "$T/mix1" >/dev/null 2>&1
for f in front.csv candidates.csv; do
	grep -v '^# command' "$T/mix/$f" >"$T/a.csv"; grep -v '^# command' "$T/mix1/$f" >"$T/b.csv"
	[ -s "$T/a.csv" ] && cmp -s "$T/a.csv" "$T/b.csv" && ok || bad "search --env-form mix: $f differs between 2 threads and 1"
done
# SIGINT: the generation ends, the checkpoint and the front so far are written, exit 130
# (a job started with & from sh inherits SIGINT ignored, and the search keeps it
# so, as POSIX asks: env restores the default; --seconds bounds it should it fail)
env --default-signal=INT $BK search --target vf2d --evals 100000000 --seconds 120 --threads 2 --checkpoint "$T/int.ck" \
	--out "$T/int" >/dev/null 2>&1 &
pid=$!
sleep 3
kill -INT $pid
wait $pid
st=$?
[ $st -eq 130 ] && has_rows "$T/int/front.csv" rmse && [ -s "$T/int.ck" ] && ok \
	|| bad "search after SIGINT: exit $st, front.csv $(ls "$T/int" 2>&1 | head -3), checkpoint $(ls -la "$T/int.ck" 2>&1)"

# ---- issue 11 (scene) ----
# A scene without image-based lighting emits no environment BRDF, one without
# punctual lights no D or V*F; one dielectric f0 is folded away (no f0 input).
printf '{"scene": "no ibl", "materials": [{"name": "m", "roughness": {"min": 0.3, "max": 1}}],\n "lighting": {"ibl": false}, "target": {"error": {"vf": 0.2}}}\n' >"$T/noibl.json"
printf '{"scene": "no punctual", "materials": [{"name": "m", "roughness": {"min": 0.3, "max": 1}, "f0": {"min": 0.02, "max": 0.05}}],\n "lighting": {"punctual": false, "diffuse": false}, "target": {"precision": "mediump", "error": {"env": 0.06}}}\n' >"$T/nopunct.json"
if $BK scene "$T/noibl.json" "$T/nopunct.json" --no-time --out "$T/scene" >"$T/out" 2>"$T/err"; then ok; else bad "scene: $(tail -3 "$T/err")"; fi
d="$T/scene/noibl/spec_diffuse_f0_040"
for l in glsl hlsl c; do
	[ -s "$d/shader.$l" ] && ! grep -q '_env\b\|DFG\|LUT' "$d/shader.$l" && grep -q 'spec_diffuse_f0_040_vf(' "$d/shader.$l" \
		&& grep -q 'spec_diffuse_f0_040_D(' "$d/shader.$l" && ok || bad "scene without IBL: $d/shader.$l"
done
grep -q 'float spec_diffuse_f0_040_vf(' "$d/shader.c" && lacks "$d/shader.c" 'float spec_diffuse_f0_040_vf([^)]*f0' && ok || bad "one dielectric f0: V*F still reads f0"
e="$T/scene/nopunct/ibl_anyf0"
for l in glsl hlsl c; do
	[ -s "$e/shader.$l" ] && ! grep -q '_vf\b\|_vf(\|_D(\|_diffuse(' "$e/shader.$l" && grep -q 'ibl_anyf0_env\|ibl_anyf0_env(' "$e/shader.$l" \
		&& ok || bad "scene without punctual lights: $e/shader.$l"
done
grep -q 'float ibl_anyf0_env([^)]*f0' "$e/shader.c" && ok || bad "an f0 range: env reads f0"
# every generated function compiles as GLSL ES 3.00 and HLSL, and its C agrees with
# the IR's single precision (brdfkit eval) at cosines 0.5, r 0.5
for dir in "$d" "$e"; do
	{ printf '#version 300 es\nprecision mediump float;\n'; cat "$dir/shader.glsl"; printf 'out vec4 o;\nvoid main() { o = vec4(0); }\n'; } >"$T/s.frag"
	glslangValidator "$T/s.frag" >"$T/glsl.log" 2>&1 && ok || bad "scene GLSL does not compile: $(grep -i error "$T/glsl.log" | head -3)"
	{ cat "$dir/shader.hlsl"; printf 'float4 main(float4 u : TEXCOORD0) : SV_Target { return u; }\n'; } >"$T/s.hlsl"
	glslangValidator -V -D -S frag -e main -o "$T/s.spv" "$T/s.hlsl" >"$T/hlsl.log" 2>&1 && ok || bad "scene HLSL does not compile: $(grep -i error "$T/hlsl.log" | head -3)"
	# each function: its form and baked parameters from the provenance comment
	awk '/^ \* form: /{ sub(/^ \* form: /, ""); form = $0; pars = "" }
	     /^ \*   p[0-9]+ = /{ pars = pars " " $2 "=" $4 }
	     /^static inline float [A-Za-z0-9_]*\(/{ name = $4; sub(/\(.*/, "", name)
	       args = $0; sub(/^[^(]*\(/, "", args); sub(/\).*/, "", args); gsub(/float /, "", args)
	       print name "|" form "|" pars "|" args }' "$dir/shader.c" >"$T/fns"
	[ -s "$T/fns" ] && ok || bad "scene: no functions found in $dir/shader.c"
	while IFS='|' read -r name form pars args; do
		call="" points="" got=""
		for v in $(echo "$args" | tr ',' ' ' | sed 's/^void$//'); do
			case $v in a) x=0.25 ;; f0) x=0.04 ;; *) x=0.5 ;; esac
			call="$call${call:+, }${x}f" points="$points $v=$x"
		done
		{ cat "$dir/shader.c"; printf '#include <stdio.h>\nint main(void) { printf("%%.9g\\n", (double)%s(%s)); return 0; }\n' "$name" "$call"; } >"$T/s.c"
		want=$($BK eval "$form" $pars $points | sed -n 's/^f32 //p')
		if cc -std=c11 -O2 "$T/s.c" -lm -o "$T/s" 2>"$T/cc.log" && got=$("$T/s") && c_matches_ir "$got" "$want"; then ok
		else bad "scene $name: C gives $got, the IR's f32 $want ($form$pars$points) $(cat "$T/cc.log")"; fi
	done <"$T/fns"
done
# highp: no guard; mediump with an f0 range: env is the fitted form and meets its budget
csv_col "$T/scene/noibl/scene.csv" fp16_guards >"$T/g" && [ "$(grep -cv '^none: highp' "$T/g")" = 0 ] && ok ||
	bad "scene highp: a guard: $(cat "$T/g")"
# env_meets SCENE.CSV SET BUDGET: the set's env term is scored on max_abs, meets BUDGET, its error within it
env_meets() {
	[ "$(csv_where "$1" feature_set "$2" term)" = env ] || return 1
	kind=$(csv_where "$1" term env error_kind) && bud=$(csv_where "$1" term env budget) &&
		meets=$(csv_where "$1" term env meets_budget) && err=$(csv_where "$1" term env error) || return 1
	[ "$kind" = max_abs ] && [ "$bud" = "$3" ] && [ "$meets" = 1 ] && is_num "$err" &&
		awk -v e="$err" -v b="$3" 'BEGIN { exit !(e + 0 <= b + 0) }'
}
env_meets "$T/scene/nopunct/scene.csv" ibl_anyf0 0.06 && ok || bad "scene env budget not met: $(csv_where "$T/scene/nopunct/scene.csv" term env error)"
# control: the same row with its error edited past the budget
csv_set "$T/scene/nopunct/scene.csv" error term env 0.0601 >"$T/sc.csv" && expect_fail "scene env budget" env_meets "$T/sc.csv" ibl_anyf0 0.06 ||
	bad "scene env budget: no control"
grep -q '^<section id="scenes">' "$T/scene/section.html" && ok || bad "scene section"
# bad scene files: one line naming the key, nothing written
printf '{"materials": [{"name": "m", "rougness": 0.3}]}' >"$T/bad1.json"
expect_error "scene unknown key" "materials[0]: unknown key 'rougness'" $BK scene "$T/bad1.json" --out "$T/sx"
printf '{"materials": [{"name": "m", "roughness": {"min": 0.2, "max": 1.3}}]}' >"$T/bad2.json"
expect_error "scene range" "materials[0].roughness.max: 1.3 is outside [0, 1]" $BK scene "$T/bad2.json" --out "$T/sx"
printf '{"materials": []}' >"$T/bad3.json"
expect_error "scene empty" "materials: the list is empty" $BK scene "$T/bad3.json" --out "$T/sx"
printf '{"materials": [\n  {"name": "m",}\n]}' >"$T/bad4.json"
expect_error "scene not json" "bad4.json: line 2, column" $BK scene "$T/bad4.json" --out "$T/sx"
printf '{"materials": [{"name": "m"}], "target": {"alu_tex": 16, "costs": {}}}' >"$T/bad5.json"
expect_error "scene conflict" "'alu_tex' and 'costs' both given" $BK scene "$T/bad5.json" --out "$T/sx"
expect_error "scene missing file" "nonexistent.json: cannot be read" $BK scene "$T/nonexistent.json" --out "$T/sx"
expect_error "scene no file" "give a scene file" $BK scene --out "$T/sx"
# the good file first: the bad one is found before any work
expect_error "scene second file bad" "bad1.json" $BK scene "$T/noibl.json" "$T/bad1.json" --out "$T/sx"
[ ! -e "$T/sx" ] && ok || bad "a refused scene left --out behind"

# determinism: the same command gives the same bytes
# (the command line is recorded in the files, so both runs use one path)
for k in 1 2; do
	$BK lut --size 8 --precision half --out "$T/d" 2>/dev/null && cp "$T/d/dfg.exr" "$T/d$k.exr" && cp "$T/d/dfg.csv" "$T/d$k.csv"
	$BK albedo --d all --v hammon --f schlick --nov 0.3 --roughness 0.6 --f0 0.04 --out "$T/alb.csv" 2>/dev/null && cp "$T/alb.csv" "$T/alb$k.csv"
done
cmp -s "$T/d1.exr" "$T/d2.exr" && ok || bad "lut exr differs between runs"
cmp -s "$T/d1.csv" "$T/d2.csv" && ok || bad "lut csv differs between runs"
cmp -s "$T/alb1.csv" "$T/alb2.csv" && ok || bad "albedo csv differs between runs"

echo "cli: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
