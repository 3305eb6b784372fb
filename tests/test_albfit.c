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
