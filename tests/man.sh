#!/bin/sh
# man.sh — the manual pages (analysis/man/*.scd, scdoc) against the tool, and
# the citation file against the version.
# usage: sh tests/man.sh path/to/brdfkit
#
#   - every command `brdfkit --help` lists (its "commands:" block, read from the
#     tool, not from a list here) has a page brdfkit-CMD.1.scd, and brdfkit.1.scd
#     names every page in its SEE ALSO;
#   - every long option `brdfkit CMD --help` prints (and the help of a mode it
#     points to, "brdfkit lut --specular --help") is an option of that page, in
#     bold (*--opt*) as OPTIONS writes it;
#   - every page has NAME (naming its own file), SYNOPSIS, DESCRIPTION, OPTIONS,
#     EXAMPLES and SEE ALSO, goes through scdoc and renders with
#     `groff -Kutf-8 -t -man -ww -z` without a warning;
#   - an example block that shows output ("$ " lines) is run by tests/readme.sh
#     and must print what the page shows;
#   - section 3 (brdfkit_HEADER.3.scd, the library's API, each named in
#     brdfkit(1)'s SEE ALSO): every function the installed headers declare (the Makefile's PUB_H, preprocessed: tests/lib.sh
#     api_names) is documented, bold as *bk_name*() in some page's text, and
#     every name a page documents or shows in its SYNOPSIS is declared; each
#     page has NAME (its own file), SYNOPSIS, DESCRIPTION, RETURN VALUES,
#     ERRORS, EXAMPLES and SEE ALSO, and goes through scdoc and groff cleanly;
#     an example that is a whole program compiles (C11, -Werror) and runs
#     (brdfkit_brdf(3)'s prints GGX D(1, 1)·π = 1, then its form in half as
#     brdfkit eval prints it);
#   - CITATION.cff parses as YAML (python3-yaml; else a line check), has the
#     fields a citation needs, and its version is brdf/brdf.h's BK_VERSION.
# Negative controls, each showing a check can fail: a tool whose --help lists
# one more command, one whose dfg --help prints one more option, a page with a
# roff request groff does not know, a page without its OPTIONS section, an
# example whose shown output is wrong, a CITATION.cff of another version and one
# that is not YAML; headers declaring one function more than the pages document,
# a page documenting a function no header declares, a section-3 page without
# its ERRORS section, an example calling an undeclared function.
set -u
BK=${1:?usage: man.sh path/to/brdfkit}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
case $BK in /*) ;; *) BK=$PWD/$BK ;; esac
MAN=$ROOT/analysis/man
T=$(mktemp -d /tmp/bk_man_XXXXXX)
trap 'rm -rf "$T"' EXIT
CSVGET=$ROOT/build/csvget
. "$ROOT/tests/lib.sh" # api_names
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
# expect_fail WHAT CMD...: a negative control, CMD must fail (its output hidden)
expect_fail() { w=$1; shift; if "$@" >/dev/null 2>&1; then bad "control passed: $w"; else ok; fi; }

# commands TOOL: the commands its --help lists, one a line
commands() { "$1" --help 2>&1 | awk '/^commands:/ { on = 1; next } on && /^  [a-z]/ { print $1 } on && /^$/ { on = 0 }'; }
# options TOOL CMD: the long options of CMD's --help, and of any mode's help it
# points to ("(brdfkit CMD --MODE --help)"), one a line
options() {
	"$1" "$2" --help >"$T/h.$2" 2>&1
	for m in $(grep -o "brdfkit $2 --[a-z-]* --help" "$T/h.$2" | awk '{ print $3 }' | sort -u); do
		"$1" "$2" "$m" --help >>"$T/h.$2" 2>&1
	done
	sed -n 's/^  \(--[a-z0-9][a-z0-9-]*\).*/\1/p' "$T/h.$2" | sort -u
	rm -f "$T/h.$2"
}

