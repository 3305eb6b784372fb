/*
 * test_stiff.c — stiff fits with known optima (numerical stability, part 5):
 * a parameter inside an exponent started far away, nearly collinear
 * parameters, the talk's form started far from its optimum, wrong-stop traps
 * (a loose function tolerance on a problem with a large irreducible cost, and
 * data so small that Ceres' absolute gradient tolerance stops at once), and an
 * optimum on a bound inside an exponent. Every fit must either converge to the
 * known optimum or say that it did not (NO_CONVERGENCE, the parameters named):
 * never a silent "converged" at a wrong point.
 *
 * Tolerances are stated next to each assertion. As in test_solver.c, with
 * exact data (optimal cost 0) the solver converges quadratically and 1e-6 on
 * parameters leaves orders of magnitude of margin; with an optimal cost C > 0
 * a parameter is pinned only to sqrt(2 ftol' C / h) by the stopping rule
 * (ftol' = function_tolerance / 100 = 1e-14, h the curvature along it).
 */
#include "brdf.h"
#include "fit.h"
#include "fit_int.h"
#include "target.h"

#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static bk_form *form(const char *text)
{
	bk_form_error e;
	bk_form *f = bk_form_parse(text, &e);
	cr_assert_not_null(f, "%s: %s", text, e.message);
	return f;
}

/* Samples y(LoH) at the n points x by hand: LoH the only input (the others
 * NaN, as bk_target_build leaves inputs a target does not provide), weight
 * 1/n each, one plane cell per sample, no albedo measure. */
static void hand_samples(bk_samples *s, size_t n, const double *x, const double *y)
{
	memset(s, 0, sizeof *s);
	s->n = n;
	for (int k = 0; k < BK_IN_COUNT; k++) {
		s->in[k] = malloc(sizeof(double) * n);
		cr_assert_not_null(s->in[k]);
		for (size_t i = 0; i < n; i++)
			s->in[k][i] = k == BK_IN_LOH ? x[i] : NAN;
	}
	s->y = malloc(sizeof(double) * n);
	s->w = malloc(sizeof(double) * n);
	s->measure = calloc(n, sizeof(double));
	s->cell = malloc(sizeof(int) * n);
	cr_assert(s->y && s->w && s->measure && s->cell);
	for (size_t i = 0; i < n; i++) {
		s->y[i] = y[i];
		s->w[i] = 1.0 / (double)n;
		s->cell[i] = (int)i;
	}
	s->start[1] = s->start[2] = n;
	s->ncomp = 1;
	s->provides = 1u << BK_IN_LOH;
	s->plane_nx = (int)n;
	s->plane_ny = 1;
	s->plane_x0 = x[0];
	s->plane_x1 = x[n - 1];
	s->plane_y1 = 1;
	s->plane_xname = "LoH";
	s->plane_yname = "-";
	s->plane_x_input = BK_IN_LOH;
	s->plane_y_input = -1;
	snprintf(s->description, sizeof s->description, "hand-made samples of y(LoH) for test_stiff.c");
}

static void spec_init(bk_fit_spec *sp, const bk_samples *s, const bk_form *f, const double *start)
{
	bk_fit_options o = BK_FIT_OPTIONS_INIT;
	memset(sp, 0, sizeof *sp);
	sp->s = s;
	sp->form[0] = f;
	sp->np = bk_form_nparams(f);
	sp->opt = o;
	sp->starts = 1;
	for (int j = 0; j < BK_MAX_PARAMS; j++) {
		sp->start[j] = j < sp->np ? start[j] : 0.0;
		sp->lower[j] = -HUGE_VAL;
		sp->upper[j] = HUGE_VAL;
	}
}

/* The honesty contract: a fit either converged (rc 0, CONVERGENCE, every
 * checked gradient small) or says it did not (rc 1, NO_CONVERGENCE, and a
 * message naming each parameter whose gradient is not small); rc -1 (failed)
 * also says so, with a message. Returns rc. */
