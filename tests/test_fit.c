/*
 * test_fit.c — the fitter against closed forms: weighted linear regression
 * (value, standard error, relative residuals, user weights), minimax of a
 * constant (the midrange), split-sum means, bounds, identifiability, rounding,
 * non-finite forms and poles on the domain's edge, and the exact form scoring
 * zero error.
 */
#include "brdf.h"
#include "fit.h"
#include "target.h"

#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

static bk_form *form(const char *text)
{
	bk_form_error e;
	bk_form *f = bk_form_parse(text, &e);
	cr_assert_not_null(f, "%s: %s", text, e.message);
	return f;
}

static void samples(bk_target_kind kind, int nx, int nr, bk_samples *s)
{
	bk_target_options o;
	char err[256];
	bk_target_defaults(kind, &o);
	o.nx = nx;
	o.nr = nr;
	cr_assert_eq(bk_target_build(&o, s, NULL, NULL, err, sizeof err), 0, "%s", err);
}

static void spec_init(bk_fit_spec *sp, const bk_samples *s, const bk_form *f, double p0)
{
	bk_fit_options o = BK_FIT_OPTIONS_INIT;
	memset(sp, 0, sizeof *sp);
	sp->s = s;
	sp->form[0] = f;
	sp->np = bk_form_nparams(f);
	sp->opt = o;
	sp->starts = 1;
	for (int j = 0; j < BK_MAX_PARAMS; j++) {
		sp->start[j] = p0;
		sp->lower[j] = -HUGE_VAL;
		sp->upper[j] = HUGE_VAL;
	}
}

/* g = f0/(4 LoH^2): the talk's form with the roughness term taken out, linear in p0 */
static double g_of(const bk_samples *s, size_t i)
{
	double LoH = s->in[BK_IN_LOH][i];
	return s->in[BK_IN_F0][i] / (4 * LoH * LoH);
}

/* min Σ w (p g - y)^2: p = Σ w g y / Σ w g^2; se^2 = σ^2 / Σ w g^2 with
 * σ^2 = Σ w (y - p g)^2 / (m - 1), the textbook weighted regression. */
Test(fit, linear_regression_closed_form)
{
	bk_samples s;
	samples(BK_TARGET_VF2D, 32, 32, &s);
	double swgy = 0, swgg = 0;
	for (size_t i = 0; i < s.n; i++) {
		double g = g_of(&s, i);
		swgy += s.w[i] * g * s.y[i];
		swgg += s.w[i] * g * g;
	}
	double p = swgy / swgg, rss = 0;
	for (size_t i = 0; i < s.n; i++) {
		double e = p * g_of(&s, i) - s.y[i];
		rss += s.w[i] * e * e;
	}
	double se = sqrt(rss / (double)(s.n - 1) / swgg);
	bk_form *f = form("p0*f0/(4*LoH*LoH)");
	bk_fit_spec sp;
	bk_fit_result res;
	spec_init(&sp, &s, f, 1.0);
	cr_assert_eq(bk_fit_run(&sp, &res), 0, "%s", res.message);
	/* 1e-6: Ceres stops on |Δcost|/cost <= 1e-12, which pins p to ~sqrt(1e-12) relative */
	cr_assert(fabs(res.p[0] - p) <= 1e-6 * fabs(p), "p %.12g vs %.12g", res.p[0], p);
	cr_assert(fabs(res.se[0] - se) <= 1e-3 * se, "se %.6g vs %.6g", res.se[0], se);
	cr_assert(fabs(res.fitted.cost - 0.5 * rss) <= 1e-9 * rss);
	bk_form_free(f);
	bk_samples_free(&s);
}

/* BK_FIT_DIGITS_SE (the CLI's default): the same regression reported to the
 * decade at or below se/100 of the closed-form se, the metrics at the value
 * shown; the unrounded point is the closed form's. */
