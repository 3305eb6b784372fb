/*
 * pareto.h — the one Pareto scan of the search layer: the points that no
 * cheaper-or-equal point beats, by increasing cost. Used by the search's
 * screening front, the env halves' compositions and the refitted front.
 *
 * Ties are broken on a key (a candidate's canonical text), never on the
 * order points arrived in: the same set gives the same front whatever the
 * thread count or the order of a merge.
 */
#ifndef FIT_SEARCH_PARETO_H
#define FIT_SEARCH_PARETO_H

#include <stddef.h>

typedef struct bk_pareto_pt {
	double cost, err; /* err already rounded to the comparison resolution by the caller */
	const char *key;  /* tie-break (compared with strcmp); NULL sorts first */
	size_t id;        /* the caller's index, carried along */
} bk_pareto_pt;

/* Sorts pt[0..n) by (cost, err, key) and moves the front to pt[0..k):
 * each of them has a smaller err than every point before it in that
 * order. Returns k. NaN errors are never on the front. */
size_t bk_pareto_scan(bk_pareto_pt *pt, size_t n);

#endif
