/*
 * fit_ctx.c — a fit's context: the weights, the blocks of samples, the
 * residuals the formula IR gives over a block (the Jacobian by rows for Ceres,
 * by columns for TinySolver) and the Ceres problem they make.
 * Used by the driver (fit.c) and the statistics (fit_stats.c); calls neither.
 */
#include "fit.h"
#include "fit_int.h"
#include "switches.h"
#include "brdf_ops.h" /* bk_ir_avx2 */

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Residuals per Ceres block: ~1000 is where the bridge's overhead stops
 * mattering (shared/references/toolchain.md: blocks of 100-1000 are ~5x
 * faster than one per residual) while there are still blocks enough to spread
 * over threads. */
#define BLOCK 1024

/* Relative residuals divide by |y|, floored at 1e-6 of the largest |y|:
 * targets that vanish (B at NoV = 1, Fresnel of f0 = 0) would otherwise give
 * 0/0 or let a handful of samples rule the fit. */
#define REL_FLOOR 1e-6

/* Finiteness over a loop, as one OR of bits: x * 0 is ±0 for a finite x (no
 * exponent bit set) and a NaN otherwise (every one set), so the OR of their
 * bits has all exponent bits set iff some x was not finite. A loop of these
 * vectorises (integer ORs), where a loop of !isfinite(x) stays scalar (its
 * quiet compare gcc does not vectorise): that scalar test was most of the
 * residual pass (perf). */
static inline uint64_t zero_bits(double x)
{
	double z = x * 0.0;
	uint64_t u;
	memcpy(&u, &z, sizeof u);
	return u;
}
#define EXP_BITS 0x7ff0000000000000ull
#define ANY_NONFINITE(acc) (((acc) & EXP_BITS) == EXP_BITS)

/* A block's k = sw inv: the solve's (kw, formed once per solve) while one
 * runs, else formed into buf (m <= BLOCK). The same product either way. */
static const double *block_k(const bk_fit_ctx *c, size_t lo, int m, double *buf)
{
	if (c->kw_live)
		return c->kw + lo;
	const double *restrict sw = c->sw + lo, *restrict inv = c->inv + lo;
	double *restrict k = buf;
	for (int i = 0; i < m; i++)
		k[i] = sw[i] * inv[i];
	return buf;
}

/*
 * The scaling loops of the residuals (residuals and residuals_cols) and of
 * residuals_cols' Jacobian columns, twice: for the x86-64
 * baseline (SSE2, 2 doubles a vector) and for AVX2 (4), picked at run time
 * as the IR picks its kernels (bk_ir_avx2, brdf_ops.h). The same bits
 * either way: a product and a difference are IEEE element-wise, exact
 * whatever the vector width; -std=c11 keeps -ffp-contract=off and
 * target("avx2") does not enable FMA, so k (r - y) is never fused
 * (tests/test_cols.c: a whole fit on both paths, its cost bit for bit).
 * residuals_cols was ~10 % of a vf2d search (perf), mostly these loops.
 */
#define SCALE_LOOPS(SUFFIX, ATTR) \
	ATTR static uint64_t scale_res_##SUFFIX(const double *restrict k, const double *restrict y, \
	                                         double *restrict r, int m) \
	{ \
		uint64_t bits = 0; \
		for (int i = 0; i < m; i++) { \
			r[i] = k[i] * (r[i] - y[i]); \
			bits |= zero_bits(r[i]); \
		} \
		return bits; \
	} \
	ATTR static uint64_t scale_col_##SUFFIX(const double *restrict k, double *restrict J, int m) \
	{ \
		uint64_t bits = 0; \
		for (int i = 0; i < m; i++) { \
			double v = k[i] * J[i]; \
			J[i] = v; \
			bits |= zero_bits(v); \
		} \
		return bits; \
	}

SCALE_LOOPS(gen, )
#if defined(__GNUC__) && defined(__x86_64__)
SCALE_LOOPS(avx2, __attribute__((target("avx2"))))
#define SCALE(name) (bk_ir_avx2() ? name##_avx2 : name##_gen)
#else
#define SCALE(name) name##_gen
#endif

