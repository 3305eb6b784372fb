/*
 * expr.c — the search's candidate trees: canonical form, printing to the
 * formula language, the tree of a compiled form, bottom-up enumeration,
 * mutation and crossover (see expr.h).
 *
 * Size: the grammar's size of a tree counts one per node, except that
 * sq(x) (MUL with two equal operands: the op table has no SQ and needs none,
 * the parser compiles sq(x) to exactly that MUL) counts 1 + size(x), as the
 * one operation the grammar names. max_size and the enumeration's sizes are
 * this measure (bk_expr_size); BK_EXPR_MAX bounds the stored nodes.
 */
#include "expr.h"
#include "brdf_ops.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Registry terms (D_ggx, F_schlick, ...) are operations of the trees too
 * when a grammar allows them (--ops F_schlick): op TERM0 + t is
 * bk_term_at(t), printed as a call the IR's parser inlines, so its cost is
 * that of its definition after folding and sharing, as for any form. */
#define TERM0 BK_OP_COUNT
/* sq is not an opcode (see the top of the file); its bit is one the op
 * table never reaches, nor a term's (a term's bit is its op). */
#define SQ_BIT 63

static int term_arity(size_t t)
{
	const char *a = bk_term_at(t)->args;
	int n = *a != '\0';
	for (; *a; a++)
		n += *a == ',';
	return n;
}

/* The ops' arities from the one table (ir_ops.h), here rather than through
 * bk_op_arity: canonicalisation asks for them at every node it walks (span_at,
 * pass), and the call into the library was 13 % of a half-precision search's
 * time on f (perf). */
static const signed char op_arity[BK_OP_COUNT] = {
#define OP(e, name, ar, ...) [BK_OP_##e] = ar,
#include "ir_ops.h"
#undef OP
};

static int arity(int op)
{
	return op >= 0 && op < TERM0 ? op_arity[op] : op >= TERM0 ? term_arity((size_t)(op - TERM0)) : -1;
}

int bk_expr_op_valid(int op)
{
	if (op < 0)
		return 0;
	if (op < TERM0)
		return 1;
	size_t t = (size_t)(op - TERM0);
	return op < SQ_BIT && t < bk_term_count() && term_arity(t) >= 1 && term_arity(t) <= 3;
}

int bk_expr_valid(const bk_expr *e, char *why, size_t len)
{
	if (e->n < 1 || e->n > BK_EXPR_MAX) {
		snprintf(why, len, "%d nodes (1 to %d)", e->n, BK_EXPR_MAX);
		return -1;
	}
	int need = 1; /* subtrees still to read: the prefix code ends where it reaches 0 */
	for (int i = 0; i < e->n; i++) {
		const bk_enode *n = &e->node[i];
		const char *bad = NULL;
		if (need == 0)
			bad = "past the end of the tree";
		else if (!bk_expr_op_valid(n->op))
			bad = "no such operation";
		else if (n->op == BK_OP_INPUT && (n->slot < 0 || n->slot >= BK_IN_COUNT))
			bad = "input out of range";
		else if (n->op == BK_OP_PARAM && (n->slot < 0 || n->slot >= BK_MAX_PARAMS))
			bad = "parameter out of range";
		else if ((n->op == BK_OP_CONST || n->op == BK_OP_PARAM) && !isfinite(n->k))
			bad = "value not finite";
		if (bad) {
			snprintf(why, len, "node %d (op %d, slot %d): %s", i, n->op, n->slot, bad);
			return -1;
		}
		need += arity(n->op) - 1;
	}
	if (need != 0) {
		snprintf(why, len, "%d operands missing after node %d", need, e->n - 1);
		return -1;
	}
	return 0;
}

static const char *op_name(int op) { return op < TERM0 ? bk_op_name(op) : bk_term_at((size_t)(op - TERM0))->name; }

static int span_at(const bk_enode *s)
{
	int need = 1, i = 0;
	while (need) {
		need += arity(s[i].op) - 1;
		i++;
	}
	return i;
}

int bk_expr_span(const bk_expr *e, int i) { return span_at(e->node + i); }

int bk_expr_nparams(const bk_expr *e)
{
	int n = 0;
	for (int i = 0; i < e->n; i++)
		if (e->node[i].op == BK_OP_PARAM && e->node[i].slot + 1 > n)
			n = e->node[i].slot + 1;
	return n;
}

/* Two subtrees equal node for node (parameters by number: sq needs the same
 * value twice). */
static int same_n(const bk_enode *a, int la, const bk_enode *b, int lb)
{
	if (la != lb)
		return 0;
	for (int i = 0; i < la; i++)
		if (a[i].op != b[i].op || a[i].slot != b[i].slot || (a[i].op == BK_OP_CONST && a[i].k != b[i].k))
			return 0;
	return 1;
}

static int same(const bk_enode *a, const bk_enode *b) { return same_n(a, span_at(a), b, span_at(b)); }

static int size_at(const bk_enode *s, int *len)
{
	int ar = arity(s->op), pos = 1, sz = 1, l;
	if (s->op == BK_OP_MUL && same(s + 1, s + 1 + span_at(s + 1))) {
		sz += size_at(s + 1, &l);
		*len = 1 + 2 * l;
		return sz;
	}
	for (int j = 0; j < ar; j++) {
		sz += size_at(s + pos, &l);
		pos += l;
	}
	*len = pos;
	return sz;
}

void bk_expr_shift_params(bk_expr *e, int by)
{
	for (int i = 0; i < e->n; i++)
		if (e->node[i].op == BK_OP_PARAM)
			e->node[i].slot += by;
}

int bk_expr_size(const bk_expr *e)
{
	int len;
	return e->n ? size_at(e->node, &len) : 0;
}

/* ---- canonical form ------------------------------------------------------- */

/* The order of commutative operands: parameters, then literals (by value),
 * then inputs (by slot), then operations (by opcode), operands compared in
 * prefix order. Parameter numbers are ignored, so p0*x and x*p1 sort alike
 * and renumbering cannot change the order. A prefix code is prefix-free, so
 * comparing node by node always decides before either tree ends. */
static int rank(int op)
{
	return op == BK_OP_PARAM ? 0 : op == BK_OP_CONST ? 1 : op == BK_OP_INPUT ? 2 : 3 + op;
}

/* a (la nodes) against b (lb nodes) in the canonical order */
static int cmp_tree(const bk_enode *a, int la, const bk_enode *b, int lb)
{
	for (int i = 0; i < la && i < lb; i++) {
		int ra = rank(a[i].op), rb = rank(b[i].op);
		if (ra != rb)
			return ra < rb ? -1 : 1;
		if (a[i].op == BK_OP_INPUT && a[i].slot != b[i].slot)
			return a[i].slot < b[i].slot ? -1 : 1;
		if (a[i].op == BK_OP_CONST && a[i].k != b[i].k)
			return a[i].k < b[i].k ? -1 : 1;
	}
	return 0;
}

static int commutative(int op)
{
	return op == BK_OP_ADD || op == BK_OP_MUL || op == BK_OP_MIN || op == BK_OP_MAX || op == BK_OP_MAD;
}

static int is_const(const bk_enode *n, double k) { return n->op == BK_OP_CONST && n->k == k; }

/* Replaces the node at d (length len) by its operand at offset off. */
static int take(bk_enode *d, int off, int len)
{
	memmove(d, d + off, sizeof *d * (size_t)len);
	return len;
}

/* The value of an input-free subtree at its parameters' start values (a
 * PARAM's k, 0 for none: expr.h); NaN when one is unknown. */
static double value_of(const bk_enode *n)
{
	if (n->op == BK_OP_CONST)
		return n->k;
	if (n->op == BK_OP_PARAM)
		return n->k != 0 ? n->k : NAN;
	if (n->op == BK_OP_INPUT || n->op >= TERM0) /* a term: the IR folds it, not the tree */
		return NAN;
	double v[3] = {0, 0, 0};
	const bk_enode *c = n + 1;
	for (int j = 0; j < arity(n->op); j++, c += span_at(c))
		if (isnan(v[j] = value_of(c)))
			return NAN;
	return bk_ir_apply((bk_op)n->op, v[0], v[1], v[2]);
}

