#!/bin/sh
# layers.sh — the data flow of shared/DESIGN.md, checked on the compiled objects
# (and, at the end, the include walls, checked on the sources):
# brdf/ -> fit/ -> analysis/ -> analysis/cli/ (and analysis/bench/), never
# backwards, and inside each folder no two files that call each other, directly
# or round a longer loop. A call is an undefined symbol of one object that
# another object defines (nm), so a header that merely names a function does
# not count, and a call through a pointer is not seen. Each rule is a function,
# run once more on made-up calls that break it (its negative control).
# usage: sh tests/layers.sh build/obj
set -u
OBJ=${1:?usage: layers.sh build/obj}
T=$(mktemp -d /tmp/bk_layers_XXXXXX)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
finish() {
	echo "layers: $pass passed, $fail failed"
	[ "$fail" -eq 0 ]
	exit
}

# a path with no objects would pass with nothing checked
for d in brdf fit analysis; do
	[ -d "$OBJ/$d" ] || { bad "no $OBJ/$d (build first)"; finish; }
done

# one line per object and symbol: "D obj sym" (defines) or "U obj sym" (uses)
find "$OBJ/brdf" "$OBJ/fit" "$OBJ/analysis" -name '*.o' | sort | while read -r o; do
	nm "$o" | awk -v o="${o#"$OBJ"/}" '
		NF == 3 && $2 ~ /^[TDBR]$/ { print "D", o, $3 }
		NF == 2 && $1 == "U" { print "U", o, $2 }'
done >"$T/syms"

# edges "from to" between objects
awk '
	$1 == "D" { def[$3] = $2 }
	$1 == "U" { n++; uo[n] = $2; us[n] = $3 }
	END { for (i = 1; i <= n; i++) if ((us[i] in def) && def[us[i]] != uo[i]) print uo[i], def[us[i]] }
' "$T/syms" | sort -u >"$T/edges"
n=$(wc -l <"$T/edges")
# every folder calls across objects: fewer than 100 calls means nm read little
[ "$n" -ge 100 ] && ok || { bad "only $n calls between objects found (nm failed?)"; finish; }

# with_flow EDGES: no call against the flow (rank of a folder in it)
with_flow() {
	awk '
		function dir(p) { sub(/\/[^\/]*$/, "", p); return p }
		function rank(d) {
			if (d == "brdf") return 0; if (d == "fit" || d ~ /^fit\//) return 1 # fit/search/: the search layer
			if (d == "analysis") return 2
			return 3 # analysis/cli, analysis/bench: the programs
		}
		rank(dir($2)) > rank(dir($1)) { print "against the flow: " $1 " calls " $2; bad = 1 }
		END { exit bad }' "$1"
}
# no_loop EDGES: no loop inside one folder (depth-first search from every
# object, following calls that stay in its folder)
no_loop() {
	awk '
		function dir(p) { sub(/\/[^\/]*$/, "", p); return p }
		{ from[NR] = $1; adj[$1] = adj[$1] " " $2 }
		END {
			for (i = 1; i <= NR; i++) node[from[i]] = 1
			for (s in node) {
				delete seen; top = 1; stack[1] = s
				while (top > 0) {
					x = stack[top--]; m = split(adj[x], nx, " ")
					for (k = 1; k <= m; k++) {
						y = nx[k]
						if (dir(y) != dir(s)) continue
						if (y == s) { loop[s] = 1; continue }
						if (!(y in seen)) { seen[y] = 1; stack[++top] = y }
					}
				}
			}
			for (s in loop) { print "call loop inside " dir(s) "/ through " s; bad = 1 }
			exit bad
		}' "$1" >"$T/loops"
	rc=$? # awk's verdict, not sort's
	sort "$T/loops"
	return $rc
}

if with_flow "$T/edges" >"$T/why"; then ok; else bad "$(cat "$T/why")"; fi
if no_loop "$T/edges" >"$T/why"; then ok; else bad "$(cat "$T/why")"; fi
# controls: the real calls plus one from brdf/ up into fit/, and plus a loop
# of two files of fit/ (a calls b, b calls a)
{ cat "$T/edges"; echo "brdf/ggx.o fit/fit.o"; } >"$T/up"
if with_flow "$T/up" >/dev/null; then bad "control: a call against the flow passed"; else ok; fi
{ cat "$T/edges"; echo "fit/zz_a.o fit/zz_b.o"; echo "fit/zz_b.o fit/zz_a.o"; } >"$T/loop"
if no_loop "$T/loop" >/dev/null; then bad "control: a loop inside fit/ passed"; else ok; fi
echo "layers: $n calls between objects"

# ---- include walls ------------------------------------------------------------
# Nothing outside a folder includes that folder's internal headers: any
# *_int.h, brdf/ir.h and brdf/dmath.h (the IR's and the libm-free math's
# internals; brdf.h and brdf_ops.h are the public face), and every header of
# fit/search/ that itself includes an internal one (the search's parts:
# search_int.h travels with them). Read from the sources (SRC, the tree's
# root: this script's folder's parent), each quoted include resolved as the
# compiler does: beside the includer, then -Ibrdf -Ifit -Ianalysis. tests/
# is exempt: its tests are white-box on purpose (they include the parts'
# headers and ir.h to check internals); every other folder is checked.
# (The shell finds each include's file; one realpath then writes every path
# found as from the root, "x/../y.h" as "y.h": a cd, pwd, sed, dirname and
# basename for each of the ~500 includes were most of this script's time.)
SRC=$(cd "$(dirname "$0")/.." && pwd)
( cd "$SRC" && find brdf fit analysis -name '*.[ch]' -o -name '*.cc' | sort | while read -r f; do
	sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"\([^"]*\)".*/\1/p' "$f" | while read -r h; do
		for d in "${f%/*}" brdf fit analysis; do
			if [ -f "$d/$h" ]; then
				printf '%s\n' "$f" >>"$T/incl_from"
				printf '%s\n' "$d/$h" >>"$T/incl_to"
				break
			fi
		done
	done
