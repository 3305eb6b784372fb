#!/bin/sh
# cli_opts.sh — no option without an effect: the walk of every command's
# option-applicability table (analysis/cli/cli.h), then the inputs around it
# that used to be taken silently (issue 21: M9, M10, L4, L7, M12).
#
# The walk: `brdfkit help --applicability` prints each command's table (its
# options, the context's dimensions, one rule per option and dimension, and
# setups: argument lists that put the command in its contexts); a command
# printed as "none" has no table and fails. Each setup alone must pass
# --check-options (the parse and the applicability check, nothing run) and
# report its context. Then every option, given in every setup that lacks it,
# must be refused (exit 2, one line "brdfkit CMD: OPT has no effect ...",
# nothing on stdout) where one of its rules says it does not act in that
# context, and accepted (exit 0, the context line) where all say it acts. The
# expectation is computed here, in awk, from the printed rules and the
# contexts the tool reports, not by the tool's own check. A dimension value no
# setup reaches, a rule no setup refuses, an option accepted nowhere, or an
# option without a rule fails the walk too.
# usage: sh tests/cli_opts.sh path/to/brdfkit
set -u
BK=${1:?usage: cli_opts.sh path/to/brdfkit}
case $BK in /*) ;; *) BK=$(pwd)/$BK ;; esac # the walk runs in a scratch directory
ROOT=$(pwd)
CSVGET=${CSVGET:-$ROOT/build/csvget}
. "$ROOT/tests/lib.sh"
T=$(mktemp -d /tmp/bk_opts_XXXXXX)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
us=$(printf '\037') # field separator of the walk's own lists: never in an argument
tab=$(printf '\t')
mkdir "$T/run"
set -f # forms hold '*'

# ---- the walk -----------------------------------------------------------------

"$BK" help --applicability >"$T/tables" 2>"$T/err" || bad "help --applicability: $(cat "$T/err")"
# every command of brdfkit --help printed a table (or "none", which fails below)
"$BK" --help | awk '/^commands:/ { on = 1; next } on && NF { print $1 }' >"$T/commands"
[ -s "$T/commands" ] && ok || bad "brdfkit --help lists no commands"
while read -r c; do
	grep -q "^\(table\|none\)$tab$c\$" "$T/tables" && ok || bad "$c: help --applicability printed nothing for it"
done <"$T/commands"

# every setup alone: accepted, and its context as the tool sees it
: >"$T/contexts"
awk -F"$tab" -v OFS="$us" '$1 == "setup" { n[$2]++; print $2, n[$2], $3 }' "$T/tables" >"$T/setups"
while IFS="$us" read -r cmd idx args; do
	(cd "$T/run" && "$BK" $cmd $args --check-options >"$T/out" 2>"$T/err")
	rc=$?
	if [ $rc -eq 0 ] && [ "$(wc -l <"$T/out")" -eq 1 ] && grep -q "^context$tab$cmd" "$T/out"; then
		ok
		awk -F"$tab" -v OFS="$tab" -v i="$idx" '{ $1 = $2; $2 = i; print }' "$T/out" >>"$T/contexts"
	else
		bad "$cmd setup '$args' --check-options: rc $rc, stdout '$(cat "$T/out")', stderr '$(cat "$T/err")'"
	fi
done <"$T/setups"

# plan TABLES CONTEXTS: the cases (CASE cmd accept|refuse shown-option setup
# added-args), and FAIL lines for what a table must reach, from the rules and
# the contexts
plan() {
	awk -F"$tab" -v OFS="$us" -v TABLES="$1" '
function has_word(s, w,   n, i, a) { n = split(s, a, " "); for (i = 1; i <= n; i++) if (a[i] == w) return 1; return 0 }
function in_list(v, l,   n, i, a) { n = split(l, a, ","); for (i = 1; i <= n; i++) if (a[i] == v) return 1; return 0 }
FILENAME == TABLES {
	if ($1 == "table") cmds[++nc] = $2
	else if ($1 == "none") print "FAIL", $2 ": no option-applicability table (analysis/cli/cli.h: cli_parse_table)"
	else if ($1 == "opt") { nopt[$2]++; optname[$2, nopt[$2]] = $3; kind[$2, $3] = $4 }
	else if ($1 == "dim") { ndim[$2]++; dimname[$2, ndim[$2]] = $3; dimvals[$2, $3] = $4
		n = split($5, un, ","); for (i = 1; i <= n; i++) unreached[$2, $3, un[i]] = 1 } # mpirun alone reaches them
	else if ($1 == "rule") { nr++; rc_[nr] = $2; ro[nr] = $3; rv[nr] = $4; rx[nr] = $5; rd[nr] = $6; ra[nr] = $7 }
	else if ($1 == "setup") { nsetup[$2]++; setup[$2, nsetup[$2]] = $3 }
	next
}
{ good[$1, $2] = 1; for (i = 3; i <= NF; i++) { split($i, kv, "="); ctx[$1, $2, kv[1]] = kv[2]; reached[$1, kv[1], kv[2]] = 1 } }
END {
	for (k = 1; k <= nc; k++) {
		c = cmds[k]
		for (d = 1; d <= ndim[c]; d++) {
			dn = dimname[c, d]; n = split(dimvals[c, dn], vals, ",")
			for (i = 1; i <= n; i++)
				if (!((c, dn, vals[i]) in reached) && !((c, dn, vals[i]) in unreached)) print "FAIL", c ": no setup reaches " dn "=" vals[i]
		}
		for (i = 1; i <= nopt[c]; i++) {
			o = optname[c, i]; ruled = 0
			for (r = 1; r <= nr; r++) if (rc_[r] == c && ro[r] == o) ruled = 1
			if (!ruled) print "FAIL", c " " o ": no applicability rule"
		}
		delete seen
		for (r = 1; r <= nr; r++) {
			if (rc_[r] != c || ((ro[r], rv[r]) in seen)) continue
			seen[ro[r], rv[r]] = 1
			o = ro[r]; v = rv[r]; ex = v != "*" ? v : ""
			for (q = 1; q <= nr && ex == ""; q++)
				if (rc_[q] == c && ro[q] == o && rv[q] == "*" && rx[q] != "-") ex = rx[q]
			if (kind[c, o] == "value" && ex == "") continue # given by every setup that needs it
			add = kind[c, o] == "flag" ? o : o " " ex
			show = v != "*" ? o " " v : o
			accepted = present = elsewhere = 0
			for (q = 1; q <= nr; q++) { # an option that acts only where no setup can reach
				if (rc_[q] != c || ro[q] != o || rv[q] != rv[r] || rd[q] == "*") continue
				n = split(ra[q], av, ","); only = 1
				for (i = 1; i <= n; i++) if (!((c, rd[q], av[i]) in unreached)) only = 0
				elsewhere += only
			}
			for (s = 1; s <= nsetup[c]; s++) {
				if (!((c, s) in good)) continue
				if (has_word(setup[c, s], o)) { present = 1; continue }
				acts = 1
				for (q = 1; q <= nr; q++) {
					if (rc_[q] != c || ro[q] != o || (rv[q] != "*" && rv[q] != ex) || rd[q] == "*") continue
					if (!in_list(ctx[c, s, rd[q]], ra[q])) { acts = 0; refused[q] = 1 }
				}
				print "CASE", c, acts ? "accept" : "refuse", show, setup[c, s], add
				accepted += acts
			}
			if (!accepted && !present && !elsewhere) print "FAIL", c " " show ": accepted in no setup"
		}
		for (r = 1; r <= nr; r++)
			if (rc_[r] == c && rd[r] != "*" && !(r in refused))
				print "FAIL", c " " ro[r] (rv[r] != "*" ? " " rv[r] : "") ": no setup where it does not act (" rd[r] " not in " ra[r] ")"
	}
}' "$1" "$2"
}
plan "$T/tables" "$T/contexts" >"$T/cases"

grep "^FAIL$us" "$T/cases" >"$T/fails"
while IFS="$us" read -r what a; do
	bad "$a"
done <"$T/fails"
[ -s "$T/fails" ] || ok

# The cases run through `brdfkit help --check-each` (analysis/cli/main.c):
# each as `brdfkit WORDS --check-options` in a process of its own, forked from
# one start of the tool rather than started ~1,450 times (most of the walk's
# time, sanitized); each case's words are the shell's split of its command,
# setup and added option, its outputs in $T/each/N.out and N.err, and
# "N<tab>STATUS" a line in $T/status. (Their output is read with the shell's
# own read and case, not a wc and a grep each: one_line.)
awk -F"$us" -v OFS="$us" '$1 == "CASE" { n = split($5 " " $6, w, " "); s = $2
	for (i = 1; i <= n; i++) s = s OFS w[i]
	print s }' "$T/cases" >"$T/list"
mkdir "$T/each"
cd "$T/run" || exit 1
"$BK" help --check-each "$T/list" "$T/each" >"$T/status" 2>"$T/err" || bad "help --check-each: $(cat "$T/err")"
ncase=0
while IFS="$us" read -r what cmd expect show sargs add; do
	[ "$what" = CASE ] || continue
	ncase=$((ncase + 1))
	k= rc=
	IFS="$tab" read -r k rc <&3
	[ "$k" = $ncase ] || { bad "help --check-each: no status for case $ncase ($cmd $sargs $add)"; break; }
	out=$T/each/$ncase.out err=$T/each/$ncase.err
	if [ "$expect" = accept ]; then
		line=
		IFS= read -r line <"$out"
		case $line in "context$tab$cmd"*) context=1 ;; *) context=0 ;; esac
		if [ "$rc" -eq 0 ] && [ $context = 1 ] && [ ! -s "$err" ]; then ok; else
			bad "$cmd $add in '$sargs': should act there, got rc $rc: $(cat "$err")"; fi
	else
		if [ "$rc" -eq 2 ] && [ ! -s "$out" ] && one_line "$err" "brdfkit $cmd: $show has no effect"; then ok; else
			bad "$cmd $add in '$sargs': should be refused, got rc $rc: stdout '$(cat "$out")' stderr '$(cat "$err")'"; fi
	fi
done <"$T/cases" 3<"$T/status"
# the control of --check-each: the first case accepted and the first refused,
# started as the tool alone, print the same bytes and exit the same
for expect in accept refuse; do
	k=$(awk -F"$us" -v e=$expect '$1 == "CASE" { n++ } $1 == "CASE" && $3 == e { print n; exit }' "$T/cases")
	[ -n "$k" ] || { bad "the walk has no case to $expect"; continue; }
	# shellcheck disable=SC2046 # the case's words, split as the walk splits them
	"$BK" $(sed -n "${k}p" "$T/list" | tr "$us" ' ') --check-options >"$T/one.out" 2>"$T/one.err"
	rc=$?
	[ "$rc" = "$(sed -n "${k}p" "$T/status" | cut -f2)" ] && cmp -s "$T/one.out" "$T/each/$k.out" &&
		cmp -s "$T/one.err" "$T/each/$k.err" && ok || bad "case $k ($expect): --check-each and a start of its own differ"
done
cd "$ROOT" || exit 1
[ $ncase -gt 0 ] && ok || bad "the walk made no case"

# negative controls of the walk's own checks: a setup that does not reach a
# context, and a rule no setup refuses, are reported (the awk above on a
# table doctored here); and --check-options is unknown to a command without
# a table, which must not run as if it were checked
printf 'table\tx\nopt\tx\t--a\tvalue\ndim\tx\tk\tp,q\nrule\tx\t--a\t*\t1\tk\tq\nsetup\tx\t--b 1\n' >"$T/t2"
printf 'x\t1\tk=q\n' >"$T/c2"
plan "$T/t2" "$T/c2" >"$T/cases2"
grep -q "no setup reaches k=p" "$T/cases2" && grep -q "x --a: no setup where it does not act" "$T/cases2" &&
	ok || bad "the walk's coverage checks do not fail on a doctored table: $(cat "$T/cases2")"
# (while one is left: the first printed as "none")
untabled=$(awk -F"$tab" '$1 == "none" { print $2; exit }' "$T/tables")
if [ -n "$untabled" ]; then
	if "$BK" $untabled --check-options >"$T/out" 2>"$T/err"; then bad "--check-options taken by $untabled, which has no table"
	else grep -qF "unknown option '--check-options'" "$T/err" && ok || bad "$untabled --check-options: $(cat "$T/err")"; fi
fi

# ---- issue 21, M10: what used to be taken without an effect -------------------

# expect_usage NAME TOKEN CMD...: exit 2, one line on stderr holding TOKEN, no stdout.
expect_usage() {
	name=$1 token=$2; shift 2
	"$@" >"$T/out" 2>"$T/err"
	rc=$?
	if [ $rc -eq 2 ] && [ ! -s "$T/out" ] && one_line "$T/err" "$token"; then ok
	else bad "$name: rc $rc, stdout '$(head -c 200 "$T/out")', stderr '$(cat "$T/err")'"; fi
}

cd "$T/run" || exit 1
expect_usage "lut --samples --tol" "brdfkit lut: --tol has no effect with --samples (the Monte Carlo bake has no tolerance)" \
	"$BK" lut --size 2 --samples 16 --tol 1e-3 --out lt
[ ! -e lt ] && ok || bad "a refused lut wrote lt"
"$BK" lut --size 2 --samples 16 --out lt >/dev/null 2>&1 && grep -q 'Hammersley' lt/dfg.csv && ok ||
	bad "lut --samples 16 alone (the control) failed"
expect_usage "dfg --tol --samples" "brdfkit dfg: --tol has no effect with --samples" \
	"$BK" dfg --nov 0.5 --roughness 0.5 --tol 1e-6 --samples 64
expect_usage "fit --seed with one start" "brdfkit fit: --seed has no effect with --starts 1 (it draws the starts after the first)" \
	"$BK" fit --target f --form 'p0*LoH' p0=1 --starts 1 --seed 3 --out fs
expect_usage "fit --threads on TinySolver" "brdfkit fit: --threads has no effect with the default solver" \
	"$BK" fit --target f --form 'p0*LoH' p0=1 --threads 2 --out fs
expect_usage "compare --fetch-cost without LUT rows" "brdfkit compare: --fetch-cost has no effect without LUT rows" \
	"$BK" compare --target vf2d --fetch-cost 32 --out cs
expect_usage "albedo --k with --f0" "brdfkit albedo: --k has no effect with --f0" \
	"$BK" albedo --d ggx --v implicit --f schlick --nov 0.5 --roughness 0.5 --f0 0.04 --k 2
expect_usage "albedo --f90 on exact Fresnel" "brdfkit albedo: --f90 has no effect on the F terms chosen" \
	"$BK" albedo --d ggx --v implicit --f dielectric --nov 0.5 --roughness 0.5 --f0 0.04 --f90 0.5
# the control: --f90 changes Schlick's albedo (F = f90 at grazing: a lower f90, a lower albedo)
a1=$("$BK" albedo --d ggx --v implicit --f schlick --nov 0.5 --roughness 0.5 --f0 0.04 2>/dev/null | tail -1 | cut -d, -f10)
a2=$("$BK" albedo --d ggx --v implicit --f schlick --nov 0.5 --roughness 0.5 --f0 0.04 --f90 0.5 2>/dev/null | tail -1 | cut -d, -f10)
awk -v a="$a1" -v b="$a2" 'BEGIN { exit !(b + 0 < a + 0) }' && ok || bad "albedo --f90 0.5 did not lower the albedo: $a1 -> $a2"
[ ! -e fs ] && [ ! -e cs ] && ok || bad "a refused command wrote its --out"

# lists: an item twice (as text or as the same number), or an empty item, is refused
expect_usage "number list twice" "--nov: '0.5' given twice in the list '0.5,0.5'" "$BK" dfg --nov 0.5,0.5 --roughness 0.5
expect_usage "number list same value" "--roughness: '5e-1' given twice in the list '0.5,5e-1'" \
	"$BK" dfg --nov 0.5 --roughness 0.5,5e-1
expect_usage "albedo f0 twice" "--f0: '0.04' given twice" \
	"$BK" albedo --d ggx --v implicit --f schlick --nov 0.5 --roughness 0.5 --f0 0.04,0.04
expect_usage "fit --hold twice" "--hold: 'p0' given twice in the list 'p0,p0'" \
	"$BK" fit --target f --form 'p0*LoH + p1' p0=1 p1=0 --hold p0,p0 --out fl
expect_usage "fit --hold p01 (one spelling of a parameter, params.h)" "--hold: expected parameters of the form (p0..p1), got 'p01'" \
	"$BK" fit --target f --form 'p0*LoH + p1' p0=1 p1=0 --hold p1,p01 --out fl
expect_usage "fit --hold trailing comma" "--hold: empty item in the list 'p0,'" \
	"$BK" fit --target f --form 'p0*LoH + p1' p0=1 p1=0 --hold p0, --out fl
expect_usage "fit --bound twice" "--bound: p0 given twice in the list 'p0=0:1,p0=0:2'" \
	"$BK" fit --target f --form 'p0*LoH' p0=0.5 --bound p0=0:1,p0=0:2 --out fl
expect_usage "fit --bound empty item" "--bound: empty item in the list 'p0=0:1,,'" \
	"$BK" fit --target f --form 'p0*LoH' p0=0.5 --bound p0=0:1,, --out fl
expect_usage "fit env --f0 twice" "--f0: '0.5' given twice" \
	"$BK" fit --target env --form 'f0*p0' p0=1 --f0 0.5,0.5 --out fl
expect_usage "fit --bound on a held parameter" "--bound p1 has no effect: --hold keeps p1 at its start value" \
	"$BK" fit --target f --form 'p0*LoH + p1' p0=1 p1=0 --hold p1 --bound p1=-1:1 --out fl
[ ! -e fl ] && ok || bad "a refused fit wrote fl"
# the control: distinct items are taken, one row each
[ "$("$BK" dfg --nov 0.5,0.6 --roughness 0.5 | wc -l)" -eq 3 ] && ok || bad "dfg --nov 0.5,0.6 is not two rows"

# ---- M9: a fit that fits nothing -------------------------------------------------

expect_usage "fit every parameter held" \
	"brdfkit fit: --hold holds every parameter of the form (p0): nothing is fitted; to evaluate the form at these values, write them into it as numbers" \
	"$BK" fit --target f --form 'p0*LoH' p0=1 --hold p0 --out fh
expect_usage "fit every parameter held (two)" "--hold holds every parameter of the form (p0..p1)" \
	"$BK" fit --target f --form 'p0*LoH + p1' p0=1 p1=0 --hold p1,p0 --out fh
[ ! -e fh ] && ok || bad "fit --hold of every parameter wrote fh"

# One parameter held: p1 = 0 held, so p0 is the regression through the origin
# of the exact Fresnel (n = 1.5, Born & Wolf) on the 256 cell centres of LoH:
# p0 = sum c y / sum c^2, se = sqrt(rss / (m - 1) / sum c^2) (uniform weights,
# computed here in awk). p1 has no standard error (an empty field), not 0.
"$BK" fit --target f --form 'p0*LoH + p1' p0=1 p1=0 --hold p1 --out fh >"$T/fit.out" 2>"$T/err" && ok ||
	bad "fit --hold p1: $(cat "$T/err")"
want=$(awk 'BEGIN { n = 1.5; m = 256
	for (i = 0; i < m; i++) { c = (i + 0.5) / m; g = sqrt(n * n - 1 + c * c)
		a = (g - c) / (g + c); b = (c * (g + c) - 1) / (c * (g - c) + 1); y[i] = 0.5 * a * a * (1 + b * b)
		scy += c * y[i]; scc += c * c }
	p = scy / scc
	for (i = 0; i < m; i++) { c = (i + 0.5) / m; e = p * c - y[i]; rss += e * e }
	printf "%.10g %.10g\n", p, sqrt(rss / (m - 1) / scc) }')
p0=$(csv_where fh/coefficients.csv parameter p0 value) && se0=$(csv_where fh/coefficients.csv parameter p0 standard_error) &&
	se1=$(csv_where fh/coefficients.csv parameter p1 standard_error) && v1=$(csv_where fh/coefficients.csv parameter p1 value) ||
	bad "coefficients.csv unreadable"
# p0 is reported to the decade at or below se/100 (fit.c, round_to_se): within se/100 of the closed form
awk -v w="$want" -v p="$p0" -v s="$se0" 'BEGIN { split(w, a, " ")
	exit !(p - a[1] <= a[2] / 100 && a[1] - p <= a[2] / 100 && s / a[2] < 1.01 && a[2] / s < 1.01) }' && ok ||
	bad "fit --hold p1: p0 $p0 ± $se0, closed form $want"
[ "$v1" = 0 ] && [ -z "$se1" ] && ok || bad "held p1: value '$v1', standard error '$se1' (want 0 and empty)"
grep -q '^# held at the start value by --hold: p1$' fh/coefficients.csv && ok || bad "coefficients.csv does not say p1 is held"
grep -q '± 0$\|± 0 ' "$T/fit.out" && bad "stdout gives a held parameter ± 0: $(cat "$T/fit.out")" || ok
# the control: the fitted p0's standard error is a number, and nonzero
awk -v s="$se0" 'BEGIN { exit !(s + 0 > 0) }' && ok || bad "p0's standard error '$se0'"

# ---- L4: errors that say what went wrong -----------------------------------------

"$BK" fit --target f --form 'p0*LoH' p0=1e308 --out fe >"$T/out" 2>"$T/err"
[ $? -eq 1 ] && [ "$(wc -l <"$T/err")" -eq 1 ] &&
	grep -qF "every start failed; the first, start 1 of 4: the cost is inf: the squared residuals overflow double" "$T/err" &&
	ok || bad "fit p0=1e308: $(cat "$T/err")"
expect_usage "form domain too wide" "the domain of 'NoV' is too wide: (1e+308 - (-1e+308)) x 256 cells overflows double" \
	"$BK" fit --target form --target-form NoV --domain NoV=-1e308:1e308 --form 'p0*NoV' p0=1 --out fe
[ ! -e fe ] && ok || bad "a failed fit wrote fe"

# ---- L7: compare --no-time measures nothing, so shows nothing -------------------

"$BK" compare --target f --no-refit --no-time --out cn >/dev/null 2>"$T/err" && ok || bad "compare --no-time: $(cat "$T/err")"
[ ! -e cn/timing.csv ] && [ ! -e cn/pareto_ns.svg ] && ok || bad "compare --no-time wrote $(ls cn | tr '\n' ' ')"
grep -q 'CPU run time: not measured (--no-time)' cn/section.html && ! grep -q 'pareto_ns' cn/section.html && ok ||
	bad "compare --no-time: the section links an empty plot or says nothing"
[ -s cn/compare.csv ] && [ -s cn/pareto_cost.svg ] && ok || bad "compare --no-time lost compare.csv or pareto_cost.svg"

# ---- M12: @FILE and - read no more than a form can hold --------------------------

# /dev/zero never ends: the reader stops at the cap (16384 characters and a
# line end, 16386 bytes, and the one more that shows there is more), in a
# 300 MB address space that a whole read would exhaust (a sanitized tool
# cannot start in one: then the time limit alone shows the read ends)
limit=300000
sh -c 'ulimit -v $1; exec "$2" --version >/dev/null 2>&1' sh $limit "$BK" 2>/dev/null || limit=unlimited
(ulimit -v $limit; timeout 10 "$BK" eval @/dev/zero NoV=0.5) >"$T/out" 2>"$T/err"
rc=$?
[ $rc -eq 2 ] && [ "$(wc -l <"$T/err")" -eq 1 ] &&
	grep -qF "@/dev/zero: longer than 16386 bytes: a form is at most 16384 characters (not read further)" "$T/err" &&
	ok || bad "eval @/dev/zero: rc $rc, $(cat "$T/err")"
# a FIFO whose writer would go on for 100 MB: the reader stops, the writer gets SIGPIPE
mkfifo fifo
timeout 20 sh -c "head -c 100000000 /dev/zero | tr '\\0' x >fifo" 2>/dev/null & # never blocks the test for good
timeout 10 "$BK" eval @fifo NoV=0.5 >"$T/out" 2>"$T/err"
rc=$?
wait
[ $rc -eq 2 ] && grep -qF "@fifo: longer than 16386 bytes" "$T/err" && ok || bad "eval @fifo: rc $rc, $(cat "$T/err")"
head -c 20000 /dev/zero | "$BK" codegen --lang c - >"$T/out" 2>"$T/err"
[ $? -eq 2 ] && grep -qF "standard input: longer than 16386 bytes" "$T/err" && ok || bad "codegen - of 20000 bytes: $(cat "$T/err")"
# the edge: 16384 characters and CRLF (16386 bytes) are a form; one character more
# reaches the parser, which names the limit at its column
awk 'BEGIN { s = "r"; for (i = 1; i < 16384; i++) s = s " "; printf "%s\r\n", s }' >edge.txt
[ "$(wc -c <edge.txt)" -eq 16386 ] && [ "$("$BK" eval @edge.txt r=0.25 2>"$T/err" | head -1)" = "f64 0.25" ] && ok ||
	bad "a 16384-character form with CRLF: $(cat "$T/err")"
awk 'BEGIN { s = "r"; for (i = 1; i <= 16384; i++) s = s " "; printf "%s\n", s }' >over.txt
"$BK" eval @over.txt r=0.25 >/dev/null 2>"$T/err"
[ $? -ne 0 ] && grep -qF "form:1:16385: form longer than 16384 characters" "$T/err" && ok || bad "16385 characters: $(cat "$T/err")"

echo "cli_opts: $pass passed, $fail failed"
[ $fail -eq 0 ]
