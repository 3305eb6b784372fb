/*
 * search.c — the search for closed forms (search.h): seeds, bottom-up
 * enumeration, then generations of mutation and crossover over a MAP-Elites
 * archive on cost; every candidate fitted once, on threads, merged in order.
 */
#include "search.h"
#include "albfit.h"
#include "fit_int.h"
#include "ir.h" /* the opcode enum the trees are made of */

#include <ctype.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

/* Screening fits stop early: a candidate only has to be ranked (errors are
 * compared at 20 bits, ~1e-6), and the front's members are refitted in full
 * afterwards with fit's tolerances. */
#define SCREEN_ITERATIONS 40
#define SCREEN_FTOL 1e-6
#define SCREEN_PTOL 1e-8
/* Children a generation tries to make before it gives up finding new ones:
 * late in a run most children are duplicates of what was fitted. */
#define TRIES_PER_CHILD 30
#define CHECKPOINT_MAGIC "brdfkit-search-checkpoint 2"
#define MIGRANTS_MAGIC "brdfkit-search-migrants 1"

typedef struct level {
	int cost;     /* floor(cost) */
	size_t *idx;  /* candidates, best first */
	int n;
} level;

struct bk_search {
	bk_search_options o;
	char **seed_text, **seed_text_b, **seed_name; /* copies */
	double (*seed_p)[BK_MAX_PARAMS];
	uint64_t fingerprint;     /* this island's options (checkpoints) */
	uint64_t fingerprint_all; /* what all islands share: not the seed or the island (migrants) */
	bk_cand *cand;
	size_t n, cap;
	bk_hashset seen; /* hashes of the canonical texts tried (fitted or over a limit) */
	level *lv;
	int nlv;
	bk_rng rng;
	long evals;
	int phase;       /* 0 seeds, 1 enumeration, 2 evolution, 3 done */
	size_t enum_pos;
	bk_grammar tree_g; /* the grammar of one tree: a pair's halves get half the parameters */
	bk_grammar feat_g; /* the grammar of a pair's shared feature */
	bk_expr *en;     /* the enumerated trees, in order */
	size_t nen;
};

double bk_search_error(const bk_search_options *o, const bk_samples *sm, const double *v, const bk_fit_metrics *m)
{
	if (o->objective == BK_OBJ_MAX)
		return o->relative ? m->max_rel : m->max_abs;
	if (o->objective == BK_OBJ_ALBEDO)
		return m->albedo_max_abs;
	if (!o->relative)
		return m->rmse;
	if (!v)
		return NAN;
	double se = 0, ymax = 0; /* the rmse of the relative residuals, floored as fit's (fit_ctx.c) */
	for (size_t i = 0; i < sm->n; i++)
		ymax = fmax(ymax, fabs(sm->y[i]));
	for (size_t i = 0; i < sm->n; i++) {
		double r = (v[i] - sm->y[i]) / fmax(fabs(sm->y[i]), 1e-6 * ymax);
		se += r * r;
	}
	return sqrt(se / (double)sm->n);
}

double bk_search_round_err(double e)
{
	if (!isfinite(e) || e == 0)
		return e;
	int x;
	double m = frexp(e, &x);
	return ldexp(nearbyint(ldexp(m, BK_SEARCH_ERR_BITS)), x - BK_SEARCH_ERR_BITS);
}

void bk_search_defaults(bk_search_options *o)
{
	o->objective = BK_OBJ_RMSE;
	o->relative = 0;
	o->precision = BK_F64;
	o->max_cost = HUGE_VAL;
	o->simple_cost = BK_COST_SIMPLE;
	o->complex_cost = BK_COST_COMPLEX;
	o->scale = 1;
	o->nonneg = 0;
	o->env_bound = 0;
	o->evals = 20000;
	o->seed = 1;
	o->threads = 1;
	o->enum_size = 5;
	o->enum_max = 5000;
	o->generation = 256;
	o->per_level = 12;
	o->starts = 2;
	o->inherit = 0;
	o->seeds = o->seeds_b = o->seed_names = NULL;
	o->seed_p = NULL;
	o->nseeds = 0;
	o->exempt_seeds = INT_MAX;
	o->island = 0;
	o->islands = 1;
}

/* ---- the cache ------------------------------------------------------------- */

/* ---- candidates: text, cost ---------------------------------------------- */

/* The fitted form's text from the trees, the shape applied. */
static int shape_text(const bk_search *s, const bk_expr *t, char *a, char *b, size_t len)
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

/* The cost the front is drawn against: op counts of the whole shader
 * expression after sharing (a pair: f0*(A) + (B), paid once where shared). */
static int cost_of(const bk_search *s, const char *a, const char *b, bk_ops *ops, double *cost, int *np)
{
	char buf[9000];
	if (b && *b)
		snprintf(buf, sizeof buf, "f0*(%s) + (%s)", a, b);
	else
		snprintf(buf, sizeof buf, "%s", a);
	bk_form_error fe;
	bk_form *f = bk_form_parse(buf, &fe);
	if (!f)
		return -1;
	bk_form_count(f, ops);
	*cost = bk_ops_cost(ops, s->o.simple_cost, s->o.complex_cost);
	*np = bk_form_nparams(f);
	bk_form_free(f);
	return 0;
}

/* "f0" replaced by "1" where it is the input (token boundaries): the g of a
 * catalog V·F form f0*g, as the seed of the F0 shape's tree. */