double bk_expr_snap(double v)
{
	double m = nearbyint(v * BK_EXPR_SNAP_DENOM) / BK_EXPR_SNAP_DENOM;
	/* never to 0: a small literal (Unreal's 1e-5) is no rounding of zero */
	return isfinite(v) && m != 0 && fabs(v - m) <= BK_EXPR_SNAP_TOL * fabs(v) ? m + 0.0 : v;
}

/* A parameter's start value through a rewrite: negated (the sign moved into
 * it) or inverted (x/p became x*p); unknown stays unknown. */
static void start_neg(bk_enode *p) { p->k = -p->k + 0.0; }
static void start_inv(bk_enode *p) { p->k = p->k != 0 && isfinite(1 / p->k) ? 1 / p->k : 0; }

/* One bottom-up pass over the subtree s, written to d; returns its length.
 * The rules, each applied to a node whose operands are already rewritten:
 *  - all operands literals: folded with bk_ir_apply, kept only if finite
 *    (sqrt(-1) stays as written: the candidate is then rejected by the fit);
 *  - no input read but a parameter used: one parameter (a constant to fit;
 *    p0*p1, sqrt(p0), p0 + 2 and -p0 are all just "a constant");
 *  - exact identities: x*1, 1*x, x/1, x - 0, x + 0, 0 + x -> x (x + 0 differs
 *    from x only in the sign of a zero), -(-x) -> x, x - k -> x + (-k) for a
 *    literal k (exact in IEEE arithmetic: one spelling for x - 1 and x + -1);
 *  - x*rcp(y) -> x/y (one rounding apart; the cheaper spelling);
 *  - x - x -> 0, x/x -> 1, min(x, x), max(x, x), mix(x, x, t) -> x, and a
 *    negation undone a level up (x - (-y), x + (-y), (-x)*(-y), (-x)/(-y),
 *    -(x - y)): the search means the model, not its NaN at x = 0 or inf;
 *  - literals within BK_EXPR_SNAP_TOL of a multiple of 1/BK_EXPR_SNAP_DENOM
 *    snapped to it (-0.4999999999999999 is -0.5: folding's rounding);
 *  - a free parameter absorbs what is around it: x - p -> x + p, x / p ->
 *    x * p (the fit finds -p and 1/p), (x op p) op p' -> x op p for op + and *
 *    (p0*p1 spread over two levels is one constant), p*(-x) -> p*x and
 *    -(p*x), -(p/x), -(x/p) -> the same without the minus (the sign goes
 *    into p);
 *  - operands of ADD MUL MIN MAX and the first two of MAD in cmp_tree order.
 * Start values go with their parameters (expr.h): a collapsed subtree's is
 * its value, an absorbed sign or inverse goes into it, p and p' of
 * (x op p) op p' combine; the function at the start values is unchanged.
 * Returns -1 if a rewrite would not fit (none grows the tree). */
/* The node at off (an operand, length len) removed from d's first pos nodes:
 * a NEG dropped in place. Returns the new length. */
static int drop(bk_enode *d, int at, int pos)
{
	memmove(&d[at], &d[at + 1], sizeof *d * (size_t)(pos - at - 1));
	return pos - 1;
}

/* One bottom-up pass over the subtree at s into d; returns d's length and
 * sets *used to s's (the source spans come back with the recursion, so no
 * operand's span is walked twice). */
static int pass(const bk_enode *s, bk_enode *d, int ra, int *used)
{
	int op = s->op, ar = arity(op);
	d[0] = *s;
	*used = 1;
	if (op == BK_OP_CONST)
		d[0].k = bk_expr_snap(d[0].k);
	if (ar == 0)
		return 1;
	d[0].slot = 0, d[0].k = 0;
	int off[3] = {1, 1, 1}, len[3] = {0, 0, 0}, pos = 1;
	const bk_enode *c = s + 1;
	for (int j = 0; j < ar; j++) {
		int u;
		off[j] = pos;
		if ((len[j] = pass(c, d + pos, ra, &u)) < 0)
			return -1;
		pos += len[j];
		c += u;
		*used += u;
	}
	int nconst = 0, input = 0, param = -1;
	for (int j = 0; j < ar; j++)
		nconst += d[off[j]].op == BK_OP_CONST;
	for (int i = 1; i < pos; i++) { /* param matters only where no input is: stop at one */
		if (d[i].op == BK_OP_INPUT) {
			input = 1;
			break;
		}
		if (d[i].op == BK_OP_PARAM && param < 0)
			param = d[i].slot;
	}
	if (nconst == ar && op < TERM0) {
		double v = bk_ir_apply((bk_op)op, d[off[0]].k, ar > 1 ? d[off[1]].k : 0, ar > 2 ? d[off[2]].k : 0);
		if (isfinite(v)) {
			d[0] = (bk_enode){BK_OP_CONST, 0, bk_expr_snap(v)};
			return 1;
		}
	}
	if (!input && param >= 0) {
		double v = value_of(d); /* a collapsed parameter starts where its parts were */
		d[0] = (bk_enode){BK_OP_PARAM, param, isfinite(v) ? v + 0.0 : 0};
		return 1;
	}
	const bk_enode *a = &d[off[0]], *b = ar > 1 ? &d[off[1]] : NULL;
	/* where both r and a = r*r are inputs: r*r -> a and sqrt(a) -> r (r >= 0
	 * by convention), one spelling of the same model, and the cheaper one */
	if (ra && op == BK_OP_MUL && a->op == BK_OP_INPUT && a->slot == BK_IN_R && b->op == BK_OP_INPUT &&
	    b->slot == BK_IN_R) {
		d[0] = (bk_enode){BK_OP_INPUT, BK_IN_A, 0};
		return 1;
	}
	if (ra && op == BK_OP_SQRT && a->op == BK_OP_INPUT && a->slot == BK_IN_A) {
		d[0] = (bk_enode){BK_OP_INPUT, BK_IN_R, 0};
		return 1;
	}
	/* x - x, x/x, min(x, x), max(x, x), mix(x, x, t): what the search means
	 * by them (a NaN at x = 0 or inf is no model; the front must not show
	 * sq(LoH)/sq(LoH)) */
	if (ar >= 2 && same_n(a, len[0], b, len[1])) {
		if (op == BK_OP_SUB || op == BK_OP_DIV) {
			d[0] = (bk_enode){BK_OP_CONST, 0, op == BK_OP_SUB ? 0.0 : 1.0};
			return 1;
		}
		if (op == BK_OP_MIN || op == BK_OP_MAX || op == BK_OP_MIX)
			return take(d, off[0], len[0]);
	}
	/* double negations spread over two levels: x - (-y) -> x + y, x + (-y)
	 * -> x - y, (-x)*(-y) -> x*y, (-x)/(-y) -> x/y, -(x - y) -> y - x (each
	 * exact: a negation is a sign flip) */
	if ((op == BK_OP_MUL || op == BK_OP_DIV) && a->op == BK_OP_NEG && b->op == BK_OP_NEG)
		return drop(d, off[0], drop(d, off[1], pos));
	if (op == BK_OP_SUB && b->op == BK_OP_NEG) {
		d[0].op = BK_OP_ADD;
		return drop(d, off[1], pos);
	}
	if (op == BK_OP_ADD && (a->op == BK_OP_NEG) != (b->op == BK_OP_NEG)) {
		if (a->op == BK_OP_NEG) { /* (-x) + y -> y - x */
			bk_enode tmp[BK_EXPR_MAX];
			memcpy(tmp, &d[off[0] + 1], sizeof *d * (size_t)(len[0] - 1));
			memmove(&d[1], &d[off[1]], sizeof *d * (size_t)len[1]);
			memcpy(&d[1 + len[1]], tmp, sizeof *d * (size_t)(len[0] - 1));
		} else {
			drop(d, off[1], pos);
		}
		d[0].op = BK_OP_SUB;
		return pos - 1;
	}
	if (op == BK_OP_NEG && a->op == BK_OP_SUB) { /* -(x - y) -> y - x */
		int qa = off[0] + 1, la = span_at(&d[qa]), lb = len[0] - 1 - la;
		bk_enode tmp[BK_EXPR_MAX];
		memcpy(tmp, &d[qa], sizeof *d * (size_t)la);
		d[0].op = BK_OP_SUB;
		memmove(&d[1], &d[qa + la], sizeof *d * (size_t)lb);
		memcpy(&d[1 + lb], tmp, sizeof *d * (size_t)la);
		return pos - 1;
	}
	switch (op) {
	case BK_OP_NEG:
		if (a->op == BK_OP_NEG)
			return take(d, off[0] + 1, len[0] - 1);
		if (a->op == BK_OP_MUL || a->op == BK_OP_DIV) { /* -(p*x) -> p*x */
			int qa = off[0] + 1, qb = qa + span_at(&d[qa]);
			if (d[qa].op == BK_OP_PARAM || d[qb].op == BK_OP_PARAM) {
				start_neg(&d[d[qa].op == BK_OP_PARAM ? qa : qb]);
				return take(d, off[0], len[0]);
			}
		}
		break;
	case BK_OP_MUL:
		if (is_const(a, 1))
			return take(d, off[1], len[1]);
		if (is_const(b, 1))
			return take(d, off[0], len[0]);
		for (int j = 0; j < 2; j++) /* x*rcp(y) -> x/y: one spelling of the model, the cheaper one */
			if (d[off[j]].op == BK_OP_RCP) {
				int x = off[1 - j], lx = len[1 - j], y = off[j] + 1, ly = len[j] - 1;
				bk_enode tmp[BK_EXPR_MAX];
				memcpy(tmp, &d[x], sizeof *d * (size_t)lx);
				memcpy(tmp + lx, &d[y], sizeof *d * (size_t)ly);
				d[0].op = BK_OP_DIV;
				memcpy(&d[1], tmp, sizeof *d * (size_t)(lx + ly));
				return 1 + lx + ly;
			}
		for (int j = 0; j < 2; j++) /* p*(-x) -> p*x; the next pass sorts */
			if (d[off[j]].op == BK_OP_PARAM && d[off[1 - j]].op == BK_OP_NEG) {
				int at = off[1 - j];
				start_neg(&d[off[j]]);
				memmove(&d[at], &d[at + 1], sizeof *d * (size_t)(pos - at - 1));
				return pos - 1;
			}
		break;
	case BK_OP_ADD:
		if (is_const(a, 0))
			return take(d, off[1], len[1]);
		if (is_const(b, 0))
			return take(d, off[0], len[0]);
		break;
	case BK_OP_SUB:
		if (is_const(b, 0))
			return take(d, off[0], len[0]);
		if (b->op == BK_OP_PARAM) {
			d[0].op = BK_OP_ADD;
			start_neg(&d[off[1]]);
		} else if (b->op == BK_OP_CONST) {
			d[0].op = BK_OP_ADD;
			d[off[1]].k = -b->k;
		}
		break;
	case BK_OP_DIV:
		if (is_const(b, 1))
			return take(d, off[0], len[0]);
		if (b->op == BK_OP_PARAM) {
			d[0].op = BK_OP_MUL;
			start_inv(&d[off[1]]);
		}
		break;
	default:
		break;
	}
	op = d[0].op;
	if (op == BK_OP_ADD || op == BK_OP_MUL) {
		for (int j = 0; j < 2; j++) {
			const bk_enode *p = &d[off[j]], *q = &d[off[1 - j]];
			if (p->op != BK_OP_PARAM || q->op != op)
				continue;
			int qa = off[1 - j] + 1, qb = qa + span_at(q + 1);
			if (d[qa].op == BK_OP_PARAM || d[qb].op == BK_OP_PARAM) {
				bk_enode *in = &d[d[qa].op == BK_OP_PARAM ? qa : qb];
				double v = op == BK_OP_ADD ? in->k + p->k : in->k * p->k;
				in->k = in->k != 0 && p->k != 0 && isfinite(v) ? v : 0;
				return take(d, off[1 - j], len[1 - j]);
			}
		}
	}
	if (commutative(op) && cmp_tree(&d[off[0]], len[0], &d[off[1]], len[1]) > 0) {
		bk_enode tmp[BK_EXPR_MAX];
		memcpy(tmp, &d[off[0]], sizeof *d * (size_t)len[0]);
		memmove(&d[1], &d[off[1]], sizeof *d * (size_t)len[1]);
		memcpy(&d[1 + len[1]], tmp, sizeof *d * (size_t)len[0]);
	}
	return pos;
}

