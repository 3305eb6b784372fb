/*
 * fit_problem.c — a fit's problem for repeated solves (fit.h,
 * bk_fit_problem_*): the fitter's context (fit_int.h) behind a public name,
 * so that the search and the benches need not include fit_int.h.
 */
#include "fit_int.h"

#include <stdlib.h>

struct bk_fit_problem {
	bk_fit_ctx ctx;
};

bk_fit_problem *bk_fit_problem_new(const bk_fit_spec *spec)
{
	bk_fit_problem *pb = malloc(sizeof *pb);
	if (pb && bk_fit_ctx_init(&pb->ctx, spec)) {
		bk_fit_ctx_free(&pb->ctx);
		free(pb);
		pb = NULL;
	}
	return pb;
}

void bk_fit_problem_free(bk_fit_problem *pb)
{
	if (!pb)
		return;
	bk_fit_ctx_free(&pb->ctx);
	free(pb);
}

int bk_fit_problem_solve(bk_fit_problem *pb, double *p, const int *constant, bk_fit_summary *sum)
{
	return bk_fit_solve(&pb->ctx, p, constant, sum);
}

static int residuals(void *ctx, int block, const double *p, double *r, double *jac)
{
	return bk_fit_residual_block(ctx, block, p, r, jac);
}

bk_problem bk_fit_problem_view(const bk_fit_problem *pb)
{
	const bk_fit_spec *sp = pb->ctx.spec;
	return (bk_problem){sp->np, pb->ctx.nblocks, pb->ctx.size, residuals, (void *)&pb->ctx, sp->lower, sp->upper,
	                    sp->hold};
}

int bk_fit_problem_values(bk_fit_problem *pb, const double *p, double *v)
{
	const bk_fit_ctx *c = &pb->ctx;
	for (int b = 0; b < c->nblocks; b++)
		if (!c->bound[b])
			return bk_fit_eval_forms(c->spec, p, v);
	for (int b = 0; b < c->nblocks; b++)
		if (bk_form_bound_eval(c->bound[b], p, v + c->lo[b], NULL))
			return -1;
	return 0;
}
