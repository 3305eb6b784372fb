/*
 * solver_fixtures.h — least-squares problems with known answers and the
 * silent-solve check, shared by test_solver.c (bk_solve, Ceres) and
 * test_tiny.c (bk_solve_tiny, TinySolver). Test code only: static functions,
 * included once per test file.
 */
#ifndef TESTS_SOLVER_FIXTURES_H
#define TESTS_SOLVER_FIXTURES_H

#include "solver.h"

#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <unistd.h>

/* Rosenbrock as least squares: r = (1 - x, 10 (y - x^2)); 1/2 |r|^2 is half
 * Rosenbrock's function, whose only minimum is (1, 1) with cost 0. */
static int rosenbrock(void *ctx, int block, const double *p, double *r, double *jac)
{
	(void)ctx, (void)block;
	r[0] = 1 - p[0];
	r[1] = 10 * (p[1] - p[0] * p[0]);
	if (jac != NULL) {
		jac[0] = -1, jac[1] = 0;
		jac[2] = -20 * p[0], jac[3] = 10;
	}
	return 0;
}

/* Rosenbrock that fails from its fail_at-th call on. */
typedef struct failing {
	int calls, fail_at, what; /* what: 0 return 7, 1 NaN residual, 2 NaN jacobian */
} failing;

static int failing_rosenbrock(void *ctx, int block, const double *p, double *r, double *jac)
{
	failing *f = ctx;
	rosenbrock(NULL, block, p, r, jac);
	if (f->calls++ < f->fail_at)
		return 0;
	if (f->what == 0)
		return 7;
	if (f->what == 1)
		r[1] = NAN;
	else if (jac != NULL)
		jac[3] = NAN;
	else
		r[0] = NAN; /* a cost-only call: make the residual bad instead */
	return 0;
}

/* A pole beside the answer: r_i = p0 (p1 + x_i^2)^(-1/2) - y_i with
 * y_i = (x_i^2 - 0.09)^(-1/2) at 32 points x_i in [0.3162, 1] (up to 10 at the
 * left end): the answer is (1, -0.09), and a step from (1, 1) lands where
 * p1 + x^2 < 0 for some x (NaN residuals there). Counts its calls that gave
 * a NaN residual (the trials to be rejected). */
typedef struct pole {
	int nan_calls;
} pole;

static double pole_x(int i) { return 0.3162 + (1 - 0.3162) * i / 31.0; }

static int pole_fn(void *ctx, int block, const double *p, double *r, double *jac)
{
	pole *q = ctx;
	int bad = 0;
	(void)block;
	for (int i = 0; i < 32; i++) {
		double x = pole_x(i), u = p[1] + x * x, s = 1 / sqrt(u); /* NaN where u < 0 */
		r[i] = p[0] * s - 1 / sqrt(x * x - 0.09);
		bad |= isnan(r[i]);
		if (jac != NULL)
			jac[2 * i] = s, jac[2 * i + 1] = -0.5 * p[0] * s / u;
	}
	q->nan_calls += bad;
	return 0;
}

/* A wall before the answer: r = p0 - 2 where p0 <= 1, NaN beyond (as
 * p0 - 2 + 0 sqrt(1 - p0)): the least squares would go to 2 and can only
 * reach the wall at 1. ctx: the wall's place instead of 1 (NULL: 1). */
static int wall_fn(void *ctx, int block, const double *p, double *r, double *jac)
{
	double edge = ctx != NULL ? *(const double *)ctx : 1;
	(void)block;
	r[0] = p[0] <= edge ? p[0] - 2 : NAN;
	if (jac != NULL)
		jac[0] = p[0] <= edge ? 1 : NAN;
	return 0;
}

/* Runs solve (bk_solve or bk_solve_tiny) with stdout and stderr redirected to
 * temporary files and asserts both stayed empty: the bridge never prints
 * (glog included). */
