/*
 * albfit.h — fitting a form's constants to the directional albedo it gives,
 * not to its values: for vf and spec the error that matters in a render is
 * the albedo of each (NoV, r) cell, e_c = Σ_{i in c} measure_i (f_i - y_i)
 * (fit_stats.c measures the same), and a least-squares fit of the values,
 * weighted by D NoL dω, does not minimise it (the talk's forms trade grazing
 * Fresnel for the highlight). Here the residuals are the cells' e_c, in least
 * squares or in Lawson's minimax (their max, the --objective albedo of the
 * search), solved with the same bridge as every fit.
 */
#ifndef FIT_ALBFIT_H
#define FIT_ALBFIT_H

#include "brdf.h"
#include "solver.h"
#include "target.h"

typedef struct bk_albfit bk_albfit;

/* The cells of s (the samples of each cell contiguous, as target.c builds
 * vf and spec) for form f with np parameters. NULL if s has no measure, its
 * cells are not contiguous, or out of memory. */
bk_albfit *bk_albfit_new(const bk_samples *s, const bk_form *f, int np);
void bk_albfit_free(bk_albfit *a);

/* Fits p (np values, the start on entry): least squares of the cells' albedo
 * errors, or with minimax their max by Lawson's reweighting (the point with
 * the smallest max seen is kept, the start's included). opt: the solver's
 * options. *max_err (may be NULL): the max |e_c| at the point returned.
 * Returns 0, or -1 if the form could not be evaluated at the start. */
int bk_albfit_run(bk_albfit *a, double *p, int minimax, const bk_fit_options *opt, double *max_err);

/* The max |e_c| at p (HUGE_VAL where the form is not finite). */
double bk_albfit_max(bk_albfit *a, const double *p);

#endif
