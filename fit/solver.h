/*
 * solver.h — the C face of the Ceres bridge (fit/solver.cc, the project's only
 * C++): nonlinear least squares over blocks of residuals whose values and
 * Jacobians come from a C callback (in brdfkit, the formula IR over blocks of
 * samples). Three steps as in Ceres: residuals (bk_residual_fn), problem
 * (bk_problem), solve (bk_solve); options with documented defaults and a
 * validity check; a summary.
 */
#ifndef FIT_SOLVER_H
#define FIT_SOLVER_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum bk_loss {
	BK_LOSS_NONE,   /* rho(s) = s */
	BK_LOSS_HUBER,  /* rho(s) = s for s <= c^2, 2c sqrt(s) - c^2 beyond */
	BK_LOSS_CAUCHY, /* rho(s) = c^2 log(1 + s/c^2) */
	BK_LOSS_SOFTL1  /* rho(s) = 2c^2 (sqrt(1 + s/c^2) - 1) */
} bk_loss;

typedef enum bk_trust_region { BK_TR_LEVENBERG_MARQUARDT, BK_TR_DOGLEG } bk_trust_region;

/* Options. Tolerances as Ceres states them:
 *   function:  |Δcost| / cost <= function_tolerance
 *   gradient:  max_i |x_i - Π(x_i - g_i)| <= gradient_tolerance  (Π: projection on the bounds)
 *   parameter: |Δx| <= parameter_tolerance (|x| + parameter_tolerance)
 */
typedef struct bk_fit_options {
	bk_trust_region trust_region; /* default Levenberg-Marquardt */
	bk_loss loss;                 /* default none; applied to EACH residual, not per block */
	double loss_scale;            /* c above, > 0; default 1 */
	int max_iterations;           /* default 200 */
	double function_tolerance;    /* default 1e-12 */
	double gradient_tolerance;    /* default 1e-12 */
	double parameter_tolerance;   /* default 1e-10 */
	int num_threads;              /* Ceres' own threads; default 1 */
} bk_fit_options;

#define BK_FIT_OPTIONS_INIT {BK_TR_LEVENBERG_MARQUARDT, BK_LOSS_NONE, 1.0, 200, 1e-12, 1e-12, 1e-10, 1}

/* 1 if the options are usable; otherwise 0 and a one-line reason in why. */
int bk_fit_options_valid(const bk_fit_options *o, char *why, size_t len);

/* Values of one block's residuals, and (when jacobian is not NULL) their
 * derivatives, row-major: jacobian[i * np + j] = d residual_i / d param_j.
 * Must be thread-safe when num_threads > 1. Return 0, or non-zero to make the
 * solve fail. A residual that is not finite fails the solve at the start or
 * at a point it accepts (jacobian asked for), and makes a trial point's step
 * rejected (jacobian NULL: the trust region shrinks, the solve goes on); a
 * solve that then stops on its step size at that edge is NO_CONVERGENCE. */
typedef int (*bk_residual_fn)(void *ctx, int block, const double *params, double *residuals,
                              double *jacobian);

typedef struct bk_problem {
	int np;                 /* parameters, 1..16 */
	int nblocks;            /* residual blocks */
	const int *block_size;  /* residuals in each block, >= 1 */
	bk_residual_fn fn;
	void *ctx;
	const double *lower;    /* NULL, or np bounds (-HUGE_VAL for none) */
	const double *upper;    /* NULL, or np bounds (+HUGE_VAL for none) */
	const int *constant;    /* NULL, or np flags: 1 holds the parameter fixed */
} bk_problem;

/* 1 if the problem and the start params pass bk_solve's checks; otherwise 0
 * and a one-line reason in why (bk_solve's message). */
int bk_problem_valid(const bk_problem *p, const double *params, char *why, size_t len);

