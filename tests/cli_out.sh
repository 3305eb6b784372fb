#!/bin/sh
# cli_out.sh — what a run may delete, from the command line (issue 21, section
# 3): a user's renamed backup or copy beside --out stays (H4); a
# .brdfkit-output brdfkit did not write, or of the format before, makes
# nothing deletable (M3); a file or directory the previous run did not list is
# refused by every command that writes a directory, before the work and again
# at the swap, and nothing is deleted (L2, and M4's checkpoint); a run that
# waits for another process's lock says so (L12); a killed run's leftovers,
# its checkpoint temporaries included, are removed by the next run (L1).
# usage: sh tests/cli_out.sh path/to/brdfkit
set -u
BK=${1:?usage: cli_out.sh path/to/brdfkit}
BK=$(cd "$(dirname "$BK")" && pwd)/$(basename "$BK")
REPO=$(pwd)
T=$(mktemp -d /tmp/bk_cli_out_XXXXXX)
trap 'rm -rf "$T"' EXIT
CSVGET=$REPO/build/csvget
. "$REPO/tests/lib.sh"
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
command -v strace >/dev/null && command -v flock >/dev/null && command -v timeout >/dev/null ||
	{ echo "cli_out: strace, flock and timeout are needed (Debian packages strace, util-linux, coreutils)"; exit 1; }
# LeakSanitizer cannot run under ptrace (the sanitized tool would exit 1 for that alone)
st() { ASAN_OPTIONS=detect_leaks=0 strace -f "$@"; }
cd "$T" || exit 1

# sums DIR: every file under DIR with its checksum (the protocol's .brdfkit-output*
# aside): two trees are the same when these are equal
sums() { (cd "$1" && find . -type f ! -name '.brdfkit-output*' -exec md5sum {} + | sort -k2); }
# refused NAME LINE CMD...: exit 1 and stderr exactly LINE (one line: the
# refusal came before the work, which prints progress)
refused() {
	name=$1 line=$2; shift 2
	"$@" >/dev/null 2>err
	r=$?
	[ $r -eq 1 ] && [ "$(cat err)" = "$line" ] && ok || bad "$name: exit $r, stderr: $(cat err)"
}
# rows DIR: the data rows of a lut's dfg.csv (size^2), read by column name
rows() { csv_col "$1/dfg.csv" nov | wc -l; }

