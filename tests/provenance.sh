#!/bin/sh
# provenance.sh — every CSV brdfkit wrote under results/ opens with its
# provenance (issue 42 item 1: one writer, analysis/prov.c): the first line
# "# brdfkit VERSION WHAT", and among the comment lines before the column
# names "# command: brdfkit ...", the command that wrote it. Controls: a CSV
# without the command line, and one whose first line is not brdfkit's, are
# each caught.
# usage: sh tests/provenance.sh   (from anywhere; reads the committed results/)
set -u
ROOT=$(cd "$(dirname "$0")/.." && pwd)
cd "$ROOT" || exit 1
T=$(mktemp -d /tmp/bk_provenance_XXXXXX)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }

# lacks FILE: prints what FILE's header lacks, nothing when it has both lines
# (a table one of the project's scripts wrote, its first line "# NAME.py: ",
# as fronts_ab.py's, is that script's: not brdfkit's to sign)
lacks() {
	awk 'NR == 1 && /^# [a-z_]+\.py: / { exit }
	     NR == 1 && !/^# brdfkit [0-9]/ { print "first line is not # brdfkit VERSION: " substr($0, 1, 60); bad = 1 }
	     !/^#/ { exit }
	     /^# command: brdfkit / { cmd = 1 }
	     END { if (!cmd && !bad && NR > 1) print "no # command: brdfkit line before the columns" }' "$1"
}

git ls-files 'results/*.csv' 2>/dev/null >"$T/list" || find results -name '*.csv' >"$T/list"
n=$(wc -l <"$T/list")
[ "$n" -ge 50 ] && ok || bad "only $n CSVs under results/: is make results' output committed?"
while IFS= read -r f; do
	why=$(lacks "$f")
	[ -z "$why" ] || echo "$f: $why"
done <"$T/list" >"$T/missing"
[ ! -s "$T/missing" ] && ok || { bad "CSVs without their provenance:"; head -20 "$T/missing"; }

# controls
printf '# brdfkit 0.1.0 a table\nx,y\n1,2\n' >"$T/nocmd.csv"
printf 'x,y\n# command: brdfkit x\n1,2\n' >"$T/nohead.csv"
printf '# brdfkit 0.1.0 a table\n# command: brdfkit fit --out o\nx,y\n' >"$T/good.csv"
[ -n "$(lacks "$T/nocmd.csv")" ] && ok || bad "control: a CSV without # command: passed"
[ -n "$(lacks "$T/nohead.csv")" ] && ok || bad "control: a CSV without the # brdfkit line passed"
[ -z "$(lacks "$T/good.csv")" ] && ok || bad "control: a CSV with both lines was refused: $(lacks "$T/good.csv")"

echo "provenance: $n CSVs; $pass passed, $fail failed"
[ "$fail" -eq 0 ]
