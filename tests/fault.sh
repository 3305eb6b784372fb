#!/bin/sh
# fault.sh — outputs under faults: a run killed (SIGKILL, injected by strace at
# the dangerous system calls) leaves --out as the old whole result or the new
# whole one, never a mix, and the next run cleans what it left; concurrent runs
# on one --out end with one whole result; SIGINT and SIGTERM remove the run's
# temporaries (the SPIR-V scratch under $TMPDIR included) and exit 130 / 143;
# a failed fsync of the parent directory after the swap is an error (exit 1).
# Which call to fault is read from a trace of the same run (the Nth fsync
# after the exchange, the one on the parent), never counted by hand, so the
# points stay right when the order of the calls changes.
# usage: sh tests/fault.sh path/to/brdfkit
set -u
BK=${1:?usage: fault.sh path/to/brdfkit}
T=$(mktemp -d /tmp/bk_fault_XXXXXX)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
command -v strace >/dev/null || { echo "fault.sh: strace not found (Debian package strace)"; exit 1; }
# st ARGS...: strace with faults injected; LeakSanitizer cannot run under ptrace
# (the sanitized tool would exit 1 for that alone), the cli_*.sh scripts check leaks
st() { ASAN_OPTIONS=detect_leaks=0 strace -f -o /dev/null "$@"; }

# tree DIR: every file under DIR with its checksum, sorted: two trees are the
# same result when these are equal (the marker and the record of the run's
# temporary names, .brdfkit-output*, are the protocol's, not the result's)
tree() { (cd "$1" 2>/dev/null && find . -type f ! -name '.brdfkit-output*' -exec md5sum {} + | sort -k2); }
# siblings OUT: what stands beside OUT (temporaries, set-aside copies)
siblings() { ls -A "$(dirname "$1")" | grep -F "$(basename "$1")." ; }

# reference results: "old" (stability NoV) and "new" (stability D_ggx), each whole
O=$T/o
$BK stability NoV --out "$O" >/dev/null 2>&1 && tree "$O" >"$T/old.tree" || bad "reference run NoV"
rm -rf "$O"
$BK stability D_ggx --out "$O" >/dev/null 2>&1 && tree "$O" >"$T/new.tree" || bad "reference run D_ggx"
rm -rf "$O"
[ -s "$T/old.tree" ] && [ -s "$T/new.tree" ] && ! cmp -s "$T/old.tree" "$T/new.tree" && ok || bad "references"

# traced CMD...: CMD run under strace, the calls that write, rename and remove
# (with the paths of their descriptors) in $T/trace
traced() { ASAN_OPTIONS=detect_leaks=0 strace -f -y -o "$T/trace" -e trace=fsync,unlinkat,rename,renameat2 "$@"; }
# nth CALL REGEX [AFTER]: the index, among the CALL calls of the trace, of the
# first whose line matches REGEX (and comes after the first line matching
# AFTER); 0 when there is none
nth() {
	awk -v s="$1(" -v re="$2" -v after="${3:-}" '
		after != "" && !seen && $0 ~ after { seen = 1 }
		index($0, s) { n++; if ((after == "" || seen) && $0 ~ re) { print n; found = 1; exit } }
		END { if (!found) print 0 }' "$T/trace"
}
# count CALL: how many CALL calls the trace holds
count() { awk -v s="$1(" 'index($0, s) { n++ } END { print n + 0 }' "$T/trace"; }

