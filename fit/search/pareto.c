/*
 * pareto.c — the Pareto scan (pareto.h): one sort, one pass keeping each point
 * that beats the best error seen at lower or equal cost.
 */
#include "search/pareto.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int by_cost_err_key(const void *pa, const void *pb)
{
	const bk_pareto_pt *a = pa, *b = pb;
	if (a->cost != b->cost)
		return a->cost < b->cost ? -1 : 1;
	if (a->err != b->err) /* NaN last: it compares false both ways, so order it by hand */
		return isnan(a->err) ? 1 : isnan(b->err) ? -1 : a->err < b->err ? -1 : 1;
	if (!a->key || !b->key)
		return (a->key != NULL) - (b->key != NULL);
	return strcmp(a->key, b->key);
}

size_t bk_pareto_scan(bk_pareto_pt *pt, size_t n)
{
	qsort(pt, n, sizeof *pt, by_cost_err_key);
	double best = HUGE_VAL;
	size_t k = 0;
	for (size_t i = 0; i < n; i++)
		if (pt[i].err < best) { /* false for NaN */
			best = pt[i].err;
			bk_pareto_pt t = pt[k];
			pt[k++] = pt[i];
			pt[i] = t;
		}
	return k;
}
