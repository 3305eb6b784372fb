/*
 * test_search_plugin.c — a generator from outside fit/search/, through the
 * public API alone (fit/search.h: bk_search_generator,
 * bk_search_schedule_add, bk_search_offer): no part of the loop is touched.
 * A generator offering one planted tree (the exact target's structure) as
 * its own stage before the seeds: the tree is fit 1 and reaches the planted
 * error, a checkpoint names the generator and its state, and loads back into
 * a search with it; the same search without it (the negative control) has
 * another fit 1 and a checkpoint that does not name it, and each refuses the
 * other's checkpoint with what is wrong.
 */
#include "fixture_search.h"

#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PLANTED "p0/(LoH*LoH + p1*r*r)" /* the target 0.3/(LoH*LoH + 0.7*r*r) with free constants */

typedef struct planted_gen {
	int offered; /* what bk_search_offer said (1: taken) */
	int loaded, freed;
} planted_gen;

/* One batch: the planted tree, then over. */
static int planted_make(void *st, bk_search *s, bk_search_sink *k)
{
	planted_gen *p = st;
	(void)s;
	bk_form_error fe;
	bk_form *f = bk_form_parse(PLANTED, &fe);
	bk_expr t[2];
	memset(t, 0, sizeof t);
	cr_assert(f && bk_expr_from_form(f, &t[0]) == 0, "the planted form does not parse");
	bk_form_free(f);
	cr_assert_gt(bk_search_sink_room(k), 0);
	p->offered = bk_search_offer(k, t, NULL);
	return p->offered < 0 ? -1 : 1;
}

static int planted_save(const void *st, const bk_search *s, FILE *f)
{
	(void)s;
	return fprintf(f, "planted offered %d\n", ((const planted_gen *)st)->offered) < 0 ? -1 : 0;
}

static int planted_load(void *st, bk_search *s, int when, FILE *f, char *err, size_t errlen)
{
	planted_gen *p = st;
	(void)s;
	if (fscanf(f, " planted offered %d", &p->offered) != 1 || p->offered < 0 || p->offered > 1 ||
	    (when < 0 && p->offered)) {
		snprintf(err, errlen, "planted: no line \"planted offered 0|1\"");
		return -1;
	}
	p->loaded = 1;
	return 0;
}

static void planted_free(void *st) { ((planted_gen *)st)->freed++; }

static void options(bk_samples *sm, bk_search_options *o)
{
	fx_planted("0.3/(LoH*LoH + 0.7*r*r)", 0.3162, 1, 6, sm);
	fx_plain_options(o, sm, 1u << BK_IN_LOH | 1u << BK_IN_R, 2, 9);
	o->enum_max = 40;
	o->generation = 16;
	o->evals = 80;
}

/* A new search of o, with the planted generator as its first stage when p. */
static bk_search *made(const bk_search_options *o, planted_gen *p)
{
	char err[256];
	bk_search *s = bk_search_new(o, err, sizeof err);
	cr_assert(s, "%s", err);
	if (p) {
		bk_search_generator g = {"planted", 0, planted_make, planted_save, planted_load, planted_free, p};
		cr_assert_eq(bk_search_schedule_add(s, 0, 0, 1, &g, err, sizeof err), 0, "%s", err);
	}
	return s;
}

static void run(bk_search *s)
{
	char err[256];
	cr_assert_eq(bk_search_drive(s, NULL, err, sizeof err), 0, "%s", err);
}

static char *saved(const bk_search *s, size_t *len)
{
	char *buf = NULL;
	FILE *f = open_memstream(&buf, len);
	cr_assert(f);
	cr_assert_eq(bk_search_save(s, f), 0);
	fclose(f);
	return buf;
}

static int load(bk_search *s, const char *text, size_t len, char *err, size_t errlen)
{
	FILE *f = fmemopen((void *)text, len, "r");
	cr_assert(f);
	int rc = bk_search_load(s, f, err, errlen);
	fclose(f);
	return rc;
}

/* The candidate fitted as fit `at` of island 0, or NULL. */
static const bk_cand *fit_number(const bk_search *s, long at)
{
	for (size_t i = 0; i < bk_search_count(s); i++)
		if (bk_search_at(s, i)->found_at == at)
			return bk_search_at(s, i);
	return NULL;
}

