/*
 * scene_fit.c — the cheapest form of a term that meets a scene's error
 * budget on its own domain (scene_fit.h): candidates from the catalog,
 * published and refitted on the set's domain, LUTs for the environment BRDF,
 * scored in the scene's precision; then the fp16 guards the choice needs;
 * for vf, the low tier's specular LUT where it could be cheaper (speclut.h).
 */
#include "scene_fit.h"

#include "catalog.h"
#include "albfit.h"
#include "fit.h"
#include "lutcache.h"
#include "lutrows.h"
#include "pool.h"
#include "search.h"
#include "search/catalogmap.h"
#include "search/refit.h"
#include "search/seeds.h"
#include "stability.h"

#include <ctype.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *bk_scene_term_name(bk_scene_term t)
{
	static const char *const n[] = {"D", "vf", "env", "ms", "sheen", "cloth"};
	return (unsigned)t < BK_SCENE_TERMS ? n[t] : "?";
}

/* ---- text rewrites -------------------------------------------------------------- */

/* text with every whole-word occurrence of word replaced by with; allocated. */
static char *replace_word(const char *text, const char *word, const char *with)
{
	size_t wl = strlen(word), n = 0;
	for (const char *p = strstr(text, word); p; p = strstr(p + wl, word))
		n++;
	char *out = malloc(strlen(text) + n * strlen(with) + 1), *o = out;
	if (!out)
		return NULL;
	for (const char *p = text; *p;) {
		int start = p == text || !(isalnum((unsigned char)p[-1]) || p[-1] == '_');
		if (start && !strncmp(p, word, wl) && !(isalnum((unsigned char)p[wl]) || p[wl] == '_')) {
			o += sprintf(o, "%s", with);
			p += wl;
		} else {
			*o++ = *p++;
		}
	}
	*o = 0;
	return out;
}

char *bk_scene_fold_f0(const char *text, double f0)
{
	char lit[40];
	snprintf(lit, sizeof lit, "(%.9g)", f0);
	return replace_word(text, "f0", lit);
}

/* Every cosine the form reads floored at c: the guard that alone makes it
 * right in half where the stability analysis found one suffices. */
static char *floor_cosines(const char *text, double c)
{
	static const char *const cos_in[] = {"NoV", "NoL", "NoH", "LoH", "VoH"};
	char *t = strdup(text);
	for (int k = 0; t && k < 5; k++) {
		char with[48];
		snprintf(with, sizeof with, "max(%s, %.9g)", cos_in[k], c);
		char *u = replace_word(t, cos_in[k], with);
		free(t);
		t = u;
	}
	return t;
}

/* ---- the samples of a term on a set's domain ----------------------------------- */

/* what a domain's samples are built from: x and r ranges, the f0 ends */
#define MEMO_KEY 6

typedef struct domain {
	bk_samples s[2]; /* vf: one per end of the f0 range; env: one holding both ends */
	int ns;
	int kept;        /* s[0] is the env memo's (read only, not freed here) */
	bk_precision prec;
	double key[MEMO_KEY]; /* what the refit's samples (s[ns - 1]) are built from (refits_at) */
} domain;

static void domain_free(domain *d)
{
	for (int k = d->kept; k < d->ns; k++)
		bk_samples_free(&d->s[k]);
}

/* ---- env references, once per domain ---------------------------------------------- */

/* An env domain's samples are reference integrals (seconds each set: most of
 * a scene's time), and the scenes of one run share domains (the same
 * roughness, NoV and f0 ranges): each distinct one is built once and kept
 * until bk_scene_forget, read by every set that has it, from any thread (one
 * builds it, the others wait for it). The samples are the same bits either
 * way: bk_target_build is a function of its options. */
#define MEMO_MAX 64

static struct {
	pthread_mutex_t mu;
	pthread_cond_t cv;
	int n;
	struct {
		double key[MEMO_KEY];
		bk_samples s;
		int state; /* 0 being built, 1 ready, -1 failed */
	} e[MEMO_MAX];
} memo = {PTHREAD_MUTEX_INITIALIZER, PTHREAD_COND_INITIALIZER, 0, {{{0}, {0}, 0}}};

static void refits_forget(void);

void bk_scene_forget(void)
{
	pthread_mutex_lock(&memo.mu);
	for (int k = 0; k < memo.n; k++)
		if (memo.e[k].state == 1)
			bk_samples_free(&memo.e[k].s);
	memo.n = 0;
	pthread_mutex_unlock(&memo.mu);
	refits_forget();
}

/* The env samples for options o (key: what domain_build sets in them) into
 * d->s[0], from the memo or built there; -1 with a message. */
static int env_samples(const bk_target_options *o, const double key[MEMO_KEY], domain *d, bk_progress_fn progress,
                       void *ctx, char *err, size_t errlen)
{
	pthread_mutex_lock(&memo.mu);
	int k = 0;
	for (;;) {
		for (k = 0; k < memo.n && memcmp(memo.e[k].key, key, sizeof memo.e[k].key); k++)
			;
		if (k == memo.n || memo.e[k].state != 0)
			break;
		pthread_cond_wait(&memo.cv, &memo.mu); /* another thread builds it */
	}
	if (k < memo.n && memo.e[k].state == 1) {
		d->s[0] = memo.e[k].s;
		d->kept = d->ns = 1;
		pthread_mutex_unlock(&memo.mu);
		return 0;
	}
	if (k == memo.n && memo.n == MEMO_MAX) { /* full: built for this set alone */
		pthread_mutex_unlock(&memo.mu);
		d->ns = 1;
		return bk_lutcache_target_build(o, &d->s[0], progress, ctx, err, errlen);
	}
	if (k == memo.n) /* a failed build is tried again, in the same slot */
		memo.n++;
	memcpy(memo.e[k].key, key, sizeof memo.e[k].key);
	memo.e[k].state = 0;
	pthread_mutex_unlock(&memo.mu);
	bk_samples s;
	int rc = bk_lutcache_target_build(o, &s, progress, ctx, err, errlen);
	pthread_mutex_lock(&memo.mu);
	memo.e[k].state = rc ? -1 : 1;
	if (!rc)
		memo.e[k].s = s;
	pthread_cond_broadcast(&memo.cv);
	pthread_mutex_unlock(&memo.mu);
	if (!rc) {
		d->s[0] = s;
		d->kept = d->ns = 1;
	}
	return rc;
}

/* A roughness or f0 range of one value gets a little width: a target is a
 * box of cells. */
static void widen(double *lo, double *hi)
{
	if (*hi - *lo < 0.01) {
		double m = 0.5 * (*lo + *hi);
		*lo = fmax(0, m - 0.005);
		*hi = fmin(1, m + 0.005);
	}
}

