/*
 * test_tiny.c — the TinySolver fast path (fit/tiny.cc, bk_solve_tiny) on
 * problems whose answers come from elsewhere: Rosenbrock's minimum (1, 1), an
 * exponential fitted to exact data, linear least squares against the normal
 * equations solved here, a constant fitted to values (the mean), and bk_solve
 * (the Ceres path) on the same problem. Also: constant flags, refusals and
 * misuse (exact messages, params untouched), callback failure (FAILURE, the
 * messages of bk_solve, nothing printed), the iteration limit, the stop on
 * gradient_tolerance meaning Ceres' unscaled test, and two threads at once
 * giving the bits of one at a time.
 */
#include "solver.h"
#include "solver_fixtures.h"

#include <criterion/criterion.h>

#include <float.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

/* ---- helpers ------------------------------------------------------------------- */

static void check_abs(double got, double want, double tol, const char *what)
{
	cr_assert(fabs(got - want) <= tol, "%s: got %.17g, want %.17g (abs err %.3g > %.3g)", what, got, want,
	          fabs(got - want), tol);
}

static void check_rel(double got, double want, double rel, const char *what)
{
	cr_assert(fabs(got - want) <= rel * fabs(want), "%s: got %.17g, want %.17g (rel err %.3g > %.3g)", what, got,
	          want, fabs(got - want) / fabs(want), rel);
}

/* g = sum over blocks of J^T r: the gradient of 1/2 sum r^2, from the
 * problem's own callback (Ceres' unscaled gradient). */
static void gradient(const bk_problem *p, const double *x, double *g)
{
	static double r[1024], jac[1024 * 16];
	for (int j = 0; j < p->np; j++)
		g[j] = 0;
	for (int b = 0; b < p->nblocks; b++) {
		cr_assert(p->block_size[b] <= 1024);
		cr_assert_eq(p->fn(p->ctx, b, x, r, jac), 0);
		for (int i = 0; i < p->block_size[b]; i++)
			for (int j = 0; j < p->np; j++)
				g[j] += jac[i * p->np + j] * r[i];
	}
}

/* Tolerances below the rounding of a double: the stop is left to the gradient
 * test or to a step that changes nothing (as test_solver.c's tight()). */
static bk_fit_options tight(void)
{
	bk_fit_options o = BK_FIT_OPTIONS_INIT;
	o.function_tolerance = 1e-16;
	o.parameter_tolerance = 1e-16;
	return o;
}

/* ---- Rosenbrock ------------------------------------------------------------------ */


/* 1. From the classic start (-1.2, 1) and three others: (1, 1) to 1e-9 (zero
 * residual: LM converges quadratically there, so the stop is far closer). */
Test(tiny, rosenbrock_minimum)
{
	static const double starts[][2] = {{-1.2, 1}, {-3, -3}, {2, 5}, {0, 0}};
	int size[] = {2};
	bk_problem p = {2, 1, size, rosenbrock, NULL, NULL, NULL, NULL};
	for (int k = 0; k < 4; k++) {
		bk_fit_options o = BK_FIT_OPTIONS_INIT;
		double q[2] = {starts[k][0], starts[k][1]};
		bk_fit_summary s;
		cr_assert_eq(bk_solve_tiny(&p, &o, q, &s), 0, "%s", s.message);
		cr_assert_eq(s.termination, BK_TERM_CONVERGENCE, "start %d: %s", k, s.message);
		check_abs(q[0], 1, 1e-9, "x");
		check_abs(q[1], 1, 1e-9, "y");
		cr_assert(s.final_cost < 1e-20, "final cost %g", s.final_cost);
		cr_assert(s.iterations > 0 && s.iterations <= o.max_iterations);
		cr_assert_eq(s.bound_resolves, 0);
	}
}

/* ---- y = a exp2(b x) over 1000 exact points, uneven blocks ---------------------------- */

enum { EXP_N = 1000, EXP_BLOCKS = 5 };

typedef struct expfit {
	double x[EXP_N], y[EXP_N];
	int first[EXP_BLOCKS + 1]; /* first point of each block */
	int size[EXP_BLOCKS];
} expfit;

