#!/bin/sh
# cli_speclut.sh — brdfkit lut --specular from outside (issue 23, part 2): the
# texels in the CSV against GGX D recomputed here (awk), the layout of each
# file, the sweep and its page section, compare's spec LUT rows, a scene that
# chooses the LUT and one that must not, and bad options exiting 2 with one
# line naming the option. The unit tests are tests/test_speclut.c.
# usage: sh tests/cli_speclut.sh path/to/brdfkit
set -u
BK=${1:?usage: cli_speclut.sh path/to/brdfkit}
case $BK in /*) ;; *) BK=$(pwd)/$BK ;; esac
ROOT=$(pwd)
CSVGET=${CSVGET:-$ROOT/build/csvget}
T=$(mktemp -d /tmp/bk_speclut_XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$ROOT/tests/lib.sh"
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
cd "$T" || exit 1

# expect_usage NAME TOKEN ARGS...: exit 2, one line on stderr holding TOKEN.
expect_usage() {
	name=$1 token=$2; shift 2
	"$BK" "$@" >out 2>err; rc=$?
	[ $rc -eq 2 ] && [ "$(wc -l <err)" -eq 1 ] && grep -qF -- "$token" err && ok \
		|| bad "$name: exit $rc, stderr '$(cat err)'"
}

# ---- the talk's LUT: files and texels ---------------------------------------------
"$BK" lut --specular --out t >out 2>err && ok || bad "lut --specular: $(cat err)"
for f in spec.exr spec.png spec.csv; do [ -s "t/$f" ] && ok || bad "t/$f missing"; done
[ "$(csv_col t/spec.csv unorm8 | wc -l)" -eq 4096 ] && ok || bad "spec.csv: not 64x64 rows"
# float = D_ggx(NoH, r^2)/4/16 with NoH = sqrt((1 + x)/2) and x = ((i + 0.5)/64)^(1/4)
csv_cols t/spec.csv i j x noh r float unorm8 >cols || bad "spec.csv columns"
check_texels() { # $1: the scale the texels are checked against; prints the worst relative error
	awk -v s="$1" 'BEGIN { pi = 3.14159265358979323846; w = 0 }
	  { x = (($1 + 0.5)/64)^0.25; r = ($2 + 0.5)/64; noh = sqrt((1 + x)/2); a2 = r^4
	    d = noh*noh*(a2 - 1) + 1; want = a2/(pi*d*d)/4/s
	    e = ($6 - want)/want; if (e < 0) e = -e; if (e > w) w = e
	    c = $6 > 1 ? 255 : int($6*255 + 0.5); if (c != $7) { print "code"; exit } }
	  END { printf "%.3g\n", w }' cols
}
W=$(check_texels 16)
awk -v w="$W" 'BEGIN { exit !(w != "code" && w + 0 < 1e-6) }' && ok || bad "texels against GGX D/64: worst $W"
W2=$(check_texels 8) # negative control: the wrong scale
awk -v w="$W2" 'BEGIN { exit !(w + 0 > 0.4) }' && ok || bad "texels at scale 8 should not match ($W2)"
grep -q '^# texel: .*V = 1/4' t/spec.csv && ok || bad "spec.csv: the texel's convention"
grep -q '^# command: brdfkit lut --specular --out t' t/spec.csv && ok || bad "spec.csv: provenance"
# the same command again replaces the directory whole
"$BK" lut --specular --warp 2 --axis noh --size 8 --rows 4 --out t >out 2>err && ok || bad "rerun: $(cat err)"
[ "$(csv_col t/spec.csv unorm8 | wc -l)" -eq 32 ] && ok || bad "rerun: not 8x4"

# ---- bad options: exit 2, one line naming the option ------------------------------
expect_usage "warp 0" "--warp" lut --specular --warp 0 --out b
expect_usage "warp 17" "--warp" lut --specular --warp 17 --out b
expect_usage "axis" "--axis: unknown value 'nhl' (known: rol, noh)" lut --specular --axis nhl --out b
expect_usage "scale 0" "--scale" lut --specular --scale 0 --out b
expect_usage "fresnel" "--fresnel: unknown value 'full' (known: none, schlick)" lut --specular --fresnel full --out b
expect_usage "r-range" "--r-range: expected LO:HI" lut --specular --r-range 0.5:0.2 --out b
expect_usage "size 1" "--size" lut --specular --size 1 --out b
expect_usage "no --out" "--out" lut --specular
expect_usage "link-prefix alone" "--link-prefix has no effect without --sweep" lut --specular --link-prefix x/ --out b
expect_usage "dfg option" "--half" lut --specular --half --out b
[ ! -e b ] && ok || bad "a refused run left b"

# ---- the sweep ----------------------------------------------------------------------
"$BK" lut --specular --sweep --out sw --link-prefix "s'\"/" >out 2>err && ok || bad "sweep: $(cat err)"
[ "$(csv_where sw/sweep.csv role sweep name | wc -l)" -eq 287 ] && ok || bad "sweep.csv: not 288 LUTs"
G=$(csv_where sw/sweep.csv role given albedo_rel_rms) B=$(csv_where sw/sweep.csv role best albedo_rel_rms)
M=$(csv_min sw/sweep.csv albedo_rel_rms) # the ranking (M5: tests/cli_precision.sh)
awk -v b="$B" -v m="$M" -v g="$G" 'BEGIN { exit !(b + 0 == m + 0 && b + 0 <= g + 0) }' && ok || bad "best $B, min $M, given $G"
[ "$(csv_where sw/sweep.csv role given name)" = "spec LUT 64x64 unorm8 rol^4 /16" ] && ok || bad "given is not the talk's"
for f in spec.exr spec.png spec.csv; do [ -s "sw/best/$f" ] && ok || bad "sw/best/$f missing"; done
"$BK" report --out page.html sw/section.html >/dev/null 2>err && ok || bad "report of the sweep's section: $(cat err)"
grep -qF "href=\"s'%22/sweep.csv\"" page.html \
	&& ok || bad "the link prefix is not percent-encoded: $(grep -o 'href="[^>]*sweep.csv"' page.html)"

# ---- compare --target spec: the LUT rows --------------------------------------------
"$BK" compare --target spec --no-time --no-refit --out cs >/dev/null 2>err && ok || bad "compare spec: $(cat err)"
[ "$(csv_where cs/compare.csv name 'spec LUT 64x64 unorm8 rol^4 /16' tex_fetches)" = 1 ] && ok || bad "talk's row fetches"
[ "$(csv_where cs/compare.csv name 'spec LUT 64x64 unorm8 rol^4 /16' cost)" = 9 ] && ok || bad "talk's row cost"
[ -s "cs/heatmaps/spec_lut_64x64_unorm8_rol_4_16.png" ] && ok || bad "talk's row heatmap"
"$BK" compare --target spec --no-time --no-refit --no-lut --out cn >/dev/null 2>err && ok || bad "--no-lut: $(cat err)"
! csv_col cn/compare.csv kind | grep -qx lut && ok || bad "--no-lut left LUT rows"

# ---- scene: chosen where it meets the budget for less, not where it misses it ----
scene() { # $1: the NoV floor
	printf '{"scene": "low tier rough", "materials": [{"name": "rubber", "roughness": {"min": 0.6, "max": 1}, '
	printf '"f0": "dielectric"}], "lighting": {"punctual": true, "ibl": false, "diffuse": false}, '
	printf '"geometry": {"nov": {"min": %s, "max": 1}}, ' "$1"
	printf '"target": {"precision": "mediump", "alu_tex": 16, "languages": ["glsl"], "error": {"vf": 0.1}}}\n'
}
scene 0.3 >rough.json
"$BK" scene rough.json --out sc >/dev/null 2>err && ok || bad "scene: $(cat err)"
case $(csv_where sc/scene.csv term vf choice) in "spec LUT "*) ok ;; *) bad "scene: vf is $(csv_where sc/scene.csv term vf choice)" ;; esac
grep -q 'the whole punctual specular D\*V\*F\*NoL is a texture here' sc/*/shader.glsl && ok || bad "shader: no LUT comment"
! grep -q '_D(' sc/*/shader.glsl && ok || bad "shader: D is still emitted"
scene 0 >grazing.json # negative control: grazing views, where V = 1/4 misses the lobe's rise
"$BK" scene grazing.json --out sg >/dev/null 2>err && ok || bad "scene grazing: $(cat err)"
case $(csv_where sg/scene.csv term vf choice) in "spec LUT "*) bad "grazing: the LUT was chosen" ;; *) ok ;; esac
grep -q 'specular LUT (replaces D\*V\*F\*NoL): best .*over the budget' sg/report.txt && ok || bad "grazing: no reason given"

echo "cli_speclut: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
