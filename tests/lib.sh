# lib.sh — helpers the shell tests share (POSIX sh; source it after setting T,
# the test's scratch directory, and CSVGET, the path of build/csvget).
#
# CSV files are read by column NAME through build/csvget (tests/tools/csvget.c,
# libcsv): comment lines are skipped, quoting is honoured, and a missing file,
# column or data row fails loudly, so a check can never pass on nothing read.

: "${CSVGET:=build/csvget}"

# csv_col FILE NAME: column NAME of every data row, one a line.
csv_col() { "$CSVGET" "$1" "$2"; }

# csv_where FILE KEY VALUE NAME: column NAME of the rows whose KEY is VALUE.
csv_where() { "$CSVGET" "$1" "$4" "$2" "$3"; }

# csv_min FILE NAME: the smallest number in column NAME (empty fields skipped;
# fails when no field is a number).
csv_min() {
	csv_col "$1" "$2" >"${T:?}/.csv_min" || return 1
	awk 'BEGIN { n = 0 } $0 != "" { x = $0 + 0; if (!n || x < m) m = x; n++ }
	     END { if (!n) { print "csv_min: no number in column" > "/dev/stderr"; exit 1 } printf "%.17g\n", m }' \
		"$T/.csv_min"
}

# csv_any_le FILE NAME BOUND: true when some row's NAME is a number <= BOUND.
csv_any_le() {
	m=$(csv_min "$1" "$2") || return 1
	awk -v m="$m" -v b="$3" 'BEGIN { exit !(m + 0 <= b + 0) }'
}
