/*
 * islands.h — the search's island protocol: rounds of `migrate` fits per
 * island, after each a migration round a ring, at the end the merge into
 * island 0. The processes and how bytes travel between them are the
 * transport's (a callback table: analysis/cli/islands.h gives one for one
 * process and one over MPI; a test gives a fake); checkpoints, progress and
 * the decision to stop are the caller's, at the end of each round.
 *
 * Every call is collective: each island makes the same calls in the same
 * order. A failure is agreed (every island returns -1 together), each with
 * its own message in err (empty where the island itself did nothing wrong):
 * the caller gathers them (the transport's gather_text).
 */
#ifndef FIT_SEARCH_ISLANDS_H
#define FIT_SEARCH_ISLANDS_H

#include "search.h"

#define BK_ISLANDS_FRONT 48 /* front members a migration picks from */

typedef struct bk_islands_transport {
	int rank, size;
	/* sends buf[0..n) to rank + 1, *in (malloc'd, NUL-terminated) what rank - 1 sent: 0, or -1 */
	int (*ring)(const char *buf, size_t n, char **in, size_t *nin);
	/* to rank 0, rank by rank in order: take(ctx, r, bytes, n) on rank 0 */
	int (*gather)(const char *buf, size_t n, int (*take)(void *ctx, int rank, const char *in, size_t n), void *ctx);
	long (*sum)(long v);
	int (*any)(int v);
} bk_islands_transport;

/* The seed of island r > 0: splitmix64 of (seed, r), folded to 32 bits as
 * --seed is; distinct islands draw distinct streams (island 0 keeps seed). */
unsigned long bk_islands_seed(unsigned long seed, int r);

/* The indices of up to `migrants` members of s's screening front, spread
 * evenly over it, its ends included: what an island sends round the ring.
 * Returns how many (<= BK_ISLANDS_FRONT). */
size_t bk_islands_pick(const bk_search *s, int migrants, size_t *pick);

/* One migration: bk_islands_pick's members to the next island, the previous
 * one's imported. 0, or -1 (agreed). */
int bk_islands_migrate(bk_search *s, const bk_islands_transport *t, int migrants, char *err, size_t errlen);

/* After every round's migration, on every island: round (1-based, resumes
 * counting on), more (agreed: some island has budget left). Returns 0 to go
 * on, 1 to end after this round (must be agreed: decide it with t->any), -1
 * a failure (agreed, already reported). */
typedef int (*bk_islands_round_end)(void *ctx, long round, int more);

/* Rounds from round0 + 1: each steps s (bk_search_run) until it holds
 * round x migrate fits or its budget is spent, then migrates, then calls
 * round_end. Returns 0 when round_end ended it, or a failure (agreed; err:
 * this island's message or empty): BK_ISLANDS_FAIL_SEARCH (a step),
 * BK_ISLANDS_FAIL_MIGRATION, BK_ISLANDS_FAIL_CALLER (round_end's -1). */
enum { BK_ISLANDS_FAIL_SEARCH = -1, BK_ISLANDS_FAIL_MIGRATION = -2, BK_ISLANDS_FAIL_CALLER = -3 };
int bk_islands_run(bk_search *s, const bk_islands_transport *t, long migrate, int migrants, long round0,
                   bk_islands_round_end round_end, void *ctx, char *err, size_t errlen);

/* The merge: every island's candidates (fronts_only: its screening front
 * alone) into island 0's search, in island order (a candidate found on
 * several islands is kept as the lowest island found it); island 0 sends
 * nothing. *bytes: the bytes sent in all. 0, or -1 (agreed where the sends
 * could not be made; a failed import is island 0's, err says which). */
int bk_islands_merge(bk_search *s, const bk_islands_transport *t, int fronts_only, long *bytes, char *err,
                     size_t errlen);

#endif