/* Parameters renumbered p0, p1, ... by first appearance in prefix order (a
 * parameter used twice keeps one number). */
static void renumber(bk_expr *e)
{
	int map[BK_MAX_PARAMS + BK_EXPR_MAX];
	int next = 0;
	for (size_t i = 0; i < sizeof map / sizeof map[0]; i++)
		map[i] = -1;
	for (int i = 0; i < e->n; i++) {
		bk_enode *n = &e->node[i];
		if (n->op != BK_OP_PARAM)
			continue;
		int s = n->slot < 0 || n->slot >= (int)(sizeof map / sizeof map[0]) ? 0 : n->slot;
		if (map[s] < 0)
			map[s] = next++;
		n->slot = map[s];
	}
}

static int equal_nodes(const bk_expr *a, const bk_expr *b)
{
	if (a->n != b->n)
		return 0;
	for (int i = 0; i < a->n; i++)
		if (a->node[i].op != b->node[i].op || a->node[i].slot != b->node[i].slot ||
		    (a->node[i].op == BK_OP_CONST && memcmp(&a->node[i].k, &b->node[i].k, sizeof(double)) != 0))
			return 0;
	return 1;
}

/* Passes until nothing changes: one rewrite can enable another above it
 * (a swap after renumbering, a fold after an identity), and repeating to a
 * fixed point is what makes canon(canon(e)) == canon(e). Every rule
 * shortens the tree or reorders it towards cmp_tree order, so this ends. */
int bk_expr_canon(bk_expr *e) { return bk_expr_canon_in(e, 0); }

int bk_expr_canon_in(bk_expr *e, unsigned inputs)
{
	if (e->n <= 0)
		return -1;
	int ra = (inputs >> BK_IN_R & 1) && (inputs >> BK_IN_A & 1);
	for (int round = 0; round < 32; round++) {
		bk_expr next;
		int used;
		next.n = pass(e->node, next.node, ra, &used);
		if (next.n < 0)
			return -1;
		renumber(&next);
		int done = equal_nodes(&next, e);
		*e = next;
		if (done)
			return 0;
	}
	return 0;
}

/* ---- printing ------------------------------------------------------------- */

typedef struct writer {
	char *buf;
	size_t len, pos;
} writer;

static void put(writer *w, const char *s)
{
	for (; *s; s++, w->pos++)
		if (w->pos + 1 < w->len)
			w->buf[w->pos] = *s;
}

/* The shortest of %.15g, %.16g, %.17g that reads back as k. */
static void put_number(writer *w, double k)
{
	char t[40];
	for (int p = 15; p <= 17; p++) {
		snprintf(t, sizeof t, "%.*g", p, k);
		if (strtod(t, NULL) == k)
			break;
	}
	put(w, t);
}

/* Priorities as the parser's (ir_parse.c): + - 1, * / 2, unary minus 3,
 * primaries and calls 5. Left operands need their operator's priority,
 * right operands one more (a + (b + c) is not (a + b) + c in floating point),
 * the operand of unary minus more than 3 (-x^2 is -(x^2)). */
static int prio(const bk_enode *n)
{
	switch (n->op) {
	case BK_OP_ADD: case BK_OP_SUB: return 1;
	case BK_OP_MUL:
		return same(n + 1, n + 1 + span_at(n + 1)) ? 5 : 2;
	case BK_OP_DIV: return 2;
	case BK_OP_NEG: return 3;
	case BK_OP_MAD: return 1;
	case BK_OP_CONST: return n->k < 0 || signbit(n->k) ? 3 : 5;
	default: return 5;
	}
}

static void print_at(writer *w, const bk_enode *n, int need);