Test(fit, digits_from_the_standard_error)
{
	bk_samples s;
	samples(BK_TARGET_VF2D, 32, 32, &s);
	double swgy = 0, swgg = 0, rss = 0;
	for (size_t i = 0; i < s.n; i++) {
		double g = g_of(&s, i);
		swgy += s.w[i] * g * s.y[i];
		swgg += s.w[i] * g * g;
	}
	double p = swgy / swgg;
	for (size_t i = 0; i < s.n; i++) {
		double e = p * g_of(&s, i) - s.y[i];
		rss += s.w[i] * e * e;
	}
	double se = sqrt(rss / (double)(s.n - 1) / swgg), q = pow(10, floor(log10(se / 100)));
	bk_form *f = form("p0*f0/(4*LoH*LoH)");
	bk_fit_spec sp;
	bk_fit_result res;
	bk_fit_metrics at;
	spec_init(&sp, &s, f, 1.0);
	sp.digits = BK_FIT_DIGITS_SE;
	cr_assert_eq(bk_fit_run(&sp, &res), 0, "%s", res.message);
	cr_assert(fabs(res.unrounded[0] - p) <= 1e-6 * fabs(p), "unrounded %.12g vs %.12g", res.unrounded[0], p);
	cr_assert_eq(res.p[0], round(p / q) * q, "%.17g vs %.17g (q %g)", res.p[0], round(p / q) * q, q);
	bk_fit_evaluate(&sp, res.p, &at);
	cr_assert_eq(res.fitted.cost, at.cost);
	bk_form_free(f);
	bk_samples_free(&s);
}

/* Relative residuals are the same regression with weights w / y^2; a user
 * weight formula multiplies the target's weight. */
Test(fit, relative_and_user_weight)
{
	bk_samples s;
	samples(BK_TARGET_VF2D, 24, 24, &s);
	double a1 = 0, b1 = 0, a2 = 0, b2 = 0;
	for (size_t i = 0; i < s.n; i++) {
		double g = g_of(&s, i), y = s.y[i], LoH = s.in[BK_IN_LOH][i];
		a1 += s.w[i] / (y * y) * g * y;
		b1 += s.w[i] / (y * y) * g * g;
		a2 += s.w[i] * LoH * g * y;
		b2 += s.w[i] * LoH * g * g;
	}
	bk_form *f = form("p0*f0/(4*LoH*LoH)"), *w = form("LoH");
	bk_fit_spec sp;
	bk_fit_result res;
	spec_init(&sp, &s, f, 1.0);
	sp.relative = 1;
	cr_assert_eq(bk_fit_run(&sp, &res), 0);
	cr_assert(fabs(res.p[0] - a1 / b1) <= 1e-6 * a1 / b1, "relative: %.12g vs %.12g", res.p[0], a1 / b1);
	spec_init(&sp, &s, f, 1.0);
	sp.weight = w;
	cr_assert_eq(bk_fit_run(&sp, &res), 0);
	cr_assert(fabs(res.p[0] - a2 / b2) <= 1e-6 * a2 / b2, "weighted: %.12g vs %.12g", res.p[0], a2 / b2);
	bk_form_free(f);
	bk_form_free(w);
	bk_samples_free(&s);
}

/* The minimax constant is the midrange, its error half the range (Chebyshev).
 * Lawson's iteration converges linearly: 30 steps reach the optimum's error
 * to within 1 %. */
Test(fit, minimax_constant_is_the_midrange)
{
	bk_samples s;
	samples(BK_TARGET_F, 256, 1, &s);
	double lo = INFINITY, hi = -INFINITY;
	for (size_t i = 0; i < s.n; i++)
		lo = fmin(lo, s.y[i]), hi = fmax(hi, s.y[i]);
	bk_form *f = form("p0");
	bk_fit_spec sp;
	bk_fit_result res;
	spec_init(&sp, &s, f, 0.5);
	sp.minimax = 1;
	cr_assert(bk_fit_run(&sp, &res) >= 0, "%s", res.message);
	cr_assert(res.fitted.max_abs <= 1.01 * 0.5 * (hi - lo), "max err %g vs %g", res.fitted.max_abs, 0.5 * (hi - lo));
	cr_assert(fabs(res.p[0] - 0.5 * (hi + lo)) <= 0.01 * (hi - lo));
	/* least squares would sit at the weighted mean instead, with a larger max error */
	spec_init(&sp, &s, f, 0.5);
	bk_fit_result lsq;
	cr_assert_eq(bk_fit_run(&sp, &lsq), 0);
	cr_assert(lsq.fitted.max_abs > res.fitted.max_abs);
	bk_form_free(f);
	bk_samples_free(&s);
}

