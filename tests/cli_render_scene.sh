#!/bin/sh
# cli_render_scene.sh — brdfkit-render(1) gives every number of its scene
# (issue 40 item 6): pixels of a render are rebuilt from the man page's "The
# scene, every number" alone by an independent implementation in Python
# (tests/tools/render_pixel.py: no code of brdfkit's; the candidate
# env_karis2014_split from Karis' published constants, so no DFG integral is
# needed) and compared with the EXR (build/exrcmp --pixel). The render is
# --device cpu (the IR in double from float inputs; render.sh holds lavapipe
# to it), so the two agree to float rounding: 2^-20 relative per channel
# (the sums of 1152 sky samples differ only in exp/cos ulps).
# Negative controls: a wrong number in the recipe (the sun glow's 8, the
# light's z, the sample grid) moves a pixel past the tolerance; a page that
# does not state a number (0.62 changed) is refused by the evaluator.
# usage: sh tests/cli_render_scene.sh path/to/brdfkit   (needs build/exrcmp, python3)
set -u
BK=${1:?usage: sh tests/cli_render_scene.sh path/to/brdfkit}
T=$(mktemp -d /tmp/bk_render_scene_XXXXXX)
trap 'rm -rf "$T"' EXIT
EXRCMP=${EXRCMP:-build/exrcmp}
. tests/lib.sh
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }

PAGE=analysis/man/brdfkit-render.1.scd
W=64 ROUGH=0.5,1
REL=0.00000095367431640625 # 2^-20
"$BK" render --device cpu --precision single --form env_karis2014_split --size $W --roughness $ROUGH \
	--out "$T/r" >"$T/log" 2>&1 || bad "render: $(cat "$T/log")"

# rebuilt PAGE X Y [NAME=VALUE ...]: the evaluator's pixel (X, Y) equals the
# EXR's in R, G and B within REL relative.
rebuilt() {
	_p=$1 _x=$2 _y=$3; shift 3
	"$EXRCMP" --pixel "$T/r/candidate_f32.exr" "$_x" "$_y" >"$T/exr" || return 1
	python3 tests/tools/render_pixel.py "$_p" $W $ROUGH "$_x" "$_y" "$@" >"$T/py" 2>"$T/pyerr" || return 1
	# the EXR line is "B b G g R r" (EXR sorts channels by name), the evaluator's "r g b"
	awk -v rel=$REL 'NR == 1 { r = $6; g = $4; b = $2 } NR == 2 { e[1] = r; e[2] = g; e[3] = b
		for (i = 1; i <= 3; i++) { d = $i - e[i]; if (d < 0) d = -d; m = e[i] < 0 ? -e[i] : e[i]
			if (!(d <= rel * m) || m == 0) exit 1 } }' "$T/exr" "$T/py"
}

# a dielectric pixel (specular, sky and diffuse), a gold one (no diffuse), a
# grazing one near the silhouette
for xy in "20 14" "40 44" "10 10" "3 16"; do
	# shellcheck disable=SC2086 # X Y are two words
	rebuilt "$PAGE" $xy && ok || bad "pixel ($xy): the EXR $(cat "$T/exr"), the page's recipe $(cat "$T/py" "$T/pyerr")"
done
expect_fail "sun glow 8.5" rebuilt "$PAGE" 20 14 glow=8.5
expect_fail "light z 0.63" rebuilt "$PAGE" 20 14 light=0.5,0.6,0.63
expect_fail "sample grid 24 x 47" rebuilt "$PAGE" 40 44 grid_phi=47
expect_fail "sky blend 0.1" rebuilt "$PAGE" 20 14 blend=0.1
sed 's/0\.5, 0\.6, 0\.62/0.5, 0.6, 0.63/' "$PAGE" >"$T/page.scd"
expect_fail "a page without the light's 0.62" rebuilt "$T/page.scd" 20 14
python3 tests/tools/render_pixel.py "$T/page.scd" $W $ROUGH 20 14 >/dev/null 2>"$T/err"
[ $? -eq 2 ] && grep -q "does not state light" "$T/err" && ok || bad "evaluator on a page without a number: $(cat "$T/err")"

echo "cli_render_scene: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
