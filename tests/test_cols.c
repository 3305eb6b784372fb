/*
 * test_cols.c — the Jacobian by columns (issue 22, throughput): the bound
 * form's column output (brdf.h, bk_form_bound_eval_cols) against closed-form
 * derivatives and against its row-major output; TinySolver fed by columns
 * (fit/solver.h, bk_solve_tiny_cols) against a planted answer and against the
 * row-major path, bit for bit, held parameters and failures included; the
 * fixed-size TinySolver (bk_tiny_fixed) against planted answers; and a fit's
 * residual blocks by columns (fit_ctx.c) against the row-major ones
 * (bk_fit_ctx_cols), a non-finite Jacobian failing with the same message.
 */
#include "brdf.h"
#include "brdf_ops.h" /* bk_ir_force_generic */
#include "fit.h"
#include "solver.h"
#include "switches.h" /* bk_tiny_fixed, bk_fit_ctx_cols, bk_fit_ctx_bind */
#include "solver_fixtures.h"

#include <criterion/criterion.h>

#include <math.h>
#include <stdint.h>
#include <string.h>

static bk_form *form(const char *text)
{
	bk_form_error e;
	bk_form *f = bk_form_parse(text, &e);
	cr_assert_not_null(f, "%s: %s", text, e.message);
	return f;
}

static int same_bits(double a, double b)
{
	return memcmp(&a, &b, sizeof a) == 0;
}

/* ---- bk_form_bound_eval_cols ------------------------------------------------- */

enum { NS = 300 }; /* two full blocks of the IR's 128 and a partial one */

static double g_loh[NS], g_r[NS];
static const double *g_in[BK_IN_COUNT];

static void inputs(void)
{
	for (int k = 0; k < NS; k++) {
		g_loh[k] = 0.3 + 0.7 * k / (NS - 1);
		g_r[k] = (double)((k * 37) % NS) / NS; /* not monotone */
	}
	for (int i = 0; i < BK_IN_COUNT; i++)
		g_in[i] = NULL;
	g_in[BK_IN_LOH] = g_loh;
	g_in[BK_IN_R] = g_r;
}

/* 1. p0*r + p1: the columns are r and 1 exactly (closed form), over every
 * block, the partial one included; the values p0 r + p1. */
Test(cols, linear_form_closed_form)
{
	inputs();
	bk_form *f = form("p0*r + p1");
	bk_form_bound *b = bk_form_bind(f, NS, g_in);
	cr_assert_not_null(b);
	double p[2] = {1.5, -0.25}, out[NS], c0[NS], c1[NS];
	double *cols[2] = {c0, c1};
	for (int call = 0; call < 2; call++) { /* the first call fills what is kept */
		cr_assert_eq(bk_form_bound_eval_cols(b, p, out, cols), 0);
		for (int k = 0; k < NS; k++) {
			cr_assert(same_bits(c0[k], g_r[k]), "d/dp0 at %d: %a, want r = %a", k, c0[k], g_r[k]);
			cr_assert(same_bits(c1[k], 1.0), "d/dp1 at %d: %a, want 1", k, c1[k]);
			cr_assert(same_bits(out[k], 1.5 * g_r[k] + -0.25), "value at %d", k);
		}
	}
	bk_form_bound_free(b);
	bk_form_free(f);
}

/* 2. Against the row-major output, bit for bit, for forms with a parameter
 * read twice, kinks, a one-parameter form (the row-major stride is 1 there
 * too), a parameter no path reaches (p1 of p0 + p2: its column must come out
 * zero, over a column filled with garbage), and a NULL column (left as it
 * was). The negative control: the garbage is there before the call, so a
 * column left unwritten would be seen. */
