/*
 * albfit.c — constants fitted to the directional albedo (albfit.h). Blocks
 * of whole cells, so that each block's residuals are its cells' albedo
 * errors: the form and its Jacobian over the block's samples, then summed
 * per cell with the cell's measure.
 *
 * Speed without new bits: each block's form is bound to its samples
 * (bk_form_bind, as fit_ctx.c: what reads no parameter is computed once per
 * fit, and the bound values are the plain evaluators' bit for bit); the
 * cells' sums run cell by cell over their contiguous samples, with the
 * Jacobian's row in a fixed-width accumulator where the form has 1 to 8
 * parameters; every sum adds the same terms in the same order as one pass
 * over the samples would. The max error of the last points asked is kept
 * (the search and the front ask it at the point they start a run from).
 */
#include "albfit.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Samples per block, about: as fit_ctx.c's blocks, where the bridge's
 * overhead stops mattering; a block holds whole cells. */
#define BLOCK 1024

/* Lawson's steps, as fit.c's minimax. */
#define MINIMAX_STEPS 30

/* Points whose max error is kept: a run's start and its result. */
#define MEMO 2

struct bk_albfit {
	const bk_samples *s;
	const bk_form *f;
	int np, nblocks, ncells;
	size_t *lo;     /* first sample of each block */
	int *nsamp;     /* samples in each block */
	int *size;      /* cells in each block (its residuals) */
	int *first;     /* first cell (0..ncells) of each block */
	size_t *cstart; /* first sample of each cell, ncells + 1 (cells are contiguous) */
	size_t *crel;   /* per block b from first[b] + b: its cells' first samples less lo[b], size[b] + 1 */
	double *u;      /* sqrt of each cell's weight (minimax changes it) */
	double *scratch;/* per block: values and Jacobian of its samples (blocks never share) */
	size_t *soff;
	/* each block's form bound to its samples at its first evaluation (NULL
	 * until then; unbound[b] where it could not be made: the plain
	 * evaluators). A block is evaluated by one thread at a time. */
	bk_form_bound **bound;
	char *unbound;
	/* the max error at the last points computed (bk_albfit_max's value) */
	int nmemo, memo_next;
	double memo_p[MEMO][BK_MAX_PARAMS], memo_max[MEMO];
};

bk_albfit *bk_albfit_new(const bk_samples *s, const bk_form *f, int np)
{
	int any = 0;
	for (size_t i = 0; i < s->n && !any; i++)
		any = s->measure[i] != 0.0;
	if (!any || s->ncomp != 1 || np < 1 || np > BK_MAX_PARAMS)
		return NULL;
	bk_albfit *a = calloc(1, sizeof *a);
	if (!a)
		return NULL;
	a->s = s, a->f = f, a->np = np;
	size_t cap = s->n + 1; /* blocks and cells: at most one per sample */
	a->lo = malloc(sizeof(size_t) * cap);
	a->nsamp = malloc(sizeof(int) * cap);
	a->size = malloc(sizeof(int) * cap);
	a->first = malloc(sizeof(int) * cap);
	a->cstart = malloc(sizeof(size_t) * (cap + 1));
	a->soff = malloc(sizeof(size_t) * cap);
	a->u = malloc(sizeof(double) * cap);
	a->scratch = malloc(sizeof(double) * (s->n ? s->n : 1) * (size_t)(1 + np));
	a->bound = calloc(cap, sizeof *a->bound);
	a->unbound = calloc(cap, 1);
	if (!a->lo || !a->nsamp || !a->size || !a->first || !a->cstart || !a->soff || !a->u || !a->scratch ||
	    !a->bound || !a->unbound) {
		bk_albfit_free(a);
		return NULL;
	}
	/* cells in order of appearance, each one contiguous run */
	int *seen = calloc((size_t)s->plane_nx * s->plane_ny + 1, sizeof *seen);
	if (!seen) {
		bk_albfit_free(a);
		return NULL;
	}
	for (size_t i = 0; i < s->n; i++) {
		int c = s->cell[i];
		if (i == 0 || c != s->cell[i - 1]) {
			if (seen[c]) { /* a cell in two runs */
				free(seen);
				bk_albfit_free(a);
				return NULL;
			}
			seen[c] = 1;
			a->u[a->ncells] = 1.0;
			a->cstart[a->ncells++] = i;
		}
	}
	a->cstart[a->ncells] = s->n;
	free(seen);
	/* blocks of whole cells, about BLOCK samples each */
	for (int c = 0; c < a->ncells;) {
		int d = c + 1;
		while (d < a->ncells && a->cstart[d] - a->cstart[c] < BLOCK)
			d++;
		int b = a->nblocks++;
		a->lo[b] = a->cstart[c];
		a->nsamp[b] = (int)(a->cstart[d] - a->cstart[c]);
		a->first[b] = c;
		a->size[b] = d - c;
		a->soff[b] = a->cstart[c] * (size_t)(1 + np);
		c = d;
	}
	a->crel = malloc(sizeof(size_t) * (size_t)(a->ncells + a->nblocks + 1));
	if (!a->crel) {
		bk_albfit_free(a);
		return NULL;
	}
	for (int b = 0; b < a->nblocks; b++)
		for (int k = 0; k <= a->size[b]; k++)
			a->crel[a->first[b] + b + k] = a->cstart[a->first[b] + k] - a->lo[b];
	return a;
}