static void print_call(writer *w, const char *name, const bk_enode *n, int ar)
{
	put(w, name);
	put(w, "(");
	const bk_enode *c = n + 1;
	for (int j = 0; j < ar; j++) {
		if (j)
			put(w, ", ");
		print_at(w, c, 0);
		c += span_at(c);
	}
	put(w, ")");
}

static void print_at(writer *w, const bk_enode *n, int need)
{
	int p = prio(n);
	if (p < need)
		put(w, "(");
	const bk_enode *a = n + 1, *b = a + (arity(n->op) > 1 ? span_at(a) : 0);
	static const char *const infix[BK_OP_COUNT] = {
		[BK_OP_ADD] = " + ", [BK_OP_SUB] = " - ", [BK_OP_MUL] = " * ", [BK_OP_DIV] = " / "};
	switch (n->op) {
	case BK_OP_CONST:
		put_number(w, n->k);
		break;
	case BK_OP_INPUT:
		put(w, bk_input_name((bk_input)n->slot));
		break;
	case BK_OP_PARAM: {
		char t[16];
		snprintf(t, sizeof t, "p%d", n->slot);
		put(w, t);
		break;
	}
	case BK_OP_NEG:
		put(w, "-");
		print_at(w, a, 4);
		break;
	case BK_OP_MAD: /* a*b + c: the parser fuses it back */
		print_at(w, a, 2);
		put(w, " * ");
		print_at(w, b, 3);
		put(w, " + ");
		print_at(w, b + span_at(b), 2);
		break;
	case BK_OP_ADD: case BK_OP_SUB: case BK_OP_MUL: case BK_OP_DIV:
		if (p == 5) { /* sq */
			put(w, "sq(");
			print_at(w, a, 0);
			put(w, ")");
			break;
		}
		print_at(w, a, p);
		put(w, infix[n->op]);
		print_at(w, b, p + 1);
		break;
	default:
		print_call(w, op_name(n->op), n, arity(n->op));
		break;
	}
	if (p < need)
		put(w, ")");
}

int bk_expr_print(const bk_expr *e, char *buf, size_t len)
{
	writer w = {buf, len, 0};
	if (e->n <= 0)
		return -1;
	print_at(&w, e->node, 0);
	if (w.pos + 1 > len)
		return -1;
	buf[w.pos] = 0;
	return (int)w.pos;
}

uint64_t bk_hash_bytes(uint64_t h, const void *p, size_t n)
{
	const unsigned char *b = p;
	for (size_t i = 0; i < n; i++) {
		h ^= b[i];
		h *= 1099511628211ull;
	}
	return h;
}

uint64_t bk_expr_hash_text(const char *text) { return bk_hash_bytes(BK_HASH_INIT, text, strlen(text)); }

/* ---- the tree of a compiled form ------------------------------------------ */

static int expand(const bk_instr *code, int r, bk_expr *e)
{
	const bk_instr *in = &code[r];
	if (e->n >= BK_EXPR_MAX || in->op >= BK_OP_COUNT)
		return -1;
	bk_enode *n = &e->node[e->n++];
	*n = (bk_enode){(int)in->op, 0, 0};
	switch (in->op) {
	case BK_OP_CONST: n->k = in->k; return 0;
	case BK_OP_INPUT: case BK_OP_PARAM: n->slot = in->slot; return 0;
	case BK_OP_MAD: /* a*b + c */
		n->op = BK_OP_ADD;
		if (e->n >= BK_EXPR_MAX)
			return -1;
		e->node[e->n++] = (bk_enode){BK_OP_MUL, 0, 0};
		return expand(code, in->a, e) || expand(code, in->b, e) || expand(code, in->c, e) ? -1 : 0;
	default: break;
	}
	int ops[3] = {in->a, in->b, in->c};
	for (int j = 0; j < arity(in->op); j++)
		if (expand(code, ops[j], e))
			return -1;
	return 0;
}

int bk_expr_from_form(const bk_form *f, bk_expr *e)
{
	e->n = 0;
	int n = 0, out = 0;
	const bk_instr *code = f ? bk_form_code(f, &n, &out) : NULL;
	if (!f || n <= 0 || expand(code, out, e)) {
		e->n = 0;
		return -1;
	}
	return 0;
}

/* ---- grammar -------------------------------------------------------------- */

_Static_assert(BK_OP_COUNT < SQ_BIT, "the op table reaches the sq bit");
/* a registry term's bit is its op, TERM0 + t: below the sq bit */
#define MAX_TERM_OPS (SQ_BIT - TERM0)

#define BIT(op) ((uint64_t)1 << (op))

uint64_t bk_grammar_default_ops(void)
{
	return BIT(BK_OP_ADD) | BIT(BK_OP_SUB) | BIT(BK_OP_MUL) | BIT(BK_OP_DIV) | BIT(SQ_BIT) |
	       BIT(BK_OP_SQRT) | BIT(BK_OP_RSQRT) | BIT(BK_OP_RCP) | BIT(BK_OP_EXP2) | BIT(BK_OP_LOG2) |
	       BIT(BK_OP_MIN) | BIT(BK_OP_MAX) | BIT(BK_OP_SATURATE) | BIT(BK_OP_MIX);
}

/* The names the operators have in an --ops list (the rest go by bk_op_name
 * or their registry term's name). */
typedef struct op_word {
	const char *name;
	int bit;
} op_word;
static const op_word op_sym[] = {
	{"+", BK_OP_ADD}, {"-", BK_OP_SUB}, {"*", BK_OP_MUL}, {"/", BK_OP_DIV}, {"sq", SQ_BIT}};

int bk_grammar_describe(const bk_grammar *g, char *buf, size_t len)
{
	size_t k = 0;
	int n;
#define PUT(...) ((n = snprintf(k < len ? buf + k : NULL, k < len ? len - k : 0, __VA_ARGS__)) < 0 ? -1 : (k += (size_t)n, 0))
	PUT("operations ");
	int first = 1;
	for (int bit = 0; bit < 64; bit++) {
		if (!(g->ops & BIT(bit)))
			continue;
		const char *name = NULL;
		for (size_t i = 0; i < sizeof op_sym / sizeof op_sym[0]; i++)
			if (op_sym[i].bit == bit)
				name = op_sym[i].name;
		if (!name && bit < BK_OP_COUNT)
			name = bk_op_name(bit);
		if (!name && bit >= TERM0 && (size_t)(bit - TERM0) < bk_term_count())
			name = bk_term_at((size_t)(bit - TERM0))->name;
		if (name && *name)
			PUT("%s%s", first ? "" : " ", name), first = 0;
	}
	PUT("; inputs");
	for (int i = 0; i < BK_IN_COUNT; i++)
		if (g->inputs & (1u << i))
			PUT(" %s", bk_input_name((bk_input)i));
	PUT("; literals");
	for (int i = 0; i < g->nconsts; i++)
		PUT(" %g", g->consts[i]);
	PUT("; at most %d parameters; no unary operation directly over another", g->max_params);
#undef PUT
	return k < len ? (int)k : -1;
}

int bk_grammar_parse_ops(const char *list, uint64_t *ops, char *err, size_t errlen)
{
	const op_word *sym = op_sym;
	uint64_t m = 0;
	const char *p = list;
	for (;;) {
		const char *e = strchr(p, ',');
		size_t n = e ? (size_t)(e - p) : strlen(p);
		int bit = -1;
		for (size_t i = 0; i < sizeof op_sym / sizeof op_sym[0] && bit < 0; i++)
			if (strlen(sym[i].name) == n && strncmp(sym[i].name, p, n) == 0)
				bit = sym[i].bit;
		for (int op = 0; op < BK_OP_COUNT && bit < 0; op++) {
			const char *name = bk_op_name(op);
			if (*name && strlen(name) == n && strncmp(name, p, n) == 0)
				bit = op;
		}
		for (size_t t = 0; t < bk_term_count() && bit < 0; t++) {
			const char *name = bk_term_at(t)->name;
			if (strlen(name) != n || strncmp(name, p, n))
				continue;
			int ar = term_arity(t);
			if (ar < 1 || ar > 3) { /* a tree's node has 1 to 3 operands */
				snprintf(err, errlen, "%s takes %d argument%s: the search's operations take 1 to 3", name, ar,
				         ar == 1 ? "" : "s");
				return -1;
			}
			if (t >= MAX_TERM_OPS) {
				snprintf(err, errlen, "%s: past the %d registry terms a grammar can hold", name, MAX_TERM_OPS);
				return -1;
			}
			bit = TERM0 + (int)t;
		}
		if (n == 0) {
			snprintf(err, errlen, "an empty item in '%.40s'", list);
			return -1;
		}
		if (bit < 0) {
			snprintf(err, errlen, "unknown operation '%.*s' (+ - * / sq, a function name or a registry term)",
			         (int)(n > 24 ? 24 : n), p);
			return -1;
		}
		if (m & BIT(bit)) { /* a list that names one twice was typed for something else */
			snprintf(err, errlen, "'%.*s' given twice", (int)(n > 24 ? 24 : n), p);
			return -1;
		}
		m |= BIT(bit);
		if (!e)
			break;
		p = e + 1;
	}
	*ops = m;
	return 0;
}