int bk_fit_ctx_bind = 1;
int bk_fit_ctx_cols = 1;

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
	/* The form's values and Jacobian go straight into r and jac, and are
	 * scaled there in place (no buffer, no copy: this runs for every block at
	 * every iteration); only a form with fewer parameters than the fit (one
	 * component of several) needs its narrower Jacobian apart. */
	double *jf = jac, *narrow = NULL;
	if (jac && npf != np) {
		narrow = malloc(sizeof(double) * (size_t)m * (size_t)(npf ? npf : 1));
		if (!narrow)
			return -1;
		jf = narrow;
	}
	bk_fit_ctx *cw = vctx; /* the block's own bound form: this thread's alone (fit_int.h) */
	if (!cw->bound[block] && !cw->unbound[block] && bk_fit_ctx_bind)
		cw->unbound[block] = !(cw->bound[block] = bk_form_bind(f, (size_t)m, in));
	int bad = cw->bound[block] ? bk_form_bound_eval(cw->bound[block], p, r, jf)
	          : jac           ? bk_form_eval_diff(f, (size_t)m, in, p, r, jf)
	                          : bk_form_eval(f, BK_F64, (size_t)m, in, p, r);
	if (bad) {
		free(narrow);
		return -1;
	}
	/* r = k (f - y), k = sqrt(w)/|y| (or sqrt(w)), and the Jacobian's rows
	 * times k (jf k is k jf: multiplication commutes exactly), in separate
	 * simple loops: the same operations per sample as one loop that stopped
	 * at the first non-finite residual (a failed block's values are not used).
	 * k is formed once per sample per solve (sw inv, block_k: the same
	 * product as before, the left one of sw inv (f - y)), the residuals and
	 * their finiteness bits in one loop. The loops vectorise (the Makefile gives
	 * this file gcc's dynamic cost model: -O2's leaves a loop of variable
	 * count scalar), and the Jacobian's by rows of a fixed width where the
	 * form has 1 to 4 parameters; the same products either way. */
	const double *restrict y = s->y + lo;
	double *restrict rr = r;
	double kbuf[BLOCK];
	const double *restrict k = block_k(c, lo, m, kbuf);
	bad = ANY_NONFINITE(SCALE(scale_res)(k, y, rr, m));
	if (jac && !narrow) {
		double *restrict J = jac;
		switch (np) {
#define ROWS(NP) \
	for (int i = 0; i < m; i++) \
		for (int j = 0; j < NP; j++) \
			J[(size_t)i * NP + j] *= k[i]; \
	break;
		case 1: ROWS(1)
		case 2: ROWS(2)
		case 3: ROWS(3)
		case 4: ROWS(4)
#undef ROWS
		default:
			for (int i = 0; i < m; i++)
				for (int j = 0; j < np; j++)
					J[(size_t)i * np + j] *= k[i];
		}
	} else if (jac) {
		for (int i = 0; i < m; i++)
			for (int j = 0; j < np; j++)
				jac[(size_t)i * np + j] = j < npf ? k[i] * jf[(size_t)i * npf + j] : 0.0;
	}
	free(narrow);
	return bad ? -1 : 0;
}

/*
 * The same residuals with the Jacobian by columns (bk_residual_cols_fn,
 * fit/solver.h), for TinySolver: the bound form writes each column where the
 * solver reads it (no row-major block, no transpose after), and the column's
 * scaling by k tests each entry as it goes, so the solver need not read the
 * Jacobian again to test it. The same values as residuals(): the same
 * products on the same operands (k (f - y), k jf), bit for bit. Without a
 * bound form (bk_fit_ctx_bind 0, or none could be made) it goes through
 * residuals()' row-major block.
 */
