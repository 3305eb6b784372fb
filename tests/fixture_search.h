/*
 * fixture_search.h — the planted samples and plain options the search's
 * unit tests start from (tests/test_search_*.c, test_islands.c, ...): one
 * place, so that every test builds its target the same checked way.
 */
#ifndef TESTS_FIXTURE_SEARCH_H
#define TESTS_FIXTURE_SEARCH_H

#include "search.h"

/* The form target `form` (no parameters) on nx cell centres of LoH in
 * [loh_lo, 1], and of r in [0, 1] when with_r (the form then reads r).
 * Fails the calling test when the target cannot be built. */
void fx_planted(const char *form, double loh_lo, int with_r, int nx, bk_samples *s);

/* Defaults for a plain search of sm: the default operations over inputs
 * (bits of bk_input), at most max_params constants and max_size nodes. */
void fx_plain_options(bk_search_options *o, const bk_samples *sm, unsigned inputs, int max_params, int max_size);

#endif
