/*
 * constraint.h — the one constraint predicate of the search layer: what a
 * generated form must satisfy on the samples it is scored on, the same on
 * the screening grid (the search) and on the full samples (the front's
 * refit). Published seeds are exempt by the caller's choice, not here.
 */
#ifndef FIT_SEARCH_CONSTRAINT_H
#define FIT_SEARCH_CONSTRAINT_H

#include "search.h"

/* 1 when the values v (sm->n of them, components in the samples' order)
 * meet o's constraints: with o->nonneg no value below 0; with o->env_bound
 * and a pair (sm->ncomp == 2), A >= 0, B >= 0 and A + B <= 1 at every
 * sample, to BK_SEARCH_ENV_SLACK. NaN values are not judged here (the
 * caller's finiteness check owns them). 0 otherwise. */
int bk_search_admissible(const bk_search_options *o, const bk_samples *sm, const double *v);

#endif
