# lib.sh — helpers the shell tests share (POSIX sh; source it after setting T,
# the test's scratch directory, and CSVGET, the path of build/csvget).
#
# CSV files are read by column NAME through build/csvget (tests/tools/csvget.c,
# libcsv): comment lines are skipped, quoting is honoured, and a missing file,
# column or data row fails loudly, so a check can never pass on nothing read.

: "${CSVGET:=build/csvget}"

# one_line FILE TEXT: FILE holds one line (one line break, as wc -l counts)
# and it holds TEXT (a string, not a pattern). The shell's read and case, no
# process: the scripts check thousands of refusals so.
one_line() {
	_n=0 _l=
	while IFS= read -r _x; do _n=$((_n + 1)) _l=$_x; done <"$1"
	[ $_n -eq 1 ] || return 1
	case $_l in *"$2"*) return 0 ;; esac
	return 1
}

# csv_col FILE NAME: column NAME of every data row, one a line.
csv_col() { "$CSVGET" "$1" "$2"; }

# csv_where FILE KEY VALUE NAME: column NAME of the rows whose KEY is VALUE.
csv_where() { "$CSVGET" "$1" "$4" "$2" "$3"; }

# csv_min FILE NAME: the smallest number in column NAME (empty fields skipped;
# fails when no field is a number, and on a field that is not one: "nan", a
# word, "0x1" would otherwise read as 0, the smallest error of all).
csv_min() {
	csv_col "$1" "$2" >"${T:?}/.csv_min" || return 1
	awk -v f="$1" -v c="$2" 'BEGIN { n = 0 }
	     $0 == "" { next }
	     $0 !~ /^[-+]?([0-9]+[.]?[0-9]*|[.][0-9]+)([eE][-+]?[0-9]+)?$/ && $0 !~ /^[-+]?inf$/ {
	         printf "csv_min: %s: column %s: \047%s\047 is not a number\n", f, c, $0 > "/dev/stderr"; bad = 1; exit 1 }
	     { x = $0 + 0; if (!n || x < m) m = x; n++ }
	     END { if (bad) exit 1
	           if (!n) { printf "csv_min: %s: no number in column %s\n", f, c > "/dev/stderr"; exit 1 }
	           printf "%.17g\n", m }' "$T/.csv_min"
}

# csv_any_le FILE NAME BOUND: true when some row's NAME is a number <= BOUND.
csv_any_le() {
	_lib_m=$(csv_min "$1" "$2") || return 1
	awk -v m="$_lib_m" -v b="$3" 'BEGIN { exit !(m + 0 <= b + 0) }'
}

# csv_cols FILE NAME...: the named columns of every data row, tab-separated
# (fails as csv_col does, and when a field holds a tab or a line break and the
# columns would no longer pair up).
csv_cols() {
	_lib_f=$1; shift
	_lib_i=0; _lib_n=""
	for _lib_c in "$@"; do
		_lib_i=$((_lib_i + 1))
		csv_col "$_lib_f" "$_lib_c" >"${T:?}/.csv_c$_lib_i" || return 1
		if grep -q "$(printf '\t')" "$T/.csv_c$_lib_i"; then echo "csv_cols: $_lib_f: a tab in column $_lib_c" >&2; return 1; fi
		_lib_l=$(wc -l <"$T/.csv_c$_lib_i")
		[ -z "$_lib_n" ] || [ "$_lib_l" -eq "$_lib_n" ] || { echo "csv_cols: $_lib_f: a field spans lines" >&2; return 1; }
		_lib_n=$_lib_l
	done
	_lib_j=1; _lib_files=""
	while [ $_lib_j -le $_lib_i ]; do _lib_files="$_lib_files $T/.csv_c$_lib_j"; _lib_j=$((_lib_j + 1)); done
	# shellcheck disable=SC2086 # the scratch paths hold no blanks (mktemp)
	paste $_lib_files
}

# Negative controls: a copy of FILE that a check must refuse, on stdout.
# csv_set FILE NAME KEY VALUE NEW: NAME set to NEW in the rows whose KEY is VALUE.
# csv_drop FILE KEY VALUE: without the rows whose KEY is VALUE.
# Both fail (exit 1) when the column or the row is not there.
csv_set() { "$CSVGET" --set "$@"; }
csv_drop() { "$CSVGET" --drop "$@"; }
# until_lines N SECS ERR CMD...: runs CMD (stdout to /dev/null, stderr to ERR)
# until ERR holds N whole lines or SECS seconds pass, then stops it (SIGTERM)
# if it still runs; returns 124 when it had to be stopped (as timeout(1)
# does), else CMD's own status. For work that would run for minutes and is
# checked by what it says first (its estimate, its warning): waiting out a
# fixed timeout burnt its CPU seconds for nothing once the lines were there.
until_lines() {
	_lib_n=$1 _lib_k=$(($2 * 20)) _lib_err=$3; shift 3
	# emptied here, not only by CMD's redirection: the loop may test ERR
	# before the child has opened it, and an ERR left by an earlier command
	# would count (its lines seen, CMD stopped before it wrote a line)
	: >"$_lib_err"
	"$@" >/dev/null 2>"$_lib_err" &
	_lib_pid=$!
	while [ "$_lib_k" -gt 0 ] && kill -0 "$_lib_pid" 2>/dev/null &&
		[ "$(wc -l <"$_lib_err")" -lt "$_lib_n" ]; do
		sleep 0.05
		_lib_k=$((_lib_k - 1))
	done
	if kill -0 "$_lib_pid" 2>/dev/null; then
		kill "$_lib_pid" 2>/dev/null
		wait "$_lib_pid"
		return 124
	fi
	wait "$_lib_pid"
}

