/*
 * test_albfit.c — constants fitted to the directional albedo (fit/albfit.c):
 * a planted scale is recovered exactly, the cells' errors agree with the
 * albedo error fit_stats.c measures by its own code, and the albedo minimax
 * of Hable's V x Schlick beats its published constant by more than 2x on
 * the vf target (the search issue's figure: published 0.068, target 0.034).
 */
#include "albfit.h"
#include "fit.h"
#include "target.h"

#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

static bk_samples s;
static char err[256];

static void build_vf(int nx, int nr, int nu, int nphi)
{
	bk_target_options o;
	bk_target_defaults(BK_TARGET_VF, &o);
	o.nx = nx, o.nr = nr, o.nu = nu, o.nphi = nphi;
	cr_assert_eq(bk_target_build(&o, &s, NULL, NULL, err, sizeof err), 0, "%s", err);
}

static bk_form *parse(const char *text)
{
	bk_form_error fe;
	bk_form *f = bk_form_parse(text, &fe);
	cr_assert(f, "%s: %s", text, fe.message);
	return f;
}

/* The exact term times p0: the albedo errors vanish at p0 = 1 and nowhere
 * else, in least squares and in minimax. */
Test(albfit, planted_scale_is_recovered)
{
	build_vf(8, 8, 8, 4);
	bk_form *f = parse("p0*V_smith_ggx_correlated(NoV, NoL, a)*F_schlick(f0, 1, LoH)");
	bk_albfit *a = bk_albfit_new(&s, f, 1);
	cr_assert(a);
	bk_fit_options o = BK_FIT_OPTIONS_INIT;
	for (int minimax = 0; minimax < 2; minimax++) {
		double p[BK_MAX_PARAMS] = {0.5}, e;
		cr_assert_eq(bk_albfit_run(a, p, minimax, &o, &e), 0);
		cr_expect(fabs(p[0] - 1) < 1e-9, "minimax %d: p0 = %.17g", minimax, p[0]);
		cr_expect(e < 1e-9, "minimax %d: max error %g", minimax, e);
	}
	bk_albfit_free(a);
	bk_form_free(f);
	bk_samples_free(&s);
}

/* bk_albfit_max and fit_stats.c's albedo_max_abs are two codes for one
 * quantity. */
Test(albfit, cell_errors_agree_with_the_metrics)
{
	build_vf(8, 8, 8, 4);
	bk_form *f = parse("f0/(4*LoH*LoH*(r + p0))");
	bk_albfit *a = bk_albfit_new(&s, f, 1);
	cr_assert(a);
	double p[BK_MAX_PARAMS] = {0.5};
	bk_fit_spec sp;
	memset(&sp, 0, sizeof sp);
	sp.s = &s;
	sp.form[0] = f;
	sp.np = 1;
	bk_fit_metrics m;
	bk_fit_evaluate(&sp, p, &m);
	double e = bk_albfit_max(a, p);
	cr_expect(fabs(e - m.albedo_max_abs) <= 1e-12 * m.albedo_max_abs, "albfit %.17g, metrics %.17g", e, m.albedo_max_abs);
	bk_albfit_free(a);
	bk_form_free(f);
	bk_samples_free(&s);
}

/* Samples without a measure (env) have no albedo to fit. */
Test(albfit, refuses_samples_without_a_measure)
{
	bk_target_options o;
	bk_target_defaults(BK_TARGET_ENV, &o);
	o.nx = o.nr = 4;
	o.env_f0_form = 1;
	o.nf0 = 1;
	cr_assert_eq(bk_target_build(&o, &s, NULL, NULL, err, sizeof err), 0, "%s", err);
	bk_form *f = parse("p0*NoV");
	cr_expect_null(bk_albfit_new(&s, f, 1));
	bk_form_free(f);
	bk_samples_free(&s);
}

Test(albfit, hable_albedo_minimax_halves_the_published_error, .timeout = 120)
{
	build_vf(16, 16, 32, 16); /* the vf target's default grid */
	bk_form *f = parse("(0.25/(LoH*LoH*(1 - sq(p0*a)) + sq(p0*a)))*F_schlick(f0, 1, LoH)");
	bk_albfit *a = bk_albfit_new(&s, f, 1);
	cr_assert(a);
	double p[BK_MAX_PARAMS] = {0.5}, published = bk_albfit_max(a, p), e;
	cr_expect(fabs(published - 0.068) < 0.001, "Hable's published k = a/2: albedo max %g, the issue's 0.068", published);
	bk_fit_options o = BK_FIT_OPTIONS_INIT;
	cr_assert_eq(bk_albfit_run(a, p, 1, &o, &e), 0);
	cr_expect(e < 0.034, "minimax: %g at p0 = %g", e, p[0]);
	cr_expect(fabs(e - bk_albfit_max(a, p)) <= 1e-15, "the max returned is the point's");
	bk_albfit_free(a);
	bk_form_free(f);
	bk_samples_free(&s);
}