static int domain_build(const bk_scene *sc, const bk_scene_set *set, bk_scene_term term, domain *d,
                        bk_progress_fn progress, void *ctx, char *err, size_t errlen)
{
	memset(d, 0, sizeof *d);
	d->prec = sc->half ? BK_F16 : BK_F32;
	double ends[2] = {set->f0_hi, set->f0_lo};
	int nends = set->f0_lo == set->f0_hi ? 1 : 2;
	bk_target_options o;
	bk_target_defaults(term == BK_SCENE_TERM_ENV ? BK_TARGET_ENV : BK_TARGET_VF, &o);
	o.r_lo = set->r_lo;
	o.r_hi = set->r_hi;
	widen(&o.r_lo, &o.r_hi);
	o.x_lo = sc->nov_lo;
	o.x_hi = sc->nov_hi;
	if (term == BK_SCENE_TERM_MS || term == BK_SCENE_TERM_SHEEN) {
		/* E and the sheen albedo have no f0 (F = 1): one set of reference
		 * integrals on env's 40x40 cells, kept as env's are; the key's f0
		 * places hold a negative marker no f0 can be */
		bk_target_defaults(term == BK_SCENE_TERM_MS ? BK_TARGET_MS : BK_TARGET_SHEEN, &o);
		o.r_lo = set->r_lo;
		o.r_hi = set->r_hi;
		widen(&o.r_lo, &o.r_hi);
		o.x_lo = sc->nov_lo;
		o.x_hi = sc->nov_hi;
		o.nx = o.nr = 40;
		double key[MEMO_KEY] = {o.x_lo, o.x_hi, o.r_lo, o.r_hi, term == BK_SCENE_TERM_MS ? -1.0 : -2.0, NAN};
		memcpy(d->key, key, sizeof d->key);
		return env_samples(&o, key, d, progress, ctx, err, errlen);
	}
	if (term == BK_SCENE_TERM_ENV) {
		/* 40x40 cells: centres that are no LUT's texel centres on [0, 1] */
		o.nx = o.nr = 40;
		o.env_f0_form = 1;
		o.nf0 = nends;
		memcpy(o.f0, ends, sizeof ends);
		double key[MEMO_KEY] = {o.x_lo, o.x_hi, o.r_lo, o.r_hi, ends[0], nends > 1 ? ends[1] : NAN};
		memcpy(d->key, key, sizeof d->key);
		return env_samples(&o, key, d, progress, ctx, err, errlen);
	}
	/* vf: the refit reads the last set, built at f0 = ends[nends - 1] */
	double key[MEMO_KEY] = {o.x_lo, o.x_hi, o.r_lo, o.r_hi, ends[nends - 1], NAN};
	memcpy(d->key, key, sizeof d->key);
	for (int k = 0; k < nends; k++) {
		o.f0[0] = ends[k];
		if (bk_lutcache_target_build(&o, &d->s[k], NULL, NULL, err, errlen)) {
			domain_free(d);
			return -1;
		}
		d->ns++;
	}
	return 0;
}

/* The term's error of values of form f (params p) in the domain's precision:
 * the largest over the sample sets; HUGE_VAL where it is not finite. */
static double score(const domain *d, bk_scene_term term, const bk_form *f, const double *p)
{
	double worst = 0;
	for (int k = 0; k < d->ns; k++) {
		const bk_samples *s = &d->s[k];
		if (bk_form_inputs(f) & ~s->provides)
			return HUGE_VAL;
		double *v = malloc(s->n * sizeof *v);
		const double *in[BK_IN_COUNT];
		for (int i = 0; i < BK_IN_COUNT; i++)
			in[i] = s->in[i];
		if (!v || bk_form_eval(f, d->prec, s->n, in, p, v)) {
			free(v);
			return HUGE_VAL;
		}
		bk_fit_metrics m;
		bk_samples_metrics(s, v, NULL, &m);
		free(v);
		double e = term == BK_SCENE_TERM_VF ? m.albedo_max_abs : m.max_abs;
		if (m.nonfinite || !isfinite(e))
			return HUGE_VAL;
		worst = fmax(worst, e);
	}
	return worst;
}

/* ---- refits, once per (samples, term, form, start) ------------------------------- */

/* The scenes of one run share domains (mobile high and low tier, rough only
 * and its highp twin, the two thesis rusted metals: the same materials), and
 * each set refits the catalog's forms on its domain: the same fit, the same
 * bits, once per scene. A refit's result is a function of the samples (made
 * from d->key: domain_build), the term, the form's text and the start, so it
 * is kept, process-wide until bk_scene_forget, and read by any thread (a
 * thread that asks a refit another is making waits for it: refit). */
typedef struct refit_entry {
	double key[MEMO_KEY], start[BK_MAX_PARAMS], p[BK_MAX_PARAMS];
	int term, rc;
	int done; /* 0 while a thread fits it: another one asking waits (refit) */
	char *text;
} refit_entry;

static struct {
	pthread_mutex_t mu;
	pthread_cond_t cv; /* a refit was made */
	refit_entry *e;
	int n, cap;
} refits = {PTHREAD_MUTEX_INITIALIZER, PTHREAD_COND_INITIALIZER, NULL, 0, 0};

static void refits_forget(void)
{
	pthread_mutex_lock(&refits.mu);
	for (int k = 0; k < refits.n; k++)
		free(refits.e[k].text);
	free(refits.e);
	refits.e = NULL;
	refits.n = refits.cap = 0;
	pthread_mutex_unlock(&refits.mu);
}

/* The entry of (d, term, text, start), or -1; under refits.mu. */
static int refits_at(const domain *d, bk_scene_term term, const char *text, const double *start)
{
	for (int k = 0; k < refits.n; k++) {
		const refit_entry *e = &refits.e[k];
		if (e->term == (int)term && !memcmp(e->key, d->key, sizeof e->key) &&
		    !memcmp(e->start, start, sizeof e->start) && !strcmp(e->text, text))
			return k;
	}
	return -1;
}

/* A new entry for (d, term, text, start), being made; -1 when out of memory
 * (the refit is then made and not kept). Under refits.mu. */
static int refits_claim(const domain *d, bk_scene_term term, const char *text, const double *start)
{
	if (refits.n == refits.cap) {
		int cap = refits.cap ? 2 * refits.cap : 64;
		refit_entry *e = realloc(refits.e, (size_t)cap * sizeof *e);
		if (!e)
			return -1;
		refits.e = e;
		refits.cap = cap;
	}
	refit_entry *e = &refits.e[refits.n];
	memset(e, 0, sizeof *e);
	if (!(e->text = strdup(text)))
		return -1;
	memcpy(e->key, d->key, sizeof e->key);
	memcpy(e->start, start, sizeof e->start);
	e->term = (int)term;
	return refits.n++;
}

static int refit_run(const domain *d, bk_scene_term term, const bk_form *f, const double *start, double *p);

/* Least squares on the set's domain (the last sample set: vf at the low end
 * of f0, where most dielectrics are), from the published constants; for env
 * minimax, the error it is scored on. text: f's text (the memo's key). p is
 * left as it was where the refit fails. Each refit is made once: a thread
 * that asks one another thread is making waits for it (the sets of scenes
 * that share a domain ask the same refits at the same moment: refits_list). */
static int refit(const domain *d, bk_scene_term term, const bk_form *f, const char *text, const double *start,
                 double *p)
{
	double s0[BK_MAX_PARAMS];
	memcpy(s0, start, sizeof s0); /* start may be p itself */
	pthread_mutex_lock(&refits.mu);
	int k;
	while ((k = refits_at(d, term, text, s0)) >= 0 && !refits.e[k].done)
		pthread_cond_wait(&refits.cv, &refits.mu);
	if (k >= 0) {
		int rc = refits.e[k].rc;
		if (!rc)
			memcpy(p, refits.e[k].p, sizeof refits.e[k].p);
		pthread_mutex_unlock(&refits.mu);
		return rc;
	}
	k = refits_claim(d, term, text, s0);
	pthread_mutex_unlock(&refits.mu);
	double q[BK_MAX_PARAMS];
	memcpy(q, p, sizeof q);
	int rc = refit_run(d, term, f, s0, q);
	if (!rc)
		memcpy(p, q, sizeof q);
	pthread_mutex_lock(&refits.mu);
	if (k >= 0) {
		refit_entry *e = &refits.e[k];
		e->rc = rc;
		memcpy(e->p, q, sizeof e->p);
		e->done = 1;
		pthread_cond_broadcast(&refits.cv);
	}
	pthread_mutex_unlock(&refits.mu);
	return rc;
}

static int refit_run(const domain *d, bk_scene_term term, const bk_form *f, const double *start, double *p)
{
	bk_fit_spec sp;
	bk_refit_spec(&sp, &d->s[d->ns - 1], f, NULL, start); /* its iteration cap: search/refit.h */
	/* env is scored on its max error: minimise that (Lawson's reweighting) */
	sp.minimax = term == BK_SCENE_TERM_ENV || term == BK_SCENE_TERM_MS || term == BK_SCENE_TERM_SHEEN;
	char where[128];
	if (!sp.np || bk_fit_nonfinite(&sp, sp.start, where, sizeof where))
		return -1;
	bk_fit_result res;
	if (bk_fit_run(&sp, &res) < 0)
		return -1;
	memcpy(p, res.p, sizeof res.p);
	/* vf is scored on the directional albedo's max error: from the least
	 * squares point, minimise that (albfit.h) */
	bk_albfit *af = term == BK_SCENE_TERM_VF ? bk_albfit_new(sp.s, f, sp.np) : NULL;
	if (af) {
		bk_fit_options o = bk_refit_albedo_options();
		bk_albfit_run(af, p, 1, &o, NULL);
		bk_albfit_free(af);
	}
	return 0;
}