void bk_albfit_free(bk_albfit *a)
{
	if (!a)
		return;
	for (int b = 0; a->bound && b < a->nblocks; b++)
		bk_form_bound_free(a->bound[b]);
	free(a->bound);
	free(a->unbound);
	free(a->lo);
	free(a->nsamp);
	free(a->size);
	free(a->first);
	free(a->cstart);
	free(a->crel);
	free(a->soff);
	free(a->u);
	free(a->scratch);
	free(a);
}

/* The form's values (and Jacobian, where jf is not NULL) over a block's
 * samples into v: the block's bound form, made at its first call. */
static int eval_block(bk_albfit *a, int block, const double *p, double *v, double *jf)
{
	const bk_samples *s = a->s;
	size_t lo = a->lo[block];
	int m = a->nsamp[block];
	const double *in[BK_IN_COUNT];
	for (int k = 0; k < BK_IN_COUNT; k++)
		in[k] = s->in[k] ? s->in[k] + lo : NULL;
	if (!a->bound[block] && !a->unbound[block])
		a->unbound[block] = !(a->bound[block] = bk_form_bind(a->f, (size_t)m, in));
	if (a->bound[block])
		return bk_form_bound_eval(a->bound[block], p, v, jf);
	return jf ? bk_form_eval_diff(a->f, (size_t)m, in, p, v, jf) : bk_form_eval(a->f, BK_F64, (size_t)m, in, p, v);
}

/* Cell c's albedo error, its samples from i0 to i1 (block-relative) of v:
 * Σ measure (v - y) in sample order. */
static double cell_sum(const double *restrict w, const double *restrict v, const double *restrict y, size_t i0,
                       size_t i1)
{
	double e = 0;
	for (size_t i = i0; i < i1; i++)
		e += w[i] * (v[i] - y[i]);
	return e;
}

/* Cells from c on of a block into r (times u): two at a time, side by side
 * (each sum its own chain in its own sample order, so the bits are
 * cell_sum's; two chains hide the adds' latency that bounds one). cs: the
 * cells' first samples, block-relative. */
static void cell_sums(const double *restrict w, const double *restrict v, const double *restrict y,
                      const size_t *cs, const double *u, int nc, double *r)
{
	int c = 0;
	for (; c + 1 < nc; c += 2) {
		size_t a = cs[c], b = cs[c + 1], na = cs[c + 1] - a, nb = cs[c + 2] - b, nmin = na < nb ? na : nb;
		double ea = 0, eb = 0;
		for (size_t t = 0; t < nmin; t++) {
			ea += w[a + t] * (v[a + t] - y[a + t]);
			eb += w[b + t] * (v[b + t] - y[b + t]);
		}
		for (size_t t = nmin; t < na; t++)
			ea += w[a + t] * (v[a + t] - y[a + t]);
		for (size_t t = nmin; t < nb; t++)
			eb += w[b + t] * (v[b + t] - y[b + t]);
		r[c] = ea * u[c];
		r[c + 1] = eb * u[c + 1];
	}
	if (c < nc)
		r[c] = cell_sum(w, v, y, cs[c], cs[c + 1]) * u[c];
}

