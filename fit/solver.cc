/*
 * solver.cc — the Ceres bridge behind fit/solver.h, and the project's only C++
 * (every Ceres include lives here: the headers cost seconds to compile).
 *
 * Facts this file relies on (shared/references/toolchain.md, Ceres 2.1 on
 * Debian 12):
 *   - misuse aborts the process (glog CHECK), so bk_solve validates everything
 *     before any Ceres call;
 *   - a ceres::LossFunction applies to a whole residual block, rho(|f|^2); our
 *     blocks hold 100-1000 residuals for speed, so the loss is applied per
 *     residual inside the cost function instead (see robustify);
 *   - with the optimum on an active bound Ceres can stop at a wrong point and
 *     still report CONVERGENCE, so the solve is followed by re-solves with the
 *     active bounds held (see solve_with_bound_guard);
 *   - glog writes to stderr even with logging_type = SILENT, so it is silenced
 *     once per process (quiet_glog);
 *   - a cost function that returns false at a trial point (residuals only,
 *     no Jacobian asked for) makes Ceres reject the step and shrink the trust
 *     region; at the start or at a point it accepts (Jacobian asked for) it
 *     fails the solve. So a trial point where a residual is not finite (a
 *     step into sqrt of a negative, a pole) is a rejected step, as in
 *     tiny.cc: the fit goes on from the accepted point. Ceres may then report
 *     CONVERGENCE at the edge of the region where the form is finite (the
 *     trust region or the step shrank to nothing there): that is reported as
 *     NO_CONVERGENCE, with bridge.h's message (AbortOnFailure::at_edge). Any callback
 *     failure, and any non-finite value where a Jacobian is asked for,
 *     aborts the solve and is reported as FAILURE.
 */
#include "solver.h"
#include "bridge.h"
#include "brdf.h" /* bk_dlog1p */

#include <ceres/ceres.h>
#include <glog/logging.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>
#include <vector>

namespace {

using bk_bridge::say;
using bk_bridge::enum_value;
using bk_bridge::kEdgeMessage;

constexpr int kMaxParams = 16;
constexpr int kMaxIterations = 100000;
constexpr int kMaxThreads = 64;

/* A coordinate "sits on" a bound b when it is within 1e-12 max(1, |b|) of it:
 * relative for large bounds, absolute near 0 where a relative test would ask for
 * exact equality. Ceres projects steps onto the box, so an active coordinate
 * normally equals its bound exactly; the slack only absorbs rounding. */
constexpr double kOnBound = 1e-12;

bool positive_finite(double x) { return std::isfinite(x) && x > 0; }

/* ---- glog ---------------------------------------------------------------------- */

/* Ceres logs through glog, which writes to stderr before InitGoogleLogging and
 * regardless of Solver::Options::logging_type. brdfkit never logs through glog
 * itself, so raising the process-wide threshold to FATAL is safe; it is done once
 * (InitGoogleLogging would abort if a host program had already called it). */
void quiet_glog()
{
	static std::once_flag once;
	std::call_once(once, [] { FLAGS_minloglevel = google::GLOG_FATAL; });
}

/* ---- robust loss, per residual -------------------------------------------------- */

/* rho(r^2) and rho'(r^2) of solver.h's losses, c the scale; computed from r so
 * that Huber needs no square root of a square. SoftL1 uses
 * 2c^2(sqrt(1 + u) - 1) = 2 r^2 / (sqrt(1 + u) + 1), u = (r/c)^2, which does not
 * cancel for small u. */
struct LossValue {
	double rho, drho;
};
using LossFn = LossValue (*)(double r, double c);

LossValue huber(double r, double c)
{
	double a = std::fabs(r);
	if (a <= c)
		return {r * r, 1.0};
	return {2 * c * a - c * c, c / a};
}

LossValue cauchy(double r, double c)
{
	double u = (r / c) * (r / c);
	/* brdfkit's log1p: glibc's has an FMA variant that differs in the last
	 * bit (brdf/dmath.c), and a robust fit's path would follow it */
	return {c * c * bk_dlog1p(u), 1 / (1 + u)};
}

LossValue softl1(double r, double c)
{
	double u = (r / c) * (r / c);
	double q = std::sqrt(1 + u);
	return {2 * r * r / (q + 1), 1 / q};
}

/* Indexed by bk_loss; BK_LOSS_NONE leaves residuals as they are. */
const LossFn kLoss[] = {nullptr, huber, cauchy, softl1};
constexpr int kNumLosses = sizeof kLoss / sizeof kLoss[0];

/* Ceres minimises 1/2 sum s_i^2. Replacing each residual r by
 *     s(r) = sign(r) sqrt(rho(r^2))
 * makes that 1/2 sum rho(r_i^2) exactly, per residual, whatever the block size.
 * Its derivative is
 *     ds/dtheta = rho'(r^2) |r| / sqrt(rho(r^2)) dr/dtheta,
 * whose limit at r = 0 is dr/dtheta since rho(s) ~ s there (rho'(0) = 1 for all
 * three losses). The gradient, sum s ds/dtheta = sum rho'(r^2) r dr/dtheta, is
 * the exact gradient of the robust objective, so the minimiser and the final
 * cost are those of per-residual robust loss; only the Gauss-Newton curvature
 * model differs from Ceres' own (Triggs-corrected) one, which changes the path,
 * not the answer. Where rho'(r^2) rounds to 1, rho(r^2) = r^2 to double
 * precision (the Huber core; tiny r for the others) and s = r is kept exactly. */
void robustify(LossFn loss, double c, int m, int np, double *r, double *jac)
{
	for (int i = 0; i < m; i++) {
		LossValue v = loss(r[i], c);
		if (v.drho == 1.0)
			continue;
		double root = std::sqrt(v.rho); /* > 0: rho'(r^2) != 1 implies r != 0 */
		double k = v.drho * std::fabs(r[i]) / root;
		r[i] = std::copysign(root, r[i]);
		if (jac != nullptr)
			for (int j = 0; j < np; j++)
				jac[i * np + j] *= k;
	}
}

/* ---- the cost function ---------------------------------------------------------- */

/* The first failure of any evaluation (callback error or non-finite value);
 * evaluations may run on several threads. */
class FailureRecord {
public:
	bool is_set() const { return set_.load(std::memory_order_acquire); }
	const char *text() const { return text_; }

