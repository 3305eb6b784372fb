/*
 * test_recovery.c — what the search needs to find a planted form (issue 22):
 * the screening starts (fit/search/starts.h) are a function of the seed, the
 * candidate's text and the start's number alone, spread over signs and four
 * decades; and a seed one free constant short of the planted target is
 * completed in the first generation (the neighbours of search.h), where a
 * seed short of something else is not.
 */
#include "fixture_search.h"
#include "search.h"
#include "search/starts.h"

#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

Test(recovery, first_starts_are_ones_then_a_tenth)
{
	double p[6];
	bk_search_start(7, "p0 * LoH", 0, 6, p);
	for (int j = 0; j < 6; j++)
		cr_assert_eq(p[j], 1.0);
	bk_search_start(7, "p0 * LoH", 1, 6, p);
	for (int j = 0; j < 6; j++)
		cr_assert_eq(p[j], 0.1);
}

Test(recovery, random_starts_are_deterministic_and_spread)
{
	double a[BK_MAX_PARAMS], b[BK_MAX_PARAMS], c[BK_MAX_PARAMS], d[BK_MAX_PARAMS];
	bk_search_start(1, "p0 / sq(p1 + sq(NoH))", 2, BK_MAX_PARAMS, a);
	bk_search_start(1, "p0 / sq(p1 + sq(NoH))", 2, BK_MAX_PARAMS, b);
	cr_assert_eq(memcmp(a, b, sizeof a), 0, "the same start twice");
	/* negative controls: another seed, text or start number moves it */
	bk_search_start(2, "p0 / sq(p1 + sq(NoH))", 2, BK_MAX_PARAMS, c);
	cr_assert_neq(memcmp(a, c, sizeof a), 0, "the seed changes nothing");
	bk_search_start(1, "p0 / sq(p1 + sq(LoH))", 2, BK_MAX_PARAMS, c);
	cr_assert_neq(memcmp(a, c, sizeof a), 0, "the text changes nothing");
	bk_search_start(1, "p0 / sq(p1 + sq(NoH))", 3, BK_MAX_PARAMS, d);
	cr_assert_neq(memcmp(a, d, sizeof a), 0, "the start number changes nothing");
	/* over many texts: both signs, magnitudes within 1e-2 .. 1e2 (10^-2 and
	 * 10^2 by the decades stated), both ends reached, and within each start
	 * the constants differ from one another (not one value for all) */
	int neg = 0, pos = 0, small = 0, large = 0, distinct = 0;
	for (int t = 0; t < 200; t++) {
		char text[32];
		snprintf(text, sizeof text, "p0 * NoV + %d", t);
		double p[4];
		bk_search_start(5, text, 2 + t % 3, 4, p);
		distinct += p[0] != p[1] || p[1] != p[2] || p[2] != p[3];
		for (int j = 0; j < 4; j++) {
			double m = fabs(p[j]);
			cr_assert(m >= 0.01 && m <= 100.0, "%g", p[j]);
			neg += p[j] < 0, pos += p[j] > 0;
			small += m == 0.01, large += m == 100.0;
		}
	}
	cr_assert_gt(neg, 300);
	cr_assert_gt(pos, 300);
	cr_assert_gt(small, 0);
	cr_assert_gt(large, 0);
	cr_assert_gt(distinct, 190);
}

/* The planted target 0.3/(LoH^2 + 0.7 r^2) on LoH in [0.3162, 1], r in [0, 1]. */
static void planted(bk_samples *s)
{
	fx_planted("0.3/(LoH*LoH + 0.7*r*r)", 0.3162, 1, 16, s);
}

/* The least screening rmse of a search seeded with one form, no enumeration,
 * one generation of 16 children: the seed's neighbours by one free constant
 * come first (search.h; at most half the generation), so a seed one constant
 * short of the target is completed in that generation (measured: without
 * the neighbours, 8 random children do not complete it; 64 do). */
static double one_generation_from(const char *seed, const bk_samples *s, int threads)
{
	bk_search_options o;
	bk_search_defaults(&o);
	o.screen = s;
	o.shape = BK_SHAPE_PLAIN;
	memset(&o.grammar, 0, sizeof o.grammar);
	char err[256];
	cr_assert_eq(bk_grammar_parse_ops("+,*,/,sq", &o.grammar.ops, err, sizeof err), 0, "%s", err);
	o.grammar.inputs = 1u << BK_IN_LOH | 1u << BK_IN_R | 1u << BK_IN_A;
	o.grammar.consts[0] = 1;
	o.grammar.nconsts = 1;
	o.grammar.max_params = 2;
	o.grammar.max_size = 16;
	o.enum_size = 0;
	o.enum_max = 0;
	o.generation = 16;
	o.evals = 17; /* the seed, then one generation */
	o.threads = threads;
	const char *const seeds[] = {seed};
	o.seeds = seeds;
	o.nseeds = 1;
	bk_search *S = bk_search_new(&o, err, sizeof err);
	cr_assert(S, "%s", err);
	cr_assert_geq(bk_search_run(S, NULL, NULL, err, sizeof err), 0, "%s", err);
	double best = HUGE_VAL;
	for (size_t i = 0; i < bk_search_count(S); i++) {
		const bk_cand *c = bk_search_at(S, i);
		if (c->status == BK_CAND_OK && c->rmse < best)
			best = c->rmse;
	}
	bk_search_free(S);
	return best;
}

Test(recovery, a_form_one_constant_short_is_completed_at_once)
{
	bk_samples s;
	planted(&s);
	/* p0/(a + sq(LoH)) is p0/(p1*a + sq(LoH)) at p1 = 1: one constant short */
	cr_assert_leq(one_generation_from("p0/(a + sq(LoH))", &s, 2), 1e-9);
	/* control: a seed one constant short of no exact form (LoH for a) is
	 * not completed in the same budget */
	cr_assert_gt(one_generation_from("p0/(LoH + sq(LoH))", &s, 2), 1e-3);
	/* the same on one thread (starts and order do not depend on threads) */
	cr_assert_leq(one_generation_from("p0/(a + sq(LoH))", &s, 1), 1e-9);
	bk_samples_free(&s);
}
