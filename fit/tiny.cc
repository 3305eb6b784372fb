/*
 * tiny.cc — bk_solve_tiny (fit/solver.h): the fast path for small dense
 * problems, Ceres' TinySolver behind bk_solve's C contract. TinySolver
 * (ceres/tiny_solver.h) is dense Levenberg-Marquardt on the normal equations,
 * header-only and built on Eigen alone: one residual vector and one dense
 * Jacobian per evaluation, no per-block machinery.
 *
 * Facts this file relies on (ceres/tiny_solver.h of Ceres 2.1, Debian 12; read
 * there, it is short):
 *   - the functor's return value is ignored ("TODO: deal with failure"): a
 *     false return leaves stale residuals in use. So a callback failure, or a
 *     non-finite value at the start or at a point it accepts, throws
 *     EvalFailure out of the functor and out of Solve (whose state is all in
 *     the solver object, freed on the way), caught here: FAILURE, with
 *     bk_solve's messages;
 *   - a NaN residual at a trial point makes its rho NaN, which fails
 *     `rho > 0` and the reject branch's cost-change test alike: the step is
 *     rejected and the trust region shrinks, as Ceres does with a cost
 *     function that fails at a trial point. So a trial whose residuals are
 *     not all finite (a step into sqrt or rsqrt of a negative, a pole) has
 *     every residual set to NaN and is rejected: the fit goes on from the
 *     accepted point with a shorter step (solver.cc does the same). Where
 *     those rejections end the solve (the step shrinks below the parameter
 *     tolerance right after one), the point is at the edge of where the form
 *     is finite, not at a minimum: NO_CONVERGENCE, said so (report);
 *   - the Jacobian it asks for is column-major (residuals x parameters), and
 *     it asks for it (jacobian != NULL) exactly at the start and at each point
 *     it accepts, right before testing the gradient and, on the next step, the
 *     function tolerance; a step's trial point is evaluated with jacobian =
 *     NULL. Its `options` are read afresh at every test, so the functor
 *     refreshes the tolerances that depend on the point (Tolerances below);
 *   - a trial's values stay in the array the functor wrote them to (its
 *     f_x_new_) until the next trial: the Update that accepts the trial
 *     finds them there (bk_solve_tiny_cols copies them once, not twice);
 *   - its Jacobian (the array the functor is handed) is read only inside
 *     Update, right after the functor fills it: between two Updates nothing
 *     reads it (the step uses JᵀJ and g, made in Update), and the array stays
 *     where it is (sized once, before the first call). So a trial's Jacobian
 *     may be written into it directly (bk_solve_tiny_cols, Residuals::by_cols):
 *     if the trial is accepted, Update finds it there; if not, the next
 *     Update overwrites it;
 *   - it neither logs nor prints (it includes only <cassert>, <cmath> and
 *     Eigen: no glog, so nothing to silence, unlike solver.cc);
 *   - Eigen without OpenMP (not enabled here) computes on the calling thread,
 *     and its one piece of global state, the cache-size table of the matrix
 *     product, is a function-local static initialised once (thread-safely in
 *     C++11) and only read after: a TinySolver per call, with the functor's
 *     state on the caller's stack, is thread-safe and deterministic.
 *
 * Tolerances: TinySolver's differ from Ceres' (solver.h); mapped so that each
 * of its stops implies Ceres' condition for the same tolerance:
 *   - function: TinySolver stops when |2 Δcost| < function_tolerance, an
 *     ABSOLUTE bound (its header's comment says relative; the code is not),
 *     tested on the trial step. Ceres: |Δcost| / cost <= ftol, cost at the
 *     current point. So at each point it accepts, the functor sets
 *     function_tolerance = 2 (ftol/100) cost. Unlike Ceres, TinySolver takes
 *     a step that lowered the cost before stopping on it (as MINPACK does),
 *     but it is asked for ftol/100 all the same, as solver.cc asks Ceres, so
 *     that both paths stop on the same relative change of the cost and the
 *     fast path is never the less converged of the two (the agreement with
 *     bk_solve in tests/test_tiny.c). About one iteration at the default.
 *   - gradient: TinySolver tests max_j |s_j g_j|, g = Jᵀr, with the Jacobi
 *     scaling s_j = 1/(1 + ||J_j||) of the start's Jacobian; Ceres tests
 *     max_j |g_j| (no bounds here: the projection is the identity). With
 *     gradient_tolerance = gtol min_j s_j its stop implies max_j |g_j| < gtol:
 *     never looser than Ceres, stricter by the spread of the column norms.
 *   - parameter: the same inequality as Ceres, |Δx| < ptol (|x| + ptol) on the
 *     candidate step, not taken; but |x| is over the free parameters only
 *     (Ceres: the whole block, held coordinates included): never looser.
 *   - iterations: TinySolver numbers them 1..max_num_iterations - 1, so it is
 *     given max_iterations + 1; each computes one step, accepted or not, as a
 *     Ceres iteration does.
 *   - cost_threshold: TinySolver also stops when the cost falls below an
 *     absolute threshold (default DBL_EPSILON); Ceres has no such test, so it
 *     is 0 (a cost of exactly 0 stops on the gradient).
 *   - the initial trust region radius 1e4 is both libraries' default. What
 *     still differs: TinySolver accepts any step that lowers the cost (Ceres
 *     only one with gain ratio > 1e-3) and solves with LDLT (Ceres' dense
 *     normal Cholesky here): the path may differ, not the minimum.
 */
