/*
 * test_formtarget.c — target form (a formula on a box of its inputs): the
 * grid is the cell centres worked out by hand, planted forms are recovered
 * to rounding, and a domain that does not match the expression, a target
 * with parameters or one with a pole on a sample are refused.
 */
#include "brdf.h"
#include "fit.h"
#include "target.h"

#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

static void form_options(bk_target_options *o, const char *text, int n, const int *in, const double *lo,
                         const double *hi)
{
	bk_target_defaults(BK_TARGET_FORM, o);
	o->form_text = text;
	o->ndomain = n;
	for (int d = 0; d < n; d++) {
		o->dom_in[d] = in[d];
		o->dom_lo[d] = lo[d];
		o->dom_hi[d] = hi[d];
	}
}

static void build(const bk_target_options *o, bk_samples *s)
{
	char err[512];
	cr_assert_eq(bk_target_build(o, s, NULL, NULL, err, sizeof err), 0, "%s", err);
}

static int build_fails(const bk_target_options *o, char *err, size_t len)
{
	bk_samples s;
	err[0] = '\0';
	int rc = bk_target_build(o, &s, NULL, NULL, err, len);
	if (rc == 0)
		bk_samples_free(&s);
	return rc;
}

/* Fits text to s from start p, returns the result. */
static void fit(const bk_samples *s, const char *text, const double *p, int np, bk_fit_result *res)
{
	bk_form_error e;
	bk_form *f = bk_form_parse(text, &e);
	cr_assert_not_null(f, "%s", e.message);
	bk_fit_spec sp;
	bk_fit_options fo = BK_FIT_OPTIONS_INIT;
	memset(&sp, 0, sizeof sp);
	sp.s = s;
	sp.form[0] = f;
	sp.np = bk_form_nparams(f);
	cr_assert_eq(sp.np, np);
	sp.opt = fo;
	sp.starts = 1;
	for (int j = 0; j < BK_MAX_PARAMS; j++) {
		sp.start[j] = j < np ? p[j] : 0;
		sp.lower[j] = -HUGE_VAL;
		sp.upper[j] = HUGE_VAL;
	}
	cr_assert_eq(bk_fit_run(&sp, res), 0, "%s", res->message);
	bk_form_free(f);
}

static const int LR[2] = {BK_IN_LOH, BK_IN_R};
static const double LR_LO[2] = {0.3162, 0}, LR_HI[2] = {1, 1};

