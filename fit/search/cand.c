/*
 * cand.c — a candidate's text, cost and key (cand.h).
 */
#include "search/cand.h"
#include "search/pair.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int bk_cand_text(const bk_search *s, const bk_expr *t, char *a, char *b, size_t len)
{
	char g[4096];
	if (bk_expr_print(&t[0], g, sizeof g) < 0)
		return -1;
	b[0] = '\0';
	switch (s->o.shape) {
	case BK_SHAPE_F0:
		return snprintf(a, len, "f0*(%s)", g) >= (int)len ? -1 : 0;
	case BK_SHAPE_PAIR: {
		if (t[1].n == 0) { /* a shared feature s: A and B linear in s and r (Karis' structure) */
			int k = bk_expr_nparams(&t[0]), r = s->o.grammar.inputs >> BK_IN_R & 1;
			int ra = snprintf(a, len, r ? "p%d*(%s) + p%d*r + p%d" : "p%d*(%s) + p%d", k, g, k + 1, k + 2);
			int rb = snprintf(b, len, r ? "p%d*(%s) + p%d*r + p%d" : "p%d*(%s) + p%d", k + 3, g, k + 4, k + 5);
			return ra >= (int)len || rb >= (int)len ? -1 : 0;
		}
		/* B's parameters follow A's: shift them in a copy */
		bk_expr tb = t[1];
		bk_expr_shift_params(&tb, bk_expr_nparams(&t[0]));
		snprintf(a, len, "%s", g);
		return bk_expr_print(&tb, b, len) < 0 ? -1 : 0;
	}
	default:
		snprintf(a, len, "%s", g);
		return 0;
	}
}

void bk_cand_cost_of(const bk_search *s, const bk_form *f, bk_ops *ops, double *cost, int *np)
{
	bk_form_count(f, ops);
	*cost = bk_ops_cost(ops, s->o.simple_cost, s->o.complex_cost);
	*np = bk_form_nparams(f);
}

/* c's forms made (form, and form_b of a pair): the pair as one form, the cost */
static int finish(const bk_search *s, bk_cand *c, const char *a, const char *b)
{
	if (b && *b) { /* A and B as the one program a shader runs: shared work counted once */
		bk_form_error fe;
		char *buf = bk_pair_dup(a, b);
		c->form_pair = buf ? bk_form_parse(buf, &fe) : NULL;
		free(buf);
	}
	if (!c->form || (b && *b && (!c->form_b || !c->form_pair))) {
		bk_cand_free_forms(c);
		return -1;
	}
	bk_cand_cost_of(s, c->form_pair ? c->form_pair : c->form, &c->ops, &c->cost, &c->np);
	return 0;
}

int bk_cand_parse(const bk_search *s, bk_cand *c, const char *a, const char *b)
{
	bk_form_error fe;
	c->form = bk_form_parse(a, &fe);
	if (b && *b)
		c->form_b = bk_form_parse(b, &fe);
	return finish(s, c, a, b);
}

int bk_cand_adopt(const bk_search *s, bk_cand *c, const bk_form *fa, const bk_form *fb, const char *a, const char *b)
{
	c->form = bk_form_dup(fa);
	if (b && *b)
		c->form_b = fb ? bk_form_dup(fb) : NULL;
	return finish(s, c, a, b);
}

void bk_cand_free_forms(bk_cand *c)
{
	bk_form_free(c->form);
	bk_form_free(c->form_b);
	bk_form_free(c->form_pair);
	c->form = c->form_b = c->form_pair = NULL;
}

/* The hash of "a;b", in pieces (no buffer to outgrow). */
uint64_t bk_cand_key(const char *a, const char *b)
{
	uint64_t h = bk_hash_bytes(BK_HASH_INIT, a, strlen(a));
	h = bk_hash_bytes(h, ";", 1);
	return b ? bk_hash_bytes(h, b, strlen(b)) : h;
}

void bk_cand_trees(const bk_cand *c, bk_expr t[2])
{
	t[0].n = t[1].n = 0;
	if (!c->tree) /* a candidate made by hand (the tests') */
		return;
	t[0].n = c->ntree[0];
	t[1].n = c->ntree[1];
	memcpy(t[0].node, c->tree, sizeof *c->tree * (size_t)t[0].n);
	memcpy(t[1].node, c->tree + t[0].n, sizeof *c->tree * (size_t)t[1].n);
}

int bk_cand_set_trees(bk_cand *c, const bk_expr *t, int two)
{
	int n0 = t[0].n, n1 = two ? t[1].n : 0;
	free(c->tree);
	c->ntree[0] = c->ntree[1] = 0;
	c->tree = malloc(sizeof *c->tree * (size_t)(n0 + n1 > 0 ? n0 + n1 : 1));
	if (!c->tree)
		return -1;
	memcpy(c->tree, t[0].node, sizeof *c->tree * (size_t)n0);
	if (n1)
		memcpy(c->tree + n0, t[1].node, sizeof *c->tree * (size_t)n1);
	c->ntree[0] = n0;
	c->ntree[1] = n1;
	return 0;
}

void bk_cand_free(bk_cand *c)
{
	free(c->text);
	free(c->text_b);
	free(c->tree);
	c->tree = NULL;
	bk_cand_free_forms(c);
}