static void without_f0(const char *t, char *buf, size_t len)
{
	size_t k = 0;
	for (size_t i = 0; t[i] && k + 2 < len; i++) {
		int tok = t[i] == 'f' && t[i + 1] == '0' && (i == 0 || !(isalnum((unsigned char)t[i - 1]) || t[i - 1] == '_')) &&
		          !(isalnum((unsigned char)t[i + 2]) || t[i + 2] == '_' || t[i + 2] == '.');
		if (tok) {
			buf[k++] = '1';
			i++;
		} else {
			buf[k++] = t[i];
		}
	}
	buf[k] = '\0';
}

/* ---- fitting one candidate (threads) ------------------------------------- */

/* Deterministic screening starts: all ones first (most constants of a shading
 * form are O(1)), then a spread of magnitudes and a sign. */
static const double start_value[4] = {1.0, 0.1, -1.0, 10.0};

static void fit_one(const bk_search *s, bk_cand *c, const double *seed_p)
{
	const bk_samples *sm = s->o.screen;
	c->status = BK_CAND_FAILED;
	c->err = c->rmse = c->max_abs = c->albedo_max_abs = HUGE_VAL;
	bk_form_error fe;
	bk_form *f[2] = {bk_form_parse(c->text, &fe), c->text_b ? bk_form_parse(c->text_b, &fe) : NULL};
	double *v = malloc(sizeof(double) * sm->n);
	if (!f[0] || (c->text_b && !f[1]) || !v)
		goto done;
	bk_fit_spec spec;
	memset(&spec, 0, sizeof spec);
	spec.s = sm;
	spec.form[0] = f[0];
	spec.form[1] = f[1] ? f[1] : f[0];
	spec.np = c->np;
	bk_fit_options opt = BK_FIT_OPTIONS_INIT;
	opt.max_iterations = SCREEN_ITERATIONS;
	opt.function_tolerance = SCREEN_FTOL;
	opt.parameter_tolerance = SCREEN_PTOL;
	spec.opt = opt;
	spec.relative = s->o.relative;
	spec.starts = 1;
	for (int j = 0; j < BK_MAX_PARAMS; j++) {
		spec.lower[j] = -HUGE_VAL;
		spec.upper[j] = HUGE_VAL;
	}
	bk_fit_ctx ctx;
	if (bk_fit_ctx_init(&ctx, &spec)) {
		bk_fit_ctx_free(&ctx);
		goto done;
	}
	double best[BK_MAX_PARAMS], best_cost = HUGE_VAL;
	int nstart = c->np ? s->o.starts + (seed_p != NULL) : 1;
	for (int k = 0; k < nstart; k++) {
		double p[BK_MAX_PARAMS];
		for (int j = 0; j < BK_MAX_PARAMS; j++)
			p[j] = seed_p ? (k == 0 ? seed_p[j] : start_value[k - 1]) : start_value[k];
		bk_fit_summary sum;
		if (c->np) {
			if (bk_fit_solve(&ctx, p, NULL, &sum) || sum.termination == BK_TERM_FAILURE)
				continue;
		} else {
			sum.final_cost = 0;
		}
		/* costs within the tie tolerance: the earlier start wins (fit.h) */
		if (sum.final_cost < best_cost * (1 - BK_FIT_COST_TIE)) {
			best_cost = sum.final_cost;
			memcpy(best, p, sizeof best);
		}
		/* the next start only where this one did not converge: most candidates
		 * converge from the first, and a screening fit is most of the search */
		if (c->np && sum.termination == BK_TERM_CONVERGENCE)
			break;
	}
	bk_fit_ctx_free(&ctx);
	if (!(best_cost < HUGE_VAL))
		goto done;
	/* the albedo objective: one more solve, least squares of the cells'
	 * albedo errors from the values' fit (fit/albfit.h), kept where it lowers
	 * the albedo's max error (the front's refit then goes on to its minimax) */
	if (s->o.objective == BK_OBJ_ALBEDO && c->np && sm->ncomp == 1 && !s->o.relative) {
		bk_albfit *af = bk_albfit_new(sm, f[0], c->np);
		double q[BK_MAX_PARAMS], e1;
		memcpy(q, best, sizeof q);
		if (af && bk_albfit_run(af, q, 0, &opt, &e1) == 0 && e1 < bk_albfit_max(af, best))
			memcpy(best, q, sizeof best);
		bk_albfit_free(af);
	}
	memcpy(c->p, best, sizeof c->p);
	for (int q = 0; q < sm->ncomp; q++) { /* the values in the search's precision */
		size_t lo = sm->start[q];
		const double *in[BK_IN_COUNT];
		for (int k = 0; k < BK_IN_COUNT; k++)
			in[k] = sm->in[k] + lo;
		if (bk_form_eval(spec.form[q], s->o.precision, sm->start[q + 1] - lo, in, c->p, v + lo))
			goto done;
	}
	c->status = BK_CAND_OK;
	for (size_t i = 0; i < sm->n; i++)
		if (!isfinite(v[i]) && isfinite(sm->y[i]))
			c->status = BK_CAND_NONFINITE;
	/* the published seeds are kept whatever the constraints say (the front
	 * starts at the state of the art; Karis' env fit dips below 0) */
	int exempt = 0;
	for (int k = 0; c->seed_name && k < s->o.nseeds && k < s->o.exempt_seeds; k++)
		exempt |= c->seed_name == s->seed_name[k];
	if (c->status == BK_CAND_OK && s->o.nonneg && !exempt)
		for (size_t i = 0; i < sm->n; i++)
			if (v[i] < 0)
				c->status = BK_CAND_CONSTRAINT;
	if (c->status == BK_CAND_OK && s->o.env_bound && sm->ncomp == 2 && !exempt) {
		size_t na = sm->start[1];
		for (size_t i = 0; i < na; i++)
			if (v[i] < -BK_SEARCH_ENV_SLACK || v[na + i] < -BK_SEARCH_ENV_SLACK || v[i] + v[na + i] > 1 + BK_SEARCH_ENV_SLACK)
				c->status = BK_CAND_CONSTRAINT;
	}
	if (c->status != BK_CAND_OK)
		goto done;
	bk_fit_metrics m;
	bk_samples_metrics(sm, v, NULL, &m);
	c->rmse = m.rmse;
	c->max_abs = m.max_abs;
	c->albedo_max_abs = m.albedo_max_abs;
	double e = bk_search_error(&s->o, sm, v, &m);
	c->err = isfinite(e) ? bk_search_round_err(e) : HUGE_VAL;
	if (!isfinite(e))
		c->status = BK_CAND_NONFINITE;
done:
	free(v);
	bk_form_free(f[0]);
	bk_form_free(f[1]);
}

