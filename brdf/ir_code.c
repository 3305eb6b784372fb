/*
 * ir_code.c — building the instruction list: common subexpressions, constant
 * folding, identities, multiply-add fusion and dead-code removal.
 */
#include "ir.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

const bk_opinfo bk_opinfo_table[BK_OP_COUNT] = {
#define OP(e, name, arity, c, glsl, hlsl, ...) [BK_OP_##e] = {name, arity, {c, glsl, hlsl}, {__VA_ARGS__}},
#include "ir_ops.h"
};

double bk_ir_apply(bk_op op, double a, double b, double c)
{
	switch (op) {
	case BK_OP_ADD: return a + b;
	case BK_OP_SUB: return a - b;
	case BK_OP_MUL: return a * b;
	case BK_OP_DIV: return a / b;
	case BK_OP_NEG: return -a;
	case BK_OP_MAD: return a * b + c;
	case BK_OP_POW: return BK_POW_AT_ZERO_UNDEFINED(a, b) ? NAN : bk_dexp2(b * bk_dlog2(a)); /* the GPU's pow (ir_eval.c) */
	case BK_OP_SQRT: return sqrt(a);
	case BK_OP_RSQRT: return 1.0 / sqrt(a);
	case BK_OP_RCP: return 1.0 / a;
	case BK_OP_EXP: return bk_dexp(a);
	case BK_OP_EXP2: return bk_dexp2(a);
	case BK_OP_LOG: return bk_dlog(a);
	case BK_OP_LOG2: return bk_dlog2(a);
	case BK_OP_MIN: return fmin(a, b);
	case BK_OP_MAX: return fmax(a, b);
	case BK_OP_CLAMP: return fmin(fmax(a, b), c);
	case BK_OP_SATURATE: return fmin(fmax(a, 0.0), 1.0);
	case BK_OP_MIX: return a + (b - a) * c;
	case BK_OP_ABS: return fabs(a);
	default: return NAN;
	}
}

int bk_ir_clamp_fixed_bounds(const bk_form *f, const bk_instr *in)
{
	bk_op lo = f->code[in->b].op, hi = f->code[in->c].op;
	return (lo == BK_OP_CONST || lo == BK_OP_PARAM) && (hi == BK_OP_CONST || hi == BK_OP_PARAM);
}

double bk_ir_apply_half(bk_op op, double a, double b, double c)
{
	double (*h)(double) = bk_half_round;
	switch (op) {
	case BK_OP_MAD: return h(h(a * b) + c);
	case BK_OP_MIX: return h(a + h(h(b - a) * c));
	case BK_OP_POW: return BK_POW_AT_ZERO_UNDEFINED(a, b) ? NAN : h(bk_dexp2(h(b * h(bk_dlog2(a)))));
	case BK_OP_EXP: return h(bk_dexp2(h(a * h(1.44269504088896340736))));
	case BK_OP_LOG: return h(h(bk_dlog2(a)) * h(0.693147180559945309417));
	default: return h(bk_ir_apply(op, a, b, c));
	}
}

/* Instructions per form (BK_FORM_MAX_INSTR): far above any BRDF term (the
 * largest catalog entry needs ~100), low enough that the recursive
 * renumbering in finish() stays a few hundred kilobytes of stack. */
#define MAX_INSTR BK_FORM_MAX_INSTR

/* Field by field, k by its bits (one zero: bk_ir_const makes -0.0 +0.0). */
static int same(const bk_instr *x, const bk_instr *y)
{
	uint64_t kx, ky;
	memcpy(&kx, &x->k, sizeof kx);
	memcpy(&ky, &y->k, sizeof ky);
	return x->op == y->op && x->a == y->a && x->b == y->b && x->c == y->c && x->slot == y->slot && kx == ky;
}

static uint32_t hash(const bk_instr *in)
{
	/* FNV-1a's offset basis and prime, word by word over the six fields: a
	 * table slot, not an identity (the floor above hashes text for that,
	 * fit/expr.h's bk_hash_bytes); any slot finds the same instruction */
	uint64_t k, h = 14695981039346656037u;
	memcpy(&k, &in->k, sizeof k);
	const uint64_t v[6] = {(uint64_t)in->op, (uint64_t)in->a, (uint64_t)in->b, (uint64_t)in->c,
	                       (uint64_t)in->slot, k};
	for (int i = 0; i < 6; i++)
		h = (h ^ v[i]) * 1099511628211u;
	return (uint32_t)(h ^ h >> 32);
}

/* Common subexpressions through an open-addressing table kept at most half
 * full: a linear search made parsing quadratic (a second for a form at
 * MAX_INSTR under the fuzzer). fuse() rewrites entries in place; a stale slot
 * then simply never matches, as the linear search would not have matched. */
static int *slot_of(bk_form *f, const bk_instr *in)
{
	unsigned mask = (unsigned)f->hcap - 1, h = hash(in) & mask;
	while (f->hash[h] && !same(&f->code[f->hash[h] - 1], in))
		h = (h + 1) & mask;
	return &f->hash[h];
}

