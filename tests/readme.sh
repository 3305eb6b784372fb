#!/bin/sh
# readme.sh — the README's examples are tests: every fenced block of README.md
# that holds a line starting with "$ " is run, command by command, and what
# each command prints must be the output the block shows under it, after the
# normalisation below. (README.md, "Contributing", says the same for authors.)
# usage: sh tests/readme.sh path/to/brdfkit [README.md]
# (tests/man.sh runs it on the manual pages' sources, analysis/man/*.scd, too:
# scdoc's literal blocks are the same fences; messages name the file read.)
#
# How a block is read
#   - "$ CMD" starts a command; a line ending in a backslash continues it on the
#     next line (as in sh). Every line up to the next "$ " line or the end of the
#     block is that command's shown output (none: it must print nothing).
#   - A block whose first line is not a "$ " line is an error (output of what?).
#   - Blocks without a "$ " line (commands alone, JSON, tables) are not run.
#
# How it is run
#   - Each command with sh, stdin /dev/null, stdout and stderr to one file, as a
#     log captures them (CMD >log 2>&1: stderr unbuffered, stdout buffered, so a
#     command's progress lines come before its stdout). On a terminal the
#     progress lines are redrawn in place instead: the README shows the log.
#   - The commands of a block run in order in one fresh scratch directory per
#     block, so later commands see what earlier ones wrote; a block needing state
#     (a directory, a file) must create it with a "$ " line the reader sees. The
#     scratch directory holds build/brdfkit (a link to the tool under test) and
#     analysis/ (a link to the repository's, for the example scene files).
#   - The exit status is not compared (the README does not show it); a failing
#     comparison reports it.
#
# Markers
#   <!-- readme-test: skip REASON -->   on the line right before the opening
#        fence: the block is not run; REASON is printed. For commands of minutes
#        (make results' searches); keep these few. Any other "<!-- readme-test:"
#        line, or a marker not right before a fence, is an error.
#   A shown output line that is exactly "..." stands for any number of lines
#   (zero included): the example is abbreviated there. Other lines match whole.
#
# Normalisation, applied to the shown and the actual output alike
#   1. the scratch directory's absolute path becomes "." (actual output only)
#   2. a progress line printed while a stage runs, "LABEL: N/M (P %, T s)",
#      is dropped (a log gets one at 1 s and every 10 % or 10 s: it depends on
#      the machine); the line that ends the stage, "LABEL: N/M done", stays
#   3. a search status line ("search: N fits, R fits/s, ...", printed every
#      10 s and at the end) followed directly by another is dropped: the last
#      stays
#   4. a duration or rate, a number followed by " s", " ms", " us", " µs",
#      " ns" or " fits/s", becomes "<time> s" etc.
#   5. trailing blanks are dropped
# Nothing else: every other byte must match.
#
# Prints one "FAIL: README.md:LINE: ..." per differing command with a unified
# diff (shown output first, actual second), "skip: ..." per skipped block, and
# ends with the plain line "readme: N passed, M failed" (N, M count commands);
# exits non-zero on any failure. README_TIMES=1 prints each command's seconds.
set -u
BK=${1:?usage: readme.sh path/to/brdfkit [README.md]}
README=${2:-README.md}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
case $BK in /*) ;; *) BK=$PWD/$BK ;; esac
case $README in /*) ;; *) README=$PWD/$README ;; esac
NAME=$(basename "$README")
T=$(mktemp -d /tmp/bk_readme_XXXXXX)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0 skipped=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); printf "FAIL: %s\n" "$*"; }

[ -x "$BK" ] || { bad "no tool at $BK"; echo "readme: $pass passed, $fail failed"; exit 1; }
[ -r "$README" ] || { bad "no README at $README"; echo "readme: $pass passed, $fail failed"; exit 1; }

# ---- the examples, one directory per block -----------------------------------------
# $T/ex/NNNN/meta: "LINE skip|run REASON"; NNNN/K.cmd, K.exp, K.line per command.
mkdir "$T/ex"
awk -v dir="$T/ex" '
function flush(   i, k, line, cmd, d, out, nl) {
	has = 0
	for (i = 1; i <= n; i++) if (L[i] ~ /^\$ /) has = 1
	if (!has) return
	nb++
	d = sprintf("%s/%04d", dir, nb)
	system("mkdir " d)
	if (L[1] !~ /^\$ /) { print open " error output before the first command" > (d "/meta"); return }
	print open " " (marker == "" ? "run" : marker) > (d "/meta"); close(d "/meta")
	k = 0
	for (i = 1; i <= n; ) {
		k++; cmd = substr(L[i], 3); nl = LN[i]; i++
		while (cmd ~ /\\$/ && i <= n) { cmd = cmd "\n" L[i]; i++ }
		print cmd > (d "/" k ".cmd"); close(d "/" k ".cmd")
		print nl > (d "/" k ".line"); close(d "/" k ".line")
		out = d "/" k ".exp"; printf "" > out
		while (i <= n && L[i] !~ /^\$ /) { print L[i] > out; i++ }
		close(out)
	}
}
/^```/ {
	if (inb) { flush(); inb = 0; marker = ""; prev = ""; next }
	inb = 1; n = 0; open = NR
	marker = (prev ~ /^<!-- readme-test: .* -->$/) ? prev : ""
	sub(/^<!-- readme-test: /, "", marker); sub(/ -->$/, "", marker)
	prev = ""
	next
}
inb { n++; L[n] = $0; LN[n] = NR; next }
{ if ($0 ~ /^<!-- readme-test:/ && $0 !~ /^<!-- readme-test: skip .+ -->$/) print NR " " $0 > (dir "/bad_markers") }
{ if (prev ~ /^<!-- readme-test:/) print (NR - 1) " a marker not right before a fence" > (dir "/bad_markers"); prev = $0 }
END { if (inb) print "unclosed fence at line " open > (dir "/bad_markers") }
' "$README"
if [ -s "$T/ex/bad_markers" ]; then
	while read -r l; do bad "$NAME:$l: not a marker readme.sh knows (<!-- readme-test: skip REASON -->)"; done <"$T/ex/bad_markers"
fi
nblocks=$(ls "$T/ex" | grep -c '^[0-9]')
[ "$nblocks" -gt 0 ] || bad "no example block found in $README"

# norm FILE: FILE after the normalisation of the header, to stdout
norm() {
	sed -e "s|$S/|./|g; s|$S|.|g" "$1" | awk '
	# a progress line while a stage runs (printed by time: 1 s in, then every
	# 10 % or 10 s); the line that ends the stage ("LABEL: N/N done") stays
	/^[^ ].*: [0-9]+\/[0-9]+ \([0-9]+ %, [0-9]+ s\)$/ { next }
	# the search status line, printed every 10 s and at the end: of two in a
	# row only the second (the last) stays
	/^search: [0-9]+ fits, [0-9.e+]+ fits\/s, / { held = $0; next }
	{ if (held != "") print held; held = ""; print }
	END { if (held != "") print held }' |
		sed -e 's/[0-9][0-9.e+-]* \(s\|ms\|us\|µs\|ns\|fits\/s\)\([^A-Za-z0-9_]\|$\)/<time> \1\2/g' \
			-e 's/[[:space:]]*$//'
}

# glob_match EXP ACT: true when ACT matches EXP, a line "..." in EXP matching
# any run of lines (segments between them matched in order, the first at the
# start unless EXP opens with "...", the last at the end unless it closes with it)
glob_match() {
	awk 'NR == FNR { e[++m] = $0; next } { a[++n] = $0 }
	function seg_at(s, len, p,   j) { for (j = 0; j < len; j++) if (e[s + j] != a[p + j]) return 0; return 1 }
	END {
		i = 1; p = 1
		while (i <= m) {
			if (e[i] == "...") { i++; continue }
			s = i; while (i <= m && e[i] != "...") i++
			len = i - s; lead = (s > 1); tail = (i <= m)
			if (!lead && !tail) exit !(n == len && seg_at(s, len, 1))
			if (!lead) { if (!(len <= n && seg_at(s, len, 1))) exit 1; p = len + 1; continue }
			if (!tail) { q = n - len + 1; exit !(q >= p && seg_at(s, len, q)) }
			for (q = p; q + len - 1 <= n; q++) if (seg_at(s, len, q)) break
			if (q + len - 1 > n) exit 1
			p = q + len
		}
		exit !(m == 0 ? n == 0 : 1)
	}' "$1" "$2"
}

# the comparison's own controls: lines it must accept and lines it must refuse
# same SHOWN ACTUAL: the comparison of one command (printf-style \n in both)
same() {
	S=/nonexistent
	printf "$1" >"$T/c_want.raw"; printf "$2" >"$T/c_act.raw"
	norm "$T/c_want.raw" >"$T/c_want"; norm "$T/c_act.raw" >"$T/c_act"
	glob_match "$T/c_want" "$T/c_act"
}
# (README_CONTROLS=0 skips them: tests/man.sh, which runs this script once per
# manual page after make test has run it on README.md with them)
ctl() { [ "${README_CONTROLS:-1}" = 0 ] && return 0; if same "$2" "$3"; then [ "$1" = pass ] && ok || bad "control: '$2' matched '$3'"
	else [ "$1" = fail ] && ok || bad "control: '$2' did not match '$3'"; fi; }
ctl pass 'a\nb\n' 'a\nb\n'
ctl fail 'a\nb\n' 'a\nc\n'
ctl fail 'a\n' 'a\nb\n'
ctl fail 'a\nb\n' 'a\n'
ctl fail 'a\n' ''
ctl pass '' ''
ctl pass 'a\n...\nd\n' 'a\nb\nc\nd\n'
ctl pass 'a\n...\nd\n' 'a\nd\n'
ctl fail 'a\n...\nd\n' 'a\nb\nc\n'
ctl fail 'a\n...\nd\n' 'x\na\nd\n'
ctl pass '...\nc\n...\n' 'a\nb\nc\nd\n'
ctl fail '...\nc\n...\n' 'a\nb\nd\n'
ctl pass '...\n' ''
ctl pass 'took 0.02 s, 6.95 ns\n' 'took 1.5 s, 12 ns\n'
ctl fail 'took 0.02 s\n' 'took 0.02 x\n'
ctl pass 'r: 3/3 done\n' 'r: 1/3 (33 %%, 1 s)\nr: 3/3 done\n'
ctl fail 'r: 3/3 done\n' 'r: 2/3 done\n'
ctl pass 'search: 9 fits, 5 fits/s, front 1 (x)\n' 'search: 5 fits, 1 fits/s, front 1 (y)\nsearch: 9 fits, 7 fits/s, front 1 (x)\n'
ctl fail 'search: 9 fits, 5 fits/s, front 1 (x)\n' 'search: 8 fits, 7 fits/s, front 1 (x)\n'

for b in "$T"/ex/[0-9]*; do
	read -r open mode reason <"$b/meta"
	if [ "$mode" = error ]; then bad "$NAME:$open: $reason"; continue; fi
	if [ "$mode" = skip ]; then
		skipped=$((skipped + 1))
		echo "skip: $NAME:$open: $reason"
		continue
	fi
	S="$T/run$(basename "$b")"
	mkdir -p "$S/build"
	ln -s "$BK" "$S/build/brdfkit"
	ln -s "$ROOT/analysis" "$S/analysis"
	k=1
	while [ -e "$b/$k.cmd" ]; do
		line=$(cat "$b/$k.line")
		t0=$(date +%s)
		(cd "$S" && sh "$b/$k.cmd") >"$b/$k.raw" 2>&1 </dev/null
		rc=$?
		[ -z "${README_TIMES:-}" ] || echo "time: $NAME:$line: $(($(date +%s) - t0)) s"
		norm "$b/$k.raw" >"$b/$k.act"
		norm "$b/$k.exp" >"$b/$k.want"
		if glob_match "$b/$k.want" "$b/$k.act"; then ok
		else
			bad "$NAME:$line: \$ $(head -1 "$b/$k.cmd") (exit $rc): the output differs from the README's"
			diff -u --label "$NAME:$line (shown)" --label "actual" "$b/$k.want" "$b/$k.act" | sed 's/^/    /'
		fi
		k=$((k + 1))
	done
done

[ "$skipped" -eq 0 ] || echo "readme: $skipped blocks skipped by a marker"
echo "readme: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
