/*
 * refit.h — the one refit preset: how compare, search and scene refit a form
 * on full samples (its constants freed from a start, several starts, the
 * digits its standard errors justify). One iteration cap for all three:
 * a solve cut off at its limit stops at a point that depends on the CPU's
 * libm (1-ulp differences in exp2 walk it), so a result would not reproduce
 * across machines; the refits of make results converge within 250
 * (env_narkowicz2014_lazarov_g1mr needs 216), 2000 leaves room.
 */
#ifndef FIT_SEARCH_REFIT_H
#define FIT_SEARCH_REFIT_H

#include "fit.h"

/* Iterations of the refit's solve, and of the albedo minimax that may follow
 * it (a polish from the refit's point: fit/albfit.h). */
#define BK_REFIT_MAX_ITERATIONS 2000
#define BK_REFIT_ALBEDO_ITERATIONS 500
/* Deterministic starts of the refit and their seed. */
#define BK_REFIT_STARTS 2
#define BK_REFIT_SEED 1

/* Fills *sp for a refit of form a (and b, B of a split pair, or NULL) on s
 * from the constants start[0..BK_MAX_PARAMS): np the larger of the forms'
 * parameter counts, bounds free, nothing held, the caps above, digits
 * BK_FIT_DIGITS_SE. relative and minimax are left 0 (the caller's). */
void bk_refit_spec(bk_fit_spec *sp, const bk_samples *s, const bk_form *a, const bk_form *b, const double *start);

/* The solver options of the albedo minimax after a refit. */
bk_fit_options bk_refit_albedo_options(void);

/* The values of sp's forms at constants p on sp's samples, each component
 * (A, B of a pair) by its own form, evaluated in precision prec: the one
 * per-component evaluation of a refitted member. BK_F16 takes, per sample,
 * the order of the form's mads farther from the target's value
 * (bk_form_eval_half_vs), so that a half error holds whichever order a
 * driver takes. 0, or -1 when a form does not evaluate. */
int bk_refit_values(const bk_fit_spec *sp, const double *p, bk_precision prec, double *v);

#endif