/* ---- refits ahead, on threads -------------------------------------------------- */

/* A set's candidates are refitted on its domain one after the other by
 * add_form (the catalog's forms of a term, the short search's front):
 * independent fits, most of a set's time, on one thread where the scene
 * has one set. So a list of them is fitted first on the online cores, each
 * kept by refit's memo; add_form then finds every one made, the same bits
 * (a refit is a function of its key), and the candidates, their order and
 * the output are as before. */
typedef struct refits_list {
	const bk_scene_set *set;
	const domain *d;
	bk_scene_term term;
	char **text;           /* the forms as add_form is given them (owned) */
	const double **start;  /* their constants (add_form's params) */
	bk_progress_fn progress; /* called under the pool's lock */
	const char *label;
	int n, done;
} refits_list;

/* Form i's refit, as add_form asks it (f0 folded where the set has one); a
 * failure is met again, and reported, where add_form asks. */
static int refit_ahead(void *ctx, int i)
{
	const refits_list *R = ctx;
	char *t = R->set->needs.fixed_f0 ? bk_scene_fold_f0(R->text[i], R->set->needs.f0) : strdup(R->text[i]);
	bk_form_error fe;
	bk_form *f = t ? bk_form_parse(t, &fe) : NULL;
	if (f && bk_form_nparams(f)) {
		double p[BK_MAX_PARAMS];
		memcpy(p, R->start[i], sizeof p);
		refit(R->d, R->term, f, t, R->start[i], p);
	}
	bk_form_free(f);
	free(t);
	return 0;
}

static void refit_ahead_done(void *ctx, int i, int rc)
{
	refits_list *R = ctx;
	(void)i, (void)rc;
	if (R->progress)
		R->progress((void *)R->label, ++R->done, R->n);
}

/* Fits R's forms ahead (above) and frees its texts. Out of memory on the
 * way: nothing is lost but the time, add_form fits what is not kept. */
static void refits_run(refits_list *R)
{
	bk_pool_run(R->n, bk_pool_cores(BK_POOL_MAX_THREADS), refit_ahead, refit_ahead_done, R);
	for (int i = 0; i < R->n; i++)
		free(R->text[i]);
	free(R->text);
	free(R->start);
}

/* A list of at most n forms, empty; 0, or -1 out of memory. */
static int refits_new(refits_list *R, const bk_scene_set *set, const domain *d, bk_scene_term term, int n)
{
	memset(R, 0, sizeof *R);
	R->set = set, R->d = d, R->term = term;
	R->text = calloc((size_t)n + 1, sizeof *R->text);
	R->start = calloc((size_t)n + 1, sizeof *R->start);
	if (!R->text || !R->start) {
		free(R->text), free(R->start);
		return -1;
	}
	return 0;
}

/* ---- candidates ------------------------------------------------------------- */

typedef struct cand {
	char name[128], source[256];
	char *text;
	bk_form *f;           /* text parsed (owned), NULL for a LUT: guards and choices take it from here */
	double p[BK_MAX_PARAMS];
	double cost, err;
	bk_ops ops;
	int lut, lut_size;
	bk_lut_layout layout; /* a LUT's layout */
	bk_lut_format fmt;
	double lut_bytes;
} cand;

typedef struct pool {
	cand *c;
	int n, cap;
} pool;

static cand *pool_add(pool *P)
{
	if (P->n == P->cap) {
		int cap = P->cap ? 2 * P->cap : 32;
		cand *c = realloc(P->c, cap * sizeof *c);
		if (!c)
			return NULL;
		P->c = c;
		P->cap = cap;
	}
	cand *c = &P->c[P->n++];
	memset(c, 0, sizeof *c);
	return c;
}

static void pool_free(pool *P)
{
	for (int i = 0; i < P->n; i++) {
		free(P->c[i].text);
		bk_form_free(P->c[i].f);
	}
	free(P->c);
}

static double form_cost(const bk_scene *sc, const bk_form *f, bk_ops *ops)
{
	bk_form_count(f, ops);
	return bk_ops_cost(ops, sc->simple_cost, sc->complex_cost);
}

/* Scores text (f0 folded where the set has one) at params, and its refit when
 * it has parameters; adds what is finite on the domain. */
static int add_form(pool *P, const bk_scene *sc, const bk_scene_set *set, const domain *d, bk_scene_term term,
                    const char *name, const char *source, const char *text, const double *params)
{
	char *t = set->needs.fixed_f0 ? bk_scene_fold_f0(text, set->needs.f0) : strdup(text);
	bk_form_error fe;
	bk_form *f = t ? bk_form_parse(t, &fe) : NULL;
	if (!f) {
		free(t);
		return t ? 0 : -1;
	}
	double zero[BK_MAX_PARAMS] = {0};
	const double *p0 = params ? params : zero;
	for (int pass = 0; pass < 2; pass++) {
		double p[BK_MAX_PARAMS];
		memcpy(p, p0, sizeof p);
		if (pass == 1 && (!bk_form_nparams(f) || refit(d, term, f, t, p0, p)))
			break;
		double e = score(d, term, f, p);
		if (!isfinite(e))
			continue;
		cand *c = pool_add(P);
		if (!c || !(c->text = strdup(t)) || !(c->f = bk_form_dup(f))) {
			bk_form_free(f);
			free(t);
			return -1;
		}
		snprintf(c->name, sizeof c->name, "%.100s%s", name, pass ? " (refit)" : "");
		snprintf(c->source, sizeof c->source, "%.180s%s", source, pass ? "; refitted on the scene's domain" : "");
		memcpy(c->p, p, sizeof p);
		c->err = e;
		c->cost = form_cost(sc, f, &c->ops);
	}
	bk_form_free(f);
	free(t);
	return 0;
}

/* The ALU ops of a LUT's coordinates and combine: the warp of NoV, the remap
 * of r onto the rows, and f0 A + B unless one channel is the term (f0
 * folded into the texel, or the cloth channel). */
static int lut_ops(const bk_lut_layout *L, int one_channel, bk_ops *ops)
{
	memset(ops, 0, sizeof *ops);
	const char *parts[3] = {bk_lut_warp_form(L->warp), L->r_lo > 0 || L->r_hi < 1 ? "r*p0 + p1" : "r",
	                        isnan(L->f0) && !one_channel ? "f0*p0 + p1" : "p0"};
	for (int k = 0; k < 3; k++)
		if (bk_form_count_add(parts[k], ops))
			return -1;
	return 0;
}

/* LUTs of 16² to 128² in three formats: the generic layout (brdfkit lut
 * --size N: A and B over [0, 1]²), and laid out for the set (brdf.h,
 * bk_lut_layout): rows over its roughness range only, f0 folded into one
 * channel where it has one f0, NoV warped towards grazing angles. sheen:
 * the cloth channel in the same layouts, never folded (no f0). */
