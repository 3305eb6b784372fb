#!/bin/sh
# fault.sh — outputs under faults: a run killed (SIGKILL, injected by strace at
# the dangerous system calls) leaves --out as the old whole result or the new
# whole one, never a mix, and the next run cleans what it left; concurrent runs
# on one --out end with one whole result; SIGINT and SIGTERM remove the run's
# temporaries (the SPIR-V scratch under $TMPDIR included) and exit 130 / 143.
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
# (the sanitized tool would exit 1 for that alone), cli.sh checks leaks
st() { ASAN_OPTIONS=detect_leaks=0 strace -f -o /dev/null "$@"; }

# tree DIR: every file under DIR with its checksum, sorted: two trees are the
# same result when these are equal
tree() { (cd "$1" 2>/dev/null && find . -type f ! -name '.brdfkit-output' -exec md5sum {} + | sort -k2); }
# siblings OUT: what stands beside OUT (temporaries, set-aside copies)
siblings() { ls -A "$(dirname "$1")" | grep -F "$(basename "$1")." ; }

# reference results: "old" (stability NoV) and "new" (stability D_ggx), each whole
O=$T/o
$BK stability NoV --out "$O" >/dev/null 2>&1 && tree "$O" >"$T/old.tree" || bad "reference run NoV"
rm -rf "$O"
$BK stability D_ggx --out "$O" >/dev/null 2>&1 && tree "$O" >"$T/new.tree" || bad "reference run D_ggx"
rm -rf "$O"
[ -s "$T/old.tree" ] && [ -s "$T/new.tree" ] && ! cmp -s "$T/old.tree" "$T/new.tree" && ok || bad "references"

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
killed renameat2:signal=SIGKILL:when=1          # at the swap
killed fsync:signal=SIGKILL:when=3              # while the new tree is flushed
killed fsync:signal=SIGKILL:when=12             # at the last fsyncs
killed unlinkat:signal=SIGKILL:when=4           # while the old tree is removed
killed unlinkat:signal=SIGKILL:when=9
killed rename:signal=SIGKILL:when=2             # while the heatmap files are placed

# no RENAME_EXCHANGE on the file system: the old result moved aside, the new in
rm -rf "$O" "$O".*
$BK stability NoV --out "$O" >/dev/null 2>&1
st -e trace=renameat2 -e inject=renameat2:error=EINVAL $BK stability D_ggx --out "$O" >/dev/null 2>&1 \
	&& tree "$O" | cmp -s - "$T/new.tree" && [ -z "$(siblings "$O")" ] && ok || bad "fallback without exchange: $(siblings "$O")"

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
# a kill between the EXR and the CSV: the pair is old or new, never one of each
for n in rename:when=1 rename:when=2 renameat2:when=1; do
	$BK lut --size 4 --out "$L" 2>/dev/null
	st -e trace="${n%%:*}" -e inject="${n%%:*}:signal=SIGKILL:${n#*:}" \
		$BK lut --size 8 --out "$L" >/dev/null 2>&1
	r=$?
	[ $r -eq 137 ] && ok || bad "lut kill at rename $n did not happen (exit $r)"
	tree "$L" >"$T/got.tree"
	cmp -s "$T/got.tree" "$T/lut4.tree" || cmp -s "$T/got.tree" "$T/lut8.tree" && ok || bad "lut killed at rename $n: $(cat "$T/got.tree")"
done
$BK lut --size 4 --out "$L" 2>/dev/null && [ -z "$(siblings "$L")" ] && ok || bad "lut leftovers: $(siblings "$L")"

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
# time: cc and glslang work in a scratch directory under $TMPDIR
sigtest TERM 143 "$T/scratch" env TMPDIR="$T/scratch" $BK time NoV 'sqrt(NoV)' 'NoV*NoV' 'D_ggx(NoH, a)' --reps 50
sigtest INT 130 "$T/scratch" env TMPDIR="$T/scratch" $BK time NoV 'sqrt(NoV)' 'NoV*NoV' 'D_ggx(NoH, a)' --reps 50

echo "fault: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