typedef enum bk_termination {
	BK_TERM_CONVERGENCE,    /* a tolerance was met */
	BK_TERM_NO_CONVERGENCE, /* iteration or time limit, or stopped at the edge of where the residuals are finite */
	BK_TERM_FAILURE         /* the solver or the callback failed */
} bk_termination;

typedef struct bk_fit_summary {
	bk_termination termination;
	char message[256];
	double initial_cost, final_cost; /* 1/2 sum rho(r_i^2), Ceres' convention */
	int iterations;                  /* over all solves */
	int bound_resolves;              /* extra solves with active bounds held (see solver.cc) */
	double seconds;
} bk_fit_summary;

/* Minimises 1/2 sum_i rho(r_i^2) from params (in: start, out: solution).
 * Validates everything first (Ceres aborts the process on misuse): returns 0,
 * or -1 with the reason in summary->message and params untouched. */
int bk_solve(const bk_problem *p, const bk_fit_options *o, double *params,
             bk_fit_summary *summary);

/* The fast path for small dense problems (fit/tiny.cc): Ceres' TinySolver,
 * dense Levenberg-Marquardt on the normal equations, no per-block overhead.
 * Same contract as bk_solve (validation first, params untouched on -1, the
 * same summary and termination meanings) for problems without bounds and
 * without a loss: a problem with lower/upper bounds that are not all
 * infinite, or o->loss != BK_LOSS_NONE, or o->trust_region != LM, is refused
 * (-1, message). Constant flags hold parameters (solved over the free ones).
 * Deterministic: one thread, the blocks evaluated in order. */
int bk_solve_tiny(const bk_problem *p, const bk_fit_options *o, double *params,
                  bk_fit_summary *summary);
/* 1 if bk_solve_tiny accepts the problem and options. */
int bk_solve_tiny_applies(const bk_problem *p, const bk_fit_options *o);
/* bk_solve_tiny for a callback that gives the same values, and fails the
 * same way, whether or not it is asked for the Jacobian (the fit's residual
 * blocks, fit_ctx.c): a trial point's Jacobian is made with its values and
 * kept for the point's acceptance, where TinySolver would evaluate the point
 * again (one forward pass less per accepted step; the same bits). */
int bk_solve_tiny_reusing(const bk_problem *p, const bk_fit_options *o, double *params,
                          bk_fit_summary *summary);
/* The Jacobian by columns: one block's residuals into residuals and, when
 * cols is not NULL, d residual_i / d param_j into cols[j][i] for every j whose
 * cols[j] is not NULL (each then block_size rows). Returns 0 when every value
 * it wrote is finite; BK_COLS_RES_NONFINITE when a residual is not (the
 * solve fails naming the first, as bk_solve; the callback tests them as it
 * writes them, so the solver need not read them again); BK_COLS_JAC_NONFINITE
 * when the residuals are finite but a Jacobian entry it wrote is not (the
 * solver decides whether that Jacobian is used); any other non-zero fails the
 * solve. */
typedef int (*bk_residual_cols_fn)(void *ctx, int block, const double *params, double *residuals,
                                   double *const *cols);
#define BK_COLS_JAC_NONFINITE 1
#define BK_COLS_RES_NONFINITE 2
/* bk_solve_tiny_reusing with the Jacobian from cols (p->fn is not called, but
 * checked as bk_solve_tiny checks it): the callback writes each free
 * parameter's column straight into TinySolver's column-major Jacobian, where
 * bk_solve_tiny transposes the row-major one in a pass of its own, and the
 * finiteness of what it writes comes back with it (BK_COLS_JAC_NONFINITE),
 * where bk_solve_tiny reads the Jacobian once more to test it. The same
 * checks, failures and messages as bk_solve_tiny_reusing, in the same order,
 * and the same bits when cols gives fn's values. */
int bk_solve_tiny_cols(const bk_problem *p, bk_residual_cols_fn cols, const bk_fit_options *o, double *params,
                       bk_fit_summary *summary);
#ifdef __cplusplus
}
#endif

#endif