Test(cols, same_bits_as_rows)
{
	inputs();
	static const char *forms[] = {
	    "p0*p0*r + p1/(LoH + p0)",
	    "max(p0*r, p1) + clamp(LoH, p2, 0.9)",
	    "pow(LoH, p0)",
	    "p0 + p2*LoH",
	};
	for (size_t t = 0; t < sizeof forms / sizeof forms[0]; t++) {
		bk_form *f = form(forms[t]);
		int np = bk_form_nparams(f);
		bk_form_bound *b = bk_form_bind(f, NS, g_in);
		cr_assert_not_null(b);
		static double jr[NS * 4], col[4][NS], ov[NS], oc[NS];
		double p[4] = {0.7, 0.2, 0.4, 1.3};
		for (int call = 0; call < 3; call++) {
			p[0] += 0.1 * call;
			cr_assert_eq(bk_form_bound_eval(b, p, ov, jr), 0);
			double *cp[4];
			for (int j = 0; j < np; j++) {
				for (int k = 0; k < NS; k++)
					col[j][k] = 12345.0; /* garbage */
				cp[j] = col[j];
			}
			int skip = call == 2 ? np - 1 : -1; /* the last column not asked for */
			if (skip >= 0)
				cp[skip] = NULL;
			cr_assert_eq(bk_form_bound_eval_cols(b, p, oc, cp), 0);
			for (int k = 0; k < NS; k++) {
				cr_assert(same_bits(ov[k], oc[k]), "%s: value %d", forms[t], k);
				for (int j = 0; j < np; j++)
					if (j == skip)
						cr_assert_eq(col[j][k], 12345.0, "%s: column %d not asked for, written", forms[t], j);
					else
						cr_assert(same_bits(jr[k * np + j], col[j][k]), "%s call %d: d/dp%d at %d: %a vs %a",
						          forms[t], call, j, k, jr[k * np + j], col[j][k]);
			}
		}
		if (strcmp(forms[t], "p0 + p2*LoH") == 0) { /* the unreached p1 */
			cr_assert_eq(np, 3);
			for (int k = 0; k < NS; k++)
				cr_assert(same_bits(col[1][k], 0.0), "d/dp1 at %d: %a", k, col[1][k]);
		}
		/* values only */
		cr_assert_eq(bk_form_bound_eval_cols(b, p, oc, NULL), 0);
		for (int k = 0; k < NS; k++)
			cr_assert(same_bits(ov[k], oc[k]));
		bk_form_bound_free(b);
		bk_form_free(f);
	}
}

/* ---- bk_solve_tiny_cols --------------------------------------------------------- */

/* y = 2 exp2(-3 x), 1,024 points in uneven blocks (as test_tiny.c's, whose
 * 1,000 take TinySolver's dynamic row count: 1,024 take the fixed one,
 * fit/tiny.cc's kFixedResiduals) */
enum { EN = 1024, EB = 4 };
static double g_x[EN], g_y[EN];
static const int g_first[EB + 1] = {0, 100, 101, 724, 1024};
static int g_size[EB] = {100, 1, 623, 300};

static void exp_data(void)
{
	for (int k = 0; k < EN; k++) {
		g_x[k] = (double)k / (EN - 1);
		g_y[k] = 2.0 * exp2(-3.0 * g_x[k]) + (k % 2 ? -1e-3 : 1e-3);
	}
}

/* r = a exp2(b x) - y (+ c x² with a third parameter, held at 0 below) */
static void exp_at(int block, const double *p, int np, double *r, double **col, double *rows)
{
	for (int k = g_first[block]; k < g_first[block + 1]; k++) {
		int i = k - g_first[block];
		double v = exp2(p[1] * g_x[k]);
		r[i] = p[0] * v - g_y[k] + (np > 2 ? p[2] * g_x[k] * g_x[k] : 0.0);
		double d[3] = {v, p[0] * g_x[k] * log(2.0) * v, g_x[k] * g_x[k]};
		for (int j = 0; j < np; j++) {
			if (rows)
				rows[i * np + j] = d[j];
			if (col && col[j])
				col[j][i] = d[j];
		}
	}
}

static int g_np;
static int exp_rows(void *ctx, int block, const double *p, double *r, double *jac)
{
	(void)ctx;
	exp_at(block, p, g_np, r, NULL, jac);
	return 0;
}

static int exp_cols(void *ctx, int block, const double *p, double *r, double *const *cols)
{
	(void)ctx;
	exp_at(block, p, g_np, r, (double **)cols, NULL);
	return 0;
}