/* Whether every operation of e is one the grammar allows (MUL with equal
 * operands is sq: allowed by either bit). */
static int within(const bk_grammar *g, const bk_expr *e)
{
	if (e->n <= 0 || bk_expr_nparams(e) > g->max_params || bk_expr_size(e) > g->max_size)
		return 0;
	for (int i = 0; i < e->n; i++) {
		int op = e->node[i].op;
		if (arity(op) == 0)
			continue;
		if (op == BK_OP_MUL && same(&e->node[i + 1], &e->node[i + 1 + span_at(&e->node[i + 1])])) {
			if (!(g->ops & (BIT(SQ_BIT) | BIT(BK_OP_MUL))))
				return 0;
		} else if (!(g->ops & BIT(op))) {
			return 0;
		}
	}
	return 1;
}

/* The operations a generator may build, by arity; sq is listed as unary
 * with op -1. MAD is never built (trees hold a*b + c). */
typedef struct opset {
	int op[3][SQ_BIT + 1];
	int n[3];
} opset;

static void opset_of(const bk_grammar *g, opset *s)
{
	memset(s, 0, sizeof *s);
	for (int op = BK_OP_PARAM + 1; op < BK_OP_COUNT; op++)
		if ((g->ops & BIT(op)) && op != BK_OP_MAD)
			s->op[arity(op) - 1][s->n[arity(op) - 1]++] = op;
	for (int op = TERM0; op < SQ_BIT && (size_t)(op - TERM0) < bk_term_count(); op++)
		if (g->ops & BIT(op)) /* parse_ops admits only 1 to 3 operands */
			s->op[arity(op) - 1][s->n[arity(op) - 1]++] = op;
	if (g->ops & (BIT(SQ_BIT) | BIT(BK_OP_MUL))) /* x*x is sq's only spelling */
		s->op[0][s->n[0]++] = -1;
}

double bk_grammar_trees(const bk_grammar *g, int size)
{
	opset os;
	opset_of(g, &os);
	double t[BK_EXPR_MAX + 1] = {0};
	int leaves = (g->max_params > 0) + g->nconsts;
	for (int i = 0; i < BK_IN_COUNT; i++)
		leaves += (g->inputs >> i) & 1;
	if (size < 1 || size > BK_EXPR_MAX)
		return 0;
	t[1] = leaves;
	for (int n = 2; n <= size; n++) {
		double bin = 0, ter = 0;
		for (int x = 1; x <= n - 2; x++)
			bin += t[x] * t[n - 1 - x];
		for (int x = 1; x <= n - 3; x++)
			for (int y = 1; x + y <= n - 2; y++)
				ter += t[x] * t[y] * t[n - 1 - x - y];
		t[n] = os.n[0] * t[n - 1] + os.n[1] * bin + os.n[2] * ter;
	}
	return t[size];
}

/* ---- rng ------------------------------------------------------------------ */

static uint64_t splitmix64(uint64_t *x)
{
	uint64_t z = (*x += 0x9e3779b97f4a7c15ull);
	z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
	z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
	return z ^ (z >> 31);
}

void bk_rng_seed(bk_rng *r, uint64_t seed)
{
	for (int i = 0; i < 4; i++)
		r->s[i] = splitmix64(&seed);
}

static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

uint64_t bk_rng_next(bk_rng *r)
{
	uint64_t *s = r->s;
	uint64_t out = rotl(s[1] * 5, 7) * 9, t = s[1] << 17;
	s[2] ^= s[0];
	s[3] ^= s[1];
	s[1] ^= s[2];
	s[0] ^= s[3];
	s[2] ^= t;
	s[3] = rotl(s[3], 45);
	return out;
}

uint32_t bk_rng_below(bk_rng *r, uint32_t n)
{
	/* reject the top 2^32 mod n values of a 32-bit draw: then uniform */
	uint32_t limit = (uint32_t)(-n) % n;
	for (;;) {
		uint32_t x = (uint32_t)(bk_rng_next(r) >> 32);
		if (x >= limit)
			return x % n;
	}
}

double bk_rng_unit(bk_rng *r) { return (double)(bk_rng_next(r) >> 11) * 0x1p-53; }

/* ---- enumeration ---------------------------------------------------------- */

/* Candidates of one size, their nodes end to end. */
typedef struct bucket {
	bk_enode *node;
	int *start, *len;
	int n, cap, ncap, nnodes;
} bucket;

/* Texts seen, by hash (open addressing; 0 marks empty, hash 0 is stored as
 * 1). A collision of two 64-bit FNV-1a hashes among 10^6 texts has
 * probability about 10^12 / 2^65, 3e-8. */
int bk_hashset_add(bk_hashset *s, uint64_t h)
{
	h = h ? h : 1;
	if (2 * (s->n + 1) > s->cap) {
		size_t cap = s->cap ? 2 * s->cap : 1024;
		uint64_t *t = calloc(cap, sizeof *t);
		if (!t)
			return -1;
		for (size_t i = 0; i < s->cap; i++)
			if (s->h[i])
				for (size_t j = s->h[i] & (cap - 1);; j = (j + 1) & (cap - 1))
					if (!t[j]) {
						t[j] = s->h[i];
						break;
					}
		free(s->h);
		s->h = t, s->cap = cap;
	}
	for (size_t j = h & (s->cap - 1);; j = (j + 1) & (s->cap - 1)) {
		if (s->h[j] == h)
			return 0;
		if (!s->h[j]) {
			s->h[j] = h;
			s->n++;
			return 1;
		}
	}
}

int bk_hashset_has(const bk_hashset *s, uint64_t h)
{
	h = h ? h : 1;
	for (size_t j = s->cap ? h & (s->cap - 1) : 0; s->cap && s->h[j]; j = (j + 1) & (s->cap - 1))
		if (s->h[j] == h)
			return 1;
	return 0;
}

void bk_hashset_free(bk_hashset *s)
{
	free(s->h);
	s->h = NULL;
	s->cap = s->n = 0;
}

static int bucket_add(bucket *b, const bk_expr *e)
{
	if (b->n == b->cap) {
		int cap = b->cap ? 2 * b->cap : 64;
		int *st = realloc(b->start, sizeof(int) * (size_t)cap);
		if (st)
			b->start = st;
		int *ln = realloc(b->len, sizeof(int) * (size_t)cap);
		if (ln)
			b->len = ln;
		if (!st || !ln)
			return -1;
		b->cap = cap;
	}
	if (b->nnodes + e->n > b->ncap) {
		int cap = b->ncap ? 2 * b->ncap : 1024;
		while (cap < b->nnodes + e->n)
			cap *= 2;
		bk_enode *t = realloc(b->node, sizeof *t * (size_t)cap);
		if (!t)
			return -1;
		b->node = t, b->ncap = cap;
	}
	memcpy(b->node + b->nnodes, e->node, sizeof *e->node * (size_t)e->n);
	b->start[b->n] = b->nnodes;
	b->len[b->n++] = e->n;
	b->nnodes += e->n;
	return 0;
}