static int honest(int rc, const bk_fit_spec *sp, const bk_fit_result *r, const char *what)
{
	cr_assert(rc >= -1 && rc <= 1, "%s: rc %d", what, rc);
	if (rc == -1) {
		cr_assert(r->message[0], "%s: failed without a message", what);
		return rc;
	}
	if (rc == 0) {
		cr_assert_eq(r->summary.termination, BK_TERM_CONVERGENCE, "%s", what);
		cr_assert_eq(r->optimal, 1, "%s: converged but optimal = %d: %s", what, r->optimal, r->message);
		for (int j = 0; j < sp->np; j++)
			cr_assert(isnan(r->grad_rel[j]) || r->grad_rel[j] <= BK_FIT_GRAD_TOL, "%s: p%d grad_rel %g", what, j,
			          r->grad_rel[j]);
		return rc;
	}
	cr_assert_neq(r->summary.termination, BK_TERM_CONVERGENCE, "%s", what);
	if (r->optimal == 0) {
		cr_assert_not_null(strstr(r->message, "not a minimum"), "%s: %s", what, r->message);
		for (int j = 0; j < sp->np; j++)
			if (r->grad_rel[j] > BK_FIT_GRAD_TOL) {
				char name[24];
				snprintf(name, sizeof name, "∂p%d|", j);
				cr_assert_not_null(strstr(r->message, name), "%s: p%d not named in: %s", what, j, r->message);
			}
	}
	return rc;
}

/* ---- a parameter inside an exponent -------------------------------------------- */

enum { N = 200 };

/* y = amp exp(-7 x) at x = (i + 1)/N, i < N: LoH in (0, 1], exact. */
static void exp_samples(bk_samples *s, double amp)
{
	double x[N], y[N];
	for (int i = 0; i < N; i++) {
		x[i] = (i + 1.0) / N;
		y[i] = amp * exp(-7 * x[i]);
	}
	hand_samples(s, N, x, y);
}

/* a. y = 2 exp(-7 LoH), the form p0 exp(p1 LoH) started at (0.1, +3): growth
 * for decay, the amplitude 20x too small, e^3 / e^-7 ~ 2e4 between start and
 * answer at LoH = 1. Both trust-region strategies. The data are exact, so a
 * converged fit has cost at the rounding of y (~1e-31 here) and is at (2, -7)
 * to ~1e-15; 1e-6 relative (the bound) leaves nine orders of margin,
 * and would still catch a stop anywhere the gradient test lets through. */
Test(stiff, exponent_far_start)
{
	bk_samples s;
	exp_samples(&s, 2.0);
	bk_form *f = form("p0*exp(p1*LoH)");
	static const double st[] = {0.1, 3.0};
	for (int tr = BK_TR_LEVENBERG_MARQUARDT; tr <= BK_TR_DOGLEG; tr++) {
		bk_fit_spec sp;
		bk_fit_result r;
		spec_init(&sp, &s, f, st);
		sp.opt.trust_region = (bk_trust_region)tr;
		int rc = honest(bk_fit_run(&sp, &r), &sp, &r, tr ? "dogleg" : "lm");
		if (rc == 0) {
			cr_assert(fabs(r.p[0] - 2) <= 1e-6 * 2, "tr %d: p0 = %.17g", tr, r.p[0]);
			cr_assert(fabs(r.p[1] + 7) <= 1e-6 * 7, "tr %d: p1 = %.17g", tr, r.p[1]);
			/* exact data: cost at the rounding of y, 1e-20 of sum w y^2 / 2 = 0.14 */
			cr_assert(r.fitted.cost < 1e-20, "tr %d: cost %g", tr, r.fitted.cost);
			cr_assert(r.condition >= 1 && r.condition < BK_FIT_COND_MAX, "tr %d: condition %g", tr, r.condition);
		} else
			cr_log_warn("exponent_far_start, tr %d: did not converge (%s)", tr, r.message);
	}
	bk_form_free(f);
	bk_samples_free(&s);
}

/* e. The same with p1 <= -8: the constrained optimum has p1 on its bound
 * exactly (the cost rises away from -7, so it is least at -8) and p0 the 1-D
 * least-squares amplitude there, p0 = Σ w y e^-8x / Σ w e^-16x (the form is
 * linear in p0). The gradient in p1 at the solution is negative: descent would
 * raise p1 above -8, out of the box, so the projected-gradient test must
 * exclude it (grad_rel NaN) and report CONVERGENCE. Started at p1 = -20 (the
 * start must lie in the box). p0: C = 6e-4 > 0 and h = Σ w e^-16x ~ 1/16, so
 * the stopping rule pins it to sqrt(2e-14 C / h) ~ 1.4e-8, relative ~7e-9;
 * 1e-7 relative. */