static int exp_residuals(void *ctx, int block, const double *p, double *r, double *jac)
{
	const expfit *e = ctx;
	for (int k = e->first[block]; k < e->first[block + 1]; k++) {
		int i = k - e->first[block];
		double v = exp2(p[1] * e->x[k]);
		r[i] = p[0] * v - e->y[k];
		if (jac != NULL) {
			jac[2 * i] = v;
			jac[2 * i + 1] = p[0] * e->x[k] * log(2.0) * v;
		}
	}
	return 0;
}

/* y = 2 exp2(-3 x) on x in [0, 1] plus noise * (-1)^k (0: exact data), in
 * blocks of 100, 1, 250, 600, 49 (uneven: the assembly of the column-major
 * Jacobian is tested with offsets that are not multiples of anything). */
static bk_problem exp_problem(expfit *e, double noise)
{
	static const int sizes[EXP_BLOCKS] = {100, 1, 250, 600, 49};
	for (int k = 0; k < EXP_N; k++) {
		e->x[k] = (double)k / (EXP_N - 1);
		e->y[k] = 2.0 * exp2(-3.0 * e->x[k]) + (k % 2 ? -noise : noise);
	}
	e->first[0] = 0;
	for (int b = 0; b < EXP_BLOCKS; b++) {
		e->size[b] = sizes[b];
		e->first[b + 1] = e->first[b] + sizes[b];
	}
	cr_assert_eq(e->first[EXP_BLOCKS], EXP_N);
	bk_problem p = {2, EXP_BLOCKS, e->size, exp_residuals, e, NULL, NULL, NULL};
	return p;
}

static expfit g_exp, g_exp2; /* kept off the stack */

/* 2. Exact data from a poor start (half the amplitude, growth for decay):
 * a = 2, b = -3 to 1e-9; the cost of rounding errors only. */
Test(tiny, exponential_exact_data)
{
	bk_problem p = exp_problem(&g_exp, 0);
	bk_fit_options o = BK_FIT_OPTIONS_INIT;
	double ab[2] = {1, 1};
	bk_fit_summary s;
	cr_assert_eq(bk_solve_tiny(&p, &o, ab, &s), 0, "%s", s.message);
	cr_assert_eq(s.termination, BK_TERM_CONVERGENCE, "%s", s.message);
	check_abs(ab[0], 2, 1e-9, "a");
	check_abs(ab[1], -3, 1e-9, "b");
	cr_assert(s.final_cost < 1e-20, "final cost %g", s.final_cost);
	/* the initial cost is that of the start, summed here */
	double c0 = 0;
	for (int k = 0; k < EXP_N; k++) {
		double r = exp2(g_exp.x[k]) - g_exp.y[k];
		c0 += 0.5 * r * r;
	}
	check_rel(s.initial_cost, c0, 1e-12, "initial cost");
}

/* ---- linear least squares against the normal equations ------------------------------ */

enum { POLY_N = 21 };

typedef struct poly {
	double x[POLY_N], y[POLY_N];
} poly;

/* r_i = p0 + p1 x_i + p2 x_i^2 - y_i, one block */
static int poly_residuals(void *ctx, int block, const double *p, double *r, double *jac)
{
	const poly *q = ctx;
	(void)block;
	for (int i = 0; i < POLY_N; i++) {
		double x = q->x[i];
		r[i] = p[0] + p[1] * x + p[2] * x * x - q->y[i];
		if (jac != NULL)
			jac[3 * i] = 1, jac[3 * i + 1] = x, jac[3 * i + 2] = x * x;
	}
	return 0;
}

/* Solves the n x n system A z = b (n <= 3) by Gaussian elimination with
 * partial pivoting in long double. */
