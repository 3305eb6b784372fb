/*
 * unique.h — semantically unique candidates (internal to the search): the
 * enumeration fits one model once, however many spellings of it the grammar
 * has. Two candidates are one model when their forms give the same values
 * at UNIQUE_PROBES of the screening samples at each of UNIQUE_VECTORS fixed
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
 * fingerprint hashes, for each of UNIQUE_VECTORS parameter vectors, each
 * probe's value rounded to 32 significant bits, its class (NaN, +inf,
 * -inf), and the number of parameters. The vectors give every parameter a
 * value in (0, 1), one in (1, 2), one negative and one above 2, so that a
 * gate (max(p0, r), saturate(p1 / r), sqrt(p0 - r)) is probed open, shut
 * and with its break inside the inputs' range. The probes are 64 screening
 * samples spread over every input (unique.c: a lattice over the sample
 * index whose stride is chosen for the most distinct input values). Two
 * forms that differ only by rounding (a + (b + c) against (a + b) + c) may
 * land either side of a rounding boundary: they are then fitted both, which
 * costs a fit and loses nothing. A false twin needs two different functions
 * of the parameters to agree to 32 bits at 4 x 64 points: the fingerprint
 * is of the family's function of its parameters, not of one fit.
 *
 * How often that happens is measured, not argued: build/bench_enum --audit
 * checks every twin against the form it was taken for at every screening
 * sample and at eight more vectors drawn in (-3, 3), and make bench prints
 * the count. Two mechanisms it found are gone: probes at sample i n / 64
 * saw 2 of env's 16 NoV values and 2 of vf2d's 32 LoH values, so
 * p0*saturate(rcp(NoV) - NoV) was taken for p0 (it is 1 for NoV <= 0.618
 * only); and three vectors whose rotation never put p1 in (0, 1), so
 * saturate(p1 / r) was taken for saturate(p1 / LoH). To 6 nodes the audit
 * finds 171 of vf2d's 71,719 twins false, 314 of f's 32,807 and 361 of
 * env's 215,692; with the probes and vectors before, 1,768 of 72,512, 848
 * of 33,181 and 4,290 of 217,893 (the same audit: its eight random vectors
 * the same). What is left: gates of two parameters whose combination never
 * falls among the inputs at one vector (saturate(p1 - (p2 + r)) taken for
 * saturate(p1 - (p2 + LoH)); many, as max(p1, max(p2, r)), spell a cheaper
 * model that is fitted, max(p, r)), and gates of the inputs alone that
 * shut on a few samples no probe is at (max(LoH, sq(LoH - a)) taken for
 * LoH). Tried and not taken: 128 probes instead of 64 (vf2d's 177 to
 * 157, under an audit with other vectors), and a fifth vector with every
 * parameter in (0, 1) (vf2d's 171 to 119, f's 314 to 282), each for a
 * quarter to twice the fingerprint's time.
 *
 * What it does not see: reparametrisations (p0*(x + p1) against p0*x + p1
 * are one model with other constants: different values at the same vector).
 * Both are fitted; the counts in bk_search_unique_counts call them unique.
 *
 * Cost: 6.4 to 9.5 us a candidate (the form evaluated 4 x 64 times; an
 * enumerated one is parsed once for its cost and this), against 40 to 100 us
 * of CPU for a screening fit (build/bench_enum), 17 to 38 % of an
 * enumeration's CPU time (most on f, whose fits of 64 samples are cheapest).
 */
#ifndef FIT_SEARCH_UNIQUE_H
#define FIT_SEARCH_UNIQUE_H

#include "search/search_int.h"

#include <stdio.h>

/* The screening samples a fingerprint reads (spread over them: unique.c). */
#define UNIQUE_PROBES 64

/* The probes of s's screening samples, made once (s->uq). 0, or -1 when out
 * of memory. */
int bk_unique_init(bk_search *s);
void bk_unique_free(bk_search *s);

/* One value as the fingerprint hashes it: NaN, +inf, -inf and zero (either
 * sign) as classes of their own, any other value rounded to 32 significant
 * bits, half to even (frexp's m times 2^32, nearbyint), with its exponent. */
uint64_t bk_unique_quantum(double v);

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
