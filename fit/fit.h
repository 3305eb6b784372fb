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

#ifdef __cplusplus
extern "C" { /* C linkage for a C++ program (tests/install.sh links one) */
#endif

typedef struct bk_fit_spec {
	const bk_samples *s;     /* the target's samples (target.h, bk_target_build) */
	const bk_form *form[2];  /* form[0]: the form fitted (A of a split-sum fit);
	                            form[1]: B, read only where s->ncomp == 2 */
	int np;                  /* parameters p0..p(np-1) (bk_form_nparams), <= BK_MAX_PARAMS */
	double start[BK_MAX_PARAMS];                      /* start 0's point; later starts move it */
	double lower[BK_MAX_PARAMS], upper[BK_MAX_PARAMS]; /* bounds (+-HUGE_VAL: none) */
	int hold[BK_MAX_PARAMS];  /* 1: keep at its start value */
	int relative;            /* residuals (f - y)/|y| instead of f - y */
	const bk_form *weight;   /* user weight formula, or NULL */
	bk_fit_options opt;      /* the solver's options (solver.h) */
	int starts;              /* deterministic starts, >= 1 */
	unsigned long seed;      /* of the starts after the first (fit.c, start_point) */
	int minimax;             /* Lawson's iteratively reweighted least squares */
	int digits;              /* 0: none; N > 0: significant digits; -1: fp16 values;
	                            BK_FIT_DIGITS_SE: the digits the standard errors justify */
} bk_fit_spec;

/* digits: round each fitted constant to the decade at or below 1/100 of its
 * standard error (fit.c, round_to_se), without refitting: the digits a
 * report shows then no longer depend on the CPU's libm. */
#define BK_FIT_DIGITS_SE (-2)

/* Relative error is reported where the target is at least this fraction of its
 * largest value: below, it measures nothing a viewer sees (B -> 0 at NoV = 1
 * would put it at 1e8) */
#define BK_REL_METRIC 1e-3

/* First-order optimality test (fit_stats.c, bk_fit_optimality). At the point
 * returned, with s the residuals as Ceres sees them (weighted, relative,
 * robustified) and J their Jacobian, g = Jᵀs is the gradient of the cost
 * 1/2 ||s||². By Cauchy-Schwarz |g_j| <= ||J_j|| ||s||, so
 *     cos_j = |g_j| / (||J_j|| ||s||)  in [0, 1]
 * is scale-free (units of p_j and of the data cancel), and cos_j² · cost is
 * the cost that re-optimising p_j alone would still remove (Gauss-Newton
 * model: g_j² / (2 ||J_j||²)). The test is cos_j <= BK_FIT_GRAD_TOL = 1e-4:
 * moving one parameter could lower the cost by at most 1e-8 of itself.
 * Why 1e-4:
 *   - a legitimate stop passes with a wide margin. Ceres stops when a step
 *     changes the cost by <= ftol' cost (the bridge asks ftol' = ftol/100 =
 *     1e-14 by default); near a minimum that step is the Gauss-Newton one,
 *     which lowers the cost by 1/2 gᵀ(JᵀJ)⁻¹g, and |g_j| <= ||J_j||
 *     sqrt(gᵀ(JᵀJ)⁻¹g) (Cauchy-Schwarz in the JᵀJ norm), so cos_j <=
 *     sqrt(ftol') = 1e-7. Rounding of a cost C > 0 pins the gradient to
 *     sqrt(2 k eps C h) (test_solver.c), cos_j ~ sqrt(k eps) ~ 1e-7, k = 64;
 *   - a wrong stop (a damped step too short to make progress, Ceres' absolute
 *     gradient_tolerance on a badly scaled problem, a function_tolerance
 *     looser than 1e-6) leaves cos_j far above it;
 * and the make results fits that converge all pass with cos_j <= 1.1e-7.
 * Two floors, for exact data where ||s|| -> 0 and its direction is noise, make
 * the test |g_j| <= ||J_j|| (tol ||s|| + floor) with
 *     floor = ptol Σ_j ||J_j|| |p_j| + 1e-12 ||ŷ||
 * (free j; ptol: the options' parameter_tolerance; ŷ: the target as the
 * residuals weight it). The first is how far from an exact fit a stop on
 * Ceres' parameter tolerance legitimately leaves the residuals, a step of ptol
 * relative in each parameter moving s by at most that (triangle inequality);
 * relative per parameter, so that a parameter of size 1e-10 is not forgiven
 * a step of 1e-10. The second is rounding: residuals below 1e-12 of the
 * target are an exact fit to what a double evaluation of a form guarantees.
 * grad_rel_j = |g_j| / (||J_j|| (||s|| + floor / tol)): the test is
 * grad_rel_j <= tol. A fit that fails it after Ceres reported CONVERGENCE is
 * re-solved from there (at most twice, fit.c POLISH), then reported as
 * NO_CONVERGENCE with the parameters named in the message. */
#define BK_FIT_GRAD_TOL 1e-4

/* Two starts whose final costs agree to BK_FIT_COST_TIE (relative) are a tie,
 * and the earlier start wins (start 0 is the given or published point). The
 * last digits of a cost follow the CPU's libm (glibc picks FMA or non-FMA exp,
 * log, pow at run time) and where Ceres stopped within its function tolerance
 * (1e-12 relative): choosing between two minima on those digits made the
 * answer depend on the machine. 1e-8 is far above both and far below any
 * difference that matters in a fit. */
#define BK_FIT_COST_TIE 1e-8
#define BK_FIT_EXACT 1e-12 /* the rounding floor above, relative to ||ŷ|| */

/* Ill-conditioning: cond(JᵀJ) of the column-scaled Jacobian (unit-norm
 * columns: the number no longer depends on the parameters' units, and is
 * within a factor np of the best diagonal scaling, van der Sluis 1969) above
 * BK_FIT_COND_MAX = 1 / BK_FIT_GRAD_TOL² = 1e8 is flagged in the message, and
 * the parameters of the weak directions in collinear[]. Why 1e8:
 *   - the optimality test then stops meaning "at the minimum": with every
 *     cos_j <= tol the cost is within n tol² cond C of the minimum (the
 *     excess 1/2 gᵀ(JᵀJ)⁻¹g of the scaled problem), which at 1e8 is n C;
 *   - rounding of the cost pins a parameter to sqrt(2 k eps C / h); along the
 *     weakest direction h is 1/cond of the strongest, so the weak combination
 *     is only known to sqrt(cond k eps) ~ 1e-3 of its scale at 1e8.
 * Below 1e-10 of the largest eigenvalue (cond > 1e10) a direction is not
 * identifiable at all (unidentified[], NaN standard errors); between 1e8 and
 * 1e10 the standard errors are large but finite. */
#define BK_FIT_COND_MAX 1e8

typedef struct bk_fit_metrics {
	double cost;          /* 1/2 sum of the squared weighted residuals, no loss (bk_fit_evaluate;
	                         NaN from bk_samples_metrics) */
	double rmse;          /* root mean square of f - y over the samples */
	double weighted_rmse; /* the same with the target's (or the user's) weights */
	double max_abs;       /* largest |f - y| */
	double albedo_max_abs; /* largest error of the directional albedo; NaN if none */
	double max_rel; /* over samples with |y| >= BK_REL_METRIC of the largest |y| */
	double comp_rmse[3], comp_max_abs[3]; /* env split: A, B, A + B */
	size_t nonfinite;                     /* samples where the form is not finite */
} bk_fit_metrics;

typedef struct bk_fit_result {
	double p[BK_MAX_PARAMS];           /* the fitted constants p0..p(np-1) */
	double se[BK_MAX_PARAMS];          /* standard errors; NaN where held (hold, lower == upper, or
	                                      held[]: not fitted, so none; the others' are conditional
	                                      on them: a 0 would read "known exactly") and where not
	                                      identifiable and not held (holding failed) */
	int unidentified[BK_MAX_PARAMS];   /* 1: in the null space of the Jacobian */
	int held[BK_MAX_PARAMS];           /* 1: not identifiable, so held at its start value (se NaN)
	                                      and the others re-solved: the answer is then unique
	                                      (fit.c, hold_unidentified) */
	bk_fit_summary summary;            /* of the best start (and later stages) */
	double start_cost_min, start_cost_max; /* spread of final costs over the starts */
	int starts_failed;                 /* starts whose solve failed */
	int starts_run;                    /* starts solved: spec->starts, fewer when a callback
	                                      stopped them (bk_fit_run_cb) */
	bk_fit_metrics fitted;             /* of the result p */
	bk_fit_metrics published;          /* left zero by the fit: the caller's slot for metrics at
	                                      published constants (bk_fit_evaluate) */
	bk_fit_metrics before_digits;      /* of the unrounded p, when digits rounds */
	double unrounded[BK_MAX_PARAMS];   /* p before digits rounded it */
	char message[512];                 /* why a fit failed; notes on optimality and conditioning */
	/* First-order optimality at the returned point, checked independently of
	 * Ceres' own stop (see BK_FIT_GRAD_TOL). With minimax, of the weighted
	 * least-squares problem of the Lawson step that gave the point; with
	 * digits, of the unrounded solution (rounding leaves the minimum on
	 * purpose, and holds every rounded constant). */
	double grad[BK_MAX_PARAMS];        /* ∂cost/∂p_j, cost = 1/2 sum rho(r_i^2) as Ceres sees it */
	double grad_rel[BK_MAX_PARAMS];    /* |∂cost/∂p_j| on its scale, compared with BK_FIT_GRAD_TOL;
	                                      NaN: excluded (held, or on a bound with the gradient
	                                      pointing out of the box) */
	int optimal;                       /* 1: every grad_rel <= BK_FIT_GRAD_TOL; 0: not a minimum
	                                      (then termination is not CONVERGENCE); -1: not checked */
	int polish_solves;                 /* extra solves from a point that failed the check */
	/* Conditioning of the fit (see BK_FIT_COND_MAX): cond(JᵀJ) with the columns
	 * of J scaled to unit norm, over the free parameters; +inf when a column
	 * is zero, NaN when nothing is free. */
	double condition;
	int collinear[BK_MAX_PARAMS];      /* 1: loads >= 0.3 on a direction whose eigenvalue is below
	                                      1/BK_FIT_COND_MAX of the largest (unidentified included) */
} bk_fit_result;

/* Metrics of values v (one per sample) against the samples: everything of
 * bk_fit_metrics but the cost (NaN). weight: per-sample weights for the
 * weighted rmse, or NULL for the target's. */
void bk_samples_metrics(const bk_samples *s, const double *v, const double *weight, bk_fit_metrics *m);
/* The signed error of values v per plane cell, by bk_fit_plane_error's rule. */
void bk_samples_plane_error(const bk_samples *s, const double *v, double *cells);

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

/* Every field's default (as Ceres' Solver::Options): no samples, forms or
 * parameters yet (s, form[], np: the caller's to set), the solver's
 * BK_FIT_OPTIONS_INIT, one start from p_j = 1, no bounds
 * (+-HUGE_VAL), nothing held, absolute residuals, no weight formula, least
 * squares, no rounding, seed 1. */
void bk_fit_defaults(bk_fit_spec *spec);

/* Returns 0 (converged), 1 (ran but did not converge), -1 (failed: message). */
int bk_fit_run(const bk_fit_spec *spec, bk_fit_result *res);

/* What a program hears from a running fit, and how it stops one (as Ceres'
 * IterationCallback, once per start rather than per iteration: a start is
 * one solve). progress (may be NULL) is called on the caller's thread after
 * start `start` (0-based) of `starts` with that start's summary; non-zero
 * ends the starts there: the rest of the fit (optimality check, minimax,
 * standard errors, digits) runs on the best start so far, and
 * res->starts_run says how many ran. */
typedef struct bk_fit_callbacks {
	int (*progress)(void *ctx, int start, int starts, const bk_fit_summary *sum);
	void *ctx;
} bk_fit_callbacks;
#define BK_FIT_CALLBACKS_INIT {NULL, NULL}
/* bk_fit_run with callbacks (cb may be NULL: bk_fit_run). */
int bk_fit_run_cb(const bk_fit_spec *spec, const bk_fit_callbacks *cb, bk_fit_result *res);

/* A fit's problem set up once for many solves from different starts: what
 * the search's screening drives (fit/search/screen.c) and the benches time.
 * bk_fit_run does the rest (starts, bounds, polish, statistics); this is
 * the solve alone, as bk_fit_run makes it. NULL when out of memory or the
 * spec cannot be set up. */
typedef struct bk_fit_problem bk_fit_problem;
bk_fit_problem *bk_fit_problem_new(const bk_fit_spec *spec);
void bk_fit_problem_free(bk_fit_problem *pb);
/* One solve from p (updated in place) with spec->opt; constant (NULL, or np
 * flags: 1 holds p_j). 0, or -1 when it could not run (sum->message). */
int bk_fit_problem_solve(bk_fit_problem *pb, double *p, const int *constant, bk_fit_summary *sum);
/* The same problem as the solver sees it (solver.h): residual blocks, their
 * callback, the spec's bounds and holds; valid while pb lives. */
bk_problem bk_fit_problem_view(const bk_fit_problem *pb);
/* The forms' values at p over the samples into v (spec->s->n), in f64:
 * bk_fit_eval_forms' bits, from the problem's bound forms where its solves
 * made them (what reads no parameter is not computed again). 0, or -1. */
int bk_fit_problem_values(bk_fit_problem *pb, const double *p, double *v);

#ifdef __cplusplus
}
#endif

#endif