typedef struct batch {
	const bk_search *s;
	bk_cand *c;
	const double **seed_p;
	size_t n;
	atomic_size_t next;
} batch;

static void *worker(void *arg)
{
	batch *b = arg;
	for (size_t i; (i = atomic_fetch_add(&b->next, 1)) < b->n;)
		fit_one(b->s, &b->c[i], b->seed_p[i]);
	return NULL;
}

static void fit_batch(const bk_search *s, bk_cand *c, const double **seed_p, size_t n)
{
	batch b = {s, c, seed_p, n, 0};
	int nt = s->o.threads < 1 ? 1 : s->o.threads;
	if ((size_t)nt > n)
		nt = (int)n;
	pthread_t th[64];
	int started = 0;
	for (int t = 1; t < nt && t < 64; t++)
		if (pthread_create(&th[started], NULL, worker, &b) == 0)
			started++;
	worker(&b); /* this thread works too; a thread that failed to start is only slower */
	for (int t = 0; t < started; t++)
		pthread_join(th[t], NULL);
}

/* ---- the archive ----------------------------------------------------------- */

/* a before b: lower error, then lower cost, then text */
static int better(const bk_cand *a, const bk_cand *b)
{
	if (a->err != b->err)
		return a->err < b->err;
	if (a->cost != b->cost)
		return a->cost < b->cost;
	int t = strcmp(a->text, b->text);
	if (t == 0 && a->text_b && b->text_b)
		t = strcmp(a->text_b, b->text_b);
	return t < 0;
}

static int archive_add(bk_search *s, size_t i)
{
	const bk_cand *c = &s->cand[i];
	if (c->status != BK_CAND_OK)
		return 0;
	int L = (int)floor(c->cost + 1e-9);
	int k = 0;
	while (k < s->nlv && s->lv[k].cost < L)
		k++;
	if (k == s->nlv || s->lv[k].cost != L) {
		level *t = realloc(s->lv, sizeof *t * (size_t)(s->nlv + 1));
		if (!t)
			return -1;
		s->lv = t;
		memmove(&s->lv[k + 1], &s->lv[k], sizeof *t * (size_t)(s->nlv - k));
		s->lv[k] = (level){L, malloc(sizeof(size_t) * (size_t)(s->o.per_level + 1)), 0};
		s->nlv++;
		if (!s->lv[k].idx)
			return -1;
	}
	level *l = &s->lv[k];
	int pos = l->n;
	while (pos > 0 && better(c, &s->cand[l->idx[pos - 1]]))
		pos--;
	if (pos >= s->o.per_level)
		return 0;
	memmove(&l->idx[pos + 1], &l->idx[pos], sizeof(size_t) * (size_t)(l->n - pos));
	l->idx[pos] = i;
	if (l->n < s->o.per_level)
		l->n++;
	return 0;
}

/* A parent: a cost level uniformly (cheap and expensive forms get the same
 * attention), then a member biased to the best of its level. */
static const bk_cand *pick(bk_search *s)
{
	const level *l = &s->lv[bk_rng_below(&s->rng, (uint32_t)s->nlv)];
	double u = bk_rng_unit(&s->rng);
	return &s->cand[l->idx[(int)(u * u * l->n)]];
}

/* ---- batches of new candidates ------------------------------------------ */

/* Linear scaling (Keijzer 2003; Operon and PySR's users do the same): the
 * tree g becomes p*g, its scale fitted with the other constants, so that a
 * shape is judged without its amplitude having to be found by mutation. A
 * tree that already has a free scale is unchanged by canonicalisation (p*p'
 * collapses to one parameter); the cost is one multiply at most. */
static int scaled(bk_expr *t)
{
	/* already scaled: p*x, x*p, p/x (the canonical form keeps p*(p'/x) as two) */
	if (t->n >= 3 && (t->node[0].op == BK_OP_MUL || t->node[0].op == BK_OP_DIV)) {
		int second = 1 + bk_expr_span(t, 1);
		if (t->node[1].op == BK_OP_PARAM || (t->node[0].op == BK_OP_MUL && t->node[second].op == BK_OP_PARAM))
			return 0;
	}
	if (t->n == 1 && t->node[0].op == BK_OP_PARAM)
		return 0;
	if (t->n + 2 > BK_EXPR_MAX)
		return -1;
	bk_expr w;
	memset(&w, 0, sizeof w);
	w.n = t->n + 2;
	w.node[0].op = BK_OP_MUL;
	w.node[1].op = BK_OP_PARAM;
	w.node[1].slot = bk_expr_nparams(t);
	memcpy(&w.node[2], t->node, sizeof(bk_enode) * (size_t)t->n);
	if (bk_expr_canon(&w))
		return -1;
	*t = w;
	return 0;
}

/* Prepares candidate c from trees t (canonical): text, cost; 1 if it is new
 * and within the limits (then counted in the cache), 0 if not, -1 on error. */
