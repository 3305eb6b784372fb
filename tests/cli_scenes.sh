#!/bin/sh
# cli_scenes.sh — brdfkit's command-line contract (the common start:
# tests/lib_cli.sh): scene: the shaders each lighting needs, budgets, bad scene
# files (issue 11).
# usage: sh tests/cli_scenes.sh path/to/brdfkit
NAME=cli_scenes
. "$(dirname "$0")/lib_cli.sh"

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

cli_done
