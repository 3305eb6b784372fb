/*
 * unique.h — semantically unique candidates (internal to the search): the
 * enumeration fits one model once, however many spellings of it the grammar
 * has. Two candidates are one model when their forms give the same values
 * at UNIQUE_PROBES of the screening samples at each of three fixed
 * parameter vectors (the fingerprint below); the cheaper is fitted (the
 * earlier at equal cost), the others are counted as twins and never fitted.
 *
 * Why values and not rules: canonical rules (fit/expr.h) already make one
 * text of x*1, a+b and b+a, p0*p1; what is left are identities over the
 * domain (saturate(r) is r on [0, 1], max(1, NoH) is 1, rsqrt(a) is 1/r),
 * about 28 % of the fits the search made (stop 36's measurement), which no
 * local rule sees. ESR (Bartlett et al. 2023) dedups its functions the same
 * way, numerically, after its rules.
 *
 * What "same values" means, and why it is safe for the certificate (a form
 * left out as a twin must not be a better model than its twin): the
 * fingerprint hashes, for each of three parameter vectors, each probe's
 * value rounded to 32 significant bits, its class (NaN, +inf, -inf), and the
 * number of parameters. The three vectors give every parameter one value in
 * (0, 1), one above 1 and one negative, so that a branch (max(p0, r),
 * sqrt(p0 - r)) taken at one is left at another. Two forms that differ only
 * by rounding (a + (b + c) against (a + b) + c) may land either side of a
 * rounding boundary: they are then fitted both, which costs a fit and loses
 * nothing. A false twin needs two different functions of the parameters to
 * agree to 32 bits at 3 x 64 points: the fingerprint is of the family's
 * function of its parameters, not of one fit. Those points are fewer
 * distinct inputs than 64 where the screening grid's size is a multiple of
 * 64 (sample i n / 64 steps over the fastest axis): env's 512 samples give
 * NoV at 2 of its 16 values (r at all 16), vf2d's 1,024 LoH at 2 of 32, vf's
 * 1,617 cover 8 NoV x 8 r. Two forms that differ only between those two
 * values (a min or max whose break falls there at all three vectors) would
 * be taken for one, and such pairs exist: with probes at a golden-ratio
 * stride coprime to n beside these (tried, not kept), and each pair that
 * the second probes split evaluated at 4,000 random points of the domain
 * and four random parameter vectors, env to 5 nodes has at least 135
 * false twins (of 20,210 twins; 87 more splits were rounding) and vf2d to
 * 6 nodes at least 887 (of 73,110; 9 rounding). They are gates that are
 * open at both probed values and shut between or beyond them:
 * p0*saturate(rcp(NoV) - NoV) taken for p0 (it is 1 for NoV <= 0.618 only),
 * p0*max(rcp(NoV), exp2(NoV)) for p0/NoV, p0*saturate(rcp(LoH) - sq(LoH))
 * for p0. So the certificate's "every unique form up to N nodes fitted"
 * misses these on env and vf2d (not on f, whose 64 samples are all
 * probes). Well-spread probes would fit them, and would move every
 * committed front and the enumeration's fit counts that make results'
 * budgets are set from (Makefile ENUM_*), so they wait for a make results
 * of their own.
 *
 * What it does not see: reparametrisations (p0*(x + p1) against p0*x + p1
 * are one model with other constants: different values at the same vector).
 * Both are fitted; the counts in bk_search_unique_counts call them unique.
 *
 * Cost: 3.6 to 7.5 us a candidate (the form evaluated 3 x 64 times; an
 * enumerated one is parsed once for its cost and this), against 40 to 100 us
 * of CPU for a screening fit (build/bench_enum).
 */
#ifndef FIT_SEARCH_UNIQUE_H
#define FIT_SEARCH_UNIQUE_H

#include "search/search_int.h"

#include <stdio.h>

/* The screening samples a fingerprint reads (spread evenly over them). */
#define UNIQUE_PROBES 64

/* The probes of s's screening samples, made once (s->uq). 0, or -1 when out
 * of memory. */
int bk_unique_init(bk_search *s);
void bk_unique_free(bk_search *s);

/* The fingerprint of the forms a (and b, a pair's B; NULL otherwise), or 0
 * when one does not evaluate (never a real fingerprint: those are made
 * non-zero). The generation parses a candidate once, for its cost, its
 * fingerprint, its fit and the front's refit (cand.h). */
uint64_t bk_unique_fingerprint_of(const bk_search *s, const bk_form *a, const bk_form *b);

/* The same of texts (0 also when one does not parse): the tests' way in. */
uint64_t bk_unique_fingerprint(const bk_search *s, const char *a, const char *b);

/* Whether a candidate of fingerprint fp and cost is a twin of one fitted
 * before at no greater cost: 1 (it is: not to be fitted), 0 (it is not; it is
 * now the model's fitted spelling), -1 when out of memory. */
int bk_unique_twin(bk_search *s, uint64_t fp, double cost);

/* The enumeration's counts, its complete size and the twins' fingerprints,
 * as lines of a checkpoint (state.c), and read back: 0, or -1 with what is
 * wrong in why. */
void bk_unique_save(const bk_search *s, FILE *f);
int bk_unique_load(bk_search *s, FILE *f, char *why, size_t len);

#endif