/*
 * Before any Eigen header: products whose every size is fixed and at most
 * 2,048 are "small" to Eigen, so TinySolver's JᵀJ of a 1,024 x N screening
 * Jacobian (N <= 4) is N² dot products of length 1,024 (Eigen's coefficient
 * product, vectorised over the depth) instead of its blocked general
 * product, which packs J twice for a 4 x 4 result (with its packing,
 * 18.5 % of a 1-thread vf2d search, perf). Eigen's own configuration macro
 * (EIGEN_CACHEFRIENDLY_PRODUCT_THRESHOLD, default 8). Sizes known only at
 * run time stay "large": the dynamic instantiations, and the cache sizes
 * pinned below, are as before. The sums run in another order than the
 * blocked product's, fixed by the build (SSE2 at the x86-64 baseline), and
 * no cache size enters them. ~8 % more screening fits/s (bench_speed). No
 * fixed-size product between 9 and 2,048 is instantiated elsewhere (solver.cc,
 * the other C++ file, has none), so the macro changes no other code.
 */
#define EIGEN_CACHEFRIENDLY_PRODUCT_THRESHOLD 2048
#include "solver.h"
#include "bridge.h"
#include "switches.h"

#include <ceres/tiny_solver.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <limits>
#include <new>
#include <vector>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace {

using bk_bridge::say;
using bk_bridge::enum_value;
using bk_bridge::kEdgeMessage;

/*
 * Eigen's cache sizes, pinned before main. Where the residuals' count is
 * dynamic (65,536 for a refit; a screening grid other than 1,024) TinySolver
 * forms JᵀJ with Eigen's general product, whose blocking splits the depth
 * (the residuals) into panels sized from the L1
 * size it reads from CPUID (max_kc = (L1 - 128)/64 for doubles: 504 at 32 KiB,
 * 760 at 48 KiB), and the panels' partial sums are added in a different order
 * for a different split: the same solve on a CPU with another L1 gave other
 * bits, and a screening error rounded to 20 bits can then move a candidate
 * across a tie. Pinned to what Eigen 3.4 reads on the AMD EPYC the committed
 * results were made on (32 KiB L1, 1 MiB L2, 320 MiB L3), so those results
 * stay as they are and every CPU takes the same panels. Static
 * initialisation: before main, before any thread; Ceres' own products
 * (solver.cc) see the same sizes.
 */
const bool kEigenCachesPinned = [] {
	Eigen::setCpuCacheSizes(32768, 1048576, 335544320);
	return true;
}();

constexpr int kMaxParams = 16; /* solver.h: np in 1..16 (checked by bk_problem_valid) */

/* What ends a solve from inside the functor: the first failed evaluation. */
struct EvalFailure {
	char text[160];
};

