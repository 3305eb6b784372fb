/*
 * refit.c — the one refit preset (refit.h).
 */
#include "search/refit.h"

#include <math.h>
#include <string.h>

void bk_refit_spec(bk_fit_spec *sp, const bk_samples *s, const bk_form *a, const bk_form *b, const double *start)
{
	memset(sp, 0, sizeof *sp);
	sp->s = s;
	sp->form[0] = a;
	sp->form[1] = b ? b : a;
	sp->np = bk_form_nparams(a);
	if (b && bk_form_nparams(b) > sp->np)
		sp->np = bk_form_nparams(b);
	sp->opt = (bk_fit_options)BK_FIT_OPTIONS_INIT;
	sp->opt.max_iterations = BK_REFIT_MAX_ITERATIONS;
	sp->starts = BK_REFIT_STARTS;
	sp->seed = BK_REFIT_SEED;
	sp->digits = BK_FIT_DIGITS_SE;
	for (int j = 0; j < BK_MAX_PARAMS; j++) {
		sp->start[j] = start[j];
		sp->lower[j] = -HUGE_VAL;
		sp->upper[j] = HUGE_VAL;
	}
}

bk_fit_options bk_refit_albedo_options(void)
{
	bk_fit_options o = BK_FIT_OPTIONS_INIT;
	o.max_iterations = BK_REFIT_ALBEDO_ITERATIONS;
	return o;
}

int bk_refit_values(const bk_fit_spec *sp, const double *p, bk_precision prec, double *v)
{
	const bk_samples *s = sp->s;
	for (int q = 0; q < s->ncomp; q++) {
		size_t lo = s->start[q];
		const double *in[BK_IN_COUNT];
		for (int k = 0; k < BK_IN_COUNT; k++)
			in[k] = s->in[k] + lo;
		/* half: the order of each mad farther from the target (a score that
		 * holds whichever order a driver takes), not from the form's f64 */
		const bk_form *f = sp->form[q < 1 ? 0 : 1];
		size_t m = s->start[q + 1] - lo;
		if (prec == BK_F16 ? bk_form_eval_half_vs(f, m, in, p, s->y + lo, v + lo)
		                   : bk_form_eval(f, prec, m, in, p, v + lo))
			return -1;
	}
	return 0;
}