	/* a trial point rejected for a non-finite residual (no failure) */
	void note_trial() { trials_.fetch_add(1, std::memory_order_relaxed); }
	long trials() const { return trials_.load(std::memory_order_relaxed); }

	void note(const char *fmt, ...) __attribute__((format(printf, 2, 3)))
	{
		std::lock_guard<std::mutex> lock(mutex_);
		if (set_.load(std::memory_order_relaxed))
			return;
		va_list ap;
		va_start(ap, fmt);
		vsnprintf(text_, sizeof text_, fmt, ap);
		va_end(ap);
		set_.store(true, std::memory_order_release);
	}

private:
	std::atomic<bool> set_{false};
	std::atomic<long> trials_{0};
	std::mutex mutex_;
	char text_[160] = "";
};

/* One residual block: the C callback over block `block`, one parameter block of
 * np doubles. The callback's row-major Jacobian is Ceres' layout, so it writes
 * straight into Ceres' buffer. */
class BlockCost final : public ceres::CostFunction {
public:
	BlockCost(const bk_problem &p, int block, LossFn loss, double c, FailureRecord *fail)
	    : p_(p), block_(block), loss_(loss), c_(c), fail_(fail)
	{
		set_num_residuals(p.block_size[block]);
		mutable_parameter_block_sizes()->push_back(p.np);
	}