/* 3. The same solve either way: the same bits of the parameters, costs and
 * iterations; and the answer planted (a = 2, b = -3, to 1e-4: the data's
 * ±1e-3 alternation moves it by ~1e-5), with a third parameter held at 0 too
 * (its column goes to scratch: the free ones must still land in place). */
Test(cols, tiny_same_bits_as_rows)
{
	exp_data();
	for (int np = 2; np <= 3; np++) {
		g_np = np;
		int held[3] = {0, 0, 1};
		bk_problem p = {np, EB, g_size, exp_rows, NULL, NULL, NULL, np == 3 ? held : NULL};
		bk_fit_options o = BK_FIT_OPTIONS_INIT;
		double a[3] = {1, 1, 0}, c[3] = {1, 1, 0};
		bk_fit_summary sa, sc;
		cr_assert_eq(bk_solve_tiny_reusing(&p, &o, a, &sa), 0, "%s", sa.message);
		cr_assert_eq(bk_solve_tiny_cols(&p, exp_cols, &o, c, &sc), 0, "%s", sc.message);
		cr_assert_eq(sc.termination, BK_TERM_CONVERGENCE, "%s", sc.message);
		cr_assert_str_eq(sa.message, sc.message);
		cr_assert_eq(sa.iterations, sc.iterations);
		cr_assert(same_bits(sa.final_cost, sc.final_cost) && same_bits(sa.initial_cost, sc.initial_cost));
		for (int j = 0; j < np; j++)
			cr_assert(same_bits(a[j], c[j]), "np %d: p%d %a vs %a", np, j, a[j], c[j]);
		cr_assert(fabs(c[0] - 2) < 1e-4 && fabs(c[1] + 3) < 1e-4, "a %.17g b %.17g", c[0], c[1]);
		if (np == 3)
			cr_assert_eq(c[2], 0.0, "held");
	}
}

/* Rosenbrock by columns that fails from its fail_at-th call on, as
 * solver_fixtures.h's failing_rosenbrock does by rows. */
static int failing_cols(void *ctx, int block, const double *p, double *r, double *const *cols)
{
	failing *f = ctx;
	double jac[4];
	rosenbrock(NULL, block, p, r, jac);
	int rc = 0;
	if (f->calls++ >= f->fail_at) {
		if (f->what == 0)
			return 7;
		if (f->what == 1)
			r[1] = NAN, rc = BK_COLS_RES_NONFINITE;
		else if (cols != NULL)
			jac[3] = NAN, rc = BK_COLS_JAC_NONFINITE;
		else
			r[0] = NAN, rc = BK_COLS_RES_NONFINITE;
	}
	for (int j = 0; cols && j < 2; j++)
		if (cols[j])
			cols[j][0] = jac[j], cols[j][1] = jac[2 + j];
	return rc;
}

/* bk_solve_tiny_cols with failing_cols, as a solve_fn (solver_fixtures.h) */
static int solve_failing_cols(const bk_problem *p, const bk_fit_options *o, double *q, bk_fit_summary *s)
{
	return bk_solve_tiny_cols(p, failing_cols, o, q, s);
}

/* 4. Failures: a non-zero return, a NaN residual, a NaN Jacobian entry, at the
 * first call and at the sixth: FAILURE (NO_CONVERGENCE at the edge where NaN
 * residuals begin at a trial point, the sixth call) with the same message, the same calls
 * and the same point returned as the row-major path with the trial's Jacobian
 * kept (bk_solve_tiny_reusing), nothing printed; at the first call the
 * messages are bk_solve's, written out here. */