Test(stiff, exponent_bound_active)
{
	bk_samples s;
	exp_samples(&s, 2.0);
	bk_form *f = form("p0*exp(p1*LoH)");
	static const double st[] = {0.1, -20.0};
	bk_fit_spec sp;
	bk_fit_result r;
	spec_init(&sp, &s, f, st);
	sp.upper[1] = -8;
	cr_assert_eq(honest(bk_fit_run(&sp, &r), &sp, &r, "bounded"), 0, "%s", r.message);
	cr_assert_eq(r.summary.termination, BK_TERM_CONVERGENCE);
	cr_assert_eq(r.p[1], -8.0, "p1 = %.17g", r.p[1]);
	double a = 0, b = 0;
	for (size_t i = 0; i < s.n; i++) {
		double e = exp(-8 * s.in[BK_IN_LOH][i]);
		a += s.w[i] * s.y[i] * e;
		b += s.w[i] * e * e;
	}
	cr_assert(fabs(r.p[0] - a / b) <= 1e-7 * a / b, "p0 %.17g vs %.17g", r.p[0], a / b);
	cr_assert(r.grad[1] < 0 && isnan(r.grad_rel[1]), "p1: grad %g, grad_rel %g", r.grad[1], r.grad_rel[1]);
	cr_assert(r.grad_rel[0] <= BK_FIT_GRAD_TOL);
	cr_assert_eq(r.optimal, 1);
	bk_form_free(f);
	bk_samples_free(&s);
}

/* A held parameter is no part of the check: p1 held at -5, away from its
 * free optimum -7, has a large gradient, and the fit of p0 alone (closed form
 * Σ w y e^-5x / Σ w e^-10x, linear; C > 0, so 1e-7 relative as in e) must
 * still report CONVERGENCE, with grad_rel[1] NaN and grad[1] not small. */
Test(stiff, held_parameter_excluded)
{
	bk_samples s;
	exp_samples(&s, 2.0);
	bk_form *f = form("p0*exp(p1*LoH)");
	static const double st[] = {0.1, -5.0};
	bk_fit_spec sp;
	bk_fit_result r;
	spec_init(&sp, &s, f, st);
	sp.hold[1] = 1;
	cr_assert_eq(honest(bk_fit_run(&sp, &r), &sp, &r, "held"), 0, "%s", r.message);
	double a = 0, b = 0;
	for (size_t i = 0; i < s.n; i++) {
		double e = exp(-5 * s.in[BK_IN_LOH][i]);
		a += s.w[i] * s.y[i] * e;
		b += s.w[i] * e * e;
	}
	cr_assert(fabs(r.p[0] - a / b) <= 1e-7 * a / b, "p0 %.17g vs %.17g", r.p[0], a / b);
	cr_assert_eq(r.p[1], -5.0);
	cr_assert(isnan(r.grad_rel[1]) && fabs(r.grad[1]) > 1e-3, "p1: grad %g, grad_rel %g", r.grad[1], r.grad_rel[1]);
	cr_assert(isnan(r.se[1]) && isfinite(r.se[0]) && r.condition == 1, "se %g %g, condition %g", r.se[0], r.se[1],
	          r.condition);
	bk_form_free(f);
	bk_samples_free(&s);
}

/* d2. A wrong-stop trap: the same exponential at amplitude 2e-8. From (0.1, 3)
 * the first steps shrink p0 to the data's size, after which every gradient is
 * below Ceres' absolute gradient_tolerance (1e-12: the cost is ~1e-17, and
 * ∂cost/∂p1 carries a factor p0 ~ 1e-10): Ceres alone stops at once with
 * "Gradient tolerance reached" and CONVERGENCE at p1 ~ 3 (checked below
 * through bk_fit_solve, the fitter's own call of the bridge). The scale-free
 * test sees cos = 0.08 for p1 there; the fitter re-solves with the residuals
 * normalised (fit.c, POLISH) and must then be at (2e-8, -7) to 1e-6 relative
 * (exact data, as in a), or report NO_CONVERGENCE naming p1. */
