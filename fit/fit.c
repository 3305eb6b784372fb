/*
 * fit.c — the fitter: residuals from the formula IR over blocks of samples,
 * handed to the Ceres bridge; several deterministic starts; Lawson's minimax;
 * rounding constants to shader literals. Statistics are in fit_stats.c.
 */
#include "fit.h"
#include "fit_int.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Residuals per Ceres block: ~1000 is where the bridge's overhead stops
 * mattering (toolchain.md: blocks of 100-1000 are ~5x faster than one per
 * residual) while there are still blocks enough to spread over threads. */
#define BLOCK 1024

/* Relative residuals divide by |y|, floored at 1e-6 of the largest |y|:
 * targets that vanish (B at NoV = 1, Fresnel of f0 = 0) would otherwise give
 * 0/0 or let a handful of samples rule the fit. */
#define REL_FLOOR 1e-6

static int residuals(void *vctx, int block, const double *p, double *r, double *jac)
{
	const bk_fit_ctx *c = vctx;
	const bk_fit_spec *spec = c->spec;
	const bk_samples *s = spec->s;
	size_t lo = c->lo[block];
	int m = c->size[block], np = spec->np;
	const bk_form *f = spec->form[c->comp[block]];
	int npf = bk_form_nparams(f);
	const double *in[BK_IN_COUNT];
	for (int k = 0; k < BK_IN_COUNT; k++)
		in[k] = s->in[k] + lo;
	double *v = malloc(sizeof(double) * (size_t)m * (size_t)(1 + (npf ? npf : 1)));
	if (!v)
		return -1;
	double *jf = v + m;
	int bad = jac ? bk_form_eval_diff(f, (size_t)m, in, p, v, jf) : bk_form_eval(f, BK_F64, (size_t)m, in, p, v);
	for (int i = 0; i < m && !bad; i++) {
		double k = c->sw[lo + i] * c->inv[lo + i];
		r[i] = k * (v[i] - s->y[lo + i]);
		bad |= !isfinite(r[i]);
		if (jac)
			for (int j = 0; j < np; j++)
				jac[(size_t)i * np + j] = j < npf ? k * jf[(size_t)i * npf + j] : 0.0;
	}
	free(v);
	return bad ? -1 : 0;
}

/* The same residuals for the statistics (all blocks, at the solution). */
int bk_fit_residual_block(bk_fit_ctx *c, int block, const double *p, double *r, double *jac)
{
	return residuals(c, block, p, r, jac);
}

int bk_fit_ctx_init(bk_fit_ctx *c, const bk_fit_spec *spec)
{
	const bk_samples *s = spec->s;
	memset(c, 0, sizeof *c);
	c->spec = spec;
	c->sw = malloc(sizeof(double) * s->n);
	c->inv = malloc(sizeof(double) * s->n);
	c->base = malloc(sizeof(double) * s->n);
	size_t nb = 0;
	for (int q = 0; q < s->ncomp; q++)
		nb += (s->start[q + 1] - s->start[q] + BLOCK - 1) / BLOCK;
	c->lo = malloc(sizeof(size_t) * nb);
	c->size = malloc(sizeof(int) * nb);
	c->comp = malloc(sizeof(int) * nb);
	if (!c->sw || !c->inv || !c->base || !c->lo || !c->size || !c->comp)
		return -1;
	for (int q = 0; q < s->ncomp; q++)
		for (size_t lo = s->start[q]; lo < s->start[q + 1]; lo += BLOCK) {
			c->lo[c->nblocks] = lo;
			c->size[c->nblocks] = (int)(s->start[q + 1] - lo < BLOCK ? s->start[q + 1] - lo : BLOCK);
			c->comp[c->nblocks++] = q;
		}
	double ymax = 0.0;
	for (size_t i = 0; i < s->n; i++)
		ymax = fmax(ymax, fabs(s->y[i]));
	for (size_t i = 0; i < s->n; i++)
		c->inv[i] = spec->relative ? 1.0 / fmax(fabs(s->y[i]), REL_FLOOR * ymax) : 1.0;
	/* the user weight multiplies the target's own */
	for (size_t i = 0; i < s->n; i++)
		c->base[i] = s->w[i];
	if (spec->weight) {
		double *uw = malloc(sizeof(double) * s->n);
		if (!uw || bk_form_eval(spec->weight, BK_F64, s->n, (const double *const *)s->in, spec->start, uw)) {
			free(uw);
			return -2;
		}
		for (size_t i = 0; i < s->n; i++) {
			if (!(uw[i] >= 0.0) || !isfinite(uw[i])) {
				free(uw);
				return -3;
			}
			c->base[i] *= uw[i];
		}
		free(uw);
	}
	for (size_t i = 0; i < s->n; i++)
		c->sw[i] = sqrt(c->base[i]);
	return 0;
}