# same_but_command A B: the two files are the same bytes but for their
# "# command:" lines (two runs of one computation typed differently)
same_but_command() {
	[ -s "$1" ] && [ -s "$2" ] && grep -v '^# command: ' "$1" >"$1.nc" && grep -v '^# command: ' "$2" >"$2.nc" &&
		cmp -s "$1.nc" "$2.nc"
}

# expect_fail NAME CHECK ARGS...: the negative control of a check: CHECK (a
# shell function, the very one the test runs) must fail on ARGS. Counts with
# the caller's ok/bad. (Variables here are _lib_*: functions share the
# caller's globals.)
expect_fail() {
	_lib_name=$1; shift
	if "$@" >/dev/null 2>&1; then bad "control $_lib_name: the check passed on an input it must refuse"; else ok; fi
}

# ---- a search's answer, checked outside the search ---------------------------------
# The search's own rmse is a claim; these re-evaluate a front member with
# `brdfkit eval` at points of the domain and compare with the target computed
# here in awk, an independent closed form.

# form_matches BK FORM PARAMS TARGET_AWK POINTS...: FORM with PARAMS
# ("p0=..;p1=.." as front.csv writes them) evaluates in f64 to the awk
# expression TARGET_AWK (of x = LoH and r) within 1e-12 relative at every POINT
# "LoH,r" (a = r^2 follows from r; an input the form does not read is not given).
form_matches() {
	_lib_bk=$1 _lib_form=$2 _lib_pars=$(echo "$3" | tr ';' ' ') _lib_target=$4; shift 4
	for _lib_pt in "$@"; do
		_lib_x=${_lib_pt%,*} _lib_r=${_lib_pt#*,} _lib_ins=""
		case $_lib_form in *LoH*) _lib_ins="LoH=$_lib_x" ;; esac
		if echo "$_lib_form" | grep -q '\(^\|[^A-Za-z0-9_]\)r\([^A-Za-z0-9_(]\|$\)'; then _lib_ins="$_lib_ins r=$_lib_r"
		elif echo "$_lib_form" | grep -q '\(^\|[^A-Za-z0-9_]\)a\([^A-Za-z0-9_(]\|$\)'; then
			_lib_ins="$_lib_ins a=$(awk -v r="$_lib_r" 'BEGIN { printf "%.17g", r * r }')"
		fi
		# shellcheck disable=SC2086 # parameters and inputs are words NAME=VALUE
		_lib_v=$("$_lib_bk" eval "$_lib_form" $_lib_pars $_lib_ins 2>/dev/null | sed -n 's/^f64 //p')
		awk -v v="$_lib_v" -v x="$_lib_x" -v r="$_lib_r" "BEGIN { w = $_lib_target
			if (v !~ /^[-+]?([0-9]+[.]?[0-9]*|[.][0-9]+)([eE][-+]?[0-9]+)?\$/) exit 1
			d = v - w; if (d < 0) d = -d; exit !(d <= 1e-12 * (w < 0 ? -w : w)) }" || return 1
	done
}

# front_answers BK FRONT TARGET_AWK POINTS...: print the name of every front
# member with rmse <= 1e-9 that form_matches confirms; fails when there is none.
front_answers() {
	_lib_bk=$1 _lib_front=$2 _lib_t=$3; shift 3
	csv_cols "$_lib_front" name rmse form parameters >"${T:?}/.front_answers" || return 1
	_lib_found=1
	while IFS="$(printf '\t')" read -r _lib_n _lib_e _lib_f _lib_p; do
		awk -v e="$_lib_e" 'BEGIN { exit !(e ~ /^[-+]?([0-9]+[.]?[0-9]*|[.][0-9]+)([eE][-+]?[0-9]+)?$/ && e + 0 <= 1e-9) }' || continue
		form_matches "$_lib_bk" "$_lib_f" "$_lib_p" "$_lib_t" "$@" || continue
		echo "$_lib_n"; _lib_found=0
	done <"$T/.front_answers"
	return $_lib_found
}

# api_names INCDIR: the bk_ names the installed headers (INCDIR/brdfkit/*.h of
# the Makefile's PUB_H) declare as functions or extern data, one a line, read
# from the preprocessed headers: macros and comments gone, a function name is
# followed by '(' (a function-pointer type reads "(*NAME)"). tests/install.sh
# checks the libraries' exports against it, tests/man.sh the section-3 pages.
api_names() {
	for _lib_h in brdf.h brdf_ops.h solver.h target.h fit.h expr.h search.h catalog.h; do
		echo "#include <brdfkit/$_lib_h>"
	done >"${T:?}/.api.c"
	gcc -std=c11 -E -P -I"$1" "$T/.api.c" | tr -s ' \t\n' '   ' | sed 's/[;{}]/&\n/g' >"$T/.api.i" || return 1
	{ grep -o '\bbk_[A-Za-z0-9_]*[ ]*(' "$T/.api.i" | sed 's/[ (]*$//'
	  grep '^ *extern [^(]*;' "$T/.api.i" | grep -o '\bbk_[A-Za-z0-9_]*[] []*;' | sed 's/[] [;]*$//'; } | LC_ALL=C sort -u
}
