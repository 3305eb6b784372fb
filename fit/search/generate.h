/*
 * generate.h — generation (internal to the search): the batch of new
 * candidates a step fits. Phase by phase: the seeds in the order given;
 * every canonical tree up to enum_size nodes, drawn bottom-up as the fits
 * need them (a pair's tree as A, as B and as a shared feature); then the
 * neighbours of the archive's leaders (up to half a generation) and
 * children of archive members by mutation (70 %) or crossover, a parent
 * being a cost level drawn uniformly and a member biased to its best.
 * A candidate is new when its canonical text's key is not in the cache
 * (s->seen): a form seen before is never fitted twice.
 */
#ifndef FIT_SEARCH_GENERATE_H
#define FIT_SEARCH_GENERATE_H

#include "search/search_int.h"

/* Room for one step's batch: the candidates, the first start of each fit
 * (NULL: the default starts) and the inherited starts they may point into. */
typedef struct bk_gen_batch {
	bk_cand *c;
	const double **start;
	double (*inherit)[BK_MAX_PARAMS];
	size_t want; /* room for this many */
	size_t n;    /* made */
	/* called (when set) with n each time a child or neighbour is whole: the
	 * screening may start on it while the rest is made (screen.h) */
	void (*made)(void *ctx, size_t n);
	void *made_ctx;
} bk_gen_batch;

/* How many candidates the next step makes at most (a generation; every seed
 * in the first step, however small the generation). */
size_t bk_gen_want(const bk_search *s);

/* Makes the next batch into b (b->n of them, each new to the cache and
 * within the limits), moving s->phase on as the seeds, the enumeration and
 * the evolution are used up (3: nothing new can be made). 0, or -1 when out
 * of memory (b->n: those made, to be freed). */
int bk_gen_batch_make(bk_search *s, bk_gen_batch *b);

/* Tree idx of the enumeration (idx never below the last one drawn: the
 * enumeration is read in order). 1 with it in *t, 0 when it has fewer trees
 * (the enumerator is then freed), -1 when out of memory. */
int bk_gen_enum_tree(bk_search *s, size_t idx, bk_expr *t);

/* One child of the archive's members (s->nlv > 0) into t (canonical, within
 * the tree grammar's limits). 0, or non-zero when none was made this try. */
int bk_gen_child(bk_search *s, bk_expr *t);

/* Candidate c from trees t (canonical): scale, shape, text, cost. 1 if it is
 * new and within the limits (then in the cache), 0 if not, -1 when out of
 * memory. */
int bk_gen_prepare(bk_search *s, const bk_expr *t, bk_cand *c);

#endif