Test(stiff, tiny_amplitude_gradient_tolerance_trap)
{
	bk_samples s;
	exp_samples(&s, 2e-8);
	bk_form *f = form("p0*exp(p1*LoH)");
	static const double st[] = {0.1, 3.0};
	bk_fit_spec sp;
	bk_fit_result r;
	spec_init(&sp, &s, f, st);
	/* the trap, as Ceres alone springs it */
	bk_fit_ctx c;
	cr_assert_eq(bk_fit_ctx_init(&c, &sp), 0);
	double p[BK_MAX_PARAMS] = {0.1, 3.0};
	bk_fit_summary sum;
	cr_assert_eq(bk_fit_solve(&c, p, sp.hold, &sum), 0, "%s", sum.message);
	bk_fit_ctx_free(&c);
	if (sum.termination != BK_TERM_CONVERGENCE || fabs(p[1] + 7) < 1)
		cr_log_warn("the trap did not spring (Ceres: %s, p1 = %g): this test no longer tests a wrong stop",
		            sum.message, p[1]);
	/* the fitter */
	int rc = honest(bk_fit_run(&sp, &r), &sp, &r, "tiny amplitude");
	if (rc == 0) {
		cr_assert(fabs(r.p[0] - 2e-8) <= 1e-6 * 2e-8, "p0 = %.17g", r.p[0]);
		cr_assert(fabs(r.p[1] + 7) <= 1e-6 * 7, "p1 = %.17g", r.p[1]);
		cr_assert(r.polish_solves >= 1, "converged without the re-solve: the trap did not spring");
		cr_assert_not_null(strstr(r.message, "re-solve"), "the re-solve is not reported: %s", r.message);
	} else
		cr_assert(rc == 1 && r.optimal == 0 && strstr(r.message, "∂p1|"), "rc %d: %s", rc, r.message);
	bk_form_free(f);
	bk_samples_free(&s);
}

/* ---- collinear parameters -------------------------------------------------------- */

/* b. y = 1 + LoH (exact), the form p0 LoH + p1 LoH (1 + 1e-7 LoH) + p2: p0
 * and p1 differ by 1e-7 LoH^2 only. The data are representable (the exact
 * optimum is p = (1, 0, 1), cost 0), but the direction p0 - p1 is pinned only
 * through that 1e-7 term: the column-scaled cond(JᵀJ) is ~(σ_max / σ_min)^2
 * with σ_min ~ 1e-7 |LoH² ⊥ {1, LoH}| ~ 5e-9: ~3e16, so above the 1e10 of
 * identifiability. So p0 is held at its start (fit.c, hold_unidentified),
 * p1 and p2 re-solved.
 * Cost ~0: a point a distance d = O(1) from the optimum along p0 - p1 costs
 * only 1/2 (5e-9 d)^2 ~ 1e-17, while missing the valley floor (p0 + p1 off by
 * 1e-6) costs 1/2 (1e-6 |LoH|)^2 ~ 2e-13: cost <= 1e-15 (sum w y^2 / 2 = 1.2)
 * says the fit is on the floor. On the floor, p0 + p1 = 1 - 1e-7 p1 and p2 =
 * 1 + 1e-7 p1 / 6 (the L2 projection of LoH^2 on {1, LoH}), so both are within
 * 1e-6 of 1 for |p1| <= 10: 1e-6, as the issue asks. */
Test(stiff, nearly_collinear_representable)
{
	double x[N], y[N];
	for (int i = 0; i < N; i++)
		x[i] = (i + 1.0) / N, y[i] = 1 + x[i];
	bk_samples s;
	hand_samples(&s, N, x, y);
	bk_form *f = form("p0*LoH + p1*LoH*(1 + 1e-7*LoH) + p2");
	static const double st[] = {0.5, 0.5, 0.5};
	bk_fit_spec sp;
	bk_fit_result r;
	spec_init(&sp, &s, f, st);
	int rc = honest(bk_fit_run(&sp, &r), &sp, &r, "collinear");
	cr_assert_eq(rc, 0, "%s", r.message);
	cr_assert(r.fitted.cost <= 1e-15, "cost %g", r.fitted.cost);
	cr_assert(fabs(r.p[0] + r.p[1] - 1) <= 1e-6, "p0 + p1 = %.17g", r.p[0] + r.p[1]);
	cr_assert(fabs(r.p[2] - 1) <= 1e-6, "p2 = %.17g", r.p[2]);
	/* the valley is cut so that the answer is unique (issue 9: the point on
	 * it moved with the CPU's libm): p0, first in index order, is held at its
	 * start and p1 re-solved, now pinned (the others span LoH(1 + 1e-7 LoH)
	 * and 1: well conditioned) */
	cr_assert(r.held[0] && !r.held[1] && !r.held[2]);
	cr_assert_eq(r.p[0], 0.5);
	cr_assert(r.condition < 1e8, "condition %g", r.condition);
	cr_assert(r.unidentified[0] && !r.unidentified[1] && !r.unidentified[2]);
	cr_assert(isnan(r.se[0]) && isfinite(r.se[1]) && isfinite(r.se[2]));
	cr_assert_not_null(strstr(r.message, "not identifiable, held at the start value so that the answer is unique: p0"),
	                   "%s", r.message);
	bk_form_free(f);
	bk_samples_free(&s);
}

