/*
 * state.c — checkpoints and migrants (state.h; bk_search_save, load,
 * export and import of fit/search.h).
 */
#include "search/state.h"
#include "search/archive.h"
#include "search/cand.h"
#include "search/schedule.h"

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* 5: the twins' fingerprints are of other probes and vectors (unique.c), so
 * a checkpoint of 4 would mix two kinds in one table */
#define CHECKPOINT_MAGIC "brdfkit-search-checkpoint 5"
#define MIGRANTS_MAGIC "brdfkit-search-migrants 1"

/* What must agree between a checkpoint and the run resuming it: everything
 * that decides which candidates are made and how they are scored, not the
 * budget or the thread count. Without own: what the islands of one run share
 * (all of it but the seed, the island and its share of the enumeration), so
 * that migrants are comparable. */
uint64_t bk_state_fingerprint(const bk_search *s, int own)
{
	const bk_search_options *o = &s->o;
	uint64_t h = BK_HASH_INIT;
	int ints[] = {o->shape, o->scale, o->objective, o->relative, o->precision, o->nonneg, o->env_bound, o->enum_size,
	              o->generation, o->per_level, o->starts, o->grammar.inputs, o->grammar.max_params,
	              o->grammar.max_size, o->grammar.nconsts, o->nseeds, o->islands};
	double dbl[] = {o->max_cost, o->simple_cost, o->complex_cost, o->semantic};
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
	bk_expr t[2];
	bk_cand_trees(c, t);
	put_tree(f, &t[0]);
	put_tree(f, &t[1]);
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
 * OK, +inf when not; its island one of the run's. 0, or -1 (why). Its
 * texts are parsed here, where they are read, and the forms kept on c. */
static int check_cand(const bk_search *s, bk_cand *c, int seed, reader *r, const char *what)
{
	int pair = s->o.shape == BK_SHAPE_PAIR;
	if (c->found_at < 1 || c->island < 0 || c->island >= s->o.islands)
		return fail(r, "%s: found at fit %ld of island %d (of %d)", what, c->found_at, c->island, s->o.islands);
	if (!pair && c->ntree[1] != 0)
		return fail(r, "%s: a second tree, and the candidates of this search have one", what);
	if ((c->text_b != NULL) != pair)
		return fail(r, "%s: %s text B", what, pair ? "no" : "a");
	if (seed >= 0) {
		const char *b = s->seed_text_b[seed];
		if (strcmp(c->text, s->seed_text[seed]) || (b && strcmp(c->text_b, b)))
			return fail(r, "%s: not the text of seed %d", what, seed + 1);
	} else {
		char a[4200], b[4200];
		bk_expr t[2];
		bk_cand_trees(c, t);
		if (bk_cand_text(s, t, a, b, sizeof a) || strcmp(a, c->text) || (pair && strcmp(b, c->text_b)))
			return fail(r, "%s: its text is not that of its trees", what);
	}
	bk_cand t;
	memset(&t, 0, sizeof t);
	if (bk_cand_parse(s, &t, c->text, c->text_b))
		return fail(r, "%s: its text is not a form", what);
	c->form = t.form, c->form_b = t.form_b, c->form_pair = t.form_pair; /* freed with c */
	if (memcmp(&t.ops, &c->ops, sizeof t.ops) || t.cost != c->cost || t.np != c->np)
		return fail(r, "%s: cost %g or %d parameters, and its text has cost %g and %d", what, c->cost, c->np, t.cost,
		            t.np);
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
	bk_expr t[2];
	snprintf(tw, sizeof tw, "%s: tree 1", what);
	if (get_tree(r, &t[0], 0, tw))
		return -1;
	snprintf(tw, sizeof tw, "%s: tree 2", what);
	if (get_tree(r, &t[1], 1, tw))
		return -1;
	if (fscanf(f, " %d %d", &seed, &has_b) != 2 || seed < -1 || seed >= s->o.nseeds || has_b < 0 || has_b > 1 ||
	    fgetc(f) != '\n')
		return fail(r, "%s: seed (-1 to %d) or text count unreadable", what, s->o.nseeds - 1);
	if (bk_cand_set_trees(c, t, 1))
		return fail(r, "%s: out of memory", what);
	c->seed_name = seed >= 0 ? s->seed_name[seed] : NULL;
	c->text = get_text(r, what);
	c->text_b = c->text && has_b ? get_text(r, what) : NULL;
	if (!c->text || (has_b && !c->text_b) || check_cand(s, c, seed, r, what)) {
		bk_cand_free(c);
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
	fprintf(m, "state %ld\nbudget %ld\n", s->evals, s->o.evals);
	int bad = bk_schedule_save(s, m); /* the stage, each generator and its state (schedule.h) */
	fprintf(m, "seen %zu\n", s->seen.n);
	for (size_t i = 0; i < s->seen.cap; i++)
		if (s->seen.h[i])
			fprintf(m, "%016llx\n", (unsigned long long)s->seen.h[i]);
	fprintf(m, "candidates %zu\n", s->n);
	for (size_t i = 0; i < s->n; i++)
		put_cand(s, m, &s->cand[i]);
	fputs("end\n", m);
	bad |= ferror(m);
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
		uint64_t h = bk_cand_key(c->text, c->text_b);
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

/* The state against the options: fits within the budget the checkpoint's
 * run had (it ends after the generation that reaches it), nothing fitted
 * while the first stage is the seeds (they are its one batch), a random
 * generator that is not stuck at zero. The stage's name and each
 * generator's state (the enumeration's position on a tree it has) were
 * checked as they were read (bk_schedule_load). */
static int check_state(bk_search *s, long budget, reader *r)
{
	long step = (long)bk_schedule_most(s); /* the most fits of one step */
	if (budget < 1 || s->evals < 0 || s->evals > budget + step - 1)
		return fail(r, "%ld fits for a budget of %ld (one step is at most %ld)", s->evals, budget, step);
	if (s->stage == 0 && s->nsched > 0 && !strcmp(s->sched[0].name, "seeds") && (s->evals || s->n))
		return fail(r, "stage seeds (the first) after %ld fits", s->evals);
	if (!(s->rng.s[0] | s->rng.s[1] | s->rng.s[2] | s->rng.s[3]))
		return fail(r, "a generator state of zeros");
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
	if (fscanf(f, " state %ld budget %ld", &s->evals, budget) != 2)
		return fail(r, "no state or budget line");
	char why[1200];
	if (bk_schedule_load(s, f, why, sizeof why))
		return fail(r, "%s", why);
	if (fscanf(f, " seen %zu", &nseen) != 1)
		return fail(r, "no cache line");
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
		if (bk_archive_push(s, &c)) {
			bk_cand_free(&c);
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
	s->begun = 1; /* its schedule is the checkpoint's from here on */
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
		int fresh = bk_hashset_add(&s->seen, bk_cand_key(c.text, c.text_b));
		if (fresh < 0 || (fresh > 0 && bk_archive_push(s, &c))) {
			bk_cand_free(&c);
			snprintf(err, errlen, "out of memory taking migrants");
			return -1;
		}
		if (fresh == 0)
			bk_cand_free(&c);
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