static int add_luts(pool *P, const bk_scene *sc, const bk_scene_set *set, const domain *d, bk_smith smith,
                    bk_scene_term term, bk_progress_fn progress, void *label)
{
	double r_lo = set->r_lo, r_hi = set->r_hi;
	widen(&r_lo, &r_hi);
	const bk_samples *s = &d->s[0];
	/* ms's samples have no f0: E = A + B is the DFG folded at f0 = 1, the
	 * generic layout included (a texture of E alone, as compare's ms rows) */
	int cloth = term == BK_SCENE_TERM_SHEEN, ms = !cloth && !(s->provides >> BK_IN_F0 & 1);
	double f0 = ms ? 1.0 : !cloth && set->needs.fixed_f0 && s->n ? s->in[BK_IN_F0][0] : NAN;
	bk_lut_layout L[BK_LUTROWS_MAX_LAYOUTS];
	bk_lutrow *rows = malloc(BK_LUTROWS_MAX * sizeof *rows);
	if (!rows)
		return -1;
	int nl = bk_lutrows_layouts(1, r_lo, r_hi, f0, L), rc = 0;
	if (ms)
		L[0].f0 = 1.0;
	int n = bk_lutrows_build(L, nl, smith, cloth, d->prec, s, progress, label, rows);
	for (int k = 0; k < n && !rc; k++) {
		const bk_lutrow *r = &rows[k];
		bk_ops ops;
		cand *c = r->scored && !lut_ops(&r->layout, cloth, &ops) ? pool_add(P) : NULL;
		if (!c) {
			rc = -1;
			break;
		}
		snprintf(c->name, sizeof c->name, "%s", r->name);
		if (cloth)
			snprintf(c->source, sizeof c->source, "the cloth channel (B) of brdfkit lut --channels filament, the "
			         "sheen albedo, bilinear, texel centres");
		else if (ms)
			snprintf(c->source, sizeof c->source, "a texture of E = A + B alone (brdfkit lut --f0 1), bilinear, "
			         "texel centres");
		else if (r->variant == 0)
			snprintf(c->source, sizeof c->source, "brdfkit lut --size %d (DFG texture, bilinear, texel centres)",
			         r->size);
		else
			snprintf(c->source, sizeof c->source, "DFG texture laid out for the set (bilinear, texel centres)");
		c->lut = 1;
		c->lut_size = r->size;
		c->layout = r->layout;
		c->fmt = r->fmt;
		c->lut_bytes = r->bytes;
		c->ops = ops;
		c->cost = sc->fetch_cost + bk_ops_cost(&ops, sc->simple_cost, sc->complex_cost);
		c->err = r->m.max_abs;
	}
	free(rows);
	return rc;
}

/* Better choice first: cheaper; at equal cost more accurate; LUTs: smaller. */
static int better(const cand *a, const cand *b)
{
	if (a->cost != b->cost)
		return a->cost < b->cost;
	if (a->lut && b->lut && a->lut_bytes != b->lut_bytes)
		return a->lut_bytes < b->lut_bytes;
	if (a->err != b->err)
		return a->err < b->err;
	return strcmp(a->name, b->name) < 0;
}

/* ---- the specular LUT ------------------------------------------------------------- */

/* The specular LUTs a scene may choose: both axes, warp powers 1 to 8,
 * scales 4 to 32, 32² to 128², 8 bits (what the low tier ships), the shader
 * with or without Schlick F (brdfkit lut --specular --sweep tries more; its
 * best on the spec target is inside this grid). */
static const int spec_warps[] = {1, 2, 4, 8};
static const double spec_scales[] = {4, 16, 32};
static const int spec_sizes[] = {32, 64, 128};
#define SPEC_NW 4
#define SPEC_NS 3
#define SPEC_NZ 3

static int spec_better(double ca, double ea, int za, double cb, double eb, int zb)
{
	return ca != cb ? ca < cb : ea != eb ? ea < eb : za < zb;
}

/* vf: the specular LUT against D + the choice ch (scene_fit.h: spec_*).
 * Returns 0, or -1 with a message. */
static int consider_speclut(const bk_scene *sc, const bk_scene_set *set, bk_scene_choice *ch, double budget,
                            char *err, size_t errlen)
{
	bk_scene_choice dch;
	if (bk_scene_choose(sc, set, BK_SCENE_TERM_D, &dch, NULL, NULL, NULL, err, errlen))
		return -1;
	double dcost = dch.cost, against = ch->cost + dcost;
	bk_scene_choice_free(&dch);
	enum { N = BK_SPECLUT_AXES * SPEC_NW * SPEC_NS * SPEC_NZ * BK_SPECLUT_FRESNELS };
	bk_speclut cand[N];
	double cost[N];
	int nc = 0;
	for (int a = 0; a < BK_SPECLUT_AXES; a++)
		for (int w = 0; w < SPEC_NW; w++)
			for (int q = 0; q < SPEC_NS; q++)
				for (int z = 0; z < SPEC_NZ; z++)
					for (int fr = 0; fr < BK_SPECLUT_FRESNELS; fr++) {
						double r_lo = set->r_lo, r_hi = set->r_hi;
						widen(&r_lo, &r_hi);
						bk_speclut L = {(bk_speclut_axis)a, spec_warps[w], spec_sizes[z], spec_sizes[z], r_lo, r_hi,
						                spec_scales[q], (bk_speclut_fresnel)fr, BK_LUT_UNORM8};
						bk_ops ops;
						if (bk_speclut_ops(&L, &ops)) {
							snprintf(err, errlen, "vf: the specular LUT's ops could not be counted");
							return -1;
						}
						double c = sc->fetch_cost + bk_ops_cost(&ops, sc->simple_cost, sc->complex_cost);
						if (c < against) { /* only what could win is scored */
							cand[nc] = L;
							cost[nc++] = c;
						}
					}
	ch->spec_considered = nc > 0;
	ch->spec_d_cost = dcost;
	if (!nc)
		return 0;
	/* the lobe's samples on the set's domain, at each end of its f0 range */
	bk_target_options o;
	bk_target_defaults(BK_TARGET_SPEC, &o);
	o.r_lo = set->r_lo;
	o.r_hi = set->r_hi;
	widen(&o.r_lo, &o.r_hi);
	o.x_lo = sc->nov_lo;
	o.x_hi = sc->nov_hi;
	double ends[2] = {set->f0_hi, set->f0_lo};
	int nends = set->f0_lo == set->f0_hi ? 1 : 2, rc = 0;
	bk_samples s[2];
	memset(s, 0, sizeof s);
	for (int k = 0; k < nends && !rc; k++) {
		o.f0[0] = ends[k];
		rc = bk_lutcache_target_build(&o, &s[k], NULL, NULL, err, errlen);
	}
	int b = -1, bm = -1; /* the cheapest within the budget; the most accurate */
	double e[N];
	for (int i = 0; i < nc && !rc; i++) {
		e[i] = 0;
		for (int k = 0; k < nends && !rc; k++) {
			bk_fit_metrics m;
			if (bk_speclut_score(&cand[i], sc->half ? BK_F16 : BK_F32, &s[k], &m, NULL)) {
				snprintf(err, errlen, "vf: a specular LUT could not be scored");
				rc = -1;
			}
			e[i] = fmax(e[i], m.nonfinite || !isfinite(m.albedo_max_abs) ? HUGE_VAL : m.albedo_max_abs);
		}
		int z = cand[i].nu * cand[i].nr;
		if (e[i] <= budget && (b < 0 || spec_better(cost[i], e[i], z, cost[b], e[b], cand[b].nu * cand[b].nr)))
			b = i;
		if (bm < 0 || e[i] < e[bm] || (e[i] == e[bm] && spec_better(cost[i], e[i], z, cost[bm], e[bm], cand[bm].nu * cand[bm].nr)))
			bm = i;
	}
	for (int k = 0; k < nends; k++)
		bk_samples_free(&s[k]);
	if (rc)
		return -1;
	int best = b >= 0 ? b : bm;
	bk_speclut_name(&cand[best], ch->spec_name, sizeof ch->spec_name);
	ch->spec_cost = cost[best];
	ch->spec_err = e[best];
	ch->spec_scored = nc;
	if (b < 0) /* none meets the budget: the choice stays */
		return 0;
	/* it meets the budget for less than D + vf: chosen */
	const bk_speclut *L = &cand[b];
	free(ch->text);
	ch->text = NULL;
	bk_form_free(ch->form);
	ch->form = NULL;
	bk_speclut_name(L, ch->name, sizeof ch->name);
	snprintf(ch->source, sizeof ch->source, "brdfkit lut --specular --axis %s --warp %d --scale %g --size %d "
	         "--r-range %.9g:%.9g --fresnel %s (one texture for D*V*F*NoL, bilinear, texel centres)",
	         bk_speclut_axis_name(L->axis), L->warp, L->scale, L->nu, L->r_lo, L->r_hi,
	         bk_speclut_fresnel_name(L->fresnel));
	memset(ch->p, 0, sizeof ch->p);
	ch->lut = 1;
	ch->speclut = 1;
	ch->spec_layout = *L;
	ch->lut_size = L->nu;
	ch->lut_fmt = L->fmt;
	ch->lut_bytes = (double)L->nu * L->nr;
	ch->fetches = 1;
	bk_speclut_ops(L, &ch->ops);
	ch->cost = cost[b] - dcost;
	ch->err = e[b];
	ch->eq_name[0] = '\0';
	snprintf(ch->guards, sizeof ch->guards, "none: a texture fetch and products of values at most %g", L->scale);
	return 0;
}