Test(cols, tiny_failures_as_rows)
{
	static const char *first[] = {
	    "callback failed: block 0 returned 7",
	    "non-finite residual: block 0, residual 1",
	    "non-finite jacobian: block 0, residual 1, parameter 1",
	};
	int size[] = {2};
	for (int what = 0; what < 3; what++)
		for (int at = 0; at <= 5; at += 5) {
			failing fr = {0, at, what}, fc = {0, at, what};
			bk_problem pr = {2, 1, size, failing_rosenbrock, &fr, NULL, NULL, NULL};
			bk_problem pc = {2, 1, size, failing_rosenbrock, &fc, NULL, NULL, NULL};
			bk_fit_options o = BK_FIT_OPTIONS_INIT;
			double qr[2] = {-1.2, 1}, qc[2] = {-1.2, 1};
			bk_fit_summary sr, sc;
			cr_assert_eq(solve_silently_with(bk_solve_tiny_reusing, &pr, &o, qr, &sr), 0);
			cr_assert_eq(solve_silently_with(solve_failing_cols, &pc, &o, qc, &sc), 0);
			/* a NaN residual from a trial point on: every trial rejected
			 * (fit/tiny.cc), the solve stops at the edge; else FAILURE */
			int edge = what == 1 && at > 0;
			cr_assert_eq(sc.termination, edge ? BK_TERM_NO_CONVERGENCE : BK_TERM_FAILURE, "what %d at %d: %s",
			             what, at, sc.message);
			cr_assert_eq(sr.termination, sc.termination, "what %d at %d: %s", what, at, sr.message);
			cr_assert_str_eq(sc.message, sr.message, "what %d at %d", what, at);
			if (edge)
				cr_assert(strncmp(sc.message, "stopped at the edge of where the form is finite", 47) == 0, "%s",
				          sc.message);
			if (at == 0)
				cr_assert_str_eq(sc.message, first[what]);
			cr_assert_eq(fc.calls, fr.calls, "what %d at %d", what, at);
			cr_assert(same_bits(qr[0], qc[0]) && same_bits(qr[1], qc[1]), "what %d at %d", what, at);
		}
	double q[2] = {0, 0};
	bk_fit_summary s;
	bk_problem ok = {2, 1, size, rosenbrock, NULL, NULL, NULL, NULL};
	bk_fit_options o = BK_FIT_OPTIONS_INIT;
	cr_assert_eq(bk_solve_tiny_cols(&ok, NULL, &o, q, &s), -1);
	cr_assert_str_eq(s.message, "cols: no callback");
}

/* 5. TinySolver with the free parameters' and residuals' counts fixed (1..4,
 * 1,024) and dynamic (bk_tiny_fixed 0): both at the planted answer of the exponential (1e-4)
 * and of a held-parameter solve; the negative control: one iteration does
 * not get there, so the 1e-4 test can fail. */
Test(cols, fixed_and_dynamic_sizes_reach_the_answer)
{
	exp_data();
	g_np = 3;
	int held[3] = {0, 0, 1};
	for (int fixed = 0; fixed <= 1; fixed++) {
		bk_tiny_fixed = fixed;
		for (int nh = 0; nh <= 1; nh++) {
			int h3[3] = {0, 0, 0};
			bk_problem p = {3, EB, g_size, exp_rows, NULL, NULL, NULL, nh ? held : h3};
			bk_fit_options o = BK_FIT_OPTIONS_INIT;
			double c[3] = {1, 1, 0};
			bk_fit_summary s;
			cr_assert_eq(bk_solve_tiny_cols(&p, exp_cols, &o, c, &s), 0, "%s", s.message);
			cr_assert_eq(s.termination, BK_TERM_CONVERGENCE, "fixed %d held %d: %s", fixed, nh, s.message);
			/* free c: the data's alternation is not quadratic, c stays near 0 */
			cr_assert(fabs(c[0] - 2) < 1e-4 && fabs(c[1] + 3) < 1e-4 && fabs(c[2]) < 1e-4,
			          "fixed %d held %d: %.17g %.17g %.17g", fixed, nh, c[0], c[1], c[2]);
			o.max_iterations = 1;
			double d[3] = {1, 1, 0};
			cr_assert_eq(bk_solve_tiny_cols(&p, exp_cols, &o, d, &s), 0, "%s", s.message);
			cr_assert(!(fabs(d[0] - 2) < 1e-4 && fabs(d[1] + 3) < 1e-4), "one iteration got there");
		}
	}
	bk_tiny_fixed = 1;
}

/* ---- a fit's residual blocks by columns (fit_ctx.c) --------------------------------- */

