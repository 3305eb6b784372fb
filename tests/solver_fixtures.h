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

#endif