	bool Evaluate(double const *const *params, double *r, double **jacobians) const override
	{
		double *jac = jacobians != nullptr ? jacobians[0] : nullptr;
		int m = num_residuals(), np = p_.np;
		int rc = p_.fn(p_.ctx, block_, params[0], r, jac);
		if (rc != 0) {
			fail_->note("callback failed: block %d returned %d", block_, rc);
			return false;
		}
		if (loss_ != nullptr)
			robustify(loss_, c_, m, np, r, jac);
		for (int i = 0; i < m; i++)
			if (!std::isfinite(r[i])) {
				if (jac == nullptr) /* a trial point: the step is rejected (see the header) */
					fail_->note_trial();
				else
					fail_->note("non-finite residual: block %d, residual %d", block_, i);
				return false;
			}
		for (int k = 0; jac != nullptr && k < m * np; k++)
			if (!std::isfinite(jac[k])) {
				fail_->note("non-finite jacobian: block %d, residual %d, parameter %d", block_,
				            k / np, k % np);
				return false;
			}
		return true;
	}

private:
	const bk_problem &p_;
	int block_;
	LossFn loss_;
	double c_;
	FailureRecord *fail_;
};

/* Stops Ceres at the end of the iteration in which an evaluation failed
 * (termination USER_FAILURE, parameters not updated), and watches whether
 * the solve's last steps were rejected for non-finite residuals: at_edge()
 * after a solve, when the last iteration Ceres reported was such a step or a
 * trial was rejected after it (Ceres stops on a tolerance inside an
 * iteration, before its callbacks). */
class AbortOnFailure final : public ceres::IterationCallback {
public:
	explicit AbortOnFailure(const FailureRecord *fail) : fail_(fail) {}
	ceres::CallbackReturnType operator()(const ceres::IterationSummary &it) override
	{
		long t = fail_->trials();
		last_rejected_ = t != seen_ && !it.step_is_successful;
		seen_ = t;
		return fail_->is_set() ? ceres::SOLVER_ABORT : ceres::SOLVER_CONTINUE;
	}
	void start() { seen_ = fail_->trials(), last_rejected_ = false; }
	bool at_edge() const { return last_rejected_ || fail_->trials() != seen_; }

private:
	const FailureRecord *fail_;
	long seen_ = 0;
	bool last_rejected_ = false;
};

/* ---- validation ----------------------------------------------------------------- */

int validate_problem(const bk_problem *p, const double *x, char *why, size_t len)
{
	if (p == nullptr)
		return say(why, len, "problem is NULL"), 0;
	if (x == nullptr)
		return say(why, len, "params is NULL"), 0;
	if (p->np < 1 || p->np > kMaxParams)
		return say(why, len, "np: must be in 1..%d, got %d", kMaxParams, p->np), 0;
	if (p->nblocks < 1)
		return say(why, len, "nblocks: must be >= 1, got %d", p->nblocks), 0;
	if (p->block_size == nullptr)
		return say(why, len, "block_size is NULL"), 0;
	long long total = 0;
	for (int b = 0; b < p->nblocks; b++) {
		if (p->block_size[b] < 1)
			return say(why, len, "block_size[%d]: must be >= 1, got %d", b, p->block_size[b]), 0;
		total += p->block_size[b];
	}
	if (total > INT_MAX) /* Ceres counts residuals in an int */
		return say(why, len, "block_size: %lld residuals in all, more than %d", total, INT_MAX), 0;
	if (p->fn == nullptr)
		return say(why, len, "fn is NULL"), 0;
	for (int i = 0; i < p->np; i++) {
		double lo = p->lower != nullptr ? p->lower[i] : -HUGE_VAL;
		double hi = p->upper != nullptr ? p->upper[i] : HUGE_VAL;
		if (std::isnan(lo))
			return say(why, len, "lower[%d]: must not be NaN", i), 0;
		if (std::isnan(hi))
			return say(why, len, "upper[%d]: must not be NaN", i), 0;
		if (lo > hi)
			return say(why, len, "bounds[%d]: lower %.17g > upper %.17g", i, lo, hi), 0;
		if (!std::isfinite(x[i]))
			return say(why, len, "params[%d]: must be finite, got %g", i, x[i]), 0;
		if (x[i] < lo || x[i] > hi)
			return say(why, len, "params[%d]: %.17g outside its bounds [%.17g, %.17g]", i, x[i], lo,
			           hi),
			       0;
		if (p->constant != nullptr && p->constant[i] != 0 && p->constant[i] != 1)
			return say(why, len, "constant[%d]: must be 0 or 1, got %d", i, p->constant[i]), 0;
	}
	return 1;
}

/* ---- solving -------------------------------------------------------------------- */

/* Where each coordinate stands: held by the caller (constant flag, or
 * lower == upper), held on a bound by the guard, or free. */
enum Hold { FREE, HELD_BY_CALLER, HELD_ON_LOWER, HELD_ON_UPPER };

class Fit {
public:
	Fit(const bk_problem &p, const bk_fit_options &o) : p_(p), o_(o), abort_(&fail_)
	{
		int loss = enum_value(&o.loss);
		for (int b = 0; b < p.nblocks; b++)
			costs_.emplace_back(new BlockCost(p, b, kLoss[loss], o.loss_scale, &fail_));
		for (int i = 0; i < p.np; i++) {
			lo_[i] = p.lower != nullptr ? p.lower[i] : -HUGE_VAL;
			hi_[i] = p.upper != nullptr ? p.upper[i] : HUGE_VAL;
			bool fixed = (p.constant != nullptr && p.constant[i]) || lo_[i] == hi_[i];
			hold_[i] = fixed ? HELD_BY_CALLER : FREE;
		}
	}

