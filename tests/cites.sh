#!/bin/sh
# cites.sh — every file a comment or a document cites exists (issue 42 item 5).
# Read: the comments of the tracked sources (C, C++, shell, Python, the
# Makefile) and the whole of the documents (Markdown, the manual pages'
# scdoc). A citation is a path under one of the tree's folders ending in a file
# extension (brdf/ir_eval.c, tests/lib.sh, results/albedo.csv), or a bare
# document name (README.md). Placeholders are not citations: a name with a
# word in capitals (tests/test_NAME.c, results/search/DIR/front.csv), a glob,
# a scratch name (zz). The project's shared documents (shared/DESIGN.md,
# shared/STYLE.md, shared/references/*.md) live outside the repository, in the shared/ folder beside
# it (BRDFKIT_SHARED to name another): cite them as shared/DESIGN.md,
# shared/references/toolchain.md; where that folder is absent (a clone alone)
# those citations are counted and said to be unchecked.
# usage: sh tests/cites.sh   (from anywhere)
set -u
ROOT=$(cd "$(dirname "$0")/.." && pwd)
cd "$ROOT" || exit 1
T=$(mktemp -d /tmp/bk_cites_XXXXXX)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
SHARED=${BRDFKIT_SHARED:-$ROOT/../shared}
# tracked: the tree's files (git's list; outside a git checkout, every file but build/)
tracked() { git ls-files 2>/dev/null || find . -path ./build -prune -o -type f -print | sed 's|^\./||'; }

# cites FILE...: "FILE: PATH" for every citation in the text of FILE a
# reader takes as prose (its comments, or all of a document), in one awk for
# every file (a pipeline of five processes a file was 40 CPU s of make test).
# A line's citations are found as grep -oE finds them, left to right, each
# match taking the character that ends it ("a.c b.c" in brdf/ gives one).
cites() {
	[ $# -gt 0 ] || return 0
	awk '
function cite(s,   pre, r, m) {
	# the citation pattern, its leading and trailing separators included
	r = "(^|[^A-Za-z0-9_./-])((shared|brdf|fit|analysis|tests|results|notebooks_data|\\.ci)/[A-Za-z0-9_./-]*\\.(c|h|cc|sh|py|md|scd|supp|ipynb|csv|exr|json|html)|[A-Za-z][A-Za-z0-9_-]*\\.md)([^A-Za-z0-9_*]|$)"
	pre = "" # past a match, ^ is not the line start: "/" neither starts a path nor separates
	while (match(pre s, r)) {
		m = substr(pre s, RSTART, RLENGTH)
		s = substr(pre s, RSTART + RLENGTH); pre = "/"
		sub(/^[^A-Za-z.]/, "", m); sub(/[^A-Za-z0-9_]$/, "", m)
		if (m ~ /zz|\*/ || m ~ /\/[A-Z]+\//) continue
		if (m ~ /\// && m !~ /\.md$/ && m ~ /[A-Z][A-Z][A-Z]/) continue
		print FILENAME ": " m
	}
}
FILENAME ~ /\.(md|scd)$/ { cite($0); next }
FILENAME ~ /\.(c|h|cc)$/ { if ($0 ~ /\/\*|^[[:space:]]*\*|\/\//) cite($0); next }
{ # the rest: shell, Python, the Makefile: after a # that opens the line, else after the last " # "
	if (match($0, /^[[:space:]]*#/)) cite(substr($0, RLENGTH + 1))
	else if (match($0, /^.*[[:space:]]#[[:space:]]/)) cite(substr($0, RLENGTH + 1))
}' "$@" | LC_ALL=C sort -u
}

# missing_in LIST: of the citations in LIST (cites' lines), those of a file
# that does not exist (a bare *.md: no tracked file of that name); shared/
# ones are checked where the shared folder is, else written to $T/unchecked
missing_in() {
	while IFS= read -r line; do
		f=${line%%: *} p=${line#*: }
		case $p in
		shared/*) if [ -d "$SHARED" ]; then [ -e "$SHARED/${p#shared/}" ] || echo "$f: $p"; else echo "$line" >>"$T/unchecked"; fi ;;
		*/*) [ -e "$p" ] || echo "$f: $p" ;;
		*) grep -q "\(^\|/\)$p\$" "$T/tracked" || echo "$f: $p (no file of that name in the tree; the shared documents are cited as shared/$p or shared/references/$p)" ;;
		esac
	done <"$1"
}
# missing FILE...: missing_in of FILE's own citations
missing() {
	cites "$@" >"$T/cites" || return 0
	missing_in "$T/cites"
}

tracked >"$T/tracked"
grep -E '\.(c|h|cc|sh|py|md|scd|supp)$|(^|/)Makefile$' "$T/tracked" >"$T/files"
[ -s "$T/files" ] && ok || bad "no files found in $ROOT"
# shellcheck disable=SC2046 # tracked paths hold no blanks
cites $(cat "$T/files") >"$T/all"
missing_in "$T/all" >"$T/missing"
[ ! -s "$T/missing" ] && ok || { bad "citations of files that do not exist:"; cat "$T/missing"; }
n=$(wc -l <"$T/all")
[ "$n" -ge 100 ] && ok || bad "only $n citations found: the reader is broken"
[ -s "$T/unchecked" ] && echo "cites: no shared folder at $SHARED: $(wc -l <"$T/unchecked") citations of shared/ not checked"

# controls: a comment citing a file that is not there, a bare document that is
# not in the tree, and a shared document that is not in the shared folder, must
# each be found; a placeholder must not
mkdir -p "$T/c"
printf '/* see brdf/no_such_file.c for why */\nint x;\n' >"$T/c/a.c"
printf '# as NOSUCHDOC.md says\n' >"$T/c/b.sh"
printf 'the [style](tests/test_NAME.c) and tests/lib.sh\n' >"$T/c/d.md"
missing "$T/c/a.c" | grep -q 'brdf/no_such_file.c$' && ok || bad "control: a missing C citation not found"
missing "$T/c/b.sh" | grep -q 'NOSUCHDOC.md' && ok || bad "control: a missing document not found"
[ -z "$(missing "$T/c/d.md")" ] && [ "$(cites "$T/c/d.md" | wc -l)" -eq 1 ] && ok || bad "control: a placeholder taken for a citation"
if [ -d "$SHARED" ]; then
	printf '/* shared/references/no_such_reference.md */\n' >"$T/c/e.h"
	missing "$T/c/e.h" | grep -q 'no_such_reference.md$' && ok || bad "control: a missing shared document not found"
fi

echo "cites: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