static int rehash(bk_form *f, int hcap)
{
	int *t = calloc((size_t)hcap, sizeof *t);
	if (!t)
		return -1;
	free(f->hash);
	f->hash = t;
	f->hcap = hcap;
	for (int i = 0; i < f->n; i++) {
		int *s = slot_of(f, &f->code[i]);
		if (!*s)
			*s = i + 1;
	}
	return 0;
}

static int push(bk_form *f, bk_instr in)
{
	if (2 * (f->n + 1) > f->hcap && rehash(f, f->hcap ? 2 * f->hcap : 64))
		return -1;
	int *s = slot_of(f, &in);
	if (*s)
		return *s - 1;
	if (f->n == MAX_INSTR)
		return -1;
	if (f->n == f->cap) {
		int cap = f->cap ? 2 * f->cap : 32;
		bk_instr *c = realloc(f->code, (size_t)cap * sizeof *c);
		if (!c)
			return -1;
		f->code = c;
		f->cap = cap;
	}
	f->code[f->n] = in;
	*s = f->n + 1;
	return f->n++;
}

static bk_instr blank(bk_op op)
{
	bk_instr in;
	memset(&in, 0, sizeof in); /* padding too: instructions are compared bytewise */
	in.op = op;
	in.a = in.b = in.c = -1;
	return in;
}

int bk_ir_const(bk_form *f, double k)
{
	bk_instr in = blank(BK_OP_CONST);
	in.k = k == 0.0 ? 0.0 : k; /* one zero: -0.0 is never folded into, see fold() */
	return push(f, in);
}

int bk_ir_input(bk_form *f, bk_input i)
{
	bk_instr in = blank(BK_OP_INPUT);
	in.slot = (int)i;
	f->inputs |= 1u << i;
	return push(f, in);
}

int bk_ir_param(bk_form *f, int p)
{
	bk_instr in = blank(BK_OP_PARAM);
	in.slot = p;
	if (p + 1 > f->nparams)
		f->nparams = p + 1;
	return push(f, in);
}

static float round32(double x) { return (float)x; }

/*
 * Folding is only done when it changes nothing the evaluator would see: the
 * result must be finite, not -0.0, and the op applied in single and in half
 * precision (to operands rounded to that precision) must give the double
 * result rounded to that precision. So 1/3 folds (each precision rounds 1/3
 * once either way), but 0.1*3 does not (half rounds 0.1 first).
 */
static int fold(bk_form *f, bk_op op, const int *arg, int arity, double *out)
{
	double v[3] = {0, 0, 0}, v32[3], v16[3];
	for (int i = 0; i < arity; i++) {
		if (f->code[arg[i]].op != BK_OP_CONST)
			return 0;
		v[i] = f->code[arg[i]].k;
		v32[i] = round32(v[i]);
		v16[i] = bk_half_round(v[i]);
	}
	double r = bk_ir_apply(op, v[0], v[1], v[2]);
	if (!isfinite(r) || (r == 0.0 && signbit(r)))
		return 0;
	double r32 = round32(bk_ir_apply(op, v32[0], v32[1], v32[2]));
	double r16 = bk_ir_apply_half(op, v16[0], v16[1], v16[2]);
	if (r32 != round32(r) || r16 != bk_half_round(r))
		return 0;
	*out = r;
	return 1;
}

static int is_const(const bk_form *f, int i, double k)
{
	return f->code[i].op == BK_OP_CONST && f->code[i].k == k;
}

/* Identities exact in every precision: x*1, 1*x, x/1, x+0, 0+x, x-0. */
static int identity(const bk_form *f, bk_op op, int a, int b)
{
	switch (op) {
	case BK_OP_MUL: return is_const(f, b, 1.0) ? a : is_const(f, a, 1.0) ? b : -1;
	case BK_OP_DIV: return is_const(f, b, 1.0) ? a : -1;
	case BK_OP_ADD: return is_const(f, b, 0.0) ? a : is_const(f, a, 0.0) ? b : -1;
	case BK_OP_SUB: return is_const(f, b, 0.0) ? a : -1;
	default: return -1;
	}
}

/* Commutative operands in a canonical order, so a*b and b*a are one register. */
static int commutative(bk_op op)
{
	return op == BK_OP_ADD || op == BK_OP_MUL || op == BK_OP_MIN || op == BK_OP_MAX;
}

int bk_ir_emit(bk_form *f, bk_op op, int a, int b, int c)
{
	if (a < 0 || (bk_opinfo_table[op].arity > 1 && b < 0) || (bk_opinfo_table[op].arity > 2 && c < 0))
		return -1;
	int arg[3] = {a, b, c}, arity = bk_opinfo_table[op].arity;
	double k;
	if (fold(f, op, arg, arity, &k))
		return bk_ir_const(f, k);
	int same = identity(f, op, a, b);
	if (same >= 0)
		return same;
	if (op == BK_OP_NEG && f->code[a].op == BK_OP_NEG)
		return f->code[a].a; /* -(-x) = x, exact in every precision */
	if (commutative(op) && b < a) {
		arg[0] = b;
		arg[1] = a;
	}
	bk_instr in = blank(op);
	in.a = arg[0];
	in.b = arity > 1 ? arg[1] : -1;
	in.c = arity > 2 ? arg[2] : -1;
	return push(f, in);
}