void bk_fit_ctx_free(bk_fit_ctx *c)
{
	free(c->sw);
	free(c->inv);
	free(c->base);
	free(c->lo);
	free(c->size);
	free(c->comp);
}

int bk_fit_solve(bk_fit_ctx *c, double *p, const int *constant, bk_fit_summary *sum)
{
	const bk_fit_spec *spec = c->spec;
	bk_problem prob = {spec->np, c->nblocks, c->size, residuals, c, spec->lower, spec->upper, constant};
	return bk_solve(&prob, &spec->opt, p, sum);
}

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

static int multi_start(bk_fit_ctx *c, bk_fit_result *res)
{
	const bk_fit_spec *spec = c->spec;
	double best = INFINITY;
	res->start_cost_min = INFINITY;
	res->start_cost_max = -INFINITY;
	for (int k = 0; k < spec->starts; k++) {
		double p[BK_MAX_PARAMS] = {0};
		bk_fit_summary sum;
		start_point(spec, k, p);
		if (bk_fit_solve(c, p, spec->hold, &sum) || sum.termination == BK_TERM_FAILURE) {
			res->starts_failed++;
			if (k == 0)
				snprintf(res->message, sizeof res->message, "%s", sum.message);
			continue;
		}
		res->start_cost_min = fmin(res->start_cost_min, sum.final_cost);
		res->start_cost_max = fmax(res->start_cost_max, sum.final_cost);
		if (sum.final_cost < best) {
			best = sum.final_cost;
			memcpy(res->p, p, sizeof p);
			res->summary = sum;
		}
	}
	if (!isfinite(best)) {
		char why[sizeof res->message];
		memcpy(why, res->message, sizeof why);
		snprintf(res->message, sizeof res->message, "every start failed: %.400s", why);
		return -1;
	}
	return 0;
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

static int minimax(bk_fit_ctx *c, bk_fit_result *res)
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
		}
		if (!(total > 0))
			break;
		for (size_t i = 0; i < s->n; i++)
			u[i] /= total;
	}
	for (size_t i = 0; i < s->n; i++)
		c->sw[i] = sqrt(c->base[i]);
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
	double e = floor(log10(fabs(x))) + 1 - digits, scale = pow(10.0, e);
	return round(x / scale) * scale;
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

int bk_fit_run(const bk_fit_spec *spec, bk_fit_result *res)
{
	memset(res, 0, sizeof *res);
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
	if (spec->np == 0) { /* nothing to fit: metrics only */
		bk_fit_evaluate(spec, res->p, &res->fitted);
		bk_fit_ctx_free(&c);
		return 0;
	}
	rc = multi_start(&c, res);
	if (rc == 0 && spec->minimax)
		rc = minimax(&c, res);
	if (rc == 0)
		bk_fit_stderr(&c, res);
	if (rc == 0 && spec->digits)
		round_digits(&c, res);
	bk_fit_ctx_free(&c);
	if (rc)
		return -1;
	bk_fit_evaluate(spec, res->p, &res->fitted);
	return res->summary.termination == BK_TERM_CONVERGENCE ? 0 : 1;
}
