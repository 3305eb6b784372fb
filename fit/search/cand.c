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

int bk_cand_cost(const bk_search *s, const char *a, const char *b, bk_ops *ops, double *cost, int *np)
{
	/* a seed may be as long as a form may: the pair's text is allocated */
	char *buf = b && *b ? bk_pair_dup(a, b) : strdup(a);
	if (!buf)
		return -1;
	bk_form_error fe;
	bk_form *f = bk_form_parse(buf, &fe);
	free(buf);
	if (!f)
		return -1;
	bk_cand_cost_of(s, f, ops, cost, np);
	bk_form_free(f);
	return 0;
}

void bk_cand_cost_of(const bk_search *s, const bk_form *f, bk_ops *ops, double *cost, int *np)
{
	bk_form_count(f, ops);
	*cost = bk_ops_cost(ops, s->o.simple_cost, s->o.complex_cost);
	*np = bk_form_nparams(f);
}

/* The hash of "a;b", in pieces (no buffer to outgrow). */
uint64_t bk_cand_key(const char *a, const char *b)
{
	uint64_t h = bk_hash_bytes(BK_HASH_INIT, a, strlen(a));
	h = bk_hash_bytes(h, ";", 1);
	return b ? bk_hash_bytes(h, b, strlen(b)) : h;
}

void bk_cand_free(bk_cand *c)
{
	free(c->text);
	free(c->text_b);
	bk_form_free(c->form);
	c->form = NULL;
}
