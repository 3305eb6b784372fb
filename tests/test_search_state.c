/*
 * test_search_state.c — the search's checkpoint state (fit/search/state.h):
 * save -> load -> save gives the same bytes (nothing is lost or rewritten
 * on the way), for a plain search and for a pair search (two trees, two
 * texts, seeds); a checkpoint is refused by a search with another seed (the
 * fingerprint), and an exported set of migrants is taken by another island.
 */
#include "search/state.h"

#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void target(bk_samples *sm, bk_target_kind kind)
{
	bk_target_options to;
	bk_target_defaults(kind, &to);
	if (kind == BK_TARGET_FORM) {
		to.form_text = "0.3/(LoH*LoH + 0.7*r*r)";
		to.ndomain = 2;
		to.dom_in[0] = BK_IN_LOH, to.dom_lo[0] = 0.3162, to.dom_hi[0] = 1;
		to.dom_in[1] = BK_IN_R, to.dom_lo[1] = 0, to.dom_hi[1] = 1;
	}
	to.nx = 6;
	to.nr = 6;
	char err[256];
	cr_assert_eq(bk_target_build(&to, sm, NULL, NULL, err, sizeof err), 0, "%s", err);
}

static const char *const seed_a[] = {"p0/(LoH*LoH + p1)"};
static const char *const env_a[] = {"1 - p0*r"}, *const env_b[] = {"p0*r*NoV"};

static void options(bk_search_options *o, const bk_samples *sm, int pair)
{
	bk_search_defaults(o);
	o->screen = sm;
	o->shape = pair ? BK_SHAPE_PAIR : BK_SHAPE_PLAIN;
	memset(&o->grammar, 0, sizeof o->grammar);
	char err[128];
	cr_assert_eq(bk_grammar_parse_ops("+,*,/,sq", &o->grammar.ops, err, sizeof err), 0, "%s", err);
	o->grammar.inputs = pair ? 1u << BK_IN_NOV | 1u << BK_IN_R : 1u << BK_IN_LOH | 1u << BK_IN_R;
	o->grammar.consts[0] = 1;
	o->grammar.nconsts = 1;
	o->grammar.max_params = pair ? 6 : 2;
	o->grammar.max_size = 9;
	o->enum_max = 100;
	o->generation = 40;
	o->evals = 220;
	o->seeds = pair ? env_a : seed_a;
	o->seeds_b = pair ? env_b : NULL;
	o->nseeds = 1;
	o->env_bound = pair;
}

static bk_search *stepped(const bk_search_options *o)
{
	char err[256];
	bk_search *s = bk_search_new(o, err, sizeof err);
	cr_assert(s, "%s", err);
	int rc;
	while ((rc = bk_search_step(s, err, sizeof err)) == 1)
		;
	cr_assert_eq(rc, 0, "%s", err);
	return s;
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

static void round_trip(int pair)
{
	bk_samples sm;
	target(&sm, pair ? BK_TARGET_ENV : BK_TARGET_FORM);
	bk_search_options o;
	options(&o, &sm, pair);
	bk_search *s = stepped(&o);
	cr_assert_gt(bk_search_count(s), 100);
	size_t n1, n2;
	char *one = saved(s, &n1);
	char err[256];
	bk_search *t = bk_search_new(&o, err, sizeof err);
	cr_assert(t, "%s", err);
	FILE *f = fmemopen(one, n1, "r");
	cr_assert_eq(bk_search_load(t, f, err, sizeof err), 0, "%s", err);
	fclose(f);
	char *two = saved(t, &n2);
	cr_assert_eq(n1, n2);
	cr_assert_eq(memcmp(one, two, n1), 0, "save -> load -> save is byte-identical");
	cr_assert_eq(bk_search_count(t), bk_search_count(s));

	/* negative control: a search with another seed refuses the checkpoint */
	o.seed = 2;
	bk_search *u = bk_search_new(&o, err, sizeof err);
	f = fmemopen(one, n1, "r");
	cr_assert_eq(bk_search_load(u, f, err, sizeof err), -1);
	cr_assert(strstr(err, "other options"), "%s", err);
	fclose(f);
	bk_search_free(u);
	free(one);
	free(two);
	bk_search_free(s);
	bk_search_free(t);
	bk_samples_free(&sm);
}

Test(search_state, save_load_save_is_byte_identical) { round_trip(0); }
Test(search_state, save_load_save_is_byte_identical_for_pairs) { round_trip(1); }

Test(search_state, migrants_taken_by_another_island)
{
	bk_samples sm;
	target(&sm, BK_TARGET_FORM);
	bk_search_options o;
	options(&o, &sm, 0);
	o.islands = 2;
	bk_search *a = stepped(&o);
	o.island = 1;
	o.seed = 5;
	char err[256];
	bk_search *b = bk_search_new(&o, err, sizeof err);
	cr_assert(b, "%s", err);
	size_t idx[4] = {0, 1, 2, 3}, added;
	char *buf = NULL;
	size_t len;
	FILE *f = open_memstream(&buf, &len);
	cr_assert_eq(bk_search_export(a, idx, 4, f), 0);
	fclose(f);
	f = fmemopen(buf, len, "r");
	cr_assert_eq(bk_search_import(b, f, &added, err, sizeof err), 0, "%s", err);
	fclose(f);
	cr_assert_eq(added, 4);
	cr_assert_eq(bk_search_evals(b), 0, "migrants cost no fit");
	cr_assert_str_eq(bk_search_at(b, 2)->text, bk_search_at(a, 2)->text);
	/* the same again: nothing new */
	f = fmemopen(buf, len, "r");
	cr_assert_eq(bk_search_import(b, f, &added, err, sizeof err), 0, "%s", err);
	fclose(f);
	cr_assert_eq(added, 0);
	free(buf);
	bk_search_free(a);
	bk_search_free(b);
	bk_samples_free(&sm);
}