# ---- H4: a renamed backup and a copy beside --out stay ----
$BK lut --size 2 --out lut 2>/dev/null || bad "lut"
mv lut lut.old202411 && echo notes >lut.old202411/notes.txt
$BK lut --size 2 --out lut 2>/dev/null && cp -a lut lut.tmp2024ab || bad "lut again"
sums lut.old202411 >backup.sums && sums lut.tmp2024ab >copy.sums
$BK lut --size 2 --out lut 2>/dev/null || bad "lut a third time"
[ "$(ls -d lut*)" = "lut
lut.old202411
lut.tmp2024ab" ] && ok || bad "H4: beside lut: $(ls -d lut* | tr '\n' ' ')"
sums lut.old202411 | cmp -s - backup.sums && [ "$(cat lut.old202411/notes.txt)" = notes ] && sums lut.tmp2024ab | cmp -s - copy.sums \
	&& ok || bad "H4: the backup or the copy changed"
# ... while a run killed before its swap (at the fsync of its list) leaves a
# temporary the next run removes: the rule is "only what brdfkit recorded",
# not "never"
st -o /dev/null -e trace=fsync -e inject=fsync:signal=SIGKILL:when=1 $BK lut --size 2 --out lut >/dev/null 2>&1
r=$?
[ $r -eq 137 ] && [ "$(ls -d lut.tmp* | wc -l)" -eq 2 ] && ok || bad "H4: the kill left no temporary (exit $r): $(ls -d lut*)"
$BK lut --size 2 --out lut 2>/dev/null && [ "$(ls -d lut* | tr '\n' ' ')" = "lut lut.old202411 lut.tmp2024ab " ] \
	&& ok || bad "H4: after a killed run: $(ls -d lut* | tr '\n' ' ')"

# ---- M3: a marker brdfkit did not write ----
mkdir -p home2/Documents && echo t >home2/Documents/thesis.tex && echo hello >home2/.brdfkit-output
refused "M3 hello" "brdfkit lut: --out home2: exists and was not written by brdfkit (its .brdfkit-output is not one brdfkit wrote); choose another path or remove it" \
	$BK lut --size 2 --out home2
# a real marker copied into a project (cp -a out/. project/) lists only out's files
mkdir project && echo t >project/thesis.tex && cp -a lut/. project/
refused "M3 cp -a" "brdfkit lut: --out project: holds 'thesis.tex', which brdfkit did not write; move it or choose another --out" \
	$BK lut --size 2 --out project
# the marker of the format before lists nothing
mkdir oldfmt && echo "brdfkit lut --size 2 --out oldfmt" >oldfmt/.brdfkit-output && echo x >oldfmt/dfg.csv
refused "M3 old format" "brdfkit lut: --out oldfmt: was written by an older brdfkit, whose .brdfkit-output lists no files; remove it yourself or choose another path" \
	$BK lut --size 2 --out oldfmt
[ "$(cat home2/Documents/thesis.tex project/thesis.tex)" = "t
t" ] && [ -e project/dfg.exr ] && [ -e oldfmt/dfg.csv ] && ok || bad "M3: a refused directory changed"
# the negative control: the same directory with only what its marker lists is replaced
rm project/thesis.tex
$BK lut --size 3 --out project 2>/dev/null && [ "$(rows project)" -eq 9 ] && ok || bad "M3: a directory of brdfkit's own was refused"

# ---- L2: what the run did not list, for every command that writes a directory ----
$BK lut --size 3 --out real 2>/dev/null || bad "lut real"
echo n >real/notes.txt && mkdir real/mysub
sums real >sums.real
refused "L2 lut" "brdfkit lut: --out real: holds 'mysub', which brdfkit did not write; move it or choose another --out" \
	$BK lut --size 256 --out real
rmdir real/mysub
for c in "stability NoV" "fit --target vf2d --form vf_talk_r --nx 8 --nr 8" "compare --target vf2d --nx 8 --nr 8 --no-time" \
	"search --target f --evals 50" "scene $REPO/analysis/scenes/rough_only.json --no-time"; do
	refused "L2 ${c%% *}" "brdfkit ${c%% *}: --out real: holds 'notes.txt', which brdfkit did not write; move it or choose another --out" \
		$BK $c --out real
done
[ "$(cat real/notes.txt)" = n ] && sums real | cmp -s - sums.real && [ -z "$(ls -d real.* 2>/dev/null)" ] \
	&& ok || bad "L2: real changed: $(ls -A real)"
# M4: a checkpoint in the previous result's directory is never deleted: the run
# fails (or is refused) and keeps it, or succeeds with it still there
$BK search --target f --evals 50 --out sC >/dev/null 2>&1 && sums sC >sums.sC || bad "search sC"
$BK search --target f --evals 300 --enum-max 300 --every 100 --threads 1 --checkpoint sC/ck --out sC >/dev/null 2>err
r=$?
if [ $r -eq 0 ]; then [ -s sC/ck ] && ok || bad "M4: exit 0 and the checkpoint is gone"
else sums sC | grep -v ' ./ck$' | cmp -s - sums.sC && [ "$(wc -l <err)" -ge 1 ] && ok || bad "M4: exit $r and sC changed: $(cat err)"; fi
# the check again at the swap: a note written while the run works (the run
# held at the fsync of its list, found in a trace of the same command)
$BK lut --size 3 --out late 2>/dev/null || bad "lut late"
ASAN_OPTIONS=detect_leaks=0 strace -f -y -o trace -e trace=fsync $BK lut --size 4 --out late >/dev/null 2>&1 || bad "traced lut"
sums late >sums.late
n=$(awk 'index($0, "fsync(") { n++; if ($0 ~ /[.]brdfkit-output>/) { print n; exit } }' trace)
st -o /dev/null -e trace=fsync -e inject=fsync:delay_enter=3000000:when="${n:-1}" $BK lut --size 4 --out late >/dev/null 2>err &
p=$!
k=0
while ! grep -qsx end late.tmp*/.brdfkit-output && [ $k -lt 100 ]; do sleep 0.1; k=$((k + 1)); done
echo n >late/notes.txt
wait $p
r=$?
[ $r -eq 1 ] && [ "$(grep -v 'lut rows' err)" = "brdfkit lut: --out late: holds 'notes.txt', which brdfkit did not write; move it or choose another --out" ] \
	&& ok || bad "L2 at the swap: exit $r, $(cat err) (list fsync $n, waited $k)"
rm late/notes.txt
sums late | cmp -s - sums.late && [ -z "$(ls -d late.* 2>/dev/null)" ] && ok || bad "L2 at the swap: late changed: $(ls -A late .)"

# ---- L12: another process holds the marker's lock ----
$BK lut --size 2 --out lk 2>/dev/null || bad "lut lk"
WAIT="brdfkit lut: --out lk: another brdfkit is writing it (its .brdfkit-output is locked); waiting for it to finish"
# hold SECONDS: a process (pid in h) holding the marker's lock for SECONDS, one
# process only (it execs sleep with the locked descriptor), so killing h frees it
hold() {
	sh -c 'exec 9<lk/.brdfkit-output && flock 9 && exec sleep "$1"' hold "$1" >/dev/null 2>&1 &
	h=$!
	k=0
	while flock -n lk/.brdfkit-output true && [ $k -lt 50 ]; do sleep 0.1; k=$((k + 1)); done
}
# held 4 s: the run says so once, waits, then replaces lk with a whole result
hold 4
t0=$(date +%s.%N)
timeout 60 $BK lut --size 3 --out lk >/dev/null 2>err
r=$?
t1=$(date +%s.%N)
wait $h
[ $r -eq 0 ] && [ "$(grep -cxF "$WAIT" err)" -eq 1 ] && [ "$(rows lk)" -eq 9 ] && awk -v a="$t0" -v b="$t1" 'BEGIN { exit !(b - a >= 3) }' \
	&& ok || bad "L12 wait: exit $r, $(awk -v a="$t0" -v b="$t1" 'BEGIN { print b - a }') s, $(cat err)"
# held longer than the caller waits: SIGTERM (timeout) ends the wait, the line
# was there, lk is still the whole previous result, nothing beside it
hold 60
timeout 5 $BK lut --size 4 --out lk >/dev/null 2>err
r=$?
kill $h
wait $h 2>/dev/null
[ $r -eq 124 ] && [ "$(grep -cxF "$WAIT" err)" -eq 1 ] && [ "$(rows lk)" -eq 9 ] && [ -z "$(ls -d lk.* 2>/dev/null)" ] \
	&& ok || bad "L12 timeout: exit $r, $(cat err), beside: $(ls -d lk.* 2>/dev/null)"
# the negative control: no holder, no line
$BK lut --size 2 --out lk 2>err && ! grep -qF "waiting" err && [ "$(rows lk)" -eq 4 ] && ok || bad "L12 control: $(cat err)"

# ---- L1: a killed search's checkpoint temporary is removed by the next run ----
# killed at the rename that puts the first checkpoint in place (from a trace)
S="search --target f --evals 300 --enum-max 300 --every 100 --threads 1 --checkpoint ck"
ASAN_OPTIONS=detect_leaks=0 strace -f -o trace -e trace=rename $BK $S --out s1 >/dev/null 2>&1 || bad "traced search"
n=$(awk 'index($0, "rename(") { n++; if (index($0, "\"ck\")")) { print n; exit } }' trace)
rm -f ck
echo mine >ck.tmp2024ab
st -o /dev/null -e trace=rename -e inject=rename:signal=SIGKILL:when="${n:-1}" $BK $S --out s2 >/dev/null 2>&1
r=$?
left=$(ls ck.tmp* | grep -vx ck.tmp2024ab)
[ $r -eq 137 ] && [ -n "$left" ] && ok || bad "L1: the kill left no temporary (exit $r, rename $n): $(ls)"
$BK $S --out s3 >/dev/null 2>&1 && [ "$(ls ck*)" = "ck
ck.tmp2024ab" ] && [ "$(cat ck.tmp2024ab)" = mine ] && ok || bad "L1: after the next run: $(ls ck*)"

# ---- the command line in comment lines: an argument's line break never starts a
# data line (the CSV's '#' header would end and the rest read as a row)
nl='x
1,2,3,4'
$BK lut --size 2 --out "lc" --r-range "0:1" >/dev/null 2>&1 && [ "$(rows lc)" -eq 4 ] && ok || bad "command line control: $(rows lc) rows"
$BK lut --size 2 --out "lc$nl" >/dev/null 2>&1
# the odd --out name is a directory of its own; its dfg.csv keeps 4 data rows
d=
for x in lc?*; do d=$x; done
if [ -n "$d" ] && [ -f "$d/dfg.csv" ]; then
	[ "$(rows "$d")" -eq 4 ] && ! grep -q '^1,2,3,4$' "$d/dfg.csv" && ok || bad "an argument's line break became a row: $(cat "$d/dfg.csv" | head -5)"
else bad "lut with a line break in --out wrote nothing: $(ls)"; fi

echo "cli_out: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