/* Split sum: constant forms for A and B fit the weighted means of A and B;
 * the A + B error is reported. */
Test(fit, split_sum_means)
{
	bk_samples s;
	bk_target_options o;
	char err[256];
	bk_target_defaults(BK_TARGET_ENV, &o);
	o.nx = o.nr = 8;
	cr_assert_eq(bk_target_build(&o, &s, NULL, NULL, err, sizeof err), 0);
	cr_assert_eq(s.ncomp, 2);
	double ma = 0, mb = 0, wa = 0, wb = 0;
	for (size_t i = 0; i < s.start[1]; i++)
		ma += s.w[i] * s.y[i], wa += s.w[i];
	for (size_t i = s.start[1]; i < s.n; i++)
		mb += s.w[i] * s.y[i], wb += s.w[i];
	bk_form *fa = form("p0"), *fb = form("p1");
	bk_fit_spec sp;
	bk_fit_result res;
	spec_init(&sp, &s, fa, 0.5);
	sp.form[1] = fb;
	sp.np = 2;
	cr_assert_eq(bk_fit_run(&sp, &res), 0, "%s", res.message);
	cr_assert(fabs(res.p[0] - ma / wa) < 1e-7 && fabs(res.p[1] - mb / wb) < 1e-7, "%g %g vs %g %g", res.p[0],
	          res.p[1], ma / wa, mb / wb);
	cr_assert(res.fitted.comp_max_abs[2] > 0 && res.fitted.comp_max_abs[0] > 0);
	bk_form_free(fa);
	bk_form_free(fb);
	bk_samples_free(&s);
}

/* An upper bound below the free optimum is where the solution lands. */
Test(fit, bound_below_the_optimum_is_active)
{
	bk_samples s;
	samples(BK_TARGET_VF2D, 16, 16, &s);
	bk_form *f = form("p0*f0/(4*LoH*LoH)");
	bk_fit_spec sp;
	bk_fit_result res;
	spec_init(&sp, &s, f, 0.1);
	sp.upper[0] = 0.2; /* the free optimum is ~0.38 */
	cr_assert_eq(bk_fit_run(&sp, &res), 0);
	cr_assert_eq(res.p[0], 0.2);
	bk_form_free(f);
	bk_samples_free(&s);
}

/* p0*p1 only appears as a product: neither is pinned by the data. */
Test(fit, unidentifiable_parameters_are_named)
{
	bk_samples s;
	samples(BK_TARGET_VF2D, 16, 16, &s);
	bk_form *f = form("p0*p1*f0/(4*LoH*LoH*(r + p2))");
	bk_fit_spec sp;
	bk_fit_result res;
	spec_init(&sp, &s, f, 0.7);
	cr_assert(bk_fit_run(&sp, &res) >= 0, "%s", res.message);
	/* p0 (first in index order) is held at its start so that the answer is
	 * unique; p1 then carries the product and is pinned */
	cr_assert(res.held[0] && !res.held[1] && !res.held[2]);
	cr_assert_eq(res.p[0], 0.7);
	cr_assert(res.unidentified[0] && !res.unidentified[1] && !res.unidentified[2]);
	cr_assert(isnan(res.se[0]) && isfinite(res.se[1]) && isfinite(res.se[2]));
	bk_form_free(f);
	bk_samples_free(&s);
}

/* Rounding: two significant digits, then fp16-representable values; the
 * others are refitted, so the error before rounding is no larger. */