static int residuals(void *ctx, int block, const double *p, double *r, double *jac)
{
	bk_albfit *a = ctx;
	const bk_samples *s = a->s;
	size_t lo = a->lo[block];
	int m = a->nsamp[block], np = a->np, npf = bk_form_nparams(a->f);
	double *v = a->scratch + a->soff[block], *jf = v + m;
	if (eval_block(a, block, p, v, jac ? jf : NULL))
		return -1;
	int nc = a->size[block], c0 = a->first[block], bad = 0;
	const double *restrict w = s->measure + lo, *restrict y = s->y + lo, *restrict u = a->u + c0;
	/* the cells' first samples, block-relative */
	size_t *cs = a->crel + c0 + block;
	if (!jac) {
		cell_sums(w, v, y, cs, u, nc, r);
		for (int c = 0; c < nc; c++)
			bad |= !isfinite(r[c]);
		return bad ? -1 : 0;
	}
	/* each cell's error and its Jacobian row, Σ measure (f - y) and
	 * Σ measure J over the cell's samples in sample order, then times u: one
	 * pass, the row's sums in registers where the width is fixed, two cells
	 * side by side (the sums are independent chains, so they add side by
	 * side; each in its own sample order) */
	switch (npf == np ? np : 0) {
#define STEP(E, ACC, I, NP) \
	do { \
		E += w[I] * (v[I] - y[I]); \
		for (int j = 0; j < NP; j++) \
			ACC[j] += w[I] * jf[(I) * NP + j]; \
	} while (0)
#define ROWS(NP) \
	for (int c = 0; c < nc; c += 2) { \
		int two = c + 1 < nc; \
		size_t a0 = cs[c], na = cs[c + 1] - a0, b0 = two ? cs[c + 1] : 0, nb = two ? cs[c + 2] - b0 : 0; \
		size_t nmin = na < nb ? na : nb; \
		double ea = 0, eb = 0, acca[NP] = {0}, accb[NP] = {0}; \
		for (size_t t = 0; t < nmin; t++) { \
			STEP(ea, acca, a0 + t, NP); \
			STEP(eb, accb, b0 + t, NP); \
		} \
		for (size_t t = nmin; t < na; t++) \
			STEP(ea, acca, a0 + t, NP); \
		for (size_t t = nmin; t < nb; t++) \
			STEP(eb, accb, b0 + t, NP); \
		r[c] = ea * u[c]; \
		for (int j = 0; j < NP; j++) \
			jac[(size_t)c * NP + j] = acca[j] * u[c]; \
		if (two) { \
			r[c + 1] = eb * u[c + 1]; \
			for (int j = 0; j < NP; j++) \
				jac[(size_t)(c + 1) * NP + j] = accb[j] * u[c + 1]; \
		} \
	} \
	break;
	case 1: ROWS(1)
	case 2: ROWS(2)
	case 3: ROWS(3)
	case 4: ROWS(4)
	case 5: ROWS(5)
	case 6: ROWS(6)
	case 7: ROWS(7)
	case 8: ROWS(8)
#undef ROWS
#undef STEP
	default:
		for (int c = 0; c < nc; c++) {
			double acc[BK_MAX_PARAMS] = {0};
			r[c] = cell_sum(w, v, y, cs[c], cs[c + 1]) * u[c];
			for (size_t i = cs[c]; i < cs[c + 1]; i++)
				for (int j = 0; j < npf && j < np; j++)
					acc[j] += w[i] * jf[i * (size_t)npf + j];
			for (int j = 0; j < np; j++)
				jac[(size_t)c * np + j] = acc[j] * u[c];
		}
	}
	for (int c = 0; c < nc; c++)
		bad |= !isfinite(r[c]);
	return bad ? -1 : 0;
}

/* The cells' errors at p into e (ncells), unweighted, block by block (the
 * blocks' bound forms; each cell's sum in sample order). */
static int errors(bk_albfit *a, const double *p, double *e)
{
	const bk_samples *s = a->s;
	for (int b = 0; b < a->nblocks; b++) {
		size_t lo = a->lo[b];
		double *v = a->scratch + a->soff[b];
		if (eval_block(a, b, p, v, NULL))
			return -1;
		for (int c = a->first[b]; c < a->first[b] + a->size[b]; c++)
			e[c] = cell_sum(s->measure + lo, v, s->y + lo, a->cstart[c] - lo, a->cstart[c + 1] - lo);
	}
	return 0;
}

