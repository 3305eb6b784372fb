/*
 * schedule.c — the search's schedule (schedule.h): its stages, the batch a
 * stage's generators make, their lines in a checkpoint; adding a generator
 * and offering a candidate (bk_search_schedule_add, bk_search_offer of
 * fit/search.h).
 */
#include "search/schedule.h"
#include "search/semantic.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The share of a generation the neighbours may take (the rest are
 * children, which make the structures no neighbour is one step from).
 * Measured on the recovery suite's hard forms (seeds 1, 2): every neighbour
 * (no cap) 2 generations in 3 are neighbours alone; 0.5 and 0.75 recovered
 * 23 and 22 of 42 runs, within the seeds' spread of each other. */
#define NEIGHBOUR_SHARE 0.5

/* A stage's name as checkpoints write it: its generators' names joined by
 * '+' ("done" after the last stage). A stage's name is kept under
 * STAGE_NAME characters (bk_search_schedule_add), so it always fits. */
enum { STAGE_NAME = 256 };

static void stage_name(const bk_search *s, int stage, char *buf, size_t len)
{
	size_t k = 0;
	buf[0] = '\0';
	if (stage >= s->nstages) {
		snprintf(buf, len, "done");
		return;
	}
	for (int i = 0; i < s->nsched; i++)
		if (s->sched[i].stage == stage)
			k += (size_t)snprintf(buf + k, len - k, "%s%s", k ? "+" : "", s->sched[i].name);
}

/* Every stage's name (or, with gens, every generator's), ", " between:
 * what a message lists as this search's. */
static void all_names(const bk_search *s, int gens, char *buf, size_t len)
{
	size_t k = 0;
	char one[STAGE_NAME];
	buf[0] = '\0';
	for (int i = 0; i < (gens ? s->nsched : s->nstages + 1) && k < len; i++) {
		if (!gens)
			stage_name(s, i, one, sizeof one);
		k += (size_t)snprintf(buf + k, len - k, "%s%s", i ? ", " : "", gens ? s->sched[i].name : one);
	}
}

static int find_gen(const bk_search *s, const char *name)
{
	for (int i = 0; i < s->nsched; i++)
		if (!strcmp(s->sched[i].name, name))
			return i;
	return -1;
}

/* A name checkpoints can carry as one word: 1 to 31 of [a-z0-9_-]. */
static int good_name(const char *n)
{
	size_t len = n ? strlen(n) : 0;
	if (len < 1 || len > 31 || !strcmp(n, "done"))
		return 0;
	for (const char *p = n; *p; p++)
		if (!((*p >= 'a' && *p <= 'z') || (*p >= '0' && *p <= '9') || *p == '_' || *p == '-'))
			return 0;
	return 1;
}

int bk_search_schedule_add(bk_search *s, int stage, int join, double share, const bk_search_generator *g, char *err,
                           size_t errlen)
{
	char name[STAGE_NAME];
	if (s->begun) {
		snprintf(err, errlen, "the schedule is fixed once the search is stepped or loaded");
		return -1;
	}
	if (!g || !g->make || !good_name(g->name)) {
		snprintf(err, errlen, "generator '%s': no make, or a name not of 1 to 31 of a-z, 0-9, _ and - (or \"done\")",
		         g && g->name ? g->name : "");
		return -1;
	}
	if (find_gen(s, g->name) >= 0) {
		snprintf(err, errlen, "generator %s: the schedule has one of that name", g->name);
		return -1;
	}
	if (!(share > 0 && share <= 1)) {
		snprintf(err, errlen, "generator %s: a share of %g of a batch (more than 0, at most 1)", g->name, share);
		return -1;
	}
	if (stage < 0 || stage > s->nstages - (join ? 1 : 0)) {
		snprintf(err, errlen, "generator %s: stage %d %s a schedule of %d stages", g->name, stage,
		         join ? "to join in" : "to go before in", s->nstages);
		return -1;
	}
	size_t len = strlen(g->name);
	if (join) {
		stage_name(s, stage, name, sizeof name);
		len += strlen(name) + 1;
	}
	if (len >= STAGE_NAME) {
		snprintf(err, errlen, "generator %s: its stage's name would be over %d characters", g->name, STAGE_NAME - 1);
		return -1;
	}
	bk_sched_gen *t = realloc(s->sched, sizeof *t * (size_t)(s->nsched + 1));
	if (!t) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	s->sched = t;
	int at = 0; /* join: after the stage's last; else before the first of a later stage */
	while (at < s->nsched && (join ? t[at].stage <= stage : t[at].stage < stage))
		at++;
	memmove(&t[at + 1], &t[at], sizeof *t * (size_t)(s->nsched - at));
	if (!join) {
		for (int i = at + 1; i <= s->nsched; i++)
			t[i].stage++;
		s->nstages++;
	}
	s->nsched++;
	t[at].g = *g;
	snprintf(t[at].name, sizeof t[at].name, "%s", g->name);
	t[at].g.name = t[at].name;
	t[at].share = share;
	t[at].stage = stage;
	return 0;
}

int bk_schedule_default(bk_search *s)
{
	char err[160];
	bk_search_generator seeds = bk_gen_seeds, sem;
	seeds.room = (size_t)s->o.nseeds; /* every seed in one batch */
	if (bk_search_schedule_add(s, 0, 0, 1, &seeds, err, sizeof err) ||
	    bk_search_schedule_add(s, 1, 0, 1, &bk_gen_enumeration, err, sizeof err) ||
	    bk_search_schedule_add(s, 2, 0, NEIGHBOUR_SHARE, &bk_gen_neighbours, err, sizeof err))
		return -1;
	if (s->o.semantic > 0) { /* after the neighbours, up to its part of the generation */
		if (bk_sem_generator(&sem))
			return -1;
		if (bk_search_schedule_add(s, 2, 1, NEIGHBOUR_SHARE + s->o.semantic, &sem, err, sizeof err)) {
			sem.free(sem.state);
			return -1;
		}
	}
	return bk_search_schedule_add(s, 2, 1, 1, &bk_gen_children, err, sizeof err) ? -1 : 0;
}

