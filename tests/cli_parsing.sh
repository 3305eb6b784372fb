#!/bin/sh
# cli_parsing.sh — option and input parsing, each rule checked as a class
# over every command and input that shares its mechanism (issue 39 item 6:
# the audit's M4, M6, M7, M12, M13, M14, L5, L6, L9): a CSV quote left open,
# ranges too narrow to sample, negative zero where no negative is allowed,
# a term budget for a term the scene lacks, --quiet twice, the "(see ...)"
# suffix of usage errors. Every refusal beside a control just inside it.
# usage: sh tests/cli_parsing.sh path/to/brdfkit
set -u
BK=${1:?usage: cli_parsing.sh path/to/brdfkit}
case $BK in /*) ;; *) BK=$(pwd)/$BK ;; esac
ROOT=$(pwd)
CSVGET=${CSVGET:-$ROOT/build/csvget}
T=$(mktemp -d /tmp/bk_parsing_XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$ROOT/tests/lib.sh"
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
cd "$T" || exit 1

# expect_rc NAME RC TOKEN CMD...: exit RC, one line on stderr holding TOKEN.
# (timeout: a binary that accepts a scene or a search would run for minutes)
expect_rc() {
	name=$1 want=$2 token=$3; shift 3
	timeout 60 "$@" >out 2>err; rc=$?
	[ $rc -eq "$want" ] && [ "$(wc -l <err)" -eq 1 ] && grep -qF -- "$token" err && ok \
		|| bad "$name: exit $rc (want $want), stderr '$(head -c 300 err)'"
}
expect_usage() { name=$1; shift; expect_rc "$name" 2 "$@"; }
# accepted NAME CMD...: exit 0
accepted() {
	name=$1; shift
	timeout 120 "$@" >out 2>err && ok || bad "$name: refused: $(head -c 300 err)"
}

# ---- M13: a quote left open in a CSV, in every reader (csvtab.c) ---------------
printf 'name,term,form\na,vf,"vf_talk_r\n' >open.csv
expect_usage "render --batch open quote" "open.csv:2: unterminated quoted field" \
	"$BK" render --batch open.csv --size 40 --out rb
printf 'name,form,form_b,parameters,cost,error\nx,"NoV,,,1,0.1\n' >front_open.csv
expect_rc "search --start-front open quote" 1 "front_open.csv:2: unterminated quoted field" \
	"$BK" search --target f --start-front front_open.csv --evals 300 --threads 1 --out so
# control: the quote closed on the next line is a field (and the error is the form's)
printf 'name,term,form\na,vf,"vf_talk_r\n"\n' >closed.csv
"$BK" render --batch closed.csv --size 40 --out rb >out 2>err
grep -q "unterminated" err && bad "closed quote: $(cat err)" || ok

# ---- L5: ranges too narrow to sample, every range option --------------------------
N=0.5:0.5000000000000001 W=0.5:0.5000006
expect_usage "search --x-range 1 ulp" "--x-range: '$N' is too narrow to sample" \
	"$BK" search --target f --x-range $N --evals 300 --threads 1 --out q
expect_usage "search --r-range 1 ulp" "--r-range: '$N' is too narrow to sample" \
	"$BK" search --target vf --r-range $N --evals 300 --threads 1 --out q
expect_usage "fit --x-range 1 ulp" "--x-range: '$N' is too narrow to sample" \
	"$BK" fit --target f --form 'p0+LoH' p0=1 --x-range $N --out q
expect_usage "fit --domain 1 ulp" "--domain: LoH: '$N' is too narrow to sample" \
	"$BK" fit --target form --target-form LoH --domain LoH=$N --form 'p0+LoH' p0=1 --out q
expect_usage "lut --r-range 1 ulp" "--r-range: '$N' is too narrow to sample" "$BK" lut --size 4 --r-range $N --out q
expect_usage "lut --specular --r-range 1 ulp" "--r-range: '$N' is too narrow to sample" \
	"$BK" lut --specular --size 4 --r-range $N --out q
# controls: 1.2e-6 of the larger end is wide enough
accepted "fit --x-range just wide enough" "$BK" fit --target f --form 'p0+LoH' p0=1 --x-range $W --out q
accepted "lut --r-range just wide enough" "$BK" lut --size 4 --r-range $W --out q

# ---- L6: negative zero where no negative is allowed -------------------------------
expect_usage "lut --r-range -0" "--r-range: expected LO:HI" "$BK" lut --size 4 --r-range -0:1 --out q
expect_usage "lut --f0 -0" "-0 is out of range" "$BK" lut --size 4 --f0 -0 --out q
expect_usage "fit --x-range -0" "--x-range: expected LO:HI with LO < HI in [0, 1], got '-0:1'" \
	"$BK" fit --target f --form 'p0+LoH' p0=1 --x-range -0:1 --out q
expect_usage "search --r-range -0" "--r-range: expected LO:HI with LO < HI in [0, 1], got '-0:0.5'" \
	"$BK" search --target vf --r-range -0:0.5 --evals 300 --threads 1 --out q
# a bound is not sampled: no least width (--hold keeps a parameter fixed)
accepted "fit --bound 1 ulp wide" "$BK" fit --target f --form 'p0+LoH' p0=1 --bound p0=1:1.0000000000000002 --out q
accepted "lut --f0 0 (control)" "$BK" lut --size 4 --f0 0 --out q
accepted "lut --r-range 0:1 (control)" "$BK" lut --size 4 --r-range 0:1 --out q

# ---- L9: --quiet twice; the "(see ... --help)" suffix ------------------------------
expect_usage "--quiet twice" "--quiet given twice (see brdfkit eval --help)" "$BK" eval --quiet --quiet NoV NoV=1
accepted "--quiet once" "$BK" eval --quiet NoV NoV=1
expect_usage "lut --r-range inf" "(see brdfkit lut --help)" "$BK" lut --size 4 --r-range 0:inf --out q

# ---- scenes: L6 negative zero, L5 narrow ranges, M7 budgets of absent terms --------
# (scene errors are bad files: exit 1, as every scene error)
scene() { printf '{"scene":"s","materials":[{"name":"m",%s}]%s}\n' "$1" "$2" >s.json; }
scene '"roughness":-0.0,"f0":0.04' ''
expect_rc "scene roughness -0.0" 1 "-0.0 is negative zero" "$BK" scene s.json --no-time --out sc
scene '"roughness":0.5,"f0":{"min":-0,"max":0.5}' ''
expect_rc "scene f0 min -0" 1 "-0 is negative zero" "$BK" scene s.json --no-time --out sc
scene '"roughness":{"min":0.5,"max":0.5000000000000001},"f0":0.04' ''
expect_rc "scene roughness 1 ulp" 1 "materials[0].roughness: [0.5, 0.50000000000000011] is too narrow" \
	"$BK" scene s.json --no-time --out sc
scene '"roughness":[0.5,0.5000000000000001],"f0":0.04' ''
expect_rc "scene roughness list 1 ulp" 1 "is too narrow" "$BK" scene s.json --no-time --out sc
scene '"roughness":0.5,"f0":0.04' ',"target":{"error":{"env":0.01}},"lighting":{"ibl":false}'
expect_rc "scene error.env without ibl" 1 \
	"target.error.env: has no effect without image-based lighting (lighting.ibl is false)" \
	"$BK" scene s.json --no-time --out sc
scene '"roughness":0.5,"f0":0.04' ',"target":{"error":{"vf":0.01}},"lighting":{"punctual":false}'
expect_rc "scene error.vf without punctual" 1 "target.error.vf: has no effect without punctual lights" \
	"$BK" scene s.json --no-time --out sc
scene '"specular":false' ',"target":{"error":{"vf":0.01}}'
expect_rc "scene error.vf, nothing specular" 1 "target.error.vf: has no effect when no material is specular" \
	"$BK" scene s.json --no-time --out sc
# controls: diffuse-only scenes (no fit: instant) with a budget that applies to every term
scene '"specular":false' ',"target":{"error":0.01}'
accepted "scene one budget, nothing specular" "$BK" scene s.json --no-time --out sc
scene '"specular":false,"roughness":0' ''
accepted "scene roughness 0" "$BK" scene s.json --no-time --out sc

# ---- M12: render --size states the cell limit, as a usage error --------------------
expect_usage "render --size 8192, one column" "--size 8192: cells of 8192 pixels for 1 column (a cell is 8 to 4096 pixels" \
	"$BK" render --form vf_talk_r --size 8192 --roughness 0.5 --out rbig
expect_usage "render --size 16, three columns" "(a cell is 8 to 4096 pixels: W from 24" \
	"$BK" render --form vf_talk_r --size 16 --roughness 0.1,0.5,1 --out rbig
accepted "render --size 64, one column (control)" "$BK" render --form vf_talk_r --size 64 --roughness 0.5 --device cpu --out rok
"$BK" render --help | grep -q -- "--size W .*(8 to 4096 pixels)" && ok || bad "render --help: the cell limit"

# ---- M6: C11's library names refused as --name (a sample of every header) ---------
for n in assert NDEBUG static_assert cabs cexpf I complex isalpha toupper errno EDOM ENOENT feclearexcept FE_UPWARD \
	FLT_MAX DBL_EPSILON DECIMAL_DIG PRId64 SCNu8 strtoimax and xor_eq INT_MAX CHAR_BIT setlocale LC_ALL jmp_buf \
	longjmp signal raise SIGINT SIG_IGN alignas va_list va_start atomic_load atomic_int memory_order_seq_cst \
	ATOMIC_VAR_INIT bool true size_t offsetof NULL int32_t uint_fast8_t INT8_C UINTMAX_MAX printf stdin FILE EOF \
	fopen exit abort malloc qsort EXIT_SUCCESS noreturn memcpy strlen thrd_create mtx_lock thread_local call_once \
	time clock_t CLOCKS_PER_SEC char16_t mbrtoc32 wprintf WEOF wint_t iswalpha towupper printf_s errno_t; do
	expect_usage "c --name $n" "'$n' is reserved in c" "$BK" codegen --lang c --name "$n" 'NoV*NoL'
done
# controls: names a header's family does not reach are accepted, and compile
# with every C11 header included (gnu11: glibc's widest declarations)
{ for h in assert complex ctype errno fenv float inttypes iso646 limits locale setjmp signal stdalign stdarg \
	stdatomic stdbool stddef stdint stdio stdlib stdnoreturn string tgmath threads time uchar wchar wctype; do
	echo "#include <$h.h>"; done; } >all.h
for n in Float total strength tm Exposure intensity D_ggx_fit print_ exit2 Signal; do
	"$BK" codegen --lang c --name "$n" 'NoV*NoL' >f.c 2>err || { bad "c --name $n refused: $(cat err)"; continue; }
	cat all.h f.c >g.c
	gcc -std=c11 -Wall -Werror -c g.c -o g.o 2>cc && ok || bad "c --name $n with every header: $(head -2 cc)"
done
# negative control: the same compile fails for a refused name written in by hand
"$BK" codegen --lang c --name ctl 'NoV*NoL' | sed 's/ ctl(/ printf(/' | cat all.h - >g.c
gcc -std=c11 -Wall -Werror -c g.c -o g.o 2>/dev/null && bad "control: printf compiled with <stdio.h>" || ok

# ---- M4: pN=VALUE read by one function (form_check.h), twice and empty refused ------
expect_usage "render --params twice" "parameters: p0 given twice in the list 'p0=1;p0=2'" \
	"$BK" render --form 'p0*f0' --params 'p0=1;p0=2' --term vf --size 40 --out r4
expect_usage "render --params empty" "parameters: empty item in the list 'p0=1;;'" \
	"$BK" render --form 'p0*f0' --params 'p0=1;;' --term vf --size 40 --out r4
expect_usage "render --params leading empty" "parameters: empty item" \
	"$BK" render --form 'p0*f0' --params ',p0=1' --term vf --size 40 --out r4
printf 'name,term,form,form_b,parameters\na,vf,p0*f0,,p0=1;p0=3\n' >b_twice.csv
expect_usage "render --batch parameters twice" "a: parameters: p0 given twice" "$BK" render --batch b_twice.csv --size 40 --out rb
printf 'name,term,form,form_b,parameters\na,vf,p0*f0,,p0=1;\n' >b_empty.csv
expect_usage "render --batch parameters empty" "a: parameters: empty item" "$BK" render --batch b_empty.csv --size 40 --out rb
for c in eval codegen gpucost time stability; do
	case $c in eval) pre="" post="NoV=0.5" ;; codegen) pre="--lang c" post="" ;; *) pre="" post="" ;; esac
	# shellcheck disable=SC2086 # pre and post are words
	expect_usage "$c p01 (a second name for p1)" "unknown parameter 'p01' (p0..p15)" \
		"$BK" $c $pre 'p1*NoV+p0' p0=1 p01=2 $post
	# shellcheck disable=SC2086
	expect_usage "$c p16" "unknown parameter 'p16' (p0..p15)" "$BK" $c $pre 'p0*NoV' p0=1 p16=2 $post
done
expect_usage "eval p0 twice" "p0 given twice" "$BK" eval 'p0*NoV' p0=1 p0=2 NoV=0.5
expect_usage "codegen p0 twice" "p0 given twice" "$BK" codegen --lang c 'p0*NoV' p0=1 p0=2
expect_usage "stability p0 twice" "p0 given twice" "$BK" stability 'p0*NoV' p0=1 p0=2
expect_usage "fit p0 twice" "p0 given twice" "$BK" fit --target f --form 'p0+LoH' p0=1 p0=2 --out q
expect_usage "fit p01" "unknown parameter 'p01'" "$BK" fit --target f --form 'p1*LoH+p0' p0=1 p01=2 --out q
# controls: each once
accepted "render --params once" "$BK" render --form 'p0*f0' --params 'p0=1' --term vf --size 40 --device cpu --out r4
accepted "eval p0 once" "$BK" eval 'p0*NoV' p0=1 NoV=0.5

# ---- M14: parameters numbered from p0, without a gap, in every command ---------------
for c in eval codegen gpucost time stability; do
	case $c in eval) pre="" post="NoV=0.5" ;; codegen) pre="--lang c" post="" ;; *) pre="" post="" ;; esac
	# shellcheck disable=SC2086
	expect_usage "$c p15 alone" "uses p15 but not p0: number the parameters from p0, without a gap" \
		"$BK" $c $pre 'p15*NoV' p15=1 $post
	# shellcheck disable=SC2086
	expect_usage "$c p0 and p2" "uses p2 but not p1: number the parameters from p0" \
		"$BK" $c $pre 'p0+p2*NoV' p0=1 p2=1 $post
done
expect_usage "fit p15 alone" "the form uses p15 but not p0" "$BK" fit --target f --form 'p15+LoH' p15=1 --out q
expect_usage "render p1 alone" "uses p1 but not p0" "$BK" render --form 'p1*f0' --params p1=1 --term vf --size 40 --out r4
printf 'name,form,form_b,parameters,cost,error\nx,p3*LoH,,p3=1,1,0.1\n' >front_gap.csv
expect_rc "search --start-front p3 alone" 1 "front_gap.csv:2: the form uses p3 but not p0" \
	"$BK" search --target f --start-front front_gap.csv --evals 300 --threads 1 --out so
printf 'name,form,form_b,parameters,cost,error\nx,p0*LoH,,p0=1;,1,0.1\n' >front_empty.csv
expect_rc "search --start-front empty item" 1 "front_empty.csv:2: parameters: empty item in the list 'p0=1;' (item 2)" \
	"$BK" search --target f --start-front front_empty.csv --evals 300 --threads 1 --out so
expect_usage "search --start p15 alone" "--start 'p15*LoH' uses p15 but not p0: number the parameters from p0" \
	"$BK" search --target f --start 'p15*LoH' --evals 300 --threads 1 --out so
expect_usage "compare p15 names what it uses" "'p15*LoH' uses p15: compare scores a typed form as written" \
	"$BK" compare --target f --out co 'p15*LoH'
# controls: numbered from p0
accepted "codegen p0 p1" "$BK" codegen --lang c 'p0+p1*NoV' p0=1 p1=2
accepted "time p0" "$BK" time 'p0*NoV' p0=1 --reps 1

# ---- L9 as a class: every usage error about an option or an argument ends with
# "(see brdfkit CMD --help)", whichever check refuses it -------------------------------
suffix() { # NAME CMD ARGS...: exit 2, one line ending with the command's suffix
	name=$1; shift
	"$BK" "$@" >out 2>err; rc=$?
	[ $rc -eq 2 ] && [ "$(wc -l <err)" -eq 1 ] && grep -q "(see brdfkit $1 --help)\$" err && ok \
		|| bad "$name: exit $rc, stderr '$(cat err)'"
}
suffix "compare --target form" compare --target form --out q
suffix "fit --bound x" fit --target f --form p0+LoH p0=1 --bound x --out q
suffix "fit no form" fit --target f --out q
suffix "fit --smith" fit --target f --form p0+LoH p0=1 --smith nope --out q
suffix "fit --x-range 0:2" fit --target vf --form vf_talk_r --x-range 0:2 --out q
suffix "gpucost p0 first" gpucost p0=1
suffix "eval unknown name" eval NoV foo=1
suffix "eval not a number" eval NoV NoV=x
suffix "eval VoH LoH differ" eval LoH LoH=0.5 VoH=0.6
suffix "eval unread input" eval NoV NoV=0.5 NoL=0.5
suffix "eval missing input" eval NoV
suffix "codegen --name 1x" codegen --lang c --name 1x NoV
suffix "codegen --name printf" codegen --lang c --name printf NoV
suffix "render --term" render --form vf_talk_r --term bad --out q
suffix "terms --role" terms --role X
suffix "time unknown part" time vf_talk_r:Z
suffix "time p0 first" time p0=1
suffix "lut --r-range 0:inf" lut --size 4 --r-range 0:inf --out q
suffix "lut --specular --r-range" lut --specular --r-range 0.5:0.2 --out q
suffix "codegen p15 alone" codegen --lang c p15 p15=1
suffix "eval p0 unset" eval 'p0*NoV' NoV=0.5
# control: a form's syntax error keeps its own location, without the suffix
"$BK" eval 'NoV+' NoV=0.5 >out 2>err
grep -q "form:1:" err && ! grep -q "(see brdfkit" err && ok || bad "form syntax error: $(cat err)"

# ---- M8: work of hours or GBs is estimated before it starts (cli_estimate) ----------
# early CMD...: CMD's stderr in err, stopped at its first line or after 3 s
# (tests/lib.sh until_lines; the work itself would run for minutes to years)
early() { until_lines 1 3 err "$@"; }
early "$BK" lut --size 4096 --samples 1073741824 --out q6
head -1 err | grep -q "^brdfkit lut: warning: the table: about .* years (.*); Ctrl-C stops it" && ok \
	|| bad "lut 2^30 samples: no warning first: $(head -c 300 err)"
early "$BK" lut --size 4096 --out q6 --quiet
grep -q "^brdfkit lut: warning: the table: about .* min" err && ok || bad "lut 4096 --quiet: the warning: $(head -c 300 err)"
early "$BK" lut --size 1024 --out q6
grep -q "^brdfkit lut: the table: about .* min" err && ok || bad "lut 1024: no estimate: $(head -c 300 err)"
early "$BK" lut --size 1024 --out q6 --quiet
[ ! -s err ] && ok || bad "lut 1024 --quiet: an estimate that is no warning is quiet: $(head -c 300 err)"
early "$BK" render --form vf_talk_r --size 2048 --device cpu --out rbig
grep -q "^brdfkit render: 1 candidate at 2048x818 pixels: about .* min" err && ok \
	|| bad "render --size 2048: no estimate: $(head -c 300 err)"
early "$BK" search --target vf2d --nx 2048 --nr 2048 --evals 300 --threads 1 --out q4
grep -q "^brdfkit search: 4.19M samples of target vf2d: about .*, 0.7 GB of memory" err && ok \
	|| bad "search --nx 2048 --nr 2048: no estimate: $(head -c 300 err)"
# controls: small work says nothing
"$BK" lut --size 16 --out q7 2>err >out && ! grep -q "about" err && ok || bad "lut 16: $(cat err)"
"$BK" render --form vf_talk_r --size 64 --device cpu --out r64 2>err >out && ! grep -q "about" err && ok \
	|| bad "render 64: $(cat err)"

echo "cli_parsing: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
