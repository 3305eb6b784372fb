/*
 * test_search_semantic.c — the `semantic` generator (fit/search/semantic.c):
 * semantic backpropagation finds the subtree a level's best lacks.
 *
 * The planted target 0.3/(LoH^2 + a) and one seed, p0/(p1 + LoH), a subtree
 * away from it: the values the seed's LoH would need for the whole to be the
 * target are p0 (LoH^2 + a)/0.3 - p1, affine in LoH^2 + a, a tree of the
 * library (4 nodes, no constant). So the first generation after the seed
 * (no enumeration) must fit p0/(p1 + (sq(LoH) + a)) or a spelling of it to
 * the planted error, made by the semantic generator: the neighbours of the
 * seed (p*x, p + x, mix(u, v, x), x*LoH, mix(p, p', in), sq(x)) are all one
 * step from it and none is the target, and the children are too few to
 * find it by chance. The negative control: the same search with
 * semantic = 0 has no such fit in that generation.
 *
 * And a pair: the planted 0.3/(0.7 LoH^2 + 1.3 LoH + 0.2) and the same
 * seed: the values wanted of its LoH are affine in 0.7 LoH^2 + 1.3 LoH,
 * which no library tree scaled and offset is (LoH (LoH + 1.857) has no
 * literal 1.857; LoH (LoH + 2) comes near), but sq(LoH) and LoH together
 * are, at any constants of the seed: p0/(p1 + (p2 sq(LoH) + p3 LoH)), the
 * planted form, in one generation. Controls: semantic = 0, and (by hand)
 * the pairs left out (SEM_PAIR_POOL 0).
 */
#include "fixture_search.h"

#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

/* A planted target, the one seed a subtree away, and the generations
 * after it (no enumeration). */
typedef struct plant {
	const char *target, *seed;
	double loh_lo;
	int with_r, nx, np, size, generations;
} plant;

static const plant SUBTREE = {"0.3/(LoH*LoH + r*r)", "p0/(p1 + LoH)", 0.1, 1, 8, 3, 12, 1};
static const plant PAIR = {"0.3/(0.7*LoH*LoH + 1.3*LoH + 0.2)", "p0/(p1 + LoH)", 0.1, 0, 64, 4, 16, 1};

static void options(const plant *pl, bk_samples *sm, bk_search_options *o, double semantic)
{
	fx_planted(pl->target, pl->loh_lo, pl->with_r, pl->nx, sm);
	fx_plain_options(o, sm, 1u << BK_IN_LOH | (pl->with_r ? 1u << BK_IN_R | 1u << BK_IN_A : 0), pl->np, pl->size);
	o->enum_size = 0;
	o->seeds = &pl->seed;
	o->nseeds = 1;
	o->generation = 16;
	o->evals = 1 + 16 * pl->generations; /* the seed, then the generations */
	o->semantic = semantic;
}

/* The least error of the fits, its text in *text. */
static double best_of(const bk_search *s, const char **text)
{
	double best = HUGE_VAL;
	for (size_t i = 0; i < bk_search_count(s); i++) {
		const bk_cand *c = bk_search_at(s, i);
		if (c->status == BK_CAND_OK && c->err < best)
			best = c->err, *text = c->text;
	}
	return best;
}

/* The least error after the seed and the generations, its text in text. */
static double run(const plant *pl, double semantic, char *text, size_t len)
{
	bk_samples sm;
	bk_search_options o;
	char err[256];
	options(pl, &sm, &o, semantic);
	bk_search *s = bk_search_new(&o, err, sizeof err);
	cr_assert(s, "%s", err);
	cr_assert_eq(bk_search_drive(s, NULL, err, sizeof err), 0, "%s", err);
	cr_assert_leq(bk_search_evals(s), 1 + 16 * pl->generations);
	const char *t = "";
	double e = best_of(s, &t);
	snprintf(text, len, "%s", t);
	bk_search_free(s);
	bk_samples_free(&sm);
	return e;
}

Test(search_semantic, the_missing_subtree_is_found_in_one_generation)
{
	char with[512], without[512];
	double e = run(&SUBTREE, BK_SEARCH_SEMANTIC, with, sizeof with), c = run(&SUBTREE, 0, without, sizeof without);
	cr_assert_lt(e, 1e-6, "the semantic generator's generation reaches %g: %s", e, with);
	/* the control: without it the same generation is nowhere near */
	cr_assert_gt(c, 1e-3, "without the semantic generator the generation reaches %g: %s", c, without);
}

Test(search_semantic, a_pair_of_library_trees_is_found)
{
	char with[512], without[512];
	double e = run(&PAIR, BK_SEARCH_SEMANTIC, with, sizeof with), c = run(&PAIR, 0, without, sizeof without);
	cr_assert_lt(e, 1e-6, "the semantic generator's generations reach %g: %s", e, with);
	cr_assert_gt(c, 1e-3, "without the semantic generator the generations reach %g: %s", c, without);
}

Test(search_semantic, a_share_out_of_range_is_refused_by_name)
{
	bk_samples sm;
	bk_search_options o;
	char why[256];
	options(&SUBTREE, &sm, &o, 0.6);
	cr_assert_eq(bk_search_options_valid(&o, why, sizeof why), 0);
	cr_assert_str_eq(why, "semantic: must be in [0, 0.5], got 0.6");
	o.semantic = NAN;
	cr_assert_eq(bk_search_options_valid(&o, why, sizeof why), 0);
	o.semantic = 0.5;
	cr_assert_eq(bk_search_options_valid(&o, why, sizeof why), 1, "%s", why);
	bk_samples_free(&sm);
}
