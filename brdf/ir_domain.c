/*
 * ir_domain.c — a form over a grid of its inputs' domain (brdf.h): whether it
 * has a value anywhere (in double), and whether a precision code is emitted
 * in can hold that value anywhere. Both read the same grid, so a form the
 * first lets through is judged by the second on the same samples.
 */
#include "ir.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* The grid: each input the form reads in {0, 1e-3, 0.3, 0.7, 1} (the ends of
 * [0, 1] and inside), a = r*r when it reads both. */
static const double grid_vals[] = {0, 1e-3, 0.3, 0.7, 1};
enum { NV = sizeof grid_vals / sizeof grid_vals[0] };

typedef struct grid {
	size_t n;                     /* samples */
	double *buf;                  /* BK_IN_COUNT input columns of n, then 2 result columns */
	const double *in[BK_IN_COUNT];
	int tie;                      /* a = r*r, a not an axis of its own */
} grid;

static int grid_make(const bk_form *f, grid *g)
{
	unsigned in = f->inputs;
	int axis[BK_IN_COUNT], na = 0;
	g->tie = (in >> BK_IN_R & 1) && (in >> BK_IN_A & 1);
	for (int i = 0; i < BK_IN_COUNT; i++)
		if ((in >> i & 1) && !(i == BK_IN_A && g->tie))
			axis[na++] = i;
	g->n = 1;
	for (int k = 0; k < na; k++)
		g->n *= NV;
	size_t n = g->n;
	g->buf = malloc(sizeof(double) * n * (BK_IN_COUNT + 2));
	if (!g->buf)
		return -1;
	for (int i = 0; i < BK_IN_COUNT; i++)
		g->in[i] = g->buf + (size_t)i * n;
	for (size_t s = 0; s < n; s++) {
		size_t rest = s;
		for (int k = 0; k < na; k++, rest /= NV)
			g->buf[(size_t)axis[k] * n + s] = grid_vals[rest % NV];
		if (g->tie)
			g->buf[(size_t)BK_IN_A * n + s] = g->buf[(size_t)BK_IN_R * n + s] * g->buf[(size_t)BK_IN_R * n + s];
	}
	return 0;
}

/* "NoV = 0.3, r = 1" for sample s ("it reads no input" when it reads none);
 * returns the length written, as snprintf. */
static size_t grid_where(const bk_form *f, const grid *g, size_t s, char *what, size_t len)
{
	size_t at = 0;
	what[0] = '\0';
	for (int i = 0; i < BK_IN_COUNT && at < len; i++)
		if ((f->inputs >> i & 1) && !(i == BK_IN_A && g->tie))
			at += (size_t)snprintf(what + at, len - at, "%s%s = %g", at ? ", " : "", bk_input_name((bk_input)i),
			                       g->buf[(size_t)i * g->n + s]);
	if (!at)
		at = (size_t)snprintf(what, len, "it reads no input");
	return at;
}

int bk_form_nowhere_finite(const bk_form *f, const double *params, char *what, size_t len)
{
	if (f->nparams > 0 && !params)
		return -1;
	grid g;
	if (grid_make(f, &g))
		return -1;
	double *out = g.buf + (size_t)BK_IN_COUNT * g.n;
	int none = bk_form_eval(f, BK_F64, g.n, g.in, params, out) == 0;
	for (size_t s = 0; none && s < g.n; s++)
		none = !isfinite(out[s]);
	if (none && what && len) {
		size_t at = grid_where(f, &g, 0, what, len);
		if (at < len)
			snprintf(what + at, len - at, ": %s", isnan(out[0]) ? "NaN" : out[0] > 0 ? "+inf" : "-inf");
	}
	free(g.buf);
	return none;
}

/* What prec makes of an exact (double) value x held as h: "+inf", "NaN",
 * "0", "subnormal", or NULL when it holds it (finite; normal unless x is 0).
 * The smallest normal is where GPUs flush: 2^-14 in half, 2^-126 in single. */
static const char *lost(double x, double h, bk_precision prec)
{
	double tiny = prec == BK_F16 ? 0x1p-14 : 0x1p-126;
	if (isnan(h))
		return "NaN";
	if (isinf(h))
		return h > 0 ? "+inf" : "-inf";
	if (x != 0 && h == 0)
		return "0";
	return x != 0 && fabs(h) < tiny ? "subnormal" : NULL;
}

int bk_form_range_lost(const bk_form *f, const double *params, bk_precision prec, char *what, size_t len)
{
	if ((f->nparams > 0 && !params) || (prec != BK_F32 && prec != BK_F16))
		return -1;
	grid g;
	if (grid_make(f, &g))
		return -1;
	double *x = g.buf + (size_t)BK_IN_COUNT * g.n, *h = x + g.n;
	int every = bk_form_eval(f, BK_F64, g.n, g.in, params, x) == 0 &&
	            bk_form_eval(f, prec, g.n, g.in, params, h) == 0;
	size_t counted = 0, first = 0;
	/* A sample counts where double has a value: finite, and non-zero unless
	 * prec loses even a 0 (inf - inf); it is lost where prec does not hold it. */
	for (size_t s = 0; every && s < g.n; s++) {
		if (!isfinite(x[s]) || (x[s] == 0 && isfinite(h[s])))
			continue;
		every = lost(x[s], h[s], prec) != NULL;
		if (!counted++)
			first = s;
	}
	every = every && counted > 0;
	if (every && what && len) {
		size_t at = grid_where(f, &g, first, what, len);
		if (at < len)
			snprintf(what + at, len - at, ": %.9g is %s in %s precision", x[first], lost(x[first], h[first], prec),
			         prec == BK_F16 ? "half" : "single");
	}
	free(g.buf);
	return every ? (int)counted : 0; /* at most 5^BK_IN_COUNT */
}