Test(fit, digits_round_and_refit)
{
	bk_samples s;
	samples(BK_TARGET_VF2D, 16, 16, &s);
	bk_form *f = form("f0/(4*LoH*LoH*(p1*r + p0))");
	bk_fit_spec sp;
	bk_fit_result res;
	spec_init(&sp, &s, f, 0.5);
	sp.digits = 2;
	cr_assert(bk_fit_run(&sp, &res) >= 0);
	for (int j = 0; j < 2; j++) {
		double e = floor(log10(fabs(res.p[j]))) - 1, k = res.p[j] / pow(10, e);
		cr_assert(fabs(k - round(k)) < 1e-9, "p%d = %.17g has more than 2 digits", j, res.p[j]);
	}
	cr_assert(res.before_digits.cost <= res.fitted.cost * (1 + 1e-12));
	spec_init(&sp, &s, f, 0.5);
	sp.digits = -1;
	cr_assert(bk_fit_run(&sp, &res) >= 0);
	cr_assert(bk_half_round(res.p[0]) == res.p[0] && bk_half_round(res.p[1]) == res.p[1]);
	bk_form_free(f);
	bk_samples_free(&s);
}

/* A form that is NaN on part of the domain is counted and located; a pole on
 * the closed edge of the domain is found (the talk's 1/LoH^2 at LoH = 0). */
Test(fit, nonfinite_forms_and_edge_poles)
{
	bk_samples s;
	samples(BK_TARGET_F, 256, 1, &s);
	bk_form *f = form("log(LoH - 0.5) + p0");
	bk_fit_spec sp;
	char where[128];
	spec_init(&sp, &s, f, 0.0);
	cr_assert_eq(bk_fit_nonfinite(&sp, sp.start, where, sizeof where), 128);
	cr_assert_not_null(strstr(where, "LoH = 0.00195"), "%s", where); /* the first cell centre, 0.5/256 */
	bk_form_free(f);
	bk_samples_free(&s);

	bk_target_options o;
	char err[128];
	bk_target_defaults(BK_TARGET_VF2D, &o);
	o.nx = o.nr = 8;
	bk_form *talk = form("f0/(4*LoH*LoH*(r + p0))");
	cr_assert_eq(bk_target_build(&o, &s, NULL, NULL, err, sizeof err), 0);
	spec_init(&sp, &s, talk, 0.5);
	cr_assert_eq(bk_fit_edge_check(&sp, sp.start, where, sizeof where), 0); /* LoH^2 >= 0.1 */
	bk_samples_free(&s);
	o.x_lo = 0.0;
	cr_assert_eq(bk_target_build(&o, &s, NULL, NULL, err, sizeof err), 0);
	spec_init(&sp, &s, talk, 0.5);
	cr_assert_eq(bk_fit_edge_check(&sp, sp.start, where, sizeof where), 35); /* the LoH = 0 edge, 33 + 2 corners */
	bk_form_free(talk);
	bk_samples_free(&s);
}

/* The exact V·F, typed as a form, scores zero on vf; its albedo error too. */
Test(fit, exact_form_scores_zero)
{
	bk_samples s;
	bk_target_options o;
	char err[128];
	bk_target_defaults(BK_TARGET_VF, &o);
	o.nx = o.nr = 4;
	o.nu = o.nphi = 8;
	cr_assert_eq(bk_target_build(&o, &s, NULL, NULL, err, sizeof err), 0);
	bk_form *f = form("V_smith_ggx_correlated(NoV, NoL, a) * F_schlick(f0, 1, LoH)");
	bk_fit_spec sp;
	bk_fit_metrics m;
	spec_init(&sp, &s, f, 0.0);
	bk_fit_evaluate(&sp, sp.start, &m);
	cr_assert(m.rmse < 1e-12 * 100 && m.albedo_max_abs < 1e-12, "rmse %g albedo %g", m.rmse, m.albedo_max_abs);
	cr_assert(m.max_rel < 1e-12);
	bk_form_free(f);
	bk_samples_free(&s);
}

/* vf weights: each roughness row sums to 1/nr (each roughness weighs the
 * same), and the albedo measure summed over a cell is the directional
 * albedo of D·V·F·NoL, which the reference integrator gives independently. */
