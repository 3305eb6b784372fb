/*
 * prune.h — dead branches of a fitted form: a min, max, clamp or saturate
 * one of whose sides never wins on the target's samples at the fitted
 * constants (max(p0, max(1.414, x)) with p0 = 1: p0 never wins) is replaced
 * by the side that always does, and the parameters no longer read are
 * dropped. The front's refit (analysis/search_front.c) refits the result and
 * keeps it where its error is no worse: the same values at fewer ops.
 */
#ifndef FIT_SEARCH_PRUNE_H
#define FIT_SEARCH_PRUNE_H

#include "target.h"

#include <stddef.h>

/* For text (one form) at parameters p on the samples s, evaluated in
 * double precision: repeatedly, the first node (prefix order) that is
 *   max(x, y) with x >= y at every sample (then x; y >= x: y),
 *   min(x, y) with x <= y at every sample (then x; y <= x: y),
 *   clamp(x, lo, hi) with lo <= x <= hi at every sample (then x),
 *   saturate(x) with 0 <= x <= 1 at every sample (then x),
 *   mix(x, y, t) with t = 0 at every sample (then x; t = 1: y, which
 *     x + (y - x) is up to its rounding),
 * every compared value finite (mix: x and y too), is replaced by the side kept. Then the
 * parameters are renumbered p0, p1, ... in order of first appearance, their
 * values in pout (BK_MAX_PARAMS). Returns how many nodes were replaced (0:
 * out and pout untouched), the new text in out (len bytes), or -1 when the
 * form does not parse, its tree does not fit bk_expr, an evaluation fails,
 * or out is too small. */
int bk_prune_dead(const char *text, const double *p, const bk_samples *s, char *out, size_t len, double *pout);

/* The same for a split pair f0 A + B (text_b not NULL): A judged on the
 * samples of s's first component, B on the rest (as the refit evaluates a
 * pair: fit/search/refit.h), the parameters, which the two forms share,
 * renumbered over A then B. out_a and out_b hold len bytes each; both are
 * written when anything was replaced. text_b NULL: bk_prune_dead. */
int bk_prune_dead_pair(const char *text_a, const char *text_b, const double *p, const bk_samples *s, char *out_a,
                       char *out_b, size_t len, double *pout);

/* The same for forms already parsed (a front member's: not parsed again);
 * fb NULL for one form. */
int bk_prune_dead_forms(const bk_form *fa, const bk_form *fb, const double *p, const bk_samples *s, char *out_a,
                        char *out_b, size_t len, double *pout);

#endif