/* 64 x 64 cell centres, LoH fastest; y is the expression at each. */
Test(formtarget, grid_is_the_cell_centres)
{
	bk_target_options o;
	bk_samples s;
	form_options(&o, "0.3/(LoH*LoH + 0.7*r*r)", 2, LR, LR_LO, LR_HI);
	build(&o, &s);
	cr_assert_eq(s.n, (size_t)64 * 64);
	double h = (1 - 0.3162) / 64;
	cr_assert_float_eq(s.in[BK_IN_LOH][0], 0.3162 + 0.5 * h, 1e-15);
	cr_assert_float_eq(s.in[BK_IN_R][0], 0.5 / 64, 1e-15);
	cr_assert_float_eq(s.in[BK_IN_LOH][1], 0.3162 + 1.5 * h, 1e-15); /* LoH varies fastest */
	cr_assert_float_eq(s.in[BK_IN_R][1], 0.5 / 64, 1e-15);
	cr_assert_float_eq(s.in[BK_IN_LOH][4095], 0.3162 + 63.5 * h, 1e-15);
	cr_assert_float_eq(s.in[BK_IN_R][4095], 63.5 / 64, 1e-15);
	cr_assert_float_eq(s.in[BK_IN_A][4095], (63.5 / 64) * (63.5 / 64), 1e-15); /* r gives a = r^2 */
	double L = 0.3162 + 0.5 * h, r = 0.5 / 64;
	cr_assert_float_eq(s.y[0], 0.3 / (L * L + 0.7 * r * r), 1e-15);
	cr_assert(isnan(s.in[BK_IN_NOV][0]) && isnan(s.in[BK_IN_F0][0]));
	cr_assert_eq(s.provides, 1u << BK_IN_LOH | 1u << BK_IN_R | 1u << BK_IN_A);
	cr_assert_eq(s.plane_nx, 64);
	cr_assert_eq(s.plane_ny, 64);
	cr_assert_str_eq(s.plane_xname, "LoH");
	cr_assert_str_eq(s.plane_yname, "r");
	bk_samples_free(&s);

	/* three inputs: 16 per axis by default; --nx 5 gives 125, the third axis slowest */
	static const int in3[3] = {BK_IN_NOV, BK_IN_F0, BK_IN_LOH};
	static const double lo3[3] = {0, 0.5, 0.2}, hi3[3] = {1, 1, 0.6};
	form_options(&o, "NoV*f0 + LoH", 3, in3, lo3, hi3);
	build(&o, &s);
	cr_assert_eq(s.n, (size_t)16 * 16 * 16);
	bk_samples_free(&s);
	o.nx = 5;
	build(&o, &s);
	cr_assert_eq(s.n, (size_t)125);
	cr_assert_float_eq(s.in[BK_IN_NOV][0], 0.1, 1e-15);
	cr_assert_float_eq(s.in[BK_IN_F0][0], 0.55, 1e-15);
	cr_assert_float_eq(s.in[BK_IN_LOH][0], 0.24, 1e-15);
	cr_assert_float_eq(s.in[BK_IN_F0][5], 0.65, 1e-15); /* index 5: NoV back to 0, f0 one step */
	cr_assert_float_eq(s.in[BK_IN_LOH][25], 0.32, 1e-15);
	cr_assert_float_eq(s.in[BK_IN_NOV][124], 0.9, 1e-15);
	cr_assert_float_eq(s.in[BK_IN_F0][124], 0.95, 1e-15);
	cr_assert_float_eq(s.in[BK_IN_LOH][124], 0.56, 1e-15);
	cr_assert_float_eq(s.y[124], 0.9 * 0.95 + 0.56, 1e-15);
	cr_assert_eq(s.provides, 1u << BK_IN_NOV | 1u << BK_IN_F0 | 1u << BK_IN_LOH);
	bk_samples_free(&s);
}

/* A planted form is recovered: the candidate is the target's family. */
Test(formtarget, planted_rational)
{
	bk_target_options o;
	bk_samples s;
	bk_fit_result res;
	form_options(&o, "0.3/(LoH*LoH + 0.7*r*r)", 2, LR, LR_LO, LR_HI);
	build(&o, &s);
	fit(&s, "p0/(LoH*LoH + p1*r*r)", (const double[]){1, 1}, 2, &res);
	cr_assert(fabs(res.p[0] - 0.3) <= 1e-9 * 0.3, "p0 %.17g", res.p[0]);
	cr_assert(fabs(res.p[1] - 0.7) <= 1e-9 * 0.7, "p1 %.17g", res.p[1]);
	cr_assert(res.fitted.cost < 1e-20, "cost %g", res.fitted.cost);
	bk_samples_free(&s);
}

Test(formtarget, planted_exponential)
{
	bk_target_options o;
	bk_samples s;
	bk_fit_result res;
	static const int in[1] = {BK_IN_LOH};
	static const double lo[1] = {0}, hi[1] = {1};
	form_options(&o, "exp2(-5.5*LoH)*0.9", 1, in, lo, hi);
	build(&o, &s);
	cr_assert_eq(s.n, (size_t)256);
	cr_assert_eq(s.plane_nx, 256);
	cr_assert_eq(s.plane_ny, 1);
	fit(&s, "p0*exp2(p1*LoH)", (const double[]){1, -1}, 2, &res);
	cr_assert(fabs(res.p[0] - 0.9) <= 1e-9 * 0.9, "p0 %.17g", res.p[0]);
	cr_assert(fabs(res.p[1] + 5.5) <= 1e-9 * 5.5, "p1 %.17g", res.p[1]);
	cr_assert(res.fitted.cost < 1e-20, "cost %g", res.fitted.cost);
	bk_samples_free(&s);
}

