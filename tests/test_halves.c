/*
 * test_halves.c — --env-form mix's compositions (fit/search/halves.h) on
 * hand-made halves: the text mix(B, S, f0) with B's parameters after S's,
 * the constants carried, the parameter cap, and the compositions' front.
 *
 * Texts as bk_expr_print writes them (spaces around *). The halves: S1 = p0 (err .1), S2 = p0*r + p1 (err .02), B1 = p0 (err .1),
 * B2 = p0*NoV (err .05). mix(b, s, f0) is a subtract and a multiply-add
 * (cost 2 with unit weights); p0*r + p1 adds a multiply-add, p0*NoV a
 * multiply: S1B1 costs 2, S1B2 and S2B1 3, S2B2 4. The estimated rmse
 * sqrt((eS^2 + eB^2)/2): S1B1 .1, S1B2 .0791, S2B1 .0721, S2B2 .0381.
 * By hand the front is S1B1, S2B1 (beats S1B2 at equal cost), S2B2.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "search/halves.h"

static bk_half half(const char *text, double p0, double p1, double err)
{
	bk_half h;
	memset(&h, 0, sizeof h);
	bk_form_error fe;
	bk_form *f = bk_form_parse(text, &fe);
	cr_assert(f, "%s", text);
	cr_assert_eq(bk_expr_from_form(f, &h.tree), 0);
	bk_form_free(f);
	h.np = bk_expr_nparams(&h.tree);
	h.p[0] = p0;
	h.p[1] = p1;
	h.err = err;
	return h;
}

static int find(const bk_halves *hv, const char *text)
{
	for (int k = 0; k < hv->n; k++)
		if (!strcmp(hv->text[k], text))
			return k;
	return -1;
}

Test(halves, compositions_and_their_front)
{
	bk_half s[2] = {half("p0", 0.5, 0, 0.1), half("p0*r + p1", 0.7, 0.2, 0.02)};
	bk_half b[2] = {half("p0", 0.25, 0, 0.1), half("p0*NoV", 0.125, 0, 0.05)};
	bk_halves hv;
	memset(&hv, 0, sizeof hv);
	cr_assert_eq(bk_halves_compose(s, 2, b, 2, 4, HUGE_VAL, 1, 4, &hv), 0);
	cr_assert_eq(hv.n, 3, "front of %d", hv.n);
	int k11 = find(&hv, "mix(p1, p0, f0)"), k21 = find(&hv, "mix(p2, p0 * r + p1, f0)"),
	    k22 = find(&hv, "mix(p2 * NoV, p0 * r + p1, f0)");
	cr_expect(k11 >= 0 && k21 >= 0 && k22 >= 0, "%s | %s | %s", hv.text[0], hv.text[1], hv.text[2]);
	cr_expect_eq(find(&hv, "mix(p1 * NoV, p0, f0)"), -1); /* S1B2: dominated by S2B1 */
	if (k21 >= 0) { /* S's constants, then B's */
		cr_expect_eq(hv.p[k21][0], 0.7);
		cr_expect_eq(hv.p[k21][1], 0.2);
		cr_expect_eq(hv.p[k21][2], 0.25);
	}
	cr_expect_str_eq(hv.name[0], "halves 1");
	bk_halves_free(&hv);
}

/* The caps: at most 2 parameters leaves S1B1 and S1B2 (S2 has 2 of its
 * own); a cost cap of 2 leaves S1B1 alone (negative controls of both). */
Test(halves, parameter_and_cost_caps)
{
	bk_half s[2] = {half("p0", 0.5, 0, 0.1), half("p0*r + p1", 0.7, 0.2, 0.02)};
	bk_half b[2] = {half("p0", 0.25, 0, 0.1), half("p0*NoV", 0.125, 0, 0.05)};
	bk_halves hv;
	memset(&hv, 0, sizeof hv);
	cr_assert_eq(bk_halves_compose(s, 2, b, 2, 2, HUGE_VAL, 1, 4, &hv), 0);
	cr_expect_eq(hv.n, 2);
	cr_expect_geq(find(&hv, "mix(p1 * NoV, p0, f0)"), 0); /* on the front once S2 is out */
	cr_assert_eq(bk_halves_compose(s, 2, b, 2, 4, 2, 1, 4, &hv), 0);
	cr_expect_eq(hv.n, 1);
	cr_expect_geq(find(&hv, "mix(p1, p0, f0)"), 0);
	bk_halves_free(&hv);
}

/* The search in f0 gets the caller's seeds first (the exempt ones), then the
 * compositions; the halves' fits come off its budget. */
Test(halves, seeds_after_the_callers)
{
	bk_half s = half("p0", 0.5, 0, 0.1), b = half("p0", 0.25, 0, 0.1);
	bk_halves hv;
	memset(&hv, 0, sizeof hv);
	cr_assert_eq(bk_halves_compose(&s, 1, &b, 1, 4, HUGE_VAL, 1, 4, &hv), 0);
	hv.evals = 300;
	bk_seeds sd;
	memset(&sd, 0, sizeof sd);
	bk_seeds_add(&sd, "p0*r", NULL, "one", NULL);
	bk_seeds_add(&sd, "p0*NoV", NULL, "two", NULL);
	bk_search_options o;
	bk_search_defaults(&o);
	o.evals = 1000;
	bk_halves_seed(&hv, &sd, &o);
	cr_expect_eq(o.nseeds, 3);
	cr_expect_eq(o.exempt_seeds, 2);
	cr_expect_str_eq(o.seed_names[1], "two");
	cr_expect_str_eq(o.seeds[2], "mix(p1, p0, f0)");
	cr_expect_eq(o.seed_p[2][1], 0.25);
	cr_expect_eq(o.evals, 700);
	/* the caller's seeds go in with their forms, a composition to be parsed */
	cr_expect(o.seed_forms && o.seed_forms[1] == sd.form[1] && !o.seed_forms[2]);
	bk_halves_free(&hv);
	bk_seeds_free(&sd);
}