static void solve_small(int n, long double a[3][3], long double *b, double *z)
{
	for (int c = 0; c < n; c++) {
		int piv = c;
		for (int i = c + 1; i < n; i++)
			if (fabsl(a[i][c]) > fabsl(a[piv][c]))
				piv = i;
		for (int j = 0; j < n; j++) {
			long double t = a[c][j];
			a[c][j] = a[piv][j], a[piv][j] = t;
		}
		long double t = b[c];
		b[c] = b[piv], b[piv] = t;
		for (int i = c + 1; i < n; i++) {
			long double f = a[i][c] / a[c][c];
			for (int j = c; j < n; j++)
				a[i][j] -= f * a[c][j];
			b[i] -= f * b[c];
		}
	}
	for (int i = n - 1; i >= 0; i--) {
		long double v = b[i];
		for (int j = i + 1; j < n; j++)
			v -= a[i][j] * z[j];
		z[i] = (double)(v / a[i][i]);
	}
}

/* The least-squares coefficients of y on the columns x^e[k] (k < n): the
 * normal equations (sum x^(e_j + e_k)) z = sum x^e_j y, solved above. */
static void normal_equations(const poly *q, int n, const int *e, const double *y, double *z)
{
	long double a[3][3] = {{0}}, b[3] = {0};
	for (int i = 0; i < POLY_N; i++)
		for (int j = 0; j < n; j++) {
			b[j] += powl(q->x[i], e[j]) * y[i];
			for (int k = 0; k < n; k++)
				a[j][k] += powl(q->x[i], e[j] + e[k]);
		}
	solve_small(n, a, b, z);
}

static poly g_poly;

static bk_problem poly_problem(void)
{
	for (int i = 0; i < POLY_N; i++) {
		g_poly.x[i] = -1 + 2.0 * i / (POLY_N - 1);
		g_poly.y[i] = exp(g_poly.x[i]); /* not a quadratic: cost > 0 at the optimum */
	}
	static int size[] = {POLY_N};
	bk_problem p = {3, 1, size, poly_residuals, &g_poly, NULL, NULL, NULL};
	return p;
}

/* 3. The quadratic least-squares fit of exp on [-1, 1]: the normal equations'
 * solution, to 1e-9 relative (condition of JᵀJ ~ 20: rounding leaves ~1e-14).
 * Then with p1 held at 0.5 (a constant flag in the middle: the free columns
 * 0 and 2 mapped back): the fit of y - 0.5 x on 1 and x², p1 exactly 0.5. */
Test(tiny, linear_least_squares_normal_equations)
{
	bk_problem p = poly_problem();
	bk_fit_options o = tight();
	double c[3] = {0, 0, 0}, want[3];
	static const int e3[] = {0, 1, 2};
	normal_equations(&g_poly, 3, e3, g_poly.y, want);
	bk_fit_summary s;
	cr_assert_eq(bk_solve_tiny(&p, &o, c, &s), 0, "%s", s.message);
	cr_assert_eq(s.termination, BK_TERM_CONVERGENCE, "%s", s.message);
	for (int j = 0; j < 3; j++)
		check_rel(c[j], want[j], 1e-9, "coefficient");

	int held[] = {0, 1, 0};
	p.constant = held;
	double yr[POLY_N], want2[2];
	for (int i = 0; i < POLY_N; i++)
		yr[i] = g_poly.y[i] - 0.5 * g_poly.x[i];
	static const int e2[] = {0, 2};
	normal_equations(&g_poly, 2, e2, yr, want2);
	double d[3] = {0, 0.5, 0};
	cr_assert_eq(bk_solve_tiny(&p, &o, d, &s), 0, "%s", s.message);
	cr_assert_eq(s.termination, BK_TERM_CONVERGENCE, "%s", s.message);
	cr_assert_eq(d[1], 0.5, "held: %.17g", d[1]);
	check_rel(d[0], want2[0], 1e-9, "p0 with p1 held");
	check_rel(d[2], want2[1], 1e-9, "p2 with p1 held");
}

/* ---- a constant fitted to values ----------------------------------------------- */

static const double g_values[] = {1, 2, 3, 10};

static int const_residuals(void *ctx, int block, const double *p, double *r, double *jac)
{
	(void)ctx;
	for (int i = 0; i < 2; i++) {
		r[i] = p[0] - g_values[2 * block + i];
		if (jac != NULL)
			jac[i] = 1;
	}
	return 0;
}

