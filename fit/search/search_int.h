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
 *   semantic.c  the semantic generator (semantic backpropagation)
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

/* The parameter vectors a fingerprint evaluates at (unique.c). */
#define UNIQUE_VECTORS 4

/* The enumeration's unique forms (unique.h): the probes a fingerprint reads
 * and the fingerprints fitted, each with the least cost it was fitted at
 * (open addressing, 0 marks a free slot). */
typedef struct bk_unique_probes {
	size_t m, stride; /* m probes, screening sample i stride mod n (unique.c) */
	double *in[BK_IN_COUNT];
	double theta[UNIQUE_VECTORS][BK_MAX_PARAMS];
	uint64_t *fp;
	double *cost;
	size_t cap, n;
} bk_unique_probes;

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
	bk_form **seed_form, **seed_form_b; /* copies of the options' seed_forms; NULL: parse the text */
	double (*seed_p)[BK_MAX_PARAMS];
	uint64_t fingerprint;     /* this island's options (checkpoints) */
	uint64_t fingerprint_all; /* what all islands share: not the seed or the island (migrants) */
	bk_cand *cand;
	size_t n, cap;
	bk_hashset seen; /* hashes of the canonical texts tried (fitted or over a limit) */
	bk_hashset nb_done; /* candidate index * 3 + pass + 1 of each neighbour list tried whole (generate.c) */
	bk_level *lv;
	int nlv;
	/* the candidates that hold their forms (archive.c, keep_forms): the OK
	 * ones no other dominates, as many as the front is long */
	size_t *held, nheld, held_cap;
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
	bk_unique_probes uq; /* the enumeration's twins (unique.h) */
	/* the enumeration's candidates by the size of their tree (a pair's tree
	 * counts once for each of its three kinds): drawn (this island's share),
	 * left out as twins, fitted; and the largest size all of whose
	 * candidates were drawn (the certificate: search.h) */
	long enum_drawn[BK_EXPR_MAX + 1], enum_twins[BK_EXPR_MAX + 1], enum_fitted[BK_EXPR_MAX + 1];
	int enum_complete;
	double dedup_seconds; /* CPU time of the fingerprints (not in checkpoints: a measurement) */
	long dedup_calls;
	int enum_cut; /* the enumerator ended at its most trees kept (expr.h) */
	int share_failed; /* split over ranks: a share failed (a step's fits or a window looked at ahead) */
	/* split over ranks (--split-fits): the enumeration's next trees drawn
	 * ahead (look_tree: those of index look_t0 on, look_nt of them) and what
	 * each position's candidate is before anything that depends on the order
	 * (look: positions look_p0 on, look_np of them), each rank having
	 * fingerprinted its share (generate.c, look_ahead) */
	struct bk_enum_look *look;
	bk_expr *look_tree;
	size_t look_t0, look_nt, look_p0, look_np;
	/* a white-box tests' hook: a tree of the enumeration for which it returns
	 * non-zero is left out, as if the grammar did not have it (the
	 * certificate's negative control, tests/test_search_unique.c); NULL in
	 * every search the tool makes */
	int (*enum_leave_out)(void *ctx, const bk_expr *tree);
	void *enum_leave_ctx;
	/* the twin test's audit (bk_search_on_twin); NULL in every search the
	 * tool makes */
	bk_search_twin_fn twin_audit;
	void *twin_audit_ctx;
};

#endif