/* ---- a short search ----------------------------------------------------------- */

/* vf when nothing cheaper than the exact form meets the budget: brdfkit
 * search's albedo objective on the set's domain (screening grid, f0 at the
 * low end), a small fixed budget, the catalog as seeds; the front members
 * cheaper than max_cost scored as every candidate is. */
static int short_search(pool *P, const bk_scene *sc, const bk_scene_set *set, const domain *d, double max_cost)
{
	bk_target_options o;
	bk_target_defaults(BK_TARGET_VF, &o);
	o.r_lo = set->r_lo;
	o.r_hi = set->r_hi;
	widen(&o.r_lo, &o.r_hi);
	o.x_lo = sc->nov_lo;
	o.x_hi = sc->nov_hi;
	o.f0[0] = set->f0_lo;
	bk_seeds_screening_grid(&o);
	bk_samples screen;
	char err[256];
	if (bk_lutcache_target_build(&o, &screen, NULL, NULL, err, sizeof err))
		return -1;
	bk_seeds sd;
	memset(&sd, 0, sizeof sd);
	bk_search_options so;
	bk_search_defaults(&so);
	so.screen = &screen;
	so.shape = BK_SHAPE_F0;
	so.objective = BK_OBJ_ALBEDO;
	so.precision = d->prec;
	so.simple_cost = sc->simple_cost;
	so.complex_cost = sc->complex_cost;
	so.max_cost = max_cost;
	so.nonneg = 1;
	so.evals = BK_SCENE_SEARCH_EVALS;
	so.enum_max = BK_SCENE_SEARCH_EVALS / 2;
	so.threads = 2; /* the answer does not depend on it (search.h) */
	bk_seeds_grammar(&so.grammar, BK_TARGET_VF);
	so.grammar.max_size = 12;
	so.grammar.inputs = screen.provides & ~(1u << BK_IN_F0);
	int rc = bk_seeds_catalog(&sd, BK_TARGET_VF, 0, screen.provides);
	bk_seeds_apply(&sd, &so);
	bk_search *S = rc ? NULL : bk_search_new(&so, err, sizeof err);
	rc = -1;
	if (S) {
		rc = bk_search_run(S, NULL, NULL, err, sizeof err) < 0 ? -1 : 0;
		size_t idx[64], nf = rc ? 0 : bk_search_front(S, idx, 64);
		refits_list R;
		if (!refits_new(&R, set, d, BK_SCENE_TERM_VF, (int)nf)) {
			for (size_t i = 0; i < nf; i++) {
				const bk_cand *c = bk_search_at(S, idx[i]);
				if (!c->seed_name && c->cost < max_cost && (R.text[R.n] = strdup(c->text)))
					R.start[R.n++] = c->p;
			}
			refits_run(&R);
		}
		for (size_t i = 0; i < nf; i++) {
			const bk_cand *c = bk_search_at(S, idx[i]);
			if (c->seed_name || c->cost >= max_cost)
				continue;
			char name[64], source[128];
			snprintf(name, sizeof name, "search #%ld", c->found_at);
			snprintf(source, sizeof source, "brdfkit search on the set's domain (albedo objective, %d fits, seed 1)",
			         BK_SCENE_SEARCH_EVALS);
			if (add_form(P, sc, set, d, BK_SCENE_TERM_VF, name, source, c->text, c->p)) {
				rc = -1;
				break;
			}
		}
		bk_search_free(S);
	}
	bk_seeds_free(&sd);
	bk_samples_free(&screen);
	return rc;
}

/* ---- guards ---------------------------------------------------------------- */

/* The fp16 guards text needs on the set (half only): none when the set's
 * roughness is above what the stability analysis finds safe without a
 * floor; a cosine floor when that suffices; else the analysis's guarded
 * form. generic: the guards a shader that knows nothing of the scene needs,
 * as for r from 0. *out: the text to emit (allocated); *form: its IR where
 * one is at hand (f's copy, or the analysis's guarded form), else NULL (a new
 * text, a cosine floor: the caller parses it); *added: the largest relative
 * error the guard adds on its own (stability.h), 0 for none. */
static int guard(const bk_scene *sc, const bk_scene_set *set, const char *name, const bk_form *f, const double *p,
                 int generic, char **out, bk_form **form, double *added, char *why, size_t whylen, char *err,
                 size_t errlen)
{
	const char *text = bk_form_text(f);
	*out = NULL;
	*form = NULL;
	*added = 0;
	if (!sc->half) {
		snprintf(why, whylen, "none: highp, no half-precision guard");
		*out = strdup(text);
		*form = bk_form_dup(f); /* NULL (out of memory): the caller parses out */
		return *out ? 0 : -1;
	}
	bk_stability st;
	if (bk_stability_run_form(name, f, p, BK_STAB_TOL, &st, err, errlen))
		return -1;
	const bk_stab_prec *h = &st.p[2];
	double r_lo = generic ? 0 : set->r_lo;
	int i = 0;
	while (i < 5 && !(st.floor_r[i] <= r_lo))
		i++;
	if (st.safe_as_is && h->nan == 0 && h->inf == 0) { /* stability.h: no pole, nothing hidden */
		snprintf(why, whylen, "none: right in half on the whole stress grid");
		*out = strdup(text);
		*form = bk_form_dup(f);
	} else if (i == 0) {
		snprintf(why, whylen, "none: r >= %g on this set, and half is right from r >= %.3g", r_lo, st.floor_r[0]);
		*out = strdup(text);
		*form = bk_form_dup(f);
	} else if (i < 5) {
		snprintf(why, whylen, "cosines floored at %g (half is right from r >= %.3g with it; r >= %g here)",
		         st.floor_cos[i], st.floor_r[i], r_lo);
		*out = floor_cosines(text, st.floor_cos[i]);
		*added = isfinite(st.guard_error[1]) ? st.guard_error[1] : 0;
	} else if (st.guarded && st.guarded_ok) {
		snprintf(why, whylen, "%.120s (adds up to %.3g relative error where it acts)", st.guards[0] ? st.guards : "guarded",
		         st.guard_error[0]);
		*out = strdup(st.guarded);
		*form = st.guarded_form;
		st.guarded_form = NULL;
		*added = st.guard_error[0];
	} else {
		snprintf(why, whylen, "not safe in half even with the guards brdfkit knows (%.150s)",
		         st.guards[0] ? st.guards : "none apply");
		*out = strdup(st.guarded); /* bk_stability_run_form: never NULL on success */
		*form = st.guarded_form;
		st.guarded_form = NULL;
	}
	bk_stability_free(&st);
	if (*out)
		return 0;
	bk_form_free(*form);
	*form = NULL;
	return -1;
}