/* 4. c fitted to {1, 2, 3, 10} (two blocks) with the default tolerances: the
 * mean 4, cost(c) = 25 + 2 (c - 4)^2. A stop on function_tolerance (1e-12
 * relative) leaves at most a cost change of ~1e-12 * 25 to gain, so
 * |c - 4| <= sqrt(12.5e-12) = 3.54e-6 and the cost within 1e-12 relative (as
 * bk_solve's test_solver.c constant_fit_default_tolerances). From c = -7 the
 * initial cost is 1/2 (64 + 81 + 100 + 289) = 267. */
Test(tiny, constant_fit_default_tolerances)
{
	int size[] = {2, 2};
	bk_problem p = {1, 2, size, const_residuals, NULL, NULL, NULL, NULL};
	bk_fit_options o = BK_FIT_OPTIONS_INIT;
	double c = -7;
	bk_fit_summary s;
	cr_assert_eq(bk_solve_tiny(&p, &o, &c, &s), 0, "%s", s.message);
	cr_assert_eq(s.termination, BK_TERM_CONVERGENCE, "%s", s.message);
	check_abs(c, 4, 3.54e-6, "c");
	check_rel(s.final_cost, 25, 1e-12, "final cost");
	check_rel(s.initial_cost, 267, 1e-15, "initial cost");
}

/* ---- constant flags --------------------------------------------------------------- */

/* 5. a held at 2.5 (not its optimum) comes back bit for bit, b moves to the
 * 1-D optimum, which bk_solve finds too (1e-9 relative). All held: nothing
 * moves, CONVERGENCE, and both costs are the start's, summed here. */
Test(tiny, constant_flags_hold_exactly)
{
	bk_problem p = exp_problem(&g_exp, 0);
	int constant[] = {1, 0};
	p.constant = constant;
	bk_fit_options o = tight();
	double ab[2] = {2.5, 0.3}, ref[2] = {2.5, 0.3};
	bk_fit_summary s;
	cr_assert_eq(bk_solve_tiny(&p, &o, ab, &s), 0, "%s", s.message);
	cr_assert_eq(s.termination, BK_TERM_CONVERGENCE, "%s", s.message);
	cr_assert_eq(ab[0], 2.5, "a = %.17g", ab[0]);
	cr_assert_eq(bk_solve(&p, &o, ref, &s), 0, "%s", s.message);
	check_rel(ab[1], ref[1], 1e-9, "b against bk_solve");
	cr_assert(ab[1] != 0.3);

	int all[] = {1, 1};
	p.constant = all;
	double q[2] = {2.5, 0.3}, c0 = 0;
	for (int k = 0; k < EXP_N; k++) {
		double r = 2.5 * exp2(0.3 * g_exp.x[k]) - g_exp.y[k];
		c0 += 0.5 * r * r;
	}
	cr_assert_eq(bk_solve_tiny(&p, &o, q, &s), 0, "%s", s.message);
	cr_assert_eq(s.termination, BK_TERM_CONVERGENCE, "%s", s.message);
	cr_assert(q[0] == 2.5 && q[1] == 0.3);
	cr_assert_eq(s.initial_cost, s.final_cost);
	check_rel(s.final_cost, c0, 1e-12, "cost where it is");
	cr_assert_eq(s.iterations, 0);
}

/* ---- agreement with bk_solve --------------------------------------------------------- */

/* 6. Inconsistent data (±0.01 alternating on the exponential: cost > 0 at
 * the optimum), tight tolerances: bk_solve_tiny and bk_solve (Ceres) reach
 * the same a, b and cost to 1e-9 relative. The optimum is pinned far better
 * than that by both: curvature ~1e2..1e3, C ~ 0.05, so sqrt(2 k eps C / h)
 * ~ 1e-9 absolute on a ~ 2, b ~ -3 (test_solver.c's pinned(), k = 64). */