Test(search_plugin, a_planted_generator_is_fitted_first_and_named_in_checkpoints)
{
	bk_samples sm;
	bk_search_options o;
	options(&sm, &o);
	planted_gen p = {0};
	bk_search *S = made(&o, &p), *C = made(&o, NULL);
	size_t len, clen;
	char *fresh = saved(S, &len); /* before any step: the planted stage is the current one */
	cr_assert(strstr(fresh, "\nstage planted\ngenerator planted\nplanted offered 0\ngenerator seeds\n"), "%s", fresh);
	free(fresh);
	run(S);
	run(C);
	cr_assert_eq(p.offered, 1, "the planted tree was not taken");
	const bk_cand *c = fit_number(S, 1), *n = fit_number(C, 1);
	cr_assert(c && n);
	cr_assert_eq(c->status, BK_CAND_OK, "%s", c->text);
	cr_assert_lt(c->err, 1e-6, "the planted form fits to %g: %s", c->err, c->text);
	/* the negative control: without the generator, fit 1 is another form, not at the planted error */
	cr_assert_str_neq(n->text, c->text);
	cr_assert(!(n->err < 1e-6), "fit 1 of the control reaches %g: %s", n->err, n->text);
	char *text = saved(S, &len), *ctext = saved(C, &clen), err[512];
	cr_assert(strstr(text, "\ngenerator planted\nplanted offered 1\ngenerator seeds\n"), "%s", text);
	cr_assert(!strstr(ctext, "planted"), "the control's checkpoint names the planted generator");
	/* it loads back into a search with the generator, whose state it restores */
	planted_gen q = {0};
	bk_search *L = made(&o, &q);
	cr_assert_eq(load(L, text, len, err, sizeof err), 0, "%s", err);
	cr_assert(q.loaded && q.offered == 1);
	cr_assert_eq(bk_search_count(L), bk_search_count(S));
	bk_search_free(L);
	cr_assert_eq(q.freed, 1, "bk_search_free did not free the generator's state");
	/* a search without the generator refuses it, naming the generator */
	L = made(&o, NULL);
	cr_assert_eq(load(L, text, len, err, sizeof err), -1);
	cr_assert_str_eq(err, "generator planted: not in this search's schedule (seeds, enumeration, neighbours, semantic, children)");
	bk_search_free(L);
	/* and the search with it refuses the control's, which lacks it */
	planted_gen z = {0};
	L = made(&o, &z);
	cr_assert_eq(load(L, ctext, clen, err, sizeof err), -1);
	cr_assert(strstr(err, "generator seeds where this search's schedule has planted"), "%s", err);
	bk_search_free(L);
	free(text);
	free(ctext);
	bk_search_free(S);
	bk_search_free(C);
	cr_assert_eq(p.freed, 1);
	bk_samples_free(&sm);
}

/* A checkpoint whose current stage is the generator's, in a search that
 * has no such stage: refused by the stage's name. */
Test(search_plugin, an_unknown_stage_is_refused)
{
	bk_samples sm;
	bk_search_options o;
	options(&sm, &o);
	planted_gen p = {0};
	bk_search *S = made(&o, &p), *L = made(&o, NULL);
	size_t len;
	char *text = saved(S, &len), err[512];
	cr_assert_eq(load(L, text, len, err, sizeof err), -1);
	cr_assert_str_eq(err, "stage planted: not one of this search's (seeds, enumeration, neighbours+semantic+children, done)");
	free(text);
	bk_search_free(L);
	bk_search_free(S);
	bk_samples_free(&sm);
}

/* What bk_search_schedule_add refuses, each with its reason; the schedule is
 * fixed once the search has stepped. */
Test(search_plugin, schedule_add_refuses_what_checkpoints_could_not_name)
{
	bk_samples sm;
	bk_search_options o;
	options(&sm, &o);
	planted_gen p = {0};
	bk_search *S = made(&o, NULL);
	char err[256];
	bk_search_generator g = {"planted", 0, planted_make, NULL, NULL, NULL, &p};
	const struct {
		const char *name;
		int stage, join;
		double share;
		const char *says;
	} bad[] = {
		{"Planted", 0, 0, 1, "a name not of 1 to 31"},
		{"done", 0, 0, 1, "a name not of 1 to 31"},
		{"", 0, 0, 1, "a name not of 1 to 31"},
		{"children", 0, 0, 1, "the schedule has one of that name"},
		{"planted", 0, 0, 0, "a share of 0"},
		{"planted", 4, 0, 1, "stage 4 to go before in a schedule of 3 stages"},
		{"planted", 3, 1, 1, "stage 3 to join in a schedule of 3 stages"},
	};
	for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
		g.name = bad[k].name;
		cr_assert_eq(bk_search_schedule_add(S, bad[k].stage, bad[k].join, bad[k].share, &g, err, sizeof err), -1,
		             "'%s' taken", bad[k].name);
		cr_assert(strstr(err, bad[k].says), "'%s': %s", bad[k].name, err);
	}
	g.name = "planted"; /* the negative control: joining the evolution stage is fine */
	cr_assert_eq(bk_search_schedule_add(S, 2, 1, 0.25, &g, err, sizeof err), 0, "%s", err);
	cr_assert_eq(bk_search_step(S, err, sizeof err), 1, "%s", err);
	g.name = "later";
	cr_assert_eq(bk_search_schedule_add(S, 3, 0, 1, &g, err, sizeof err), -1);
	cr_assert_str_eq(err, "the schedule is fixed once the search is stepped or loaded");
	bk_search_free(S);
	bk_samples_free(&sm);
}
