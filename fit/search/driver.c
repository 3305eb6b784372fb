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
	o->seed_forms = o->seed_forms_b = NULL;
	o->seed_p = NULL;
	o->nseeds = 0;
	o->exempt_seeds = INT_MAX;
	o->island = 0;
	o->islands = 1;
	o->semantic = BK_SEARCH_SEMANTIC;
	o->split = NULL;
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
	c->text = c->text_b = NULL; /* the archive's now, and its trees and forms */
	c->tree = NULL;
	c->form = c->form_b = c->form_pair = NULL;
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
		if (bk_screen_end(&crew, rc == 0 ? b.n : 0, merge_one, &m))
			s->share_failed = 1;
		rc = rc ? rc : s->share_failed ? -1 : m.rc;
	}
	for (size_t i = 0; i < b.n; i++)
		bk_cand_free(&b.c[i]);
	free(b.c);
	free(b.start);
	free(b.inherit);
	if (rc < 0 && s->share_failed) {
		snprintf(err, errlen, "sharing a step's work among the %d ranks failed after %ld fits", s->o.split->size,
		         s->evals);
		return -1;
	}
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

/* The caller's form of a seed whose text (one line) is text, copied into
 * *out; NULL there when none is given or its text is another (the seed is
 * then parsed where it is made, generate.c). 0, or -1 out of memory. */
static int seed_form_of(const bk_form *const *forms, int k, const char *text, bk_form **out)
{
	*out = NULL;
	if (!forms || !forms[k] || strcmp(bk_form_text(forms[k]), text))
		return 0;
	return (*out = bk_form_dup(forms[k])) ? 0 : -1;
}

/* "name: must be ..., got ..." into why, and 0 */
#define BAD(...) (snprintf(why, len, __VA_ARGS__), 0)

int bk_search_options_valid(const bk_search_options *o, char *why, size_t len)
{
	if (!o)
		return BAD("options are NULL");
	if (!o->screen || o->screen->n == 0)
		return BAD("screen: no screening samples (bk_target_build)");
	if (o->shape != BK_SHAPE_PLAIN && o->shape != BK_SHAPE_F0 && o->shape != BK_SHAPE_PAIR)
		return BAD("shape: must be BK_SHAPE_PLAIN, F0 or PAIR, got %d", (int)o->shape);
	if (o->objective != BK_OBJ_RMSE && o->objective != BK_OBJ_MAX && o->objective != BK_OBJ_ALBEDO)
		return BAD("objective: must be BK_OBJ_RMSE, MAX or ALBEDO, got %d", (int)o->objective);
	if (o->precision != BK_F64 && o->precision != BK_F32 && o->precision != BK_F16)
		return BAD("precision: must be BK_F64, F32 or F16, got %d", (int)o->precision);
	if (o->grammar.max_params < 0 || o->grammar.max_params > BK_MAX_PARAMS)
		return BAD("grammar.max_params: must be in 0..%d, got %d", BK_MAX_PARAMS, o->grammar.max_params);
	if (o->grammar.max_size < 1 || o->grammar.max_size > BK_EXPR_MAX)
		return BAD("grammar.max_size: must be in 1..%d, got %d", BK_EXPR_MAX, o->grammar.max_size);
	if (o->grammar.nconsts < 0 || o->grammar.nconsts > 8)
		return BAD("grammar.nconsts: must be in 0..8, got %d", o->grammar.nconsts);
	for (int k = 0; k < o->grammar.nconsts; k++)
		if (!isfinite(o->grammar.consts[k]))
			return BAD("grammar.consts[%d]: must be finite, got %g", k, o->grammar.consts[k]);
	if (o->grammar.inputs >> BK_IN_COUNT)
		return BAD("grammar.inputs: bits past the %d inputs (0x%x)", BK_IN_COUNT, o->grammar.inputs);
	if (!(o->max_cost > 0))
		return BAD("max_cost: must be > 0 (HUGE_VAL: no limit), got %g", o->max_cost);
	if (!(o->simple_cost >= 0) || !(o->complex_cost >= 0) || !isfinite(o->simple_cost) ||
	    !isfinite(o->complex_cost) || o->simple_cost + o->complex_cost <= 0)
		return BAD("simple_cost, complex_cost: must be finite, >= 0 and not both 0, got %g and %g", o->simple_cost,
		           o->complex_cost);
	if (o->evals < 1)
		return BAD("evals: must be >= 1, got %ld", o->evals);
	if (o->threads < 1 || o->threads > 64)
		return BAD("threads: must be in 1..64, got %d", o->threads);
	if (o->enum_size < 0 || o->enum_size > BK_EXPR_MAX)
		return BAD("enum_size: must be in 0..%d, got %d", BK_EXPR_MAX, o->enum_size);
	if (o->enum_max < 0)
		return BAD("enum_max: must be >= 0, got %ld", o->enum_max);
	if (o->generation < 1)
		return BAD("generation: must be >= 1, got %d", o->generation);
	if (o->per_level < 1)
		return BAD("per_level: must be >= 1, got %d", o->per_level);
	if (o->starts < 1 || o->starts > 4)
		return BAD("starts: must be in 1..4, got %d", o->starts);
	if (o->nseeds < 0 || (o->nseeds > 0 && !o->seeds))
		return BAD("nseeds: %d seeds and %s", o->nseeds, o->seeds ? "a negative count" : "no seeds array");
	for (int k = 0; k < o->nseeds; k++)
		if (!o->seeds[k])
			return BAD("seeds[%d]: NULL", k);
	if (o->islands < 1 || o->island < 0 || o->island >= o->islands)
		return BAD("island, islands: must be 0 <= island < islands, got %d of %d", o->island, o->islands);
	if (o->split && (o->split->size < 1 || o->split->rank < 0 || o->split->rank >= o->split->size ||
	                 !o->split->share))
		return BAD("split: must have 0 <= rank < size and a share function, got rank %d of %d%s", o->split->rank,
		           o->split->size, o->split->share ? "" : ", no share");
	if (o->split && o->split->size > 1 && o->islands > 1)
		return BAD("split, islands: ranks split the fits of one search or run islands, not both");
	if (!(o->semantic >= 0 && o->semantic <= 0.5))
		return BAD("semantic: must be in [0, 0.5], got %g", o->semantic);
	return 1;
}

