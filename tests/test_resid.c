/*
 * test_resid.c — a fit's residual blocks (fit/fit_ctx.c) and the IR's
 * reverse-mode Jacobian (brdf/ir_diff.c), bit for bit against closed forms.
 *
 * The speed work of issue 10 writes the form's values and Jacobian straight
 * into the solver's arrays and scales them there, and splits the backward
 * sweep per operand so that it vectorises; both promise the same IEEE
 * operations per sample as before. These tests hold them to it: for forms
 * whose derivative is exact in floating point, each residual and each
 * Jacobian entry must equal the closed form computed here with the same
 * operations (the build has no FMA contraction: -std=c11), to the last bit.
 * Sample counts that are not multiples of the blocks (1024 residuals per fit
 * block, BK_IR_BLOCK per IR block) exercise the partial blocks.
 */
#include "fit.h"
#include "fit_int.h"

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

/* n samples of LoH in (0, 1], y = 1 + sin-like wiggle, weight varying, split
 * into ncomp components at n0 (ncomp 1: n0 = n). Inputs other than LoH NaN,
 * as bk_target_build leaves those a target does not provide. */
static void samples(bk_samples *s, size_t n, size_t n0, int ncomp)
{
	memset(s, 0, sizeof *s);
	s->n = n;
	for (int k = 0; k < BK_IN_COUNT; k++) {
		s->in[k] = malloc(sizeof(double) * n);
		cr_assert_not_null(s->in[k]);
		for (size_t i = 0; i < n; i++)
			s->in[k][i] = k == BK_IN_LOH ? (i + 1.0) / (double)n : NAN;
	}
	s->y = malloc(sizeof(double) * n);
	s->w = malloc(sizeof(double) * n);
	s->measure = calloc(n, sizeof(double));
	s->cell = malloc(sizeof(int) * n);
	cr_assert(s->y && s->w && s->measure && s->cell);
	for (size_t i = 0; i < n; i++) {
		double x = s->in[BK_IN_LOH][i];
		s->y[i] = 0.5 + x * x - 0.25 * x; /* never 0: relative residuals defined */
		s->w[i] = 1.0 + (double)(i % 7);
		s->cell[i] = (int)i;
	}
	s->start[0] = 0;
	s->start[1] = ncomp == 2 ? n0 : n;
	s->start[2] = n;
	s->ncomp = ncomp;
	s->provides = 1u << BK_IN_LOH;
	s->plane_nx = (int)n;
	s->plane_ny = 1;
	s->plane_x0 = s->in[BK_IN_LOH][0];
	s->plane_x1 = 1;
	s->plane_y1 = 1;
	s->plane_xname = "LoH";
	s->plane_yname = "-";
	s->plane_x_input = BK_IN_LOH;
	s->plane_y_input = -1;
	snprintf(s->description, sizeof s->description, "hand-made samples for test_resid.c");
}

static void spec_init(bk_fit_spec *sp, const bk_samples *s, const bk_form *f0, const bk_form *f1, int np,
                      int relative)
{
	bk_fit_options o = BK_FIT_OPTIONS_INIT;
	memset(sp, 0, sizeof *sp);
	sp->s = s;
	sp->form[0] = f0;
	sp->form[1] = f1;
	sp->np = np;
	sp->opt = o;
	sp->starts = 1;
	sp->relative = relative;
	for (int j = 0; j < BK_MAX_PARAMS; j++) {
		sp->lower[j] = -HUGE_VAL;
		sp->upper[j] = HUGE_VAL;
	}
}

/* The residual scale of sample i, as the fit defines it (fit.h: sqrt of the
 * weight, over |y| floored at 1e-6 of the largest |y| when relative). */
static double scale(const bk_samples *s, size_t i, int relative)
{
	double ymax = 0;
	for (size_t j = 0; j < s->n; j++)
		ymax = fmax(ymax, fabs(s->y[j]));
	double inv = relative ? 1.0 / fmax(fabs(s->y[i]), 1e-6 * ymax) : 1.0;
	return sqrt(s->w[i]) * inv;
}

/* One component, the form p0 LoH + p1 over 2500 samples (blocks of 1024,
 * 1024, 452): r = k ((p0 x + p1) - y), ∂r/∂p0 = k x, ∂r/∂p1 = k, every bit,
 * with and without relative residuals, and the residuals alone (no Jacobian)
 * the same bits. */
