/*
 * fit.c — the fitter: several deterministic starts of the Ceres problem that
 * fit_ctx.c builds from the formula IR's residuals; Lawson's minimax; rounding
 * constants to shader literals. Statistics are in fit_stats.c. Calls run one
 * way: fit.c -> fit_stats.c -> fit_ctx.c.
 */
#include "fit.h"
#include "fit_int.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Start k > 0: each parameter moved by up to ±50 % of its size (at least 0.1),
 * from a fixed LCG seeded by (seed, k): the same command gives the same starts. */
static void start_point(const bk_fit_spec *spec, int k, double *p)
{
	unsigned long long st = (unsigned long long)spec->seed * 0x9E3779B97F4A7C15ull + (unsigned long long)k;
	for (int j = 0; j < spec->np; j++) {
		p[j] = spec->start[j];
		if (k == 0 || spec->hold[j])
			continue;
		st = st * 6364136223846793005ull + 1442695040888963407ull;
		double u = (double)(st >> 11) * 0x1p-53 * 2.0 - 1.0;
		p[j] += 0.5 * u * fmax(fabs(p[j]), 0.1);
		p[j] = fmin(fmax(p[j], spec->lower[j]), spec->upper[j]);
	}
}

/* A start fails when the solver does, or ends at a cost that is not finite
 * (residuals near 1e154 or more, whose squares overflow: p0 = 1e308): there
 * is no point to compare. A failed first start stays a note; when every
 * start fails, the message names the first failure. */
static int multi_start(bk_fit_ctx *c, const bk_fit_callbacks *cb, bk_fit_result *res)
{
	const bk_fit_spec *spec = c->spec;
	double best = INFINITY;
	char first[400] = "";
	res->start_cost_min = INFINITY;
	res->start_cost_max = -INFINITY;
	for (int k = 0; k < spec->starts; k++) {
		double p[BK_MAX_PARAMS] = {0};
		bk_fit_summary sum;
		start_point(spec, k, p);
		int failed = bk_fit_solve(c, p, spec->hold, &sum) || sum.termination == BK_TERM_FAILURE;
		if (!failed && !isfinite(sum.final_cost)) {
			snprintf(sum.message, sizeof sum.message, "the cost is %g: the squared residuals overflow "
			         "double", sum.final_cost);
			failed = 1;
		}
		res->starts_run = k + 1;
		/* the program hears every start, failed ones too; a stop ends the
		 * loop once this start is counted below */
		int stop = cb && cb->progress && cb->progress(cb->ctx, k, spec->starts, &sum);
		if (failed) {
			if (!res->starts_failed++)
				snprintf(first, sizeof first, "start %d of %d: %s", k + 1, spec->starts,
				         sum.message[0] ? sum.message : "the solver gave no reason");
			if (k == 0)
				snprintf(res->message, sizeof res->message, "%s", sum.message);
		} else {
			res->start_cost_min = fmin(res->start_cost_min, sum.final_cost);
			res->start_cost_max = fmax(res->start_cost_max, sum.final_cost);
			if (!isfinite(best) || sum.final_cost < best * (1.0 - BK_FIT_COST_TIE)) {
				best = sum.final_cost;
				memcpy(res->p, p, sizeof p);
				res->summary = sum;
			}
		}
		if (stop)
			break;
	}
	if (!isfinite(best)) {
		snprintf(res->message, sizeof res->message, "every start failed; the first, %s", first);
		return -1;
	}
	return 0;
}

/* ---- honest convergence (fit.h: BK_FIT_GRAD_TOL, BK_FIT_COND_MAX) ------------------ */