/* 3 x 3 inverse by cofactors, in long double (64-bit significand: JᵀJ of b2
 * has condition ~1e9, which costs ~1e-10 relative there). */
static void inverse3(const long double m[3][3], long double inv[3][3])
{
	long double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
	                  m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
	                  m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++) {
			int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
			inv[i][j] = (m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]) / det;
		}
}

/* b2. Nearly collinear but identifiable: p0 and p1 differ by 1e-3 LoH^2, so
 * the scaled condition is ~3e8, between BK_FIT_COND_MAX (1e8: flagged, p0 and
 * p1 collinear) and 1e10 (unidentifiable): the standard errors must be large
 * but finite, and right. The data y = 1 + LoH + 0.01 cos(20 LoH) are not
 * representable (C > 0). The form is linear, so everything is closed form:
 * p* = (JᵀJ)⁻¹ Jᵀ y, se_j = sqrt(σ² (JᵀJ)⁻¹_jj), σ² = Σ w r² / (m - 3).
 * Tolerances: se to 1e-6 relative (J does not depend on p, and the QR and
 * Jacobi SVD are accurate to ~eps cond(J) ~ 1e-12; σ² is stationary at the
 * optimum); p to 1e-5 se: the stopping rule leaves p at sqrt(2 ftol' C / h)
 * along the weakest direction, which is sqrt(ftol' (m - 3)) = 1.4e-6 of its
 * standard error, and rounding sqrt(64 eps (m - 3) / 2) = 1.2e-6 of it. */
Test(stiff, nearly_collinear_finite_standard_errors)
{
	double x[N], y[N];
	for (int i = 0; i < N; i++)
		x[i] = (i + 1.0) / N, y[i] = 1 + x[i] + 0.01 * cos(20 * x[i]);
	bk_samples s;
	hand_samples(&s, N, x, y);
	bk_form *f = form("p0*LoH + p1*LoH*(1 + 1e-3*LoH) + p2");
	static const double st[] = {0.5, 0.5, 0.5};
	bk_fit_spec sp;
	bk_fit_result r;
	spec_init(&sp, &s, f, st);
	cr_assert_eq(honest(bk_fit_run(&sp, &r), &sp, &r, "nearly collinear"), 0, "%s", r.message);
	long double jtj[3][3] = {{0}}, jty[3] = {0}, inv[3][3], ps[3] = {0}, rss = 0;
	for (int i = 0; i < N; i++) {
		long double col[3] = {x[i], x[i] * (1 + 1e-3L * x[i]), 1}, w = s.w[i];
		for (int a = 0; a < 3; a++) {
			jty[a] += w * col[a] * y[i];
			for (int b = 0; b < 3; b++)
				jtj[a][b] += w * col[a] * col[b];
		}
	}
	inverse3(jtj, inv);
	for (int a = 0; a < 3; a++)
		for (int b = 0; b < 3; b++)
			ps[a] += inv[a][b] * jty[b];
	for (int i = 0; i < N; i++) {
		long double e = ps[0] * x[i] + ps[1] * x[i] * (1 + 1e-3L * x[i]) + ps[2] - y[i];
		rss += s.w[i] * e * e;
	}
	for (int j = 0; j < 3; j++) {
		double se = (double)sqrtl(rss / (N - 3) * inv[j][j]);
		cr_assert(isfinite(r.se[j]) && fabs(r.se[j] - se) <= 1e-6 * se, "p%d: se %.10g vs %.10g", j, r.se[j], se);
		cr_assert(fabs(r.p[j] - (double)ps[j]) <= 1e-5 * se, "p%d = %.17g vs %.17Lg (se %g)", j, r.p[j], ps[j], se);
	}
	/* large: the collinear pair's errors are ~1e3 times p2's (and than the
	 * 0.01 amplitude of what the form cannot represent) */
	cr_assert(r.se[0] > 1e3 * r.se[2] && r.se[1] > 1e3 * r.se[2], "se %g %g %g", r.se[0], r.se[1], r.se[2]);
	cr_assert(r.condition > BK_FIT_COND_MAX && r.condition < 1e10, "condition %g", r.condition);
	cr_assert(r.collinear[0] && r.collinear[1] && !r.collinear[2]);
	cr_assert(!r.unidentified[0] && !r.unidentified[1] && !r.unidentified[2]);
	cr_assert_not_null(strstr(r.message, "ill-conditioned"), "%s", r.message);
	bk_form_free(f);
	bk_samples_free(&s);
}