[[noreturn]] void fail(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

void fail(const char *fmt, ...)
{
	EvalFailure f;
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(f.text, sizeof f.text, fmt, ap);
	va_end(ap);
	throw f;
}

/* Whether the fast path refuses valid options and a valid problem (a loss,
 * dogleg, a bound that is not infinite), the reason in why. */
bool refuses(const bk_problem &p, const bk_fit_options &o, char *why, size_t len)
{
	static const char *const kLossName[] = {"NONE", "HUBER", "CAUCHY", "SOFTL1"};
	int loss = enum_value(&o.loss); /* in range: the options are valid */
	if (loss != BK_LOSS_NONE)
		return say(why, len, "loss: bk_solve_tiny takes no robust loss (bk_solve does), got %s",
		           kLossName[loss]),
		       true;
	if (enum_value(&o.trust_region) != BK_TR_LEVENBERG_MARQUARDT)
		return say(why, len, "trust_region: bk_solve_tiny is Levenberg-Marquardt only, got DOGLEG"),
		       true;
	for (int i = 0; i < p.np; i++) {
		if (p.lower != nullptr && p.lower[i] != -HUGE_VAL)
			return say(why, len, "lower[%d]: bk_solve_tiny takes no bounds (bk_solve does), got %.17g", i,
			           p.lower[i]),
			       true;
		if (p.upper != nullptr && p.upper[i] != HUGE_VAL)
			return say(why, len, "upper[%d]: bk_solve_tiny takes no bounds (bk_solve does), got %.17g", i,
			           p.upper[i]),
			       true;
	}
	return false;
}

/* 1 if every x[0..n) is finite. x - x is 0 for a finite x and NaN otherwise,
 * so one sum tells, with no overflow, in any order. A loop of isfinite with
 * an early exit does not vectorise (this check was ~10 % of a vf2d solve,
 * perf); Eigen's sum of x * 0 did, with two vectors of partial sums, one
 * serial chain of additions each (1.5 % of a vf2d search); four here. */
bool all_finite(const double *x, size_t n)
{
#ifdef __SSE2__
	__m128d a0 = _mm_setzero_pd(), a1 = a0, a2 = a0, a3 = a0;
	size_t i = 0;
	for (; i + 8 <= n; i += 8) {
		__m128d v0 = _mm_loadu_pd(x + i), v1 = _mm_loadu_pd(x + i + 2);
		__m128d v2 = _mm_loadu_pd(x + i + 4), v3 = _mm_loadu_pd(x + i + 6);
		a0 = _mm_add_pd(a0, _mm_sub_pd(v0, v0));
		a1 = _mm_add_pd(a1, _mm_sub_pd(v1, v1));
		a2 = _mm_add_pd(a2, _mm_sub_pd(v2, v2));
		a3 = _mm_add_pd(a3, _mm_sub_pd(v3, v3));
	}
	double t[2];
	_mm_storeu_pd(t, _mm_add_pd(_mm_add_pd(a0, a1), _mm_add_pd(a2, a3)));
	double sum = t[0] + t[1];
	for (; i < n; i++)
		sum += x[i] - x[i];
	return std::isfinite(sum);
#else
	return std::isfinite((Eigen::Map<const Eigen::ArrayXd>(x, (Eigen::Index)n) * 0.0).sum());
#endif
}

/* What the functor keeps between calls (on bk_solve_tiny's stack). */
struct State {
	double x[kMaxParams];      /* the full parameter vector: held ones at their values */
	double good[kMaxParams];   /* the last point evaluated with its Jacobian, all finite */
	double first_cost = NAN;   /* cost at the start (NAN until evaluated) */
	double good_cost = NAN;    /* cost at good */
	bool scaled = false;       /* the gradient tolerance is set (first Jacobian seen) */
	double *function_tolerance = nullptr; /* TinySolver's options, refreshed per point */
	double *gradient_tolerance = nullptr;
	std::vector<double> block_jac; /* one block's row-major Jacobian, all np columns */
	/* the last trial point (evaluated without a Jacobian asked for): its
	 * values and, made in the same pass, its Jacobian (every block's rows, all
	 * np columns), kept for the call that accepts it (see Residuals); by
	 * columns, its values stay where TinySolver keeps them (trial_rs) and
	 * its Jacobian is written where TinySolver reads it (trial_at), so the
	 * two buffers are the row-major path's alone */
	bool keeps = false; /* trials are kept for their acceptance */
	bool trial_valid = false;
	double trial_x[kMaxParams];
	std::vector<double> trial_r, trial_jac;
	/* bk_solve_tiny_cols: the trial's Jacobian is by columns (nfree of m),
	 * and whether it failed its finiteness test, with the message its
	 * acceptance fails with */
	bool trial_bad = false;
	char trial_why[160];
	double *solver_jac = nullptr; /* TinySolver's Jacobian, from its first Update */
	double *trial_at = nullptr;   /* where the last trial's Jacobian is */
	const double *trial_rs = nullptr; /* and its values: TinySolver's array (see the header) */
	bool last_trial_nonfinite = false; /* the last trial was rejected for a non-finite residual */
	std::vector<double> held; /* the held parameters' columns of one block (tested, not used) */
};

/* The residuals of all blocks, in order, as one vector over the free
 * parameters: TinySolver's functor (ceres/tiny_solver.h), the residuals'
 * count dynamic, the free parameters' N fixed at compile time (1..kMaxFixed)
 * or dynamic (Eigen::Dynamic, beyond): see solve_n. */
template <int N, int M = Eigen::Dynamic>
class Residuals {
public:
	using Scalar = double;
	enum { NUM_RESIDUALS = M, NUM_PARAMETERS = N };

	Residuals(const bk_problem &p, const bk_fit_options &o, State *st, bool reuse, bk_residual_cols_fn cols)
	    : p_(p), o_(o), st_(st), cols_(cols)
	{
		int max_block = 0;
		for (int b = 0; b < p.nblocks; b++) {
			m_ += p.block_size[b]; /* <= INT_MAX: bk_problem_valid */
			max_block = std::max(max_block, p.block_size[b]);
		}
		for (int i = 0; i < p.np; i++)
			if (p.constant == nullptr || !p.constant[i])
				free_[nfree_++] = i;
		if (cols == nullptr)
			st->block_jac.resize((size_t)max_block * (size_t)p.np);
		else if (nfree_ < p.np)
			st->held.resize((size_t)max_block * (size_t)p.np);
		st->keeps = reuse && bk_tiny_reuse_trial;
		if (st->keeps && cols == nullptr) { /* zeroed at every solve: not where they go unused */
			st->trial_r.resize((size_t)m_);
			st->trial_jac.resize((size_t)m_ * (size_t)p.np);
		}
	}

	int NumResiduals() const { return m_; }
	int NumParameters() const { return nfree_; }
	int free_index(int k) const { return free_[k]; }

	/* Residuals at the free parameters xf (held ones from st_->x), and the
	 * column-major Jacobian over the free ones when jac is not NULL. Throws
	 * EvalFailure (see the header); never returns false. */
	/*
	 * TinySolver evaluates a trial point without the Jacobian and, when it
	 * accepts it, the same point again with it (Update): the forward pass
	 * twice. So a trial computes the Jacobian in the same pass (the
	 * residuals' values are the same whether it is asked for or not: one
	 * kernel) and keeps it with the values; the accepting call, at the same
	 * parameters bit for bit, takes both from there and runs the same checks
	 * in the same order (a non-finite Jacobian still fails at the accepting
	 * call, not at the trial). A rejected trial wastes its backward sweep;
	 * most are accepted. Only for bk_solve_tiny_reusing, whose callback's
	 * values do not depend on whether the Jacobian is asked for (a test's
	 * callback may fail differently in a cost-only call); bk_tiny_reuse_trial
	 * = 0: never (bench_speed).
	 */
	bool operator()(const double *xf, double *r, double *jac) const
	{
		int np = p_.np;
		bool trial = xf != nullptr && jac == nullptr; /* not the start (nor solve's every-held call) */
		for (int k = 0; k < nfree_; k++) {
			if (!std::isfinite(xf[k]))
				fail("linear solver failed: non-finite step in parameter %d", free_[k]);
			st_->x[free_[k]] = xf[k];
		}
		bool reuse = false, keep = false;
		if (st_->keeps) {
			if (jac != nullptr) {
				reuse = st_->trial_valid && std::memcmp(st_->trial_x, st_->x, sizeof(double) * (size_t)np) == 0;
			} else {
				keep = true;
				std::copy(st_->x, st_->x + np, st_->trial_x);
			}
			st_->trial_valid = false;
		}
		if (trial)
			st_->last_trial_nonfinite = false;
		if (cols_ != nullptr) {
			if (!by_cols(r, jac, reuse, keep, trial))
				return reject(r);
			st_->trial_valid = keep;
			if (jac != nullptr)
				accepted(r, jac);
			return true;
		}
		double *bj = keep ? st_->trial_jac.data() : jac != nullptr ? st_->block_jac.data() : nullptr;
		size_t row = 0;
		for (int b = 0; b < p_.nblocks; b++) {
			int mb = p_.block_size[b];
			double *rb = r + row;
			if (reuse) {
				std::copy(st_->trial_r.data() + row, st_->trial_r.data() + row + mb, rb);
				bj = st_->trial_jac.data() + row * (size_t)np;
			} else {
				int rc = p_.fn(p_.ctx, b, st_->x, rb, bj);
				if (rc != 0)
					fail("callback failed: block %d returned %d", b, rc);
			}
			if (trial && !all_finite(rb, (size_t)mb))
				return reject(r);
			check_residuals(b, rb, mb);
			if (keep) {
				std::copy(rb, rb + mb, st_->trial_r.data() + row);
				bj += (size_t)mb * (size_t)np;
			} else if (bj != nullptr) {
				/* all np columns checked, as bk_solve checks what Ceres is given */
				if (!all_finite(bj, (size_t)mb * np))
					for (int k = 0; k < mb * np; k++)
						if (!std::isfinite(bj[k]))
							fail("non-finite jacobian: block %d, residual %d, parameter %d", b, k / np,
							     k % np);
				for (int k = 0; k < nfree_; k++) {
					double *col = jac + (size_t)k * (size_t)m_ + row;
					for (int i = 0; i < mb; i++)
						col[i] = bj[(size_t)i * np + free_[k]];
				}
			}
			row += (size_t)mb;
		}
		st_->trial_valid = keep;
		if (jac != nullptr)
			accepted(r, jac);
		return true;
	}

private:
	/* A trial point with a residual that is not finite: every residual NaN,
	 * so that TinySolver rejects the step (see the header). */
	bool reject(double *r) const
	{
		std::fill(r, r + m_, std::numeric_limits<double>::quiet_NaN());
		st_->trial_valid = false;
		st_->last_trial_nonfinite = true;
		return true;
	}

	/* The residuals' non-finite check and message, as bk_solve's. */
	static void check_residuals(int b, const double *rb, int mb)
	{
		if (!all_finite(rb, (size_t)mb)) /* then the first one is named */
			for (int i = 0; i < mb; i++)
				if (!std::isfinite(rb[i]))
					fail("non-finite residual: block %d, residual %d", b, i);
	}

	/*
	 * operator() for bk_solve_tiny_cols: the callback writes the free
	 * parameters' columns where TinySolver reads them (jac, or the trial's
	 * buffer when keep, both nfree columns of m_ rows), the held ones into a
	 * scratch block (tested as bk_solve tests all np columns, then dropped).
	 * The same checks as the row-major path, in the same order: per block the
	 * callback's failure, then the residuals, then (where a Jacobian is used:
	 * now, or at the trial's acceptance) the Jacobian, its first non-finite
	 * entry named in row-major order as there. False: a trial whose
	 * residuals are not all finite (rejected by the caller, see the header).
	 */
	bool by_cols(double *r, double *jac, bool reuse, bool keep, bool trial) const
	{
		size_t m = (size_t)m_;
		if (reuse) {
			/* the trial's values are still where it wrote them (see the header) */
			if (st_->trial_rs != r)
				std::copy(st_->trial_rs, st_->trial_rs + m, r);
			if (st_->trial_bad)
				fail("%s", st_->trial_why);
			if (st_->trial_at != jac) /* not where TinySolver reads it (see below) */
				std::copy(st_->trial_at, st_->trial_at + m * (size_t)nfree_, jac);
			return true;
		}
		if (jac != nullptr)
			st_->solver_jac = jac;
		/* a trial writes its Jacobian where TinySolver reads it (see the
		 * header), so that its acceptance copies nothing; into a buffer of its
		 * own only before TinySolver's first Update (never: that comes first;
		 * made then, should a later TinySolver change that) */
		if (keep && st_->solver_jac == nullptr)
			st_->trial_jac.resize(m * (size_t)p_.np);
		if (keep)
			st_->trial_at = st_->solver_jac != nullptr ? st_->solver_jac : st_->trial_jac.data();
		double *dst = keep ? st_->trial_at : jac;
		st_->trial_bad = false;
		size_t row = 0;
		for (int b = 0; b < p_.nblocks; b++) {
			int mb = p_.block_size[b];
			double *rb = r + row;
			double *cp[kMaxParams];
			for (int j = 0; j < p_.np; j++) /* the held ones: scratch */
				cp[j] = dst != nullptr && !st_->held.empty() ? st_->held.data() + (size_t)j * (size_t)mb : nullptr;
			for (int k = 0; k < nfree_; k++)
				cp[free_[k]] = dst != nullptr ? dst + (size_t)k * m + row : nullptr;
			int rc = cols_(p_.ctx, b, st_->x, rb, dst != nullptr ? cp : nullptr);
			if (rc == BK_COLS_RES_NONFINITE && trial)
				return false;
			if (rc == BK_COLS_RES_NONFINITE) /* the first is named; the callback tested them all */
				check_residuals(b, rb, mb);
			if (rc != 0 && rc != BK_COLS_JAC_NONFINITE)
				fail("callback failed: block %d returned %d", b, rc);
			if (rc == BK_COLS_JAC_NONFINITE && dst != nullptr && !st_->trial_bad) {
				int bad_i = 0, bad_j = 0;
				for (int i = mb - 1; i >= 0; i--) /* the first in row-major order */
					for (int j = p_.np - 1; j >= 0; j--)
						if (!std::isfinite(cp[j][i]))
							bad_i = i, bad_j = j;
				char why[160];
				say(why, sizeof why, "non-finite jacobian: block %d, residual %d, parameter %d", b, bad_i, bad_j);
				if (!keep)
					fail("%s", why);
				st_->trial_bad = true; /* fails at the acceptance: the first block's */
				std::memcpy(st_->trial_why, why, sizeof why);
			}
			row += (size_t)mb;
		}
		if (keep)
			st_->trial_rs = r;
		return true;
	}

	/* A point TinySolver starts from or accepted: record it and set the
	 * tolerances its next tests read (see the header). */
	void accepted(const double *r, const double *jac) const
	{
		/* Eigen's reductions, as TinySolver's own (vectorised: a plain loop is
		 * one serial chain of additions) */
		double cost = Eigen::Map<const Eigen::VectorXd>(r, m_).squaredNorm() / 2;
		if (!st_->scaled) {
			Eigen::Map<const Eigen::MatrixXd> J(jac, m_, nfree_);
			double max_norm = J.colwise().norm().maxCoeff();
			*st_->gradient_tolerance = o_.gradient_tolerance / (1 + max_norm);
			st_->first_cost = cost;
			st_->scaled = true;
		}
		*st_->function_tolerance = 2 * (o_.function_tolerance / 100) * cost;
		std::copy(st_->x, st_->x + p_.np, st_->good);
		st_->good_cost = cost;
	}

	const bk_problem &p_;
	const bk_fit_options &o_;
	State *st_;
	bk_residual_cols_fn cols_; /* bk_solve_tiny_cols' callback, or NULL: p_.fn's rows */
	int m_ = 0, nfree_ = 0;
	int free_[kMaxParams];
};

/* The summary's termination and message from TinySolver's status. */
template <class Tiny>
void report(const Tiny &t, const bk_fit_options &o, const State &st, bk_fit_summary *s)
{
	const typename Tiny::Summary &ts = t.summary;
	s->termination = BK_TERM_CONVERGENCE;
	if (ts.status == Tiny::RELATIVE_STEP_SIZE_TOO_SMALL && st.last_trial_nonfinite) {
		s->termination = BK_TERM_NO_CONVERGENCE;
		say(s->message, sizeof s->message, "%s", kEdgeMessage);
		return;
	}
	switch (ts.status) {
	case Tiny::GRADIENT_TOO_SMALL:
		say(s->message, sizeof s->message,
		    "gradient tolerance reached (TinySolver): Jacobi-scaled max |g_j| %.3e < %.3e", ts.gradient_max_norm,
		    t.options.gradient_tolerance);
		break;
	case Tiny::RELATIVE_STEP_SIZE_TOO_SMALL:
		say(s->message, sizeof s->message,
		    "parameter tolerance reached (TinySolver): |step| < %.3e (|x| + %.3e)", o.parameter_tolerance,
		    o.parameter_tolerance);
		break;
	case Tiny::COST_CHANGE_TOO_SMALL:
		say(s->message, sizeof s->message,
		    "function tolerance reached (TinySolver): |cost change| < %.3e cost", o.function_tolerance);
		break;
	case Tiny::COST_TOO_SMALL: /* cost_threshold 0: cannot happen; mapped for completeness */
		say(s->message, sizeof s->message, "cost below threshold (TinySolver): %.3e", ts.final_cost);
		break;
	case Tiny::HIT_MAX_ITERATIONS:
	default:
		s->termination = BK_TERM_NO_CONVERGENCE;
		say(s->message, sizeof s->message, "iteration limit reached (TinySolver): %d iterations",
		    o.max_iterations);
		break;
	}
}

/*
 * The solve proper over N free parameters (N = nfree, or Eigen::Dynamic) and
 * M residuals (M = their count, or Eigen::Dynamic: see kFixedResiduals).
 * With N fixed, TinySolver's vectors, JᵀJ and its LDLT are fixed-size and its
 * Jacobian has N columns known at compile time: the column scaling of each
 * Update (J diag(s)) is a loop per column instead of Eigen's generic
 * coefficient loop, Jᵀr is N dot products instead of a dynamic gemv, and
 * nothing is resized (~5 % more screening fits/s, bench_speed 1b). The same
 * TinySolver (the algorithm is its, unchanged); the sums come in another
 * order, so the last bits of a solve may differ from the dynamic
 * instantiation's, but they are fixed per build: the fixed-size code is
 * Eigen's SSE2 packets at the x86-64 baseline (no -march), JᵀJ goes
 * through Eigen's blocked product with the cache sizes pinned above where M
 * is dynamic and is N² dot products where M is fixed (the threshold at the
 * top of the file), and one solve runs on one thread.
 */
template <int N, int M = Eigen::Dynamic>
void solve_n(const bk_problem &p, const bk_fit_options &o, State *st, bk_fit_summary *s, bool reuse,
             bk_residual_cols_fn cols)
{
	using Tiny = ceres::TinySolver<Residuals<N, M>>;
	Tiny tiny;
	Residuals<N, M> f(p, o, st, reuse, cols);
	int nfree = f.NumParameters();
	tiny.options.max_num_iterations = o.max_iterations + 1;
	tiny.options.parameter_tolerance = o.parameter_tolerance;
	tiny.options.cost_threshold = 0;
	/* set by the functor at the start, before TinySolver's first test */
	tiny.options.function_tolerance = 0;
	tiny.options.gradient_tolerance = 0;
	st->function_tolerance = &tiny.options.function_tolerance;
	st->gradient_tolerance = &tiny.options.gradient_tolerance;
	typename Tiny::Parameters x(nfree);
	for (int k = 0; k < nfree; k++)
		x[k] = st->x[f.free_index(k)];
	tiny.Solve(f, &x);
	for (int k = 0; k < nfree; k++)
		st->x[f.free_index(k)] = x[k];
	s->initial_cost = tiny.summary.initial_cost;
	s->final_cost = tiny.summary.final_cost;
	s->iterations = std::min(tiny.summary.iterations, o.max_iterations);
	report(tiny, o, *st, s);
}

/* Free parameters up to which TinySolver is instantiated with a fixed count
 * (a screening fit has <= 4; more go to the dynamic one). */
constexpr int kMaxFixed = 4;

/*
 * And the residuals' count fixed too where it is 1,024: the screening grids
 * of vf2d, D and two-input forms (32 x 32, fit/search/seeds.c), one block of
 * fit_ctx.c's 1,024. Then every size is known at compile time: J diag(s) is a
 * loop of constant bounds over storage inside the solver (~half the time of
 * the dynamic-row loop, whose pointers are reloaded at every step), Jᵀr a
 * fixed product, and JᵀJ Eigen's coefficient product of fixed sizes (see
 * EIGEN_CACHEFRIENDLY_PRODUCT_THRESHOLD at the top: no packing, no cache
 * size read, so no CPU-dependent split either). The solver then holds its
 * 1,024 x N Jacobian and two residual vectors (~50 KB) on the calling
 * thread's stack (glibc's default 8 MB; nothing here sets a smaller one).
 * ~7 % more screening fits/s than fixed N alone (bench_speed 1b, the older
 * machine), and ~8 % more again from the coefficient product.
 */
constexpr int kFixedResiduals = 1024;

/* The solve proper, validated; throws EvalFailure or std::bad_alloc. */
void solve(const bk_problem &p, const bk_fit_options &o, State *st, bk_fit_summary *s, bool reuse,
           bk_residual_cols_fn cols)
{
	int nfree = 0;
	for (int i = 0; i < p.np; i++)
		nfree += p.constant == nullptr || !p.constant[i];
	if (nfree == 0) { /* every parameter held: the cost where it is */
		Residuals<Eigen::Dynamic> f(p, o, st, reuse, cols);
		Eigen::VectorXd r(f.NumResiduals());
		f(nullptr, r.data(), nullptr);
		s->initial_cost = s->final_cost = r.squaredNorm() / 2;
		s->termination = BK_TERM_CONVERGENCE;
		say(s->message, sizeof s->message, "every parameter is held: nothing to solve");
		return;
	}
	static_assert(kMaxFixed == 4, "one case per fixed count");
	long m = 0;
	for (int b = 0; b < p.nblocks; b++)
		m += p.block_size[b];
#ifndef BK_TINY_DYNAMIC_ONLY
	if (bk_tiny_fixed && m == kFixedResiduals)
		switch (nfree) {
		case 1: solve_n<1, kFixedResiduals>(p, o, st, s, reuse, cols); return;
		case 2: solve_n<2, kFixedResiduals>(p, o, st, s, reuse, cols); return;
		case 3: solve_n<3, kFixedResiduals>(p, o, st, s, reuse, cols); return;
		case 4: solve_n<4, kFixedResiduals>(p, o, st, s, reuse, cols); return;
		default: break;
		}
	switch (bk_tiny_fixed ? nfree : 0) {
	case 1: solve_n<1>(p, o, st, s, reuse, cols); break;
	case 2: solve_n<2>(p, o, st, s, reuse, cols); break;
	case 3: solve_n<3>(p, o, st, s, reuse, cols); break;
	case 4: solve_n<4>(p, o, st, s, reuse, cols); break;
	default: solve_n<Eigen::Dynamic>(p, o, st, s, reuse, cols);
	}
#else
	/* the sanitized kernels runner's object (Makefile, BK_TINY_DYNAMIC_ONLY):
	 * every solve through the one instantiation of run-time sizes, the same
	 * lines as the fixed ones; those eight were three quarters of its compile */
	(void)m;
	solve_n<Eigen::Dynamic>(p, o, st, s, reuse, cols);
#endif
}

} // namespace