typedef int (*solve_fn)(const bk_problem *, const bk_fit_options *, double *, bk_fit_summary *);
static int solve_silently_with(solve_fn solve, const bk_problem *p, const bk_fit_options *o, double *q,
                               bk_fit_summary *s)
{
	FILE *out = tmpfile(), *err = tmpfile();
	cr_assert(out != NULL && err != NULL);
	fflush(stdout), fflush(stderr);
	int saved_out = dup(1), saved_err = dup(2);
	cr_assert(saved_out >= 0 && saved_err >= 0);
	dup2(fileno(out), 1), dup2(fileno(err), 2);
	int rc = solve(p, o, q, s);
	fflush(stdout), fflush(stderr);
	dup2(saved_out, 1), dup2(saved_err, 2);
	close(saved_out), close(saved_err);
	long nout = (fseek(out, 0, SEEK_END), ftell(out));
	long nerr = (fseek(err, 0, SEEK_END), ftell(err));
	fclose(out), fclose(err);
	cr_assert_eq(nout, 0, "%ld bytes written to stdout", nout);
	cr_assert_eq(nerr, 0, "%ld bytes written to stderr", nerr);
	return rc;
}

/* The pole and the wall through solve (silently): a trial step into NaN is
 * rejected and the fit goes on to (1, -0.09) (the premise: a trial did give
 * NaN); at the wall the solve stops at p0 <= 1, within 1e-6 of it, and says
 * it stopped at the edge (NO_CONVERGENCE, not CONVERGENCE at a point that is
 * no minimum, nor FAILURE). */
static inline void check_pole_and_wall(solve_fn solve, const char *who)
{
	int size32[] = {32}, size1[] = {1};
	pole q = {0};
	bk_problem p = {2, 1, size32, pole_fn, &q, NULL, NULL, NULL};
	bk_fit_options o = BK_FIT_OPTIONS_INIT;
	o.function_tolerance = 1e-12;
	double x[2] = {1, 1};
	bk_fit_summary s;
	cr_assert_eq(solve_silently_with(solve, &p, &o, x, &s), 0, "%s: %s", who, s.message);
	cr_assert_gt(q.nan_calls, 0, "%s: the premise: a trial step gave NaN", who);
	cr_assert_eq(s.termination, BK_TERM_CONVERGENCE, "%s: %s", who, s.message);
	cr_assert(fabs(x[0] - 1) < 1e-9 && fabs(x[1] + 0.09) < 1e-9, "%s: %.17g %.17g", who, x[0], x[1]);
	bk_problem w = {1, 1, size1, wall_fn, NULL, NULL, NULL, NULL};
	double y[1] = {0};
	o = (bk_fit_options)BK_FIT_OPTIONS_INIT;
	cr_assert_eq(solve_silently_with(solve, &w, &o, y, &s), 0, "%s: %s", who, s.message);
	cr_assert_eq(s.termination, BK_TERM_NO_CONVERGENCE, "%s: %s", who, s.message);
	cr_assert_str_eq(s.message,
	                 "stopped at the edge of where the form is finite: the last trial steps gave non-finite "
	                 "residuals and were rejected",
	                 "%s", who);
	cr_assert(y[0] <= 1 && y[0] > 1 - 1e-6, "%s: %.17g", who, y[0]);
	/* The controls: each check above can fail. From near the answer no
	 * trial reaches the pole (the premise's count stays 0), and the fit
	 * still lands on it; with the wall beyond the answer (at 3) the solve
	 * converges at 2, no edge named, not at the wall. */
	pole near = {0};
	p.ctx = &near;
	double xn[2] = {0.99, -0.085};
	o = (bk_fit_options)BK_FIT_OPTIONS_INIT;
	o.function_tolerance = 1e-12;
	cr_assert_eq(solve_silently_with(solve, &p, &o, xn, &s), 0, "%s: %s", who, s.message);
	cr_assert_eq(near.nan_calls, 0, "%s: control: %d NaN trials from near the answer", who, near.nan_calls);
	cr_assert(fabs(xn[0] - 1) < 1e-9 && fabs(xn[1] + 0.09) < 1e-9, "%s: %.17g %.17g", who, xn[0], xn[1]);
	double far = 3, z[1] = {0};
	w.ctx = &far;
	o = (bk_fit_options)BK_FIT_OPTIONS_INIT;
	cr_assert_eq(solve_silently_with(solve, &w, &o, z, &s), 0, "%s: %s", who, s.message);
	cr_assert_eq(s.termination, BK_TERM_CONVERGENCE, "%s: control: %s", who, s.message);
	cr_assert(strstr(s.message, "edge") == NULL, "%s: control: %s", who, s.message);
	cr_assert(fabs(z[0] - 2) < 1e-9, "%s: control: %.17g", who, z[0]);
}

#endif