# killed KILLSPEC: old result at $O, stability D_ggx killed at the injected call;
# $O must be old or new whole, and the next run must leave nothing beside it
killed() {
	rm -rf "$O" "$O".*
	$BK stability NoV --out "$O" >/dev/null 2>&1
	st -e trace="${1%%:*}" -e inject="$1" $BK stability D_ggx --out "$O" >/dev/null 2>&1
	r=$?
	[ $r -eq 137 ] && ok || bad "kill at $1 did not happen (exit $r)"
	tree "$O" >"$T/got.tree"
	if cmp -s "$T/got.tree" "$T/old.tree"; then ok; elif cmp -s "$T/got.tree" "$T/new.tree"; then ok
	else bad "kill at $1: a mix: $(diff "$T/old.tree" "$T/got.tree" | head -5)"; fi
	$BK stability NoV --out "$O" >/dev/null 2>&1 && tree "$O" | cmp -s - "$T/old.tree" && ok || bad "after kill at $1: no clean run"
	[ -z "$(siblings "$O")" ] && ok || bad "after kill at $1: left beside: $(siblings "$O")"
}
# the points, from a trace of the same replacement
rm -rf "$O" "$O".*
$BK stability NoV --out "$O" >/dev/null 2>&1
traced $BK stability D_ggx --out "$O" >/dev/null 2>&1 || bad "traced reference run"
X=RENAME_EXCHANGE B=$(basename "$O")
for p in "renameat2 $(nth renameat2 "$X")"  `# at the swap` \
	"fsync $(nth fsync '/maps/')"            `# while the new tree is flushed` \
	"fsync $(nth fsync '/[.]brdfkit-output>')" `# the marker's list, the last before the swap` \
	"fsync $(nth fsync . "$X")"              `# the parent, right after the swap` \
	"unlinkat $(nth unlinkat . "$X")"        `# the first removal from the previous result` \
	"unlinkat $(nth unlinkat '"[.]brdfkit-output", 0' "$X")" `# its marker` \
	"unlinkat $(nth unlinkat "\"$B[.]tmp[A-Za-z0-9]*\", AT_REMOVEDIR" "$X")" `# its directory` \
	"unlinkat $(count unlinkat)"             `# the last: the record of the new result's temporary name` \
	"rename $(nth rename '[.]png"[)]')"; do  `# while the heatmap files are placed`
	set -- $p
	[ "$2" -gt 0 ] && ok || { bad "no $1 call to kill at in the trace: $(grep -c "$1(" "$T/trace")"; continue; }
	killed "$1:signal=SIGKILL:when=$2"
done

# no RENAME_EXCHANGE on the file system: the old result moved aside, the new in
rm -rf "$O" "$O".*
$BK stability NoV --out "$O" >/dev/null 2>&1
st -e trace=renameat2 -e inject=renameat2:error=EINVAL $BK stability D_ggx --out "$O" >/dev/null 2>&1 \
	&& tree "$O" | cmp -s - "$T/new.tree" && [ -z "$(siblings "$O")" ] && ok || bad "fallback without exchange: $(siblings "$O")"
# killed between its two renames (found in a trace): DIR absent, the previous
# result at DIR.oldXXXXXX and the new one at DIR.tmpXXXXXX, both whole; both
# names are recorded (the new tree's), so the next run removes both. Killed
# in the removal after them: the next run finishes it.
rm -rf "$O" "$O".*
$BK stability NoV --out "$O" >/dev/null 2>&1
ASAN_OPTIONS=detect_leaks=0 strace -f -o "$T/trace" -e trace=renameat,renameat2,unlinkat -e inject=renameat2:error=EINVAL \
	$BK stability D_ggx --out "$O" >/dev/null 2>&1 || bad "traced fallback"
n=$(nth renameat "\"$B[.]tmp[A-Za-z0-9]*\", [0-9]*, \"$B\")") u=$(nth unlinkat . "\"$B[.]tmp[A-Za-z0-9]*\", [0-9]*, \"$B\")")
[ "$n" -gt 0 ] && [ "$u" -gt 0 ] && ok || bad "fallback trace: rename $n, unlinkat $u"
for p in renameat:signal=SIGKILL:when=$n unlinkat:signal=SIGKILL:when=$u; do
	rm -rf "$O" "$O".*
	$BK stability NoV --out "$O" >/dev/null 2>&1
	st -e trace="renameat2,${p%%:*}" -e inject=renameat2:error=EINVAL -e inject="$p" $BK stability D_ggx --out "$O" >/dev/null 2>&1
	r=$?
	[ $r -eq 137 ] && ok || bad "fallback kill at $p did not happen (exit $r)"
	case $p in renameat*)
		[ ! -e "$O" ] && tree "$O".old* | cmp -s - "$T/old.tree" && tree "$O".tmp* | cmp -s - "$T/new.tree" \
			&& ok || bad "fallback killed at $p: $(ls -A "$T")";;
	*) tree "$O" | cmp -s - "$T/new.tree" && ok || bad "fallback killed at $p: $(tree "$O")";;
	esac
	$BK stability NoV --out "$O" >/dev/null 2>&1 && tree "$O" | cmp -s - "$T/old.tree" && [ -z "$(siblings "$O")" ] \
		&& ok || bad "after the fallback killed at $p: left beside: $(siblings "$O")"
