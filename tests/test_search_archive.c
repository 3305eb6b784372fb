/*
 * test_search_archive.c — the search's archive (fit/search/archive.h):
 * MAP-Elites keeps the per_level best of each integer cost level (error,
 * then cost, then text), leaves out candidates that did not fit, and the
 * front (bk_search_front) is the Pareto scan of the candidates that fitted,
 * ties broken on the text (a pair's: A's, then B's) whatever the order of
 * arrival; a candidate keeps its forms (its IR, for the front's refit) while
 * no other dominates it, so a real search's front members all hold theirs
 * and no dominated candidate does. Every expected level and front is worked
 * out by hand below.
 */
#include "fixture_search.h"
#include "search/archive.h"

#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A search with nothing fitted: only its archive is used here. */
static bk_search *empty_search(int per_level, bk_samples *sm)
{
	fx_planted("LoH", 0, 0, 4, sm);
	bk_search_options o;
	fx_plain_options(&o, sm, 1u << BK_IN_LOH, 2, 8);
	char err[256];
	o.per_level = per_level;
	bk_search *s = bk_search_new(&o, err, sizeof err);
	cr_assert(s, "%s", err);
	return s;
}

static void add(bk_search *s, const char *a, const char *b, double cost, double err, bk_cand_status st)
{
	bk_cand c;
	memset(&c, 0, sizeof c);
	c.text = strdup(a);
	c.text_b = b ? strdup(b) : NULL;
	c.cost = cost;
	c.err = err;
	c.status = st;
	cr_assert_eq(bk_archive_push(s, &c), 0);
}

/* The texts of level k, best first, joined by spaces. */
static void level_texts(const bk_search *s, int k, char *buf, size_t len)
{
	buf[0] = '\0';
	for (int i = 0; i < s->lv[k].n; i++) {
		strncat(buf, s->cand[s->lv[k].idx[i]].text, len - strlen(buf) - 1);
		if (i + 1 < s->lv[k].n)
			strncat(buf, " ", len - strlen(buf) - 1);
	}
}

/* The same seven candidates for both tests, in this order:
 *   a (3.0, 0.5)  b (3.5, 0.2)  c (3.2, 0.2)  d (5, 0.1, not fitted)
 *   e (4.9999999999, 0.9)  f (1, 0.3)  g (1, 0.3)
 * Level 1: f, g tie on error and cost: one member per error in a level,
 *   text decides: f stays, g is dropped.
 * Level 3: b and c tie on error, c is cheaper: c stays, b is dropped; then a.
 * Level 5: e (cost a rounding below 5 is on level 5); d is in no level. */
static void seven(bk_search *s)
{
	add(s, "a", NULL, 3.0, 0.5, BK_CAND_OK);
	add(s, "b", NULL, 3.5, 0.2, BK_CAND_OK);
	add(s, "c", NULL, 3.2, 0.2, BK_CAND_OK);
	add(s, "d", NULL, 5.0, 0.1, BK_CAND_CONSTRAINT);
	add(s, "e", NULL, 4.9999999999, 0.9, BK_CAND_OK);
	add(s, "g", NULL, 1.0, 0.3, BK_CAND_OK);
	add(s, "f", NULL, 1.0, 0.3, BK_CAND_OK);
}

Test(search_archive, per_level_best_per_cost_level)
{
	bk_samples sm;
	bk_search *s = empty_search(2, &sm);
	seven(s);
	cr_assert_eq(bk_search_count(s), 7, "every candidate is kept, levels or not");
	cr_assert_eq(s->nlv, 3);
	char t[64];
	cr_assert_eq(s->lv[0].cost, 1);
	level_texts(s, 0, t, sizeof t);
	cr_assert_str_eq(t, "f", "g: the same error as f, worse by text");
	cr_assert_eq(s->lv[1].cost, 3);
	level_texts(s, 1, t, sizeof t);
	cr_assert_str_eq(t, "c a", "b: the same error as c at a higher cost");
	cr_assert_eq(s->lv[2].cost, 5);
	level_texts(s, 2, t, sizeof t);
	cr_assert_str_eq(t, "e", "d did not fit: in no level");
	bk_search_free(s);
	bk_samples_free(&sm);

	/* negative control: with room for one, the cap drops a too */
	s = empty_search(1, &sm);
	seven(s);
	level_texts(s, 1, t, sizeof t);
	cr_assert_str_eq(t, "c");
	bk_search_free(s);
	bk_samples_free(&sm);
}

Test(search_archive, front_is_the_pareto_scan_of_what_fitted)
{
	bk_samples sm;
	bk_search *s = empty_search(2, &sm);
	seven(s);
	/* by cost: f and g at 1 (f first by text) -> f; a at 3 (0.5) no; c at 3.2
	 * (0.2) yes; b at 3.5 (0.2, not below) no; e no; d (0.1) did not fit */
	size_t idx[8];
	size_t k = bk_search_front(s, idx, 8);
	cr_assert_eq(k, 2);
	cr_assert_str_eq(bk_search_at(s, idx[0])->text, "f");
	cr_assert_str_eq(bk_search_at(s, idx[1])->text, "c");
	cr_assert_eq(bk_search_front(s, idx, 1), 1, "max caps the count");
	cr_assert_str_eq(bk_search_at(s, idx[0])->text, "f");
	/* negative control: had d fitted, it would end the front */
	s->cand[3].status = BK_CAND_OK;
	cr_assert_eq(bk_search_front(s, idx, 8), 3);
	cr_assert_str_eq(bk_search_at(s, idx[2])->text, "d");
	bk_search_free(s);
	bk_samples_free(&sm);
}