	const FailureRecord &failure() const { return fail_; }

	/* One Ceres solve from x (updated in place) with the current holds. */
	ceres::Solver::Summary solve_once(double *x)
	{
		ceres::Problem::Options po;
		po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP; /* reused across solves */
		ceres::Problem problem(po);
		for (auto &cost : costs_)
			problem.AddResidualBlock(cost.get(), nullptr, x);
		std::vector<int> held;
		for (int i = 0; i < p_.np; i++) {
			/* Ceres calls lower == upper an infeasible bound (FAILURE): such a
			 * coordinate is held instead, and its bounds are left out. */
			bool pinned = lo_[i] == hi_[i];
			if (std::isfinite(lo_[i]) && !pinned)
				problem.SetParameterLowerBound(x, i, lo_[i]);
			if (std::isfinite(hi_[i]) && !pinned)
				problem.SetParameterUpperBound(x, i, hi_[i]);
			if (hold_[i] != FREE)
				held.push_back(i);
		}
		if ((int)held.size() == p_.np)
			problem.SetParameterBlockConstant(x); /* Ceres' way to hold a whole block */
		else if (!held.empty())
			problem.SetManifold(x, new ceres::SubsetManifold(p_.np, held));

		ceres::Solver::Options so;
		so.trust_region_strategy_type = enum_value(&o_.trust_region) == BK_TR_DOGLEG
		                                        ? ceres::DOGLEG
		                                        : ceres::LEVENBERG_MARQUARDT;
		/* At most 16 parameters against up to ~10^6 residuals: forming JᵀJ
		 * (m p² flops, no copy of J) beats QR of J (2 m p² and a copy); 2.2x
		 * faster on Karis's 11-parameter env fit (make bench). The squared
		 * condition number is harmless here: LM adds λD to JᵀJ, which keeps it
		 * positive definite even when parameters are not identifiable. */
		so.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
		/* Ceres tests the function and parameter tolerances on a candidate step
		 * and stops WITHOUT taking it, so with a non-zero optimal cost C the
		 * answer is as close as a step that changes C by function_tolerance·C. */
		so.max_num_iterations = o_.max_iterations;
		/* ... so ask Ceres for 1/100 of the tolerance: the step it then declines
		 * changes the cost by at most ftol/100, and the point returned is at
		 * least as converged as MINPACK's (which takes its last step, then
		 * tests). About one more iteration; measured in make bench. */
		so.function_tolerance = o_.function_tolerance / 100.0;
		so.gradient_tolerance = o_.gradient_tolerance;
		so.parameter_tolerance = o_.parameter_tolerance;
		so.num_threads = o_.num_threads;
		so.logging_type = ceres::SILENT;
		so.minimizer_progress_to_stdout = false;
		so.callbacks.push_back(&abort_);
		ceres::Solver::Summary s;
		abort_.start();
		ceres::Solve(so, &problem, &s);
		if (s.termination_type == ceres::CONVERGENCE && abort_.at_edge()) {
			s.termination_type = ceres::NO_CONVERGENCE;
			s.message = kEdgeMessage;
		}
		return s;
	}

