/*
 * fit_int.h — what fit.c, fit_stats.c and fit_ctx.c share (internal).
 * Calls run one way: fit.c -> fit_stats.c -> fit_ctx.c.
 */
#ifndef FIT_FIT_INT_H
#define FIT_FIT_INT_H

#include "fit.h"

typedef struct bk_fit_ctx {
	const bk_fit_spec *spec;
	double *sw;   /* sqrt of the weight in use (minimax changes it) */
	double *inv;  /* 1, or 1/|y| for relative residuals */
	double *base; /* the target's weight times the user's */
	/* sw inv per sample, formed once per solve (bk_fit_solve) while the
	 * weights hold still: the residuals' factor k, the same product the
	 * callbacks formed per block at every evaluation. kw_live is set only
	 * inside bk_fit_solve (minimax and the polish change sw between solves;
	 * the statistics' calls form k afresh). */
	double *kw;
	int kw_live;
	int nblocks;
	size_t *lo;   /* first sample of each block */
	int *size;
	int *comp;    /* which form a block evaluates */
	/* each block's form bound to its samples (bk_form_bind), made at the
	 * block's first evaluation: what reads no parameter is computed once per
	 * fit, not once per iteration. NULL until then; unbound[b] set when it
	 * could not be made (the plain evaluators are used). A block is evaluated
	 * by one thread at a time, so each is written by one thread. */
	bk_form_bound **bound;
	char *unbound;
} bk_fit_ctx;


/* fit_ctx.c: the context, its residuals and the Ceres problem */
int bk_fit_ctx_init(bk_fit_ctx *c, const bk_fit_spec *spec);
void bk_fit_ctx_free(bk_fit_ctx *c);
int bk_fit_solve(bk_fit_ctx *c, double *p, const int *constant, bk_fit_summary *sum);
int bk_fit_residual_block(bk_fit_ctx *c, int block, const double *p, double *r, double *jac);
/* Values of the forms at every sample (each component its form). */
int bk_fit_eval_forms(const bk_fit_spec *spec, const double *p, double *v);

/* fit_stats.c: what the driver asks of the statistics */
/* Standard errors, identifiability and condition at res->p (the parameters
 * in c->spec->hold fixed). Returns the number of directions the data do not
 * pin (the null space's dimension), -1 if J could not be evaluated. */
int bk_fit_stderr(bk_fit_ctx *c, bk_fit_result *res);
/* First-order optimality at p with the weights in use (c->sw) and the
 * parameters in held[] fixed: fills res->grad, grad_rel, optimal (see
 * BK_FIT_GRAD_TOL). Returns the index of the parameter with the largest
 * grad_rel among those failing, -1 if none fails, -2 if the residuals could not
 * be evaluated (optimal = -1). flat (may be NULL): the number of free
 * parameters whose Jacobian column is zero or not finite at p, where a zero
 * gradient says nothing about a minimum. */
int bk_fit_optimality(bk_fit_ctx *c, const double *p, const int *held, bk_fit_result *res, int *flat);

#endif