#undef BAD

bk_search *bk_search_new(const bk_search_options *o, char *err, size_t errlen)
{
	char why[200];
	if (!bk_search_options_valid(o, why, sizeof why)) {
		snprintf(err, errlen, "search options: %s", why);
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
	s->seed_form = calloc((size_t)ns + 1, sizeof *s->seed_form);
	s->seed_form_b = calloc((size_t)ns + 1, sizeof *s->seed_form_b);
	if (!s->seed_text || !s->seed_text_b || !s->seed_name || !s->seed_p || !s->seed_form || !s->seed_form_b)
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
		if (seed_form_of(o->seed_forms, k, s->seed_text[k], &s->seed_form[k]) ||
		    (s->seed_text_b[k] && seed_form_of(o->seed_forms_b, k, s->seed_text_b[k], &s->seed_form_b[k])))
			goto oom;
	}
	s->o.seeds = (const char *const *)s->seed_text;
	s->o.seeds_b = (const char *const *)s->seed_text_b;
	s->o.seed_forms = (const bk_form *const *)s->seed_form; /* the caller's need not outlive s */
	s->o.seed_forms_b = (const bk_form *const *)s->seed_form_b;
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
	for (int k = 0; s->seed_form && s->seed_form_b && k < s->o.nseeds; k++) {
		bk_form_free(s->seed_form[k]);
		bk_form_free(s->seed_form_b[k]);
	}
	free(s->seed_form);
	free(s->seed_form_b);
	free(s->seed_text);
	free(s->seed_text_b);
	free(s->seed_name);
	free(s->seed_p);
	bk_expr_enum_free(s->gen);
	free(s->look);
	free(s->look_tree);
	bk_unique_free(s);
	bk_schedule_free(s);
	free(s);
}

long bk_search_evals(const bk_search *s) { return s->evals; }

int bk_search_cert_text(const bk_search_cert *c, const bk_grammar *gr, char *buf, size_t len)
{
	char g[1024];
	if (bk_grammar_describe(gr, g, sizeof g) < 0)
		snprintf(g, sizeof g, "(too long to state)");
	long drawn = 0, twins = 0, fitted = 0;
	for (int k = 1; k <= c->complete_size; k++)
		drawn += c->drawn[k], twins += c->twins[k], fitted += c->fitted[k];
	char cost[64] = "";
	if (isfinite(c->max_cost))
		snprintf(cost, sizeof cost, " and cost <= %g", c->max_cost);
	int n;
	if (c->complete_size < 1)
		n = snprintf(buf, len, "none: the enumeration completed no size (grammar: %s)", g);
	else
		n = snprintf(buf, len, "every unique form of the grammar up to %d nodes%s was fitted, with up to %d screening "
		             "start%s each (%ld enumerated, %ld fitted, %ld left out as twins: the same values at %d "
		             "parameter vectors); grammar: %s", c->complete_size, cost, c->starts, c->starts == 1 ? "" : "s",
		             drawn, fitted, twins, UNIQUE_VECTORS, g);
	return n >= 0 && (size_t)n < len ? n : -1;
}

int bk_search_brief(const bk_search *s, char *buf, size_t len)
{
	bk_search_cert c;
	bk_search_certificate(s, &c);
	long fitted = 0, twins = 0;
	for (int k = 0; k <= BK_EXPR_MAX; k++)
		fitted += c.fitted[k], twins += c.twins[k];
	size_t idx[64];
	size_t nf = bk_search_front(s, idx, 64);
	size_t k = 0;
	int n;
#define PUT(...) ((n = snprintf(k < len ? buf + k : NULL, k < len ? len - k : 0, __VA_ARGS__)) < 0 ? 0 : (k += (size_t)n))
	PUT("%ld fits, %zu distinct candidates; the enumeration fitted %ld unique forms and left out %ld twins; ", s->evals,
	    s->n, fitted, twins);
	if (c.complete_size > 0)
		PUT("complete to %d nodes: no form of the grammar of at most %d nodes does better than the front "
		    "(as far as a screening fit finds its constants). ", c.complete_size, c.complete_size);
	else
		PUT("no size of the enumeration is complete. ");
	char cert[2048];
	bk_search_cert_text(&c, &s->o.grammar, cert, sizeof cert);
	PUT("Certificate: %s. ", cert);
	if (nf == 0)
		PUT("No candidate fitted within the limits.");
	else {
		const bk_cand *lo = &s->cand[idx[0]], *hi = &s->cand[idx[nf - 1]];
		PUT("Front of %zu (screening): cost %g at error %.4g to cost %g at error %.4g (%s).", nf, lo->cost, lo->err,
		    hi->cost, hi->err, hi->text);
	}
#undef PUT
	return k < len ? (int)k : -1;
}

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

int bk_search_seed_index(const bk_search *s, const bk_cand *c)
{
	for (int k = 0; c && c->seed_name && k < s->o.nseeds; k++)
		if (c->seed_name == s->seed_name[k]) /* the search's own copy: one pointer a seed */
			return k;
	return -1;
}