static int prepare(bk_search *s, const bk_expr *t0, bk_cand *c)
{
	char a[4200], b[4200];
	memset(c, 0, sizeof *c);
	bk_expr t[2] = {t0[0], t0[1]};
	int feature = s->o.shape == BK_SHAPE_PAIR && t[1].n == 0; /* affine in its feature already */
	for (int h = 0; s->o.scale && !feature && h < (s->o.shape == BK_SHAPE_PAIR ? 2 : 1); h++) {
		bk_expr w = t[h];
		if (scaled(&w) == 0 && bk_expr_nparams(&w) <= s->tree_g.max_params) /* room for the scale */
			t[h] = w;
	}
	if (shape_text(s, t, a, b, sizeof a))
		return 0;
	char key[8500];
	snprintf(key, sizeof key, "%s;%s", a, b);
	int fresh = bk_hashset_add(&s->seen, bk_expr_hash_text(key));
	if (fresh <= 0)
		return fresh;
	if (cost_of(s, a, b, &c->ops, &c->cost, &c->np) || c->cost > s->o.max_cost ||
	    c->np > s->o.grammar.max_params)
		return 0;
	c->text = strdup(a);
	c->text_b = s->o.shape == BK_SHAPE_PAIR ? strdup(b) : NULL;
	if (!c->text || (s->o.shape == BK_SHAPE_PAIR && !c->text_b))
		return -1;
	c->tree[0] = t[0];
	if (s->o.shape == BK_SHAPE_PAIR)
		c->tree[1] = t[1];
	return 1;
}

static int push(bk_search *s, bk_cand *c)
{
	if (s->n == s->cap) {
		size_t cap = s->cap ? 2 * s->cap : 1024;
		bk_cand *t = realloc(s->cand, sizeof *t * cap);
		if (!t)
			return -1;
		s->cand = t;
		s->cap = cap;
	}
	s->cand[s->n++] = *c;
	return archive_add(s, s->n - 1);
}

static void cand_free(bk_cand *c)
{
	free(c->text);
	free(c->text_b);
}

/* A lone parameter: the other half of an enumerated pair. */
static bk_expr lone_param(void)
{
	bk_expr e;
	memset(&e, 0, sizeof e);
	e.n = 1;
	e.node[0].op = BK_OP_PARAM;
	return e;
}

/* Where parameter `slot` of tree h of trees t sits in the fitted text: pN is
 * slot N of tree 0, and tree 1's follow tree 0's (shape_text). */
static int text_param(const bk_expr *t, int h, int slot)
{
	return (h ? bk_expr_nparams(&t[0]) : 0) + slot;
}

/* The trees of c to breed from: with --inherit, its fitted constants written
 * into its parameters' nodes as their start values (expr.h); a candidate that
 * did not fit passes on no values. */
static void parent_trees(const bk_search *s, const bk_cand *c, bk_expr *t)
{
	t[0] = c->tree[0];
	t[1] = c->tree[1];
	for (int h = 0; s->o.inherit && h < 2; h++)
		for (int i = 0; i < t[h].n; i++) {
			bk_enode *n = &t[h].node[i];
			int j = text_param(c->tree, h, n->slot);
			if (n->op == BK_OP_PARAM)
				n->k = c->status == BK_CAND_OK && j < c->np && isfinite(c->p[j]) ? c->p[j] + 0.0 : 0;
		}
}

/* The start of a child's first fit from its trees' start values (1, the
 * first default start, where a value is unknown or the parameter is the
 * shape's own). 1 if any value is known, else 0: the child then starts as an
 * enumerated tree does. */
static int inherited(const bk_cand *c, double *p)
{
	int known = 0;
	for (int j = 0; j < BK_MAX_PARAMS; j++)
		p[j] = 1.0;
	for (int h = 0; h < 2; h++)
		for (int i = 0; i < c->tree[h].n; i++) {
			const bk_enode *n = &c->tree[h].node[i];
			int j = text_param(c->tree, h, n->slot);
			if (n->op == BK_OP_PARAM && n->k != 0 && j < BK_MAX_PARAMS)
				p[j] = n->k, known = 1;
		}
	return known;
}

/* One child of the archive by mutation (70 %) or crossover; with --inherit
 * its parameters start from its parents' fitted values. */
static int child(bk_search *s, bk_expr *t)
{
	const bk_grammar *g = &s->tree_g;
	const bk_cand *a = pick(s);
	int which = s->o.shape == BK_SHAPE_PAIR ? (int)bk_rng_below(&s->rng, 2) : 0;
	bk_expr pa[2], pb[2];
	parent_trees(s, a, pa);
	t[0] = pa[0];
	t[1] = pa[1];
	if (s->o.shape == BK_SHAPE_PAIR && a->tree[1].n == 0) { /* a shared feature: its one tree */
		g = &s->feat_g;
		which = 0;
		if (bk_rng_unit(&s->rng) < 0.7)
			return bk_expr_mutate(g, &s->rng, &pa[0], &t[0]);
		const bk_cand *b = pick(s);
		parent_trees(s, b, pb);
		return bk_expr_crossover(g, &s->rng, &pa[0], &pb[bk_rng_below(&s->rng, b->tree[1].n ? 2 : 1)], &t[0]);
	}
	if (bk_rng_unit(&s->rng) < 0.7)
		return bk_expr_mutate(g, &s->rng, &pa[which], &t[which]);
	const bk_cand *b = pick(s);
	parent_trees(s, b, pb);
	const bk_expr *donor = pb[which].n ? &pb[which] : &pb[0]; /* a feature pair has one tree */
	if (s->o.shape == BK_SHAPE_PAIR && bk_rng_unit(&s->rng) < 0.25) { /* swap a whole half */
		t[which] = *donor;
		return 0;
	}
	return bk_expr_crossover(g, &s->rng, &pa[which], donor, &t[which]);
}

