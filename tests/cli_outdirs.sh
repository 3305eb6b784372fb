#!/bin/sh
# cli_outdirs.sh — brdfkit's command-line contract (the common start:
# tests/lib_cli.sh): output directories: only brdfkit's replaced, whole (issue
# 9).
# usage: sh tests/cli_outdirs.sh path/to/brdfkit
NAME=cli_outdirs
. "$(dirname "$0")/lib_cli.sh"

# ---- issue 9 (output directories: only brdfkit's replaced, whole) ----
# siblings OUT: what a run left beside OUT (temporaries, set-aside copies)
siblings() { ls -A "$(dirname "$1")" | grep -F "$(basename "$1")." ; }
in_dir() { (d=$1; shift; cd "$d" && exec "$@"); }
case $BK in /*) BKA=$BK ;; *) BKA=$PWD/$BK ;; esac
O="$T/own"; mkdir -p "$O/d/mydocs"; echo x >"$O/d/mydocs/thesis.tex"
# a user's directory is refused, before any work, and left as it was
expect_error "stability onto a user's dir" "--out d/mydocs" in_dir "$O" $BKA stability NoV --out d/mydocs
[ "$(cat "$T/err")" = "brdfkit stability: --out d/mydocs: exists and was not written by brdfkit; choose another path or remove it" ] \
	&& ok || bad "stability refusal text: $(cat "$T/err")"
for c in "compare --target vf2d --nx 8 --nr 8 --no-time" "fit --target vf2d --form vf_talk_r --nx 8 --nr 8" "lut --size 4"; do
	expect_error "${c%% *} onto a user's dir" "--out $O/d/mydocs: exists and was not written by brdfkit" $BK $c --out "$O/d/mydocs"
done
[ "$(ls -A "$O/d/mydocs")" = thesis.tex ] && [ "$(cat "$O/d/mydocs/thesis.tex")" = x ] && ok || bad "user's dir touched: $(ls -A "$O/d/mydocs")"
# fit no longer moves a user's files aside to DIR.oldXXXXXX
[ -z "$(siblings "$O/d/mydocs")" ] && ok || bad "beside the user's dir: $(siblings "$O/d/mydocs")"
echo x >"$O/file"
expect_error "stability onto a file" "--out $O/file: exists and was not written by brdfkit" $BK stability NoV --out "$O/file"
# the current directory and its parents are refused, whatever they hold (/ is in
# test_out.c: a broken build must not be let loose on it)
mkdir -p "$O/cwd/sub"; : >"$O/cwd/sub/keep"
for o in . .. ../.. ../sub ./; do
	expect_error "--out $o" "--out $o: is the current directory or one of its parents" in_dir "$O/cwd/sub" $BKA stability NoV --out "$o"
done
[ -e "$O/cwd/sub/keep" ] && [ -e "$O/d/mydocs/thesis.tex" ] && ok || bad "--out . emptied the current directory"
# an empty directory may be used; the result carries the marker with the command
mkdir "$O/empty"
$BK stability NoV --out "$O/empty" >/dev/null 2>&1 && [ "$(csv_col "$O/empty/stability.csv" form)" = NoV ] && ok || bad "empty dir not used"
grep -qx "brdfkit stability NoV --out $O/empty" "$O/empty/.brdfkit-output" && ok || bad "marker: $(cat "$O/empty/.brdfkit-output")"
# a brdfkit directory is replaced whole: nothing of the old run stays, nothing beside it
$BK stability D_ggx --out "$O/s" >/dev/null 2>&1 && [ -s "$O/s/maps/d_ggx.png" ] && ok || bad "stability D_ggx"
$BK stability NoV --out "$O/s" >/dev/null 2>&1 && [ -s "$O/s/maps/form.png" ] && [ ! -e "$O/s/maps/d_ggx.png" ] \
	&& ok || bad "not replaced whole: $(ls "$O/s/maps")"
[ -z "$(siblings "$O/s")" ] && ok || bad "left beside: $(siblings "$O/s")"
# a symlink inside a brdfkit directory was not written by its run: refused,
# nothing followed or removed (issue 21: only what the marker lists is deleted)
mkdir "$O/p"; echo keep >"$O/p/keep.txt"; ln -s ../p "$O/s/link"; ln -s ../p/keep.txt "$O/s/maps/file_link"
expect_error "replace with a symlink inside" "--out $O/s: holds 'link', which brdfkit did not write" $BK stability NoV --out "$O/s"
[ -L "$O/s/link" ] && [ "$(cat "$O/p/keep.txt" 2>/dev/null)" = keep ] && ok || bad "symlink followed: $(ls -A "$O/p")"
rm "$O/s/link" "$O/s/maps/file_link"
# a symlink at --out itself is not brdfkit's directory
ln -s s "$O/slink"
expect_error "--out a symlink" "--out $O/slink: is a symlink: give the directory itself" $BK stability NoV --out "$O/slink"
# look-alikes of a killed run's temporary, with a marker or without, whose
# names brdfkit never recorded, stay (issue 21, H4; a real killed run's
# temporary is removed: tests/fault.sh, tests/cli_out.sh)
mkdir "$O/s.tmpAbC123" "$O/s.tmpXyZ789"; : >"$O/s.tmpAbC123/.brdfkit-output"; : >"$O/s.tmpAbC123/stability.csv"
: >"$O/s.tmpXyZ789/mine.txt"
$BK stability NoV --out "$O/s" >/dev/null 2>&1 && [ -e "$O/s.tmpAbC123/stability.csv" ] && [ -e "$O/s.tmpXyZ789/mine.txt" ] \
	&& ok || bad "leftovers: $(siblings "$O/s")"
rm -rf "$O/s.tmpAbC123" "$O/s.tmpXyZ789"
# lut: the EXR and its CSV are one directory
$BK lut --size 4 --out "$O/lut" 2>/dev/null && [ "$(ls "$O/lut" | tr '\n' ' ')" = "dfg.csv dfg.exr " ] \
	&& ok || bad "lut dir: $(ls -A "$O/lut")"
$BK lut --size 2 --out "$O/lut" 2>/dev/null && grep -q '^# brdfkit .* 2x2' "$O/lut/dfg.csv" && [ -z "$(siblings "$O/lut")" ] \
	&& ok || bad "lut replaced: $(siblings "$O/lut")"
rm -rf "$O"

cli_done