/* ---- far from the optimum ----------------------------------------------------------- */

/* c. The talk's form f0 / (4 LoH^2 (r + p0)) on vf2d (32 x 32 cells), from
 * its catalog start 0.5 and from 50 and 1e-3 (100x too large: the form ~0;
 * 500x too small: a near-pole at r -> 0, the form ~30x too large there) and,
 * further, 1e3 and 1e-5. Each must reach the optimum from 0.5 to 1e-6 relative
 * or say it did not converge. Why 1e-6: the cost C > 0, h = ∂²cost/∂p0², and
 * the stopping rule pins p0 to sqrt(2 ftol' C / h), ~3e-8 relative here (the
 * spread seen is 3e-8): 1e-6 is 30x that. */
Test(stiff, talk_form_far_starts)
{
	bk_target_options o;
	char err[256];
	bk_samples s;
	bk_target_defaults(BK_TARGET_VF2D, &o);
	o.nx = o.nr = 32;
	cr_assert_eq(bk_target_build(&o, &s, NULL, NULL, err, sizeof err), 0, "%s", err);
	bk_form *f = form("f0/(4*LoH*LoH*(r + p0))");
	bk_fit_spec sp;
	bk_fit_result r;
	static const double ref_start[] = {0.5};
	spec_init(&sp, &s, f, ref_start);
	cr_assert_eq(honest(bk_fit_run(&sp, &r), &sp, &r, "from 0.5"), 0, "%s", r.message);
	double ref = r.p[0];
	cr_assert(ref > 0.2 && ref < 0.4, "p0 = %g", ref); /* ~0.2956: the optimum found on this grid */
	static const double starts[] = {50, 1e-3, 1e3, 1e-5};
	for (int k = 0; k < 4; k++) {
		char what[32];
		snprintf(what, sizeof what, "from %g", starts[k]);
		spec_init(&sp, &s, f, &starts[k]);
		int rc = honest(bk_fit_run(&sp, &r), &sp, &r, what);
		if (rc == 0)
			cr_assert(fabs(r.p[0] - ref) <= 1e-6 * ref, "%s: p0 = %.17g vs %.17g", what, r.p[0], ref);
		else
			cr_log_warn("talk_form_far_starts %s: did not converge (%s)", what, r.message);
	}
	bk_form_free(f);
	bk_samples_free(&s);
}

/* ---- wrong stops ---------------------------------------------------------------------- */

/* Rosenbrock as a form: at LoH = 0 the form is p0, at LoH = 1 it is
 * 10 (p1 - p0^2). Samples in pairs: LoH = 0 with y = 1 ± 0.1, LoH = 1 with
 * y = ±0.3. Each pair's residuals are (v - y0) ± δ, whose sum of squares is
 * 2 (v - y0)^2 + 2 δ^2: the problem is Rosenbrock's, minimum at (1, 1), plus
 * an irreducible cost C = (2 (0.1^2 + 0.3^2)) / 4 / 2 = 0.025 (weights 1/4).
 * A known optimum with C > 0, in a curved valley. */
static void rosenbrock_samples(bk_samples *s)
{
	static const double x[] = {0, 0, 1, 1}, y[] = {0.9, 1.1, -0.3, 0.3};
	hand_samples(s, 4, x, y);
}

/* d. The trap: function_tolerance = 1e-2 (Ceres is asked for 1e-4 by the
 * bridge) from (-3, 5). The function tolerance is relative to the cost, and
 * near the valley nearly all of the cost is the irreducible C, so Ceres
 * declines a step that would lower it by 7e-5 of itself and reports
 * CONVERGENCE at (0.99846, 0.99670), with relative gradients 6.7e-3 and
 * 7.0e-3 (measured when this was written; a re-solve from there declines the
 * same step). The fitter must not
 * call that converged: either it reaches (1, 1) (to 1e-6, as with the default
 * tolerances, checked first: there the stop pins p to sqrt(2 ftol' C / h),
 * ~3e-8 with h ~ 1 along the valley's floor) or it reports NO_CONVERGENCE
 * naming the parameters. Also with 0.5 and 1 (the loosest Ceres accepts). */