Test(tiny, agrees_with_bk_solve)
{
	bk_problem p = exp_problem(&g_exp, 0.01);
	bk_fit_options o = tight();
	double t[2] = {1, 1}, c[2] = {1, 1};
	bk_fit_summary st, sc;
	cr_assert_eq(bk_solve_tiny(&p, &o, t, &st), 0, "%s", st.message);
	cr_assert_eq(bk_solve(&p, &o, c, &sc), 0, "%s", sc.message);
	cr_assert_eq(st.termination, BK_TERM_CONVERGENCE, "%s", st.message);
	cr_assert_eq(sc.termination, BK_TERM_CONVERGENCE, "%s", sc.message);
	check_rel(t[0], c[0], 1e-9, "a");
	check_rel(t[1], c[1], 1e-9, "b");
	check_rel(st.final_cost, sc.final_cost, 1e-9, "cost");
	check_rel(st.initial_cost, sc.initial_cost, 1e-12, "initial cost");
	/* and with the default tolerances, the fitter's */
	bk_fit_options d = BK_FIT_OPTIONS_INIT;
	double t2[2] = {1, 1}, c2[2] = {1, 1};
	cr_assert_eq(bk_solve_tiny(&p, &d, t2, &st), 0, "%s", st.message);
	cr_assert_eq(bk_solve(&p, &d, c2, &sc), 0, "%s", sc.message);
	check_rel(t2[0], c2[0], 1e-9, "a, default tolerances");
	check_rel(t2[1], c2[1], 1e-9, "b, default tolerances");
	check_rel(st.final_cost, sc.final_cost, 1e-12, "cost, default tolerances");
}

/* ---- tolerance meanings ----------------------------------------------------------- */

/* 7. gradient_tolerance means Ceres' unscaled max_j |g_j| (TinySolver's own
 * test is Jacobi-scaled, |g_j| / (1 + ||J_j||), ||J_1|| ~ 20 here): with
 * gtol 1e-3 and the other tolerances out of the way, a stop on the gradient
 * leaves every |g_j|, computed here from the callback, below 1e-3. */
Test(tiny, gradient_tolerance_is_unscaled)
{
	bk_problem p = exp_problem(&g_exp, 0.01);
	bk_fit_options o = tight();
	o.gradient_tolerance = 1e-3;
	double ab[2] = {1, 1}, g[2];
	bk_fit_summary s;
	cr_assert_eq(bk_solve_tiny(&p, &o, ab, &s), 0, "%s", s.message);
	cr_assert_eq(s.termination, BK_TERM_CONVERGENCE, "%s", s.message);
	cr_assert_not_null(strstr(s.message, "gradient tolerance"), "%s", s.message);
	gradient(&p, ab, g);
	cr_assert(fabs(g[0]) < 1e-3 && fabs(g[1]) < 1e-3, "g = (%g, %g)", g[0], g[1]);
}

/* 8. The iteration limit: Rosenbrock from (-1.2, 1) needs more than 2
 * iterations; with max_iterations = 2: NO_CONVERGENCE, 2 iterations, the
 * cost not raised (a rejected step is not taken). */
Test(tiny, iteration_limit_is_no_convergence)
{
	int size[] = {2};
	bk_problem p = {2, 1, size, rosenbrock, NULL, NULL, NULL, NULL};
	bk_fit_options o = BK_FIT_OPTIONS_INIT;
	o.max_iterations = 2;
	double q[2] = {-1.2, 1};
	bk_fit_summary s;
	cr_assert_eq(bk_solve_tiny(&p, &o, q, &s), 0, "%s", s.message);
	cr_assert_eq(s.termination, BK_TERM_NO_CONVERGENCE, "%s", s.message);
	cr_assert_eq(s.iterations, 2);
	cr_assert_str_eq(s.message, "iteration limit reached (TinySolver): 2 iterations");
	/* start cost: 1/2 (2.2^2 + (10 (1 - 1.44))^2) = 1/2 (4.84 + 19.36) = 12.1 */
	check_rel(s.initial_cost, 12.1, 1e-14, "initial cost");
	cr_assert(s.final_cost <= s.initial_cost);
}

/* ---- refusals and misuse ------------------------------------------------------------ */

