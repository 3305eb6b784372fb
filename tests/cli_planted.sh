#!/bin/sh
# cli_planted.sh — brdfkit's command-line contract (the common start:
# tests/lib_cli.sh): search: planted forms recovered and confirmed outside the
# search, one thread against two, checkpoint and resume, the screening front,
# every front member's shaders (issue 10).
# usage: sh tests/cli_planted.sh path/to/brdfkit
NAME=cli_planted
. "$(dirname "$0")/lib_cli.sh"

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
# (c_matches_ir, tests/lib_cli.sh)
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
	# eval takes the inputs the form reads (the front's one signature may take
	# more, and r where the form reads a = r*r): a 0.25, the others 0.5
	points=""
	for v in NoV NoL NoH LoH r a f0; do
		echo "$form" | grep -q "\(^\|[^A-Za-z0-9_]\)$v\([^A-Za-z0-9_(]\|$\)" || continue
		case $v in a) x=0.25 ;; *) x=0.5 ;; esac
		points="$points $v=$x"
	done
	want=$($BK eval "$form" $pars $points | sed -n 's/^f32 //p')
	got=""
	if cc -std=c11 -O2 "$T/m.c" -lm -o "$T/m" 2>"$T/cc.log" && got=$("$T/m") && c_matches_ir "$got" "$want"; then ok
	else bad "front $name: C gives $got, the IR's f32 $want ($form $pars $points) $(cat "$T/cc.log")"; fi
	# control, once: the same comparison against a value 1e-5 off must fail
	[ $n -eq 1 ] && expect_fail "C against the IR" c_matches_ir "$got" "$(awk -v w="$want" 'BEGIN { printf "%.9g", w * (1 + 1e-5) }')"
done
[ "$n" -ge 3 ] && ok || bad "the planted search's front has $n members"

cli_done