/* 6. A fit by columns and by rows (bk_fit_ctx_cols 1 and 0), by columns
 * through the plain evaluators (bk_fit_ctx_bind 0), and by columns on the
 * x86-64 baseline's code where the CPU has AVX2 (fit_ctx.c's scaling loops
 * and the IR's kernels, bk_ir_force_generic): the same bits;
 * y = 0.5 + 2 LoH r² planted, recovered. Then sqrt(p0 r) from p0 = 0: values
 * finite (0), d/dp0 = r / (2 sqrt(0)) = inf wherever r > 0: FAILURE with the
 * row path's message, naming the first entry that is not finite (row 0,
 * where r = 0: 0 · inf). */
Test(cols, fit_same_bits_as_rows)
{
	inputs();
	bk_samples sm;
	memset(&sm, 0, sizeof sm);
	double y[NS], w[NS];
	for (int k = 0; k < NS; k++)
		y[k] = 0.5 + 2 * g_loh[k] * g_r[k] * g_r[k], w[k] = 0.5 + g_r[k]; /* k = sqrt(w) not 1: the scaling rounds */
	sm.n = NS;
	sm.ncomp = 1;
	sm.start[0] = 0, sm.start[1] = NS;
	for (int i = 0; i < BK_IN_COUNT; i++)
		sm.in[i] = (double *)g_in[i];
	sm.y = y;
	sm.w = w;
	static const char *texts[] = {"p0 + p1*LoH*r*r", "sqrt(p0*r)"};
	for (int t = 0; t < 2; t++) {
		bk_form *f = form(texts[t]);
		bk_fit_spec spec;
		memset(&spec, 0, sizeof spec);
		spec.s = &sm;
		spec.form[0] = spec.form[1] = f;
		spec.np = bk_form_nparams(f);
		bk_fit_options o = BK_FIT_OPTIONS_INIT;
		spec.opt = o;
		spec.starts = 1;
		for (int j = 0; j < BK_MAX_PARAMS; j++)
			spec.lower[j] = -HUGE_VAL, spec.upper[j] = HUGE_VAL;
		double q[4][BK_MAX_PARAMS];
		bk_fit_summary s[4];
		for (int side = 0; side < 4; side++) {
			bk_fit_ctx_cols = side > 0; /* 2: by columns without a bound form */
			bk_fit_ctx_bind = side != 2;
			bk_ir_force_generic(side == 3); /* 3: the x86-64 baseline's loops and kernels, not AVX2's */
			bk_fit_problem *pb = bk_fit_problem_new(&spec);
			cr_assert_not_null(pb);
			for (int j = 0; j < BK_MAX_PARAMS; j++)
				q[side][j] = t == 0 ? 1.0 : 0.0;
			cr_assert_eq(bk_fit_problem_solve(pb, q[side], NULL, &s[side]), 0);
			bk_fit_problem_free(pb);
		}
		bk_fit_ctx_cols = 1;
		bk_fit_ctx_bind = 1;
		bk_ir_force_generic(0);
		for (int side = 1; side < 4; side++) {
			cr_assert_str_eq(s[0].message, s[side].message, "%s", texts[t]);
			cr_assert_eq(s[0].termination, s[side].termination);
			cr_assert(same_bits(s[0].final_cost, s[side].final_cost), "%s side %d: cost %a vs %a", texts[t], side,
			          s[0].final_cost, s[side].final_cost);
			for (int j = 0; j < spec.np; j++)
				cr_assert(same_bits(q[0][j], q[side][j]), "%s side %d: p%d %a vs %a", texts[t], side, j, q[0][j],
				          q[side][j]);
		}
		if (t == 0) {
			cr_assert_eq(s[1].termination, BK_TERM_CONVERGENCE, "%s", s[1].message);
			cr_assert(fabs(q[1][0] - 0.5) < 1e-9 && fabs(q[1][1] - 2) < 1e-9, "%.17g %.17g", q[1][0], q[1][1]);
		} else {
			cr_assert_eq(g_r[0], 0.0); /* so d/dp0 there is r · inf = NaN */
			cr_assert_eq(s[1].termination, BK_TERM_FAILURE, "%s", s[1].message);
			cr_assert_str_eq(s[1].message, "non-finite jacobian: block 0, residual 0, parameter 0");
		}
		bk_form_free(f);
	}
}