/* Fills ch from candidate c: guards, then the final text's cost and error. */
static int finish(const bk_scene *sc, const bk_scene_set *set, const domain *d, bk_scene_term term, const cand *c,
                  int generic, bk_scene_choice *ch, char *err, size_t errlen)
{
	snprintf(ch->name, sizeof ch->name, "%s", c->name);
	snprintf(ch->source, sizeof ch->source, "%s", c->source);
	memcpy(ch->p, c->p, sizeof ch->p);
	ch->lut = c->lut;
	ch->lut_size = c->lut_size;
	ch->lut_fmt = c->fmt;
	ch->lut_layout = c->layout;
	ch->lut_bytes = c->lut_bytes;
	ch->ops = c->ops;
	ch->cost = c->cost;
	ch->err = c->err;
	ch->fetches = c->lut;
	if (c->lut) {
		snprintf(ch->guards, sizeof ch->guards, "none: a texture fetch%s", ch->ops.simple + ch->ops.complex
		         ? " and arithmetic on values in [0, 1]" : "");
		return 0;
	}
	double added;
	if (!c->f) { /* a constant of this file that does not parse (bk_stability_run's message) */
		bk_form_error fe;
		bk_form *f = bk_form_parse(c->text, &fe);
		if (!f)
			bk_stability_parse_error(c->name, &fe, err, errlen);
		else
			snprintf(err, errlen, "%s: out of memory", c->name);
		bk_form_free(f);
		return -1;
	}
	if (guard(sc, set, c->name, c->f, c->p, generic, &ch->text, &ch->form, &added, ch->guards, sizeof ch->guards,
	          err, errlen))
		return -1;
	if (!d) /* D is exact: its error is what the guard adds */
		ch->err = added;
	bk_form_error fe;
	if (!ch->form && !(ch->form = bk_form_parse(ch->text, &fe))) { /* a new text: its cosines floored */
		snprintf(err, errlen, "%s: the guarded form does not parse: %s", c->name, fe.message);
		return -1;
	}
	ch->cost = form_cost(sc, ch->form, &ch->ops);
	if (d)
		ch->err = score(d, term, ch->form, ch->p);
	return 0;
}

/* "at-generic-cost": of the candidates at no more than the generic term's
 * cost (a LUT: and memory), the one whose error after its fp16 guards is
 * least. Candidates are finished (guarded and scored) in order of their error
 * as fitted; a guard only ever adds error here (a roughness floor, a clamp
 * of values the form already keeps in range), so once a candidate's error as
 * fitted is no better than the best guarded one, none after it can win; a
 * candidate whose guards take it over the generic's cost is passed over.
 * Returns 0 with ch set, or -1 with a message (none at that cost). */
static int most_accurate_at(const bk_scene *sc, const bk_scene_set *set, const domain *d, bk_scene_term term,
                            const pool *P, double cost, double lut_bytes, bk_scene_choice *ch, char *err,
                            size_t errlen)
{
	int *order = malloc((P->n ? P->n : 1) * sizeof *order), no = 0;
	if (!order) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	for (int i = 0; i < P->n; i++) {
		const cand *c = &P->c[i];
		if (!(c->cost <= cost) || (c->lut && c->lut_bytes > lut_bytes) || !isfinite(c->err))
			continue;
		int k = no++;
		while (k > 0 && (c->err < P->c[order[k - 1]].err ||
		                 (c->err == P->c[order[k - 1]].err && better(c, &P->c[order[k - 1]])))) {
			order[k] = order[k - 1];
			k--;
		}
		order[k] = i;
	}
	int rc = 0, have = 0;
	bk_scene_choice best, one;
	memset(&best, 0, sizeof best);
	for (int k = 0; k < no && !(have && P->c[order[k]].err >= best.err); k++) {
		memset(&one, 0, sizeof one);
		if (finish(sc, set, d, term, &P->c[order[k]], 0, &one, err, errlen)) {
			bk_scene_choice_free(&one);
			rc = -1;
			break;
		}
		if (one.cost <= cost && (!have || one.err < best.err)) { /* its guards may have cost more */
			bk_scene_choice_free(&best);
			best = one;
			have = 1;
		} else {
			bk_scene_choice_free(&one);
		}
	}
	free(order);
	if (rc == 0 && !have) {
		snprintf(err, errlen, "%s: no candidate at or below the generic's cost %g is finite on the set's domain",
		         bk_scene_term_name(term), cost);
		rc = -1;
	}
	if (rc)
		bk_scene_choice_free(&best);
	else
		*ch = best;
	return rc;
}

/* ---- the terms a scene asks for (ms, sheen, cloth) -------------------------------- */

/* The budget and the catalog's target of a fitted term. */
static double term_budget(const bk_scene *sc, bk_scene_term term)
{
	switch (term) {
	case BK_SCENE_TERM_VF: return sc->budget_vf;
	case BK_SCENE_TERM_MS: return sc->budget_ms;
	case BK_SCENE_TERM_SHEEN: return sc->budget_sheen;
	default: return sc->budget_env;
	}
}

static bk_target_kind term_kind(bk_scene_term term)
{
	return term == BK_SCENE_TERM_VF ? BK_TARGET_VF : term == BK_SCENE_TERM_MS ? BK_TARGET_MS
	     : term == BK_SCENE_TERM_SHEEN ? BK_TARGET_SHEEN : BK_TARGET_ENV;
}

/* A DFG LUT's metrics on the domain: env's f0 A + B; for ms, E = A + B,
 * the same fetch at f0 = 1 (the samples' f0, NaN for E, read as 1 on a
 * shallow copy). Returns 0 or -1. */
static int lut_metrics(const bk_lut_layout *L, bk_lut_format fmt, bk_scene_term term, const domain *d,
                       bk_fit_metrics *m)
{
	const bk_samples *s = &d->s[0];
	if (term != BK_SCENE_TERM_MS)
		return bk_lut_score_layout(L, fmt, BK_SMITH_CORRELATED, d->prec, s, m, NULL);
	double *one = malloc((s->n ? s->n : 1) * sizeof *one);
	if (!one)
		return -1;
	for (size_t i = 0; i < s->n; i++)
		one[i] = 1;
	bk_samples at1 = *s;
	at1.in[BK_IN_F0] = one;
	at1.provides |= 1u << BK_IN_F0;
	int rc = bk_lut_score_layout(L, fmt, BK_SMITH_CORRELATED, d->prec, &at1, m, NULL);
	free(one);
	return rc;
}

/* cloth: the exact sheen lobe, as D: only the guards are decided. */
static int choose_exact(const bk_scene *sc, const bk_scene_set *set, bk_scene_term term, const char *name,
                        const char *source, const char *text, bk_scene_choice *ch, bk_scene_choice *generic,
                        char *err, size_t errlen)
{
	cand c;
	memset(&c, 0, sizeof c);
	snprintf(c.name, sizeof c.name, "%s", name);
	snprintf(c.source, sizeof c.source, "%s", source);
	c.text = (char *)text;
	c.f = bk_form_parse(c.text, NULL); /* a constant: parsed where it enters (NULL: finish says why) */
	int bad = finish(sc, set, NULL, term, &c, 0, ch, err, errlen) ||
	          (generic && finish(sc, set, NULL, term, &c, 1, generic, err, errlen));
	bk_form_free(c.f);
	if (bad)
		return -1;
	ch->budget = NAN; /* nothing to choose: no budget applies */
	ch->meets = 1;
	ch->scored = 1;
	if (generic) {
		snprintf(generic->name, sizeof generic->name, "generic");
		generic->budget = NAN;
		generic->meets = 1;
	}
	return 0;
}

