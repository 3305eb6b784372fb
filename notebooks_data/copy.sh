#!/bin/sh
# copy.sh — the one rule that fills notebooks_data/ from results/ (make notebooks-data).
#
#   sh notebooks_data/copy.sh DIR < LIST
#
# LIST: one "SOURCE NAME" pair a line (SOURCE a CSV of results/, NAME a plain
# name: letters, digits, '_', '-'). For each pair it writes into DIR
#   NAME.csv       SOURCE without its comment lines (those starting with '#'):
#                  a header line and the data rows, which plain
#                  pandas.read_csv(path) loads;
#   NAME.meta.txt  a first line "source: SOURCE", then SOURCE's comment lines
#                  byte for byte (provenance: the command; conventions and units),
#                  or "(no comment lines)" when it has none.
# So `grep '^#' NAME.meta.txt; cat NAME.csv` gives SOURCE back.
#
# Whole or nothing: every pair is written into a scratch directory inside DIR
# first; only when all of them succeeded are DIR's old *.csv and *.meta.txt
# removed and the new ones moved in (a missing source leaves DIR as it was).
# results/ is only read.
set -eu
[ $# -eq 1 ] || { echo "usage: sh notebooks_data/copy.sh DIR < LIST" >&2; exit 2; }
dir=$1
[ -d "$dir" ] || { echo "notebooks-data: $dir: not a directory" >&2; exit 1; }
tmp=$(mktemp -d "$dir/.copy.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
trap 'exit 130' INT TERM  # (dash runs the EXIT trap on exit, not on a signal)
n=0
while read -r src name rest; do
	[ -n "$src" ] || continue
	[ -z "$rest" ] || { echo "notebooks-data: a line with more than two fields: $src $name $rest" >&2; exit 1; }
	case $name in
	''|*[!A-Za-z0-9_-]*) echo "notebooks-data: $src: bad name '$name'" >&2; exit 1 ;;
	esac
	[ -f "$src" ] || { echo "notebooks-data: $src: no such file (run make results first)" >&2; exit 1; }
	[ ! -e "$tmp/$name.csv" ] || { echo "notebooks-data: $name.csv: named twice" >&2; exit 1; }
	# comment lines are the leading ones (brdfkit writes them before the header);
	# one after the header would be a data row pandas cannot read: refuse it
	awk -v src="$src" -v csv="$tmp/$name.csv" -v meta="$tmp/$name.meta.txt" '
		BEGIN { print "source: " src > meta; c = 0; d = 0 }
		/^#/ { if (d) { printf "notebooks-data: %s:%d: a comment line after the header\n", src, NR > "/dev/stderr"; exit 1 }
		       print > meta; c++; next }
		{ d = 1; print > csv }
		END { if (!d) { printf "notebooks-data: %s: no header line\n", src > "/dev/stderr"; exit 1 }
		      if (!c) print "(no comment lines)" > meta }' "$src"
	n=$((n + 1))
done
[ "$n" -gt 0 ] || { echo "notebooks-data: no files listed" >&2; exit 1; }
rm -f "$dir"/*.csv "$dir"/*.meta.txt
mv "$tmp"/*.csv "$tmp"/*.meta.txt "$dir"/
echo "notebooks-data: $n CSV files and their .meta.txt into $dir"