int bk_search_step(bk_search *s, char *err, size_t errlen)
{
	if (s->phase == 3 || s->evals >= s->o.evals)
		return 0;
	/* whole generations, whatever the budget: a run stopped at a budget and
	 * resumed with a larger one must make the same batches as a run that
	 * never stopped (so a run may end up to generation - 1 fits past it) */
	size_t want = (size_t)s->o.generation;
	bk_cand *c = calloc(want ? want : 1, sizeof *c);
	const double **sp = calloc(want ? want : 1, sizeof *sp);
	double (*start)[BK_MAX_PARAMS] = calloc(want ? want : 1, sizeof *start); /* children's inherited starts */
	size_t n = 0;
	int rc = 0;
	if (!c || !sp || !start)
		goto oom;
	if (s->phase == 0) { /* the seeds, in the order given */
		for (int k = 0; k < s->o.nseeds && n < want; k++) {
			bk_cand *q = &c[n];
			memset(q, 0, sizeof *q);
			char key[8500];
			snprintf(key, sizeof key, "%s;%s", s->seed_text[k], s->seed_text_b[k] ? s->seed_text_b[k] : "");
			if (bk_hashset_add(&s->seen, bk_expr_hash_text(key)) <= 0)
				continue;
			if (cost_of(s, s->seed_text[k], s->seed_text_b[k], &q->ops, &q->cost, &q->np))
				continue;
			q->text = strdup(s->seed_text[k]);
			q->text_b = s->seed_text_b[k] ? strdup(s->seed_text_b[k]) : NULL;
			q->seed_name = s->seed_name[k];
			bk_form_error fe;
			for (int h = 0; h < (s->o.shape == BK_SHAPE_PAIR ? 2 : 1); h++) {
				/* the search tree of a seed: its form read back (for F0, without the f0*) */
				const char *txt = h ? s->seed_text_b[k] : s->seed_text[k];
				char g[8192];
				if (s->o.shape == BK_SHAPE_F0) {
					without_f0(txt, g, sizeof g);
					txt = g;
				}
				bk_form *f = bk_form_parse(txt, &fe);
				if (!f || bk_expr_from_form(f, &q->tree[h]) || bk_expr_canon(&q->tree[h]))
					q->tree[h] = lone_param();
				bk_form_free(f);
			}
			sp[n] = s->seed_p ? s->seed_p[k] : NULL;
			n++;
		}
		s->phase = 1;
	} else if (s->phase == 1) { /* the enumeration */
		/* at most enum_max fits (not a share of --evals: a resumed run with a
		 * larger budget must make the same candidates); the smallest trees come
		 * first, and a default grammar at 5 nodes holds tens of thousands */
		long cap = s->o.enum_max;
		size_t kinds = s->o.shape == BK_SHAPE_PAIR ? 3 : 1;
		while (n < want && s->evals + (long)n < cap && s->enum_pos < s->nen * kinds) {
			size_t k = s->enum_pos++;
			if ((k / kinds) % (size_t)s->o.islands != (size_t)s->o.island)
				continue; /* another island's share of the enumeration */
			bk_expr t[2] = {s->en[k / kinds], lone_param()};
			if (k % kinds == 1) { /* pairs: (T, p), (p, T), and T as a shared feature */
				t[1] = t[0];
				t[0] = lone_param();
			} else if (k % kinds == 2) {
				t[1].n = 0;
				if (bk_expr_nparams(&t[0]) > s->feat_g.max_params)
					continue;
			}
			int r = prepare(s, t, &c[n]);
			if (r < 0)
				goto oom;
			n += (size_t)r;
		}
		if (s->enum_pos >= s->nen * kinds || s->evals + (long)n >= cap)
			s->phase = 2;
	} else { /* evolution */
		if (s->nlv == 0) {
			s->phase = 3;
			goto out;
		}
		for (size_t tries = 0; n < want && tries < want * TRIES_PER_CHILD; tries++) {
			bk_expr t[2];
			if (child(s, t))
				continue;
			int r = prepare(s, t, &c[n]);
			if (r < 0)
				goto oom;
			if (r > 0 && s->o.inherit && inherited(&c[n], start[n]))
				sp[n] = start[n];
			n += (size_t)r;
		}
		if (n == 0)
			s->phase = 3;
	}
	fit_batch(s, c, sp, n);
	for (size_t i = 0; i < n; i++) { /* merged in candidate order */
		c[i].found_at = ++s->evals;
		c[i].island = s->o.island;
		if (push(s, &c[i]))
			goto oom;
		c[i].text = c[i].text_b = NULL;
	}
out:
	for (size_t i = 0; i < n; i++)
		cand_free(&c[i]);
	free(c);
	free(sp);
	free(start);
	return rc < 0 ? rc : (s->phase == 3 || s->evals >= s->o.evals) ? 0 : 1;
oom:
	snprintf(err, errlen, "out of memory after %ld fits", s->evals);
	rc = -1;
	goto out;
}

/* ---- set-up --------------------------------------------------------------- */

typedef struct en_ctx {
	bk_search *s;
	int fail;
} en_ctx;

static int collect(void *vctx, const bk_expr *e)
{
	en_ctx *x = vctx;
	bk_search *s = x->s;
	if (s->nen % 4096 == 0) {
		bk_expr *t = realloc(s->en, sizeof *t * (s->nen + 4096));
		if (!t) {
			x->fail = 1;
			return 1;
		}
		s->en = t;
	}
	s->en[s->nen++] = *e;
	return 0;
}


