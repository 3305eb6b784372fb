#!/bin/sh
# bench_search_mpi.sh — make bench: the search's islands under MPI (issue 12).
#
# One target (vf2d, --objective max, the screening grid of 32x32 cells), run
# on 1, 2 and 4 ranks of one thread each (4 is oversubscribed on a 2-core
# machine: the curve must bend there), REPS times each, the rank counts
# interleaved so that machine noise hits them alike. Two budgets:
#   - strong: one total budget of EVALS fits shared out over the ranks. Printed:
#     the median screening fits/s of the whole job, the median wall time of the
#     job (reference build and final refits, rank 0's alone, included), and the
#     front's error at the issue's cost levels (deterministic: one value per
#     rank count) — does the front improve with islands at equal fits?
#   - weak: PER fits on every rank. A search's fits/s falls as it goes on (the
#     enumerated small trees come first, the archive then breeds larger forms),
#     so islands that each run a shorter search fit faster per fit: the strong
#     figures mix that with the parallel speed-up. At equal fits per island the
#     fits/s is the machine's own scaling (--enum-max 1000 per rank, so that
#     every island enumerates as many trees as the one rank does).
#   - split: the strong budget with --split-fits, the ranks running one search
#     and each fitting its share of every step: the front is one process's
#     (checked, byte for byte), so the speed-up is the whole story; every rank
#     still makes every candidate, the part that does not
#     shrink with the ranks (Amdahl's serial fraction, printed from 2 ranks);
#     and the certified enumeration alone (ENUM_SIZE nodes), whose
#     fingerprints the ranks split too (fit/search/generate.c, look_ahead).
# Then the bytes of one migration and of the final merge, and the merge's time.
# README "On a cluster" extrapolates these to 64 and 1,024 ranks.
# usage: sh analysis/bench/bench_search_mpi.sh build/brdfkit-mpi build/brdfkit
set -u
BKM=${1:?usage: bench_search_mpi.sh build/brdfkit-mpi build/brdfkit}
BK=${2:?usage: bench_search_mpi.sh build/brdfkit-mpi build/brdfkit}
EVALS=${EVALS:-20000}
PER=${PER:-6000}
REPS=${REPS:-3}
ENUM_SIZE=${ENUM_SIZE:-6}   # vf2d to 6 nodes: 48,804 unique forms fitted
ENUM_EVALS=${ENUM_EVALS:-49000}
T=$(mktemp -d /tmp/bk_bench_mpi_XXXXXX)
trap 'rm -rf "$T"' EXIT
MPIRUN="mpirun"
if mpirun --version 2>/dev/null | grep -q "Open MPI"; then
	MPIRUN="mpirun --oversubscribe"
	export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi
ARGS="--target vf2d --objective max --threads 1 --nx 64 --nr 64"

echo "bench_search_mpi: vf2d, --objective max, 1 thread per rank, $(nproc) cores; strong: $EVALS fits in all;" \
	"weak: $PER fits per rank; median of $REPS runs, rank counts interleaved"
# run NAME NP EVALS [OPTIONS]: one job, its stderr in $T/e.NAME, its wall seconds in $T/w.NAME
run() {
	t0=$(date +%s.%N)
	if [ "$2" = 1 ]; then # one rank is brdfkit itself: no MPI at all
		$BK search $ARGS --evals "$3" ${4:-} --out "$T/o" >/dev/null 2>"$T/e.$1" || { cat "$T/e.$1"; exit 1; }
	else
		$MPIRUN -np "$2" "$BKM" search $ARGS --evals "$3" ${4:-} --out "$T/o" >/dev/null 2>"$T/e.$1" ||
			{ cat "$T/e.$1"; exit 1; }
	fi
	echo "$(date +%s.%N) $t0" | awk '{ print $1 - $2 }' >"$T/w.$1"
	rm -rf "$T/o.keep"; mv "$T/o" "$T/o.keep"
}
for rep in $(seq 1 "$REPS"); do
	for np in 1 2 4; do
		run "s$np.$rep" "$np" "$EVALS"
		cp "$T/o.keep/front.csv" "$T/front$np.csv"
		run "w$np.$rep" "$np" "$((PER * np))" "--enum-max $((1000 * np))"
		if [ "$np" -gt 1 ]; then
			run "p$np.$rep" "$np" "$EVALS" --split-fits
			grep -v '^# command' "$T/o.keep/front.csv" >"$T/split$np.csv"
		fi
	done
	# the certified enumeration alone (to ENUM_SIZE nodes, its fits and no
	# more), one process and split over 2 ranks
	for np in 1 2; do
		run "q$np.$rep" "$np" "$ENUM_EVALS" "--enum-size $ENUM_SIZE --enum-max 1000000$([ "$np" = 1 ] || echo ' --split-fits')"
		grep -v '^# command' "$T/o.keep/front.csv" >"$T/enum$np.csv"
	done
done

