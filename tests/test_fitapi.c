/*
 * test_fitapi.c — the fitter as a library user calls it (fit.h): the
 * defaults of bk_fit_defaults against the values its header and solver.h
 * state, a planted form recovered from those defaults alone, and the
 * per-start callback of bk_fit_run_cb (called once per start with the start's
 * index, its summary, and a non-zero return ending the starts).
 */
#include "fit.h"
#include "target.h"

#include <criterion/criterion.h>
#include <math.h>

/* samples of text on LoH in [0, 1], 32 cells */
static void plant(const char *text, bk_samples *s)
{
	bk_target_options o;
	bk_target_defaults(BK_TARGET_FORM, &o);
	o.form_text = text;
	o.ndomain = 1;
	o.dom_in[0] = BK_IN_LOH, o.dom_lo[0] = 0, o.dom_hi[0] = 1;
	o.nx = 32;
	char err[256];
	cr_assert_eq(bk_target_build(&o, s, NULL, NULL, err, sizeof err), 0, "%s", err);
}

Test(fitapi, defaults_as_documented)
{
	bk_fit_spec sp;
	bk_fit_defaults(&sp);
	/* solver.h's stated defaults, not BK_FIT_OPTIONS_INIT read back */
	cr_expect_eq(sp.opt.trust_region, BK_TR_LEVENBERG_MARQUARDT);
	cr_expect_eq(sp.opt.loss, BK_LOSS_NONE);
	cr_expect_eq(sp.opt.max_iterations, 200);
	cr_expect_eq(sp.opt.function_tolerance, 1e-12);
	cr_expect_eq(sp.opt.parameter_tolerance, 1e-10);
	cr_expect_eq(sp.opt.num_threads, 1);
	cr_expect(sp.s == NULL && sp.form[0] == NULL && sp.form[1] == NULL && sp.np == 0 && sp.weight == NULL);
	cr_expect(sp.starts == 1 && sp.seed == 1 && !sp.relative && !sp.minimax && sp.digits == 0);
	for (int j = 0; j < BK_MAX_PARAMS; j++) {
		cr_expect_eq(sp.start[j], 1.0);
		cr_expect(isinf(sp.lower[j]) && sp.lower[j] < 0 && isinf(sp.upper[j]) && sp.upper[j] > 0);
		cr_expect_eq(sp.hold[j], 0);
	}
}

/* Counts the calls; stops after stop_after starts (0: never). */
typedef struct heard {
	int calls, last_start, starts, stop_after;
	double cost[8];
} heard;

static int progress(void *ctx, int start, int starts, const bk_fit_summary *sum)
{
	heard *h = ctx;
	if (h->calls < 8)
		h->cost[h->calls] = sum->final_cost;
	h->calls++;
	h->last_start = start;
	h->starts = starts;
	return h->stop_after && h->calls >= h->stop_after;
}

/* p0*LoH^2 + p1 on samples of 0.45*LoH^2 + 0.2 from bk_fit_defaults alone
 * (starts p = 1): the planted constants to rounding; the same fit on a
 * plant of 0.5 gives 0.5, so the check tells the constants apart. */
static void fit_plant(const char *text, int starts, heard *h, bk_fit_result *res)
{
	bk_samples s;
	plant(text, &s);
	bk_form_error fe;
	bk_form *f = bk_form_parse("p0*LoH*LoH + p1", &fe);
	cr_assert(f);
	bk_fit_spec sp;
	bk_fit_defaults(&sp);
	sp.s = &s;
	sp.form[0] = f;
	sp.np = bk_form_nparams(f);
	sp.starts = starts;
	bk_fit_callbacks cb = BK_FIT_CALLBACKS_INIT;
	cb.progress = progress;
	cb.ctx = h;
	cr_expect_eq(bk_fit_run_cb(&sp, h ? &cb : NULL, res), 0, "%s", res->message);
	bk_form_free(f);
	bk_samples_free(&s);
}

Test(fitapi, planted_from_defaults)
{
	bk_fit_result res, wrong;
	fit_plant("0.45*LoH*LoH + 0.2", 1, NULL, &res);
	cr_expect(fabs(res.p[0] - 0.45) < 1e-9 && fabs(res.p[1] - 0.2) < 1e-9, "p %.17g %.17g", res.p[0], res.p[1]);
	cr_expect(res.fitted.rmse < 1e-9);
	cr_expect_eq(res.starts_run, 1);
	fit_plant("0.5*LoH*LoH + 0.2", 1, NULL, &wrong);
	cr_expect(fabs(wrong.p[0] - 0.45) > 1e-2, "negative control: another plant, other constants");
}

Test(fitapi, progress_once_per_start)
{
	heard h = {0};
	bk_fit_result res;
	fit_plant("0.45*LoH*LoH + 0.2", 3, &h, &res);
	cr_expect_eq(h.calls, 3);
	cr_expect_eq(h.last_start, 2);
	cr_expect_eq(h.starts, 3);
	cr_expect_eq(res.starts_run, 3);
	/* the summaries are the starts' own: each ends at the minimum (exact
	 * data: a cost of rounding, below 1e-20 of the start's) */
	for (int k = 0; k < 3; k++)
		cr_expect(h.cost[k] >= 0 && h.cost[k] < 1e-20, "start %d cost %g", k, h.cost[k]);
	cr_expect(fabs(res.p[0] - 0.45) < 1e-9);
}

Test(fitapi, progress_stops_the_starts)
{
	heard h = {.stop_after = 1};
	bk_fit_result res;
	fit_plant("0.45*LoH*LoH + 0.2", 3, &h, &res);
	cr_expect_eq(h.calls, 1);
	cr_expect_eq(res.starts_run, 1); /* negative control of the count above: 3 without the stop */
	cr_expect(fabs(res.p[0] - 0.45) < 1e-9, "the first start's answer is kept");
}
