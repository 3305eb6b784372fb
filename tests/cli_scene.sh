#!/bin/sh
# cli_scene.sh — brdfkit scene and brdfkit report from outside (issue 21:
# H5, M8, M12, M13, L3, L4, L5, L6, L8, M10): nothing from a scene file, a
# file name or an option runs as code in the shaders or the page; what was
# not measured says so and is an empty field; inputs are read with a bound;
# the scene's numbers are the values typed; the work is estimated before it
# starts; report takes only whole brdfkit sections, each once, never its own
# output. Scenes here are diffuse-only (no fit: instant) except two V*F-only
# ones of a few seconds. The writers' full fuzz is tests/test_scene_write.c.
# usage: sh tests/cli_scene.sh path/to/brdfkit
set -u
BK=${1:?usage: cli_scene.sh path/to/brdfkit}
case $BK in /*) ;; *) BK=$(pwd)/$BK ;; esac
ROOT=$(pwd)
CSVGET=${CSVGET:-$ROOT/build/csvget}
T=$(mktemp -d /tmp/bk_scene_XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$ROOT/tests/lib.sh"
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
cd "$T" || exit 1

# bounded CMD...: CMD under a 4 GB address-space limit where the tool starts
# in one (a sanitized tool reserves more than that: a time limit alone), so
# that a tool reading /dev/zero whole fails here instead of filling the machine.
if (ulimit -v 4000000 && "$BK" --help >/dev/null 2>&1; exit $?) 2>/dev/null; then # exit: no exec, no "Aborted"
	bounded() { (ulimit -v 4000000 && timeout 60 "$@"); }
else
	bounded() { timeout 60 "$@"; }
fi

# expect_error NAME TOKEN CMD...: non-zero exit, one line on stderr holding TOKEN.
expect_error() {
	name=$1 token=$2; shift 2
	if "$@" >out 2>err; then bad "$name: exit 0"; return; fi
	[ "$(wc -l <err)" -eq 1 ] && grep -qF -- "$token" err && ok || bad "$name: stderr '$(cat err)'"
}

# ---- H5: the scene's name, a material's name, the file's name, the link prefix ----

printf '{"scene": "%s", "materials": [{"name": "</h3><script>alert(2)</script>", "specular": false}]}\n' \
	'x */ int injected_c = 1; /* y </pre><script>x</script> & \\' >inj.json
# a file name with line breaks: it reaches every shader through the command line
F=$(printf 'inj\nfloat inj(){return 1.0;}\nx.json')
cp inj.json "$F"
if "$BK" scene "$F" --out o --link-prefix "p'\"<b>/" >out 2>err; then ok; else bad "scene inj: $(cat err)"; fi
cc -std=c11 -Wall -Wextra -Werror -c o/diffuse/shader.c -o s.o 2>cc.log && ok || bad "shader.c: $(head -3 cc.log)"
nm --defined-only s.o >nm.txt 2>&1; ! grep -q injected nm.txt && ok || bad "shader.c defines: $(cat nm.txt)"
# the escaped name is in the comment, whole
grep -qF "scene 'x * / int injected_c = 1; / * y </pre><script>x</script> & \\' (file hash" o/diffuse/shader.c \
	&& ok || bad "shader.c: the name's comment: $(head -1 o/diffuse/shader.c)"
glsl_with() { # GLSL ES 3.00 around the shader; $1: an expression main evaluates
	{ printf '#version 300 es\nprecision highp float;\n'; cat o/diffuse/shader.glsl
	  printf 'out vec4 o;\nvoid main() { o = vec4(%s); }\n' "$1"; } >s.frag
	glslangValidator s.frag >glsl.log 2>&1
}
glsl_with "diffuse_diffuse()" && ok || bad "shader.glsl does not compile: $(grep ERROR glsl.log | head -3)"
# negative control of the injection: a call of inj() must find no such function
! glsl_with "inj()" && grep -q "no matching overloaded function" glsl.log && ok || bad "inj() is defined in shader.glsl"
{ cat o/diffuse/shader.hlsl; printf 'float4 main(float4 u : TEXCOORD0) : SV_Target { return u; }\n'; } >s.hlsl
glslangValidator -V -D -S frag -e main -o s.spv s.hlsl >hlsl.log 2>&1 && ok || bad "shader.hlsl: $(grep ERROR hlsl.log | head -3)"
grep -q inj o/diffuse/shader.hlsl && ! grep -q '^float inj' o/diffuse/shader.hlsl && ok || bad "shader.hlsl: a line of its own"
# the page: no script, the names as text, the prefix as the links' value
if "$BK" report --out page.html o/section.html 2>err; then ok; else bad "report of the scene's section: $(cat err)"; fi
[ "$(xmllint --html --xpath 'count(//script)' page.html 2>/dev/null)" = 0 ] && ok || bad "page: a <script> element"
[ "$(xmllint --html --xpath 'string(//h3)' page.html 2>/dev/null)" = "x */ int injected_c = 1; /* y </pre><script>x</script> & \\" ] \
	&& ok || bad "page: the scene's heading reads '$(xmllint --html --xpath 'string(//h3)' page.html 2>/dev/null)'"
# (percent-encoded where written: " and < are no path characters, RFC 3986)
[ "$(xmllint --html --xpath 'string(//section//a/@href)' page.html 2>/dev/null)" = "p'%22%3Cb%3E/scene.csv" ] \
	&& ok || bad "page: the first link is '$(xmllint --html --xpath 'string(//section//a/@href)' page.html 2>/dev/null)'"
[ "$(csv_col o/sets.csv materials)" = "</h3><script>alert(2)</script>" ] && ok || bad "sets.csv materials"
# --id goes into the section's opening and comes back through report's check
expect_error "scene --id" "--id: 'a\"b' is not 1 to 63 letters" "$BK" scene inj.json --id 'a"b' --out o2
[ ! -e o2 ] && ok || bad "a refused --id left o2"

# L3: the link prefix of stability and compare sections, escaped and read back
P="x'\"<b>/"
"$BK" stability NoV --out stl --link-prefix "$P" >/dev/null 2>err || bad "stability --link-prefix: $(cat err)"
"$BK" compare --target f --no-time --out cmp --link-prefix "$P" >/dev/null 2>err || bad "compare --link-prefix: $(cat err)"
for s in stl cmp; do
	if "$BK" report --out "$s.html" "$s/section.html" 2>err; then ok; else bad "report $s: $(cat err)"; fi
	href=$(xmllint --html --xpath 'string((//section//a/@href)[1])' "$s.html" 2>/dev/null)
	case $href in "x'%22%3Cb%3E/"*) ok ;; *) bad "$s: the first link reads '$href'" ;; esac
done

# ---- M8 and L8: no compiler, no spirv-opt; a budget nothing meets ----

printf '{"materials": [{"name": "m", "roughness": {"min": 0.3, "max": 1}}], "lighting": {"ibl": false},\n "target": {"precision": "mediump", "error": {"vf": 1e-6}}}\n' >vf6.json
if env PATH=/nonexistent "$BK" scene vf6.json --out nt >out 2>err; then ok; else bad "scene without tools: $(cat err)"; fi
grep -qx 'brdfkit scene: warning: SPIR-V counts not measured: spirv-opt not found on PATH (Debian package spirv-tools)' err \
	&& ok || bad "no word of the SPIR-V counts: $(cat err)"
grep -q '^brdfkit scene: warning: CPU timings not measured: cc not found on PATH' err && ok || bad "no word of the timings: $(cat err)"
[ "$(grep -c 'not measured' err)" -eq 2 ] && ok || bad "one line each: $(grep 'not measured' err)"
for c in spirv generic_spirv; do [ "$(csv_col nt/sets.csv $c)" = "" ] && ok || bad "sets.csv $c: '$(csv_col nt/sets.csv $c)'"; done
for c in ns_per_eval generic_ns_per_eval; do [ "$(csv_col nt/timing.csv $c)" = "" ] && ok || bad "timing.csv $c: '$(csv_col nt/timing.csv $c)'"; done
grep -q 'SPIR-V not measured' nt/report.txt && grep -q 'CPU time not measured' out && ok || bad "report: $(grep shader nt/report.txt)"
! grep -rq -e '-2\b' -e 'nan' nt/report.txt nt/sets.csv nt/timing.csv nt/section.html out && ok || bad "a sentinel: $(grep -r -e '-2\b' -e nan nt out | head -3)"
# L8: rc 0 (the shaders are the most accurate found), NOT MET in the report and one warning
grep -q 'budget 1e-06: NOT MET' nt/report.txt && ok || bad "report: $(grep vf nt/report.txt)"
[ "$(csv_col nt/scene.csv meets_budget | sort -u | tr '\n' ' ')" = "0 1 " ] && ok || bad "scene.csv meets_budget (D 1, vf 0)"
grep -q '^brdfkit scene: warning: vf6: spec_diffuse_f0_040: vf budget 1e-06 not met: the most accurate candidate, exact, is off by' err \
	&& ok || bad "no warning of the budget: $(cat err)"
# negative control of the warning: a budget met
printf '{"materials": [{"name": "m", "roughness": {"min": 0.3, "max": 1}}], "lighting": {"ibl": false}, "target": {"error": {"vf": 0.2}}}\n' >vf2.json
"$BK" scene vf2.json --no-time --out met >out 2>err && ! grep -q 'not met' err && ok || bad "a met budget warned: $(cat err)"
[ "$(csv_col met/sets.csv spirv)" -gt 0 ] 2>/dev/null && ok || bad "with the tools, spirv is a count: '$(csv_col met/sets.csv spirv)'"

# ---- M13: the estimate before the work, progress per set ----

grep -q '^brdfkit scene: 1 feature set, 1 term to fit: about 30 s (30 s per V\*F or env term)$' err && ok || bad "estimate: $(head -2 err)"
[ "$(grep -n 'term to fit' err | cut -d: -f1)" = 1 ] && ok || bad "the estimate is not the first line: $(head -2 err)"
grep -q '^brdfkit scene: vf2: spec_diffuse_f0_040 done (1 of 1 terms fitted, [0-9]* s)$' err && ok || bad "progress: $(cat err)"
awk 'BEGIN { printf "{\"materials\": [" } { } END {
	for (i = 1; i <= 64; i++) printf "%s{\"name\": \"m%d\", \"f0\": %.3f}", (i > 1 ? ", " : ""), i, 0.2 + i / 100
	print "]}" }' /dev/null >many.json
until_lines 2 5 err "$BK" scene many.json --no-time --out many # stopped once its two warnings are out
[ $? -eq 124 ] && ok || bad "many.json did not run on (its estimate is over an hour)"
grep -q '^brdfkit scene: warning: 64 feature sets, 128 terms to fit: about 1 h (30 s per V\*F or env term)$' err \
	&& grep -q 'warning: that is more than 30 minutes' err && ok || bad "no warning before 64 sets: $(head -3 err)"

# ---- L5, L4, M10: what the file says is what is read ----

printf '{"materials": [{"name": "m", "roughness": 1e-999, "specular": false}]}\n' >tiny.json
expect_error "1e-999" "tiny.json: line 1, column 43: 1e-999 is not 0 but underflows to it" "$BK" scene tiny.json --out t1
printf '{"materials": [{"name": "m", "roughness": [-0.0, 0.5], "specular": false}]}\n' >negz.json
expect_error "-0.0" "negz.json: line 1, column 44: -0.0 is negative zero (every number of a scene is 0 or above" \
	"$BK" scene negz.json --out t2
printf '{"materials": [{"name": "m", "roughness": [0.0, 0.5], "specular": false}]}\n' >zero.json
"$BK" scene zero.json --out t2 >out 2>err && grep -q 'r in \[0, 0.5\]' out && ok || bad "0.0: $(grep 'r in' out) $(cat err)"
printf '\357\273\277{"materials": [{"name": "m"}]}\n' >bom.json
expect_error "BOM" "bom.json: line 1, column 1: the file starts with a UTF-8 byte-order mark" "$BK" scene bom.json --out t3
printf '{"materials": [{"name": "m"}], "target": {"languages": ["glsl", "glsl"]}}\n' >langs.json
expect_error "languages twice" "target.languages[1]: 'glsl' is also target.languages[0]" "$BK" scene langs.json --out t4
printf '{"scene": "a\\nb", "materials": [{"name": "m"}]}\n' >nl.json
expect_error "a line break in the name" "nl.json: scene: a control character in the name" "$BK" scene nl.json --out t5

# ---- M12: read with a bound ----

expect_error "scene /dev/zero" "/dev/zero: is longer than 1048576 bytes (a scene file is at most 1 MiB)" bounded "$BK" scene /dev/zero --out t6
head -c 2097152 /dev/zero | tr '\0' ' ' >big.json
expect_error "scene 2 MiB" "big.json: is 2097152 bytes, more than 1048576 (a scene file is at most 1 MiB)" "$BK" scene big.json --out t7
expect_error "scene a directory" "$T: is a directory" "$BK" scene "$T" --out t8
mkfifo fifo.json
cat zero.json >fifo.json &
"$BK" scene fifo.json --out t9 >/dev/null 2>err && ok || bad "a scene from a FIFO: $(cat err)"
wait
[ ! -e t1 ] && [ ! -e t3 ] && [ ! -e t6 ] && [ ! -e t7 ] && ok || bad "a refused scene left its --out"

# ---- L6, M12: report takes whole brdfkit sections, once, never its own page ----

cp o/section.html sec.html
expect_error "report --out its input" "sec.html: is --out sec.html itself" "$BK" report --out sec.html sec.html
cmp -s sec.html o/section.html && ok || bad "report overwrote its own section"
ln sec.html hard.html
expect_error "report --out a hard link of its input" "hard.html: is --out sec.html itself" "$BK" report --out sec.html hard.html
expect_error "report a section twice" "sec.html: given twice (also as sec.html)" "$BK" report --out p.html sec.html sec.html
cp sec.html copy.html
expect_error "report one id twice" "copy.html: its id 'scenes' is also sec.html's" "$BK" report --out p.html sec.html copy.html
sed 's|</table>|</table><script>alert(3)</script>|' sec.html >script.html
expect_error "report a script" "script.html: line " "$BK" report --out p.html script.html
grep -q "<script>: not an element brdfkit writes" err && ok || bad "report a script: $(cat err)"
printf '<p>not a section</p>\n' >plain.html
expect_error "report no marker" "plain.html: line 1: does not open with <section id=" "$BK" report --out p.html plain.html
expect_error "report /dev/zero" "/dev/zero: not a regular file (a character device)" bounded "$BK" report --out p.html /dev/zero
[ ! -e p.html ] && ok || bad "a refused report left p.html"
# make results' page has more than 16 sections: 32 are one page, the 33rd is named
for i in $(seq 1 33); do printf '<section id="s%d"><p>%d</p></section>\n' "$i" "$i" >"many$i.html"; done
"$BK" report --out page32.html $(for i in $(seq 1 32); do echo "many$i.html"; done) >out 2>err &&
	[ "$(grep -c '<section id="s' page32.html)" = 32 ] && ok || bad "report of 32 sections: $(cat err)"
expect_error "report of 33 sections" "'many33.html': at most 32 arguments" \
	"$BK" report --out page33.html $(for i in $(seq 1 33); do echo "many$i.html"; done)
[ ! -e page33.html ] && ok || bad "a refused report of 33 sections left its page"

# "languages": ["msl"]: Metal alone, SPIRV-Cross's translation (analysis/msl.c),
# half in mediump and float in highp (control: the default writes no Metal)
for p in mediump highp; do
	printf '{"scene": "m", "materials": [{"name": "m1", "specular": false}], "target": {"languages": ["msl"], "precision": "%s"}}\n' $p >msl.json
	rm -rf mo
	if "$BK" scene msl.json --out mo >out 2>err; then ok; else bad "scene msl $p: $(cat err)"; fi
	t=float; [ $p = mediump ] && t=half
	[ "$(ls mo/diffuse)" = shader.metal ] && grep -q "^$t diffuse_diffuse()\$" mo/diffuse/shader.metal &&
		grep -q '^using namespace metal;$' mo/diffuse/shader.metal && ok ||
		bad "scene msl $p: $(ls mo/diffuse) $(grep diffuse_diffuse mo/diffuse/shader.metal)"
done
printf '{"scene": "m", "materials": [{"name": "m1", "specular": false}]}\n' >nomsl.json
rm -rf mo
"$BK" scene nomsl.json --out mo >out 2>err && [ ! -e mo/diffuse/shader.metal ] && [ -e mo/diffuse/shader.glsl ] && ok ||
	bad "scene: Metal by default, or no GLSL: $(ls mo/diffuse) $(cat err)"

echo "cli_scene: $pass passed, $fail failed"
[ $fail -eq 0 ]
