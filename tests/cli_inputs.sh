#!/bin/sh
# cli_inputs.sh — what brdfkit takes from a user's files and options (issue
# 39, items 4 and 5): forms that read an input the target does not sample
# are refused everywhere a form meets a target (M1); a front or catalog read
# for comparison or seeding must state the target, objective and precision
# the run needs (H2); numbers in a user's CSV are decimal (L8); links in
# every section are relative, percent-encoded and checked where the option
# is parsed and where report reads them (H4, L2, L3).
# usage: sh tests/cli_inputs.sh path/to/brdfkit
set -u
BK=${1:?usage: cli_inputs.sh path/to/brdfkit}
BK=$(cd "$(dirname "$BK")" && pwd)/$(basename "$BK")
REPO=$(pwd)
T=$(mktemp -d /tmp/bk_cli_inputs_XXXXXX)
trap 'rm -rf "$T"' EXIT
CSVGET=$REPO/build/csvget
. "$REPO/tests/lib.sh"
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
cd "$T" || exit 1

# refused RC NAME TOKEN CMD...: exit RC, one line on stderr holding TOKEN
refused() {
	want=$1 name=$2 token=$3; shift 3
	"$@" >out 2>err; rc=$?
	if [ "$rc" -eq "$want" ] && [ "$(wc -l <err)" -eq 1 ] && grep -qF -- "$token" err; then ok
	else bad "$name: exit $rc, stderr '$(head -c 400 err)'"; fi
}
# runs NAME CMD...: exit 0 (the matching case, the control of each refusal)
runs() {
	name=$1; shift
	if "$@" >out 2>err; then ok; else bad "$name: exit $?, stderr '$(head -c 400 err)'"; fi
}
S="search --evals 10 --threads 1 --quiet"

# ---- M1: an input the target does not sample ------------------------------------------
# f is Fresnel of LoH alone (it had r = 0.5 and a = 0.25 as constants), d is
# GGX D of NoH and r (it had f0): a form reading them fitted a constant.
refused 2 "f --start r" "--start 'r' reads an input target f does not provide" $BK $S --target f --start r --out m1
refused 2 "f --start a" "reads an input target f does not provide" $BK $S --target f --start 'a*LoH' --out m2
refused 2 "d --start f0" "--start 'f0*NoH' reads an input target d does not provide" $BK $S --target d --start 'f0*NoH' --out m3
refused 1 "fit f a" "the form reads a, which target f does not provide" $BK fit --target f --form 'p0*LoH + a' p0=1 --out m4
refused 1 "fit d f0" "the form reads f0, which target d does not provide" $BK fit --target d --form 'p0*NoH*f0' p0=1 --out m5
refused 2 "f --inputs r" "--inputs: the target does not provide r" $BK $S --target f --inputs LoH,r --out m6
refused 2 "compare f r" "'r*LoH' reads r, which target f does not provide" $BK compare --target f --no-time --no-refit --quiet --out m7 'r*LoH'
refused 2 "compare d f0" "'f0*NoH' reads f0, which target d does not provide" $BK compare --target d --no-time --no-refit --quiet --out m8 'f0*NoH'
# controls: what each target samples is still taken
runs "f --start f0" $BK $S --target f --start 'f0 + (1 - f0)*(1 - LoH)' --out m9
runs "d --start r" $BK $S --target d --start 'r*NoH' --out m10
runs "fit f f0" $BK fit --target f --nx 16 --form 'f0 + p0*(1 - LoH)' p0=1 --out m11
# the grammar a search on f enumerates: LoH and f0, no r or a
grep -q '^# certificate: .*; inputs LoH f0;' m9/front.csv && ok || bad "f's grammar: $(grep '^# certificate' m9/front.csv)"
# a --start-front member reading r, on f
{ grep '^#' m9/front.csv; printf 'name,form,form_b,parameters\nx,r*LoH,,\n'; } >rfront.csv
L=$(($(grep -c '^#' m9/front.csv) + 2))
refused 1 "f --start-front r" "rfront.csv:$L: x: the form reads an input the target does not provide" $BK $S --target f --start-front rfront.csv --out m12