/* Appends candidate i of size sz to e, its parameters numbered after *np. */
static int append(bk_expr *e, const bucket *b, int i, int *np)
{
	int len = b->len[i], top = 0;
	if (e->n + len > BK_EXPR_MAX)
		return -1;
	for (int k = 0; k < len; k++) {
		bk_enode n = b->node[b->start[i] + k];
		if (n.op == BK_OP_PARAM) {
			if (n.slot + 1 > top)
				top = n.slot + 1;
			n.slot += *np;
		}
		e->node[e->n++] = n;
	}
	*np += top;
	return 0;
}

static int nparams_of(const bucket *b, int i)
{
	int top = 0;
	for (int k = 0; k < b->len[i]; k++) {
		const bk_enode *n = &b->node[b->start[i] + k];
		if (n->op == BK_OP_PARAM && n->slot + 1 > top)
			top = n->slot + 1;
	}
	return top;
}

/* The lazy enumerator (expr.h): the loops of a bottom-up enumeration as
 * explicit state, so that a caller draws trees one at a time and the trees
 * not drawn are never built. Size s is made from the kept trees of smaller
 * sizes: leaves (s = 1: a parameter, the literals, the inputs), then each
 * unary operation (and sq) over size s - 1, each binary operation over
 * operand sizes x + (s - 1 - x), each ternary over x + y + z = s - 1; the
 * indices below are where those loops stand. */
struct bk_expr_enum {
	bk_grammar g;
	opset os;
	bucket b[BK_EXPR_MAX + 1]; /* b[s]: the trees of size s drawn so far, kept while s < max */
	bk_hashset seen;           /* their canonical texts */
	int max, size, stage;      /* stage: 0 leaves, 1 unary, 2 binary, 3 ternary */
	int u, x, y, i, j, k;
	long count, kept, limit; /* trees drawn; kept as operands, at most limit */
	int cut;                 /* 1 once the limit ended it */
};

static void stage_reset(bk_expr_enum *E, int stage)
{
	E->stage = stage;
	E->u = E->i = E->j = E->k = 0;
	E->x = E->y = 1;
}

/* The next tree of size 1 as built (before canon): 1, or 0 when none is left. */
static int raw_leaf(bk_expr_enum *E, bk_expr *e)
{
	const bk_grammar *g = &E->g;
	while (E->i < 1 + g->nconsts + BK_IN_COUNT) {
		int t = E->i++;
		e->n = 1;
		if (t == 0 && g->max_params >= 1)
			e->node[0] = (bk_enode){BK_OP_PARAM, 0, 0};
		else if (t >= 1 && t <= g->nconsts)
			e->node[0] = (bk_enode){BK_OP_CONST, 0, g->consts[t - 1]};
		else if (t > g->nconsts && (g->inputs & (1u << (t - 1 - g->nconsts))))
			e->node[0] = (bk_enode){BK_OP_INPUT, t - 1 - g->nconsts, 0};
		else
			continue;
		return 1;
	}
	return 0;
}

/* The next tree of size E->size >= 2 as built: 1, or 0 when none is left. */
static int raw_next(bk_expr_enum *E, bk_expr *e)
{
	const bk_grammar *g = &E->g;
	const opset *os = &E->os;
	int s = E->size;
	for (;;) {
		int np = 0;
		e->n = 1;
		if (E->stage == 1) { /* unary (and sq) over size s - 1 */
			const bucket *b = &E->b[s - 1];
			if (E->u >= os->n[0]) {
				stage_reset(E, 2);
			} else if (E->i >= b->n) {
				E->u++, E->i = 0;
			} else {
				int op = os->op[0][E->u], i = E->i++;
				e->node[0] = (bk_enode){op < 0 ? BK_OP_MUL : op, 0, 0};
				if (!append(e, b, i, &np) && !(op < 0 && (np = 0, append(e, b, i, &np))))
					return 1;
			}
		} else if (E->stage == 2) { /* binary: operand sizes x + (s - 1 - x) */
			const bucket *bx = &E->b[E->x], *by = &E->b[s - 1 - E->x];
			if (E->u >= os->n[1]) {
				stage_reset(E, 3);
			} else if (E->x > s - 2) {
				E->u++, E->x = 1, E->i = E->j = 0;
			} else if (E->i >= bx->n) {
				E->x++, E->i = E->j = 0;
			} else if (E->j >= by->n) {
				E->i++, E->j = 0;
			} else {
				int i = E->i, j = E->j++;
				e->node[0] = (bk_enode){os->op[1][E->u], 0, 0};
				if (nparams_of(bx, i) + nparams_of(by, j) <= g->max_params && !append(e, bx, i, &np) &&
				    !append(e, by, j, &np))
					return 1;
			}
		} else { /* ternary: x + y + z = s - 1 */
			if (E->u >= os->n[2])
				return 0;
			if (E->x > s - 3) {
				E->u++, E->x = E->y = 1, E->i = E->j = E->k = 0;
				continue;
			}
			if (E->x + E->y > s - 2) {
				E->x++, E->y = 1, E->i = E->j = E->k = 0;
				continue;
			}
			const bucket *bx = &E->b[E->x], *by = &E->b[E->y], *bz = &E->b[s - 1 - E->x - E->y];
			if (E->i >= bx->n) {
				E->y++, E->i = E->j = E->k = 0;
			} else if (E->j >= by->n) {
				E->i++, E->j = E->k = 0;
			} else if (E->k >= bz->n) {
				E->j++, E->k = 0;
			} else {
				int i = E->i, j = E->j, k = E->k++;
				e->node[0] = (bk_enode){os->op[2][E->u], 0, 0};
				if (!append(e, bx, i, &np) && !append(e, by, j, &np) && !append(e, bz, k, &np) &&
				    np <= g->max_params)
					return 1;
			}
		}
	}
}

/* A built tree canonicalised: 1 if it is new, of the size being built and
 * within the limits (a tree whose canonical form is smaller is found at that
 * smaller size, built from its own canonical operands), 0 if not, -1 when
 * out of memory. */
/* Whether e has a unary operation (sq included) directly over another (not
 * sq): sqrt(rcp(x)), rsqrt(sqrt(sq(x))), log2(exp2(x)), ... Most such pairs are
 * another unary (rsqrt), a power or the identity, and the rest are rarely
 * what a shading form is made of; at 5 nodes they are half the trees. The
 * enumeration leaves them out (a nesting limit, as PySR's and Operon's
 * users set one), so that its budget reaches the binary and ternary trees;
 * mutation can still make them. */
static int unary_over_unary(const bk_expr *e)
{
	for (int i = 0; i + 1 < e->n; i++) {
		int op = e->node[i].op, sq = op == BK_OP_MUL && same(&e->node[i + 1], &e->node[i + 1 + span_at(&e->node[i + 1])]);
		int below = e->node[i + 1].op;
		if ((sq || (arity(op) == 1 && op < TERM0)) && arity(below) == 1 && below < TERM0)
			return 1;
	}
	return 0;
}

static int keep(bk_expr_enum *E, bk_expr *e)
{
	char text[4096];
	if (bk_expr_canon_in(e, E->g.inputs) || !within(&E->g, e) || bk_expr_size(e) != E->size ||
	    unary_over_unary(e))
		return 0;
	if (bk_expr_print(e, text, sizeof text) < 0)
		return 0;
	return bk_hashset_add(&E->seen, bk_expr_hash_text(text));
}

bk_expr_enum *bk_expr_enum_new(const bk_grammar *g, int max_size, long max_trees)
{
	bk_expr_enum *E = calloc(1, sizeof *E);
	if (!E)
		return NULL;
	E->g = *g;
	opset_of(g, &E->os);
	E->max = max_size < g->max_size ? max_size : g->max_size;
	if (E->max > BK_EXPR_MAX)
		E->max = BK_EXPR_MAX;
	E->size = 1;
	E->limit = max_trees;
	stage_reset(E, 0);
	return E;
}

