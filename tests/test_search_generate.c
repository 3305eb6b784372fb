/*
 * test_search_generate.c — the search's generation (fit/search/generate.h):
 * every child is canonical (canonicalising it again changes nothing) and
 * within the grammar's limits (size, parameters, operations, inputs); a
 * candidate already in the cache is not made twice; the enumeration is read
 * in order and ends.
 */
#include "fixture_search.h"
#include "search/generate.h"
#include "ir.h" /* the opcodes, to check a child's operations against the grammar */

#include <criterion/criterion.h>
#include <stdlib.h>
#include <string.h>

/* The options of a search of the planted README form over LoH and r with
 * the operations ops, up to max_size nodes and max_params parameters. */
static void planted_options(bk_samples *sm, const char *ops, int max_size, int max_params, bk_search_options *o)
{
	fx_planted("0.3/(LoH*LoH + 0.7*r*r)", 0.3162, 1, 6, sm);
	char err[256];
	bk_search_defaults(o);
	o->screen = sm;
	o->shape = BK_SHAPE_PLAIN;
	memset(&o->grammar, 0, sizeof o->grammar);
	cr_assert_eq(bk_grammar_parse_ops(ops, &o->grammar.ops, err, sizeof err), 0, "%s", err);
	o->grammar.inputs = 1u << BK_IN_LOH | 1u << BK_IN_R;
	o->grammar.consts[0] = 1;
	o->grammar.nconsts = 1;
	o->grammar.max_params = max_params;
	o->grammar.max_size = max_size;
}

static bk_search *grown(bk_samples *sm, const char *ops, int max_size, int max_params)
{
	char err[256];
	bk_search_options o;
	planted_options(sm, ops, max_size, max_params, &o);
	o.enum_max = 150;
	o.generation = 50;
	o.evals = 300;
	bk_search *s = bk_search_new(&o, err, sizeof err);
	cr_assert(s, "%s", err);
	int rc;
	while ((rc = bk_search_step(s, err, sizeof err)) == 1)
		;
	cr_assert_eq(rc, 0, "%s", err);
	cr_assert_gt(s->nlv, 0, "the archive has parents");
	return s;
}

/* 0 when t is canonical and within g's limits, else which rule it breaks. */
static const char *breaks(const bk_grammar *g, const bk_expr *t)
{
	char why[128], a[4096], b[4096];
	if (bk_expr_valid(t, why, sizeof why))
		return "not a valid tree";
	bk_expr c = *t;
	if (bk_expr_canon(&c) || bk_expr_print(t, a, sizeof a) < 0 || bk_expr_print(&c, b, sizeof b) < 0 || strcmp(a, b))
		return "not canonical";
	if (bk_expr_size(t) > g->max_size)
		return "over max_size";
	if (bk_expr_nparams(t) > g->max_params)
		return "over max_params";
	for (int i = 0; i < t->n; i++) {
		const bk_enode *n = &t->node[i];
		if (n->op == BK_OP_INPUT && !(g->inputs >> n->slot & 1))
			return "an input the grammar does not allow";
		if (n->op > BK_OP_PARAM && !(g->ops >> n->op & 1))
			return "an operation the grammar does not allow";
	}
	return NULL;
}

Test(search_generate, child_is_canonical_and_within_the_grammar)
{
	bk_samples sm;
	bk_search *s = grown(&sm, "+,*,/,sq,sqrt", 9, 2);
	int made = 0;
	for (int k = 0; k < 2000; k++) {
		bk_expr t[2];
		if (bk_gen_child(s, t))
			continue;
		made++;
		const char *why = breaks(&s->tree_g, &t[0]);
		char txt[4096];
		bk_expr_print(&t[0], txt, sizeof txt);
		cr_assert_null(why, "child %d %s: %s", k, txt, why);
	}
	cr_assert_gt(made, 1000, "most tries make a child (%d)", made);
	bk_search_free(s);
	bk_samples_free(&sm);
}