int bk_scene_ms_from_env(const bk_scene *sc, const bk_scene_set *set, const bk_scene_choice *env, bk_scene_choice *ms,
                         bk_scene_choice *gen, int *taken, char *err, size_t errlen)
{
	*taken = 0;
	if (gen) { /* the generic's env LUT is BK_SCENE_GENERIC_LUT's A and B: E from that fetch */
		snprintf(gen->name, sizeof gen->name, "generic (E = A + B of its env LUT %dx%d half)", BK_SCENE_GENERIC_LUT,
		         BK_SCENE_GENERIC_LUT);
		memset(&gen->ops, 0, sizeof gen->ops);
		gen->ops.simple = 1;
		gen->cost = sc->simple_cost;
		gen->fetches = 0;
		gen->lut_bytes = 0;
		/* ms's candidate "at the generic's cost" was found against a fetch of
		 * its own: at one add, only the env LUT's A + B is (below), or none */
		ms->eq_name[0] = '\0';
	}
	/* a folded layout stores f0 A + B at one f0, the specular LUT D V F NoL:
	 * neither gives A + B */
	if (!env->lut || env->speclut || !isnan(env->lut_layout.f0))
		return 0;
	domain d;
	if (domain_build(sc, set, BK_SCENE_TERM_MS, &d, NULL, NULL, err, errlen))
		return -1;
	bk_fit_metrics m;
	int rc = lut_metrics(&env->lut_layout, env->lut_fmt, BK_SCENE_TERM_MS, &d, &m);
	domain_free(&d);
	if (rc) {
		snprintf(err, errlen, "ms: the env LUT could not be scored for E");
		return -1;
	}
	double e = m.nonfinite || !isfinite(m.max_abs) ? HUGE_VAL : m.max_abs, cost = sc->simple_cost; /* A + B */
	if (gen && isfinite(e)) { /* the most accurate at the generic's cost of one add */
		snprintf(ms->eq_name, sizeof ms->eq_name, "env %.100s, A + B", env->name);
		ms->eq_cost = cost;
		ms->eq_err = e;
	}
	int better_pick = ms->at_cost || !ms->meets ? e < ms->err
	                : e <= ms->budget && (cost < ms->cost || (cost == ms->cost && e < ms->err));
	if (!better_pick)
		return 0;
	free(ms->text);
	ms->text = NULL;
	bk_form_free(ms->form); /* a LUT: no form (scene_fit.h) */
	ms->form = NULL;
	snprintf(ms->name, sizeof ms->name, "env %.100s, A + B", env->name);
	snprintf(ms->source, sizeof ms->source, "E = A + B of the set's env texture fetch (no fetch of its own)");
	memset(ms->p, 0, sizeof ms->p);
	memset(&ms->ops, 0, sizeof ms->ops);
	ms->ops.simple = 1;
	ms->lut = 1;
	ms->lut_size = env->lut_size;
	ms->lut_layout = env->lut_layout;
	ms->lut_fmt = env->lut_fmt;
	ms->lut_bytes = 0; /* env's texture */
	ms->fetches = 0;
	ms->cost = cost;
	ms->err = e;
	ms->meets = e <= ms->budget;
	ms->scored++;
	snprintf(ms->guards, sizeof ms->guards, "none: the sum of two fetched values in [0, 1]");
	*taken = 1;
	return 0;
}

