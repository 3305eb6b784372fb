/*
 * test_pareto.c — the search layer's one Pareto scan (fit/search/pareto.h),
 * on point sets whose front is known by hand.
 */
#include <criterion/criterion.h>
#include <math.h>

#include "search/pareto.h"

/* (cost, err): (1, .5) (2, .5) (2, .3) (3, .4) (4, .1) (4, NaN) (5, .1);
 * by hand the front is (1, .5), (2, .3), (4, .1). */
Test(pareto, known_front)
{
	bk_pareto_pt pt[] = {{5, .1, "e", 0}, {4, NAN, "f", 1}, {3, .4, "d", 2}, {2, .5, "b", 3},
	                     {1, .5, "a", 4}, {4, .1, "g", 5}, {2, .3, "c", 6}};
	size_t k = bk_pareto_scan(pt, sizeof pt / sizeof pt[0]);
	cr_assert_eq(k, 3);
	cr_expect_eq(pt[0].id, 4);
	cr_expect_eq(pt[1].id, 6);
	cr_expect_eq(pt[2].id, 5);
}

/* Equal cost and error: the key decides, not the arrival order. */
Test(pareto, ties_broken_by_key)
{
	bk_pareto_pt a[] = {{1, .2, "zeta", 0}, {1, .2, "alpha", 1}};
	bk_pareto_pt b[] = {{1, .2, "alpha", 1}, {1, .2, "zeta", 0}};
	cr_assert_eq(bk_pareto_scan(a, 2), 1);
	cr_assert_eq(bk_pareto_scan(b, 2), 1);
	cr_expect_eq(a[0].id, 1);
	cr_expect_eq(b[0].id, 1);
}

/* Nothing finite: no front. */
Test(pareto, nan_only)
{
	bk_pareto_pt pt[] = {{1, NAN, "a", 0}, {2, HUGE_VAL, "b", 1}};
	cr_expect_eq(bk_pareto_scan(pt, 2), 0);
}

#include "search/pair.h"
#include <stdlib.h>
#include <string.h>

/* The pair's text is the split sum f0·A + B, and a buffer too short gives
 * -1 and an empty string, never a cut formula. */
Test(pair, text_and_truncation)
{
	char buf[64];
	cr_assert_eq(bk_pair_text("1 - r", "r*NoV", buf, sizeof buf), 0);
	cr_expect_str_eq(buf, "f0*(1 - r) + (r*NoV)");
	cr_expect_eq(bk_pair_text("1 - r", "r*NoV", buf, 10), -1);
	cr_expect_str_eq(buf, "");
	char *d = bk_pair_dup("a", "b");
	cr_assert_not_null(d);
	cr_expect_str_eq(d, "f0*(a) + (b)");
	free(d);
}

#include "search/constraint.h"

/* env's bound by hand: A, B >= 0 and A + B <= 1 to half an 8-bit step. */
Test(constraint, env_bound_and_nonneg)
{
	bk_search_options o;
	bk_search_defaults(&o);
	o.env_bound = 1;
	bk_samples sm;
	memset(&sm, 0, sizeof sm);
	sm.n = 4;
	sm.ncomp = 2;
	sm.start[0] = 0;
	sm.start[1] = 2;
	sm.start[2] = 4;
	double ok[4] = {0.5, 1.0, 0.5, 0.0};            /* A = .5, 1; B = .5, 0: sums 1, 1 */
	double over[4] = {0.5, 1.0, 0.5 + 0.003, 0.0};  /* A + B = 1.003 > 1 + 0.5/255 */
	double under[4] = {-0.003, 1.0, 0.5, 0.0};      /* A < -0.5/255 */
	double slack[4] = {-0.001, 1.0, 0.5, 0.001};    /* within half a step */
	cr_expect_eq(bk_search_admissible(&o, &sm, ok), 1);
	cr_expect_eq(bk_search_admissible(&o, &sm, over), 0);
	cr_expect_eq(bk_search_admissible(&o, &sm, under), 0);
	cr_expect_eq(bk_search_admissible(&o, &sm, slack), 1);
	o.env_bound = 0;
	o.nonneg = 1;
	cr_expect_eq(bk_search_admissible(&o, &sm, slack), 0); /* -0.001 < 0 */
	cr_expect_eq(bk_search_admissible(&o, &sm, ok), 1);
}
