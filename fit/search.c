/*
 * search.c — the search for closed forms (search.h): seeds, bottom-up
 * enumeration, then generations of mutation and crossover over a MAP-Elites
 * archive on cost; every candidate fitted once, on threads, merged in order.
 */
#include "search.h"
#include "albfit.h"
#include "fit_int.h"
#include "search/starts.h"
#include "ir.h" /* the opcode enum the trees are made of */

#include <ctype.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdint.h>
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
#define CHECKPOINT_MAGIC "brdfkit-search-checkpoint 3"
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
	bk_grammar enum_g; /* the grammar of an enumerated tree (room for its scale) */
	bk_expr_enum *gen; /* the enumeration, drawn as the search goes; NULL once done */
	bk_expr cur;       /* the last tree drawn from it */
	size_t drawn;      /* how many were drawn */
};

double bk_search_error(const bk_search_options *o, const bk_samples *sm, const double *v, const bk_fit_metrics *m)
{
	/* the metrics leave out the samples where the values are not finite:
	 * over those alone an error is no error of the form (over none it reads
	 * 0, a perfect fit), so a form not finite somewhere has none */
	if (m->nonfinite)
		return HUGE_VAL;
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
	size_t len = strlen(a) + (b ? strlen(b) : 0) + 16; /* a seed may be as long as a form may */
	char *buf = malloc(len);
	if (!buf)
		return -1;
	if (b && *b)
		snprintf(buf, len, "f0*(%s) + (%s)", a, b);
	else
		snprintf(buf, len, "%s", a);
	bk_form_error fe;
	bk_form *f = bk_form_parse(buf, &fe);
	free(buf);
	if (!f)
		return -1;
	bk_form_count(f, ops);
	*cost = bk_ops_cost(ops, s->o.simple_cost, s->o.complex_cost);
	*np = bk_form_nparams(f);
	bk_form_free(f);
	return 0;
}

/* The cache's key of a candidate of texts a and b (NULL: none): the hash of
 * "a;b", in pieces (no buffer to outgrow). */