int bk_tiny_reuse_trial = 1;
int bk_tiny_fixed = 1;

/* Valid options and what the fast path itself refuses; the rest of the
 * problem (and params) is checked by the solve with bk_solve's messages, so a
 * caller that falls back to bk_solve on 0 gets the same errors either way. */
extern "C" int bk_solve_tiny_applies(const bk_problem *p, const bk_fit_options *o)
{
	if (p == nullptr || p->np < 1 || p->np > kMaxParams || !bk_fit_options_valid(o, nullptr, 0))
		return 0;
	return !refuses(*p, *o, nullptr, 0);
}

namespace {

int solve_tiny(const bk_problem *p, const bk_fit_options *o, double *params, bk_fit_summary *summary, bool reuse,
               bk_residual_cols_fn cols = nullptr)
{
	if (summary == nullptr)
		return -1;
	std::memset(summary, 0, sizeof *summary);
	summary->termination = BK_TERM_FAILURE;
	char *why = summary->message;
	size_t len = sizeof summary->message;
	if (!bk_fit_options_valid(o, why, len) || !bk_problem_valid(p, params, why, len) || refuses(*p, *o, why, len))
		return -1;

	auto t0 = std::chrono::steady_clock::now();
	State st;
	std::copy(params, params + p->np, st.x);
	std::copy(params, params + p->np, st.good);
	try {
		solve(*p, *o, &st, summary, reuse, cols);
		std::copy(st.x, st.x + p->np, params);
	} catch (const EvalFailure &e) {
		/* as bk_solve: FAILURE naming the first failure; the point returned is
		 * the last one whose residuals and Jacobian were evaluated (an accepted
		 * iterate, or the start) */
		summary->termination = BK_TERM_FAILURE;
		say(summary->message, sizeof summary->message, "%s", e.text);
		summary->initial_cost = st.first_cost;
		summary->final_cost = st.good_cost;
		std::copy(st.good, st.good + p->np, params);
	} catch (const std::bad_alloc &) {
		summary->termination = BK_TERM_FAILURE;
		say(summary->message, sizeof summary->message, "out of memory");
	}
	summary->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	return 0;
}

} // namespace

extern "C" int bk_solve_tiny(const bk_problem *p, const bk_fit_options *o, double *params,
                             bk_fit_summary *summary)
{
	return solve_tiny(p, o, params, summary, false);
}

extern "C" int bk_solve_tiny_reusing(const bk_problem *p, const bk_fit_options *o, double *params,
                                     bk_fit_summary *summary)
{
	return solve_tiny(p, o, params, summary, true);
}

extern "C" int bk_solve_tiny_cols(const bk_problem *p, bk_residual_cols_fn cols, const bk_fit_options *o,
                                  double *params, bk_fit_summary *summary)
{
	if (cols == nullptr) {
		if (summary != nullptr) {
			std::memset(summary, 0, sizeof *summary);
			summary->termination = BK_TERM_FAILURE;
			say(summary->message, sizeof summary->message, "cols: no callback");
		}
		return -1;
	}
	return solve_tiny(p, o, params, summary, true, cols);
}
