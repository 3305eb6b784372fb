/*
 * search_int.h — the search's state, shared by its parts (internal to
 * fit/search/: tests/layers.sh refuses it, and every header that includes
 * it, anywhere else). The public face is fit/search.h.
 *
 * The parts, each with its header, and the one way their calls run:
 *   driver.c    new, free, step (schedule -> screen -> merge, overlapped:
 *               screen.h), run
 *   schedule.c  the schedule: its stages, the batch a stage's generators
 *               make, their checkpoint lines; offering a candidate
 *   generate.c  the built-in generators: seeds, enumeration, neighbours,
 *               children
 *   screen.c    fitting and scoring a batch on threads
 *   archive.c   the MAP-Elites levels, the merge, the front
 *   state.c     checkpoints and migrants (save, load, export, import)
 *   cand.c      a candidate's text, cost and cache key (used by all)
 */
#ifndef FIT_SEARCH_SEARCH_INT_H
#define FIT_SEARCH_SEARCH_INT_H

#include "search.h"

#include <stdint.h>

/* One cost level of the archive: the per_level best candidates of cost
 * floor(cost) == cost. */
typedef struct bk_level {
	int cost;     /* floor(cost) */
	size_t *idx;  /* candidates, best first */
	int n;
} bk_level;

/* One generator of the schedule: its table (the name copied), the share
 * of the batch it fills up to, its stage. */
typedef struct bk_sched_gen {
	bk_search_generator g;
	char name[32];
	double share;
	int stage;
} bk_sched_gen;

struct bk_search {
	bk_search_options o;
	char **seed_text, **seed_text_b, **seed_name; /* copies */
	double (*seed_p)[BK_MAX_PARAMS];
	uint64_t fingerprint;     /* this island's options (checkpoints) */
	uint64_t fingerprint_all; /* what all islands share: not the seed or the island (migrants) */
	bk_cand *cand;
	size_t n, cap;
	bk_hashset seen; /* hashes of the canonical texts tried (fitted or over a limit) */
	bk_hashset nb_done; /* candidate index * 3 + pass + 1 of each neighbour list tried whole (generate.c) */
	bk_level *lv;
	int nlv;
	bk_rng rng;
	long evals;
	bk_sched_gen *sched; /* the schedule (schedule.h): generators stage by stage, in order */
	int nsched, nstages;
	int stage;       /* the current stage (nstages: the search is over) */
	int begun;       /* stepped or loaded: the schedule is fixed */
	size_t enum_pos; /* the enumeration's state (generate.c): trees taken, x3 for a pair */
	bk_grammar tree_g; /* the grammar of one tree: a pair's halves get half the parameters */
	bk_grammar feat_g; /* the grammar of a pair's shared feature */
	bk_grammar enum_g; /* the grammar of an enumerated tree (room for its scale) */
	bk_expr_enum *gen; /* the enumeration, drawn as the search goes; NULL once done */
	bk_expr cur;       /* the last tree drawn from it */
	size_t drawn;      /* how many were drawn */
};

#endif
