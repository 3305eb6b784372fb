/*
 * generate.h — generation (internal to the search): the built-in
 * generators the default schedule runs (schedule.h), each a
 * bk_search_generator (fit/search.h): `seeds`, the seeds in the order
 * given; `enumeration`, every canonical tree up to enum_size nodes, drawn
 * bottom-up as the fits need them (a pair's tree as A, as B and as a shared
 * feature); `neighbours`, those of the archive's leaders (not for pairs);
 * `children` of archive members by mutation (70 %) or crossover, a parent
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
	size_t want; /* room for this many (while a generator makes: its share, schedule.c) */
	size_t n;    /* made */
	/* called (when set) with n each time a child or neighbour is whole: the
	 * screening may start on it while the rest is made (screen.h) */
	void (*made)(void *ctx, size_t n);
	void *made_ctx;
} bk_gen_batch;

/* What a generator's make is handed (bk_search_sink in fit/search.h): the
 * search and its batch, b->want being the generator's share of it while it
 * runs (schedule.c). */
struct bk_search_sink {
	bk_search *s;
	bk_gen_batch *b;
};

/* The built-in generators; their state is the search's own (state NULL).
 * seeds is over after its one batch (its room: set to the seeds' count by
 * the schedule), enumeration when its trees or enum_max fits are used up,
 * neighbours never holds its stage open (and makes none for pairs),
 * children is over when the batch comes out empty. */
extern const bk_search_generator bk_gen_seeds, bk_gen_enumeration, bk_gen_neighbours, bk_gen_children;

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

/* The candidate of trees t (canonical) into batch b, its first fit from
 * start (as many values as it has parameters; NULL: the default starts),
 * the screening told it is whole (b->made): what bk_search_offer takes
 * after its checks, and what the semantic generator offers. 1 taken, 0 not
 * (seen before, over a limit), -1 out of memory; b must have room. */
int bk_gen_take(bk_search *s, bk_gen_batch *b, const bk_expr *t, const double *start);

#endif
