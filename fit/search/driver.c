/*
 * driver.c — the search's driver (fit/search.h): the options' defaults,
 * set-up, the step that wires the parts together (schedule -> screen ->
 * merge) and the one loop that drives it. The parts are in fit/search/
 * (search_int.h lists them).
 */
#include "search/archive.h"
#include "search/cand.h"
#include "search/schedule.h"
#include "search/screen.h"
#include "search/state.h"
#include "search/unique.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

/* ---- a step: schedule -> screen -> merge ---------------------------------- */

/* The batch's fits join the archive in candidate order (the same order for
 * any thread count), numbered as this island's fits: one at a time, as the
 * screening hands them on (screen.h). */
typedef struct merging {
	bk_search *s;
	bk_gen_batch *b;
	int rc;
} merging;

static void merge_one(void *ctx, size_t i)
{
	merging *m = ctx;
	bk_cand *c = &m->b->c[i];
	if (m->rc)
		return;
	c->found_at = ++m->s->evals;
	c->island = m->s->o.island;
	if (bk_archive_push(m->s, c)) {
		m->rc = -1;
		return;
	}
	c->text = c->text_b = NULL; /* the archive's now */
}

static void made(void *crew, size_t n)
{
	bk_screen_ready(crew, n);
}

int bk_search_step(bk_search *s, char *err, size_t errlen)
{
	if (s->stage >= s->nstages || s->evals >= s->o.evals)
		return 0;
	s->begun = 1;
	size_t want = bk_schedule_want(s), room = want ? want : 1;
	bk_gen_batch b = {calloc(room, sizeof *b.c), calloc(room, sizeof *b.start), calloc(room, sizeof *b.inherit),
	                  want, 0, NULL, NULL};
	int rc = !b.c || !b.start || !b.inherit ? -1 : 0;
	if (rc == 0) { /* generate -> screen -> merge, the fits starting as the candidates are made */
		bk_screen_crew crew;
		bk_screen_begin(&crew, s, b.c, b.start, room);
		b.made = made;
		b.made_ctx = &crew;
		rc = bk_schedule_make(s, &b);
		merging m = {s, &b, 0};
		bk_screen_end(&crew, rc == 0 ? b.n : 0, merge_one, &m);
		rc = rc ? rc : m.rc;
	}
	for (size_t i = 0; i < b.n; i++)
		bk_cand_free(&b.c[i]);
	free(b.c);
	free(b.start);
	free(b.inherit);
	if (rc < 0) {
		snprintf(err, errlen, "out of memory after %ld fits", s->evals);
		return -1;
	}
	return s->stage >= s->nstages || s->evals >= s->o.evals ? 0 : 1;
}

int bk_search_drive(bk_search *s, const bk_search_callbacks *cb, char *err, size_t errlen)
{
	static const bk_search_callbacks none = BK_SEARCH_CALLBACKS_INIT;
	if (!cb)
		cb = &none;
	long heard = s->evals; /* the fits when progress was last called */
	int rc;
	while ((rc = bk_search_step(s, err, errlen)) == 1) {
		if (cb->progress && s->evals - heard >= cb->progress_every) {
			cb->progress(cb->ctx, s);
			heard = s->evals;
		}
		if (cb->stop && cb->stop(cb->ctx, s)) {
			rc = 1;
			break;
		}
	}
	if (rc >= 0 && cb->progress)
		cb->progress(cb->ctx, s);
	return rc;
}

/* after_step as a stop callback (a function pointer does not convert to void *) */
typedef struct after_ctx {
	bk_search_after_step fn;
	void *ctx;
} after_ctx;

static int after_stop(void *ctx, const bk_search *s)
{
	const after_ctx *a = ctx;
	return a->fn(a->ctx, s);
}

int bk_search_run(bk_search *s, bk_search_after_step after_step, void *ctx, char *err, size_t errlen)
{
	after_ctx a = {after_step, ctx};
	bk_search_callbacks cb = {NULL, after_step ? after_stop : NULL, &a, 0};
	return bk_search_drive(s, &cb, err, errlen);
}

/* ---- set-up --------------------------------------------------------------- */

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
	s->feat_g = g; /* a shared feature leaves 6 parameters to A and B (bk_cand_text) */
	s->feat_g.max_params = g.max_params > 6 ? g.max_params - 6 : 0;
	if (s->o.shape == BK_SHAPE_PAIR && g.max_params > 1)
		g.max_params /= 2;
	s->tree_g = g;
	if (s->o.scale && g.max_params > 0) /* the enumerated tree leaves room for its scale */
		g.max_params--;
	s->enum_g = g;
	if (!(s->gen = bk_expr_enum_new(&g, o->enum_size, BK_SEARCH_ENUM_TREES)) || bk_unique_init(s) ||
	    bk_schedule_default(s))
		goto oom;
	s->fingerprint = bk_state_fingerprint(s, 1);
	s->fingerprint_all = bk_state_fingerprint(s, 0);
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
	bk_archive_free(s);
	bk_hashset_free(&s->seen);
	bk_hashset_free(&s->nb_done);
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
	bk_unique_free(s);
	bk_schedule_free(s);
	free(s);
}

long bk_search_evals(const bk_search *s) { return s->evals; }

void bk_search_certificate(const bk_search *s, bk_search_cert *c)
{
	memset(c, 0, sizeof *c);
	c->complete_size = s->enum_complete;
	c->max_cost = s->o.max_cost;
	c->starts = s->o.starts;
	c->island = s->o.island;
	c->islands = s->o.islands;
	c->dedup_seconds = s->dedup_seconds;
	for (int k = 0; k <= BK_EXPR_MAX; k++) {
		c->drawn[k] = s->enum_drawn[k];
		c->twins[k] = s->enum_twins[k];
		c->fitted[k] = s->enum_fitted[k];
	}
}
size_t bk_search_count(const bk_search *s) { return s->n; }
const bk_cand *bk_search_at(const bk_search *s, size_t i) { return i < s->n ? &s->cand[i] : NULL; }