static void expect_refused(const bk_problem *p, const bk_fit_options *o, double *params, const char *message)
{
	double before[16];
	int np = p != NULL && p->np > 0 && p->np <= 16 && params != NULL ? p->np : 0;
	if (np > 0)
		memcpy(before, params, np * sizeof *params);
	bk_fit_summary s;
	cr_assert_eq(bk_solve_tiny(p, o, params, &s), -1, "expected '%s'", message);
	cr_assert_str_eq(s.message, message);
	cr_assert_eq(s.termination, BK_TERM_FAILURE);
	for (int i = 0; i < np; i++)
		cr_assert(memcmp(&before[i], &params[i], sizeof *params) == 0, "params untouched");
}

/* 9. What the fast path does not take (finite bounds, a loss, dogleg) is
 * refused with a reason, and bk_solve_tiny_applies says 0; what bk_solve
 * rejects is rejected with bk_solve's message. Bounds of ±inf, given or NULL,
 * are no bounds: applies says 1 and the solve runs. */
Test(tiny, refusals_and_misuse)
{
	int size[] = {2};
	bk_problem ok = {2, 1, size, rosenbrock, NULL, NULL, NULL, NULL}, p;
	bk_fit_options d = BK_FIT_OPTIONS_INIT, o;
	double q[2] = {0.5, 0.5};
	cr_assert_eq(bk_solve_tiny_applies(&ok, &d), 1);

	double lo[] = {-HUGE_VAL, 0}, hi[] = {HUGE_VAL, 1}, none_lo[] = {-HUGE_VAL, -HUGE_VAL},
	       none_hi[] = {HUGE_VAL, HUGE_VAL};
	p = ok, p.lower = lo;
	expect_refused(&p, &d, q, "lower[1]: bk_solve_tiny takes no bounds (bk_solve does), got 0");
	cr_assert_eq(bk_solve_tiny_applies(&p, &d), 0);
	p = ok, p.upper = hi;
	expect_refused(&p, &d, q, "upper[1]: bk_solve_tiny takes no bounds (bk_solve does), got 1");
	cr_assert_eq(bk_solve_tiny_applies(&p, &d), 0);
	p = ok, p.lower = none_lo, p.upper = none_hi;
	cr_assert_eq(bk_solve_tiny_applies(&p, &d), 1);
	bk_fit_summary s;
	double q2[2] = {0.5, 0.5};
	cr_assert_eq(bk_solve_tiny(&p, &d, q2, &s), 0, "%s", s.message);
	cr_assert_eq(s.termination, BK_TERM_CONVERGENCE, "%s", s.message);

	o = d, o.loss = BK_LOSS_HUBER;
	expect_refused(&ok, &o, q, "loss: bk_solve_tiny takes no robust loss (bk_solve does), got HUBER");
	cr_assert_eq(bk_solve_tiny_applies(&ok, &o), 0);
	o = d, o.trust_region = BK_TR_DOGLEG;
	expect_refused(&ok, &o, q, "trust_region: bk_solve_tiny is Levenberg-Marquardt only, got DOGLEG");
	cr_assert_eq(bk_solve_tiny_applies(&ok, &o), 0);

	/* bk_solve's checks, bk_solve's messages */
	o = d, o.max_iterations = 0;
	expect_refused(&ok, &o, q, "max_iterations: must be in 1..100000, got 0");
	cr_assert_eq(bk_solve_tiny_applies(&ok, &o), 0);
	p = ok, p.np = 0;
	expect_refused(&p, &d, q, "np: must be in 1..16, got 0");
	cr_assert_eq(bk_solve_tiny_applies(&p, &d), 0);
	p = ok, p.np = 17;
	expect_refused(&p, &d, q, "np: must be in 1..16, got 17");
	cr_assert_eq(bk_solve_tiny_applies(&p, &d), 0);
	p = ok, p.fn = NULL;
	expect_refused(&p, &d, q, "fn is NULL");
	expect_refused(NULL, &d, q, "problem is NULL");
	cr_assert_eq(bk_solve_tiny_applies(NULL, &d), 0);
	expect_refused(&ok, NULL, q, "options are NULL");
	cr_assert_eq(bk_solve_tiny_applies(&ok, NULL), 0);
	expect_refused(&ok, &d, NULL, "params is NULL");
	double nan_start[2] = {0, NAN};
	expect_refused(&ok, &d, nan_start, "params[1]: must be finite, got nan");
	int flags[] = {0, 2};
	p = ok, p.constant = flags;
	expect_refused(&p, &d, q, "constant[1]: must be 0 or 1, got 2");
	cr_assert_eq(bk_solve_tiny(&ok, &d, q, NULL), -1, "summary NULL");
}