static uint64_t cand_key(const char *a, const char *b)
{
	uint64_t h = bk_hash_bytes(BK_HASH_INIT, a, strlen(a));
	h = bk_hash_bytes(h, ";", 1);
	return b ? bk_hash_bytes(h, b, strlen(b)) : h;
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

/* The starts: search/starts.h (ones, 0.1, then random ones from the seed and
 * the candidate's text, the same on any thread). */
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
		for (int j = 0; seed_p && j < BK_MAX_PARAMS; j++)
			p[j] = seed_p[j];
		if (!seed_p || k > 0)
			bk_search_start(s->o.seed, c->text, k - (seed_p != NULL), BK_MAX_PARAMS, p);
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
	/* one member per error in a level: equal errors at equal cost are
	 * mostly one model spelled twice (p*(p' + x) and p*x + p'), and a level
	 * full of them breeds one model */
	for (int j = 0; j < l->n; j++) {
		if (s->cand[l->idx[j]].err != c->err)
			continue;
		if (!better(c, &s->cand[l->idx[j]]))
			return 0;
		memmove(&l->idx[j], &l->idx[j + 1], sizeof(size_t) * (size_t)(l->n - j - 1));
		l->n--;
		break;
	}
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
	int fresh = bk_hashset_add(&s->seen, cand_key(a, b));
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

/* Tree idx of the enumeration (idx never below the last one drawn: the
 * enumeration is read in order). 1 with it in *t, 0 when it has fewer trees
 * (the enumerator is then freed), -1 when out of memory. */
static int enum_tree(bk_search *s, size_t idx, bk_expr *t)
{
	while (s->drawn <= idx && s->gen) {
		int r = bk_expr_enum_next(s->gen, &s->cur);
		if (r < 0)
			return -1;
		if (r == 0) {
			bk_expr_enum_free(s->gen);
			s->gen = NULL;
		} else {
			s->drawn++;
		}
	}
	if (s->drawn != idx + 1)
		return 0;
	*t = s->cur;
	return 1;
}

/* The neighbours (expr.h) of the archive's leaders, as candidates c[*n..want):
 * p*x and p + x of each level's best, mix(u, v, x) of each front level's.
 * 0, or -1 when out of memory. */
static int neighbours(bk_search *s, bk_cand *c, size_t *n, size_t want)
{
	enum { MAXNB = 8 * BK_EXPR_MAX };
	bk_expr *nb = malloc(sizeof *nb * MAXNB);
	if (!nb)
		return -1;
	double front_err = HUGE_VAL;
	for (int pass = 0; pass < 2; pass++)
		for (int L = 0; L < s->nlv && *n < want; L++) {
			const bk_cand *b = &s->cand[s->lv[L].idx[0]];
			if (pass == 1 && !(b->err < front_err))
				continue;
			front_err = pass == 1 ? b->err : front_err;
			int m = pass == 0 ? bk_expr_neighbours(&s->tree_g, &b->tree[0], nb, MAXNB)
			                  : bk_expr_mix_neighbours(&s->tree_g, &b->tree[0], nb, MAXNB);
			for (int j = 0; j < m && *n < want; j++) {
				bk_expr t[2] = {nb[j], b->tree[1]};
				int r = prepare(s, t, &c[*n]);
				if (r < 0) {
					free(nb);
					return -1;
				}
				*n += (size_t)r;
			}
		}
	free(nb);
	return 0;
}

int bk_search_step(bk_search *s, char *err, size_t errlen)
{
	if (s->phase == 3 || s->evals >= s->o.evals)
		return 0;
	/* whole generations, whatever the budget: a run stopped at a budget and
	 * resumed with a larger one must make the same batches as a run that
	 * never stopped (so a run may end up to generation - 1 fits past it) */
	size_t want = (size_t)s->o.generation;
	if (s->phase == 0 && want < (size_t)s->o.nseeds) /* every seed in the first step, however small the generation */
		want = (size_t)s->o.nseeds;
	bk_cand *c = calloc(want ? want : 1, sizeof *c);
	const double **sp = calloc(want ? want : 1, sizeof *sp);
	double (*start)[BK_MAX_PARAMS] = calloc(want ? want : 1, sizeof *start); /* children's inherited starts */
	size_t n = 0;
	int rc = 0;
	if (!c || !sp || !start)
		goto oom;
	if (s->phase == 0) { /* the seeds, in the order given */
		for (int k = 0; k < s->o.nseeds; k++) {
			bk_cand *q = &c[n];
			memset(q, 0, sizeof *q);
			int fresh = bk_hashset_add(&s->seen, cand_key(s->seed_text[k], s->seed_text_b[k]));
			if (fresh < 0)
				goto oom;
			if (fresh == 0)
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
		bk_expr tree;
		int more = 1;
		while (n < want && s->evals + (long)n < cap && (more = enum_tree(s, s->enum_pos / kinds, &tree)) > 0) {
			size_t k = s->enum_pos++;
			if ((k / kinds) % (size_t)s->o.islands != (size_t)s->o.island)
				continue; /* another island's share of the enumeration */
			bk_expr t[2] = {tree, lone_param()};
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
		if (more < 0)
			goto oom;
		/* the enumeration ends with the step that draws its last tree, as it
		 * did when it was drawn whole up front (checkpoints say phase 2 there) */
		if (more > 0 && s->evals + (long)n < cap && (more = enum_tree(s, s->enum_pos / kinds, &tree)) < 0)
			goto oom;
		if (more == 0 || s->evals + (long)n >= cap) {
			s->phase = 2;
			bk_expr_enum_free(s->gen); /* its trees are no longer needed */
			s->gen = NULL;
		}
	} else { /* evolution */
		if (s->nlv == 0) {
			s->phase = 3;
			goto out;
		}
		/* first the neighbours of each level's best by one free constant,
		 * then the blends of the front's levels' best (expr.h; a level is on
		 * the front when its best beats every cheaper level's); the cache
		 * makes each tried once, so a level whose best has not changed
		 * gives none */
		if (s->o.shape != BK_SHAPE_PAIR && (rc = neighbours(s, c, &n, want)) < 0)
			goto oom;
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

/* A copy of form text t on one line (a newline is white space to the parser;
 * a checkpoint keeps a text a line): what the search fits and writes. */
static char *one_line(const char *t)
{
	char *c = strdup(t);
	for (char *p = c; p && *p; p++)
		if (*p == '\n' || *p == '\r')
			*p = ' ';
	return c;
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
		s->seed_text[k] = one_line(o->seeds[k]);
		s->seed_text_b[k] = o->seeds_b && o->seeds_b[k] ? one_line(o->seeds_b[k]) : NULL;
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
	bk_grammar g = o->grammar;
	s->feat_g = g; /* a shared feature leaves 6 parameters to A and B (shape_text) */
	s->feat_g.max_params = g.max_params > 6 ? g.max_params - 6 : 0;
	if (s->o.shape == BK_SHAPE_PAIR && g.max_params > 1)
		g.max_params /= 2;
	s->tree_g = g;
	if (s->o.scale && g.max_params > 0) /* the enumerated tree leaves room for its scale */
		g.max_params--;
	s->enum_g = g;
	if (!(s->gen = bk_expr_enum_new(&g, o->enum_size, BK_SEARCH_ENUM_TREES)))
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
	bk_expr_enum_free(s->gen);
	free(s);
}

int bk_search_run(bk_search *s, bk_search_after_step after_step, void *ctx, char *err, size_t errlen)
{
	int rc;
	while ((rc = bk_search_step(s, err, errlen)) == 1)
		if (after_step && after_step(ctx, s))
			return 1;
	return rc;
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

/* The checkpoint and migrant formats (CHECKPOINT_MAGIC, MIGRANTS_MAGIC): lines
 * of text, numbers exact (%a), each candidate a line of numbers and its trees
 * followed by its texts on lines of their own. A checkpoint ends with the
 * line "checksum H": H the 64-bit FNV-1a (bk_hash_bytes) of every byte before
 * it, so that a flipped digit is found before it changes a result. Whatever
 * is read is checked field by field against what a search with these
 * options can hold (check_cand, check_state) before anything uses it: a
 * damaged file is refused with what is wrong, never followed. */

/* The first problem found while reading; the reading goes on harmlessly. */
typedef struct reader {
	FILE *f;
	char *err;
	size_t errlen;
	int bad;
} reader;

static int fail(reader *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int fail(reader *r, const char *fmt, ...)
{
	if (!r->bad) {
		va_list ap;
		va_start(ap, fmt);
		vsnprintf(r->err, r->errlen, fmt, ap);
		va_end(ap);
	}
	r->bad = 1;
	return -1;
}

static void put_tree(FILE *f, const bk_expr *e)
{
	fprintf(f, " %d", e->n);
	for (int i = 0; i < e->n; i++)
		fprintf(f, " %d:%d:%a", e->node[i].op, e->node[i].slot, e->node[i].k);
}

static int get_tree(reader *r, bk_expr *e, int empty_ok, const char *what)
{
	char why[128];
	if (fscanf(r->f, " %d", &e->n) != 1 || e->n < 0 || e->n > BK_EXPR_MAX)
		return fail(r, "%s: no node count from 0 to %d", what, BK_EXPR_MAX);
	for (int i = 0; i < e->n; i++)
		if (fscanf(r->f, " %d:%d:%la", &e->node[i].op, &e->node[i].slot, &e->node[i].k) != 3)
			return fail(r, "%s: node %d unreadable", what, i);
	if (e->n == 0 && empty_ok)
		return 0;
	if (bk_expr_valid(e, why, sizeof why))
		return fail(r, "%s: %s", what, why);
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

/* A line of at most BK_FORM_MAX_LEN characters, malloc'd; NULL if longer,
 * empty or absent. */
static char *get_text(reader *r, const char *what)
{
	char *line = malloc(BK_FORM_MAX_LEN + 2);
	if (!line) {
		fail(r, "out of memory");
		return NULL;
	}
	if (!fgets(line, BK_FORM_MAX_LEN + 2, r->f) || !strchr(line, '\n') || line[0] == '\n') {
		free(line);
		fail(r, "%s: no text of 1 to %d characters on a line of its own", what, BK_FORM_MAX_LEN);
		return NULL;
	}
	line[strcspn(line, "\n")] = '\0';
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

static int nonneg_or_nan(double x) { return isnan(x) || x >= 0; }

/* What a candidate of this search can be (what): its texts those of its
 * seed, or the shape's text of its trees; its cost, operations and
 * parameters those of its texts; its error a rounded number >= 0 when it is
 * OK, +inf when not; its island one of the run's. 0, or -1 (why). */
static int check_cand(const bk_search *s, const bk_cand *c, int seed, reader *r, const char *what)
{
	int pair = s->o.shape == BK_SHAPE_PAIR;
	if (c->found_at < 1 || c->island < 0 || c->island >= s->o.islands)
		return fail(r, "%s: found at fit %ld of island %d (of %d)", what, c->found_at, c->island, s->o.islands);
	if (!pair && c->tree[1].n != 0)
		return fail(r, "%s: a second tree, and the candidates of this search have one", what);
	if ((c->text_b != NULL) != pair)
		return fail(r, "%s: %s text B", what, pair ? "no" : "a");
	if (seed >= 0) {
		const char *b = s->seed_text_b[seed];
		if (strcmp(c->text, s->seed_text[seed]) || (b && strcmp(c->text_b, b)))
			return fail(r, "%s: not the text of seed %d", what, seed + 1);
	} else {
		char a[4200], b[4200];
		if (shape_text(s, c->tree, a, b, sizeof a) || strcmp(a, c->text) || (pair && strcmp(b, c->text_b)))
			return fail(r, "%s: its text is not that of its trees", what);
	}
	bk_ops ops;
	double cost;
	int np;
	if (cost_of(s, c->text, c->text_b, &ops, &cost, &np))
		return fail(r, "%s: its text is not a form", what);
	if (memcmp(&ops, &c->ops, sizeof ops) || cost != c->cost || np != c->np)
		return fail(r, "%s: cost %g or %d parameters, and its text has cost %g and %d", what, c->cost, c->np, cost,
		            np);
	if (seed < 0 && (c->cost > s->o.max_cost || c->np > s->o.grammar.max_params))
		return fail(r, "%s: over --max-cost or --max-params", what);
	if (c->status == BK_CAND_OK ? !(isfinite(c->err) && c->err >= 0 && c->err == bk_search_round_err(c->err) &&
	                                isfinite(c->rmse) && c->rmse >= 0 && isfinite(c->max_abs) && c->max_abs >= 0 &&
	                                nonneg_or_nan(c->albedo_max_abs))
	                            : !(c->err == HUGE_VAL && nonneg_or_nan(c->rmse) && nonneg_or_nan(c->max_abs) &&
	                                nonneg_or_nan(c->albedo_max_abs)))
		return fail(r, "%s: status %d with error %a (rmse %a, max %a)", what, (int)c->status, c->err, c->rmse,
		            c->max_abs);
	return 0;
}

/* Reads one candidate into c (its texts allocated) and checks it. 0, or -1
 * (why in r). */
static int get_cand(const bk_search *s, reader *r, bk_cand *c, size_t i)
{
	char what[48];
	snprintf(what, sizeof what, "candidate %zu", i + 1);
	memset(c, 0, sizeof *c);
	int status, seed, has_b;
	FILE *f = r->f;
	if (fscanf(f, " c %ld %d %d %d %la %la %la %la %la", &c->found_at, &c->island, &status, &c->np, &c->cost, &c->err,
	           &c->rmse, &c->max_abs, &c->albedo_max_abs) != 9)
		return fail(r, "%s: its first numbers are unreadable", what);
	if (c->np < 0 || c->np > BK_MAX_PARAMS || status < 0 || status > BK_CAND_FAILED)
		return fail(r, "%s: %d parameters (0 to %d), status %d (0 to %d)", what, c->np, BK_MAX_PARAMS, status,
		            BK_CAND_FAILED);
	c->status = (bk_cand_status)status;
	for (int k = 0; k < BK_K_COUNT; k++)
		if (fscanf(f, " %d", &c->ops.n[k]) != 1)
			return fail(r, "%s: operation counts unreadable", what);
	if (fscanf(f, " %d %d", &c->ops.simple, &c->ops.complex) != 2)
		return fail(r, "%s: operation counts unreadable", what);
	for (int j = 0; j < c->np; j++)
		if (fscanf(f, " %la", &c->p[j]) != 1)
			return fail(r, "%s: parameter %d unreadable", what, j);
	char tw[64];
	snprintf(tw, sizeof tw, "%s: tree 1", what);
	if (get_tree(r, &c->tree[0], 0, tw))
		return -1;
	snprintf(tw, sizeof tw, "%s: tree 2", what);
	if (get_tree(r, &c->tree[1], 1, tw))
		return -1;
	if (fscanf(f, " %d %d", &seed, &has_b) != 2 || seed < -1 || seed >= s->o.nseeds || has_b < 0 || has_b > 1 ||
	    fgetc(f) != '\n')
		return fail(r, "%s: seed (-1 to %d) or text count unreadable", what, s->o.nseeds - 1);
	c->seed_name = seed >= 0 ? s->seed_name[seed] : NULL;
	c->text = get_text(r, what);
	c->text_b = c->text && has_b ? get_text(r, what) : NULL;
	if (!c->text || (has_b && !c->text_b) || check_cand(s, c, seed, r, what)) {
		cand_free(c);
		return -1;
	}
	return 0;
}

int bk_search_save(const bk_search *s, FILE *f)
{
	char *body = NULL;
	size_t len = 0;
	FILE *m = open_memstream(&body, &len);
	if (!m)
		return -1;
	fprintf(m, "%s\nfingerprint %016llx\nrng %016llx %016llx %016llx %016llx\n", CHECKPOINT_MAGIC,
	        (unsigned long long)s->fingerprint, (unsigned long long)s->rng.s[0], (unsigned long long)s->rng.s[1],
	        (unsigned long long)s->rng.s[2], (unsigned long long)s->rng.s[3]);
	fprintf(m, "state %ld %d %zu\nbudget %ld\nseen %zu\n", s->evals, s->phase, s->enum_pos, s->o.evals, s->seen.n);
	for (size_t i = 0; i < s->seen.cap; i++)
		if (s->seen.h[i])
			fprintf(m, "%016llx\n", (unsigned long long)s->seen.h[i]);
	fprintf(m, "candidates %zu\n", s->n);
	for (size_t i = 0; i < s->n; i++)
		put_cand(s, m, &s->cand[i]);
	fputs("end\n", m);
	int bad = ferror(m);
	if (fclose(m) || bad) {
		free(body);
		return -1;
	}
	fwrite(body, 1, len, f);
	fprintf(f, "checksum %016llx\n", (unsigned long long)bk_hash_bytes(BK_HASH_INIT, body, len));
	free(body);
	return ferror(f) ? -1 : 0;
}

/* The rest of f, whole (malloc'd, NUL-terminated). NULL when out of memory. */
static char *slurp(FILE *f, size_t *len)
{
	size_t cap = 1 << 16, n = 0;
	char *buf = malloc(cap);
	while (buf) {
		n += fread(buf + n, 1, cap - n - 1, f);
		if (n < cap - 1)
			break;
		char *t = cap < SIZE_MAX / 2 ? realloc(buf, cap * 2) : NULL;
		if (!t)
			free(buf);
		buf = t;
		cap *= 2;
	}
	if (buf)
		buf[n] = '\0';
	*len = n;
	return buf;
}

/* The body of a checkpoint text (its length in *len) once its last line is a
 * checksum that matches it; -1 (why) if not. */
static int checked_body(const char *text, size_t *len, reader *r)
{
	size_t n = *len;
	if (n == 0 || text[n - 1] != '\n')
		return fail(r, "it ends in the middle of a line: cut short");
	size_t last = n - 1;
	while (last > 0 && text[last - 1] != '\n')
		last--;
	char want[32];
	int k = snprintf(want, sizeof want, "checksum %016llx\n", (unsigned long long)bk_hash_bytes(BK_HASH_INIT, text, last));
	if (strncmp(text + last, "checksum ", 9))
		return fail(r, "no checksum line at its end: cut short or not written by this version");
	if (n - last != (size_t)k || memcmp(text + last, want, (size_t)k))
		return fail(r, "its checksum does not match: the file was changed or damaged after it was written");
	*len = last;
	return 0;
}

/* Each of the search's own fits once, numbered 1.. in order, and nothing of
 * its own island besides (candidates taken from other islands keep theirs);
 * every candidate's key in the cache, none twice. */
static int check_found(const bk_search *s, reader *r)
{
	long own = 0;
	bk_hashset keys = {0};
	int rc = 0;
	for (size_t i = 0; i < s->n && !rc; i++) {
		const bk_cand *c = &s->cand[i];
		if (c->island == s->o.island && c->found_at != ++own)
			rc = fail(r, "candidate %zu: found at fit %ld, and it is fit %ld of this island", i + 1, c->found_at, own);
		uint64_t h = cand_key(c->text, c->text_b);
		int fresh = bk_hashset_add(&keys, h);
		if (!rc && fresh <= 0)
			rc = fail(r, fresh < 0 ? "out of memory" : "candidate %zu: the same as an earlier one", i + 1);
		if (!rc && !bk_hashset_has(&s->seen, h))
			rc = fail(r, "candidate %zu: not in the cache of texts tried", i + 1);
	}
	if (!rc && own != s->evals)
		rc = fail(r, "%ld fits of this island listed, and the state says %ld", own, s->evals);
	bk_hashset_free(&keys);
	return rc;
}

/* The state line against the options: a phase, fits within the budget the
 * checkpoint's run had (it ends after the generation that reaches it), the
 * enumeration's position on a tree it has (the enumeration drawn again up
 * to there), a generator that is not stuck at zero. */
static int check_state(bk_search *s, long budget, reader *r)
{
	long step = s->o.generation > s->o.nseeds ? s->o.generation : s->o.nseeds; /* the most fits of one step */
	if (s->phase < 0 || s->phase > 3)
		return fail(r, "phase %d (0 to 3)", s->phase);
	if (budget < 1 || s->evals < 0 || s->evals > budget + step - 1)
		return fail(r, "%ld fits for a budget of %ld (one step is at most %ld)", s->evals, budget, step);
	if (s->phase == 0 && (s->evals || s->n || s->enum_pos))
		return fail(r, "phase 0 (the seeds) after %ld fits", s->evals);
	if (!(s->rng.s[0] | s->rng.s[1] | s->rng.s[2] | s->rng.s[3]))
		return fail(r, "a generator state of zeros");
	size_t kinds = s->o.shape == BK_SHAPE_PAIR ? 3 : 1;
	if (s->enum_pos > kinds * (size_t)BK_SEARCH_ENUM_TREES)
		return fail(r, "enumeration position %zu past the most trees it draws", s->enum_pos);
	bk_expr t;
	int have = s->enum_pos == 0 ? 1 : enum_tree(s, (s->enum_pos - 1) / kinds, &t);
	if (have < 0)
		return fail(r, "out of memory drawing the enumeration to its position");
	if (!have)
		return fail(r, "enumeration position %zu past its end (%zu trees)", s->enum_pos, s->drawn);
	if (s->phase >= 2) { /* the enumeration is over: its trees are not needed */
		bk_expr_enum_free(s->gen);
		s->gen = NULL;
	}
	return 0;
}

/* Reads the body of a checkpoint (checksum checked) into s. */
static int load_body(bk_search *s, reader *r, long *budget)
{
	char magic[64];
	unsigned long long fp, g[4];
	size_t nseen, ncand;
	FILE *f = r->f;
	if (!fgets(magic, sizeof magic, f) || strcmp(magic, CHECKPOINT_MAGIC "\n"))
		return fail(r, "not a brdfkit search checkpoint (of this version)");
	if (fscanf(f, " fingerprint %llx", &fp) != 1)
		return fail(r, "no fingerprint line");
	if (fp != s->fingerprint)
		return fail(r, "it was written by a search with other options or another target "
		               "(only --evals, --seconds and --threads may change on resume)");
	if (fscanf(f, " rng %llx %llx %llx %llx", &g[0], &g[1], &g[2], &g[3]) != 4)
		return fail(r, "no generator line");
	for (int k = 0; k < 4; k++)
		s->rng.s[k] = g[k];
	if (fscanf(f, " state %ld %d %zu budget %ld seen %zu", &s->evals, &s->phase, &s->enum_pos, budget, &nseen) != 5)
		return fail(r, "no state, budget or cache line");
	for (size_t i = 0; i < nseen; i++) {
		unsigned long long h;
		int fresh = fscanf(f, " %16llx", &h) != 1 || h == 0 ? -2 : bk_hashset_add(&s->seen, h);
		if (fresh <= 0)
			return fail(r, fresh == -1 ? "out of memory" : "cache entry %zu of %zu unreadable or repeated", i + 1,
			            nseen);
	}
	if (fscanf(f, " candidates %zu", &ncand) != 1)
		return fail(r, "no candidates line after the %zu cache entries", nseen);
	for (size_t i = 0; i < ncand; i++) {
		bk_cand c;
		if (get_cand(s, r, &c, i))
			return -1;
		if (push(s, &c)) {
			cand_free(&c);
			return fail(r, "out of memory");
		}
	}
	char end[8];
	if (fscanf(f, " %7s", end) != 1 || strcmp(end, "end") || fgetc(f) != '\n' || fgetc(f) != EOF)
		return fail(r, "no end line after the %zu candidates", ncand);
	return check_state(s, *budget, r) || check_found(s, r) ? -1 : 0;
}

int bk_search_load(bk_search *s, FILE *f, char *err, size_t errlen)
{
	reader r = {NULL, err, errlen, 0};
	if (s->evals || s->n || s->seen.n) {
		fail(&r, "a checkpoint is loaded into a new search only");
		return -1;
	}
	size_t len;
	char *text = slurp(f, &len);
	if (!text) {
		fail(&r, "out of memory reading it");
		return -1;
	}
	long budget = 0;
	int rc = -1;
	if (checked_body(text, &len, &r) == 0 && (r.f = fmemopen(text, len, "r")) != NULL) {
		rc = load_body(s, &r, &budget);
		fclose(r.f);
	} else if (!r.bad) {
		fail(&r, "out of memory reading it");
	}
	free(text);
	/* a budget below the fits done and below the budget the checkpoint's
	 * run had: its candidates are more than this budget can make */
	if (rc == 0 && s->o.evals < s->evals && s->o.evals < budget)
		rc = fail(&r, "it holds %ld fits, more than --evals %ld (its run had --evals %ld)", s->evals, s->o.evals,
		          budget);
	return rc;
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
	reader r = {f, err, errlen, 0};
	*added = 0;
	if (!fgets(magic, sizeof magic, f) || strcmp(magic, MIGRANTS_MAGIC "\n") ||
	    fscanf(f, " fingerprint %llx candidates %zu", &fp, &n) != 2) {
		fail(&r, "the migrants are damaged or cut short: no header");
		return -1;
	}
	if (fp != s->fingerprint_all) {
		fail(&r, "migrants from a search with other options or another target");
		return -1;
	}
	for (size_t i = 0; i < n; i++) {
		bk_cand c;
		if (get_cand(s, &r, &c, i)) {
			char why[400];
			snprintf(why, sizeof why, "%s", err);
			snprintf(err, errlen, "the migrants are damaged: %s", why);
			return -1;
		}
		/* the cache's key (prepare, the seeds): a candidate this island has
		 * already fitted or received is not taken twice */
		int fresh = bk_hashset_add(&s->seen, cand_key(c.text, c.text_b));
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
	if (fscanf(f, " %7s", end) != 1 || strcmp(end, "end")) {
		snprintf(err, errlen, "the migrants are damaged or cut short: no end line");
		return -1;
	}
	return 0;
}