Test(search_archive, pair_ties_broken_on_b_whatever_the_order)
{
	for (int order = 0; order < 2; order++) {
		bk_samples sm;
		bk_search *s = empty_search(2, &sm);
		/* same A, cost and error: B's text decides ("x + 1" < "x + 2") */
		add(s, "x", order ? "x + 2" : "x + 1", 4, 0.25, BK_CAND_OK);
		add(s, "x", order ? "x + 1" : "x + 2", 4, 0.25, BK_CAND_OK);
		/* "x" < "x*2" as A: A decides before B */
		add(s, "x*2", "a", 4, 0.25, BK_CAND_OK);
		size_t idx[4];
		cr_assert_eq(bk_search_front(s, idx, 4), 1);
		cr_assert_str_eq(bk_search_at(s, idx[0])->text, "x");
		cr_assert_str_eq(bk_search_at(s, idx[0])->text_b, "x + 1", "order %d", order);
		char t[64];
		level_texts(s, 0, t, sizeof t);
		cr_assert_str_eq(t, "x", "one member per error: the level keeps the better one");
		cr_assert_str_eq(s->cand[s->lv[0].idx[0]].text_b, "x + 1");
		bk_search_free(s);
		bk_samples_free(&sm);
	}
}

/* seven's candidates, each made with a form (any form: the archive only
 * keeps or frees it). By hand, in order of arrival: a held; b held (neither
 * dominates the other); c (3.2, 0.2) dominates b (3.5, 0.2): b drops its;
 * d did not fit: drops; e (5, 0.9) is dominated by a: drops; g (1, 0.3)
 * dominates a: a drops; f ties g: held. So c, f and g hold theirs. */
Test(search_archive, forms_kept_while_nothing_dominates)
{
	bk_samples sm;
	bk_search *s = empty_search(2, &sm);
	const char *name[7] = {"a", "b", "c", "d", "e", "g", "f"};
	const double cost[7] = {3.0, 3.5, 3.2, 5.0, 4.9999999999, 1.0, 1.0}, err[7] = {0.5, 0.2, 0.2, 0.1, 0.9, 0.3, 0.3};
	for (int i = 0; i < 7; i++) {
		bk_cand c;
		memset(&c, 0, sizeof c);
		c.text = strdup(name[i]);
		c.form = bk_form_parse("LoH", NULL);
		c.cost = cost[i];
		c.err = err[i];
		c.status = i == 3 ? BK_CAND_CONSTRAINT : BK_CAND_OK;
		cr_assert(c.text && c.form);
		cr_assert_eq(bk_archive_push(s, &c), 0);
	}
	const char *held = "cgf";
	for (int i = 0; i < 7; i++)
		cr_expect_eq(bk_search_at(s, (size_t)i)->form != NULL, strchr(held, name[i][0]) != NULL, "%s %s its form",
		             name[i], bk_search_at(s, (size_t)i)->form ? "holds" : "dropped");
	size_t idx[8], k = bk_search_front(s, idx, 8);
	for (size_t i = 0; i < k; i++)
		cr_expect_not_null(bk_search_at(s, idx[i])->form, "front member %s without its form", bk_search_at(s, idx[i])->text);
	/* negative control: a candidate that dominates them all (cost 0.5, error
	 * 0.1) leaves it alone holding one */
	bk_cand z;
	memset(&z, 0, sizeof z);
	z.text = strdup("z");
	z.form = bk_form_parse("LoH", NULL);
	z.cost = 0.5, z.err = 0.1, z.status = BK_CAND_OK;
	cr_assert_eq(bk_archive_push(s, &z), 0);
	for (int i = 0; i < 7; i++)
		cr_expect_null(bk_search_at(s, (size_t)i)->form, "%s still holds its form", name[i]);
	cr_expect_not_null(bk_search_at(s, 7)->form);
	bk_search_free(s);
	bk_samples_free(&sm);
}

/* A real search: every front member holds its forms, and a candidate that
 * holds them is dominated by no candidate that fitted (checked pairwise). */
Test(search_archive, a_search_keeps_the_forms_of_its_front)
{
	bk_samples sm;
	fx_planted("1/(LoH*LoH + 0.7*r*r)", 0.3, 1, 16, &sm);
	bk_search_options o;
	fx_plain_options(&o, &sm, 1u << BK_IN_LOH | 1u << BK_IN_R, 2, 7);
	o.evals = 400;
	char err[256];
	bk_search *s = bk_search_new(&o, err, sizeof err);
	cr_assert(s, "%s", err);
	cr_assert_eq(bk_search_run(s, NULL, NULL, err, sizeof err), 0, "%s", err);
	size_t idx[64], k = bk_search_front(s, idx, 64), n = bk_search_count(s);
	cr_assert_gt(k, 2);
	for (size_t i = 0; i < k; i++)
		cr_expect_not_null(bk_search_at(s, idx[i])->form, "front member %s without its form", bk_search_at(s, idx[i])->text);
	for (size_t i = 0; i < n; i++) {
		const bk_cand *c = bk_search_at(s, i);
		if (!c->form)
			continue;
		for (size_t j = 0; j < n; j++) {
			const bk_cand *d = bk_search_at(s, j);
			cr_expect(!(d->status == BK_CAND_OK && d->cost <= c->cost && d->err <= c->err &&
			            (d->cost < c->cost || d->err < c->err)),
			          "%s (%g, %g) holds its form, dominated by %s (%g, %g)", c->text, c->cost, c->err, d->text, d->cost,
			          d->err);
		}
	}
	bk_search_free(s);
	bk_samples_free(&sm);
}