Test(stiff, loose_function_tolerance_trap)
{
	bk_samples s;
	rosenbrock_samples(&s);
	bk_form *f = form("(1 - LoH)*p0 + LoH*10*(p1 - p0*p0)");
	static const double st[] = {-3.0, 5.0};
	bk_fit_spec sp;
	bk_fit_result r;
	spec_init(&sp, &s, f, st);
	cr_assert_eq(honest(bk_fit_run(&sp, &r), &sp, &r, "default tolerances"), 0, "%s", r.message);
	cr_assert(fabs(r.p[0] - 1) <= 1e-6 && fabs(r.p[1] - 1) <= 1e-6, "p = (%.17g, %.17g)", r.p[0], r.p[1]);
	cr_assert(fabs(r.fitted.cost - 0.025) <= 1e-12, "cost %.17g", r.fitted.cost);
	static const double ftol[] = {1e-2, 0.5, 1.0};
	int flagged = 0;
	for (int k = 0; k < 3; k++) {
		char what[32];
		snprintf(what, sizeof what, "ftol %g", ftol[k]);
		spec_init(&sp, &s, f, st);
		sp.opt.function_tolerance = ftol[k];
		/* a finite bound far from the answer sends the fit through Ceres, whose
		 * wrong stop this test is about (unbounded fits take the TinySolver
		 * fast path, which does not fall into it: test_tiny.c) */
		sp.lower[0] = -1e6;
		int rc = honest(bk_fit_run(&sp, &r), &sp, &r, what);
		/* A loose stop that passes the optimality check is a legitimate answer
		 * (the fast path, fit/tiny.cc, takes the step that meets ftol and
		 * stops at ~4e-5 from (1, 1) with ftol 1e-2, no polish needed): it is
		 * held to what that check promises. cost = 1/4 Rosenbrock + C, so
		 * H = 1/4 [[802, -400], [-400, 200]] at (1, 1), smallest eigenvalue
		 * (1002 - sqrt(1002404))/8 = 0.0998; honest() bounds each |g_j| by
		 * 1e-4 ||J_j|| ||s|| (||J_0||² = 200.5, ||J_1||² = 50, ||s||² = 2C),
		 * so |p - (1, 1)| <= 1e-4 sqrt(0.05 · 250.5) / 0.0998 = 3.5e-3. */
		if (rc == 0)
			cr_assert(hypot(r.p[0] - 1, r.p[1] - 1) <= 3.6e-3, "%s: converged at (%.17g, %.17g)", what, r.p[0],
			          r.p[1]);
		else {
			cr_assert_eq(rc, 1, "%s: %s", what, r.message);
			cr_assert_eq(r.optimal, 0, "%s", what);
			cr_assert_not_null(strstr(r.summary.message, "not a minimum"), "%s: %s", what, r.summary.message);
			flagged++;
		}
	}
	if (!flagged)
		cr_log_warn("loose_function_tolerance_trap: every loose fit reached (1, 1): the trap did not spring");
	bk_form_free(f);
	bk_samples_free(&s);
}

/* The check is of the cost Ceres minimises: with a robust loss, of
 * 1/2 Σ rho(r²), whose gradient is Σ rho'(r²) r ∂r. On the exponential of a
 * with 10 samples pushed far off (outliers), a Huber or Cauchy fit converges
 * to a point where the plain least-squares gradient is far from 0 but the
 * robust one is not: it must pass (a check of the wrong cost would call it not
 * a minimum). */
Test(stiff, robust_loss_is_checked_on_its_own_cost)
{
	double x[N], y[N];
	for (int i = 0; i < N; i++) {
		x[i] = (i + 1.0) / N;
		y[i] = 2 * exp(-7 * x[i]) + (i % 20 == 7 ? 0.5 : 0.0);
	}
	bk_samples s;
	hand_samples(&s, N, x, y);
	bk_form *f = form("p0*exp(p1*LoH)");
	static const double st[] = {1.0, -5.0};
	for (int loss = BK_LOSS_HUBER; loss <= BK_LOSS_SOFTL1; loss++) {
		bk_fit_spec sp;
		bk_fit_result r;
		spec_init(&sp, &s, f, st);
		sp.opt.loss = (bk_loss)loss;
		sp.opt.loss_scale = 0.01; /* in the weighted residuals' units: sqrt(1/N) * 0.14 */
		cr_assert_eq(honest(bk_fit_run(&sp, &r), &sp, &r, "robust"), 0, "loss %d: %s", loss, r.message);
		/* the plain least-squares gradient at that point: not small */
		bk_fit_spec plain = sp;
		plain.opt.loss = BK_LOSS_NONE;
		bk_fit_ctx c;
		bk_fit_result chk;
		cr_assert_eq(bk_fit_ctx_init(&c, &plain), 0);
		memset(&chk, 0, sizeof chk);
		cr_assert(bk_fit_optimality(&c, r.p, plain.hold, &chk, NULL) >= 0, "loss %d: plain lsq would pass too", loss);
		bk_fit_ctx_free(&c);
	}
	bk_form_free(f);
	bk_samples_free(&s);
}