/* Appends "; text" (or text) to res->message. */
static void note(bk_fit_result *res, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void note(bk_fit_result *res, const char *fmt, ...)
{
	size_t k = strlen(res->message);
	if (k + 3 >= sizeof res->message)
		return;
	if (k)
		k += (size_t)snprintf(res->message + k, sizeof res->message - k, "; ");
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(res->message + k, sizeof res->message - k, fmt, ap);
	va_end(ap);
}

/* Extra solves from a point that fails the optimality check although Ceres
 * reported CONVERGENCE. A fresh solve restarts Ceres' trust region, which is
 * what a stop on a damped step too short to change the cost needs (the common
 * wrong stop); a point that is still not a minimum after two is reported as
 * such rather than chased further. The polish solves see the residuals
 * multiplied by 1/||ŷ|| (the weighted target scaled to unit norm): the
 * minimiser is the same, but Ceres' gradient_tolerance, an absolute bound on
 * max |g_j|, then no longer stops at once on data of small magnitude (y ~ 1e-8
 * gives a cost ~ 1e-16 and gradients below 1e-12 anywhere). Not with a robust
 * loss, whose scale c is in the residuals' units. */
#define POLISH 2

/* ||ŷ||: the target as the residuals weight it */
static double target_norm(const bk_fit_ctx *c)
{
	const bk_samples *s = c->spec->s;
	double t = 0;
	for (size_t i = 0; i < s->n; i++) {
		double v = c->sw[i] * c->inv[i] * s->y[i];
		t += v * v;
	}
	return sqrt(t);
}

/* The no-step rule: a solve that reported CONVERGENCE without lowering the
 * cost took no step, so its stop says nothing about the point; it is a
 * minimum only if the point passes the optimality check by itself. A point
 * where the check fails, the gradient or the residuals are not finite
 * (worst = -2), or the cost is flat in a free parameter (a zero Jacobian
 * column: an overflowed or saturated start such as p0 = 1e308, where a zero
 * gradient is a plateau, not a minimum) is reported NO_CONVERGENCE with the
 * reason. Returns 1 if it did so and there is no gradient to name (the
 * caller names a failing one). */
static int no_step(bk_fit_result *res, int worst, int flat)
{
	bk_fit_summary *sm = &res->summary;
	if (sm->termination != BK_TERM_CONVERGENCE || sm->final_cost < sm->initial_cost || (worst == -1 && !flat))
		return 0;
	char why[200];
	if (worst == -2)
		snprintf(why, sizeof why, "the residuals are not finite there");
	else if (worst >= 0 && !isfinite(res->grad[worst]))
		snprintf(why, sizeof why, "the gradient in p%d is not finite there", worst);
	else if (worst >= 0)
		snprintf(why, sizeof why, "p%d has relative gradient %.3g > %g there", worst, res->grad_rel[worst],
		         BK_FIT_GRAD_TOL);
	else
		snprintf(why, sizeof why, "the cost is flat in %d free parameter%s there (a zero Jacobian column: a "
		         "plateau, not a minimum)", flat, flat > 1 ? "s" : "");
	sm->termination = BK_TERM_NO_CONVERGENCE;
	snprintf(sm->message, sizeof sm->message, "no step taken from a point that is not a minimum: %s", why);
	if (worst < 0)
		note(res, "%s", sm->message); /* else check_optimality names the gradients */
	return worst < 0;
}

/* Checks first-order optimality at res->p (the weights in c->sw, held[]
 * fixed); with polish, re-solves as above. A point that fails is reported
 * NO_CONVERGENCE whatever Ceres said, and the message names the parameters
 * whose gradient is not small. */
static void check_optimality(bk_fit_ctx *c, bk_fit_result *res, const int *held, int polish)
{
	const bk_samples *s = c->spec->s;
	int flat = 0;
	int worst = bk_fit_optimality(c, res->p, held, res, &flat);
	char first[sizeof res->summary.message];
	memcpy(first, res->summary.message, sizeof first);
	if (polish && worst >= 0 && res->summary.termination == BK_TERM_CONVERGENCE) {
		double norm = target_norm(c), k2 = 1.0;
		if (c->spec->opt.loss == BK_LOSS_NONE && norm > 0 && isfinite(1 / norm)) {
			for (size_t i = 0; i < s->n; i++)
				c->sw[i] /= norm;
			k2 = 1 / (norm * norm); /* costs of the polish solves are k2 times the fit's */
		}
		for (int k = 0; k < POLISH && worst >= 0 && res->summary.termination == BK_TERM_CONVERGENCE; k++) {
			double p[BK_MAX_PARAMS];
			bk_fit_summary sum;
			memcpy(p, res->p, sizeof p);
			if (bk_fit_solve(c, p, held, &sum) || sum.termination == BK_TERM_FAILURE)
				break;
			res->polish_solves++;
			res->summary.iterations += sum.iterations;
			res->summary.bound_resolves += sum.bound_resolves;
			res->summary.seconds += sum.seconds;
			if (!(sum.final_cost / k2 <= res->summary.final_cost * (1 + 1e-12)))
				break; /* Ceres never returns a worse point; a guard (and the rounding of k2) */
			int moved = memcmp(p, res->p, sizeof p) != 0;
			memcpy(res->p, p, sizeof p);
			res->summary.final_cost = sum.final_cost / k2;
			res->summary.termination = sum.termination;
			memcpy(res->summary.message, sum.message, sizeof sum.message);
			worst = bk_fit_optimality(c, res->p, held, res, NULL); /* scale-free: same with sw scaled */
			if (!moved)
				break; /* the same solve again would stop at the same place */
		}
		if (k2 != 1.0)
			for (size_t i = 0; i < s->n; i++)
				c->sw[i] *= norm;
		worst = bk_fit_optimality(c, res->p, held, res, &flat);
	}
	if (no_step(res, worst, flat))
		return; /* not a minimum, and nothing to name (else it goes on below) */
	if (worst == -1 && res->polish_solves)
		note(res, "converged after %d re-solve%s from a point that was not a minimum (the solver had stopped with: "
		     "%.120s)", res->polish_solves, res->polish_solves > 1 ? "s" : "", first);
	if (worst < 0)
		return; /* optimal, or not evaluated (optimal = -1) */
	char list[320];
	size_t k = 0;
	list[0] = '\0';
	for (int j = 0; j < c->spec->np && k < sizeof list; j++)
		if (res->grad_rel[j] > BK_FIT_GRAD_TOL)
			k += (size_t)snprintf(list + k, sizeof list - k, "%s|∂cost/∂p%d| = %.3g, relative %.3g", k ? "; " : "",
			                      j, fabs(res->grad[j]), res->grad_rel[j]);
	note(res, "stopped at a point that is not a minimum (relative gradient > %g): %s (solver: %.120s)",
	     BK_FIT_GRAD_TOL, list, res->summary.message);
	if (res->summary.termination != BK_TERM_CONVERGENCE)
		return; /* the solver says so itself (iteration limit) */
	res->summary.termination = BK_TERM_NO_CONVERGENCE;
	snprintf(res->summary.message, sizeof res->summary.message,
	         "not a minimum: p%d has relative gradient %.3g > %g although the solver reported convergence", worst,
	         res->grad_rel[worst], BK_FIT_GRAD_TOL);
}

/* Names the parameters hold_unidentified held; they count as not identifiable
 * (unidentified[]), with no standard error (held: not fitted). */
static void note_held(bk_fit_result *res, int np)
{
	char list[160] = "";
	size_t k = 0;
	for (int j = 0; j < np; j++)
		if (res->held[j] && k < sizeof list) {
			res->unidentified[j] = res->collinear[j] = 1;
			k += (size_t)snprintf(list + k, sizeof list - k, "%sp%d", k ? ", " : "", j);
		}
	if (k)
		note(res, "not identifiable, held at the start value%s so that the answer is unique: %s", strchr(list, ',') ? "s" : "", list);
}

/* Names ill-conditioning (condition above BK_FIT_COND_MAX) in the message. */
static void note_conditioning(bk_fit_result *res, int np)
{
	if (!(res->condition > BK_FIT_COND_MAX))
		return;
	char weak[160] = "", none[160] = "";
	size_t kw = 0, kn = 0;
	for (int j = 0; j < np; j++) {
		if (res->collinear[j] && kw < sizeof weak)
			kw += (size_t)snprintf(weak + kw, sizeof weak - kw, "%sp%d", kw ? ", " : "", j);
		if (res->unidentified[j] && kn < sizeof none)
			kn += (size_t)snprintf(none + kn, sizeof none - kn, "%sp%d", kn ? ", " : "", j);
	}
	note(res, "ill-conditioned: cond(JᵀJ) = %.3g with unit-norm columns (> %g); nearly collinear: %s%s%s",
	     res->condition, BK_FIT_COND_MAX, kw ? weak : "none named", kn ? "; not identifiable: " : "", none);
}

/* A valley of exact minima (a null space of J: parameters the data do not
 * pin) leaves the point returned to the path the solver took, which 1-ulp
 * differences of libm (glibc picks FMA or non-FMA exp/log/pow at run time)
 * change: the printed constants moved in their first digit between machines.
 * So the valley is cut: free parameters are tried in index order, and each
 * whose holding lowers the null space's dimension is held at its start value
 * (the catalog's published constant, or --p0); the rest are re-solved, and are
 * then pinned by the data. Only the dimension is used, not the null vectors'
 * loadings: a null space of dimension k > 1 has no unique basis, its dimension
 * does. Holding a parameter that does not load on the null space leaves the
 * dimension as it is, so only parameters of the valley are held; one loading
 * on a direction whose eigenvalue sits near the threshold (NULL_RATIO) could
 * flip, which structural null spaces (eigenvalues ~1e-29) never do. */
static int hold_unidentified(bk_fit_ctx *c, bk_fit_spec *fs, bk_fit_result *res)
{
	int nnull = bk_fit_stderr(c, res);
	if (nnull <= 0)
		return 0;
	for (int j = 0; j < fs->np && nnull > 0; j++) {
		if (fs->hold[j] || fs->lower[j] == fs->upper[j])
			continue;
		fs->hold[j] = 1;
		int k = bk_fit_stderr(c, res);
		if (k >= 0 && k < nnull) {
			res->held[j] = 1;
			nnull = k;
		} else {
			fs->hold[j] = 0;
		}
	}
	int any = 0;
	for (int j = 0; j < fs->np; j++)
		any |= res->held[j];
	if (!any)
		return 0; /* J could not be evaluated: the report names the parameters */
	double p[BK_MAX_PARAMS];
	memcpy(p, res->p, sizeof p);
	for (int j = 0; j < fs->np; j++)
		if (res->held[j])
			p[j] = fs->start[j];
	bk_fit_summary sum;
	if (bk_fit_solve(c, p, fs->hold, &sum) || sum.termination == BK_TERM_FAILURE) {
		/* keep the valley point; name the parameters, the answer is not unique */
		for (int j = 0; j < fs->np; j++)
			fs->hold[j] &= !res->held[j], res->held[j] = 0;
		note(res, "holding the parameters that are not identifiable failed (%.120s)", sum.message);
		return 0;
	}
	memcpy(res->p, p, sizeof p);
	res->summary.iterations += sum.iterations;
	res->summary.bound_resolves += sum.bound_resolves;
	res->summary.seconds += sum.seconds;
	res->summary.final_cost = sum.final_cost;
	res->summary.termination = sum.termination;
	memcpy(res->summary.message, sum.message, sizeof sum.message);
	return 1;
}

/* Lawson 1961 (as in Rice & Usow 1968): weights u_i <- u_i |e_i| / sum u |e|
 * drive weighted least squares toward the minimax solution; each step is one
 * Ceres solve from the previous point. The best max |e| seen is kept. */
#define MINIMAX_STEPS 30

static double max_error(bk_fit_ctx *c, const double *p)
{
	const bk_fit_spec *spec = c->spec;
	double *v = malloc(sizeof(double) * spec->s->n), e = INFINITY;
	if (v && bk_fit_eval_forms(spec, p, v) == 0) {
		e = 0.0;
		for (size_t i = 0; i < spec->s->n; i++)
			if (c->base[i] > 0)
				e = fmax(e, fabs(v[i] - spec->s->y[i]) * c->inv[i]);
	}
	free(v);
	return e;
}

/* noted: the length of res->message before the least-squares point's check,
 * whose note no longer applies once a minimax step replaces that point */
static int minimax(bk_fit_ctx *c, bk_fit_result *res, size_t noted)
{
	const bk_fit_spec *spec = c->spec;
	const bk_samples *s = spec->s;
	double *u = malloc(sizeof(double) * s->n), *v = malloc(sizeof(double) * s->n);
	if (!u || !v) {
		free(u);
		free(v);
		return -1;
	}
	size_t live = 0;
	for (size_t i = 0; i < s->n; i++)
		live += c->base[i] > 0;
	for (size_t i = 0; i < s->n; i++)
		u[i] = c->base[i] > 0 ? 1.0 / (double)live : 0.0;
	double p[BK_MAX_PARAMS], best = max_error(c, res->p);
	double *best_sw = NULL; /* the weights of the step that gave the best point */
	memcpy(p, res->p, sizeof p);
	for (int step = 0; step < MINIMAX_STEPS; step++) {
		for (size_t i = 0; i < s->n; i++)
			c->sw[i] = sqrt(u[i]);
		bk_fit_summary sum;
		if (bk_fit_solve(c, p, spec->hold, &sum) || sum.termination == BK_TERM_FAILURE)
			break;
		if (bk_fit_eval_forms(spec, p, v))
			break;
		double total = 0.0, e = 0.0;
		for (size_t i = 0; i < s->n; i++) {
			double ei = fabs(v[i] - s->y[i]) * c->inv[i];
			if (c->base[i] > 0)
				e = fmax(e, ei);
			u[i] *= ei;
			total += u[i];
		}
		if (e < best) {
			best = e;
			memcpy(res->p, p, sizeof p);
			res->summary = sum;
			if (!best_sw)
				best_sw = malloc(sizeof(double) * s->n);
			if (best_sw)
				memcpy(best_sw, c->sw, sizeof(double) * s->n);
		}
		if (!(total > 0))
			break;
		for (size_t i = 0; i < s->n; i++)
			u[i] /= total;
	}
	/* the point kept is the minimum of the weighted problem of its step:
	 * checked with those weights (no polish: the point was chosen by its max
	 * error, which a re-solve would change) */
	if (best_sw) {
		res->message[noted] = '\0';
		memcpy(c->sw, best_sw, sizeof(double) * s->n);
		check_optimality(c, res, spec->hold, 0);
	}
	for (size_t i = 0; i < s->n; i++)
		c->sw[i] = sqrt(c->base[i]);
	free(best_sw);
	free(u);
	free(v);
	return 0;
}

/* n significant digits, or the nearest binary16 value (digits = -1). */
static double round_constant(double x, int digits)
{
	if (digits < 0)
		return bk_half_round(x);
	if (x == 0.0 || !isfinite(x))
		return x;
	double e = floor(bk_dlog10(fabs(x))) + 1 - digits, scale = bk_dpow(10.0, e);
	return round(x / scale) * scale;
}

/* The reported constants keep the digits their standard errors justify: each
 * free p_j is rounded to the decade at or below se_j/100 (p0 = -1.66333329
 * ± 0.0106 is reported -1.6633). The digits below are noise twice over: the
 * data pin p_j only to ~se_j, and where the solver stops is itself only known
 * to ~sqrt(ftol (m - n)) se_j (a stop on a relative cost change ftol, with
 * σ² = 2 cost/(m - n)), which 1-ulp differences of libm move (the env fits
 * moved ~1e-6 se_j between FMA and non-FMA exp/log/pow). Printed to all nine
 * digits, those runs differed; rounded here, two runs differ only if a decade
 * boundary falls between their points (probability ~|Δp|/quantum, ~1e-4 for
 * well-conditioned fits). The metrics, the CSV and the shaders all use the
 * rounded values. Held parameters (no se), exact fits (se 0) and ones without
 * a standard error keep every digit. */
static void round_to_se(const bk_fit_spec *spec, bk_fit_result *res)
{
	memcpy(res->unrounded, res->p, sizeof res->p); /* no "unrounded" metrics row: the digits shown are the answer */
	for (int j = 0; j < spec->np; j++) {
		double se = res->se[j];
		if (spec->hold[j] || !(se > 0) || !isfinite(se) || !isfinite(res->p[j]))
			continue;
		double q = bk_dpow(10.0, floor(bk_dlog10(se / 100)));
		if (!(q > 0) || !isfinite(res->p[j] / q))
			continue;
		double v = round(res->p[j] / q) * q;
		res->p[j] = fmin(fmax(v, spec->lower[j]), spec->upper[j]);
	}
}

/* Round one constant at a time, largest standard-error-relative first would
 * be cleverer; index order keeps it predictable. After each, the others are
 * refitted with the rounded ones held. */
static int round_digits(bk_fit_ctx *c, bk_fit_result *res)
{
	const bk_fit_spec *spec = c->spec;
	int held[BK_MAX_PARAMS];
	memcpy(held, spec->hold, sizeof held);
	memcpy(res->unrounded, res->p, sizeof res->p);
	bk_fit_evaluate(spec, res->p, &res->before_digits);
	for (int j = 0; j < spec->np; j++) {
		if (spec->hold[j])
			continue; /* held constants stay as given */
		res->p[j] = round_constant(res->p[j], spec->digits);
		res->p[j] = fmin(fmax(res->p[j], spec->lower[j]), spec->upper[j]);
		held[j] = 1;
		if (j + 1 == spec->np)
			break;
		double p[BK_MAX_PARAMS];
		memcpy(p, res->p, sizeof p);
		bk_fit_summary sum;
		if (bk_fit_solve(c, p, held, &sum) == 0 && sum.termination != BK_TERM_FAILURE) {
			memcpy(res->p, p, sizeof p);
			res->summary.iterations += sum.iterations;
		}
	}
	return 0;
}

void bk_fit_defaults(bk_fit_spec *spec)
{
	bk_fit_options opt = BK_FIT_OPTIONS_INIT;
	memset(spec, 0, sizeof *spec);
	for (int j = 0; j < BK_MAX_PARAMS; j++) {
		spec->start[j] = 1.0;
		spec->lower[j] = -HUGE_VAL;
		spec->upper[j] = HUGE_VAL;
	}
	spec->opt = opt;
	spec->starts = 1;
	spec->seed = 1;
}

int bk_fit_run(const bk_fit_spec *spec, bk_fit_result *res)
{
	return bk_fit_run_cb(spec, NULL, res);
}

int bk_fit_run_cb(const bk_fit_spec *spec_in, const bk_fit_callbacks *cb, bk_fit_result *res)
{
	memset(res, 0, sizeof *res);
	bk_fit_spec fs = *spec_in; /* hold_unidentified adds to fs.hold */
	const bk_fit_spec *spec = &fs;
	bk_fit_ctx c;
	int rc = bk_fit_ctx_init(&c, spec);
	if (rc) {
		snprintf(res->message, sizeof res->message, "%s",
		         rc == -2 ? "the weight formula reads an input this target does not provide"
		         : rc == -3 ? "the weight formula is negative or not finite on part of the domain"
		                    : "out of memory");
		bk_fit_ctx_free(&c);
		return -1;
	}
	memcpy(res->p, spec->start, sizeof res->p);
	res->optimal = -1;
	res->condition = NAN;
	for (int j = 0; j < BK_MAX_PARAMS; j++)
		res->grad[j] = res->grad_rel[j] = NAN;
	if (spec->np == 0) { /* nothing to fit: metrics only */
		bk_fit_evaluate(spec, res->p, &res->fitted);
		bk_fit_ctx_free(&c);
		return 0;
	}
	int free_params = 0;
	for (int j = 0; j < spec->np; j++)
		free_params += !spec->hold[j] && spec->lower[j] != spec->upper[j];
	if (!free_params) { /* a solve would move nothing and report CONVERGENCE */
		snprintf(res->message, sizeof res->message, "every parameter is held (hold, or lower == upper): nothing to "
		         "fit");
		bk_fit_ctx_free(&c);
		return -1;
	}
	rc = multi_start(&c, cb, res);
	if (rc == 0)
		check_optimality(&c, res, spec->hold, 1);
	if (rc == 0 && res->summary.termination == BK_TERM_CONVERGENCE && hold_unidentified(&c, &fs, res)) {
		res->message[0] = '\0'; /* the notes were about the valley point */
		check_optimality(&c, res, spec->hold, 1);
	}
	size_t noted = strlen(res->message);
	if (rc == 0 && spec->minimax)
		rc = minimax(&c, res, noted);
	if (rc == 0) {
		bk_fit_stderr(&c, res);
		note_held(res, spec->np);
		note_conditioning(res, spec->np);
	}
	if (rc == 0 && spec->digits == BK_FIT_DIGITS_SE)
		round_to_se(spec, res);
	else if (rc == 0 && spec->digits)
		round_digits(&c, res);
	bk_fit_ctx_free(&c);
	if (rc)
		return -1;
	bk_fit_evaluate(spec, res->p, &res->fitted);
	return res->summary.termination == BK_TERM_CONVERGENCE ? 0 : 1;
}
