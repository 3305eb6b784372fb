/*
 * prune.c — dead branches of a fitted form (prune.h). The form's tree
 * (bk_expr_from_form, the IR's code back as a tree) is walked in prefix
 * order; each candidate node's operand subtrees are printed, compiled and
 * evaluated on the samples, and a node whose one side always wins is
 * spliced out (a subtree is a contiguous run of nodes, expr.h).
 */
#include "search/prune.h"

#include "brdf_ops.h"
#include "expr.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The samples a form is judged on: n of them from in. */
typedef struct range {
	size_t n;
	const double *in[BK_IN_COUNT];
} range;

static range range_of(const bk_samples *s, size_t lo, size_t hi)
{
	range r = {hi - lo, {0}};
	for (int k = 0; k < BK_IN_COUNT; k++)
		r.in[k] = s->in[k] ? s->in[k] + lo : NULL;
	return r;
}

/* The values of the subtree at node i of e on the samples; 0 or -1. */
static int subtree_values(const bk_expr *e, int i, const double *p, const range *s, double *v)
{
	bk_expr sub;
	sub.n = bk_expr_span(e, i);
	memcpy(sub.node, e->node + i, sizeof(bk_enode) * (size_t)sub.n);
	char text[4096];
	if (bk_expr_print(&sub, text, sizeof text) < 0)
		return -1;
	bk_form_error fe;
	bk_form *f = bk_form_parse(text, &fe);
	if (!f)
		return -1;
	int rc = bk_form_eval(f, BK_F64, s->n, s->in, p, v);
	bk_form_free(f);
	return rc;
}

/* 1 if lo[k] <= hi[k] at every sample, each finite (lo or hi NULL: the
 * constant c in its place). */
static int always_le(const double *lo, const double *hi, double c, size_t n)
{
	for (size_t k = 0; k < n; k++) {
		double a = lo ? lo[k] : c, b = hi ? hi[k] : c;
		if (!(isfinite(a) && isfinite(b) && a <= b))
			return 0;
	}
	return 1;
}

/* Which operand (0, 1, 2) node i always equals, or -1. v: three buffers of
 * s->n values. */
static int winner(const bk_expr *e, int i, const double *p, const range *s, double *v[3], int *err)
{
	int op = e->node[i].op;
	if (op != BK_OP_MAX && op != BK_OP_MIN && op != BK_OP_CLAMP && op != BK_OP_SATURATE && op != BK_OP_MIX)
		return -1;
	int at = i + 1;
	for (int j = 0; j < bk_op_arity(op); j++) {
		if (subtree_values(e, at, p, s, v[j])) {
			*err = 1;
			return -1;
		}
		at += bk_expr_span(e, at);
	}
	size_t n = s->n;
	switch (op) {
	case BK_OP_MAX: return always_le(v[1], v[0], 0, n) ? 0 : always_le(v[0], v[1], 0, n) ? 1 : -1;
	case BK_OP_MIN: return always_le(v[0], v[1], 0, n) ? 0 : always_le(v[1], v[0], 0, n) ? 1 : -1;
	case BK_OP_CLAMP: return always_le(v[1], v[0], 0, n) && always_le(v[0], v[2], 0, n) ? 0 : -1;
	case BK_OP_MIX: /* x + (y - x) t: x where t is 0 at every sample, y where 1 (x, y finite) */
		return always_le(v[2], NULL, 0, n) && always_le(NULL, v[2], 0, n) && always_le(v[0], v[0], 0, n)    ? 0
		       : always_le(v[2], NULL, 1, n) && always_le(NULL, v[2], 1, n) && always_le(v[1], v[1], 0, n) ? 1
		                                                                                                     : -1;
	default: return always_le(NULL, v[0], 0, n) && always_le(v[0], NULL, 1, n) ? 0 : -1; /* saturate */
	}
}

