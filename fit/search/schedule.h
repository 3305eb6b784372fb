/*
 * schedule.h — the search's schedule (internal): a list of stages, each a
 * list of generators (bk_search_generator, fit/search.h) sharing a step's
 * batch, each filling it up to its share. The default schedule is the
 * built-in generators (generate.h) in three stages: seeds; enumeration;
 * neighbours (half a generation) + children (the rest). A stage is over
 * after the batch in which every one of its generators said so, the search
 * after its last stage (s->stage == s->nstages).
 *
 * In a checkpoint (state.c) the schedule is the line "stage NAME" (the
 * current stage's generators' names joined by '+', "done" after the last)
 * and for each generator in order "generator NAME" followed by the lines of
 * its own state (its save).
 */
#ifndef FIT_SEARCH_SCHEDULE_H
#define FIT_SEARCH_SCHEDULE_H

#include "search/generate.h"

/* The default schedule into s (a new search). 0, or -1 when out of memory. */
int bk_schedule_default(bk_search *s);

/* Frees the schedule and every generator's state. */
void bk_schedule_free(bk_search *s);

/* How many candidates the next step makes at most: a generation, or more
 * where a generator of the current stage needs more room (every seed in
 * their step, however small the generation). */
size_t bk_schedule_want(const bk_search *s);

/* The most candidates any step of this schedule makes. */
size_t bk_schedule_most(const bk_search *s);

/* Makes the current stage's batch into b (b->n of them, each new to the
 * cache and within the limits), moving s->stage on when the stage is over.
 * 0, or -1 when out of memory (b->n: those made, to be freed). */
int bk_schedule_make(bk_search *s, bk_gen_batch *b);

/* The checkpoint's schedule lines (see above). 0, or -1. */
int bk_schedule_save(const bk_search *s, FILE *f);

/* Reads them back into s (s->evals read before): the stage one of this
 * schedule's (the first only before any fit), every generator named in
 * order, each generator's state read and checked by its load. 0, or -1
 * with what is wrong in err. */
int bk_schedule_load(bk_search *s, FILE *f, char *err, size_t errlen);

#endif
