/*
 * test_prune.c — dead branches of a fitted form (fit/search/prune.c): a
 * planted max whose constant side never wins on the samples comes out
 * without it, its parameters renumbered, with the same values at every
 * sample; the controls are the same forms where the branch does win
 * somewhere (kept), and each operation's edge (a clamp bound reached at one
 * sample) moved across.
 */
#include "search/prune.h"
#include "fixture_search.h"

#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* LoH in [0.3, 1], 32 cell centres: the samples the branches are judged on. */
static bk_samples S;
static void setup(void) { fx_planted("LoH", 0.3, 0, 32, &S); }
static void teardown(void) { bk_samples_free(&S); }
TestSuite(prune, .init = setup, .fini = teardown, .timeout = 30);

/* The values of text at p on S. */
static void values(const char *text, const double *p, double *v)
{
	bk_form_error fe;
	bk_form *f = bk_form_parse(text, &fe);
	cr_assert_not_null(f, "%s", text);
	cr_assert_eq(bk_form_eval(f, BK_F64, S.n, (const double *const *)S.in, p, v), 0);
	bk_form_free(f);
}

/* text at p pruned to want (n nodes replaced), the same values everywhere. */
static void expect_pruned(const char *text, const double *p, int n, const char *want, const double *pwant, int np)
{
	char out[256];
	double q[BK_MAX_PARAMS];
	cr_assert_eq(bk_prune_dead(text, p, &S, out, sizeof out, q), n, "%s", text);
	cr_expect_str_eq(out, want, "%s", text);
	for (int k = 0; k < np; k++)
		cr_expect_eq(q[k], pwant[k], "%s: p%d", text, k);
	double *a = malloc(sizeof(double) * S.n * 2), *b = a + S.n;
	values(text, p, a);
	values(out, q, b);
	for (size_t k = 0; k < S.n; k++)
		cr_expect_eq(a[k], b[k], "%s at sample %zu: %.17g against %.17g", text, k, a[k], b[k]);
	free(a);
}

/* issue 40's search_vf2d_4 in small: max(p0, max(1.414, p1 LoH)) with p0 = 1
 * is never p0 (the inner max is at least 1.414); p1 = 2 becomes p0. */
Test(prune, a_dead_constant_side_of_max)
{
	double p[] = {1, 2};
	expect_pruned("max(p0, max(1.414, p1 * LoH))", p, 1, "max(1.414, p0 * LoH)", (double[]){2}, 1);
	/* control: with p0 = 1.5 the outer max is p0 where 2 LoH < 1.5: kept */
	char out[256];
	double q[BK_MAX_PARAMS];
	cr_expect_eq(bk_prune_dead("max(p0, max(1.414, p1 * LoH))", (double[]){1.5, 2}, &S, out, sizeof out, q), 0);
}

/* min, clamp and saturate alike; a dead branch inside another is found
 * after the outer one goes. Controls: a bound met by one sample's value. */
Test(prune, min_clamp_saturate)
{
	char out[256];
	double q[BK_MAX_PARAMS];
	expect_pruned("min(LoH, p0)", (double[]){2}, 1, "LoH", NULL, 0);
	expect_pruned("p1 * saturate(LoH * p0)", (double[]){0.5, 3}, 1, "p0 * (LoH * p1)", (double[]){3, 0.5}, 2);
	expect_pruned("clamp(LoH, 0, p0)", (double[]){1}, 1, "LoH", NULL, 0);
	expect_pruned("min(max(LoH, 0.1), p0) + max(0.2, LoH)", (double[]){4}, 3, "LoH + LoH", NULL, 0);
	/* controls: the samples reach 0.3 < 0.5 (max live), 1 > 0.9 (clamp live), 2 LoH > 1 (saturate live) */
	cr_expect_eq(bk_prune_dead("max(LoH, 0.5)", NULL, &S, out, sizeof out, q), 0);
	cr_expect_eq(bk_prune_dead("clamp(LoH, 0, p0)", (double[]){0.9}, &S, out, sizeof out, q), 0);
	cr_expect_eq(bk_prune_dead("saturate(2 * LoH)", NULL, &S, out, sizeof out, q), 0);
	/* mix(x, y, t) with t 0 (or 1) everywhere is x (or y); t = LoH is live */
	expect_pruned("mix(LoH, p0, p1 * LoH)", (double[]){2, 0}, 1, "LoH", NULL, 0);
	expect_pruned("mix(LoH, p0, p1)", (double[]){2, 1}, 1, "p0", (double[]){2}, 1);
	cr_expect_eq(bk_prune_dead("mix(LoH, 2, LoH)", NULL, &S, out, sizeof out, q), 0);
	/* a side NaN somewhere proves nothing: kept */
	cr_expect_eq(bk_prune_dead("max(sqrt(LoH - 0.5), -1)", NULL, &S, out, sizeof out, q), 0);
}

/* A split pair: A judged on the first component's samples, B on the
 * second's, the shared parameters renumbered over A then B. B = min(p2, NoV)
 * with p2 = 0.5 is p2 on the second component (NoV 0.6, 0.9), though not on
 * the first (NoV 0.1, 0.2): judged on all samples it would stay, so the
 * answer shows the ranges. A = max(p0, p1 NoV) at p0 = 0 loses p0. */
Test(prune, a_split_pair_by_component)
{
	double nov[] = {0.1, 0.2, 0.6, 0.9};
	bk_samples t = {.n = 4, .ncomp = 2, .start = {0, 2, 4}};
	t.in[BK_IN_NOV] = nov;
	char a[256], b[256];
	double q[BK_MAX_PARAMS];
	cr_assert_eq(bk_prune_dead_pair("max(p0, p1 * NoV)", "min(p2, NoV)", (double[]){0, 1, 0.5}, &t, a, b, sizeof a, q),
	             2);
	cr_expect_str_eq(a, "p0 * NoV");
	cr_expect_str_eq(b, "p1");
	cr_expect(q[0] == 1 && q[1] == 0.5, "p0 = %g, p1 = %g", q[0], q[1]);
	/* control: B's component holding every sample keeps its min (and A,
	 * with no sample, is not judged: nothing shows a side dead) */
	t.start[1] = 0;
	cr_expect_eq(bk_prune_dead_pair("max(p0, p1 * NoV)", "min(p2, NoV)", (double[]){0, 1, 0.5}, &t, a, b, sizeof a, q),
	             0);
}