done

# concurrent pairs on one --out: both succeed (the later whole result replaces
# the earlier whole one) or the loser says so; never a mix
rm -rf "$O" "$O".*
for k in 1 2 3 4 5 6 7 8; do
	$BK stability NoV --out "$O" >/dev/null 2>"$T/e1" & p1=$!
	$BK stability D_ggx --out "$O" >/dev/null 2>"$T/e2" & p2=$!
	wait $p1; r1=$?; wait $p2; r2=$?
	tree "$O" >"$T/got.tree"
	if [ $r1 -eq 0 ] && [ $r2 -eq 0 ] && { cmp -s "$T/got.tree" "$T/old.tree" || cmp -s "$T/got.tree" "$T/new.tree"; }; then ok
	else bad "pair $k: exits $r1 $r2: $(cat "$T/e1" "$T/e2" | grep -v done) $(diff "$T/old.tree" "$T/got.tree" | head -3)"; fi
done
[ -z "$(siblings "$O")" ] && ok || bad "pairs left beside: $(siblings "$O")"

# the same for lut: dfg.exr and dfg.csv always from one run
L=$T/lut
for s in 4 8; do $BK lut --size $s --out "$L" 2>/dev/null && tree "$L" >"$T/lut$s.tree"; done
for k in 1 2 3 4 5 6 7 8; do
	$BK lut --size 4 --out "$L" 2>/dev/null & p1=$!
	$BK lut --size 8 --out "$L" 2>/dev/null & p2=$!
	wait $p1; r1=$?; wait $p2; r2=$?
	tree "$L" >"$T/got.tree"
	if [ $r1 -eq 0 ] && [ $r2 -eq 0 ] && { cmp -s "$T/got.tree" "$T/lut4.tree" || cmp -s "$T/got.tree" "$T/lut8.tree"; }; then ok
	else bad "lut pair $k: exits $r1 $r2, $(cat "$T/got.tree")"; fi
done
# a kill at every rename (between the EXR and the CSV) and at the swap: the
# pair is old or new, never one of each
$BK lut --size 4 --out "$L" 2>/dev/null
traced $BK lut --size 8 --out "$L" >/dev/null 2>&1 || bad "traced lut"
n=$(count rename) x=$(nth renameat2 RENAME_EXCHANGE)
[ "$n" -ge 2 ] && [ "$x" -gt 0 ] && ok || bad "lut trace: $n renames, exchange at $x"
for p in $(seq 1 "$n" | sed 's/^/rename:when=/') renameat2:when=$x; do
	$BK lut --size 4 --out "$L" 2>/dev/null
	st -e trace="${p%%:*}" -e inject="${p%%:*}:signal=SIGKILL:${p#*:}" \
		$BK lut --size 8 --out "$L" >/dev/null 2>&1
	r=$?
	[ $r -eq 137 ] && ok || bad "lut kill at $p did not happen (exit $r)"
	tree "$L" >"$T/got.tree"
	cmp -s "$T/got.tree" "$T/lut4.tree" || cmp -s "$T/got.tree" "$T/lut8.tree" && ok || bad "lut killed at $p: $(cat "$T/got.tree")"
done
$BK lut --size 4 --out "$L" 2>/dev/null && [ -z "$(siblings "$L")" ] && ok || bad "lut leftovers: $(siblings "$L")"

