# lib_cli.sh — the common start of the command-line contract's scripts
# (tests/cli_basics.sh, cli_outdirs.sh, cli_fitstab.sh, cli_numbers.sh,
# cli_numerics.sh, cli_longfits.sh, cli_formtarget.sh, cli_planted.sh,
# cli_envsearch.sh, cli_scenes.sh: once one serial cli.sh, split so
# that make -j runs them side by side, issue 42). The contract: help, exact values where a
# closed form exists, one-line errors naming the bad input with a non-zero
# exit, nothing left on disk after a failure, and the same bytes for the same
# command. CSV is read by column name (tests/lib.sh); every threshold check is
# a named function, run once more on an input it must refuse (its negative
# control).
#
# Source it with NAME set to the script's name and the script's arguments as
# they came (usage: sh tests/NAME.sh path/to/brdfkit); end the script with
# cli_done. Its name does not match tests/cli_*.sh: the Makefile runs every
# such script as a test, and this one is no test on its own.
set -u
BK=${1:?usage: $NAME.sh path/to/brdfkit}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
: "${CSVGET:=$ROOT/build/csvget}"
T=$(mktemp -d "/tmp/bk_${NAME}_XXXXXX")
trap 'rm -rf "$T"' EXIT
pass=0 fail=0

ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
# cli_done: the script's count, and its exit status (non-zero on a failure)
cli_done() { echo "$NAME: $pass passed, $fail failed"; [ "$fail" -eq 0 ]; }
. "$ROOT/tests/lib.sh"
[ -x "$CSVGET" ] || { bad "no $CSVGET (make build/csvget)"; cli_done; exit 1; }

# lacks FILE PATTERN: FILE was written (non-empty) and no line matches PATTERN
# (a bare "grep -q ... && bad || ok" passes when the file is missing)
lacks() { [ -s "$1" ] || return 1; grep -q -- "$2" "$1"; [ $? -eq 1 ]; }
# close_to GOT WANT RTOL: both numbers, |GOT - WANT| <= RTOL |WANT| + 1e-30
close_to() {
	awk -v g="$1" -v w="$2" -v t="$3" 'BEGIN { num = "^[-+]?([0-9]+[.]?[0-9]*|[.][0-9]+)([eE][-+]?[0-9]+)?$"
		if (g !~ num || w !~ num) exit 1
		d = g - w; if (d < 0) d = -d; m = w < 0 ? -w : w; exit !(d <= t * m + 1e-30) }'
}
# is_num TEXT: TEXT is one decimal or scientific number
is_num() { close_to "$1" "$1" 0; }
# has_rows FILE COLUMN: FILE is a CSV with COLUMN and at least one data row
has_rows() { csv_col "$1" "$2" >/dev/null; }
# c_matches_ir GOT WANT: generated C's value is the IR's f32 (brdfkit eval) to
# 1e-6 relative (cli_planted.sh's front members, cli_scenes.sh's functions)
c_matches_ir() { close_to "$1" "$2" 1e-6; }

# expect_out NAME EXPECTED CMD...: stdout equals EXPECTED, exit 0.
expect_out() {
	name=$1 want=$2; shift 2
	got=$("$@" 2>"$T/err") && [ "$got" = "$want" ] && ok || bad "$name: got '$got' $(cat "$T/err")"
}

# expect_error NAME TOKEN CMD...: non-zero exit, one line on stderr naming TOKEN.
expect_error() {
	name=$1 token=$2; shift 2
	if "$@" >"$T/out" 2>"$T/err"; then bad "$name: exit 0"; return; fi
	if one_line "$T/err" "$token"; then ok; else bad "$name: stderr '$(cat "$T/err")'"; fi
}

# expect_usage_error NAME TOKEN CMD...: exit 2 (bad usage), one line on stderr naming TOKEN.
expect_usage_error() {
	name=$1 token=$2; shift 2
	"$@" >"$T/out" 2>"$T/err"; rc=$?
	if [ "$rc" -eq 2 ] && one_line "$T/err" "$token"; then ok
	else bad "$name: exit $rc, stderr '$(cat "$T/err")'"; fi
}