/* What must agree between a checkpoint and the run resuming it: everything
 * that decides which candidates are made and how they are scored, not the
 * budget or the thread count. Without own: what the islands of one run share
 * (all of it but the seed, the island and its share of the enumeration), so
 * that migrants are comparable. */
static uint64_t fingerprint(const bk_search *s, int own)
{
	const bk_search_options *o = &s->o;
	uint64_t h = BK_HASH_INIT;
	int ints[] = {o->shape, o->scale, o->objective, o->relative, o->precision, o->nonneg, o->env_bound, o->enum_size,
	              o->generation, o->per_level, o->starts, o->grammar.inputs, o->grammar.max_params,
	              o->grammar.max_size, o->grammar.nconsts, o->nseeds, o->islands};
	double dbl[] = {o->max_cost, o->simple_cost, o->complex_cost};
	h = bk_hash_bytes(h, ints, sizeof ints);
	h = bk_hash_bytes(h, dbl, sizeof dbl);
	if (o->inherit) /* hashed only when on: checkpoints made before the option stay valid */
		h = bk_hash_bytes(h, &o->inherit, sizeof o->inherit);
	if (o->exempt_seeds < o->nseeds) /* likewise */
		h = bk_hash_bytes(h, &o->exempt_seeds, sizeof o->exempt_seeds);
	if (own) {
		double seed = (double)o->seed;
		h = bk_hash_bytes(h, &o->island, sizeof o->island);
		h = bk_hash_bytes(h, &seed, sizeof seed);
		h = bk_hash_bytes(h, &o->enum_max, sizeof o->enum_max); /* the island's share of the enumeration */
	}
	h = bk_hash_bytes(h, &o->grammar.ops, sizeof o->grammar.ops);
	h = bk_hash_bytes(h, o->grammar.consts, sizeof(double) * (size_t)o->grammar.nconsts);
	for (int k = 0; k < o->nseeds; k++) {
		h = bk_hash_bytes(h, s->seed_text[k], strlen(s->seed_text[k]) + 1);
		if (s->seed_text_b[k])
			h = bk_hash_bytes(h, s->seed_text_b[k], strlen(s->seed_text_b[k]) + 1);
	}
	const bk_samples *sm = o->screen;
	h = bk_hash_bytes(h, &sm->n, sizeof sm->n);
	h = bk_hash_bytes(h, sm->y, sizeof(double) * sm->n);
	return h;
}

bk_search *bk_search_new(const bk_search_options *o, char *err, size_t errlen)
{
	if (o->evals < 1 || o->threads < 1 || o->threads > 64 || o->generation < 1 || o->per_level < 1 ||
	    o->starts < 1 || o->starts > 4 || o->enum_size < 0 || o->enum_size > BK_EXPR_MAX ||
	    o->grammar.max_params < 0 || o->grammar.max_params > BK_MAX_PARAMS || o->grammar.max_size < 1 ||
	    o->grammar.max_size > BK_EXPR_MAX || !(o->max_cost > 0) || o->islands < 1 || o->island < 0 ||
	    o->island >= o->islands) {
		snprintf(err, errlen, "search options out of range");
		return NULL;
	}
	bk_search *s = calloc(1, sizeof *s);
	if (!s)
		goto oom;
	s->o = *o;
	int ns = o->nseeds;
	s->seed_text = calloc((size_t)ns + 1, sizeof(char *));
	s->seed_text_b = calloc((size_t)ns + 1, sizeof(char *));
	s->seed_name = calloc((size_t)ns + 1, sizeof(char *));
	s->seed_p = calloc((size_t)ns + 1, sizeof *s->seed_p);
	if (!s->seed_text || !s->seed_text_b || !s->seed_name || !s->seed_p)
		goto oom;
	for (int k = 0; k < ns; k++) {
		s->seed_text[k] = strdup(o->seeds[k]);
		s->seed_text_b[k] = o->seeds_b && o->seeds_b[k] ? strdup(o->seeds_b[k]) : NULL;
		char name[32];
		snprintf(name, sizeof name, "start %d", k + 1);
		s->seed_name[k] = strdup(o->seed_names && o->seed_names[k] ? o->seed_names[k] : name);
		for (int j = 0; j < BK_MAX_PARAMS; j++)
			s->seed_p[k][j] = o->seed_p ? o->seed_p[k][j] : 1.0;
		if (!s->seed_text[k] || !s->seed_name[k])
			goto oom;
	}
	s->o.seeds = (const char *const *)s->seed_text;
	s->o.seeds_b = (const char *const *)s->seed_text_b;
	s->o.seed_names = (const char *const *)s->seed_name;
	bk_rng_seed(&s->rng, o->seed);
	en_ctx x = {s, 0};
	bk_grammar g = o->grammar;
	s->feat_g = g; /* a shared feature leaves 6 parameters to A and B (shape_text) */
	s->feat_g.max_params = g.max_params > 6 ? g.max_params - 6 : 0;
	if (s->o.shape == BK_SHAPE_PAIR && g.max_params > 1)
		g.max_params /= 2;
	s->tree_g = g;
	if (s->o.scale && g.max_params > 0) /* the enumerated tree leaves room for its scale */
		g.max_params--;
	for (int size = 1; size <= o->enum_size && size <= g.max_size && !x.fail; size++)
		if (bk_expr_enumerate(&g, size, collect, &x) < 0)
			x.fail = 1;
	if (x.fail)
		goto oom;
	s->fingerprint = fingerprint(s, 1);
	s->fingerprint_all = fingerprint(s, 0);
	return s;
oom:
	snprintf(err, errlen, "out of memory setting up the search");
	bk_search_free(s);
	return NULL;
}