void bk_schedule_free(bk_search *s)
{
	for (int i = 0; i < s->nsched; i++)
		if (s->sched[i].g.free)
			s->sched[i].g.free(s->sched[i].g.state);
	free(s->sched);
	s->sched = NULL;
	s->nsched = s->nstages = 0;
}

size_t bk_schedule_want(const bk_search *s)
{
	/* whole generations, whatever the budget: a run stopped at a budget and
	 * resumed with a larger one must make the same batches as a run that
	 * never stopped (so a run may end up to generation - 1 fits past it) */
	size_t want = (size_t)s->o.generation;
	for (int i = 0; i < s->nsched; i++)
		if (s->sched[i].stage == s->stage && s->sched[i].g.room > want)
			want = s->sched[i].g.room;
	return want;
}

size_t bk_schedule_most(const bk_search *s)
{
	size_t most = (size_t)s->o.generation;
	for (int i = 0; i < s->nsched; i++)
		if (s->sched[i].g.room > most)
			most = s->sched[i].g.room;
	return most;
}

int bk_schedule_make(bk_search *s, bk_gen_batch *b)
{
	b->n = 0;
	if (s->stage >= s->nstages)
		return 0;
	bk_search_sink k = {s, b};
	size_t want = b->want;
	int over = 1;
	for (int i = 0; i < s->nsched; i++) {
		const bk_sched_gen *g = &s->sched[i];
		if (g->stage != s->stage)
			continue;
		/* its share, counted from the batch's start: at least one */
		size_t cap = (size_t)(want * g->share);
		b->want = cap < 1 ? 1 : cap > want ? want : cap;
		int r = g->g.make(g->g.state, s, &k);
		b->want = want;
		if (r < 0)
			return -1;
		over &= r > 0;
	}
	if (over)
		s->stage++;
	return 0;
}

/* ---- a plug-in's candidates ------------------------------------------------ */

size_t bk_search_sink_room(const bk_search_sink *k) { return k->b->n < k->b->want ? k->b->want - k->b->n : 0; }

int bk_search_offer(bk_search_sink *k, const bk_expr t0[2], const double *start)
{
	bk_search *s = k->s;
	bk_gen_batch *b = k->b;
	int pair = s->o.shape == BK_SHAPE_PAIR;
	char why[128];
	if (b->n >= b->want)
		return 0;
	bk_expr t[2] = {t0[0], pair ? t0[1] : t0[0]};
	if (!pair)
		t[1].n = 0;
	/* canonical within the grammar's inputs, as the generators' trees are */
	for (int h = 0; h < 2; h++)
		if ((h == 0 || t[h].n > 0) &&
		    (bk_expr_valid(&t[h], why, sizeof why) || bk_expr_canon_in(&t[h], s->tree_g.inputs)))
			return 0;
	if (pair && t[1].n == 0 && bk_expr_nparams(&t[0]) > s->feat_g.max_params)
		return 0; /* a shared feature leaves A and B their parameters (as the enumeration's) */
	return bk_gen_take(s, b, t, start);
}

/* ---- checkpoint lines ------------------------------------------------------ */

int bk_schedule_save(const bk_search *s, FILE *f)
{
	char name[STAGE_NAME];
	stage_name(s, s->stage, name, sizeof name);
	fprintf(f, "stage %s\n", name);
	for (int i = 0; i < s->nsched; i++) {
		const bk_sched_gen *g = &s->sched[i];
		fprintf(f, "generator %s\n", g->name);
		if (g->g.save && g->g.save(g->g.state, s, f))
			return -1;
	}
	return ferror(f) ? -1 : 0;
}

int bk_schedule_load(bk_search *s, FILE *f, char *err, size_t errlen)
{
	char name[STAGE_NAME], one[STAGE_NAME], list[1024];
	if (fscanf(f, " stage %255s", name) != 1) {
		snprintf(err, errlen, "no stage line");
		return -1;
	}
	int st = 0;
	for (; st <= s->nstages; st++) {
		stage_name(s, st, one, sizeof one);
		if (!strcmp(one, name))
			break;
	}
	if (st > s->nstages) {
		all_names(s, 0, list, sizeof list);
		snprintf(err, errlen, "stage %s: not one of this search's (%s)", name, list);
		return -1;
	}
	s->stage = st;
	all_names(s, 1, list, sizeof list);
	for (int i = 0; i < s->nsched; i++) {
		bk_sched_gen *g = &s->sched[i];
		if (fscanf(f, " generator %255s", name) != 1) {
			snprintf(err, errlen, "no generator line for %s (this search's: %s)", g->name, list);
			return -1;
		}
		if (strcmp(name, g->name)) {
			if (find_gen(s, name) < 0)
				snprintf(err, errlen, "generator %s: not in this search's schedule (%s)", name, list);
			else
				snprintf(err, errlen, "generator %s where this search's schedule has %s (%s)", name, g->name, list);
			return -1;
		}
		int when = g->stage < st ? 1 : g->stage == st ? 0 : -1;
		if (g->g.load && g->g.load(g->g.state, s, when, f, err, errlen))
			return -1;
	}
	if (fscanf(f, " generator %255s", name) == 1) { /* one this schedule lacks */
		snprintf(err, errlen, "generator %s: not in this search's schedule (%s)", name, list);
		return -1;
	}
	return 0;
}