/* ---- callback failure --------------------------------------------------------------- */

static int solve_silently(const bk_problem *p, const bk_fit_options *o, double *q, bk_fit_summary *s)
{
	return solve_silently_with(bk_solve_tiny, p, o, q, s);
}

/* 10. Failing at the first evaluation and in the middle of the solve (call
 * 5): a non-zero return, a NaN residual, a NaN Jacobian entry. Each gives
 * return 0, FAILURE with bk_solve's message for the first failure, no further
 * call after it (TinySolver itself would go on with a NaN cost), nothing
 * printed, and finite params (the last point evaluated in full). */
Test(tiny, callback_failure_is_failure)
{
	static const char *first[] = {
	    "callback failed: block 0 returned 7",
	    "non-finite residual: block 0, residual 1",
	    "non-finite jacobian: block 0, residual 1, parameter 1",
	};
	int size[] = {2};
	for (int what = 0; what < 3; what++)
		for (int at = 0; at <= 5; at += 5) {
			failing f = {0, at, what};
			bk_problem p = {2, 1, size, failing_rosenbrock, &f, NULL, NULL, NULL};
			bk_fit_options o = BK_FIT_OPTIONS_INIT;
			double q[2] = {-1.2, 1};
			bk_fit_summary s;
			cr_assert_eq(solve_silently(&p, &o, q, &s), 0, "%s", s.message);
			cr_assert_eq(s.termination, BK_TERM_FAILURE, "what %d at %d: %s", what, at, s.message);
			cr_assert_eq(f.calls, at + 1, "what %d at %d: %d calls, the failing one last", what, at, f.calls);
			if (at == 0 || what != 2)
				cr_assert_str_eq(s.message, first[what]);
			else /* at call 5 the failing call may be cost-only (NaN residual 0) */
				cr_assert(strcmp(s.message, first[2]) == 0 ||
				              strcmp(s.message, "non-finite residual: block 0, residual 0") == 0,
				          "%s", s.message);
			cr_assert(isfinite(q[0]) && isfinite(q[1]));
			if (at == 0)
				cr_assert(q[0] == -1.2 && q[1] == 1, "a failure at the start leaves the start");
		}
}

/* A line y = p0 + p1 x over 37 residuals with one of them, bad, made NaN or
 * +-inf at the first call: the finiteness check reads them eight at a time
 * and the rest one by one (fit/tiny.cc, all_finite), so the bad one is put
 * at each place of both; every value finite is the control. */
typedef struct bad_line {
	int bad;
	double v;
} bad_line;

static int line_with_a_bad_residual(void *ctx, int block, const double *p, double *r, double *jac)
{
	const bad_line *b = ctx;
	(void)block;
	for (int i = 0; i < 37; i++) {
		r[i] = p[0] + p[1] * i - (0.5 + 0.25 * i);
		if (jac)
			jac[2 * i] = 1, jac[2 * i + 1] = i;
	}
	if (b->bad >= 0)
		r[b->bad] = b->v;
	return 0;
}

Test(tiny, a_non_finite_residual_is_found_at_any_place)
{
	int size[] = {37};
	const double bad[] = {NAN, INFINITY, -INFINITY};
	for (int k = -1; k < 37; k++)
		for (int v = 0; v < 3; v++) {
			bad_line b = {k, bad[v]};
			bk_problem p = {2, 1, size, line_with_a_bad_residual, &b, NULL, NULL, NULL};
			bk_fit_options o = BK_FIT_OPTIONS_INIT;
			double q[2] = {1, 1};
			bk_fit_summary s;
			cr_assert_eq(bk_solve_tiny(&p, &o, q, &s), 0, "%s", s.message);
			if (k < 0) { /* the control: every residual finite, the line's constants */
				cr_assert_eq(s.termination, BK_TERM_CONVERGENCE, "%s", s.message);
				cr_assert(fabs(q[0] - 0.5) < 1e-9 && fabs(q[1] - 0.25) < 1e-9, "%g %g", q[0], q[1]);
				break;
			}
			char want[80];
			snprintf(want, sizeof want, "non-finite residual: block 0, residual %d", k);
			cr_assert_eq(s.termination, BK_TERM_FAILURE, "residual %d = %g: %s", k, bad[v], s.message);
			cr_assert_str_eq(s.message, want);
		}
}

