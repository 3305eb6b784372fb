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

/* For text (one form, not a split pair) at parameters p on the samples s,
 * evaluated in double precision: repeatedly, the first node (prefix order)
 * that is
 *   max(x, y) with x >= y at every sample (then x; y >= x: y),
 *   min(x, y) with x <= y at every sample (then x; y <= x: y),
 *   clamp(x, lo, hi) with lo <= x <= hi at every sample (then x),
 *   saturate(x) with 0 <= x <= 1 at every sample (then x),
 * every compared value finite, is replaced by the side kept. Then the
 * parameters are renumbered p0, p1, ... in order of first appearance, their
 * values in pout (BK_MAX_PARAMS). Returns how many nodes were replaced (0:
 * out and pout untouched), the new text in out (len bytes), or -1 when the
 * form does not parse, its tree does not fit bk_expr, an evaluation fails,
 * or out is too small. */
int bk_prune_dead(const char *text, const double *p, const bk_samples *s, char *out, size_t len, double *pout);

#endif
