#!/bin/sh
# cli_envsearch.sh — brdfkit's command-line contract (the common start:
# tests/lib_cli.sh): search: usage errors, --fetch-cost, --env-form f0 and mix,
# SIGINT (issue 10).
# usage: sh tests/cli_envsearch.sh path/to/brdfkit
NAME=cli_envsearch
. "$(dirname "$0")/lib_cli.sh"

# usage errors: one line naming the bad input, nothing written
expect_error "search objective" "'worst'" $BK search --target vf2d --objective worst --out "$T/s1"
expect_error "search albedo on vf2d" "albedo" $BK search --target vf2d --objective albedo --out "$T/s1"
expect_error "search precision" "'quad'" $BK search --target vf2d --precision quad --out "$T/s1"
expect_error "search ops" "'cos'" $BK search --target vf2d --ops '+,cos' --out "$T/s1"
expect_error "search inputs" "'NoX'" $BK search --target vf2d --inputs LoH,NoX --out "$T/s1"
expect_error "search inputs provided" "NoV" $BK search --target vf2d --inputs NoV --out "$T/s1"
expect_error "search evals" "--evals" $BK search --target vf2d --evals 0 --out "$T/s1"
expect_error "search every" "--every" $BK search --target vf2d --every 10 --out "$T/s1"
expect_error "search f0 on env pairs" "--f0 has no effect on env split pairs" $BK search --target env --f0 1 --out "$T/s1"
expect_error "search f0 list" "--f0: one value, got 2" $BK search --target vf2d --f0 0.1,0.2 --out "$T/s1"
expect_error "search start target" "vf_talk_r" $BK search --target env --start vf_talk_r --out "$T/s1"
expect_error "search r-range names search" "brdfkit search: --r-range" $BK search --target vf2d --r-range 1:0 --out "$T/s1"
expect_error "search weights" "--cost-weights" $BK search --target vf2d --cost-weights simple=-1 --out "$T/s1"
[ ! -e "$T/s1" ] && ok || bad "a refused search left --out behind"
# --fetch-cost puts compare's LUT rows on the search's axis: cost K + 1 (the fetch
# and the mad of f0 A + B); refused where there is no LUT
expect_error "search fetch-cost on vf2d" "--fetch-cost" $BK search --target vf2d --fetch-cost 16 --out "$T/s3"
if $BK search --target env --evals 300 --fetch-cost 16 --out "$T/lut" >/dev/null 2>"$T/err" &&
	[ "$(csv_cols "$T/lut/catalog.csv" name cost | grep -c '^LUT [0-9]*x[0-9]* [a-z0-9]*	17$')" = 12 ]; then ok
else bad "search --fetch-cost: $(grep LUT "$T/lut/catalog.csv" | head -3) $(tail -2 "$T/err")"; fi
# --env-form f0: one form in f0 scored on f0 A + B (compare's quantity): the
# catalog's forms in f0 seed it, each split pair as f0*(A) + (B); no form_b
expect_error "search env-form" "'triple'" $BK search --target env --env-form triple --out "$T/s4"
expect_error "search env-form split start" "write it as 'f0*(A) + (B)'" $BK search --target env --env-form f0 \
	--start env_karis2014_split --out "$T/s4"
if $BK search --target env --env-form f0 --evals 400 --out "$T/ef0" >/dev/null 2>"$T/err"; then ok
else bad "search --env-form f0: $(tail -2 "$T/err")"; fi
grep -q '^# target: env: .*one form in f0 fitted to f0 A + B over the f0 list' "$T/ef0/front.csv" && ok ||
	bad "search --env-form f0: the target line: $(grep '^# target' "$T/ef0/front.csv")"
csv_col "$T/ef0/catalog.csv" name | grep -qx env_pesce_iwanicki2015 && ok || bad "search --env-form f0: Pesce-Iwanicki not a seed"
csv_where "$T/ef0/catalog.csv" name env_karis2014_split form | grep -q '^f0\*((p9\*' && ok ||
	bad "search --env-form f0: the split pair not as f0*(A) + (B)"
# every row: name, form (quoted or not), an empty form_b
csv_col "$T/ef0/front.csv" form_b >"$T/fb" && [ "$(grep -c . "$T/fb")" = 0 ] && ok ||
	bad "search --env-form f0: a front member with form_b"
# --env-form mix: f0 A + B is exactly mix(B, S, f0) (S = A + B, linear in
# f0), so searches of S (f0 = 1) and of B (f0 = 0) run first, a quarter of the
# budget each, and their fronts' compositions seed the search of forms in f0
expect_error "search mix checkpoint" "--checkpoint has no effect with --env-form mix" $BK search --target env --env-form mix \
	--checkpoint "$T/mx.ck" --out "$T/s5"
expect_error "search mix budget" "too few to share among three searches" $BK search --target env --env-form mix \
	--evals 500 --out "$T/s5"
expect_error "search mix max-cost" "leaves nothing to the halves" $BK search --target env --env-form mix --max-cost 3 \
	--out "$T/s5"
if $BK search --target env --env-form mix --evals 4000 --max-cost 15 --threads 2 --out "$T/mix" >/dev/null 2>"$T/err" &&
	grep -q '^search: S = A + B half: [0-9]* fits in' "$T/err" && grep -q '^search: B half: [0-9]* fits in' "$T/err" &&
	grep -q '^search: [0-9]* compositions mix(B, S, f0) seed the search' "$T/err"; then ok
else bad "search --env-form mix: $(tail -3 "$T/err")"; fi
# the compositions compete on the front (named after their seeding), and none
# is listed as a catalog row (those are the published forms)
csv_cols "$T/mix/front.csv" name form | grep -q '^seed_halves_[0-9]*	mix(' && ok || bad "search --env-form mix: no composition on the front"
csv_col "$T/mix/catalog.csv" name >"$T/names" && lacks "$T/names" '^halves\|^seed_halves' && ok || bad "search --env-form mix: a composition in catalog.csv"
# three searches in turn, still the same bytes on one thread
$BK search --target env --env-form mix --evals 4000 --max-cost 15 --threads 1 --out "$T/mix1" >/dev/null 2>&1
for f in front.csv candidates.csv; do
	grep -v '^# command' "$T/mix/$f" >"$T/a.csv"; grep -v '^# command' "$T/mix1/$f" >"$T/b.csv"
	[ -s "$T/a.csv" ] && cmp -s "$T/a.csv" "$T/b.csv" && ok || bad "search --env-form mix: $f differs between 2 threads and 1"
done
# SIGINT: the generation ends, the checkpoint and the front so far are written, exit 130
# (a job started with & from sh inherits SIGINT ignored, and the search keeps it
# so, as POSIX asks: env restores the default; --seconds bounds it should it fail)
env --default-signal=INT $BK search --target vf2d --evals 100000000 --seconds 120 --threads 2 --checkpoint "$T/int.ck" \
	--out "$T/int" >/dev/null 2>&1 &
pid=$!
sleep 3
kill -INT $pid
wait $pid
st=$?
[ $st -eq 130 ] && has_rows "$T/int/front.csv" rmse && [ -s "$T/int.ck" ] && ok \
	|| bad "search after SIGINT: exit $st, front.csv $(ls "$T/int" 2>&1 | head -3), checkpoint $(ls -la "$T/int.ck" 2>&1)"

cli_done