# ---- H2: what a front's '#' lines state is checked ---------------------------------------
# tiny fronts: f (the run below compares with them), f on another grid, on
# another domain, of another objective, in half; vf2d
Q="search --evals 300 --enum-max 100 --threads 1 --seed 7 --quiet"
$BK $Q --target f --out fA >/dev/null 2>&1 || bad "search fA"
$BK $Q --target f --nx 64 --out fN >/dev/null 2>&1 || bad "search fN"
$BK $Q --target f --x-range 0:0.5 --out fX >/dev/null 2>&1 || bad "search fX"
$BK $Q --target f --objective max --out fM >/dev/null 2>&1 || bad "search fM"
$BK $Q --target f --precision half --out fH >/dev/null 2>&1 || bad "search fH"
$BK $Q --target vf2d --nx 8 --nr 8 --out vV >/dev/null 2>&1 || bad "search vV"
H="$BK $Q --target f --precision half"
refused 1 "vs other target" "--vs-front vV/front.csv: a front of target vf2d, this search's target is f" $H --vs-front vV/front.csv --out h1
refused 1 "vs other objective" "--vs-front fM/front.csv: a front of objective max_abs, this search's objective is rmse" $H --vs-front fM/front.csv --out h2
refused 1 "vs a catalog" "--vs-front fA/catalog.csv: a catalog of brdfkit search (its published forms), not a front" $H --vs-front fA/catalog.csv --out h3
refused 1 "vs a half front" "--vs-front fH/front.csv: a front in f16 precision, not f64" $H --vs-front fH/front.csv --out h4
refused 1 "vs other samples" "--vs-front fN/front.csv: a front of target f on other samples, domain or options: it says '...[0, 1] (64 cell centres)', this search's '...[0, 1] (256 cell centres)'" $H --vs-front fN/front.csv --out h5
refused 1 "vs other domain" "--vs-front fX/front.csv: a front of target f on another domain or with other options: it says '...in [0, 0.5] (N cell centres)', this search's '...in [0, 1] (N cell centres)'" $H --vs-front fX/front.csv --out h6
grep -v '^# target:' fA/front.csv >notarget.csv
refused 1 "vs no target line" "--vs-front notarget.csv: no '# target:' line" $H --vs-front notarget.csv --out h7
grep -v '^#' fA/front.csv >nohead.csv
refused 1 "vs no header" "--vs-front nohead.csv: no '# brdfkit ... search front' line: not a front.csv of brdfkit search" $H --vs-front nohead.csv --out h8
runs "vs the double front of f" $H --vs-front fA/front.csv --out h9
[ -s h9/vs_double.csv ] && ok || bad "vs the double front: no vs_double.csv"
# --start-front: target and domain, not grid, objective or precision
refused 1 "seed other target" "--start-front vV/front.csv: a front of target vf2d, this search's target is f" $H --start-front vV/front.csv --out h10
refused 1 "seed other domain" "--start-front fX/front.csv: a front of target f on another domain or with other options: it says '...in [0, 0.5] (N cell centres)'" $H --start-front fX/front.csv --out h11
refused 1 "seed a catalog" "--start-front fA/catalog.csv: a catalog of brdfkit search (its published forms), not a front" $H --start-front fA/catalog.csv --out h12
for ok_front in fA fN fM fH; do runs "seed from $ok_front" $H --start-front $ok_front/front.csv --out h13; done
# --start-forms: the forms of any target's front; the members that do not fit
# this target are left out and counted. vV is vf2d's front: its members that
# read r or a (counted here from its form column) do not fit f (LoH and f0)
n=$("$CSVGET" vV/front.csv form | wc -l)
m=$("$CSVGET" vV/front.csv form | grep -cE '(^|[^A-Za-z0-9_])(r|a)([^A-Za-z0-9_]|$)')
[ "$m" -gt 0 ] && [ "$m" -lt "$n" ] || bad "--start-forms premise: vV's front has $m of $n members reading r or a"
$H --start-forms vV/front.csv --out h14 >out 2>err && ok || bad "--start-forms vf2d's front on f: exit $?, $(cat err)"
grep -qE -- "^search: --start-forms vV/front.csv: $n members, [0-9]+ new seeds beside the [0-9]+ before, $m left out as not fitting target f \\(the first, line [0-9]+, [^:]+: the form reads an input the target does not provide\\)\$" err &&
	ok || bad "--start-forms: not '$n members ... $m left out': $(cat err)"
# a front none of whose members fits: refused, the first member named
refused 1 "--start-forms nothing fits" "--start-forms rfront.csv: none of its 1 members fits target f (line $L, x: the form reads an input the target does not provide)" $BK $S --target f --start-forms rfront.csv --out h15
refused 1 "--start-forms a catalog" "--start-forms fA/catalog.csv: a catalog of brdfkit search (its published forms), not a front" $H --start-forms fA/catalog.csv --out h16
# report --summary: front.csv and catalog.csv of one search
mkdir mixT mixM mixP
cp fA/catalog.csv fA/section.html mixT/ && cp vV/front.csv mixT/
cp fA/catalog.csv mixM/ && cp fM/front.csv mixM/
cp fA/catalog.csv mixP/ && cp fH/front.csv mixP/
refused 1 "summary other target" "--summary: mixT/front.csv: a front of target vf2d, its catalog.csv's target is f" $BK report --out p1.html --summary mixT fA/section.html
refused 1 "summary other objective" "--summary: mixM/front.csv: a front of objective max_abs, its catalog.csv's objective is rmse" $BK report --out p2.html --summary mixM fA/section.html
refused 1 "summary other precision" "--summary: mixP/front.csv: a front in f16 precision, not f64" $BK report --out p3.html --summary mixP fA/section.html
runs "summary of one search" $BK report --out p4.html --summary fA,fM,fH,vV fA/section.html

