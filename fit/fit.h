/*
 * fit.h — fitting a form (or a pair of forms sharing parameters) to a target's
 * samples with the Ceres bridge: several deterministic starts, bounds,
 * robust losses, a minimax objective, standard errors, identifiability, and
 * rounding the constants to shader literals.
 */
#ifndef FIT_FIT_H
#define FIT_FIT_H

#include "brdf.h"
#include "solver.h"
#include "target.h"

typedef struct bk_fit_spec {
	const bk_samples *s;
	const bk_form *form[2];  /* form[1]: B of a split-sum fit (s->ncomp == 2) */
	int np;                  /* parameters p0..p(np-1) */
	double start[BK_MAX_PARAMS];
	double lower[BK_MAX_PARAMS], upper[BK_MAX_PARAMS];
	int hold[BK_MAX_PARAMS];  /* 1: keep at its start value */
	int relative;            /* residuals (f - y)/|y| instead of f - y */
	const bk_form *weight;   /* user weight formula, or NULL */
	bk_fit_options opt;
	int starts;              /* deterministic starts, >= 1 */
	unsigned long seed;
	int minimax;             /* Lawson's iteratively reweighted least squares */
	int digits;              /* 0: none; N > 0: significant digits; -1: fp16 values */
} bk_fit_spec;

/* Relative error is reported where the target is at least this fraction of its
 * largest value: below, it measures nothing a viewer sees (B -> 0 at NoV = 1
 * would put it at 1e8) */
#define BK_REL_METRIC 1e-3

typedef struct bk_fit_metrics {
	double cost, rmse, weighted_rmse, max_abs, albedo_max_abs; /* albedo: NaN if none */
	double max_rel; /* over samples with |y| >= BK_REL_METRIC of the largest |y| */
	double comp_rmse[3], comp_max_abs[3]; /* env split: A, B, A + B */
	size_t nonfinite;                     /* samples where the form is not finite */
} bk_fit_metrics;

typedef struct bk_fit_result {
	double p[BK_MAX_PARAMS];
	double se[BK_MAX_PARAMS];          /* standard errors; NaN where not identifiable */
	int unidentified[BK_MAX_PARAMS];   /* 1: in the null space of the Jacobian */
	bk_fit_summary summary;            /* of the best start (and later stages) */
	double start_cost_min, start_cost_max; /* spread of final costs over the starts */
	int starts_failed;
	bk_fit_metrics fitted, published, before_digits;
	double unrounded[BK_MAX_PARAMS];
	char message[512];                 /* why a fit failed */
} bk_fit_result;

/* Metrics of the forms with parameters p on the samples. */
void bk_fit_evaluate(const bk_fit_spec *spec, const double *p, bk_fit_metrics *m);

/* The signed error of each plane cell (approximation - target): the sample's
 * error for one-sample cells, the albedo error for vf/spec, the A + B error
 * for a split env fit, the error at the last f0 for an env form in f0.
 * cells must hold plane_nx * plane_ny values; cells without samples are NaN. */
void bk_fit_plane_error(const bk_fit_spec *spec, const double *p, double *cells);

/* Samples where a form is not finite but the target is (where: the first). */
size_t bk_fit_nonfinite(const bk_fit_spec *spec, const double *p, char *where, size_t len);
/* Points on the closed edges of the target's plane where a form is not finite. */
int bk_fit_edge_check(const bk_fit_spec *spec, const double *p, char *where, size_t len);

/* Returns 0 (converged), 1 (ran but did not converge), -1 (failed: message). */
int bk_fit_run(const bk_fit_spec *spec, bk_fit_result *res);

#endif