/* ---- the no-step rule (issue 9) ------------------------------------------------- */

/* A fit that took no step is converged only if its start passes the
 * optimality check by itself. y = 1/(1 + x) is fitted by 1/(p0 + x), optimum
 * p0 = 1 (exact data); started at p0 = 1e300 the form is ~1e-300 and its
 * derivative -1/(p0 + x)² underflows to 0: the gradient is exactly 0, Ceres
 * stops at once, and the old fitter called that converged. It is a plateau:
 * NO_CONVERGENCE, saying that no step was taken and why. */
Test(stiff, no_step_on_a_plateau_is_not_convergence)
{
	double x[N], y[N];
	for (int i = 0; i < N; i++)
		x[i] = (i + 1.0) / N, y[i] = 1 / (1 + x[i]);
	bk_samples s;
	hand_samples(&s, N, x, y);
	bk_form *f = form("1/(p0 + LoH)");
	static const double far[] = {1e300}, near[] = {3};
	bk_fit_spec sp;
	bk_fit_result r;
	spec_init(&sp, &s, f, far);
	int rc = bk_fit_run(&sp, &r);
	cr_assert_eq(rc, 1, "rc %d: %s", rc, r.message);
	cr_assert_eq(r.summary.termination, BK_TERM_NO_CONVERGENCE);
	cr_assert_not_null(strstr(r.summary.message, "no step taken from a point that is not a minimum: the cost is flat"),
	                   "%s", r.summary.message);
	/* the same problem from a start it can leave finds the optimum */
	spec_init(&sp, &s, f, near);
	cr_assert_eq(honest(bk_fit_run(&sp, &r), &sp, &r, "near"), 0, "%s", r.message);
	cr_assert(fabs(r.p[0] - 1) <= 1e-6, "p0 = %.17g", r.p[0]);
	bk_form_free(f);
	bk_samples_free(&s);
}

/* A Huber scale of 1e-300 flattens every residual: the cost is 2c Σ|r| ~ 1e-300
 * and its gradient far below Ceres' absolute gradient tolerance, so Ceres
 * stops at the start. y = 2x fitted by p0 x from p0 = 3 (optimum 2, every
 * residual x > 0 of one sign: the L1 gradient is not small): the old check
 * measured the gradient against a floor in the unrobustified target's units
 * (~1) and passed it. Now: NO_CONVERGENCE, p0 named; the same loss at scale
 * 1e-2 still finds p0 = 2. */
Test(stiff, no_step_under_a_flattening_loss_is_not_convergence)
{
	double x[N], y[N];
	for (int i = 0; i < N; i++)
		x[i] = (i + 1.0) / N, y[i] = 2 * x[i];
	bk_samples s;
	hand_samples(&s, N, x, y);
	bk_form *f = form("p0*LoH");
	static const double st[] = {3};
	bk_fit_spec sp;
	bk_fit_result r;
	spec_init(&sp, &s, f, st);
	sp.opt.loss = BK_LOSS_HUBER;
	sp.opt.loss_scale = 1e-300;
	int rc = honest(bk_fit_run(&sp, &r), &sp, &r, "huber 1e-300");
	cr_assert_eq(rc, 1, "rc %d: %s", rc, r.message);
	cr_assert_not_null(strstr(r.summary.message, "no step taken from a point that is not a minimum: p0"), "%s",
	                   r.summary.message);
	sp.opt.loss_scale = 1e-2;
	cr_assert_eq(honest(bk_fit_run(&sp, &r), &sp, &r, "huber 1e-2"), 0, "%s", r.message);
	cr_assert(fabs(r.p[0] - 2) <= 1e-6, "p0 = %.17g", r.p[0]);
	bk_form_free(f);
	bk_samples_free(&s);
}