static int residuals_cols(void *vctx, int block, const double *p, double *r, double *const *cols)
{
	bk_fit_ctx *c = vctx;
	const bk_fit_spec *spec = c->spec;
	const bk_samples *s = spec->s;
	size_t lo = c->lo[block];
	int m = c->size[block], np = spec->np;
	const bk_form *f = spec->form[c->comp[block]];
	int npf = bk_form_nparams(f);
	if (!c->bound[block] && !c->unbound[block] && bk_fit_ctx_bind) {
		const double *in[BK_IN_COUNT];
		for (int k = 0; k < BK_IN_COUNT; k++)
			in[k] = s->in[k] + lo;
		c->unbound[block] = !(c->bound[block] = bk_form_bind(f, (size_t)m, in));
	}
	if (!c->bound[block]) { /* the row-major block, then its columns */
		double *rows = cols ? malloc(sizeof(double) * (size_t)m * (size_t)np) : NULL;
		if (cols && !rows)
			return -1;
		int rc = residuals(vctx, block, p, r, rows), bad = 0;
		for (int i = 0; rc == -1 && i < m; i++) /* residuals() fails on these, or out of memory */
			if (!isfinite(r[i]))
				rc = BK_COLS_RES_NONFINITE;
		for (int j = 0; rc == 0 && cols && j < np; j++)
			if (cols[j])
				for (int i = 0; i < m; i++) {
					double v = rows[(size_t)i * np + j];
					cols[j][i] = v;
					bad |= !isfinite(v);
				}
		free(rows);
		return rc ? rc : bad ? BK_COLS_JAC_NONFINITE : 0;
	}
	double *fc[BK_MAX_PARAMS];
	for (int j = 0; j < npf; j++)
		fc[j] = cols && j < np ? cols[j] : NULL;
	bk_form_bound_eval_cols(c->bound[block], p, r, cols ? fc : NULL);
	/* as residuals(): k once per sample, then the residuals, then the columns */
	const double *restrict y = s->y + lo;
	double *restrict rr = r;
	double kbuf[BLOCK];
	const double *restrict k = block_k(c, lo, m, kbuf);
	uint64_t rbits = SCALE(scale_res)(k, y, rr, m), jbits = 0;
	for (int j = 0; cols && j < np; j++) {
		double *restrict J = cols[j];
		if (!J)
			continue;
		if (j >= npf) { /* a parameter of the fit that this form does not read */
			for (int i = 0; i < m; i++)
				J[i] = 0.0;
			continue;
		}
		jbits |= SCALE(scale_col)(k, J, m);
	}
	return ANY_NONFINITE(rbits) ? BK_COLS_RES_NONFINITE : ANY_NONFINITE(jbits) ? BK_COLS_JAC_NONFINITE : 0;
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
	c->kw = malloc(sizeof(double) * (s->n ? s->n : 1));
	size_t nb = 0;
	for (int q = 0; q < s->ncomp; q++)
		nb += (s->start[q + 1] - s->start[q] + BLOCK - 1) / BLOCK;
	c->lo = malloc(sizeof(size_t) * nb);
	c->size = malloc(sizeof(int) * nb);
	c->comp = malloc(sizeof(int) * nb);
	c->bound = calloc(nb ? nb : 1, sizeof *c->bound);
	c->unbound = calloc(nb ? nb : 1, 1);
	if (!c->sw || !c->inv || !c->base || !c->kw || !c->lo || !c->size || !c->comp || !c->bound || !c->unbound)
		return -1;
	for (int q = 0; q < s->ncomp; q++)
		for (size_t lo = s->start[q]; lo < s->start[q + 1]; lo += BLOCK) {
			c->lo[c->nblocks] = lo;
			c->size[c->nblocks] = (int)(s->start[q + 1] - lo < BLOCK ? s->start[q + 1] - lo : BLOCK);
			c->comp[c->nblocks++] = q;
		}
	/* a fit's set-up runs once per candidate in a search (~2 % of its
	 * screening before): comparisons where libm's fmax was a call each (the
	 * same results: neither compares a NaN, which fmax would skip, with
	 * ymax or the floor, which are never NaN), and the square roots below
	 * vectorised (the Makefile builds this file without errno: sqrt is
	 * correctly rounded either way) */
	double ymax = 0.0;
	for (size_t i = 0; i < s->n; i++) {
		double a = fabs(s->y[i]);
		ymax = a > ymax ? a : ymax;
	}
	const double floor = REL_FLOOR * ymax;
	for (size_t i = 0; i < s->n; i++) {
		double a = fabs(s->y[i]);
		c->inv[i] = spec->relative ? 1.0 / (a > floor ? a : floor) : 1.0;
	}
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
	free(c->kw);
	free(c->lo);
	free(c->size);
	free(c->comp);
	for (int b = 0; c->bound && b < c->nblocks; b++)
		bk_form_bound_free(c->bound[b]);
	free(c->bound);
	free(c->unbound);
}

int bk_fit_solve(bk_fit_ctx *c, double *p, const int *constant, bk_fit_summary *sum)
{
	const bk_fit_spec *spec = c->spec;
	bk_problem prob = {spec->np, c->nblocks, c->size, residuals, c, spec->lower, spec->upper, constant};
	/* the weights hold still for the solve: k = sw inv once for all its
	 * evaluations (one pass over the samples, not one per evaluation) */
	const double *restrict sw = c->sw, *restrict inv = c->inv;
	double *restrict kw = c->kw;
	for (size_t i = 0, n = spec->s->n; i < n; i++)
		kw[i] = sw[i] * inv[i];
	c->kw_live = 1;
	int rc;
	/* the fast path where it applies (no finite bounds, no loss, LM): TinySolver */
	if (bk_solve_tiny_applies(&prob, &spec->opt))
		/* residuals() gives the same values with or without the Jacobian (one
		 * kernel) and fails only on them: a trial's Jacobian may be kept */
		rc = bk_fit_ctx_cols ? bk_solve_tiny_cols(&prob, residuals_cols, &spec->opt, p, sum)
		                     : bk_solve_tiny_reusing(&prob, &spec->opt, p, sum);
	else
		rc = bk_solve(&prob, &spec->opt, p, sum);
	c->kw_live = 0;
	return rc;
}

int bk_fit_eval_forms(const bk_fit_spec *spec, const double *p, double *v)
{
	const bk_samples *s = spec->s;
	for (int q = 0; q < s->ncomp; q++) {
		size_t lo = s->start[q];
		const double *in[BK_IN_COUNT];
		for (int k = 0; k < BK_IN_COUNT; k++)
			in[k] = s->in[k] + lo;
		if (bk_form_eval(spec->form[q], BK_F64, s->start[q + 1] - lo, in, p, v + lo))
			return -1;
	}
	return 0;
}
