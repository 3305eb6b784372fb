/*
 * albfit.c — constants fitted to the directional albedo (albfit.h). Blocks
 * of whole cells, so that each block's residuals are its cells' albedo
 * errors: the form and its Jacobian over the block's samples, then summed
 * per cell with the cell's measure.
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

struct bk_albfit {
	const bk_samples *s;
	const bk_form *f;
	int np, nblocks, ncells;
	size_t *lo;     /* first sample of each block */
	int *nsamp;     /* samples in each block */
	int *size;      /* cells in each block (its residuals) */
	int *first;     /* first cell (0..ncells) of each block */
	int *cell;      /* per sample: its cell, 0..ncells */
	double *u;      /* sqrt of each cell's weight (minimax changes it) */
	double *scratch;/* per block: values and Jacobian of its samples (blocks never share) */
	size_t *soff;
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
	a->cell = malloc(sizeof(int) * (s->n ? s->n : 1));
	a->lo = malloc(sizeof(size_t) * cap);
	a->nsamp = malloc(sizeof(int) * cap);
	a->size = malloc(sizeof(int) * cap);
	a->first = malloc(sizeof(int) * cap);
	a->soff = malloc(sizeof(size_t) * cap);
	a->u = malloc(sizeof(double) * cap);
	a->scratch = malloc(sizeof(double) * (s->n ? s->n : 1) * (size_t)(1 + np));
	if (!a->cell || !a->lo || !a->nsamp || !a->size || !a->first || !a->soff || !a->u || !a->scratch) {
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
			a->ncells++;
		}
		a->cell[i] = a->ncells - 1;
	}
	free(seen);
	/* blocks of whole cells, about BLOCK samples each */
	for (size_t i = 0; i < s->n;) {
		size_t j = i;
		while (j < s->n && (j - i < BLOCK || a->cell[j] == a->cell[j - 1]))
			j++;
		int b = a->nblocks++;
		a->lo[b] = i;
		a->nsamp[b] = (int)(j - i);
		a->first[b] = a->cell[i];
		a->size[b] = a->cell[j - 1] - a->cell[i] + 1;
		a->soff[b] = i * (size_t)(1 + np);
		i = j;
	}
	return a;
}

void bk_albfit_free(bk_albfit *a)
{
	if (!a)
		return;
	free(a->cell);
	free(a->lo);
	free(a->nsamp);
	free(a->size);
	free(a->first);
	free(a->soff);
	free(a->u);
	free(a->scratch);
	free(a);
}

static int residuals(void *ctx, int block, const double *p, double *r, double *jac)
{
	bk_albfit *a = ctx;
	const bk_samples *s = a->s;
	size_t lo = a->lo[block];
	int m = a->nsamp[block], np = a->np, npf = bk_form_nparams(a->f);
	const double *in[BK_IN_COUNT];
	for (int k = 0; k < BK_IN_COUNT; k++)
		in[k] = s->in[k] ? s->in[k] + lo : NULL;
	double *v = a->scratch + a->soff[block], *jf = v + m;
	if (jac ? bk_form_eval_diff(a->f, (size_t)m, in, p, v, jf) : bk_form_eval(a->f, BK_F64, (size_t)m, in, p, v))
		return -1;
	int nc = a->size[block], c0 = a->first[block];
	for (int c = 0; c < nc; c++)
		r[c] = 0;
	if (jac)
		memset(jac, 0, sizeof(double) * (size_t)nc * np);
	for (int i = 0; i < m; i++) {
		int c = a->cell[lo + i] - c0;
		double w = s->measure[lo + i];
		r[c] += w * (v[i] - s->y[lo + i]);
		if (jac)
			for (int j = 0; j < npf && j < np; j++)
				jac[(size_t)c * np + j] += w * jf[(size_t)i * npf + j];
	}
	int bad = 0;
	for (int c = 0; c < nc; c++) {
		double u = a->u[c0 + c];
		r[c] *= u;
		bad |= !isfinite(r[c]);
		if (jac)
			for (int j = 0; j < np; j++)
				jac[(size_t)c * np + j] *= u;
	}
	return bad ? -1 : 0;
}

/* The cells' errors at p into e (ncells), unweighted. */
static int errors(bk_albfit *a, const double *p, double *e)
{
	const bk_samples *s = a->s;
	double *v = a->scratch;
	const double *in[BK_IN_COUNT];
	for (int k = 0; k < BK_IN_COUNT; k++)
		in[k] = s->in[k];
	if (bk_form_eval(a->f, BK_F64, s->n, in, p, v))
		return -1;
	for (int c = 0; c < a->ncells; c++)
		e[c] = 0;
	for (size_t i = 0; i < s->n; i++)
		e[a->cell[i]] += s->measure[i] * (v[i] - s->y[i]);
	return 0;
}

static double max_abs(const double *e, int n)
{
	double m = 0;
	for (int c = 0; c < n; c++)
		m = isfinite(e[c]) ? fmax(m, fabs(e[c])) : HUGE_VAL;
	return m;
}

double bk_albfit_max(bk_albfit *a, const double *p)
{
	double *e = malloc(sizeof(double) * a->ncells), m = HUGE_VAL;
	if (e && errors(a, p, e) == 0)
		m = max_abs(e, a->ncells);
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
	if (!e || !w || errors(a, p, e)) {
		free(e);
		free(w);
		return -1;
	}
	double best[BK_MAX_PARAMS], q[BK_MAX_PARAMS], best_max = max_abs(e, a->ncells);
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
	memcpy(p, best, sizeof best);
	if (max_err)
		*max_err = best_max;
	free(e);
	free(w);
	return 0;
}
