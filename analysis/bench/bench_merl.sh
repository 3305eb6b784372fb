#!/bin/sh
# bench_merl.sh — the figure for --target merl: a MERL-format file of
# 90x90x180 bins a channel (1.46 million; about 1.1 million above the horizon
# and measured) loads and fits in under 10 s on 2 cores. The file is written
# by build/mkmerl from brdf/'s exact GGX x correlated Smith x Schlick, and the
# fit (4 starts, the default) recovers its r = 0.4 and f0 = 0.9 (red).
# usage: sh analysis/bench/bench_merl.sh build/brdfkit build/mkmerl
set -u
BK=${1:?usage: bench_merl.sh path/to/brdfkit path/to/mkmerl}
MK=${2:?usage: bench_merl.sh path/to/brdfkit path/to/mkmerl}
T=$(mktemp -d /tmp/bk_bench_merl_XXXXXX)
trap 'rm -rf "$T"' EXIT
"$MK" "$T/m.binary" 0.4 0.9 0.6 0.3 || exit 1
t0=$(date +%s.%N)
"$BK" fit --target merl --target-file "$T/m.binary" --channel r --quiet --out "$T/o" \
	--form 'D_ggx(NoH, p0*p0) * V_smith_ggx_correlated(NoV, NoL, p0*p0) * F_schlick(p1, 1, LoH)' p0=0.6 p1=0.5 \
	>"$T/log" 2>&1 || { cat "$T/log"; exit 1; }
t1=$(date +%s.%N)
awk -v a="$t0" -v b="$t1" 'BEGIN { s = b - a; printf "bench_merl: MERL file loaded and fitted (4 starts) in %.2f s (goal < 10 s)\n", s; exit !(s < 10) }'
grep -E '^  p[01] ' "$T/log"
