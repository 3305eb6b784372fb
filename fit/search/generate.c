/*
 * generate.c — the built-in generators (generate.h): seeds, enumeration,
 * neighbours, children by mutation and crossover, with inherited starts.
 */
#include "search/generate.h"
#include "search/cand.h"
#include "search/unique.h"
#include "brdf_ops.h" /* the opcode enum the trees are made of */

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Children a generation tries to make before it gives up finding new ones:
 * late in a run most children are duplicates of what was fitted. */
#define TRIES_PER_CHILD 30

/* ---- the seeds ------------------------------------------------------------ */

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

/* A lone parameter: the other half of an enumerated pair. */
static bk_expr lone_param(void)
{
	bk_expr e;
	memset(&e, 0, sizeof e);
	e.n = 1;
	e.node[0].op = BK_OP_PARAM;
	return e;
}

/* The seeds, in the order given (those already in the cache skipped). */
static int gen_seeds(bk_search *s, bk_gen_batch *b)
{
	for (int k = 0; k < s->o.nseeds; k++) {
		bk_cand *q = &b->c[b->n];
		memset(q, 0, sizeof *q);
		int fresh = bk_hashset_add(&s->seen, bk_cand_key(s->seed_text[k], s->seed_text_b[k]));
		if (fresh < 0)
			return -1;
		if (fresh == 0)
			continue;
		/* the seed's forms: the caller's when it gave them, else parsed, once */
		const char *ta = s->seed_text[k], *tb = s->seed_text_b[k];
		const bk_form *fa = s->seed_form[k], *fb = s->seed_form_b[k];
		if (fa && (!tb || fb) ? bk_cand_adopt(s, q, fa, fb, ta, tb) : bk_cand_parse(s, q, ta, tb))
			continue;
		q->text = strdup(s->seed_text[k]);
		q->text_b = s->seed_text_b[k] ? strdup(s->seed_text_b[k]) : NULL;
		q->seed_name = s->seed_name[k];
		b->n++;
		if (!q->text || (s->seed_text_b[k] && !q->text_b))
			return -1;
		bk_form_error fe;
		bk_expr qt[2] = {{0}, {0}};
		for (int h = 0; h < (s->o.shape == BK_SHAPE_PAIR ? 2 : 1); h++) {
			/* the search tree of a seed: its form read back; for F0, the part
			 * f0 multiplies, a form of its own (f0 made 1, a text's tokens
			 * replaced: the only seed text parsed twice) */
			const bk_form *f = h ? q->form_b : q->form;
			bk_form *own = NULL;
			if (s->o.shape == BK_SHAPE_F0) {
				char g[8192];
				without_f0(h ? tb : ta, g, sizeof g);
				f = own = bk_form_parse(g, &fe);
			}
			if (!f || bk_expr_from_form(f, &qt[h]) || bk_expr_canon_in(&qt[h], s->tree_g.inputs))
				qt[h] = lone_param();
			bk_form_free(own);
		}
		if (bk_cand_set_trees(q, qt, s->o.shape == BK_SHAPE_PAIR))
			return -1;
		b->start[b->n - 1] = s->seed_p ? s->seed_p[k] : NULL;
	}
	return 0;
}

/* ---- the enumeration ------------------------------------------------------ */

/* What an enumerated position's candidate is before anything that depends
 * on the order (prepare's checks of the cache and the twins): its text's
 * key, and once parsed within the budget its cost and fingerprint. Sent
 * between the ranks that split a search as bytes (one build, one job). */
typedef struct bk_enum_look {
	uint64_t key, fp;
	double cost;
	int32_t stage; /* 0 no text; 1 a text, not parsed or over the budget; 2 fingerprinted */
	int32_t pad;
} bk_enum_look;

static int prepare(bk_search *s, const bk_expr *t0, bk_cand *c, int size, const bk_enum_look *look);
static int look_ahead(bk_search *s, size_t pos, const bk_expr *tree);
#define DEDUP_SAMPLE 64