int bk_expr_enum_next(bk_expr_enum *E, bk_expr *out)
{
	while (E->size <= E->max) {
		bk_expr e;
		if (!(E->size == 1 ? raw_leaf(E, &e) : raw_next(E, &e))) { /* this size is done: the next */
			E->size++;
			stage_reset(E, 1);
			continue;
		}
		int r = keep(E, &e);
		if (r < 0)
			return -1;
		if (r == 0)
			continue;
		if (E->size < E->max) { /* an operand of larger trees: kept, within the limit */
			if (E->kept >= E->limit) {
				E->cut = 1;
				return 0;
			}
			if (bucket_add(&E->b[E->size], &e))
				return -1;
			E->kept++;
		}
		E->count++;
		*out = e;
		return E->size;
	}
	return 0;
}

long bk_expr_enum_count(const bk_expr_enum *E) { return E->count; }
int bk_expr_enum_cut(const bk_expr_enum *E) { return E->cut; }

void bk_expr_enum_free(bk_expr_enum *E)
{
	if (!E)
		return;
	for (int s = 0; s <= BK_EXPR_MAX; s++) {
		free(E->b[s].node);
		free(E->b[s].start);
		free(E->b[s].len);
	}
	bk_hashset_free(&E->seen);
	free(E);
}

long bk_expr_enumerate(const bk_grammar *g, int size, bk_expr_visit fn, void *ctx)
{
	if (size < 1 || size > g->max_size || size > BK_EXPR_MAX)
		return 0;
	bk_expr_enum *E = bk_expr_enum_new(g, size, LONG_MAX);
	if (!E)
		return -1;
	long count = 0;
	bk_expr e;
	int r;
	while ((r = bk_expr_enum_next(E, &e)) > 0)
		if (r == size && (count++, fn && fn(ctx, &e)))
			break;
	bk_expr_enum_free(E);
	return r < 0 ? -1 : count;
}

/* ---- mutation and crossover ----------------------------------------------- */

/* A random leaf: a fresh parameter (slot np), a literal or an input. */
static bk_enode random_leaf(const bk_grammar *g, bk_rng *r, int np)
{
	int nin = 0, ins[BK_IN_COUNT];
	for (int i = 0; i < BK_IN_COUNT; i++)
		if (g->inputs & (1u << i))
			ins[nin++] = i;
	uint32_t k = bk_rng_below(r, (uint32_t)(1 + g->nconsts + nin));
	if (k == 0 || (int)k > g->nconsts + nin)
		return (bk_enode){BK_OP_PARAM, np, 0};
	if ((int)k <= g->nconsts)
		return (bk_enode){BK_OP_CONST, 0, g->consts[k - 1]};
	return (bk_enode){BK_OP_INPUT, ins[k - 1 - g->nconsts], 0};
}

/* A random tree of depth <= depth into d (grow method); returns its length. */
static int random_tree(const bk_grammar *g, const opset *os, bk_rng *r, int depth, int *np, bk_enode *d,
                       int room)
{
	int nops = os->n[0] + os->n[1] + os->n[2];
	if (room < 8 || depth == 0 || nops == 0 || bk_rng_below(r, 2) == 0) {
		d[0] = random_leaf(g, r, (*np)++);
		return 1;
	}
	uint32_t k = bk_rng_below(r, (uint32_t)nops);
	int ar = k < (uint32_t)os->n[0] ? 1 : k < (uint32_t)(os->n[0] + os->n[1]) ? 2 : 3;
	int op = ar == 1 ? os->op[0][k] : ar == 2 ? os->op[1][k - os->n[0]] : os->op[2][k - os->n[0] - os->n[1]];
	int pos = 1;
	if (op < 0) { /* sq */
		d[0] = (bk_enode){BK_OP_MUL, 0, 0};
		int l = random_tree(g, os, r, depth - 1, np, d + 1, (room - 1) / 2);
		memcpy(d + 1 + l, d + 1, sizeof *d * (size_t)l);
		return 1 + 2 * l;
	}
	d[0] = (bk_enode){op, 0, 0};
	for (int j = 0; j < ar; j++)
		pos += random_tree(g, os, r, depth - 1, np, d + pos, (room - pos) / (ar - j));
	return pos;
}

/* e with the subtree at i replaced by the len nodes at s; -1 if too big. */
static int splice(bk_expr *e, int i, const bk_enode *s, int len)
{
	int old = span_at(e->node + i);
	if (e->n - old + len > BK_EXPR_MAX)
		return -1;
	bk_enode tmp[BK_EXPR_MAX];
	memcpy(tmp, s, sizeof *s * (size_t)len);
	memmove(e->node + i + len, e->node + i + old, sizeof *e->node * (size_t)(e->n - i - old));
	memcpy(e->node + i, tmp, sizeof *s * (size_t)len);
	e->n += len - old;
	return 0;
}

static int pick_node(bk_rng *r, const bk_expr *e, int want_op)
{
	int idx[BK_EXPR_MAX], n = 0;
	for (int i = 0; i < e->n; i++) {
		int ar = arity(e->node[i].op);
		if (want_op < 0 || (want_op == 0 && ar == 0) || (want_op == 1 && ar > 0) ||
		    (want_op == 2 && e->node[i].op == BK_OP_CONST))
			idx[n++] = i;
	}
	return n ? idx[bk_rng_below(r, (uint32_t)n)] : -1;
}

/* One raw mutation of c (not yet canonical); -1 if this kind does not apply. */
static int mutate_once(const bk_grammar *g, const opset *os, bk_rng *r, bk_expr *c)
{
	bk_enode t[BK_EXPR_MAX];
	int np = bk_expr_nparams(c), i, l;
	switch (bk_rng_below(r, 7)) {
	case 0: /* a subtree replaced by a random small one */
		i = pick_node(r, c, -1);
		l = random_tree(g, os, r, 2, &np, t, BK_EXPR_MAX);
		return splice(c, i, t, l);
	case 1: { /* an operation changed to another of the same arity */
		i = pick_node(r, c, 1);
		if (i < 0)
			return -1;
		int ar = arity(c->node[i].op);
		if (os->n[ar - 1] == 0)
			return -1;
		int op = os->op[ar - 1][bk_rng_below(r, (uint32_t)os->n[ar - 1])];
		if (op < 0) /* sq: unary only */
			return -1;
		c->node[i].op = op;
		return 0;
	}
	case 2: /* a leaf replaced */
		i = pick_node(r, c, 0);
		c->node[i] = random_leaf(g, r, np);
		return 0;
	case 3: /* a literal becomes a parameter */
		if ((i = pick_node(r, c, 2)) < 0)
			return -1;
		c->node[i] = (bk_enode){BK_OP_PARAM, np, c->node[i].k}; /* starts at the literal */
		return 0;
	case 4: { /* a subtree wrapped in a unary operation */
		if (os->n[0] == 0)
			return -1;
		i = pick_node(r, c, -1);
		int op = os->op[0][bk_rng_below(r, (uint32_t)os->n[0])], len = span_at(c->node + i);
		if (1 + 2 * len > BK_EXPR_MAX)
			return -1;
		t[0] = (bk_enode){op < 0 ? BK_OP_MUL : op, 0, 0};
		memcpy(t + 1, c->node + i, sizeof *t * (size_t)len);
		if (op < 0)
			memcpy(t + 1 + len, c->node + i, sizeof *t * (size_t)len);
		return splice(c, i, t, op < 0 ? 1 + 2 * len : 1 + len);
	}
	case 5: { /* a subtree x made an operand of a binary or ternary operation
	           * beside leaves or copies of the tree's own subtrees: x op leaf,
	           * leaf op x (p/(LoH^2 + p') -> p/(LoH^2 + p'*a)), x*y with y a
	           * subtree of the tree (sq(y) -> sq(y)*y: odd powers, Schlick's
	           * fifth), mix(leaf, leaf', x) (f0 + (1 - f0)*x, Smith's
	           * NoV*(1 - k) + k) */
		int nbin = os->n[1], nter = 0;
		for (int k = 0; k < os->n[2]; k++)
			nter += os->op[2][k] == BK_OP_MIX;
		if (nbin + nter == 0)
			return -1;
		i = pick_node(r, c, -1);
		int len = span_at(c->node + i), k = (int)bk_rng_below(r, (uint32_t)(nbin + nter));
		int op = k < nbin ? os->op[1][k] : BK_OP_MIX, ar = op == BK_OP_MIX ? 3 : 2;
		int at = (int)bk_rng_below(r, (uint32_t)ar), pos = 1;
		t[0] = (bk_enode){op, 0, 0};
		for (int j = 0; j < ar; j++) {
			const bk_enode *src = c->node + i;
			int l = len;
			if (j != at) {
				int y = bk_rng_below(r, 2) ? pick_node(r, c, -1) : -1;
				if (y < 0) { /* a leaf */
					if (pos + 1 > BK_EXPR_MAX)
						return -1;
					t[pos++] = random_leaf(g, r, np++);
					continue;
				}
				src = c->node + y;
				l = span_at(src);
			}
			if (pos + l > BK_EXPR_MAX)
				return -1;
			memcpy(t + pos, src, sizeof *t * (size_t)l);
			pos += l;
		}
		return splice(c, i, t, pos);
	}
	default: { /* an operand hoisted over its operation */
		if ((i = pick_node(r, c, 1)) < 0)
			return -1;
		int j = i + 1;
		for (uint32_t k = bk_rng_below(r, (uint32_t)arity(c->node[i].op)); k; k--)
			j += span_at(c->node + j);
		l = span_at(c->node + j);
		memcpy(t, c->node + j, sizeof *t * (size_t)l);
		return splice(c, i, t, l);
	}
	}
}