	/* Holds every free coordinate that sits on a bound, snapping it onto the
	 * bound; returns how many were newly held. */
	int hold_active(double *x)
	{
		int added = 0;
		for (int i = 0; i < p_.np; i++) {
			if (hold_[i] != FREE)
				continue;
			if (std::isfinite(lo_[i]) && x[i] - lo_[i] <= kOnBound * std::fmax(1, std::fabs(lo_[i])))
				hold_[i] = HELD_ON_LOWER, x[i] = lo_[i], added++;
			else if (std::isfinite(hi_[i]) && hi_[i] - x[i] <= kOnBound * std::fmax(1, std::fabs(hi_[i])))
				hold_[i] = HELD_ON_UPPER, x[i] = hi_[i], added++;
		}
		return added;
	}

	/* Frees every coordinate held on a bound whose descent direction -g points
	 * into the box by more than the gradient tolerance (the KKT sign condition
	 * fails there); returns how many, or -1 if the gradient could not be had. */
	int release_inward(const double *x)
	{
		double g[kMaxParams];
		if (!gradient(x, g))
			return -1;
		int released = 0;
		for (int i = 0; i < p_.np; i++) {
			bool inward = (hold_[i] == HELD_ON_LOWER && g[i] < -o_.gradient_tolerance) ||
			              (hold_[i] == HELD_ON_UPPER && g[i] > o_.gradient_tolerance);
			if (inward)
				hold_[i] = FREE, released++;
		}
		return released;
	}

private:
	/* g = sum over blocks of J_s^T s: the gradient of 1/2 sum rho(r_i^2). */
	bool gradient(const double *x, double *g)
	{
		int np = p_.np, m_max = 0;
		for (int b = 0; b < p_.nblocks; b++)
			m_max = std::max(m_max, p_.block_size[b]);
		std::vector<double> r(m_max), jac((size_t)m_max * np);
		double *jacs[1] = {jac.data()};
		const double *params[1] = {x};
		std::fill(g, g + np, 0.0);
		for (int b = 0; b < p_.nblocks; b++) {
			if (!costs_[b]->Evaluate(params, r.data(), jacs))
				return false;
			for (int i = 0; i < p_.block_size[b]; i++)
				for (int j = 0; j < np; j++)
					g[j] += jac[(size_t)i * np + j] * r[i];
		}
		return true;
	}

	const bk_problem &p_;
	const bk_fit_options &o_;
	std::vector<std::unique_ptr<BlockCost>> costs_;
	FailureRecord fail_;
	AbortOnFailure abort_;
	double lo_[kMaxParams], hi_[kMaxParams];
	Hold hold_[kMaxParams];
};

bk_termination termination_of(ceres::TerminationType t)
{
	switch (t) {
	case ceres::CONVERGENCE:
	case ceres::USER_SUCCESS:
		return BK_TERM_CONVERGENCE;
	case ceres::NO_CONVERGENCE:
		return BK_TERM_NO_CONVERGENCE;
	default: /* FAILURE, USER_FAILURE (our abort on a failed evaluation) */
		return BK_TERM_FAILURE;
	}
}

void add_solve(bk_fit_summary *s, const ceres::Solver::Summary &c)
{
	s->termination = termination_of(c.termination_type);
	say(s->message, sizeof s->message, "%s", c.message.c_str());
	s->final_cost = c.final_cost;
	/* Ceres counts iteration 0 (the start) as a successful step; the number of
	 * the last iteration is the count that max_num_iterations bounds. */
	s->iterations += std::max(0, c.num_successful_steps + c.num_unsuccessful_steps - 1);
}

/* The bounds guard. Ceres 2.1 handles bounds by projecting each trust-region
 * step onto the box (a projected line search along it, in the trust-region
 * minimiser); with the optimum on a bound and the free coordinates
 * coupled to the bounded one, the projected steps can stop making progress and
 * Ceres reports CONVERGENCE at a point that is not a constrained minimum
 * (upstream issues #187, #1056). On a box the constrained minimum is the
 * unconstrained minimum over the free coordinates with the active ones held on
 * their bounds, which Ceres solves without projection. So:
 *   1. solve;
 *   2. while that converged and some free coordinate sits on a bound: hold every
 *      such coordinate on its bound (SubsetManifold) and solve again from there.
 *      The held set only grows, so this ends after at most np re-solves (the
 *      loop stops at np + 1 in any case);
 *   3. check the KKT sign condition of the held coordinates: on a lower bound
 *      the gradient must be >= 0, on an upper bound <= 0 (the descent direction
 *      leaves the box). A coordinate whose gradient points inward was held
 *      wrongly (Ceres reached its bound on the way, not at the optimum): release
 *      it and solve once more, still holding the others.
 * Every re-solve counts in bound_resolves; the guard runs only after
 * CONVERGENCE, since a solve that ran out of iterations is not at an optimum
 * anyway. */
void solve_with_bound_guard(Fit &fit, int np, double *x, bk_fit_summary *s)
{
	ceres::Solver::Summary c = fit.solve_once(x);
	s->initial_cost = c.initial_cost;
	add_solve(s, c);
	for (int round = 0; round <= np && s->termination == BK_TERM_CONVERGENCE; round++) {
		if (fit.hold_active(x) == 0)
			break;
		add_solve(s, fit.solve_once(x));
		s->bound_resolves++;
	}
	if (s->bound_resolves == 0 || s->termination != BK_TERM_CONVERGENCE)
		return;
	int released = fit.release_inward(x);
	if (released > 0) {
		add_solve(s, fit.solve_once(x));
		s->bound_resolves++;
	}
}

} // namespace