static double max_abs(const double *e, int n)
{
	double m = 0;
	for (int c = 0; c < n; c++)
		m = isfinite(e[c]) ? fmax(m, fabs(e[c])) : HUGE_VAL;
	return m;
}

static void memo_put(bk_albfit *a, const double *p, double m)
{
	int k = a->memo_next;
	memcpy(a->memo_p[k], p, sizeof(double) * a->np);
	a->memo_max[k] = m;
	a->memo_next = (k + 1) % MEMO;
	if (a->nmemo < MEMO)
		a->nmemo++;
}

/* The max error at p from the memo (1), or 0 (the same bits of p only:
 * the value is a function of them). */
static int memo_get(const bk_albfit *a, const double *p, double *m)
{
	for (int k = 0; k < a->nmemo; k++)
		if (!memcmp(a->memo_p[k], p, sizeof(double) * a->np)) {
			*m = a->memo_max[k];
			return 1;
		}
	return 0;
}

/* The max |e_c| at p, e (ncells) the scratch; HUGE_VAL and -1 in *rc
 * where the form could not be evaluated (not kept: the run fails there). */
static double max_at(bk_albfit *a, const double *p, double *e, int *rc)
{
	double m = HUGE_VAL;
	*rc = 0;
	if (memo_get(a, p, &m))
		return m;
	if (errors(a, p, e)) {
		*rc = -1;
		return HUGE_VAL;
	}
	m = max_abs(e, a->ncells);
	memo_put(a, p, m);
	return m;
}

double bk_albfit_max(bk_albfit *a, const double *p)
{
	double *e = malloc(sizeof(double) * a->ncells), m = HUGE_VAL;
	int rc;
	if (e)
		m = max_at(a, p, e, &rc);
	free(e);
	return m;
}

static int solve(bk_albfit *a, double *p, const bk_fit_options *opt)
{
	bk_problem prob = {a->np, a->nblocks, a->size, residuals, a, NULL, NULL, NULL};
	bk_fit_summary sum;
	int rc = bk_solve_tiny_applies(&prob, opt) ? bk_solve_tiny(&prob, opt, p, &sum) : bk_solve(&prob, opt, p, &sum);
	return rc || sum.termination == BK_TERM_FAILURE ? -1 : 0;
}

int bk_albfit_run(bk_albfit *a, double *p, int minimax, const bk_fit_options *opt, double *max_err)
{
	double *e = malloc(sizeof(double) * a->ncells), *w = malloc(sizeof(double) * a->ncells);
	int rc = -1;
	double best_max = e && w ? max_at(a, p, e, &rc) : HUGE_VAL;
	if (rc) {
		free(e);
		free(w);
		return -1;
	}
	double best[BK_MAX_PARAMS], q[BK_MAX_PARAMS];
	memcpy(best, p, sizeof best);
	memcpy(q, p, sizeof q);
	for (int c = 0; c < a->ncells; c++)
		w[c] = 1.0 / a->ncells;
	int steps = minimax ? MINIMAX_STEPS : 1;
	for (int step = 0; step < steps; step++) {
		for (int c = 0; c < a->ncells; c++)
			a->u[c] = minimax ? sqrt(w[c]) : 1.0;
		if (solve(a, q, opt) || errors(a, q, e))
			break;
		double m = max_abs(e, a->ncells);
		/* least squares: its own minimum; minimax: the smallest max seen */
		if (!minimax || m < best_max) {
			best_max = m;
			memcpy(best, q, sizeof best);
		}
		double total = 0;
		for (int c = 0; c < a->ncells; c++)
			total += w[c] *= fabs(e[c]);
		if (!(total > 0) || !isfinite(total))
			break;
		for (int c = 0; c < a->ncells; c++)
			w[c] /= total;
	}
	for (int c = 0; c < a->ncells; c++)
		a->u[c] = 1.0;
	memo_put(a, best, best_max);
	memcpy(p, best, sizeof best);
	if (max_err)
		*max_err = best_max;
	free(e);
	free(w);
	return 0;
}