/* The cells' sums by fixed widths (1 to 8 parameters) and the generic width
 * (a fit wider than its form): forms that are the exact term times a factor
 * equal to 1 only at a planted point, (1 + p1 NoV + p2 r + ...)-like, so the
 * albedo errors vanish there and nowhere else (NoV and r are constant over
 * a cell, and the cells hold several of each). From a start off the point,
 * least squares must land on it. */
Test(albfit, planted_points_of_every_width)
{
	build_vf(8, 8, 8, 4);
	static const char *const forms[] = {
		"p0*V_smith_ggx_correlated(NoV, NoL, a)*F_schlick(f0, 1, LoH)",
		"(p0 + p1*NoV)*V_smith_ggx_correlated(NoV, NoL, a)*F_schlick(f0, 1, LoH)",
		"(p0 + p1*NoV + p2*r)*V_smith_ggx_correlated(NoV, NoL, a)*F_schlick(f0, 1, LoH)",
		"(p0 + p1*NoV + p2*r + p3*NoV*r)*V_smith_ggx_correlated(NoV, NoL, a)*F_schlick(f0, 1, LoH)",
	};
	/* the planted point: p0 = 1, the rest 0 */
	for (int k = 0; k < 4; k++)
		for (int wide = 0; wide < 2; wide++) {
			bk_form *f = parse(forms[k]);
			int np = bk_form_nparams(f) + (wide ? 2 : 0); /* wide: two columns the form never reads */
			bk_albfit *a = bk_albfit_new(&s, f, np);
			cr_assert(a);
			double p[BK_MAX_PARAMS] = {0}, e;
			p[0] = 0.7;
			for (int j = 1; j < bk_form_nparams(f); j++)
				p[j] = 0.05 * j;
			double start = bk_albfit_max(a, p);
			bk_fit_options o = BK_FIT_OPTIONS_INIT;
			cr_assert_eq(bk_albfit_run(a, p, 0, &o, &e), 0);
			cr_expect(start > 0.01, "%s: the start is off the point (%g)", forms[k], start);
			cr_expect(fabs(p[0] - 1) < 1e-7, "%s np %d: p0 = %.17g", forms[k], np, p[0]);
			for (int j = 1; j < bk_form_nparams(f); j++)
				cr_expect(fabs(p[j]) < 1e-7, "%s np %d: p%d = %.17g", forms[k], np, j, p[j]);
			cr_expect(e < 1e-9, "%s np %d: max error %g", forms[k], np, e);
			bk_albfit_free(a);
			bk_form_free(f);
		}
	bk_samples_free(&s);
}

/* The max kept for the last points asked is the max at that point: after
 * other points, the first one's value again, the same bits as a fresh
 * albfit's (which has kept nothing); and a point 1e-6 away is not taken
 * for it (its max differs). */
Test(albfit, kept_max_is_the_points_own)
{
	build_vf(8, 8, 8, 4);
	bk_form *f = parse("f0/(4*LoH*LoH*(r + p0))");
	bk_albfit *a = bk_albfit_new(&s, f, 1);
	cr_assert(a);
	double p1[BK_MAX_PARAMS] = {0.5}, p2[BK_MAX_PARAMS] = {0.25}, p3[BK_MAX_PARAMS] = {1.0};
	double m1 = bk_albfit_max(a, p1), m2 = bk_albfit_max(a, p2), m3 = bk_albfit_max(a, p3);
	cr_expect(m1 != m2 && m2 != m3 && m1 != m3, "three points, three maxima: %g %g %g", m1, m2, m3);
	cr_expect_eq(bk_albfit_max(a, p1), m1);
	bk_albfit *b = bk_albfit_new(&s, f, 1);
	cr_assert(b);
	cr_expect_eq(bk_albfit_max(b, p1), m1, "a fresh albfit: %.17g, kept %.17g", bk_albfit_max(b, p1), m1);
	double q[BK_MAX_PARAMS] = {0.5 + 1e-6};
	double mq = bk_albfit_max(b, q);
	cr_expect_neq(mq, m1, "1e-6 away: %.17g", mq);
	cr_expect_eq(bk_albfit_max(a, q), mq, "kept nothing for it: computed");
	/* a run's result is kept: its max is the one the run returned */
	double p[BK_MAX_PARAMS] = {0.5}, e;
	bk_fit_options o = BK_FIT_OPTIONS_INIT;
	cr_assert_eq(bk_albfit_run(a, p, 1, &o, &e), 0);
	cr_expect_eq(bk_albfit_max(a, p), e);
	cr_expect_eq(bk_albfit_max(b, p), e, "fresh: %.17g, run %.17g", bk_albfit_max(b, p), e);
	bk_albfit_free(a);
	bk_albfit_free(b);
	bk_form_free(f);
	bk_samples_free(&s);
}