extern "C" int bk_fit_options_valid(const bk_fit_options *o, char *why, size_t len)
{
	if (o == nullptr)
		return say(why, len, "options are NULL"), 0;
	int tr = enum_value(&o->trust_region), loss = enum_value(&o->loss);
	if (tr != BK_TR_LEVENBERG_MARQUARDT && tr != BK_TR_DOGLEG)
		return say(why, len, "trust_region: must be LEVENBERG_MARQUARDT or DOGLEG, got %d", tr), 0;
	if (loss < 0 || loss >= kNumLosses)
		return say(why, len, "loss: must be NONE, HUBER, CAUCHY or SOFTL1, got %d", loss), 0;
	if (!positive_finite(o->loss_scale))
		return say(why, len, "loss_scale: must be finite and > 0, got %g", o->loss_scale), 0;
	if (o->max_iterations < 1 || o->max_iterations > kMaxIterations)
		return say(why, len, "max_iterations: must be in 1..%d, got %d", kMaxIterations,
		           o->max_iterations),
		       0;
	if (!positive_finite(o->function_tolerance))
		return say(why, len, "function_tolerance: must be finite and > 0, got %g",
		           o->function_tolerance),
		       0;
	if (!positive_finite(o->gradient_tolerance))
		return say(why, len, "gradient_tolerance: must be finite and > 0, got %g",
		           o->gradient_tolerance),
		       0;
	if (!positive_finite(o->parameter_tolerance))
		return say(why, len, "parameter_tolerance: must be finite and > 0, got %g",
		           o->parameter_tolerance),
		       0;
	if (o->num_threads < 1 || o->num_threads > kMaxThreads)
		return say(why, len, "num_threads: must be in 1..%d, got %d", kMaxThreads, o->num_threads), 0;
	return 1;
}

extern "C" int bk_problem_valid(const bk_problem *p, const double *params, char *why, size_t len)
{
	return validate_problem(p, params, why, len);
}

extern "C" int bk_solve(const bk_problem *p, const bk_fit_options *o, double *params,
                        bk_fit_summary *summary)
{
	if (summary == nullptr)
		return -1;
	std::memset(summary, 0, sizeof *summary);
	summary->termination = BK_TERM_FAILURE;
	if (!bk_fit_options_valid(o, summary->message, sizeof summary->message) ||
	    !validate_problem(p, params, summary->message, sizeof summary->message))
		return -1;

	quiet_glog();
	auto t0 = std::chrono::steady_clock::now();
	double x[kMaxParams];
	std::copy(params, params + p->np, x);
	Fit fit(*p, *o);
	solve_with_bound_guard(fit, p->np, x, summary);
	if (fit.failure().is_set()) {
		summary->termination = BK_TERM_FAILURE;
		say(summary->message, sizeof summary->message, "%s", fit.failure().text());
	}
	std::copy(x, x + p->np, params);
	summary->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	return 0;
}
