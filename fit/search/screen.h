/*
 * screen.h — screening (internal to the search): each candidate of a batch
 * fitted on the screening samples with the fast solver (few iterations,
 * deterministic starts), its values judged by the one constraint predicate
 * (search/constraint.h) and scored by the objective, rounded to
 * BK_SEARCH_ERR_BITS. A batch runs on the search's threads; each candidate's
 * result depends on it alone, so any thread count gives the same bytes.
 */
#ifndef FIT_SEARCH_SCREEN_H
#define FIT_SEARCH_SCREEN_H

#include "search/search_int.h"

/* Fits c (its text, text_b and np set) and fills p, status, err and the
 * metrics. seed_p: the first start (a seed's published constants, a child's
 * inherited ones), or NULL for the default starts alone. */
void bk_screen_one(const bk_search *s, bk_cand *c, const double *seed_p);

/* bk_screen_one of c[i] from seed_p[i], i < n, on s->o.threads threads. */
void bk_screen_batch(const bk_search *s, bk_cand *c, const double *const *seed_p, size_t n);

#endif