# check_pages TOOL DIR: a page per command, all named in brdfkit(1)'s SEE ALSO
check_pages() {
	rc=0
	[ -n "$(commands "$1")" ] || { echo "no command read from $1 --help"; return 1; }
	for c in $(commands "$1"); do
		[ -f "$2/brdfkit-$c.1.scd" ] || { echo "no page $2/brdfkit-$c.1.scd for the command $c"; rc=1; }
	done
	for p in "$2"/brdfkit-*.1.scd; do
		n=$(basename "$p" .1.scd)
		awk '/^# SEE ALSO/ { on = 1 } on' "$2/brdfkit.1.scd" | grep -q "\*$n\*(1)" ||
			{ echo "brdfkit(1) does not name $n(1) in SEE ALSO"; rc=1; }
	done
	return $rc
}
# check_options TOOL DIR: each command's options in bold in its page's OPTIONS
check_options() {
	rc=0
	for c in $(commands "$1"); do
		p="$2/brdfkit-$c.1.scd"
		[ -f "$p" ] || continue
		awk '/^# OPTIONS/ { on = 1; next } /^# / { on = 0 } on' "$p" >"$T/opts"
		n=0
		for o in $(options "$1" "$c"); do
			n=$((n + 1))
			grep -qF -- "*$o*" "$T/opts" || { echo "$c: $o is not in OPTIONS of $p"; rc=1; }
		done
		[ "$n" -gt 0 ] || { echo "$c: no option read from its --help"; rc=1; }
	done
	return $rc
}
# check_page FILE.scd: the sections, scdoc, and groff without a warning
check_page() {
	n=$(basename "$1" .1.scd)
	head -1 "$1" | grep -qx "$n(1)" || { echo "$1: first line is not $n(1)"; return 1; }
	for s in NAME SYNOPSIS DESCRIPTION OPTIONS EXAMPLES "SEE ALSO"; do
		grep -qx "# $s" "$1" || { echo "$1: no section $s"; return 1; }
	done
	awk '/^# NAME/ { getline; getline; print; exit }' "$1" | grep -q "^$n - " || { echo "$1: NAME is not '$n - ...'"; return 1; }
	scdoc <"$1" >"$T/page.1" 2>"$T/scdoc.err" || { echo "$1: scdoc: $(cat "$T/scdoc.err")"; return 1; }
	check_roff "$T/page.1" || { echo "$1: roff warnings above"; return 1; }
}
# check_roff FILE.1: groff renders it (tables, man macros) with no warning
check_roff() {
	groff -Kutf-8 -t -man -ww -z "$1" >"$T/groff.err" 2>&1 && [ ! -s "$T/groff.err" ] || { cat "$T/groff.err"; return 1; }
}
# pub_headers: the installed headers (the Makefile's PUB_H), as an include
# directory $T/inc/brdfkit/ of links, the names they are installed under
pub_headers() {
	rm -rf "$T/inc" && mkdir -p "$T/inc/brdfkit"
	for h in $(awk '/^PUB_H *=/ { on = 1; sub(/^PUB_H *= */, "") } on { c = sub(/\\$/, ""); print; if (!c) exit }' \
		"$ROOT/Makefile"); do
		ln -s "$ROOT/$h" "$T/inc/brdfkit/$(basename "$h")" || return 1
	done
	[ -e "$T/inc/brdfkit/catalog.h" ] || { echo "PUB_H not read from the Makefile"; return 1; }
}
# check_api INCDIR DIR: the functions INCDIR/brdfkit declares against the
# section-3 pages DIR/*.3.scd (documented: *bk_name*( in the text; named: that,
# or bk_name( in a SYNOPSIS)
check_api() {
	api_names "$1" >"$T/api.names" || return 1
	[ "$(wc -l <"$T/api.names")" -ge 150 ] || { echo "only $(wc -l <"$T/api.names") names read from $1"; return 1; }
	cat "$2"/*.3.scd | grep -o '\*bk_[A-Za-z0-9_]*\*(' | tr -d '*(' | LC_ALL=C sort -u >"$T/api.bold"
	for p in "$2"/*.3.scd; do awk '/^# SYNOPSIS/ { on = 1; next } /^# / { on = 0 } on' "$p"; done |
		grep -o '\bbk_[A-Za-z0-9_]*(' | tr -d '(' | LC_ALL=C sort -u >"$T/api.syn"
	rc=0
	for n in $(LC_ALL=C comm -23 "$T/api.names" "$T/api.bold"); do echo "$n: declared, documented in no section-3 page"; rc=1; done
	for n in $(LC_ALL=C sort -u "$T/api.bold" "$T/api.syn" | LC_ALL=C comm -13 "$T/api.names" -); do
		echo "$n: in a section-3 page, declared in no installed header"; rc=1
	done
	return $rc
}
# check_see3 DIR: brdfkit(1)'s SEE ALSO names every section-3 page of DIR
check_see3() {
	rc=0
	for p in "$1"/*.3.scd; do
		n=$(basename "$p" .3.scd)
		awk '/^# SEE ALSO/ { on = 1 } on' "$MAN/brdfkit.1.scd" | grep -q "\*$n\*(3)" ||
			{ echo "brdfkit(1) does not name $n(3) in SEE ALSO"; rc=1; }
	done
	return $rc
}
# check_page3 FILE.3.scd: the sections, scdoc, and groff without a warning
check_page3() {
	n=$(basename "$1" .3.scd)
	head -1 "$1" | grep -qx "$n(3)" || { echo "$1: first line is not $n(3)"; return 1; }
	for s in NAME SYNOPSIS DESCRIPTION "RETURN VALUES" ERRORS EXAMPLES "SEE ALSO"; do
		grep -qx "# $s" "$1" || { echo "$1: no section $s"; return 1; }
	done
	awk '/^# NAME/ { getline; getline; print; exit }' "$1" | grep -q "^$n - " || { echo "$1: NAME is not '$n - ...'"; return 1; }
	scdoc <"$1" >"$T/page.3" 2>"$T/scdoc.err" || { echo "$1: scdoc: $(cat "$T/scdoc.err")"; return 1; }
	check_roff "$T/page.3" || { echo "$1: roff warnings above"; return 1; }
}
# example3 FILE.3.scd: the code of its EXAMPLES section (the fenced lines)
example3() { awk '/^# EXAMPLES/ { on = 1; next } /^# / { on = 0 } on && /^```/ { code = !code; next } on && code' "$1"; }
# run_example3 FILE.3.scd OUT: an example that is a whole program (int main)
# compiled as C11 with -Wall -Wextra -Werror against the installed headers'
# names ($T/inc, brdf.h) and libbrdf, run, its output in OUT; 2: no program
run_example3() {
	example3 "$1" >"$T/ex3.c"
	grep -q '^int main' "$T/ex3.c" || return 2
	cc -std=c11 -Wall -Wextra -Werror -I"$T/inc" -I"$ROOT/brdf" "$T/ex3.c" "$ROOT/build/libbrdf.a" -lm -o "$T/ex3" \
		2>"$2" && "$T/ex3" >"$2" 2>&1
}
# check_cff FILE HEADER: YAML, the fields, the version of HEADER
check_cff() {
	v=$(sed -n 's/^#define BK_VERSION "\(.*\)"/\1/p' "$2")
	[ -n "$v" ] || { echo "no BK_VERSION in $2"; return 1; }
	if python3 -c 'import yaml' 2>/dev/null; then
		python3 - "$1" "$v" <<'PY' || return 1
import sys, yaml
c = yaml.safe_load(open(sys.argv[1]))
need = ["cff-version", "message", "title", "version", "authors", "license", "date-released", "abstract", "keywords"]
missing = [k for k in need if k not in c]
if missing: sys.exit("CITATION.cff: missing %s" % ", ".join(missing))
if str(c["version"]) != sys.argv[2]: sys.exit("CITATION.cff: version %s, BK_VERSION %s" % (c["version"], sys.argv[2]))
if str(c["cff-version"]) != "1.2.0" or c["license"] != "MIT": sys.exit("CITATION.cff: cff-version or license")
if not any(a.get("name") for a in c["authors"]): sys.exit("CITATION.cff: no author entity")
PY
	else # no YAML parser: the line the version is on
		grep -qx "version: \"\\{0,1\\}$v\"\\{0,1\\}" "$1" || { echo "CITATION.cff: version is not $v"; return 1; }
	fi
}

# ---- the pages ------------------------------------------------------------------
[ -x "$BK" ] || { bad "no tool at $BK"; # section 3: headers declaring one function more, a page naming one no header
# declares, a page without ERRORS
mkdir -p "$T/more/brdfkit" "$T/man3"
cp -L "$T/inc/brdfkit/"*.h "$T/more/brdfkit/"
printf '#ifdef __cplusplus\nextern "C" {\n#endif\nint bk_zz_undocumented(void);\n#ifdef __cplusplus\n}\n#endif\n' >>"$T/more/brdfkit/catalog.h"
expect_fail "a declared function without a page" check_api "$T/more" "$MAN"
cp "$MAN"/*.3.scd "$T/man3/"
printf '\n*bk_zz_fake*() is not in any header.\n' >>"$T/man3/brdfkit_catalog.3.scd"
expect_fail "a page naming an undeclared function" check_api "$T/inc" "$T/man3"
sed 's/^# ERRORS$/# ERROR/' "$MAN/brdfkit_fit.3.scd" >"$T/man3/brdfkit_fit.3.scd"
expect_fail "a section-3 page without ERRORS" check_page3 "$T/man3/brdfkit_fit.3.scd"
cp "$MAN/brdfkit_fit.3.scd" "$T/man3/brdfkit_zzfake.3.scd"
expect_fail "a section-3 page brdfkit(1) does not name" check_see3 "$T/man3"
sed 's/bk_D_ggx(1, 1)/bk_D_ggx_zz(1, 1)/' "$MAN/brdfkit_brdf.3.scd" >"$T/man3/brdfkit_brdf.3.scd"
expect_fail "an example calling a function no header declares" run_example3 "$T/man3/brdfkit_brdf.3.scd" "$T/ex3.out"

echo "man: $pass passed, $fail failed"; exit 1; }
check_pages "$BK" "$MAN" && ok || bad "a page per command"
check_options "$BK" "$MAN" && ok || bad "every option in its page"
for p in "$MAN"/*.1.scd; do check_page "$p" && ok || bad "page $(basename "$p")"; done
# examples with output: shown as the tool prints it
for p in "$MAN"/*.1.scd; do
	grep -q '^\$ ' "$p" || continue
	README_CONTROLS=0 sh "$ROOT/tests/readme.sh" "$BK" "$p" >"$T/ex.out" 2>&1 && ok || { bad "examples of $(basename "$p")"; cat "$T/ex.out"; }
done
# section 3
n3=0
for p in "$MAN"/*.3.scd; do check_page3 "$p" && ok || bad "page $(basename "$p")"; n3=$((n3 + 1)); done
[ "$n3" -ge 8 ] && ok || bad "$n3 section-3 pages, fewer than the 8 installed headers"
check_see3 "$MAN" && ok || bad "brdfkit(1)'s SEE ALSO and the section-3 pages"
pub_headers && check_api "$T/inc" "$MAN" && ok || bad "the section-3 pages against the installed headers"
# the examples that are whole programs compile and run (libbrdf's); brdfkit_brdf(3)'s
# first number is GGX D at NoH = 1, a = 1 times π: 1
nx=0
for p in "$MAN"/*.3.scd; do
	run_example3 "$p" "$T/ex3.out"
	case $? in 0) ok; nx=$((nx + 1)) ;; 2) ;; *) bad "example of $(basename "$p"): $(head -3 "$T/ex3.out")" ;; esac
done
[ "$nx" -ge 2 ] && ok || bad "$nx section-3 examples compiled and ran, fewer than 2"
# and its second the form in half, as brdfkit eval prints it (5 digits: within
# 1e-4, less than half a half ulp there, 2^-11 relative)
h=$("$BK" eval --quiet 'D_ggx(NoH, a) * p0' NoH=0.9 a=0.25 p0=2 | awk '$1 == "f16" { print $2 }')
run_example3 "$MAN/brdfkit_brdf.3.scd" "$T/ex3.out" &&
	awk -v h="$h" '{ d = $2 - h; if (d < 0) d = -d; exit !($1 == 1 && h != "" && d <= 1e-4 * h) }' "$T/ex3.out" && ok ||
	bad "brdfkit_brdf(3)'s example: $(cat "$T/ex3.out"), brdfkit eval's f16 $h"
check_cff "$ROOT/CITATION.cff" "$ROOT/brdf/brdf.h" && ok || bad "CITATION.cff"
[ -f "$ROOT/LICENSE" ] && grep -q '^MIT License' "$ROOT/LICENSE" && grep -q 'Copyright (c) 2026 the brdfkit developers' "$ROOT/LICENSE" &&
	ok || bad "LICENSE"

# ---- negative controls ----------------------------------------------------------
# a tool with one command more, and one whose dfg prints one option more
cat >"$T/more_cmd" <<EOF
#!/bin/sh
if [ "\$#" -eq 1 ] && [ "\$1" = --help ]; then "$BK" --help | sed 's/^commands:/commands:\n  zzfake   a command without a page/'; exit 0; fi
exec "$BK" "\$@"
EOF
cat >"$T/more_opt" <<EOF
#!/bin/sh
if [ "\$#" -eq 2 ] && [ "\$1" = dfg ] && [ "\$2" = --help ]; then "$BK" dfg --help; echo '  --zzfake-opt N         an option without a line in the page'; exit 0; fi
exec "$BK" "\$@"
EOF
chmod +x "$T/more_cmd" "$T/more_opt"
expect_fail "a command without a page" check_pages "$T/more_cmd" "$MAN"
expect_fail "an option not in the page" check_options "$T/more_opt" "$MAN"
# a page with a request groff does not know, and one without OPTIONS
scdoc <"$MAN/brdfkit-dfg.1.scd" | sed '/^\.SH DESCRIPTION/a .zzbogus request' >"$T/bogus.1"
expect_fail "a roff warning" check_roff "$T/bogus.1"
mkdir "$T/noopt"
sed 's/^# OPTIONS$/# OPTION/' "$MAN/brdfkit-dfg.1.scd" >"$T/noopt/brdfkit-dfg.1.scd"
expect_fail "a page without OPTIONS" check_page "$T/noopt/brdfkit-dfg.1.scd"
# an example whose shown output is off by one digit
awk '/^\$ build\/brdfkit dfg/ { print; getline; print; getline; sub(/[0-9]$/, "x"); print; next } { print }' \
	"$MAN/brdfkit-dfg.1.scd" >"$T/noopt/ex.1.scd"
expect_fail "a wrong example output" env README_CONTROLS=0 sh "$ROOT/tests/readme.sh" "$BK" "$T/noopt/ex.1.scd"
# CITATION.cff of another version, and one that is not YAML
sed 's/^version: .*/version: "9.9.9"/' "$ROOT/CITATION.cff" >"$T/v.cff"
expect_fail "another version" check_cff "$T/v.cff" "$ROOT/brdf/brdf.h"
{ cat "$ROOT/CITATION.cff"; printf 'title: [unclosed\n'; } >"$T/y.cff"
if python3 -c 'import yaml' 2>/dev/null; then expect_fail "not YAML" check_cff "$T/y.cff" "$ROOT/brdf/brdf.h"; fi

echo "man: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