/* Uses of each register by the instructions reachable from out. */
static void count_uses(const bk_form *f, int out, int *uses, char *live)
{
	memset(uses, 0, sizeof(int) * (size_t)f->n);
	memset(live, 0, (size_t)f->n);
	live[out] = 1;
	for (int i = out; i >= 0; i--) {
		if (!live[i])
			continue;
		const bk_instr *in = &f->code[i];
		int ops[3] = {in->a, in->b, in->c};
		for (int j = 0; j < bk_opinfo_table[in->op].arity; j++) {
			uses[ops[j]]++;
			live[ops[j]] = 1;
		}
	}
}

/* a*b + c and c + a*b, with the product used once, become MAD(a, b, c);
 * a*b - c becomes MAD(a, b, -c) and c - a*b MAD(-a, b, c): negation is a free
 * source modifier on GPUs. MAD still rounds twice when evaluated (GLSL ES 3.00
 * has no fused multiply-add; a mediump GPU may or may not fuse). */
static int fuse(bk_form *f, int out)
{
	int *uses = malloc(sizeof(int) * (size_t)f->n);
	char *live = malloc((size_t)f->n);
	if (!uses || !live) {
		free(uses);
		free(live);
		return -1;
	}
	count_uses(f, out, uses, live);
	int n = f->n;
	for (int i = 0; i < n; i++) {
		bk_instr in = f->code[i];
		if (!live[i] || (in.op != BK_OP_ADD && in.op != BK_OP_SUB))
			continue;
		int prod = -1, other = -1, neg_prod = 0, neg_other = 0;
		if (f->code[in.a].op == BK_OP_MUL && uses[in.a] == 1) {
			prod = in.a, other = in.b, neg_other = in.op == BK_OP_SUB;
		} else if (f->code[in.b].op == BK_OP_MUL && uses[in.b] == 1) {
			prod = in.b, other = in.a, neg_prod = in.op == BK_OP_SUB;
		}
		if (prod < 0)
			continue;
		int x = f->code[prod].a, y = f->code[prod].b;
		if (neg_prod && (x = bk_ir_emit(f, BK_OP_NEG, x, -1, -1)) < 0)
			goto oom;
		if (neg_other && (other = bk_ir_emit(f, BK_OP_NEG, other, -1, -1)) < 0)
			goto oom;
		/* Rewrite in place: the new operands may sit after i (NEG just
		 * emitted), which the renumbering in finish() puts back in order. */
		bk_instr m = blank(BK_OP_MAD);
		m.a = x, m.b = y, m.c = other;
		f->code[i] = m;
	}
	free(uses);
	free(live);
	return 0;
oom:
	free(uses);
	free(live);
	return -1;
}

/* Depth-first post-order from out: operands before users, unreachable dropped. */
static int order(const bk_form *f, int i, int *newidx, bk_instr *dst, int *n)
{
	if (newidx[i] >= 0)
		return 0;
	const bk_instr *in = &f->code[i];
	int ops[3] = {in->a, in->b, in->c};
	for (int j = 0; j < bk_opinfo_table[in->op].arity; j++)
		order(f, ops[j], newidx, dst, n);
	bk_instr c = *in;
	if (c.a >= 0) c.a = newidx[c.a];
	if (c.b >= 0) c.b = newidx[c.b];
	if (c.c >= 0) c.c = newidx[c.c];
	dst[*n] = c;
	newidx[i] = (*n)++;
	return 0;
}

int bk_ir_finish(bk_form *f, int out)
{
	if (fuse(f, out))
		return -1;
	int *newidx = malloc(sizeof(int) * (size_t)f->n);
	bk_instr *dst = malloc(sizeof(bk_instr) * (size_t)f->n);
	if (!newidx || !dst) {
		free(newidx);
		free(dst);
		return -1;
	}
	for (int i = 0; i < f->n; i++)
		newidx[i] = -1;
	int n = 0;
	order(f, out, newidx, dst, &n);
	free(newidx);
	free(f->code);
	f->code = dst;
	f->n = f->cap = n;
	free(f->hash); /* built: nothing is pushed any more */
	f->hash = NULL;
	f->hcap = 0;
	f->out = n - 1;
	/* Recompute what is read: dead inputs and parameters do not count. */
	f->inputs = f->params = 0;
	for (int i = 0; i < n; i++)
		if (dst[i].op == BK_OP_INPUT)
			f->inputs |= 1u << dst[i].slot;
		else if (dst[i].op == BK_OP_PARAM)
			f->params |= 1u << dst[i].slot;
	return 0;
}

int bk_form_constants(const bk_form *f, double *k, int max)
{
	int n = 0;
	for (int i = 0; i < f->n; i++)
		if (f->code[i].op == BK_OP_CONST) {
			if (n < max)
				k[n] = f->code[i].k;
			n++;
		}
	return n;
}
