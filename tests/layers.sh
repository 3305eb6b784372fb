#!/bin/sh
# layers.sh — the data flow of DESIGN.md, checked on the compiled objects:
# brdf/ -> fit/ -> analysis/ -> analysis/cli/ (and analysis/bench/), never
# backwards, and inside each folder no two files that call each other, directly
# or round a longer loop. A call is an undefined symbol of one object that
# another object defines (nm), so a header that merely names a function does
# not count, and a call through a pointer is not seen.
# usage: sh tests/layers.sh build/obj
set -u
OBJ=${1:?usage: layers.sh build/obj}
T=$(mktemp -d /tmp/bk_layers_XXXXXX)
trap 'rm -rf "$T"' EXIT

# a path with no objects would pass with nothing checked
for d in brdf fit analysis; do
	[ -d "$OBJ/$d" ] || { echo "layers: no $OBJ/$d (build first)"; exit 1; }
done

# one line per object and symbol: "D obj sym" (defines) or "U obj sym" (uses)
find "$OBJ/brdf" "$OBJ/fit" "$OBJ/analysis" -name '*.o' | sort | while read -r o; do
	nm "$o" | awk -v o="${o#"$OBJ"/}" '
		NF == 3 && $2 ~ /^[TDBR]$/ { print "D", o, $3 }
		NF == 2 && $1 == "U" { print "U", o, $2 }'
done >"$T/syms"

# edges "from to" between objects; rank of a folder in the flow
awk '
	$1 == "D" { def[$3] = $2 }
	$1 == "U" { n++; uo[n] = $2; us[n] = $3 }
	END { for (i = 1; i <= n; i++) if ((us[i] in def) && def[us[i]] != uo[i]) print uo[i], def[us[i]] }
' "$T/syms" | sort -u >"$T/edges"
[ -s "$T/edges" ] || { echo "layers: no calls between objects found (nm failed?)"; exit 1; }

awk '
	function dir(p) { sub(/\/[^\/]*$/, "", p); return p }
	function rank(d) {
		if (d == "brdf") return 0; if (d == "fit") return 1; if (d == "analysis") return 2
		return 3 # analysis/cli, analysis/bench: the programs
	}
	{ from[NR] = $1; to[NR] = $2; adj[$1] = adj[$1] " " $2 }
	END {
		bad = 0
		for (i = 1; i <= NR; i++)
			if (rank(dir(to[i])) > rank(dir(from[i]))) {
				print "against the flow: " from[i] " calls " to[i]; bad = 1
			}
		# a loop inside one folder: depth-first search from every object,
		# following edges that stay in its folder
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
	}
' "$T/edges" >"$T/report"
rc=$?
n=$(wc -l <"$T/edges")
if [ "$rc" -ne 0 ]; then
	sort "$T/report"
	echo "layers: FAILED ($n calls between objects)"
	exit 1
fi
echo "layers: $n calls between objects, all with the flow, no loop inside a folder"
