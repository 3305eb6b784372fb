/*
 * semantic.c — the `semantic` generator (semantic.h): semantic
 * backpropagation into a library of small trees.
 */
#include "search/semantic.h"
#include "search/generate.h"
#include "brdf_ops.h" /* the opcodes the inversion walks */

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The library: every parameter-free canonical tree up to SEM_LIB_SIZE nodes
 * (at most SEM_LIB_MAX of them, one per affine class of values at the
 * probes: g and p + p'*g are one entry). */
#define SEM_LIB_SIZE 5
#define SEM_LIB_MAX 32768
/* Library trees offered at each subtree, the nearest first. */
#define SEM_PER_SITE 2
/* And the pair p' g + p'' h that comes nearest together, where it halves
 * the nearest single's residual: a subtree such as p2 sq(x) + p3 x, which
 * no one library tree scaled is. Its two come from a pool: the
 * SEM_PAIR_SMALL first trees of the library (the smallest: the enumeration
 * goes by size) and the SEM_PAIR_POOL nearest alone (the parts of a pair
 * need not be near alone: sq(x) and x are not). */
#define SEM_PAIR_POOL 12
#define SEM_PAIR_SMALL 32
/* A subtree is worth replacing only where at least this many probes say
 * what it should be. */
#define SEM_MIN_PROBES 16
/* Values wanted beyond this size come from an inversion near a pole
 * (x / b with b ~ 0): their probes are left free. */
#define SEM_MAX_WANT 1e6
/* The most probes a walk reads (the fingerprint's are 64). */
#define SEM_PROBES_MAX 256

/* A library tree, packed (a bk_expr holds 64 nodes; these hold at most
 * twice their size: sq(x) is x twice). */
typedef struct lib_tree {
	int n;
	bk_enode node[2 * SEM_LIB_SIZE];
} lib_tree;

typedef struct sem_state {
	int built;       /* the library is made (at the first make) */
	size_t m;        /* probes: the fingerprint's (unique.h) */
	lib_tree *lib;   /* library trees */
	double *z;       /* their values at the probes, centred and of unit norm: m each */
	double *mu, *nu; /* their mean and norm before (g = mu + nu z) */
	size_t nlib, cap;
	bk_hashset classes; /* the library's affine classes */
	bk_hashset done;    /* candidate index + 1 of each best walked whole */
} sem_state;

/* ---- values ----------------------------------------------------------------- */

/* The values of every node of e at the m probes in (node i's at V + i m),
 * with parameters p (NULL: none), by the IR's own operations (bk_ir_apply:
 * its folding and f64 kernel, so each operation has the meaning it has
 * everywhere); a registry term's are NaN, which leaves its probes free. In
 * prefix order a node's operands follow it, so the last node comes first. */
static void node_values(const bk_expr *e, const double *p, size_t m, double *const in[BK_IN_COUNT], double *V)
{
	for (int i = e->n - 1; i >= 0; i--) {
		const bk_enode *x = &e->node[i];
		double *out = V + (size_t)i * m;
		int ar = x->op < BK_OP_COUNT ? bk_op_arity(x->op) : -1;
		if (x->op == BK_OP_CONST || x->op == BK_OP_PARAM || (x->op == BK_OP_INPUT && !in[x->slot])) {
			double k = x->op == BK_OP_CONST ? x->k : x->op == BK_OP_PARAM && p ? p[x->slot] : NAN;
			for (size_t j = 0; j < m; j++)
				out[j] = k;
		} else if (x->op == BK_OP_INPUT) {
			memcpy(out, in[x->slot], sizeof *out * m);
		} else if (ar < 1 || ar > 3) {
			for (size_t j = 0; j < m; j++)
				out[j] = NAN;
		} else {
			const double *o[3] = {NULL, NULL, NULL};
			for (int a = 0, at = i + 1; a < ar; a++, at += bk_expr_span(e, at))
				o[a] = V + (size_t)at * m;
			for (size_t j = 0; j < m; j++)
				out[j] = bk_ir_apply((bk_op)x->op, o[0][j], ar > 1 ? o[1][j] : 0, ar > 2 ? o[2][j] : 0);
		}
	}
}

/* ---- the library ------------------------------------------------------------ */

typedef struct lib_build {
	sem_state *S;
	double *const *in;
	int failed; /* out of memory */
} lib_build;

/* The affine class of v (m values): centred, unit norm, its sign fixed by
 * its first value clear of zero, each value to 24 bits. */
static uint64_t class_of(const double *z, size_t m)
{
	double sign = 0;
	for (size_t i = 0; i < m && sign == 0; i++)
		if (fabs(z[i]) > 1e-6)
			sign = z[i] > 0 ? 1 : -1;
	uint64_t h = BK_HASH_INIT;
	for (size_t i = 0; i < m; i++) {
		long long q = llround(sign * z[i] * 16777216.0);
		h = bk_hash_bytes(h, &q, sizeof q);
	}
	return h;
}

/* Room for twice as many library trees. 0, or -1 when out of memory. */
static int lib_grow(sem_state *S)
{
	size_t cap = S->cap ? 2 * S->cap : 256;
	lib_tree *lib = realloc(S->lib, sizeof *lib * cap);
	if (lib)
		S->lib = lib;
	double *z = realloc(S->z, sizeof *z * cap * S->m);
	if (z)
		S->z = z;
	double *mu = realloc(S->mu, sizeof *mu * cap);
	if (mu)
		S->mu = mu;
	double *nu = realloc(S->nu, sizeof *nu * cap);
	if (nu)
		S->nu = nu;
	if (!lib || !z || !mu || !nu)
		return -1;
	S->cap = cap;
	return 0;
}

static int lib_visit(void *ctx, const bk_expr *e)
{
	lib_build *b = ctx;
	sem_state *S = b->S;
	size_t m = S->m;
	if (S->nlib >= SEM_LIB_MAX)
		return 1;
	if (bk_expr_nparams(e) > 0 || e->n > 2 * SEM_LIB_SIZE)
		return 0;
	if (S->nlib == S->cap && lib_grow(S)) {
		b->failed = 1;
		return 1;
	}
	double V[SEM_LIB_SIZE * 2 * SEM_PROBES_MAX], *z = S->z + S->nlib * m;
	node_values(e, NULL, m, b->in, V);
	memcpy(z, V, sizeof *z * m);
	double mean = 0, norm = 0;
	for (size_t i = 0; i < m; i++) {
		if (!isfinite(z[i]) || fabs(z[i]) > SEM_MAX_WANT)
			return 0;
		mean += z[i];
	}
	mean /= (double)m;
	for (size_t i = 0; i < m; i++)
		norm += (z[i] - mean) * (z[i] - mean);
	norm = sqrt(norm);
	if (!(norm > 1e-9 * (1 + fabs(mean)) * sqrt((double)m)))
		return 0; /* constant at the probes: a parameter does as well */
	for (size_t i = 0; i < m; i++)
		z[i] = (z[i] - mean) / norm;
	int fresh = bk_hashset_add(&S->classes, class_of(z, m));
	if (fresh < 0) {
		b->failed = 1;
		return 1;
	}
	if (fresh == 0)
		return 0;
	S->lib[S->nlib].n = e->n;
	memcpy(S->lib[S->nlib].node, e->node, sizeof *e->node * (size_t)e->n);
	S->mu[S->nlib] = mean;
	S->nu[S->nlib] = norm;
	S->nlib++;
	return 0;
}

static int build_library(sem_state *S, bk_search *s)
{
	S->built = 1;
	S->m = s->uq.m;
	if (S->m == 0 || S->m > SEM_PROBES_MAX)
		return 0; /* an empty library: nothing is offered */
	bk_grammar g = s->tree_g;
	g.max_params = 0;
	lib_build b = {S, s->uq.in, 0};
	for (int size = 1; size <= SEM_LIB_SIZE && S->nlib < SEM_LIB_MAX; size++)
		if (bk_expr_enumerate(&g, size, lib_visit, &b) < 0 || b.failed)
			return -1;
	return 0;
}

/* ---- the inversion ---------------------------------------------------------- */

/* Whether node i of e is sq(x): a product of two equal subtrees. */
static int is_sq(const bk_expr *e, int i)
{
	if (e->node[i].op != BK_OP_MUL)
		return 0;
	int l = bk_expr_span(e, i + 1);
	if (bk_expr_span(e, i + 1 + l) != l)
		return 0;
	for (int k = 0; k < l; k++) {
		const bk_enode *a = &e->node[i + 1 + k], *b = &e->node[i + 1 + l + k];
		if (a->op != b->op || a->slot != b->slot || (a->op == BK_OP_CONST && a->k != b->k))
			return 0;
	}
	return 1;
}

/* The value operand `which` of op must take for op to give d, the others
 * at their values o[] (o[which] its own value); NAN where none does or any
 * does (that probe is then free). brdfkit's own exp2, log2, exp and log
 * (brdf.h), as the IR's: glibc's differ in the last bit between its FMA
 * and non-FMA variants, and an offer must not depend on the CPU. */
static double invert(int op, int which, double d, const double *o)
{
	double a = o[0], b = o[1], c = o[2], r = NAN;
	switch (op) {
	case BK_OP_ADD: r = d - o[1 - which]; break;
	case BK_OP_SUB: r = which ? a - d : d + b; break;
	case BK_OP_MUL: r = d / o[1 - which]; break;
	case BK_OP_DIV: r = which ? a / d : d * b; break;
	case BK_OP_NEG: r = -d; break;
	case BK_OP_MAD: r = which == 2 ? d - a * b : (d - c) / o[1 - which]; break;
	case BK_OP_SQRT: r = d >= 0 ? d * d : NAN; break;
	case BK_OP_RSQRT: r = d > 0 ? 1 / (d * d) : NAN; break;
	case BK_OP_RCP: r = 1 / d; break;
	case BK_OP_EXP2: r = d > 0 ? bk_dlog2(d) : NAN; break;
	case BK_OP_LOG2: r = bk_dexp2(d); break;
	case BK_OP_EXP: r = d > 0 ? bk_dlog(d) : NAN; break;
	case BK_OP_LOG: r = bk_dexp(d); break;
	case BK_OP_MIN: r = d < o[1 - which] ? d : NAN; break;
	case BK_OP_MAX: r = d > o[1 - which] ? d : NAN; break;
	case BK_OP_SATURATE: r = d > 0 && d < 1 ? d : NAN; break;
	case BK_OP_CLAMP: r = which == 0 && d > b && d < c ? d : NAN; break;
	case BK_OP_MIX: /* a + (b - a) c */
		r = which == 0 ? (d - b * c) / (1 - c) : which == 1 ? (d - a * (1 - c)) / c : (d - a) / (b - a);
		break;
	case BK_OP_POW:
		r = d > 0 && a > 0 ? (which == 0 ? bk_dexp2(bk_dlog2(d) / b) : bk_dlog2(d) / bk_dlog2(a)) : NAN;
		break;
	default: break; /* abs, registry terms: not inverted */
	}
	return isfinite(r) && fabs(r) <= SEM_MAX_WANT ? r : NAN;
}

/* The weighted least squares of d on 1, z (weights w, zero where d is
 * free): its residual sum, and the line in *c0, *c1 (d ~ c0 + c1 z). */
typedef struct wanted {
	const double *d, *w;
	double W, sd, sdd;
} wanted;

static double line_residual(const wanted *q, const double *z, size_t m, double *c0, double *c1)
{
	double sz = 0, szz = 0, sdz = 0;
	for (size_t i = 0; i < m; i++) {
		double wz = q->w[i] * z[i];
		sz += wz;
		szz += wz * z[i];
		sdz += wz * q->d[i];
	}
	double var = szz - sz * sz / q->W, cov = sdz - q->sd * sz / q->W;
	if (!(var > 1e-12))
		return HUGE_VAL;
	*c1 = cov / var;
	*c0 = (q->sd - *c1 * sz) / q->W;
	double r = q->sdd - q->sd * q->sd / q->W - cov * cov / var;
	return r > 0 ? r : 0;
}

/* One regressor's weighted sums under q: of w z, w z z and w z d. */
typedef struct zsums {
	double s, ss, sd;
} zsums;

static zsums sums_of(const wanted *q, const double *z, size_t m)
{
	zsums t = {0, 0, 0};
	for (size_t i = 0; i < m; i++) {
		double w = q->w[i], a = z[i];
		t.s += w * a, t.ss += w * a * a, t.sd += w * a * q->d[i];
	}
	return t;
}

/* The weighted least squares of d on 1, z1, z2 (their sums t1, t2, made
 * once per tree, not once per pair): its residual sum, and the plane in
 * c[0..2] (d ~ c0 + c1 z1 + c2 z2); HUGE_VAL where z1 and z2 are (nearly)
 * collinear under the weights. */
static double plane_residual(const wanted *q, const double *z1, const double *z2, const zsums *t1,
                             const zsums *t2, size_t m, double c[3])
{
	double s12 = 0;
	for (size_t i = 0; i < m; i++)
		s12 += q->w[i] * z1[i] * z2[i];
	double s1 = t1->s, s2 = t2->s, s11 = t1->ss, s22 = t2->ss, sd1 = t1->sd, sd2 = t2->sd;
	/* centred by the weighted means: a 2 x 2 system */
	double W = q->W, v11 = s11 - s1 * s1 / W, v22 = s22 - s2 * s2 / W, v12 = s12 - s1 * s2 / W;
	double u1 = sd1 - q->sd * s1 / W, u2 = sd2 - q->sd * s2 / W;
	double det = v11 * v22 - v12 * v12;
	if (!(v11 > 1e-12 && v22 > 1e-12 && det > 1e-9 * v11 * v22))
		return HUGE_VAL;
	c[1] = (u1 * v22 - u2 * v12) / det;
	c[2] = (u2 * v11 - u1 * v12) / det;
	c[0] = (q->sd - c[1] * s1 - c[2] * s2) / W;
	double r = q->sdd - q->sd * q->sd / W - (c[1] * u1 + c[2] * u2);
	return r > 0 ? r : 0;
}

/* ---- the offers ------------------------------------------------------------- */

/* e with every subtree at the positions at[0..nat) replaced by the nodes
 * t[0..len) into out. -1 when it would not fit. */
static int replace_at(const bk_expr *e, const int *at, int nat, const bk_enode *t, int len, bk_expr *out)
{
	int n = 0;
	for (int i = 0; i < e->n;) {
		int hit = 0;
		for (int k = 0; k < nat; k++)
			hit |= at[k] == i;
		if (hit) {
			if (n + len > BK_EXPR_MAX)
				return -1;
			memcpy(out->node + n, t, sizeof *t * (size_t)len);
			n += len;
			i += bk_expr_span(e, i);
		} else {
			if (n + 1 > BK_EXPR_MAX)
				return -1;
			out->node[n++] = e->node[i++];
		}
	}
	out->n = n;
	return 0;
}

/* Offers e with the subtrees at at[] replaced by the nodes t[0..len), its
 * new constants numbered from e's count on, starting from e's fitted
 * constants and the new ones' values in t. 1 taken, 0 not (a form made
 * before), 2 outside the grammar's limits (a spelling with fewer constants
 * may do), -1 out of memory. */
static int offer_tree(bk_search *s, bk_search_sink *k, const bk_expr *e, const double *p, int np, const int *at,
                      int nat, const bk_enode *t, int len)
{
	int q = bk_expr_nparams(e);
	bk_expr x[2];
	memset(x, 0, sizeof x);
	if (replace_at(e, at, nat, t, len, &x[0]))
		return 2;
	for (int i = 0; i < x[0].n; i++) /* the fitted constants as start values */
		if (x[0].node[i].op == BK_OP_PARAM && x[0].node[i].slot < np && x[0].node[i].slot < q)
			x[0].node[i].k = p[x[0].node[i].slot];
	if (bk_expr_canon_in(&x[0], s->tree_g.inputs) || bk_expr_nparams(&x[0]) > s->tree_g.max_params ||
	    bk_expr_size(&x[0]) > s->tree_g.max_size)
		return 2;
	double start[BK_MAX_PARAMS];
	for (int j = 0; j < BK_MAX_PARAMS; j++)
		start[j] = 1.0;
	for (int i = 0; i < x[0].n; i++)
		if (x[0].node[i].op == BK_OP_PARAM && x[0].node[i].k != 0 && isfinite(x[0].node[i].k))
			start[x[0].node[i].slot] = x[0].node[i].k;
	char why[128];
	if (bk_expr_valid(&x[0], why, sizeof why))
		return 2;
	return bk_gen_take(s, k->b, x, start);
}

/* Offers e with the subtrees at at[] replaced by c0 + c1 g (fewer new
 * constants where the grammar's limits leave no room for two). */
static int offer_site(bk_search *s, bk_search_sink *k, const bk_expr *e, const double *p, int np, const int *at,
                 int nat, const lib_tree *g, double c0, double c1)
{
	for (int form = 0; form < 3; form++) {
		bk_enode t[BK_EXPR_MAX];
		int len = 0, q = bk_expr_nparams(e);
		if (q + 2 - form > BK_MAX_PARAMS)
			continue; /* no slot for its new constants */
		if (form == 0) { /* p + p' g */
			t[len++] = (bk_enode){BK_OP_ADD, 0, 0};
			t[len++] = (bk_enode){BK_OP_PARAM, q, c0};
		}
		if (form <= 1) { /* p' g */
			t[len++] = (bk_enode){BK_OP_MUL, 0, 0};
			t[len++] = (bk_enode){BK_OP_PARAM, q + (form == 0), c1};
		}
		if (len + g->n > BK_EXPR_MAX)
			continue;
		memcpy(t + len, g->node, sizeof *t * (size_t)g->n);
		len += g->n;
		int r = offer_tree(s, k, e, p, np, at, nat, t, len);
		if (r != 2) /* taken, made before (not spelled again), or out of memory */
			return r;
	}
	return 0;
}

/* Offers e with the subtrees at at[] replaced by c0 + c1 g + c2 h, or
 * c1 g + c2 h where the grammar's limits leave no room for three. */
static int offer_pair(bk_search *s, bk_search_sink *k, const bk_expr *e, const double *p, int np, const int *at,
                      int nat, const lib_tree *g, const lib_tree *h, const double c[3])
{
	for (int form = 0; form < 2; form++) {
		bk_enode t[BK_EXPR_MAX];
		int len = 0, q = bk_expr_nparams(e);
		if (q + 3 - form > BK_MAX_PARAMS || 6 + g->n + h->n > BK_EXPR_MAX)
			continue;
		if (form == 0) { /* p + (p' g + p'' h) */
			t[len++] = (bk_enode){BK_OP_ADD, 0, 0};
			t[len++] = (bk_enode){BK_OP_PARAM, q, c[0]};
		}
		int j = q + (form == 0);
		t[len++] = (bk_enode){BK_OP_ADD, 0, 0};
		t[len++] = (bk_enode){BK_OP_MUL, 0, 0};
		t[len++] = (bk_enode){BK_OP_PARAM, j, c[1]};
		memcpy(t + len, g->node, sizeof *t * (size_t)g->n);
		len += g->n;
		t[len++] = (bk_enode){BK_OP_MUL, 0, 0};
		t[len++] = (bk_enode){BK_OP_PARAM, j + 1, c[2]};
		memcpy(t + len, h->node, sizeof *t * (size_t)h->n);
		len += h->n;
		int r = offer_tree(s, k, e, p, np, at, nat, t, len);
		if (r != 2) /* taken, made before (not spelled again), or out of memory */
			return r;
	}
	return 0;
}

/* An offer of a walk: at node site, library tree la scaled and offset
 * (c0 + c1 g), or la and lb together (pair: c0 + c1 g + c2 h); score, the
 * share of the wanted values' variance it leaves. */
typedef struct sem_offer {
	int site;
	size_t la, lb;
	double c[3];
	double score;
	int pair;
} sem_offer;

static int offer_order(const void *a, const void *b)
{
	const sem_offer *x = a, *y = b;
	if (x->score != y->score)
		return x->score < y->score ? -1 : 1;
	if (x->site != y->site)
		return x->site < y->site ? -1 : 1;
	if (x->pair != y->pair)
		return x->pair - y->pair;
	if (x->la != y->la)
		return x->la < y->la ? -1 : 1;
	return x->lb < y->lb ? -1 : x->lb > y->lb;
}

/* Walks c: for each subtree, the values wanted of it and the library trees
 * nearest them, offered. 1 when walked whole, 0 when the sink filled first,
 * -1 out of memory. */
static int walk_best(sem_state *S, bk_search *s, const bk_cand *c, bk_search_sink *k)
{
	size_t m = S->m;
	const bk_samples *sm = s->o.screen;
	bk_expr t[2];
	bk_cand_trees(c, t);
	const bk_expr *e = &t[0];
	int n = e->n;
	if (n < 2 || c->status != BK_CAND_OK)
		return 1;
	double *v = malloc(sizeof *v * (size_t)n * m), *d = malloc(sizeof *d * (size_t)n * m),
	       *w = malloc(sizeof *w * m);
	if (!v || !d || !w) {
		free(v), free(d), free(w);
		return -1;
	}
	node_values(e, c->p, m, s->uq.in, v); /* each node's values at the fitted constants */
	/* parents (prefix order: a parent precedes its operands), the operand
	 * each node is, and whether it lies in the second copy of a sq */
	int parent[BK_EXPR_MAX], which[BK_EXPR_MAX], mirror[BK_EXPR_MAX];
	parent[0] = -1, which[0] = 0, mirror[0] = 0;
	for (int i = 0; i < n; i++) {
		int ar = e->node[i].op < BK_OP_COUNT ? bk_op_arity(e->node[i].op) : -1, at = i + 1;
		for (int a = 0; a < ar && at < n; a++) {
			parent[at] = i, which[at] = a;
			mirror[at] = mirror[i] || (a == 1 && is_sq(e, i));
			at += bk_expr_span(e, at);
		}
		if (ar < 0) /* a registry term: its operands are left alone */
			for (int j = i + 1; j < i + bk_expr_span(e, i); j++)
				parent[j] = i, which[j] = -1, mirror[j] = 1;
	}
	/* the root's wanted values: the target (F0: the tree is f0 times) */
	for (size_t j = 0; j < m; j++) {
		size_t at = (size_t)((unsigned long long)j * s->uq.stride % sm->n);
		double y = sm->y[at];
		if (s->o.shape == BK_SHAPE_F0)
			y = s->uq.in[BK_IN_F0] && s->uq.in[BK_IN_F0][j] != 0 ? y / s->uq.in[BK_IN_F0][j] : NAN;
		d[j] = isfinite(y) ? y : NAN;
		w[j] = sm->w ? sm->w[at] : 1.0; /* not times f0^2 under F0: a guide, the fit judges */
		if (s->o.relative)
			w[j] = y != 0 ? w[j] / (y * y) : 0;
	}
	int ret = 1, noffers = 0;
	sem_offer offers[BK_EXPR_MAX * (SEM_PER_SITE + 1)];
	for (int i = 1; i < n; i++) {
		double *di = d + (size_t)i * m;
		int pa = parent[i];
		int op = e->node[pa].op;
		int sq = is_sq(e, pa);
		for (size_t j = 0; j < m; j++) {
			double o[3] = {NAN, NAN, NAN};
			int at = pa + 1;
			for (int a = 0; a < 3 && which[i] >= 0 && a < bk_op_arity(op); a++) {
				o[a] = v[(size_t)at * m + j];
				at += bk_expr_span(e, at);
			}
			double dp = d[(size_t)pa * m + j];
			if (which[i] < 0 || !isfinite(dp))
				di[j] = NAN;
			else if (sq) /* x*x = dp: x keeps its sign */
				di[j] = dp >= 0 ? copysign(sqrt(dp), o[0]) : NAN;
			else
				di[j] = invert(op, which[i], dp, o);
		}
		if (mirror[i])
			continue;
		/* what is wanted of node i, and how near its own values are */
		/* (m <= SEM_PROBES_MAX: the library is empty otherwise, and sem_make
		 * walks nothing.) A free probe weighs nothing in the least squares,
		 * which read its wanted value as 0 (dz); di keeps it free (NaN), so
		 * that the operands below are free there too. */
		double wi[SEM_PROBES_MAX], dz[SEM_PROBES_MAX];
		double W = 0, sd = 0, sdd = 0;
		size_t free_ = 0;
		for (size_t j = 0; j < m; j++) {
			int ok = isfinite(di[j]) && isfinite(v[(size_t)i * m + j]);
			wi[j] = ok ? w[j] : 0;
			free_ += !ok;
			dz[j] = ok ? di[j] : 0;
			W += wi[j], sd += wi[j] * dz[j], sdd += wi[j] * dz[j] * dz[j];
		}
		if (m - free_ < SEM_MIN_PROBES || !(W > 0))
			continue;
		wanted q = {dz, wi, W, sd, sdd};
		/* the node's own values as a library tree would be judged (a
		 * probe where it is not finite weighs nothing: 0 there) */
		double own[SEM_PROBES_MAX], mean = 0, norm = 0, a0, a1;
		for (size_t j = 0; j < m; j++)
			mean += own[j] = wi[j] > 0 ? v[(size_t)i * m + j] : 0;
		mean /= (double)m;
		for (size_t j = 0; j < m; j++)
			own[j] -= mean, norm += own[j] * own[j];
		norm = sqrt(norm);
		for (size_t j = 0; j < m; j++)
			own[j] = norm > 0 ? own[j] / norm : 0;
		double now = norm > 0 ? line_residual(&q, own, m, &a0, &a1) : q.sdd - q.sd * q.sd / q.W;
		/* the SEM_PER_SITE nearest library trees, the earlier at a tie */
		size_t best[SEM_PER_SITE];
		double br[SEM_PER_SITE], b0[SEM_PER_SITE], b1[SEM_PER_SITE];
		int nb = 0, npool = 0;
		size_t pool[SEM_PAIR_POOL + SEM_PAIR_SMALL];
		double pr[SEM_PAIR_POOL];
		for (size_t l = 0; l < S->nlib; l++) {
			double c0, c1, r = line_residual(&q, S->z + l * m, m, &c0, &c1);
			if (r < HUGE_VAL) { /* the pool of the nearest, the earlier at a tie */
				int at = npool < SEM_PAIR_POOL ? npool++ : SEM_PAIR_POOL;
				for (; at > 0 && r < pr[at - 1]; at--)
					if (at < SEM_PAIR_POOL)
						pool[at] = pool[at - 1], pr[at] = pr[at - 1];
				if (at < SEM_PAIR_POOL)
					pool[at] = l, pr[at] = r;
			}
			if (!(r < now * 0.5))
				continue;
			int at = nb < SEM_PER_SITE ? nb++ : SEM_PER_SITE;
			while (at > 0 && r < br[at - 1]) {
				if (at < SEM_PER_SITE)
					best[at] = best[at - 1], br[at] = br[at - 1], b0[at] = b0[at - 1], b1[at] = b1[at - 1];
				at--;
			}
			if (at < SEM_PER_SITE)
				best[at] = l, br[at] = r, b0[at] = c0, b1[at] = c1;
		}
		double var = q.sdd - q.sd * q.sd / q.W; /* of the wanted values: the scores' scale */
		if (!(var > 0))
			continue;
		for (int b = 0; b < nb; b++) {
			size_t l = best[b];
			sem_offer *f = &offers[noffers++];
			*f = (sem_offer){i, l, l, {b0[b] - b1[b] * S->mu[l] / S->nu[l], b1[b] / S->nu[l], 0}, br[b] / var, 0};
		}
		/* the pair of the pool nearest together, where it halves the
		 * nearest single's residual (and so the node's own) */
		double bestr = HUGE_VAL, bc[3] = {0, 0, 0}, cc[3] = {0, 0, 0};
		int ga = -1, gb = -1, nsingle = npool;
		if (nsingle == 0) /* no single to halve: no pair is offered */
			continue;
		for (size_t l = 0; l < S->nlib && l < SEM_PAIR_SMALL; l++) { /* and the smallest, once */
			int in = 0;
			for (int a = 0; a < nsingle; a++)
				in |= pool[a] == l;
			if (!in)
				pool[npool++] = l;
		}
		zsums ts[SEM_PAIR_POOL + SEM_PAIR_SMALL];
		for (int a = 0; a < npool; a++)
			ts[a] = sums_of(&q, S->z + pool[a] * m, m);
		for (int a = 0; a < npool; a++)
			for (int b = a + 1; b < npool; b++) {
				double r = plane_residual(&q, S->z + pool[a] * m, S->z + pool[b] * m, &ts[a], &ts[b], m, cc);
				if (r < bestr)
					bestr = r, ga = a, gb = b, memcpy(bc, cc, sizeof bc);
			}
		if (ga >= 0 && bestr < 0.5 * fmin(pr[0], now)) {
			size_t la = pool[ga], lb = pool[gb];
			sem_offer *f = &offers[noffers++];
			*f = (sem_offer){i, la, lb,
			                 {bc[0] - bc[1] * S->mu[la] / S->nu[la] - bc[2] * S->mu[lb] / S->nu[lb],
			                  bc[1] / S->nu[la], bc[2] / S->nu[lb]},
			                 bestr / var, 1};
		}
	}
	/* the offers, the best explained first (the least share of the wanted
	 * values' variance left), the earlier site and the single first at a
	 * tie: a small share of a generation goes where the match is closest,
	 * not to the sites nearest the root */
	qsort(offers, (size_t)noffers, sizeof *offers, offer_order);
	for (int o = 0; o < noffers && ret == 1; o++) {
		if (k->b->n >= k->b->want) {
			ret = 0;
			break;
		}
		const sem_offer *f = &offers[o];
		/* the positions the replacement takes: the node and its copies in
		 * the second operand of each sq above it */
		int pos[BK_EXPR_MAX], npos = 1;
		pos[0] = f->site;
		for (int a = parent[f->site], below = f->site; a >= 0; below = a, a = parent[a])
			if (is_sq(e, a) && which[below] == 0) {
				int l = bk_expr_span(e, a + 1);
				for (int k2 = npos - 1; k2 >= 0 && npos < BK_EXPR_MAX; k2--)
					pos[npos++] = pos[k2] + l;
			}
		int r = f->pair ? offer_pair(s, k, e, c->p, c->np, pos, npos, &S->lib[f->la], &S->lib[f->lb], f->c)
		                : offer_site(s, k, e, c->p, c->np, pos, npos, &S->lib[f->la], f->c[0], f->c[1]);
		if (r < 0)
			ret = -1;
	}
	free(v), free(d), free(w);
	return ret;
}

/* ---- the generator ---------------------------------------------------------- */

static int sem_make(void *st, bk_search *s, bk_search_sink *k)
{
	sem_state *S = st;
	if (s->o.shape == BK_SHAPE_PAIR || s->nlv == 0)
		return 1;
	if (!S->built && build_library(S, s))
		return -1;
	if (S->nlib == 0)
		return 1;
	double front = HUGE_VAL;
	for (int L = 0; L < s->nlv && k->b->n < k->b->want; L++) {
		size_t bi = s->lv[L].idx[0];
		const bk_cand *c = &s->cand[bi];
		if (!(c->err < front)) /* not on the front: a cheaper level does better */
			continue;
		front = c->err;
		if (bk_hashset_has(&S->done, (uint64_t)bi + 1))
			continue;
		int r = walk_best(S, s, c, k);
		if (r < 0 || (r == 1 && bk_hashset_add(&S->done, (uint64_t)bi + 1) < 0))
			return -1;
	}
	return 1;
}

static void sem_free(void *st)
{
	sem_state *S = st;
	if (!S)
		return;
	free(S->lib), free(S->z), free(S->mu), free(S->nu);
	bk_hashset_free(&S->classes);
	bk_hashset_free(&S->done);
	free(S);
}

int bk_sem_generator(bk_search_generator *g)
{
	sem_state *S = calloc(1, sizeof *S);
	if (!S)
		return -1;
	*g = (bk_search_generator){"semantic", 0, sem_make, NULL, NULL, sem_free, S};
	return 0;
}