/* Canonical, within the grammar, and not the parent itself. */
static int acceptable(const bk_grammar *g, bk_expr *c, const bk_expr *parent)
{
	return bk_expr_canon_in(c, g->inputs) == 0 && within(g, c) && !(parent && equal_nodes(c, parent));
}

/* e with its subtree at i replaced by the len nodes t, kept in out[0..*m)
 * when acceptable and not already there. */
static void add_neighbour(const bk_grammar *g, const bk_expr *e, int i, const bk_enode *t, int len, bk_expr *out,
                          int *m)
{
	bk_expr c = *e;
	if (splice(&c, i, t, len) || !acceptable(g, &c, e))
		return;
	for (int j = 0; j < *m; j++)
		if (equal_nodes(&out[j], &c))
			return;
	out[(*m)++] = c;
}

int bk_expr_mix_neighbours(const bk_grammar *g, const bk_expr *e, bk_expr *out, int max)
{
	if (!(g->ops & BIT(BK_OP_MIX)))
		return 0;
	bk_enode leaf[BK_IN_COUNT + 2];
	int nl = 0, m = 0, np = bk_expr_nparams(e);
	for (int i = 0; i < BK_IN_COUNT; i++)
		if (g->inputs & (1u << i))
			leaf[nl++] = (bk_enode){BK_OP_INPUT, i, 0};
	leaf[nl++] = (bk_enode){BK_OP_CONST, 0, 1.0};
	leaf[nl++] = (bk_enode){BK_OP_PARAM, np, 0};
	for (int i = 0; i < e->n && m < max; i++)
		for (int u = 0; u < nl && m < max; u++)
			for (int v = 0; v < nl && m < max; v++) {
				int len = span_at(e->node + i);
				if (u == v || 3 + len > BK_EXPR_MAX)
					continue;
				bk_enode t[BK_EXPR_MAX];
				t[0] = (bk_enode){BK_OP_MIX, 0, 0};
				t[1] = leaf[u];
				t[2] = leaf[v];
				if (t[2].op == BK_OP_PARAM && t[1].op == BK_OP_PARAM)
					continue;
				memcpy(t + 3, e->node + i, sizeof *t * (size_t)len);
				add_neighbour(g, e, i, t, 3 + len, out, &m);
			}
	return m;
}

int bk_expr_neighbours(const bk_grammar *g, const bk_expr *e, bk_expr *out, int max)
{
	static const int ops[2] = {BK_OP_MUL, BK_OP_ADD};
	int m = 0, np = bk_expr_nparams(e);
	for (int i = 0; i < e->n && m < max; i++)
		for (int k = 0; k < 2 && m < max; k++) {
			if (!(g->ops & BIT(ops[k])))
				continue;
			int len = span_at(e->node + i);
			bk_enode t[BK_EXPR_MAX];
			if (2 + len > BK_EXPR_MAX)
				continue;
			t[0] = (bk_enode){ops[k], 0, 0};
			t[1] = (bk_enode){BK_OP_PARAM, np, 0};
			memcpy(t + 2, e->node + i, sizeof *t * (size_t)len);
			add_neighbour(g, e, i, t, 2 + len, out, &m);
		}
	return m;
}

int bk_expr_input_neighbours(const bk_grammar *g, const bk_expr *e, bk_expr *out, int max)
{
	int m = 0, np = bk_expr_nparams(e), first_in = -1;
	for (int in = BK_IN_COUNT - 1; in >= 0; in--)
		if (g->inputs & (1u << in))
			first_in = in;
	for (int in = 0; in < BK_IN_COUNT; in++) {
		if (!(g->inputs & (1u << in)))
			continue;
		const bk_enode x = {BK_OP_INPUT, in, 0};
		/* a constant made affine in the input: p -> mix(p, p', in) */
		for (int i = 0; (g->ops & BIT(BK_OP_MIX)) && i < e->n && m < max; i++)
			if (e->node[i].op == BK_OP_PARAM) {
				bk_enode t[4] = {{BK_OP_MIX, 0, 0}, e->node[i], {BK_OP_PARAM, np, 0}, x};
				add_neighbour(g, e, i, t, 4, out, &m);
			}
		/* a power: x -> sq(x) (once, with the first input) */
		for (int i = 0; in == first_in && (g->ops & (BIT(SQ_BIT) | BIT(BK_OP_MUL))) && i < e->n && m < max; i++) {
			int len = span_at(e->node + i);
			if (e->node[i].op == BK_OP_PARAM || 1 + 2 * len > BK_EXPR_MAX)
				continue;
			bk_enode t[BK_EXPR_MAX];
			t[0] = (bk_enode){BK_OP_MUL, 0, 0};
			memcpy(t + 1, e->node + i, sizeof *t * (size_t)len);
			memcpy(t + 1 + len, e->node + i, sizeof *t * (size_t)len);
			add_neighbour(g, e, i, t, 1 + 2 * len, out, &m);
		}
		/* a factor of the input: x -> x*in (not of a scale p, a lone input) */
		for (int i = 0; (g->ops & BIT(BK_OP_MUL)) && i < e->n && m < max; i++) {
			int len = span_at(e->node + i);
			if (e->node[i].op == BK_OP_PARAM || 2 + len > BK_EXPR_MAX)
				continue;
			bk_enode t[BK_EXPR_MAX];
			t[0] = (bk_enode){BK_OP_MUL, 0, 0};
			memcpy(t + 1, e->node + i, sizeof *t * (size_t)len);
			t[1 + len] = x;
			add_neighbour(g, e, i, t, 2 + len, out, &m);
		}
	}
	return m;
}

#define TRIES 32

int bk_expr_mutate(const bk_grammar *g, bk_rng *r, const bk_expr *parent, bk_expr *child)
{
	opset os;
	opset_of(g, &os);
	for (int t = 0; t < TRIES; t++) {
		*child = *parent;
		if (mutate_once(g, &os, r, child) == 0 && acceptable(g, child, parent))
			return 0;
	}
	*child = *parent;
	return -1;
}

int bk_expr_crossover(const bk_grammar *g, bk_rng *r, const bk_expr *a, const bk_expr *b, bk_expr *child)
{
	int na = bk_expr_nparams(a);
	for (int t = 0; t < TRIES; t++) {
		*child = *a;
		int i = (int)bk_rng_below(r, (uint32_t)a->n), j = (int)bk_rng_below(r, (uint32_t)b->n);
		int l = span_at(b->node + j);
		bk_enode s[BK_EXPR_MAX];
		memcpy(s, b->node + j, sizeof *s * (size_t)l);
		for (int k = 0; k < l; k++)
			if (s[k].op == BK_OP_PARAM)
				s[k].slot += na; /* b's parameters are not a's */
		if (splice(child, i, s, l) == 0 && acceptable(g, child, a))
			return 0;
	}
	*child = *a;
	return -1;
}