Test(search_generate, the_check_can_fail)
{
	/* negative control of breaks(): a non-canonical tree (x*1), one too
	 * large, one with an operation outside the grammar */
	bk_grammar g;
	memset(&g, 0, sizeof g);
	char err[128];
	cr_assert_eq(bk_grammar_parse_ops("+,*", &g.ops, err, sizeof err), 0);
	g.inputs = 1u << BK_IN_LOH;
	g.max_params = 1;
	g.max_size = 3;
	bk_expr t = {.n = 3, .node = {{BK_OP_MUL, 0, 0}, {BK_OP_INPUT, BK_IN_LOH, 0}, {BK_OP_CONST, 0, 1}}};
	cr_assert_str_eq(breaks(&g, &t), "not canonical");
	bk_expr u = {.n = 2, .node = {{BK_OP_SQRT, 0, 0}, {BK_OP_INPUT, BK_IN_LOH, 0}}};
	cr_assert_str_eq(breaks(&g, &u), "an operation the grammar does not allow");
	g.max_size = 2;
	bk_expr v = {.n = 3, .node = {{BK_OP_ADD, 0, 0}, {BK_OP_INPUT, BK_IN_LOH, 0}, {BK_OP_PARAM, 0, 0}}};
	cr_assert_eq(bk_expr_canon(&v), 0);
	cr_assert_str_eq(breaks(&g, &v), "over max_size");
	g.max_size = 3;
	cr_assert_null(breaks(&g, &v));
}

Test(search_generate, a_candidate_in_the_cache_is_not_made_again)
{
	bk_samples sm;
	bk_search *s = grown(&sm, "+,*,/,sq", 9, 2);
	bk_expr t[2];
	memset(t, 0, sizeof t);
	bk_cand_trees(&s->cand[s->n - 1], t); /* fitted already */
	t[1].n = 0;
	bk_cand c;
	cr_assert_eq(bk_gen_prepare(s, t, &c), 0);
	/* negative control: a tree the search cannot have made (larger than its
	 * max_size; prepare judges cost and parameters, not size) is new once */
	bk_form_error fe;
	bk_form *f = bk_form_parse("sq(LoH + r) + sq(r*LoH + r)", &fe);
	cr_assert(f);
	bk_expr e;
	cr_assert_eq(bk_expr_from_form(f, &e), 0);
	bk_form_free(f);
	cr_assert_eq(bk_expr_canon(&e), 0);
	t[0] = e;
	size_t seen = s->seen.n;
	cr_assert_eq(bk_gen_prepare(s, t, &c), 1);
	free(c.text);
	cr_assert_eq(s->seen.n, seen + 1);
	cr_assert_eq(bk_gen_prepare(s, t, &c), 0);
	bk_search_free(s);
	bk_samples_free(&sm);
}

/* The search of grown()'s options to n fits, one step at a time; with forget,
 * the record of neighbour lists tried whole (nb_done) is emptied after every
 * step, and with poison every list is recorded as tried before the first. */
static bk_search *stepped(bk_samples *sm, int forget, int poison)
{
	char err[256];
	bk_search_options o;
	planted_options(sm, "+,*,/,sq,mix", 11, 3, &o);
	o.enum_max = 100;
	o.generation = 40;
	o.evals = 900;
	bk_search *s = bk_search_new(&o, err, sizeof err);
	cr_assert(s, "%s", err);
	for (uint64_t k = 1; poison && k <= 3 * 2000; k++)
		cr_assert_geq(bk_hashset_add(&s->nb_done, k), 0);
	int rc;
	while ((rc = bk_search_step(s, err, sizeof err)) == 1)
		if (forget)
			bk_hashset_free(&s->nb_done);
	cr_assert_eq(rc, 0, "%s", err);
	return s;
}

/* 1 when a and b fitted the same candidates in the same order */
static int same_run(const bk_search *a, const bk_search *b)
{
	if (a->n != b->n)
		return 0;
	for (size_t i = 0; i < a->n; i++)
		if (strcmp(a->cand[i].text, b->cand[i].text))
			return 0;
	return 1;
}

Test(search_generate, skipping_neighbour_lists_tried_whole_changes_no_candidate)
{
	bk_samples sm[3];
	bk_search *kept = stepped(&sm[0], 0, 0), *remade = stepped(&sm[1], 1, 0);
	cr_assert_gt(kept->nb_done.n, 20, "lists were skipped (%zu recorded)", kept->nb_done.n);
	cr_assert(same_run(kept, remade), "the same %zu candidates with the lists made again", kept->n);
	/* negative control: lists recorded as tried before they were (none then
	 * comes from a neighbour) make another run, and same_run says so */
	bk_search *poisoned = stepped(&sm[2], 0, 1);
	cr_assert_not(same_run(kept, poisoned), "a run without neighbours differs");
	bk_search_free(kept);
	bk_search_free(remade);
	bk_search_free(poisoned);
	for (int k = 0; k < 3; k++)
		bk_samples_free(&sm[k]);
}
