/*
 * halves.h — --env-form mix: the two halves of the environment BRDF first.
 *
 * f0 A + B is linear in f0: it is mix(B, S, f0) with S = A + B (the albedo,
 * f0 = 1) and B (f0 = 0), exactly. Each half is a smooth function of (NoV, r)
 * that a cheap form fits well (S within 0.013 rmse at cost 7, B within 0.008),
 * while f0 A + B as one form is harder to grow: so 3/8 of the budget
 * searches S, 3/8 B (the same grammar without f0, the same seed), and the
 * pairs of their fronts, as mix(B, S, f0) with B's parameters after S's and
 * each half's fitted constants as the start, seed the search of the forms in
 * f0 with the last quarter (measured: 1,200,000 fits split 1/4, 1/4, 1/2 put
 * only compositions on the front at cost <= 15; the halves' fits are both
 * where the gain is and faster, 256 screening samples against 3 x 256 per
 * form, and no f0). Only the compositions on the Pareto front of (cost after
 * sharing, the halves' combined rmse) are kept: the others are dominated
 * before any fit. They are held to the constraints as generated forms are,
 * and listed in no catalog row.
 */
#ifndef FIT_SEARCH_HALVES_H
#define FIT_SEARCH_HALVES_H

#include "search.h"
#include "search/seeds.h"

#define BK_HALVES_MAX 24   /* compositions kept */
#define BK_HALVES_FRONT 48 /* members of each half's front composed */

/* A member of one half's front: its tree (f0 absent), fitted constants and
 * rounded error. */
typedef struct bk_half {
	bk_expr tree;
	int np;
	double p[BK_MAX_PARAMS], err;
} bk_half;

typedef struct bk_halves {
	char *text[BK_HALVES_MAX], name[BK_HALVES_MAX][32]; /* "mix(B, S, f0)", "halves K" */
	double p[BK_HALVES_MAX][BK_MAX_PARAMS];
	int n;
	long evals; /* the two searches' fits */
	/* the seeds of the search in f0 (bk_halves_seed): the caller's, then the compositions */
	const char *seed_text[BK_SEEDS_MAX + BK_HALVES_MAX], *seed_text_b[BK_SEEDS_MAX + BK_HALVES_MAX];
	const bk_form *seed_form[BK_SEEDS_MAX + BK_HALVES_MAX], *seed_form_b[BK_SEEDS_MAX + BK_HALVES_MAX]; /* the
	                  caller's seeds' forms (bk_seeds), NULL for a composition (parsed by the search) */
	const char *seed_name[BK_SEEDS_MAX + BK_HALVES_MAX];
	double seed_p[BK_SEEDS_MAX + BK_HALVES_MAX][BK_MAX_PARAMS];
} bk_halves;

/* Progress of the two searches: step after each step of half ("S = A + B"
 * or "B", the same pointer for all the steps of one half; it cannot stop
 * the search: the budget is the halves'), done at its end. Either may be
 * NULL. */
typedef struct bk_halves_report {
	void (*step)(void *ctx, const char *half, const bk_search *s);
	void (*done)(void *ctx, const char *half, long fits, size_t front);
	void *ctx;
} bk_halves_report;

/* The compositions mix(B, S, f0) of the fronts s[0..ns) of S and b[0..nb)
 * of B: those within max_params and max_cost (cost of the whole text with
 * the weights simple, complex), then their Pareto front by (cost, estimated
 * rmse sqrt((eS^2 + eB^2)/2), text), at most BK_HALVES_MAX, into hv (its
 * compositions replaced). 0, or -1 out of memory. */
int bk_halves_compose(const bk_half *s, size_t ns, const bk_half *b, size_t nb, int max_params, double max_cost,
                      double simple, double complex, bk_halves *hv);

/* Both searches on the screening grid screen (the target options of the
 * search in f0: env with env_f0_form; each half at its one f0) with the
 * options o of the search in f0 (its seeds ignored; 3/8 of o->evals each,
 * max_cost - 2, no f0 input), then bk_halves_compose. 0, or -1 (message). */
int bk_halves_run(const bk_search_options *o, const bk_target_options *screen, const bk_halves_report *rep,
                  bk_halves *hv, char *err, size_t errlen);

/* The seeds of the search in f0: sd's (which alone are exempt from the
 * constraints), then the compositions; the halves' fits off the budget.
 * Points o at hv's arrays (hv must outlive the search). */
void bk_halves_seed(bk_halves *hv, const bk_seeds *sd, bk_search_options *o);

void bk_halves_free(bk_halves *hv);

#endif