Test(fit, vf_measure_sums_to_the_albedo)
{
	bk_samples s;
	bk_target_options o;
	char err[128];
	bk_target_defaults(BK_TARGET_VF, &o);
	o.nx = o.nr = 4;
	o.nu = 256;
	o.nphi = 128;
	o.f0[0] = 1.0; /* F = 1: the albedo is A + B */
	cr_assert_eq(bk_target_build(&o, &s, NULL, NULL, err, sizeof err), 0);
	double rows[4] = {0}, cell[16] = {0};
	for (size_t i = 0; i < s.n; i++) {
		rows[s.cell[i] / 4] += s.w[i];
		cell[s.cell[i]] += s.measure[i] * s.y[i];
	}
	for (int j = 0; j < 4; j++)
		cr_assert(fabs(rows[j] - 0.25) < 1e-12);
	for (int c = 0; c < 16; c++) {
		double NoV = (c % 4 + 0.5) / 4, r = (c / 4 + 0.5) / 4, A, B;
		bk_dfg(NoV, r, BK_SMITH_CORRELATED, 1e-9, &A, &B, NULL);
		/* midpoint rule in (u, φ): first order where the NoL = 0 cut crosses the
		 * grid (grazing NoV); 3.6e-3 worst seen at 256 x 128, so 5e-3 */
		cr_assert(fabs(cell[c] - (A + B)) < 5e-3, "NoV %g r %g: %g vs %g", NoV, r, cell[c], A + B);
	}
	bk_samples_free(&s);
}

/* ---- what a fit that fitted nothing says (issue 21: M9, L4) ------------------ */

/* p1 held at 0: the regression of p0 alone, as above, and p1 has no standard
 * error (NaN), not 0, which would read "known exactly". Every parameter held:
 * nothing moves, so it is no fit at all (-1), never "converged". */
Test(fit, held_parameters_have_no_standard_error_and_all_held_is_no_fit)
{
	bk_samples s;
	samples(BK_TARGET_VF2D, 16, 16, &s);
	double swgy = 0, swgg = 0;
	for (size_t i = 0; i < s.n; i++) {
		double g = g_of(&s, i);
		swgy += s.w[i] * g * s.y[i];
		swgg += s.w[i] * g * g;
	}
	bk_form *f = form("p0*f0/(4*LoH*LoH) + p1");
	bk_fit_spec sp;
	bk_fit_result res;
	spec_init(&sp, &s, f, 1.0);
	sp.start[1] = 0.0;
	sp.hold[1] = 1;
	cr_assert_eq(bk_fit_run(&sp, &res), 0, "%s", res.message);
	cr_assert(fabs(res.p[0] - swgy / swgg) <= 1e-6 * fabs(swgy / swgg), "p0 %.12g vs %.12g", res.p[0], swgy / swgg);
	cr_assert_eq(res.p[1], 0.0);
	cr_assert(isfinite(res.se[0]) && res.se[0] > 0, "se p0 %g", res.se[0]);
	cr_assert(isnan(res.se[1]), "a held parameter's standard error is %g, not 'none'", res.se[1]);
	sp.hold[0] = 1;
	cr_assert_eq(bk_fit_run(&sp, &res), -1, "every parameter held gave %d (%s)", res.summary.termination,
	             res.message);
	cr_assert_not_null(strstr(res.message, "every parameter is held"), "%s", res.message);
	sp.hold[0] = 0; /* lower == upper fixes a parameter as --hold does */
	sp.lower[0] = sp.upper[0] = 1.0;
	cr_assert_eq(bk_fit_run(&sp, &res), -1, "%s", res.message);
	bk_form_free(f);
	bk_samples_free(&s);
}

/* p0 = 1e308: p0 LoH is finite but its square is not, so every start ends at
 * an infinite cost: a failure that says so, never an empty reason. The
 * control: the same form from p0 = 1 fits. */
Test(fit, every_start_failing_names_the_reason)
{
	bk_samples s;
	samples(BK_TARGET_F, 64, 1, &s);
	bk_form *f = form("p0*LoH");
	bk_fit_spec sp;
	bk_fit_result res;
	spec_init(&sp, &s, f, 1e308);
	sp.starts = 3;
	cr_assert_eq(bk_fit_run(&sp, &res), -1, "%s", res.message);
	cr_assert_not_null(strstr(res.message, "every start failed; the first, start 1 of 3: the cost is inf"), "'%s'",
	                   res.message);
	spec_init(&sp, &s, f, 1.0);
	cr_assert_eq(bk_fit_run(&sp, &res), 0, "%s", res.message);
	bk_form_free(f);
	bk_samples_free(&s);
}
