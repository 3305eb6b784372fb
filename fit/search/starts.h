/*
 * starts.h — where a screening fit starts its constants. Start k of a
 * candidate:
 *   k = 0: all ones (most constants of a shading form are O(1), and a form
 *          the enumeration grows keeps its scale in one linear parameter);
 *   k = 1: all 0.1 (a small constant beside an input: r + 0.1, LoH^2 + k);
 *   k >= 2: a random start, each constant a sign and a magnitude drawn
 *          log-uniformly in [1e-2, 1e2] (BK_START_DECADES decades either side
 *          of 1), so that a right structure whose minimum lies far from the
 *          first two starts (a constant of -5.5, of 1e3, a pair of opposite
 *          signs) still gets a fit that can reach it.
 * The random starts are a function of (the search's seed, the candidate's
 * canonical text, k) alone — splitmix64 of FNV-1a — so a candidate starts at
 * the same values whatever thread fits it, and a run gives the same bytes on
 * any thread count.
 */
#ifndef FIT_SEARCH_STARTS_H
#define FIT_SEARCH_STARTS_H

#include <stdint.h>

#define BK_START_DECADES 2

/* Writes start k of the candidate of text (NUL-terminated; a pair's A and B
 * joined by the caller as it hashes them) into p[0..np). */
void bk_search_start(uint64_t seed, const char *text, int k, int np, double *p);

#endif
