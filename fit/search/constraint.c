/*
 * constraint.c — the constraint predicate (constraint.h).
 */
#include "search/constraint.h"

int bk_search_admissible(const bk_search_options *o, const bk_samples *sm, const double *v)
{
	if (o->nonneg)
		for (size_t i = 0; i < sm->n; i++)
			if (v[i] < 0)
				return 0;
	if (o->env_bound && sm->ncomp == 2) {
		size_t na = sm->start[1];
		for (size_t i = 0; i < na; i++)
			if (v[i] < -BK_SEARCH_ENV_SLACK || v[na + i] < -BK_SEARCH_ENV_SLACK ||
			    v[i] + v[na + i] > 1 + BK_SEARCH_ENV_SLACK)
				return 0;
	}
	return 1;
}