void bk_search_free(bk_search *s)
{
	if (!s)
		return;
	for (size_t i = 0; i < s->n; i++)
		cand_free(&s->cand[i]);
	free(s->cand);
	bk_hashset_free(&s->seen);
	for (int k = 0; k < s->nlv; k++)
		free(s->lv[k].idx);
	free(s->lv);
	for (int k = 0; s->seed_text && k < s->o.nseeds; k++) {
		free(s->seed_text[k]);
		free(s->seed_text_b[k]);
		free(s->seed_name[k]);
	}
	free(s->seed_text);
	free(s->seed_text_b);
	free(s->seed_name);
	free(s->seed_p);
	free(s->en);
	free(s);
}

long bk_search_evals(const bk_search *s) { return s->evals; }
size_t bk_search_count(const bk_search *s) { return s->n; }
const bk_cand *bk_search_at(const bk_search *s, size_t i) { return i < s->n ? &s->cand[i] : NULL; }

static const bk_search *sort_s; /* qsort has no context argument; the search is single-threaded here */

static int by_cost(const void *pa, const void *pb)
{
	const bk_cand *a = &sort_s->cand[*(const size_t *)pa], *b = &sort_s->cand[*(const size_t *)pb];
	if (a->cost != b->cost)
		return a->cost < b->cost ? -1 : 1;
	return better(a, b) ? -1 : better(b, a) ? 1 : 0;
}

size_t bk_search_front(const bk_search *s, size_t *idx, size_t max)
{
	size_t m = 0;
	for (size_t i = 0; i < s->n; i++)
		m += s->cand[i].status == BK_CAND_OK;
	size_t *all = malloc(sizeof(size_t) * (m ? m : 1));
	if (!all)
		return 0;
	m = 0;
	for (size_t i = 0; i < s->n; i++)
		if (s->cand[i].status == BK_CAND_OK)
			all[m++] = i;
	sort_s = s;
	qsort(all, m, sizeof *all, by_cost);
	size_t k = 0;
	double best = HUGE_VAL;
	for (size_t i = 0; i < m && k < max; i++)
		if (s->cand[all[i]].err < best) {
			best = s->cand[all[i]].err;
			idx[k++] = all[i];
		}
	free(all);
	return k;
}

/* ---- checkpoint ------------------------------------------------------------ */

static void put_tree(FILE *f, const bk_expr *e)
{
	fprintf(f, " %d", e->n);
	for (int i = 0; i < e->n; i++)
		fprintf(f, " %d:%d:%a", e->node[i].op, e->node[i].slot, e->node[i].k);
}

static int get_tree(FILE *f, bk_expr *e)
{
	if (fscanf(f, " %d", &e->n) != 1 || e->n < 0 || e->n > BK_EXPR_MAX)
		return -1;
	for (int i = 0; i < e->n; i++)
		if (fscanf(f, " %d:%d:%la", &e->node[i].op, &e->node[i].slot, &e->node[i].k) != 3 ||
		    !bk_expr_op_valid(e->node[i].op))
			return -1;
	return 0;
}

/* One text on a line of its own (forms hold no newline: the parser refuses none,
 * but the search never makes one; a seed with one is written with spaces). */
static void put_text(FILE *f, const char *t)
{
	for (; t && *t; t++)
		fputc(*t == '\n' || *t == '\r' ? ' ' : *t, f);
	fputc('\n', f);
}

static char *get_text(FILE *f)
{
	char *line = NULL;
	size_t cap = 0;
	ssize_t len = getline(&line, &cap, f);
	if (len <= 0) {
		free(line);
		return NULL;
	}
	if (line[len - 1] == '\n')
		line[len - 1] = '\0';
	return line;
}

/* One candidate: a line of numbers (exact: %a), its trees, then its texts on
 * lines of their own. The format of checkpoints and of migrants. */
static void put_cand(const bk_search *s, FILE *f, const bk_cand *c)
{
	fprintf(f, "c %ld %d %d %d %a %a %a %a %a", c->found_at, c->island, (int)c->status, c->np, c->cost, c->err,
	        c->rmse, c->max_abs, c->albedo_max_abs);
	for (int k = 0; k < BK_K_COUNT; k++)
		fprintf(f, " %d", c->ops.n[k]);
	fprintf(f, " %d %d", c->ops.simple, c->ops.complex);
	for (int j = 0; j < c->np; j++)
		fprintf(f, " %a", c->p[j]);
	put_tree(f, &c->tree[0]);
	put_tree(f, &c->tree[1]);
	int seed = -1;
	for (int k = 0; c->seed_name && k < s->o.nseeds; k++)
		if (c->seed_name == s->seed_name[k])
			seed = k;
	fprintf(f, " %d %d\n", seed, c->text_b != NULL);
	put_text(f, c->text);
	if (c->text_b)
		put_text(f, c->text_b);
}

/* Reads one candidate into c (its texts allocated). 0, or -1 if damaged. */
static int get_cand(const bk_search *s, FILE *f, bk_cand *c)
{
	memset(c, 0, sizeof *c);
	int status, seed, has_b;
	if (fscanf(f, " c %ld %d %d %d %la %la %la %la %la", &c->found_at, &c->island, &status, &c->np, &c->cost, &c->err,
	           &c->rmse, &c->max_abs, &c->albedo_max_abs) != 9 || c->np < 0 || c->np > BK_MAX_PARAMS || status < 0 ||
	    status > BK_CAND_FAILED || c->island < 0)
		return -1;
	c->status = (bk_cand_status)status;
	for (int k = 0; k < BK_K_COUNT; k++)
		if (fscanf(f, " %d", &c->ops.n[k]) != 1)
			return -1;
	if (fscanf(f, " %d %d", &c->ops.simple, &c->ops.complex) != 2)
		return -1;
	for (int j = 0; j < c->np; j++)
		if (fscanf(f, " %la", &c->p[j]) != 1)
			return -1;
	if (get_tree(f, &c->tree[0]) || get_tree(f, &c->tree[1]) || fscanf(f, " %d %d", &seed, &has_b) != 2 ||
	    seed >= s->o.nseeds || fgetc(f) != '\n')
		return -1;
	c->seed_name = seed >= 0 ? s->seed_name[seed] : NULL;
	c->text = get_text(f);
	c->text_b = has_b ? get_text(f) : NULL;
	if (!c->text || (has_b && !c->text_b)) {
		cand_free(c);
		return -1;
	}
	return 0;
}