int bk_gen_enum_tree(bk_search *s, size_t idx, bk_expr *t)
{
	if (idx >= s->look_t0 && idx - s->look_t0 < s->look_nt) { /* drawn ahead (look_ahead) */
		*t = s->look_tree[idx - s->look_t0];
		return 1;
	}
	while (s->drawn <= idx && s->gen && s->drawn < (size_t)BK_SEARCH_ENUM_DRAWN) {
		int r = bk_expr_enum_next(s->gen, &s->cur);
		if (r < 0)
			return -1;
		if (r == 0) {
			s->enum_cut = bk_expr_enum_cut(s->gen);
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

/* The trees of position k's candidate, tree taken as its kind: alone; for
 * a pair (three positions a tree) (T, p), (p, T), and T as a shared feature
 * (its B empty). */
static void kind_trees(const bk_expr *tree, size_t k, size_t kinds, bk_expr *t)
{
	t[0] = *tree;
	t[1] = lone_param();
	if (k % kinds == 1) {
		t[1] = t[0];
		t[0] = lone_param();
	} else if (k % kinds == 2) {
		t[1].n = 0;
	}
}

/* The next trees of the enumeration, this island's share. 1 when it is
 * over, 0 when it has more, -1 when out of memory. */
static int gen_enum(bk_search *s, bk_gen_batch *b)
{
	/* at most enum_max fits (not a share of --evals: a resumed run with a
	 * larger budget must make the same candidates); the smallest trees come
	 * first, and a default grammar at 5 nodes holds tens of thousands */
	long cap = s->o.enum_max;
	size_t kinds = s->o.shape == BK_SHAPE_PAIR ? 3 : 1;
	bk_expr tree;
	int more = 1;
	while (b->n < b->want && s->evals + (long)b->n < cap &&
	       (more = bk_gen_enum_tree(s, s->enum_pos / kinds, &tree)) > 0) {
		size_t k = s->enum_pos++;
		int size = bk_expr_size(&tree);
		if (size - 1 > s->enum_complete) /* every tree of the sizes below is drawn */
			s->enum_complete = size - 1;
		if ((k / kinds) % (size_t)s->o.islands != (size_t)s->o.island)
			continue; /* another island's share of the enumeration */
		if (s->enum_leave_out && s->enum_leave_out(s->enum_leave_ctx, &tree))
			continue;
		s->enum_drawn[size]++;
		bk_expr t[2];
		kind_trees(&tree, k, kinds, t);
		if (k % kinds == 2 && bk_expr_nparams(&t[0]) > s->feat_g.max_params)
			continue;
		const bk_enum_look *look = NULL;
		if (s->o.split && s->o.split->size > 1 && !s->twin_audit) {
			if (!(k >= s->look_p0 && k - s->look_p0 < s->look_np) && look_ahead(s, k, &tree))
				return -1;
			look = &s->look[k - s->look_p0];
		}
		int r = prepare(s, t, &b->c[b->n], size, look);
		if (r < 0)
			return -1;
		b->n += (size_t)r;
	}
	if (more < 0)
		return -1;
	/* the enumeration ends with the step that draws its last tree, as it
	 * did when it was drawn whole up front (checkpoints name the next stage
	 * there) */
	if (more > 0 && s->evals + (long)b->n < cap && (more = bk_gen_enum_tree(s, s->enum_pos / kinds, &tree)) < 0)
		return -1;
	else if (more > 0 && s->evals + (long)b->n < cap && bk_expr_size(&tree) - 1 > s->enum_complete)
		s->enum_complete = bk_expr_size(&tree) - 1; /* the next tree is of a larger size */
	if (more == 0 && !s->enum_cut && s->drawn < (size_t)BK_SEARCH_ENUM_DRAWN) /* drawn whole */
		s->enum_complete = s->o.enum_size < s->enum_g.max_size ? s->o.enum_size : s->enum_g.max_size;
	if (more == 0 || s->evals + (long)b->n >= cap) {
		bk_expr_enum_free(s->gen); /* its trees are no longer needed */
		s->gen = NULL;
		return 1;
	}
	return 0;
}

/* ---- candidates from trees ------------------------------------------------ */

/* Linear scaling (Keijzer 2003; Operon and PySR's users do the same): the
 * tree g becomes p*g, its scale fitted with the other constants, so that a
 * shape is judged without its amplitude having to be found by mutation. A
 * tree that already has a free scale is unchanged by canonicalisation (p*p'
 * collapses to one parameter); the cost is one multiply at most. */
static int scaled(bk_expr *t, unsigned inputs)
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
	if (bk_expr_canon_in(&w, inputs))
		return -1;
	*t = w;
	return 0;
}

/* The trees prepare fits for t0: each with room for it scaled by a
 * parameter, where the search scales (a pair's shared feature is affine in
 * itself already). */
static void shaped(const bk_search *s, const bk_expr *t0, bk_expr *t)
{
	t[0] = t0[0];
	t[1] = t0[1];
	int feature = s->o.shape == BK_SHAPE_PAIR && t[1].n == 0;
	for (int h = 0; s->o.scale && !feature && h < (s->o.shape == BK_SHAPE_PAIR ? 2 : 1); h++) {
		bk_expr w = t[h];
		if (scaled(&w, s->tree_g.inputs) == 0 && bk_expr_nparams(&w) <= s->tree_g.max_params) /* room for the scale */
			t[h] = w;
	}
}

/* The fingerprint of c's forms, its CPU time measured (bench_enum) at one
 * call in DEDUP_SAMPLE: the thread's clock is a system call. */
static uint64_t fingerprint(bk_search *s, const bk_cand *c)
{
	struct timespec t0, t1;
	int timed = s->dedup_calls++ % DEDUP_SAMPLE == 0;
	if (timed)
		clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
	uint64_t fp = bk_unique_fingerprint_of(s, c->form, c->form_b);
	if (timed) {
		clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t1);
		s->dedup_seconds += DEDUP_SAMPLE * ((double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec));
	}
	return fp;
}

/* What look_ahead records of trees t: prepare's order-free part. */
static void look_at(bk_search *s, const bk_expr *t0, bk_enum_look *l)
{
	char a[4200], b[4200];
	bk_expr t[2];
	shaped(s, t0, t);
	memset(l, 0, sizeof *l);
	if (bk_cand_text(s, t, a, b, sizeof a))
		return;
	l->key = bk_cand_key(a, b);
	l->stage = 1;
	bk_cand c;
	memset(&c, 0, sizeof c);
	if (bk_cand_parse(s, &c, a, s->o.shape == BK_SHAPE_PAIR ? b : NULL))
		return;
	if (c.cost <= s->o.max_cost && c.np <= s->o.grammar.max_params) {
		l->cost = c.cost;
		l->fp = fingerprint(s, &c);
		l->stage = 2;
	}
	bk_cand_free_forms(&c);
}

/* The trees of the enumeration after tree (the one of position pos, taken
 * now) drawn ahead, LOOK_TREES in all at most, and the positions from pos
 * to their last looked at: this rank the i-th of them with i % size ==
 * rank, the others' by the split's share. Every rank calls it at the same
 * position (the enumeration's order is each one's), the share being
 * collective. 0, or -1 (out of memory, or the share failed: on every rank). */
#define LOOK_TREES 1024
static int look_ahead(bk_search *s, size_t pos, const bk_expr *tree)
{
	const bk_search_split *sp = s->o.split;
	size_t kinds = s->o.shape == BK_SHAPE_PAIR ? 3 : 1, t0 = pos / kinds, nt = 1;
	int r = 1;
	s->look_t0 = t0;
	s->look_nt = 0; /* the window being made: its trees come from the enumerator */
	s->look_np = 0;
	if (!s->look_tree && !(s->look_tree = malloc(LOOK_TREES * sizeof *s->look_tree)))
		r = -1;
	else
		s->look_tree[0] = *tree;
	while (r > 0 && nt < LOOK_TREES && (r = bk_gen_enum_tree(s, t0 + nt, &s->look_tree[nt])) > 0)
		nt++;
	size_t n = (t0 + nt) * kinds - pos;
	free(s->look);
	s->look = r < 0 ? NULL : calloc(n, sizeof *s->look);
	/* out of memory here: the share is still called (with NULL), so that it
	 * fails on every rank, not leave the others waiting */
	for (size_t i = (size_t)sp->rank; s->look && i < n; i += (size_t)sp->size) {
		size_t k = pos + i;
		bk_expr t[2];
		kind_trees(&s->look_tree[k / kinds - t0], k, kinds, t);
		look_at(s, t, &s->look[i]);
	}
	if (sp->share(sp->ctx, s->look, sizeof *s->look, n)) {
		s->share_failed = 1;
		return -1;
	}
	if (!s->look)
		return -1;
	s->look_nt = nt;
	s->look_p0 = pos;
	s->look_np = n;
	return 0;
}

/* Candidate c from trees t0 (bk_gen_prepare); with size >= 0, an
 * enumerated one of that size, left out when it is a twin of a model fitted
 * before at no greater cost (unique.h), and counted. With look (the split's
 * enumeration: look_ahead) what needs no order is read from it, not made. */
static int prepare(bk_search *s, const bk_expr *t0, bk_cand *c, int size, const bk_enum_look *look)
{
	char a[4200], b[4200];
	memset(c, 0, sizeof *c);
	bk_expr t[2];
	if (look) { /* in the order of the checks below */
		int fresh = look->stage ? bk_hashset_add(&s->seen, look->key) : 0;
		if (fresh <= 0 || look->stage < 2)
			return fresh < 0 ? -1 : 0;
		int twin = bk_unique_twin(s, look->fp, look->cost);
		if (twin)
			return twin < 0 ? -1 : (s->enum_twins[size]++, 0);
		/* a model to fit: its trees, text and forms made again (they were,
		 * on the rank that looked at it); failing now, only for want of memory */
		shaped(s, t0, t);
		if (bk_cand_text(s, t, a, b, sizeof a) || bk_cand_parse(s, c, a, s->o.shape == BK_SHAPE_PAIR ? b : NULL))
			return -1;
		s->enum_fitted[size]++;
		goto keep;
	}
	shaped(s, t0, t);
	if (bk_cand_text(s, t, a, b, sizeof a))
		return 0;
	int fresh = bk_hashset_add(&s->seen, bk_cand_key(a, b));
	if (fresh <= 0)
		return fresh;
	/* parsed once, for its cost, its fingerprint, its fit and the front's
	 * refit (the forms travel on c: cand.h): one tree's form, or a pair's A,
	 * B and whole f0*(A) + (B), whose cost it is (its fit is of A and B) */
	if (bk_cand_parse(s, c, a, s->o.shape == BK_SHAPE_PAIR ? b : NULL))
		return 0;
	if (c->cost > s->o.max_cost || c->np > s->o.grammar.max_params) {
		bk_cand_free_forms(c);
		return 0;
	}
	if (size >= 0) {
		uint64_t fp = fingerprint(s, c);
		int twin = bk_unique_twin(s, fp, c->cost);
		if (s->twin_audit && twin >= 0)
			s->twin_audit(s->twin_audit_ctx, a, s->o.shape == BK_SHAPE_PAIR ? b : NULL, fp, twin);
		if (twin) {
			bk_cand_free_forms(c);
			return twin < 0 ? -1 : (s->enum_twins[size]++, 0);
		}
		s->enum_fitted[size]++;
	}
keep:
	c->text = strdup(a);
	c->text_b = s->o.shape == BK_SHAPE_PAIR ? strdup(b) : NULL;
	if (!c->text || (s->o.shape == BK_SHAPE_PAIR && !c->text_b)) {
		bk_cand_free(c);
		return -1;
	}
	if (bk_cand_set_trees(c, t, s->o.shape == BK_SHAPE_PAIR)) {
		bk_cand_free(c);
		return -1;
	}
	return 1;
}

int bk_gen_prepare(bk_search *s, const bk_expr *t, bk_cand *c) { return prepare(s, t, c, -1, NULL); }

int bk_gen_take(bk_search *s, bk_gen_batch *b, const bk_expr *t, const double *start)
{
	int r = bk_gen_prepare(s, t, &b->c[b->n]);
	if (r <= 0)
		return r;
	if (start) { /* kept with the batch until it is fitted */
		for (int j = 0; j < BK_MAX_PARAMS; j++)
			b->inherit[b->n][j] = j < b->c[b->n].np ? start[j] : 1.0;
		b->start[b->n] = b->inherit[b->n];
	}
	b->n++;
	if (b->made)
		b->made(b->made_ctx, b->n);
	return 1;
}

/* ---- children ------------------------------------------------------------- */

/* Whether level L is on the front: its best beats every cheaper level's
 * (front_err: the least error of the levels below L, updated here). */
static int on_front(const bk_search *s, int L, double *front_err)
{
	double e = s->cand[s->lv[L].idx[0]].err;
	if (!(e < *front_err))
		return 0;
	*front_err = e;
	return 1;
}

/* The share of parents drawn from the front's levels; the rest from every
 * level uniformly. Measured on the recovery suite (bench_recovery, 20,000
 * fits) when it was chosen (the tree of 3457758; the coefficient JᵀJ since
 * gives 136 and 134), against every level uniformly (0): 0.75 recovered 136 and 135 of 153
 * runs at seeds 1-3 and 4-6 (0: 129 and 132) and 11 of 16 catalog forms at
 * every seed (0: 9); 0.5: 136 and 125; 0.25: 129 at seeds 1-3; two draws,
 * the cheaper level: 135 at 1-3. A level the front has passed (a cheaper one
 * does better) mostly breeds forms no better than its cheaper rivals. */
#define FRONT_PARENT_SHARE 0.75

/* A parent: a level (FRONT_PARENT_SHARE of the draws one of the front's, the
 * rest any, uniformly), then a member biased to the best of its level (u²
 * puts 1/√2 of the draws on the better half). */
static const bk_cand *pick(bk_search *s)
{
	uint32_t li = bk_rng_below(&s->rng, (uint32_t)s->nlv);
	if (bk_rng_unit(&s->rng) < FRONT_PARENT_SHARE) {
		int nf = 0;
		double fe = HUGE_VAL;
		for (int L = 0; L < s->nlv; L++)
			nf += on_front(s, L, &fe);
		if (nf > 0) { /* the k-th front level, in cost order */
			int k = (int)bk_rng_below(&s->rng, (uint32_t)nf);
			fe = HUGE_VAL;
			for (int L = 0; L < s->nlv; L++)
				if (on_front(s, L, &fe) && k-- == 0) {
					li = (uint32_t)L;
					break;
				}
		}
	}
	const bk_level *l = &s->lv[li];
	double u = bk_rng_unit(&s->rng);
	return &s->cand[l->idx[(int)(u * u * l->n)]];
}

/* Where parameter `slot` of tree h of trees t sits in the fitted text: pN is
 * slot N of tree 0, and tree 1's follow tree 0's (bk_cand_text). */
static int text_param(const bk_expr *t, int h, int slot)
{
	return (h ? bk_expr_nparams(&t[0]) : 0) + slot;
}

/* The trees of c to breed from: with --inherit, its fitted constants written
 * into its parameters' nodes as their start values (expr.h); a candidate that
 * did not fit passes on no values. */
static void parent_trees(const bk_search *s, const bk_cand *c, bk_expr *t)
{
	bk_cand_trees(c, t);
	for (int h = 0; s->o.inherit && h < 2; h++)
		for (int i = 0; i < t[h].n; i++) {
			bk_enode *n = &t[h].node[i];
			int j = text_param(t, h, n->slot);
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
	bk_expr t[2];
	bk_cand_trees(c, t);
	for (int h = 0; h < 2; h++)
		for (int i = 0; i < t[h].n; i++) {
			const bk_enode *n = &t[h].node[i];
			int j = text_param(t, h, n->slot);
			if (n->op == BK_OP_PARAM && n->k != 0 && j < BK_MAX_PARAMS)
				p[j] = n->k, known = 1;
		}
	return known;
}

/* The rates, set by hand when the search was written and not tuned since
 * (no measurement stands behind them yet): 0.7 of children by mutation; a
 * pair's crossover swaps a whole half a quarter of the time, so that a good
 * A and a good B found apart can meet. */
#define MUTATION_RATE 0.7
#define HALF_SWAP_RATE 0.25

int bk_gen_child(bk_search *s, bk_expr *t)
{
	const bk_grammar *g = &s->tree_g;
	const bk_cand *a = pick(s);
	int which = s->o.shape == BK_SHAPE_PAIR ? (int)bk_rng_below(&s->rng, 2) : 0;
	bk_expr pa[2], pb[2];
	parent_trees(s, a, pa);
	t[0] = pa[0];
	t[1] = pa[1];
	if (s->o.shape == BK_SHAPE_PAIR && a->ntree[1] == 0) { /* a shared feature: its one tree */
		g = &s->feat_g;
		which = 0;
		if (bk_rng_unit(&s->rng) < MUTATION_RATE)
			return bk_expr_mutate(g, &s->rng, &pa[0], &t[0]);
		const bk_cand *b = pick(s);
		parent_trees(s, b, pb);
		return bk_expr_crossover(g, &s->rng, &pa[0], &pb[bk_rng_below(&s->rng, b->ntree[1] ? 2 : 1)], &t[0]);
	}
	if (bk_rng_unit(&s->rng) < MUTATION_RATE)
		return bk_expr_mutate(g, &s->rng, &pa[which], &t[which]);
	const bk_cand *b = pick(s);
	parent_trees(s, b, pb);
	const bk_expr *donor = pb[which].n ? &pb[which] : &pb[0]; /* a feature pair has one tree */
	if (s->o.shape == BK_SHAPE_PAIR && bk_rng_unit(&s->rng) < HALF_SWAP_RATE) { /* swap a whole half */
		t[which] = *donor;
		return 0;
	}
	return bk_expr_crossover(g, &s->rng, &pa[which], donor, &t[which]);
}

/* The neighbours (expr.h) of the archive's leaders, as candidates
 * b->c[b->n..cap): p*x and p + x of each level's best, then for each front
 * level's best (a level is on the front when its best beats every cheaper
 * level's) its neighbours by one input (mix(p, p', in), x*in) and by a blend
 * (mix(u, v, x)). The cache makes each tried once, so a level whose best has
 * not changed gives none, and those left out by the cap come in the next
 * generation. A list tried whole is not made again (nb_done): every one of
 * its trees is then in the cache, or failed its text, and would again, so
 * making it again only finds nothing new: ~60 % of a generation's serial
 * time at 20,000 vf2d fits, and the same candidates (bench_speed's header).
 * 0, or -1 when out of memory. */
static int gen_neighbours(bk_search *s, bk_gen_batch *b, size_t cap)
{
	enum { MAXNB = 8 * BK_EXPR_MAX };
	bk_expr *nb = malloc(sizeof *nb * MAXNB);
	if (!nb)
		return -1;
	for (int pass = 0; pass < 3; pass++) {
		double front_err = HUGE_VAL;
		for (int L = 0; L < s->nlv && b->n < cap; L++) {
			size_t bi = s->lv[L].idx[0];
			const bk_cand *best = &s->cand[bi];
			if (pass > 0 && !on_front(s, L, &front_err))
				continue;
			uint64_t done = (uint64_t)bi * 3 + (uint64_t)pass + 1;
			if (bk_hashset_has(&s->nb_done, done))
				continue;
			bk_expr bt[2];
			bk_cand_trees(best, bt);
			int m = pass == 0   ? bk_expr_neighbours(&s->tree_g, &bt[0], nb, MAXNB)
			        : pass == 1 ? bk_expr_input_neighbours(&s->tree_g, &bt[0], nb, MAXNB)
			                    : bk_expr_mix_neighbours(&s->tree_g, &bt[0], nb, MAXNB);
			int j = 0;
			for (; j < m && b->n < cap; j++) {
				bk_expr t[2] = {nb[j], bt[1]};
				int r = bk_gen_prepare(s, t, &b->c[b->n]);
				if (r < 0) {
					free(nb);
					return -1;
				}
				b->n += (size_t)r;
				if (r && b->made)
					b->made(b->made_ctx, b->n);
			}
			if (j == m && bk_hashset_add(&s->nb_done, done) < 0) {
				free(nb);
				return -1;
			}
		}
	}
	free(nb);
	return 0;
}

/* Children filling the batch (after the neighbours: the schedule's
 * evolution stage), those with inherited constants starting from them. 1
 * when the batch is empty (nothing new can be made: the evolution is over),
 * 0 when not, -1 when out of memory. */
static int gen_children(bk_search *s, bk_gen_batch *b)
{
	if (s->nlv == 0)
		return 1;
	for (size_t tries = 0; b->n < b->want && tries < b->want * TRIES_PER_CHILD; tries++) {
		bk_expr t[2];
		if (bk_gen_child(s, t))
			continue;
		int r = bk_gen_prepare(s, t, &b->c[b->n]);
		if (r < 0)
			return -1;
		if (r > 0 && s->o.inherit && inherited(&b->c[b->n], b->inherit[b->n]))
			b->start[b->n] = b->inherit[b->n];
		b->n += (size_t)r;
		if (r && b->made)
			b->made(b->made_ctx, b->n);
	}
	return b->n == 0;
}

/* ---- the generators ------------------------------------------------------ */

/* The built-ins as bk_search_generator (generate.h): their state is the
 * search's own, their bodies above. */

static int seeds_make(void *st, bk_search *s, bk_search_sink *k)
{
	(void)st;
	return gen_seeds(s, k->b) < 0 ? -1 : 1;
}

static int enum_make(void *st, bk_search *s, bk_search_sink *k)
{
	(void)st;
	return gen_enum(s, k->b);
}

/* not for pairs, as the search has always had it (the neighbour lists are
 * of a candidate's first tree alone) */
static int neighbours_make(void *st, bk_search *s, bk_search_sink *k)
{
	(void)st;
	if (s->o.shape == BK_SHAPE_PAIR)
		return 1;
	return gen_neighbours(s, k->b, k->b->want) < 0 ? -1 : 1;
}

static int children_make(void *st, bk_search *s, bk_search_sink *k)
{
	(void)st;
	return gen_children(s, k->b);
}

/* The enumeration's state: the trees taken (x3 for a pair: as A, as B, as a
 * shared feature), on a line "position N"; then its counts, the size it has
 * completed and the twins' fingerprints (unique.h). */
static int enum_save(const void *st, const bk_search *s, FILE *f)
{
	(void)st;
	if (fprintf(f, "position %zu\n", s->enum_pos) < 0)
		return -1;
	bk_unique_save(s, f);
	return ferror(f) ? -1 : 0;
}

/* The position checked against what the enumeration holds: none taken
 * before its stage, no more than the most trees it draws, on a tree it has
 * (drawn again up to there); once over its trees are not needed. */
static int enum_load(void *st, bk_search *s, int when, FILE *f, char *err, size_t errlen)
{
	(void)st;
	if (fscanf(f, " position %zu", &s->enum_pos) != 1) {
		snprintf(err, errlen, "enumeration: no position line");
		return -1;
	}
	size_t kinds = s->o.shape == BK_SHAPE_PAIR ? 3 : 1;
	if (when < 0 && s->enum_pos) {
		snprintf(err, errlen, "enumeration position %zu before its stage", s->enum_pos);
		return -1;
	}
	if (s->enum_pos > kinds * (size_t)BK_SEARCH_ENUM_DRAWN) {
		snprintf(err, errlen, "enumeration position %zu past the most trees it draws", s->enum_pos);
		return -1;
	}
	bk_expr t;
	int have = s->enum_pos == 0 ? 1 : bk_gen_enum_tree(s, (s->enum_pos - 1) / kinds, &t);
	if (have <= 0) {
		if (have < 0)
			snprintf(err, errlen, "out of memory drawing the enumeration to its position");
		else
			snprintf(err, errlen, "enumeration position %zu past its end (%zu trees)", s->enum_pos, s->drawn);
		return -1;
	}
	if (when > 0) { /* the enumeration is over: its trees are not needed */
		bk_expr_enum_free(s->gen);
		s->gen = NULL;
	}
	return bk_unique_load(s, f, err, errlen);
}

const bk_search_generator bk_gen_seeds = {"seeds", 0, seeds_make, NULL, NULL, NULL, NULL};
const bk_search_generator bk_gen_enumeration = {"enumeration", 0, enum_make, enum_save, enum_load, NULL, NULL};
const bk_search_generator bk_gen_neighbours = {"neighbours", 0, neighbours_make, NULL, NULL, NULL, NULL};
const bk_search_generator bk_gen_children = {"children", 0, children_make, NULL, NULL, NULL, NULL};