# ---- L8: decimal numbers only in a user's CSV ---------------------------------------------
# report --summary (front.csv, catalog.csv), --vs-front and --start-front (front.csv)
for v in 0x1p-30 ' 5' '5 ' 0x10 inf; do
	mkdir -p "n$v" && cp fA/catalog.csv "n$v/" &&
		csv_set fA/front.csv error name search_f_1 "$v" >"n$v/front.csv" || bad "csv_set '$v'"
	line=$(($(grep -c '^#' fA/front.csv) + 2))
	refused 1 "summary error '$v'" "n$v/front.csv:$line: error: expected a finite number >= 0, got '$v'" $BK report --out pn.html --summary "n$v" fA/section.html
	refused 1 "--vs-front error '$v'" "n$v/front.csv:$line: error: expected a finite number >= 0, got '$v'" $H --vs-front "n$v/front.csv" --out hn
	csv_set fA/front.csv parameters name search_f_1 "p0=$v" >"nseed.csv" || bad "csv_set p0"
	refused 1 "--start-front p0 '$v'" "nseed.csv:$line: parameters: p0: expected a finite number, got '$v' (item 1)" $H --start-front nseed.csv --out hn
done
cp -r fA n_ok && csv_set fA/front.csv error name search_f_1 0.5e-1 >n_ok/front.csv
runs "summary error 0.5e-1" $BK report --out pn.html --summary n_ok fA/section.html

# ---- H4, L2, L3: links ------------------------------------------------------------------
# --link-prefix: a relative path only, refused as the option is parsed (exit 2)
for p in 'javascript:alert(1)//' 'data:text/html;base64,PHNjcmlwdD5hbGVydCgxKTwvc2NyaXB0Pg==#' '//evil.example/' '\\evil/' 'http://x/'; do
	refused 2 "stability $p" "--link-prefix '$p':" $BK stability NoV --out l1 --link-prefix "$p"
	refused 2 "search $p" "--link-prefix '$p':" $BK $S --target f --out l2 --link-prefix "$p"
	refused 2 "render $p" "--link-prefix '$p':" $BK render --form vf_talk_r --size 16 --out l3 --link-prefix "$p"
	refused 2 "lut --sweep $p" "--link-prefix '$p':" $BK lut --specular --sweep --out l4 --link-prefix "$p"
	refused 2 "compare $p" "--link-prefix '$p':" $BK compare --target f --no-time --no-refit --out l5 --link-prefix "$p"
	refused 2 "scene $p" "--link-prefix '$p':" $BK scene "$REPO/analysis/scenes/rough_only.json" --no-time --out l6 --link-prefix "$p"
done
for l in l1 l2 l3 l4 l5 l6; do [ ! -e $l ] && ok || bad "a refused --link-prefix left $l"; done
# the control: a relative prefix, percent-encoded where written, and report takes the section
runs "stability ok/a b#/" $BK stability NoV --out l7 --link-prefix 'ok/a b#/'
grep -qF 'href="ok/a%20b%23/stability.csv"' l7/section.html && ok || bad "prefix not encoded: $(grep -o 'href="[^"]*stability.csv"' l7/section.html)"
runs "report of l7" $BK report --out pl.html l7/section.html
# report: network-path links refused, whichever slashes
for h in '//evil.example/x' '\\evil.example\x' '/\evil' ' //evil'; do
	printf '%s\n' '<section id="ev">' "<p><a href=\"$h\">x</a></p>" '</section>' >ev.html
	refused 1 "report href '$h'" "ev.html: line 2: a network-path link" $BK report --out pe.html ev.html
done
printf '%s\n' '<section id="ev">' '<p><a href="ok/x">x</a> <a href="/abs/x">y</a></p>' '</section>' >ev.html
runs "report relative hrefs" $BK report --out pe.html ev.html
# report --summary: folders named a#b, c%41d, e?f are paths in the hrefs
for d in 'a#b' 'c%41d' 'e?f'; do cp -r fA "$d"; done
runs "summary odd names" $BK report --out ps.html --summary 'a#b,c%41d,e?f' fA/section.html
for want in './a%23b/front.csv' './c%2541d/front.csv' './e%3Ff/front.csv' './a%23b/catalog.csv' './e%3Ff/'; do
	grep -qF "href=\"$want\"" ps.html && ok || bad "summary: no href $want: $(grep -o 'href="[^"]*"' ps.html | sort -u | head -8)"
done
! grep -qF 'href="./a#b/' ps.html && ! grep -qF 'href="./e?f/' ps.html && ok || bad "summary: a raw # or ? in a folder's link"

echo "cli_inputs: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