int bk_search_save(const bk_search *s, FILE *f)
{
	fprintf(f, "%s\nfingerprint %016llx\nrng %016llx %016llx %016llx %016llx\n", CHECKPOINT_MAGIC,
	        (unsigned long long)s->fingerprint, (unsigned long long)s->rng.s[0], (unsigned long long)s->rng.s[1],
	        (unsigned long long)s->rng.s[2], (unsigned long long)s->rng.s[3]);
	fprintf(f, "state %ld %d %zu\nseen %zu\n", s->evals, s->phase, s->enum_pos, s->seen.n);
	for (size_t i = 0; i < s->seen.cap; i++)
		if (s->seen.h[i])
			fprintf(f, "%016llx\n", (unsigned long long)s->seen.h[i]);
	fprintf(f, "candidates %zu\n", s->n);
	for (size_t i = 0; i < s->n; i++)
		put_cand(s, f, &s->cand[i]);
	fputs("end\n", f);
	return ferror(f) ? -1 : 0;
}

int bk_search_load(bk_search *s, FILE *f, char *err, size_t errlen)
{
	char magic[64];
	unsigned long long fp, r[4];
	size_t nseen, ncand;
	if (!fgets(magic, sizeof magic, f) || strncmp(magic, CHECKPOINT_MAGIC, strlen(CHECKPOINT_MAGIC))) {
		snprintf(err, errlen, "not a brdfkit search checkpoint (of this version)");
		return -1;
	}
	if (fscanf(f, " fingerprint %llx rng %llx %llx %llx %llx state %ld %d %zu seen %zu", &fp, &r[0], &r[1], &r[2],
	           &r[3], &s->evals, &s->phase, &s->enum_pos, &nseen) != 9)
		goto bad;
	if (fp != s->fingerprint) {
		snprintf(err, errlen, "it was written by a search with other options or another target "
		                      "(only --evals, --seconds and --threads may change on resume)");
		return -1;
	}
	for (int k = 0; k < 4; k++)
		s->rng.s[k] = r[k];
	for (size_t i = 0; i < nseen; i++) {
		unsigned long long h;
		if (fscanf(f, " %llx", &h) != 1 || bk_hashset_add(&s->seen, h) < 0)
			goto bad;
	}
	if (fscanf(f, " candidates %zu", &ncand) != 1)
		goto bad;
	for (size_t i = 0; i < ncand; i++) {
		bk_cand c;
		if (get_cand(s, f, &c))
			goto bad;
		if (push(s, &c)) {
			cand_free(&c);
			goto bad;
		}
	}
	char end[8];
	if (fscanf(f, " %7s", end) != 1 || strcmp(end, "end"))
		goto bad;
	return 0;
bad:
	snprintf(err, errlen, "the checkpoint is damaged or cut short");
	return -1;
}

/* ---- migrants (islands) ---------------------------------------------------- */

int bk_search_export(const bk_search *s, const size_t *idx, size_t n, FILE *f)
{
	fprintf(f, "%s\nfingerprint %016llx\ncandidates %zu\n", MIGRANTS_MAGIC, (unsigned long long)s->fingerprint_all,
	        n);
	for (size_t i = 0; i < n; i++)
		put_cand(s, f, &s->cand[idx[i]]);
	fputs("end\n", f);
	return ferror(f) ? -1 : 0;
}

int bk_search_import(bk_search *s, FILE *f, size_t *added, char *err, size_t errlen)
{
	char magic[64];
	unsigned long long fp;
	size_t n;
	*added = 0;
	if (!fgets(magic, sizeof magic, f) || strncmp(magic, MIGRANTS_MAGIC, strlen(MIGRANTS_MAGIC)) ||
	    fscanf(f, " fingerprint %llx candidates %zu", &fp, &n) != 2)
		goto bad;
	if (fp != s->fingerprint_all) {
		snprintf(err, errlen, "migrants from a search with other options or another target");
		return -1;
	}
	for (size_t i = 0; i < n; i++) {
		bk_cand c;
		if (get_cand(s, f, &c))
			goto bad;
		/* the cache's key (prepare, the seeds): a candidate this island has
		 * already fitted or received is not taken twice */
		size_t la = strlen(c.text), lb = c.text_b ? strlen(c.text_b) : 0;
		char *key = malloc(la + lb + 2);
		int fresh = -1;
		if (key) {
			memcpy(key, c.text, la);
			key[la] = ';';
			memcpy(key + la + 1, c.text_b ? c.text_b : "", lb + 1);
			fresh = bk_hashset_add(&s->seen, bk_expr_hash_text(key));
			free(key);
		}
		if (fresh < 0 || (fresh > 0 && push(s, &c))) {
			cand_free(&c);
			snprintf(err, errlen, "out of memory taking migrants");
			return -1;
		}
		if (fresh == 0)
			cand_free(&c);
		else
			++*added;
	}
	char end[8];
	if (fscanf(f, " %7s", end) != 1 || strcmp(end, "end"))
		goto bad;
	return 0;
bad:
	snprintf(err, errlen, "the migrants are damaged or cut short");
	return -1;
}