Test(formtarget, refused)
{
	bk_target_options o;
	char err[512];
	static const int L[1] = {BK_IN_LOH};
	static const double lo[1] = {0}, hi[1] = {1};
	form_options(&o, "0.3/(LoH*LoH + 0.7*r*r)", 1, L, lo, hi);
	cr_assert_eq(build_fails(&o, err, sizeof err), -1);
	cr_assert_str_eq(err, "the target form reads 'r', which the domain does not give (add r=LO:HI)");
	form_options(&o, "LoH", 2, LR, LR_LO, LR_HI);
	cr_assert_eq(build_fails(&o, err, sizeof err), -1);
	cr_assert_str_eq(err, "the domain gives 'r', which the target form does not read");
	form_options(&o, "p0*LoH + r", 2, LR, LR_LO, LR_HI);
	cr_assert_eq(build_fails(&o, err, sizeof err), -1);
	cr_assert_str_eq(err, "the target form uses p0: a target has no parameters (write its constants as numbers)");
	form_options(&o, "a*LoH", 2, LR, LR_LO, LR_HI); /* r covers a */
	cr_assert_eq(bk_target_form_check(&o, err, sizeof err), 0, "%s", err);
	static const int RA[2] = {BK_IN_R, BK_IN_A};
	static const double lo2[2] = {0, 0}, hi2[2] = {1, 1};
	form_options(&o, "a*r", 2, RA, lo2, hi2);
	cr_assert_eq(build_fails(&o, err, sizeof err), -1);
	cr_assert_str_eq(err, "the domain gives both 'r' and 'a': with r, a is r^2 (give one)");
	/* a pole on a sample: 0.625 is the third of 4 cell centres of [0, 1] */
	form_options(&o, "1/(LoH - 0.625)", 1, L, lo, hi);
	o.nx = 4;
	cr_assert_eq(build_fails(&o, err, sizeof err), -1);
	cr_assert_str_eq(err, "the target form is inf at LoH = 0.625 (sample 3 of 4): a target must be finite on its domain");
}

/* A domain whose width times the cells overflows double would put inf in the
 * cell centres (lo + (i + 0.5) (hi - lo) / n): refused, naming the input.
 * 256 cells (one input): (2^1023 - 0) x 256 overflows; the largest domain
 * that does not, [0, DBL_MAX / 256], builds with finite centres. */
Test(formtarget, domain_too_wide)
{
	bk_target_options o;
	bk_samples s;
	char err[512];
	static const int V[1] = {BK_IN_NOV};
	static const double lo[1] = {-1e308}, hi[1] = {1e308};
	form_options(&o, "NoV", 1, V, lo, hi);
	cr_assert_eq(build_fails(&o, err, sizeof err), -1);
	cr_assert_str_eq(err, "the domain of 'NoV' is too wide: (1e+308 - (-1e+308)) x 256 cells overflows double");
	static const double lo1[1] = {0}, hi1[1] = {0x1p1023};
	form_options(&o, "NoV", 1, V, lo1, hi1);
	cr_assert_eq(build_fails(&o, err, sizeof err), -1);
	static const double hi2[1] = {0x1.fffffffffffffp1023 / 256};
	form_options(&o, "NoV", 1, V, lo1, hi2);
	build(&o, &s);
	for (size_t i = 0; i < s.n; i++)
		cr_assert(isfinite(s.in[BK_IN_NOV][i]) && isfinite(s.y[i]), "sample %zu: %g", i, s.in[BK_IN_NOV][i]);
	bk_samples_free(&s);
}