done
[ -s "$T/incl_to" ] && tr '\n' '\0' <"$T/incl_to" | xargs -0 realpath -m -s --relative-to=. >"$T/incl_rel" ) &&
	paste -d ' ' "$T/incl_from" "$T/incl_rel" >"$T/incl"
# internal headers: the rule's names, then headers of fit/search/ including one
{ awk '{ print $2 }' "$T/incl"; } | sort -u | grep -E '(_int\.h$|^brdf/ir\.h$|^brdf/dmath\.h$)' >"$T/internal"
awk 'NR == FNR { internal[$1] = 1; next } $1 ~ /^fit\/search\/.*\.h$/ && ($2 in internal) { print $1 }' \
	"$T/internal" "$T/incl" >>"$T/internal"
# walls INCLUDES INTERNAL: no "includer header" line crossing into another
# folder's internal header
walls() {
	awk '
		function dir(p) { sub(/\/[^\/]*$/, "", p); return p }
		NR == FNR { internal[$1] = 1; next }
		($2 in internal) && dir($1) != dir($2) { print $1 " includes " $2 ", internal to " dir($2) "/"; bad = 1 }
		END { exit bad }' "$2" "$1"
}
ni=$(wc -l <"$T/incl")
[ "$ni" -ge 200 ] && ok || bad "only $ni includes read (sed or find failed?)"
grep -q '^fit/search/archive.h$' "$T/internal" && ok || bad "the search's part headers are not seen as internal"
if walls "$T/incl" "$T/internal" >"$T/why"; then ok; else bad "$(cat "$T/why")"; fi
# controls: a program including fit_int.h, analysis/ including ir.h, and
# analysis/ including a part of the search must each fail
for fake in "analysis/bench/zz.c fit/fit_int.h" "analysis/zz.c brdf/ir.h" "analysis/cli/zz.c fit/search/archive.h" \
	"fit/zz.c brdf/dmath.h"; do
	{ cat "$T/incl"; echo "$fake"; } >"$T/fake"
	if walls "$T/fake" "$T/internal" >/dev/null; then bad "control: $fake passed"; else ok; fi
done
echo "layers: $ni includes"
finish