int bk_scene_choose(const bk_scene *sc, const bk_scene_set *set, bk_scene_term term, bk_scene_choice *ch,
                    bk_scene_choice *generic, bk_progress_fn progress, void *ctx, char *err, size_t errlen)
{
	memset(ch, 0, sizeof *ch);
	ch->term = term;
	if (generic) {
		memset(generic, 0, sizeof *generic);
		generic->term = term;
	}
	if (term == BK_SCENE_TERM_CLOTH)
		return choose_exact(sc, set, term, "D_charlie*V_neubelt",
		                    "Estevez & Kulla 2017 (Charlie D), Neubelt & Pettineo 2013 (V); exact, as Filament's cloth",
		                    BK_SCENE_CLOTH, ch, generic, err, errlen);
	if (term == BK_SCENE_TERM_D) /* exact GGX: only the guards are decided */
		return choose_exact(sc, set, term, "D_ggx", "Walter et al. 2007 (exact GGX)", BK_SCENE_GENERIC_D, ch,
		                    generic, err, errlen);
	/* the phases' labels (bk_scene_choose's contract in scene_fit.h) */
	char lab_ref[200] = "", lab_cat[200] = "", lab_lut[200] = "";
	if (progress) {
		snprintf(lab_ref, sizeof lab_ref, "%s: reference", (const char *)ctx);
		snprintf(lab_cat, sizeof lab_cat, "%s: catalog forms", (const char *)ctx);
		snprintf(lab_lut, sizeof lab_lut, "%s: LUT rows", (const char *)ctx);
	}
	domain d;
	if (domain_build(sc, set, term, &d, progress, lab_ref, err, errlen))
		return -1;
	pool P = {0};
	int rc = -1;
	/* the generic term first: its error is the "generic" budget */
	cand gen;
	memset(&gen, 0, sizeof gen);
	bk_scene_choice g;
	memset(&g, 0, sizeof g);
	if (term == BK_SCENE_TERM_VF) {
		bk_form_error fe;
		bk_form *f = bk_form_parse(BK_SCENE_GENERIC_VF, &fe);
		snprintf(gen.name, sizeof gen.name, "generic");
		snprintf(gen.source, sizeof gen.source, "exact height-correlated Smith GGX V x Schlick F");
		gen.text = BK_SCENE_GENERIC_VF;
		gen.f = f; /* freed at done */
		gen.cost = f ? form_cost(sc, f, &gen.ops) : HUGE_VAL;
		if (finish(sc, set, &d, term, &gen, 1, &g, err, errlen))
			goto done;
	} else if (term == BK_SCENE_TERM_SHEEN) { /* MaterialX's fit at its published constants */
		const bk_catalog_entry *e = bk_catalog_find(BK_SCENE_GENERIC_SHEEN);
		bk_form_error fe;
		bk_form *f = e ? bk_form_parse(e->form, &fe) : NULL;
		if (!f) {
			snprintf(err, errlen, "sheen: the generic form %s is missing", BK_SCENE_GENERIC_SHEEN);
			goto done;
		}
		snprintf(gen.name, sizeof gen.name, "generic (%s)", e->name);
		snprintf(gen.source, sizeof gen.source, "%.250s", e->source);
		gen.text = (char *)e->form;
		memcpy(gen.p, e->defaults, sizeof gen.p);
		gen.f = f; /* freed at done; finish guards it */
		gen.cost = form_cost(sc, f, &gen.ops);
		gen.err = score(&d, term, f, gen.p);
		if (finish(sc, set, &d, term, &gen, 1, &g, err, errlen))
			goto done;
	} else { /* env: f0 A + B; ms: E = A + B, Filament's G channel (lut_metrics) */
		bk_fit_metrics m;
		bk_lut_layout gl = {BK_SCENE_GENERIC_LUT, BK_SCENE_GENERIC_LUT, 0, 1, BK_LUT_WARP_NONE, NAN};
		if (lut_metrics(&gl, BK_LUT_HALF, term, &d, &m)) {
			snprintf(err, errlen, "%s: the generic LUT could not be scored", bk_scene_term_name(term));
			goto done;
		}
		snprintf(gen.name, sizeof gen.name, "generic (LUT %dx%d half)", BK_SCENE_GENERIC_LUT, BK_SCENE_GENERIC_LUT);
		snprintf(gen.source, sizeof gen.source, "DFG texture, bilinear");
		gen.lut = 1;
		gen.lut_size = BK_SCENE_GENERIC_LUT;
		gen.layout = (bk_lut_layout){BK_SCENE_GENERIC_LUT, BK_SCENE_GENERIC_LUT, 0, 1, BK_LUT_WARP_NONE, NAN};
		gen.fmt = BK_LUT_HALF;
		gen.lut_bytes = BK_SCENE_GENERIC_LUT * BK_SCENE_GENERIC_LUT * 4;
		gen.ops.n[BK_K_MAD] = 1;
		gen.ops.simple = 1;
		gen.cost = sc->fetch_cost + sc->simple_cost;
		gen.err = m.max_abs;
		if (finish(sc, set, &d, term, &gen, 1, &g, err, errlen))
			goto done;
	}
	double budget = term_budget(sc, term);
	int at_cost = budget == BK_SCENE_BUDGET_AT_COST;
	if (budget == BK_SCENE_BUDGET_GENERIC || at_cost)
		budget = g.err;
	/* the candidates */
	bk_target_kind k = term_kind(term);
	int ncat = 0;
	for (size_t i = 0; i < bk_catalog_count(); i++)
		ncat += bk_catmap_answers(k, 1, bk_catalog_at(i)); /* D and cloth returned above */
	refits_list R;
	if (refits_new(&R, set, &d, term, ncat)) {
		snprintf(err, errlen, "%s: out of memory", bk_scene_term_name(term));
		goto done;
	}
	R.progress = progress, R.label = lab_cat;
	for (size_t i = 0; i < bk_catalog_count(); i++) {
		const bk_catalog_entry *e = bk_catalog_at(i);
		if (bk_catmap_answers(k, 1, e) && (R.text[R.n] = bk_catmap_form(k, 1, e)))
			R.start[R.n++] = e->defaults;
	}
	refits_run(&R);
	for (size_t i = 0; i < bk_catalog_count(); i++) {
		const bk_catalog_entry *e = bk_catalog_at(i);
		/* the catalog's forms of the term, each as one form (f0 A + B for env) */
		if (!bk_catmap_answers(k, 1, e))
			continue;
		char *text = bk_catmap_form(k, 1, e);
		int bad = !text || add_form(&P, sc, set, &d, term, e->name, e->source, text, e->defaults);
		free(text);
		if (bad) {
			snprintf(err, errlen, "%s: out of memory", e->name);
			goto done;
		}
	}
	if (term == BK_SCENE_TERM_VF && add_form(&P, sc, set, &d, term, "exact", gen.source, BK_SCENE_GENERIC_VF, NULL))
		goto done;
	if (term == BK_SCENE_TERM_ENV && sc->lut && add_luts(&P, sc, set, &d, BK_SMITH_CORRELATED, term, progress, lab_lut)) {
		snprintf(err, errlen, "env: a LUT could not be scored");
		goto done;
	}
	/* ms: a texture of E alone (where the set has an env LUT of A and B,
	 * cmd_scene reads E from it instead: bk_scene_ms_from_env); sheen: the
	 * cloth channel's texture */
	if ((term == BK_SCENE_TERM_MS || term == BK_SCENE_TERM_SHEEN) && sc->lut &&
	    add_luts(&P, sc, set, &d, BK_SMITH_CORRELATED, term, progress, lab_lut)) {
		snprintf(err, errlen, "%s: a LUT could not be scored", term == BK_SCENE_TERM_MS ? "ms" : "sheen");
		goto done;
	}
	/* the cheapest that meets the budget; else the most accurate */
	/* indices, not pointers: the short search grows the pool */
	int b = -1;
	for (int i = 0; i < P.n; i++)
		if (P.c[i].err <= budget && (b < 0 || better(&P.c[i], &P.c[b])))
			b = i;
	int meets = b >= 0;
	for (int i = 0; !meets && i < P.n; i++)
		if (b < 0 || P.c[i].err < P.c[b].err || (P.c[i].err == P.c[b].err && better(&P.c[i], &P.c[b])))
			b = i;
	/* vf: the exact form (or nothing) meets it: a short search for a cheaper one
	 * (not when accuracy at the generic's cost is asked: it finds cheaper forms,
	 * not more accurate ones) */
	if (term == BK_SCENE_TERM_VF && !at_cost && (!meets || !strcmp(P.c[b].name, "exact"))) {
		int before = P.n;
		if (short_search(&P, sc, set, &d, b >= 0 ? P.c[b].cost : HUGE_VAL)) {
			snprintf(err, errlen, "vf: the short search failed");
			goto done;
		}
		for (int i = before; i < P.n; i++)
			if (P.c[i].err <= budget && (!meets || better(&P.c[i], &P.c[b]))) {
				b = i;
				meets = 1;
			}
	}
	if (b < 0) {
		snprintf(err, errlen, "%s: no candidate is finite on the set's domain", bk_scene_term_name(term));
		goto done;
	}
	/* env: the most accurate at the generic's cost and memory (vf's
	 * candidates are scored before their guards, the generic after: no
	 * fair comparison there) */
	int eq = -1;
	for (int i = 0; term != BK_SCENE_TERM_VF && i < P.n; i++)
		if (P.c[i].cost <= g.cost && (!P.c[i].lut || P.c[i].lut_bytes <= gen.lut_bytes) &&
		    (eq < 0 || P.c[i].err < P.c[eq].err || (P.c[i].err == P.c[eq].err && better(&P.c[i], &P.c[eq]))))
			eq = i;
	if (at_cost) {
		if (most_accurate_at(sc, set, &d, term, &P, g.cost, gen.lut_bytes, ch, err, errlen))
			goto done;
		meets = 1; /* chosen: the block below must not choose again */
		eq = -1;   /* the choice is that candidate, guarded */
	}
	/* the guards a form needs in half can cost accuracy (a roughness floor):
	 * the candidates that meet the budget as fitted are tried in order of
	 * preference until one still meets it guarded */
	else if (meets) {
		int *order = malloc(P.n * sizeof *order), no = 0;
		if (!order) {
			snprintf(err, errlen, "out of memory");
			goto done;
		}
		for (int i = 0; i < P.n; i++)
			if (P.c[i].err <= budget) {
				int k = no++;
				while (k > 0 && better(&P.c[i], &P.c[order[k - 1]])) {
					order[k] = order[k - 1];
					k--;
				}
				order[k] = i;
			}
		int ok = 0;
		for (int k = 0; k < no && !ok; k++) {
			bk_scene_choice_free(ch);
			if (finish(sc, set, &d, term, &P.c[order[k]], 0, ch, err, errlen)) {
				free(order);
				goto done;
			}
			ok = ch->err <= budget;
		}
		free(order);
		if (!ok) { /* none does: the most accurate as fitted */
			meets = 0;
			for (int i = 0; i < P.n; i++)
				if (P.c[i].err < P.c[b].err || (P.c[i].err == P.c[b].err && better(&P.c[i], &P.c[b])))
					b = i;
		}
	}
	if (!meets) {
		bk_scene_choice_free(ch);
		if (finish(sc, set, &d, term, &P.c[b], 0, ch, err, errlen))
			goto done;
	}
	if (eq >= 0) {
		snprintf(ch->eq_name, sizeof ch->eq_name, "%s", P.c[eq].name);
		ch->eq_cost = P.c[eq].cost;
		ch->eq_err = P.c[eq].err;
	}
	ch->budget = budget;
	ch->at_cost = at_cost;
	ch->meets = ch->err <= budget;
	ch->scored = P.n;
	/* the specular LUT for an error budget given as a number: "generic" asks
	 * for the exact V·F's own rounding error, which a texture of D/4 (V = 1/4,
	 * no Fresnel: 1e-2 and more of model error) never reaches, and
	 * "at-generic-cost" for the most accurate */
	if (term == BK_SCENE_TERM_VF && sc->lut && sc->budget_vf >= 0 && ch->meets &&
	    consider_speclut(sc, set, ch, budget, err, errlen))
		goto done;
	if (ch->speclut)
		ch->scored += ch->spec_scored;
	g.budget = budget;
	g.meets = g.err <= budget;
	if (generic)
		*generic = g;
	else
		bk_scene_choice_free(&g);
	memset(&g, 0, sizeof g);
	rc = 0;
done:
	bk_scene_choice_free(&g);
	bk_form_free(gen.f);
	pool_free(&P);
	domain_free(&d);
	return rc;
}

void bk_scene_choice_free(bk_scene_choice *ch)
{
	free(ch->text);
	ch->text = NULL;
	bk_form_free(ch->form);
	ch->form = NULL;
}

int bk_scene_form_error(const bk_scene *sc, const bk_scene_set *set, bk_scene_term term, const char *text, double *p,
                        int refit_first, double *err_out, char *err, size_t errlen)
{
	if (term == BK_SCENE_TERM_D || term == BK_SCENE_TERM_CLOTH) {
		snprintf(err, errlen, "%s: exact, nothing to score", bk_scene_term_name(term));
		return -1;
	}
	bk_form_error fe;
	bk_form *f = bk_form_parse(text, &fe);
	if (!f) {
		snprintf(err, errlen, "%s", fe.message);
		return -1;
	}
	domain d;
	if (domain_build(sc, set, term, &d, NULL, NULL, err, errlen)) {
		bk_form_free(f);
		return -1;
	}
	int rc = 0;
	double start[BK_MAX_PARAMS];
	memcpy(start, p, sizeof start);
	if (refit_first && refit(&d, term, f, text, start, p)) {
		snprintf(err, errlen, "the refit failed");
		rc = -1;
	}
	if (!rc)
		*err_out = score(&d, term, f, p);
	domain_free(&d);
	bk_form_free(f);
	return rc;
}