Test(tiny, a_trial_into_nan_is_rejected)
{
	check_pole_and_wall(bk_solve_tiny, "bk_solve_tiny");
	check_pole_and_wall(bk_solve_tiny_reusing, "bk_solve_tiny_reusing");
}

/* And a healthy solve prints nothing either. */
Test(tiny, healthy_solve_is_silent)
{
	bk_problem p = exp_problem(&g_exp, 0);
	bk_fit_options o = BK_FIT_OPTIONS_INIT;
	double ab[2] = {1, 0};
	bk_fit_summary s;
	cr_assert_eq(solve_silently(&p, &o, ab, &s), 0);
	cr_assert_eq(s.termination, BK_TERM_CONVERGENCE, "%s", s.message);
}

/* ---- threads ------------------------------------------------------------------------- */

/* One thread's work: REPEAT solves of its problem, each from the same start. */
enum { REPEAT = 200 };

typedef struct job {
	bk_problem p;
	double start[3], out[REPEAT][3];
	double cost[REPEAT];
	int rc;
} job;

static void *run_job(void *arg)
{
	job *j = arg;
	bk_fit_options o = BK_FIT_OPTIONS_INIT;
	j->rc = 0;
	for (int k = 0; k < REPEAT; k++) {
		bk_fit_summary s;
		memcpy(j->out[k], j->start, sizeof j->start);
		j->rc |= bk_solve_tiny(&j->p, &o, j->out[k], &s) != 0 || s.termination != BK_TERM_CONVERGENCE;
		j->cost[k] = s.final_cost;
	}
	return NULL;
}

static job g_jobs[2];

/* 11. Two threads at once, each solving its own problem (the noisy
 * exponential, the quadratic fit) 200 times: every solution and cost is,
 * bit for bit, the one the same solve gives alone on this thread. */
Test(tiny, two_threads_same_bits)
{
	g_jobs[0].p = exp_problem(&g_exp2, 0.01);
	g_jobs[0].start[0] = 1, g_jobs[0].start[1] = 1, g_jobs[0].start[2] = 0;
	g_jobs[1].p = poly_problem();
	g_jobs[1].start[0] = g_jobs[1].start[1] = g_jobs[1].start[2] = 0;
	double alone[2][3], alone_cost[2];
	for (int t = 0; t < 2; t++) {
		bk_fit_options o = BK_FIT_OPTIONS_INIT;
		bk_fit_summary s;
		memcpy(alone[t], g_jobs[t].start, sizeof alone[t]);
		cr_assert_eq(bk_solve_tiny(&g_jobs[t].p, &o, alone[t], &s), 0, "%s", s.message);
		alone_cost[t] = s.final_cost;
	}
	pthread_t th[2];
	for (int t = 0; t < 2; t++)
		cr_assert_eq(pthread_create(&th[t], NULL, run_job, &g_jobs[t]), 0);
	for (int t = 0; t < 2; t++)
		cr_assert_eq(pthread_join(th[t], NULL), 0);
	for (int t = 0; t < 2; t++) {
		cr_assert_eq(g_jobs[t].rc, 0, "thread %d: a solve failed", t);
		for (int k = 0; k < REPEAT; k++) {
			cr_assert(memcmp(g_jobs[t].out[k], alone[t], sizeof alone[t]) == 0, "thread %d run %d: other bits",
			          t, k);
			cr_assert(memcmp(&g_jobs[t].cost[k], &alone_cost[t], sizeof(double)) == 0, "thread %d run %d cost", t,
			          k);
		}
	}
}