/* Node i of e replaced by its operand j (a whole subtree). */
static void splice(bk_expr *e, int i, int j)
{
	int at = i + 1;
	for (int k = 0; k < j; k++)
		at += bk_expr_span(e, at);
	int keep = bk_expr_span(e, at), whole = bk_expr_span(e, i);
	memmove(e->node + i, e->node + at, sizeof(bk_enode) * (size_t)keep);
	memmove(e->node + i + keep, e->node + i + whole, sizeof(bk_enode) * (size_t)(e->n - i - whole));
	e->n -= whole - keep;
}

/* Parameters renumbered by first appearance over the trees e[0..n), their
 * values from p. */
static void renumber(bk_expr *e, int n, const double *p, double *pout)
{
	int map[BK_MAX_PARAMS], next = 0;
	for (int k = 0; k < BK_MAX_PARAMS; k++)
		map[k] = -1;
	for (int t = 0; t < n; t++)
		for (int i = 0; i < e[t].n; i++) {
			bk_enode *x = &e[t].node[i];
			if (x->op != BK_OP_PARAM)
				continue;
			if (map[x->slot] < 0) {
				pout[next] = p[x->slot];
				map[x->slot] = next++;
			}
			x->slot = map[x->slot];
			x->k = pout[x->slot]; /* where a fit of the tree starts (expr.h) */
		}
	for (int k = next; k < BK_MAX_PARAMS; k++)
		pout[k] = 0;
}

/* f's tree into e, its dead nodes replaced on the samples r; the count
 * replaced, or -1. */
static int prune_tree(const bk_form *f, const double *p, const range *r, bk_expr *e)
{
	int rc = bk_expr_from_form(f, e);
	if (!rc && r->n == 0)
		return 0; /* no sample: nothing shows a side dead */
	double *buf = rc ? NULL : malloc(sizeof(double) * 3 * r->n);
	if (!buf)
		return -1;
	double *v[3] = {buf, buf + r->n, buf + 2 * r->n};
	int pruned = 0, err = 0;
	for (int i = 0; i < e->n && !err;) {
		int j = winner(e, i, p, r, v, &err);
		if (j < 0) {
			i++;
			continue;
		}
		splice(e, i, j);
		pruned++; /* node i is now the kept side: looked at again */
	}
	free(buf);
	return err ? -1 : pruned;
}

int bk_prune_dead_forms(const bk_form *fa, const bk_form *fb, const double *p, const bk_samples *s, char *out_a,
                        char *out_b, size_t len, double *pout)
{
	int two = fb != NULL;
	size_t split = two && s->ncomp > 1 ? s->start[1] : s->n;
	range r[2] = {range_of(s, 0, split), range_of(s, split, s->n)};
	bk_expr e[2];
	int na = prune_tree(fa, p, &r[0], &e[0]), nb = two ? prune_tree(fb, p, &r[1], &e[1]) : 0;
	if (na < 0 || nb < 0)
		return -1;
	if (na + nb == 0)
		return 0;
	renumber(e, two ? 2 : 1, p, pout);
	if (bk_expr_print(&e[0], out_a, len) < 0 || (two && bk_expr_print(&e[1], out_b, len) < 0))
		return -1;
	return na + nb;
}

int bk_prune_dead_pair(const char *text_a, const char *text_b, const double *p, const bk_samples *s, char *out_a,
                       char *out_b, size_t len, double *pout)
{
	bk_form_error fe;
	bk_form *f[2] = {bk_form_parse(text_a, &fe), text_b ? bk_form_parse(text_b, &fe) : NULL};
	int n = !f[0] || (text_b && !f[1]) ? -1 : bk_prune_dead_forms(f[0], f[1], p, s, out_a, out_b, len, pout);
	bk_form_free(f[0]);
	bk_form_free(f[1]);
	return n;
}

int bk_prune_dead(const char *text, const double *p, const bk_samples *s, char *out, size_t len, double *pout)
{
	return bk_prune_dead_pair(text, NULL, p, s, out, NULL, len, pout);
}