# issue 21, L15: a failed fsync of the parent directory after the swap was
# ignored (exit 0). It is an error now: exit 1, one line; the new result is in
# place and whole, the previous one stays beside it until the next run. The
# fsync to fail is the first after the exchange, checked to be the parent's.
P=$T/l15 TP=$(cd "$T" && pwd -P)
$BK lut --size 4 --out "$P" 2>/dev/null && tree "$P" >"$T/l15new.tree" && rm -rf "$P" || bad "l15 reference"
$BK lut --size 5 --out "$P" 2>/dev/null
traced $BK lut --size 4 --out "$P" >/dev/null 2>&1 || bad "l15 traced run"
n=$(nth fsync "<$TP>[)]" RENAME_EXCHANGE)
[ "$n" -gt 0 ] && [ "$n" -eq "$(nth fsync . RENAME_EXCHANGE)" ] && ok || bad "l15: the parent's fsync is not the first after the swap ($n)"
# inject_fsync N CMD...: CMD with its Nth fsync failing (ENOSPC); its exit status
# in r, stderr in $T/err, and the line of the faulted call in $T/hit
inject_fsync() {
	n=$1; shift
	ASAN_OPTIONS=detect_leaks=0 strace -f -y -o "$T/inj" -e trace=fsync -e inject=fsync:error=ENOSPC:when="$n" \
		"$@" >/dev/null 2>"$T/err"
	r=$?
	grep INJECTED "$T/inj" >"$T/hit"
}
$BK lut --size 5 --out "$P" 2>/dev/null
inject_fsync "$n" $BK lut --size 4 --out "$P"
grep -q "<$TP>) *= -1 ENOSPC" "$T/hit" && ok || bad "l15: the fault did not hit the parent: $(cat "$T/hit")"
msg=$(grep -v 'lut rows' "$T/err")
case $msg in
"brdfkit lut: --out $P: the new result is in place, but the fsync of its parent directory failed: no space left on device; the previous result stays at $P.tmp"??????" until the next run")
	[ $r -eq 1 ] && ok || bad "l15: exit $r";;
*) bad "l15: exit $r, stderr: $msg";;
esac
tree "$P" | cmp -s - "$T/l15new.tree" && ok || bad "l15: the new result is not whole: $(tree "$P")"
$BK lut --size 4 --out "$P" 2>/dev/null && [ -z "$(siblings "$P")" ] && ok || bad "l15: left beside after the next run: $(siblings "$P")"
# the negative control: the same run, no fault, exits 0 (the check above can fail)
$BK lut --size 4 --out "$P" 2>/dev/null && ok || bad "l15: a run without a fault failed"
# the same for a single file (albedo --out FILE): the fsync of its directory
A=$T/albedo.csv
traced $BK albedo --d ggx --v implicit --f schlick --nov 0.5 --roughness 0.5 --f0 1 --out "$A" >/dev/null 2>&1 || bad "albedo trace"
n=$(nth fsync "<$TP>[)]")
[ "$n" -gt 0 ] && ok || bad "albedo: no fsync of the directory in the trace"
inject_fsync "$n" $BK albedo --d ggx --v implicit --f schlick --nov 0.5 --roughness 0.5 --f0 1 --out "$A"
[ $r -eq 1 ] && [ "$(grep -v 'albedo combinations' "$T/err")" = "brdfkit albedo: $A: written, but the fsync of its directory failed: no space left on device (it may not survive a crash)" ] \
	&& grep -q "<$TP>) *= -1 ENOSPC" "$T/hit" && ok || bad "albedo with a failed directory fsync: exit $r, $(cat "$T/err")"

# SIGTERM and SIGINT: exit 128 + signal, no temporary left. A background job of
# a non-interactive shell starts with SIGINT ignored, so env gives it back.
# sigtest SIG STATUS DIR CMD...: CMD started, SIG after 0.3 s, DIR must hold no temporary.
sigtest() {
	sig=$1 want=$2 d=$3; shift 3
	env --default-signal=INT "$@" >/dev/null 2>&1 & p=$!
	sleep 0.3
	kill -s "$sig" $p 2>/dev/null
	{ wait $p; r=$?; } 2>/dev/null
	left=$(ls -A "$d" | grep -E '\.tmp|^bk_' | tr '\n' ' ')
	[ $r -eq "$want" ] && [ -z "$left" ] && ok || bad "$sig: exit $r, left: $left ($*)"
}
mkdir "$T/sig" "$T/scratch"
sigtest TERM 143 "$T/sig" $BK lut --size 512 --out "$T/sig/lut"
sigtest INT 130 "$T/sig" $BK lut --size 512 --out "$T/sig/lut"
[ ! -e "$T/sig/lut" ] && ok || bad "a killed lut left its directory"
# time: cc and glslang work in a scratch directory under $TMPDIR (500 reps:
# about 1.4 s; at 50 the command took 0.33 s on a fast hour and could end
# before the signal, exit 0)
sigtest TERM 143 "$T/scratch" env TMPDIR="$T/scratch" $BK time NoV 'sqrt(NoV)' 'NoV*NoV' 'D_ggx(NoH, a)' --reps 500
sigtest INT 130 "$T/scratch" env TMPDIR="$T/scratch" $BK time NoV 'sqrt(NoV)' 'NoV*NoV' 'D_ggx(NoH, a)' --reps 500

echo "fault: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