# the last progress line of a run: "..., N fits/s, ..."
rate() { grep -o '[0-9.]* fits/s' "$1" | tail -1 | cut -d' ' -f1; }
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
# the front's error column is named for the objective: find it by name
best() { awk -F, -v c="$2" '/^#/ { next } !h { for (i = 1; i <= NF; i++) { if ($i == "cost") ci = i; if ($i == "max_abs") ei = i }; h = 1; next }
	$ci + 0 <= c { if (b == "" || $ei + 0 < b) b = $ei + 0 } END { print (b == "" ? "-" : b) }' "$1"; }
med() { for rep in $(seq 1 "$REPS"); do $1 "$T/$2.$rep"; done | median; }
wall() { cat "$(echo "$1" | sed 's|/e\.|/w.|')"; }
merge_s() { grep -o 'bytes, [0-9.]* s' "$1" | awk '{ print $2 }'; }

printf '\n  strong: %s fits in all\n  %-6s %10s %9s %9s %14s %15s %14s %10s\n' "$EVALS" ranks "fits/s" ratio "wall s" \
	"max @ cost<=8" "max @ cost<=12" "merge bytes" "merge s"
base=""
for np in 1 2 4; do
	r=$(med rate "e.s$np")
	[ -n "$base" ] || base=$r
	mb=$(grep -o 'merged [0-9]* islands: [0-9]* bytes' "$T/e.s$np.1" | awk '{ print $4 }')
	ms=$(med merge_s "e.s$np")
	printf '  %-6s %10.0f %8.2fx %9.1f %14s %15s %14s %10s\n' "$np" "$r" "$(echo "$r $base" | awk '{ print $1 / $2 }')" \
		"$(med wall "e.s$np")" "$(best "$T/front$np.csv" 8)" "$(best "$T/front$np.csv" 12)" "${mb:--}" "${ms:--}"
done
printf '\n  split (--split-fits): %s fits of one search\n  %-6s %10s %9s %9s %22s\n' "$EVALS" ranks "fits/s" speed-up \
	"wall s" "front.csv"
grep -v '^# command' "$T/front1.csv" >"$T/split1.csv"
base=$(med rate "e.s1")
for np in 2 4; do
	r=$(med rate "e.p$np")
	printf '  %-6s %10.0f %8.2fx %9.1f %22s\n' "$np" "$r" "$(echo "$r $base" | awk '{ print $1 / $2 }')" \
		"$(med wall "e.p$np")" "$(cmp -s "$T/split1.csv" "$T/split$np.csv" && echo "one process's" || echo "DIFFERS from 1 rank's")"
done
echo "$(med rate e.p2) $base" | awk '{ s = $1 / $2; f = 2 / s - 1; printf "  serial fraction from 2 ranks: %.3f (Amdahl: at most %.1fx; 64 ranks %.1fx)\n", f, 1 / f, 1 / (f + (1 - f) / 64) }'
r1=$(med rate e.q1) r2=$(med rate e.q2)
printf '\n  split in the certified enumeration alone (to %s nodes, %s fits): 1 rank %.0f fits/s, 2 ranks %.0f, %.2fx; front.csv %s\n' \
	"$ENUM_SIZE" "$ENUM_EVALS" "$r1" "$r2" "$(echo "$r2 $r1" | awk '{ print $1 / $2 }')" \
	"$(cmp -s "$T/enum1.csv" "$T/enum2.csv" && echo "one process's" || echo "DIFFERS from 1 rank's")"
grep -o 'up to [0-9]* nodes' "$T/enum2.csv" | head -1 | sed 's/^/  certificate: every unique form /'
echo "$r2 $r1" | awk '{ s = $1 / $2; f = 2 / s - 1; printf "  serial fraction from 2 ranks: %.3f (every rank draws every tree: Amdahl at most %.1fx)\n", f, 1 / f }'

printf '\n  weak: %s fits per rank (fits/s of the search phase; fits per wall second of the whole job)\n  %-6s %10s %9s %9s %13s %9s\n' "$PER" ranks "fits/s" speed-up "wall s" "fits/wall-s" speed-up
base="" wbase=""
for np in 1 2 4; do
	r=$(med rate "e.w$np")
	[ -n "$base" ] || base=$r
	w=$(med wall "e.w$np")
	fw=$(echo "$PER $np $w" | awk '{ print $1 * $2 / $3 }')
	[ -n "$wbase" ] || wbase=$fw
	printf '  %-6s %10.0f %8.2fx %9.1f %13.0f %8.2fx\n' "$np" "$r" "$(echo "$r $base" | awk '{ print $1 / $2 }')" "$w" \
		"$fw" "$(echo "$fw $wbase" | awk '{ print $1 / $2 }')"
done

# the merge with --merge-fronts: the islands' fronts alone (the same front.csv)
run mf 4 "$EVALS" --merge-fronts
grep -v '^#' "$T/front4.csv" >"$T/fa"; grep -v '^#' "$T/o.keep/front.csv" >"$T/fb"
printf '  4, --merge-fronts: merge %s bytes, %s s; front.csv %s\n' \
	"$(grep -o 'merged [0-9]* islands (fronts): [0-9]* bytes' "$T/e.mf" | awk '{ print $5 }')" "$(merge_s "$T/e.mf")" \
	"$(cmp -s "$T/fa" "$T/fb" && echo "the same as the full merge's" || echo "DIFFERS from the full merge's")"

# one migration: the text of --migrants (8) front members, measured on a front
$BK search --target vf2d --objective max --evals 3000 --threads 1 --nx 32 --nr 32 --checkpoint "$T/ck" \
	--out "$T/m" >/dev/null 2>&1
per=$(awk '/^c / { n++; b += length($0) + 1; getline; b += length($0) + 1 } END { printf "%.0f", b / n }' "$T/ck")
echo
echo "  one candidate as text: ~$per bytes; one migration: 8 members, ~$((8 * per)) bytes and 2 messages per rank"
echo "  (its size, then the bytes) to one neighbour; per round also 4 allreduces of one word (done, stop,"
echo "  failure, the fit count); the final merge sends every island's candidates (--merge-fronts: its front)"
echo "  to rank 0, one rank at a time"