Test(resid, linear_form_bit_exact)
{
	enum { N = 2500 };
	bk_samples s;
	samples(&s, N, N, 1);
	bk_form *f = form("p0*LoH + p1");
	const double p[2] = {0.7, -0.3};
	static double r[1024], r2[1024], J[1024 * 2];
	for (int relative = 0; relative <= 1; relative++) {
		bk_fit_spec sp;
		spec_init(&sp, &s, f, NULL, 2, relative);
		bk_fit_ctx c;
		cr_assert_eq(bk_fit_ctx_init(&c, &sp), 0);
		cr_assert_eq(c.nblocks, 3);
		for (int b = 0; b < c.nblocks; b++) {
			cr_assert_eq(bk_fit_residual_block(&c, b, p, r, J), 0);
			cr_assert_eq(bk_fit_residual_block(&c, b, p, r2, NULL), 0);
			for (int i = 0; i < c.size[b]; i++) {
				size_t at = c.lo[b] + (size_t)i;
				double x = s.in[BK_IN_LOH][at], k = scale(&s, at, relative);
				double want = k * ((p[0] * x + p[1]) - s.y[at]);
				cr_assert(r[i] == want && r2[i] == want, "relative %d, sample %zu: r %.17g, %.17g vs %.17g",
				          relative, at, r[i], r2[i], want);
				cr_assert(J[2 * i] == k * x && J[2 * i + 1] == k, "relative %d, sample %zu: J %.17g %.17g vs %.17g %.17g",
				          relative, at, J[2 * i], J[2 * i + 1], k * x, k);
			}
		}
		bk_fit_ctx_free(&c);
	}
	bk_form_free(f);
	bk_samples_free(&s);
}

/* Two components, the second form using fewer parameters than the fit (p0
 * only, np = 2): its blocks' Jacobian has the p1 column exactly 0 (the path
 * with a narrower Jacobian apart), the first component's both columns. */
Test(resid, narrower_form_zero_columns)
{
	enum { N = 3000, N0 = 1100 };
	bk_samples s;
	samples(&s, N, N0, 2);
	bk_form *f0 = form("p0*LoH + p1"), *f1 = form("p0*LoH");
	const double p[2] = {1.25, 0.125};
	static double r[1024], J[1024 * 2];
	bk_fit_spec sp;
	spec_init(&sp, &s, f0, f1, 2, 0);
	bk_fit_ctx c;
	cr_assert_eq(bk_fit_ctx_init(&c, &sp), 0);
	int seen1 = 0;
	for (int b = 0; b < c.nblocks; b++) {
		cr_assert_eq(bk_fit_residual_block(&c, b, p, r, J), 0);
		int q = c.comp[b];
		seen1 |= q == 1;
		for (int i = 0; i < c.size[b]; i++) {
			size_t at = c.lo[b] + (size_t)i;
			double x = s.in[BK_IN_LOH][at], k = scale(&s, at, 0);
			double v = q == 0 ? p[0] * x + p[1] : p[0] * x;
			cr_assert(r[i] == k * (v - s.y[at]), "block %d, sample %zu: r %.17g vs %.17g", b, at, r[i],
			          k * (v - s.y[at]));
			cr_assert(J[2 * i] == k * x, "block %d, sample %zu: J0 %.17g vs %.17g", b, at, J[2 * i], k * x);
			cr_assert(J[2 * i + 1] == (q == 0 ? k : 0.0) && !signbit(J[2 * i + 1]),
			          "block %d, sample %zu: J1 %.17g", b, at, J[2 * i + 1]);
		}
	}
	cr_assert(seen1, "no block of the second component");
	bk_fit_ctx_free(&c);
	bk_form_free(f0);
	bk_form_free(f1);
	bk_samples_free(&s);
}

/* The backward sweep where both operands of a product are the same register
 * (p0*p0): both updates land on one adjoint, in order, so ∂/∂p0 of p0 p0 LoH
 * is (x p0) + (x p0) = 2 x p0 exactly; and a division's two operand updates,
 * ∂/∂p0 of LoH / (p0 + LoH) = -(1 r / B) with r the quotient, B = p0 + x,
 * and ∂/∂p1 of p1 / LoH = 1 / x. 300 samples: two full IR blocks and a part. */
Test(resid, backward_same_register_and_division)
{
	enum { N = 300 };
	double *in[BK_IN_COUNT] = {0}, x[N], v[N], J[N * 2];
	for (int i = 0; i < N; i++)
		x[i] = (i + 1.0) / N;
	in[BK_IN_LOH] = x;
	const double p[2] = {0.75, 3.0};
	bk_form *sq = form("p0*p0*LoH");
	cr_assert_eq(bk_form_eval_diff(sq, N, (const double *const *)in, p, v, J), 0);
	for (int i = 0; i < N; i++)
		cr_assert(J[i] == 2 * (x[i] * p[0]), "p0*p0*LoH at %d: %.17g vs %.17g", i, J[i], 2 * (x[i] * p[0]));
	bk_form_free(sq);
	bk_form *q = form("LoH/(p0 + LoH) + p1/LoH");
	cr_assert_eq(bk_form_eval_diff(q, N, (const double *const *)in, p, v, J), 0);
	for (int i = 0; i < N; i++) {
		double B = p[0] + x[i], quot = x[i] / B;
		double d0 = 0.0 - 1.0 * quot / B, d1 = 0.0 + 1.0 / x[i];
		cr_assert(J[2 * i] == d0 && J[2 * i + 1] == d1, "at %d: %.17g %.17g vs %.17g %.17g", i, J[2 * i],
		          J[2 * i + 1], d0, d1);
	}
	bk_form_free(q);
}
